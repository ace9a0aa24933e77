// The step's graph (cuda_graph.h): recording, the kept graphs, their updates and builds.
#include "cuda_graph.h"

#include <cstring>
#include <limits>

namespace pbf::cuda {

StepGraph::~StepGraph() { clear(); }

void StepGraph::clear() {
    for (Kept& k : kept_) release(&k);
    kept_.clear();
}

void StepGraph::init(const Driver* cu, CUcontext context, bool enabled) {
    cu_ = cu;
    context_ = context;
    enabled_ = enabled && cu && cu->cuGraphCreate && cu->cuGraphAddKernelNode && cu->cuGraphAddMemsetNode &&
               cu->cuGraphExecKernelNodeSetParams && cu->cuGraphExecMemsetNodeSetParams &&
               cu->cuGraphInstantiateWithFlags && cu->cuGraphLaunch && cu->cuGraphExecDestroy && cu->cuGraphDestroy;
}

void StepGraph::add_kernel(CUfunction f, uint32_t blocks, uint32_t threads, const KernelArg* args, uint32_t count) {
    Recording& r = recording_;
    Command c;
    c.f = f;
    c.blocks = blocks;
    c.threads = threads;
    c.first_arg = uint32_t(r.arg_offset.size());
    c.args = count;
    for (uint32_t a = 0; a < count; ++a) {
        // Each value starts on 16 bytes, the widest alignment a kernel argument here has.
        const size_t offset = (r.data.size() + 15) & ~size_t(15);
        r.data.resize(offset + args[a].bytes);
        std::memcpy(r.data.data() + offset, args[a].value, args[a].bytes);
        r.arg_offset.push_back(uint32_t(offset));
        r.arg_bytes.push_back(args[a].bytes);
    }
    r.commands.push_back(c);
}

void StepGraph::add_memset(CUdeviceptr dst, size_t bytes) {
    Command c;
    c.dst = dst;
    c.bytes = bytes;
    c.first_arg = uint32_t(recording_.arg_offset.size());
    recording_.commands.push_back(c);
}

bool StepGraph::same_command(const Recording& a, size_t i, const Recording& b, size_t j) {
    const Command &x = a.commands[i], &y = b.commands[j];
    if (x.f != y.f || x.blocks != y.blocks || x.threads != y.threads || x.args != y.args || x.dst != y.dst ||
        x.bytes != y.bytes)
        return false;
    for (uint32_t k = 0; k < x.args; ++k) {
        const uint32_t n = a.arg_bytes[x.first_arg + k];
        if (n != b.arg_bytes[y.first_arg + k] || std::memcmp(a.data.data() + a.arg_offset[x.first_arg + k],
                                                             b.data.data() + b.arg_offset[y.first_arg + k], n) != 0)
            return false;
    }
    return true;
}

// The same kernels in the same order (grids and arguments may differ), the same memset sizes:
// what a kept graph can be updated to in place.
bool StepGraph::same_shape(const Recording& a, const Recording& b) {
    if (a.commands.size() != b.commands.size()) return false;
    for (size_t i = 0; i < a.commands.size(); ++i) {
        const Command &x = a.commands[i], &y = b.commands[i];
        if (x.f != y.f || x.args != y.args || (!x.f && x.bytes != y.bytes)) return false;
    }
    return true;
}

size_t StepGraph::differences(const Recording& a, const Recording& b) const {
    size_t n = 0;
    for (size_t i = 0; i < a.commands.size(); ++i) n += same_command(a, i, b, i) ? 0 : 1;
    return n;
}

void StepGraph::kernel_params(const Recording& r, const Command& c, std::vector<void*>* pointers,
                              CUDA_KERNEL_NODE_PARAMS* p) const {
    pointers->resize(c.args);
    for (uint32_t k = 0; k < c.args; ++k)
        (*pointers)[k] = const_cast<unsigned char*>(r.data.data()) + r.arg_offset[c.first_arg + k];
    *p = CUDA_KERNEL_NODE_PARAMS{};
    p->func = c.f;
    p->gridDimX = c.blocks;
    p->gridDimY = p->gridDimZ = 1;
    p->blockDimX = c.threads;
    p->blockDimY = p->blockDimZ = 1;
    p->kernelParams = pointers->data();
}

CUDA_MEMSET_NODE_PARAMS StepGraph::memset_params(const Command& c) const {
    CUDA_MEMSET_NODE_PARAMS p{};
    p.dst = c.dst;
    p.value = 0;
    p.elementSize = 1;
    p.width = c.bytes;
    p.height = 1;
    return p;
}

// The nodes whose command changed take the recording's; the node copies the argument values.
CUresult StepGraph::update(Kept* k) {
    for (size_t i = 0; i < recording_.commands.size(); ++i) {
        if (same_command(k->recording, i, recording_, i)) continue;
        const Command& c = recording_.commands[i];
        CUresult e;
        if (c.f) {
            CUDA_KERNEL_NODE_PARAMS p;
            kernel_params(recording_, c, &pointers_, &p);
            e = cu_->cuGraphExecKernelNodeSetParams(k->exec, k->nodes[i], &p);
        } else {
            const CUDA_MEMSET_NODE_PARAMS p = memset_params(c);
            e = cu_->cuGraphExecMemsetNodeSetParams(k->exec, k->nodes[i], &p, context_);
        }
        if (e != CUDA_SUCCESS) return e;
    }
    std::swap(k->recording, recording_);
    return CUDA_SUCCESS;
}

CUresult StepGraph::build(Kept* k) {
    CUresult e = cu_->cuGraphCreate(&k->graph, 0);
    k->nodes.clear();
    for (size_t i = 0; e == CUDA_SUCCESS && i < recording_.commands.size(); ++i) {
        const Command& c = recording_.commands[i];
        CUgraphNode node = nullptr;
        const CUgraphNode* after = k->nodes.empty() ? nullptr : &k->nodes.back();
        const size_t deps = k->nodes.empty() ? 0 : 1;
        if (c.f) {
            CUDA_KERNEL_NODE_PARAMS p;
            kernel_params(recording_, c, &pointers_, &p);
            e = cu_->cuGraphAddKernelNode(&node, k->graph, after, deps, &p);
        } else {
            const CUDA_MEMSET_NODE_PARAMS p = memset_params(c);
            e = cu_->cuGraphAddMemsetNode(&node, k->graph, after, deps, &p, context_);
        }
        k->nodes.push_back(node);
    }
    if (e == CUDA_SUCCESS) e = cu_->cuGraphInstantiateWithFlags(&k->exec, k->graph, 0);
    if (e == CUDA_SUCCESS) std::swap(k->recording, recording_);
    return e;
}

CUresult StepGraph::direct(CUstream stream) {
    CUresult first = CUDA_SUCCESS;
    for (const Command& c : recording_.commands) {
        CUresult e;
        if (c.f) {
            CUDA_KERNEL_NODE_PARAMS p;
            kernel_params(recording_, c, &pointers_, &p);
            e = cu_->cuLaunchKernel(c.f, c.blocks, 1, 1, c.threads, 1, 1, 0, stream, p.kernelParams, nullptr);
        } else {
            e = cu_->cuMemsetD8Async(c.dst, 0, c.bytes, stream);
        }
        if (first == CUDA_SUCCESS) first = e;
    }
    return first;
}

void StepGraph::release(Kept* k) {
    if (k->exec) cu_->cuGraphExecDestroy(k->exec);
    if (k->graph) cu_->cuGraphDestroy(k->graph);
    k->exec = nullptr;
    k->graph = nullptr;
    k->nodes.clear();
    k->recording.clear();
}

CUresult StepGraph::end(CUstream stream) {
    open_ = false;
    ++recordings_;
    if (recording_.commands.empty()) return CUDA_SUCCESS;
    if (!enabled_) return direct(stream);
    // The kept graph of this shape with the fewest changed nodes.
    size_t best = kept_.size(), fewest = std::numeric_limits<size_t>::max();
    for (size_t i = 0; i < kept_.size(); ++i) {
        if (!same_shape(kept_[i].recording, recording_)) continue;
        const size_t d = differences(kept_[i].recording, recording_);
        if (d < fewest) best = i, fewest = d;
    }
    bool rebuild = best == kept_.size();  // no kept graph of this shape
    if (!rebuild && fewest > 0 && update(&kept_[best]) != CUDA_SUCCESS) {
        release(&kept_[best]);  // partly updated: built again, in the same slot
        rebuild = true;
    }
    if (rebuild) {
        if (best == kept_.size() && kept_.size() < kKeptGraphs) {
            kept_.emplace_back();
        } else if (best == kept_.size()) {
            best = 0;  // the graph that ran longest ago makes room
            for (size_t i = 1; i < kept_.size(); ++i)
                if (kept_[i].used < kept_[best].used) best = i;
            release(&kept_[best]);
        }
        if (build(&kept_[best]) != CUDA_SUCCESS) {
            // No graph for this world from now on: the launches go on the stream one by one.
            clear();
            enabled_ = false;
            return direct(stream);
        }
    }
    kept_[best].used = recordings_;
    return cu_->cuGraphLaunch(kept_[best].exec, stream);
}

}  // namespace pbf::cuda
