// A step's launches as one CUDA graph. The solver's host code runs as it always does, but while
// a recording is open the executor's kernels and memsets are written down (function, grid,
// argument bytes) instead of queued; closing it queues them all with one graph launch. The
// graphs of the last few recordings are kept: a recording identical to one of them replays it
// as it is, one of the same shape (the same kernels in the same order, other arguments: a new
// particle count, other buffers after the roles rotated, another dt) updates that graph's nodes
// in place, and only a new shape (another substep or iteration count, a feature switched on)
// builds and instantiates a new graph. So a frame costs one graph launch instead of a launch per
// kernel, and the GPU runs the kernels back to back without waiting on the host between them.
//
// Each kernel node depends on the one before it: the step is a chain, as it was on the stream.
// Where the driver has no graphs, or a graph cannot be built, the recording is queued on the
// stream launch by launch, which is what the step did before graphs.
#pragma once
#include <cstdint>
#include <vector>

#include "cuda_driver.h"

namespace pbf::cuda {

// One kernel argument: where its value is and how many bytes the kernel takes.
struct KernelArg {
    const void* value;
    uint32_t bytes;
};

class StepGraph {
public:
    StepGraph() = default;
    ~StepGraph();
    StepGraph(const StepGraph&) = delete;
    StepGraph& operator=(const StepGraph&) = delete;

    // Graphs are used where the driver has the entry points and `enabled` is set.
    void init(const Driver* cu, CUcontext context, bool enabled);
    bool enabled() const { return enabled_; }
    // Destroys the kept graphs (before the world lets its context go).
    void clear();

    void begin() { recording_.clear(), open_ = true; }
    bool open() const { return open_; }
    void add_kernel(CUfunction f, uint32_t blocks, uint32_t threads, const KernelArg* args, uint32_t count);
    void add_memset(CUdeviceptr dst, size_t bytes);
    // Closes the recording and queues it on stream (see above); the driver's first error.
    CUresult end(CUstream stream);

private:
    struct Command {
        CUfunction f = nullptr;  // null: a memset of `bytes` zero bytes at dst
        uint32_t blocks = 0, threads = 0;
        uint32_t first_arg = 0, args = 0;  // into Recording::arg_offset
        CUdeviceptr dst = 0;
        size_t bytes = 0;
    };
    struct Recording {
        std::vector<Command> commands;
        std::vector<uint32_t> arg_offset, arg_bytes;  // each argument's bytes in data
        std::vector<unsigned char> data;
        void clear() {
            commands.clear();
            arg_offset.clear();
            arg_bytes.clear();
            data.clear();
        }
    };
    struct Kept {
        Recording recording;  // what the graph's nodes hold now
        CUgraph graph = nullptr;
        CUgraphExec exec = nullptr;
        std::vector<CUgraphNode> nodes;
        uint64_t used = 0;  // the recording count when it last ran: the oldest goes first
    };
    static constexpr size_t kKeptGraphs = 4;

    static bool same_command(const Recording& a, size_t i, const Recording& b, size_t j);
    static bool same_shape(const Recording& a, const Recording& b);
    size_t differences(const Recording& a, const Recording& b) const;
    void kernel_params(const Recording& r, const Command& c, std::vector<void*>* pointers,
                       CUDA_KERNEL_NODE_PARAMS* p) const;
    CUDA_MEMSET_NODE_PARAMS memset_params(const Command& c) const;
    CUresult update(Kept* k);
    CUresult build(Kept* k);
    CUresult direct(CUstream stream);
    void release(Kept* k);

    const Driver* cu_ = nullptr;
    CUcontext context_ = nullptr;
    bool enabled_ = false;
    bool open_ = false;
    Recording recording_;
    std::vector<Kept> kept_;
    std::vector<void*> pointers_;  // kernel argument pointers for one node
    uint64_t recordings_ = 0;
};

}  // namespace pbf::cuda
