// CUDA executor: plain C++ over the CUDA driver, which the library opens at run time
// (cuda_driver.h), launching the kernels embedded in the library (cuda_kernels.cu, cuda_module.h).
// One stream per world, every buffer allocated at creation, kernels queued asynchronously; errors
// are recorded (the first one wins) and returned, never fatal.
#pragma once
#include <string>

#include "cuda_graph.h"
#include "cuda_module.h"
#include "exec_common.h"

namespace pbf {

class CudaExec {
public:
    static constexpr pbf_backend kKind = PBF_BACKEND_CUDA;
    static constexpr int kBlock = PBF_CUDA_BLOCK;

    explicit CudaExec(int device = 0) : device_(device) {}
    ~CudaExec();
    CudaExec(const CudaExec&) = delete;
    CudaExec& operator=(const CudaExec&) = delete;

    Status init(uint32_t capacity, uint32_t num_cells);
    // Makes the world's context current on the calling thread (the primary context of its
    // device, the one the CUDA runtime selects for that device too).
    void activate() {
        if (cu_) record(cu_->cuCtxSetCurrent(k_->context));
    }
    std::string device_name() const { return name_; }
    std::string last_error_text() const {
        return cuda::error_text(first_error_ != CUDA_SUCCESS ? first_error_ : refused_alloc_);
    }
    uint64_t allocated_bytes() const { return bytes_; }

    template <class T>
    T* alloc(size_t count) {
        return static_cast<T*>(alloc_bytes(count * sizeof(T)));
    }
    // An allocation the caller may refuse without harm (a mesh's build): a failure returns null
    // and, unlike alloc, is not recorded as the world's error, so the world steps on.
    template <class T>
    T* try_alloc(size_t count) {
        return static_cast<T*>(try_alloc_bytes(count * sizeof(T)));
    }
    void release(void* p);
    void zero(void* p, size_t bytes);
    void download(void* dst, const void* src, size_t bytes);
    // Queues a host-to-device copy on the stream without waiting for the GPU: src is staged in
    // pinned memory (a ring of slots, each reused once its last copy has run).
    void upload(void* dst, const void* src, size_t bytes);
    // Pinned, mapped host memory that kernels write and the host reads (unified addressing: one
    // pointer serves both).
    template <class T>
    T* alloc_host_visible(size_t count) {
        return static_cast<T*>(alloc_host_bytes(count * sizeof(T)));
    }
    void release_host_visible(void* p);
    // Marks the end of a step's feedback writes; feedback_ready() says, without waiting,
    // whether the latest marked step has finished.
    void feedback_published() {
        flush_recording();
        record(cu_->cuEventRecord(feedback_event_, stream_));
    }
    bool feedback_ready();
    // *out (device memory) = the max over live particles (i < *count) of each field of feedback_sample.
    void reduce_feedback(const HeightFrame& frame, const Vec4* positions, const Vec4* velocities, const uint32_t* count,
                         uint32_t n, FeedbackBits* out);
    void* native_stream() const { return stream_; }
    // A step's launches, recorded between these two and queued as one CUDA graph (cuda_graph.h).
    // Anything else that uses the stream meanwhile (a copy, an event) queues what was recorded
    // before it first, so the order on the stream is always the order of the calls. Not while
    // profiling: the stage marks are events between the launches.
    void record_begin() {
        if (!profiling_ && graph_.enabled()) graph_.begin();
    }
    void record_end() {
        if (graph_.open()) record(graph_.end(stream_));
    }
    // Runs on stream from now on (null: the world's own); work queued before is ordered first.
    Status use_stream(void* stream);

    // op(i) for i in [0, n), one thread each: the op's own kernel (cuda_ops.h lists them).
    template <class Op>
    void for_each(uint32_t n, const Op& op) {
        if (n > 0) launch_op(CudaOp<Op>::index, n, &op, uint32_t(sizeof(Op)));
    }

    // The grid's sort: (cell, slot) pairs by cell, cells in 0..num_cells (num_cells: the dead),
    // slots in increasing order in each cell; `counters` (num_cells + 2 words, clobbered) count
    // the cells: a counting sort into the cells, each cell's few slots then put back in input
    // order (cuda_kernels.cu). The dead come last in no particular order. Result in buffers [1].
    void sort_cells(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t num_cells, uint32_t* counters,
                    int* key_sel, int* value_sel);
    // A stable sort of any (key, value) pairs for builds outside a step (a mesh's field): LSD
    // radix passes of kCudaRadixBits over the bits max_key needs; and a scan; of any length, with
    // temporary storage the caller allocates (alloc) of the size these return.
    size_t sort_temp_bytes(uint32_t n, uint32_t max_key) const;
    size_t scan_temp_bytes(uint32_t n) const;
    void sort_pairs(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t max_key, int* key_sel, int* value_sel,
                    void* temp, size_t temp_bytes);
    void exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n, void* temp, size_t temp_bytes);
    // out[i] = Σ_{k<i} in[k] on the stream; reserve_scan allocates the temporary storage of the
    // longest scan once, at world creation.
    Status reserve_scan(uint32_t max_n);
    void exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n);
    void reduce_stats(const WorldConstants& s, const float* density, const Vec4* velocities, uint32_t n,
                      StatsReadback* out);
    // *out += Σ over live particles (i < *count) of max(ρ/ρ0 - 1, 0); on the stream, no wait.
    void sum_compressive_error(const WorldConstants& s, const float* density, const uint32_t* count, uint32_t n,
                               float* out);

    void timer_begin() {
        flush_recording();
        record(cu_->cuEventRecord(start_, stream_));
    }
    void timer_end() {
        flush_recording();
        record(cu_->cuEventRecord(stop_, stream_));
        timed_ = true;
    }
    float timer_ms();
    Status check(const char* what) const;

    // Stage timeline: a mark records an event that starts a stage (and ends the previous one).
    void profile_enable(bool on);
    void profile_reset() { marks_ = 0; }
    void profile_mark(int stage) {
        if (!profiling_ || marks_ >= kMaxMarks) return;
        mark_stage_[marks_] = stage;
        record(cu_->cuEventRecord(mark_event_[marks_++], stream_));
    }
    void profile_read(float* ms, int stages);

private:
    static constexpr int kMaxMarks = 1024;
    static constexpr int kStagingSlots = 8;
    static constexpr size_t kStagingBytes = 256 * 1024;
    void launch_op(uint32_t index, uint32_t n, const void* op, uint32_t op_bytes);
    template <class... Args>
    void launch(CUfunction f, uint32_t blocks, uint32_t threads, const Args&... args) {
        const cuda::KernelArg list[] = {cuda::KernelArg{&args, uint32_t(sizeof(Args))}...};
        launch_args(f, blocks, threads, list, uint32_t(sizeof...(Args)));
    }
    void launch_args(CUfunction f, uint32_t blocks, uint32_t threads, const cuda::KernelArg* args, uint32_t count);
    // Queues what the open recording holds and keeps recording after it (see record_begin).
    void flush_recording() {
        if (graph_.open()) {
            record(graph_.end(stream_));
            graph_.begin();
        }
    }
    void* alloc_bytes(size_t bytes);
    void* try_alloc_bytes(size_t bytes);
    void* malloc_counted(size_t bytes, CUresult* error);
    void* alloc_host_bytes(size_t bytes);
    void record(CUresult e) {
        if (e != CUDA_SUCCESS && first_error_ == CUDA_SUCCESS) first_error_ = e;
    }

    int device_ = 0;
    const cuda::Driver* cu_ = nullptr;
    const cuda::Kernels* k_ = nullptr;
    bool context_retained_ = false;
    CUresult first_error_ = CUDA_SUCCESS;
    CUresult refused_alloc_ = CUDA_SUCCESS;  // the last try_alloc failure
    CUstream stream_ = nullptr;              // where work is queued: own_stream_ or the caller's
    CUstream own_stream_ = nullptr;          // created and destroyed by the world
    CUevent switch_event_ = nullptr;
    CUevent start_ = nullptr, stop_ = nullptr;
    bool timed_ = false;
    void* staging_[kStagingSlots] = {};
    CUevent staging_event_[kStagingSlots] = {};
    int staging_next_ = 0;
    CUevent feedback_event_ = nullptr;
    bool profiling_ = false;
    int marks_ = 0;
    int mark_stage_[kMaxMarks] = {};
    CUevent mark_event_[kMaxMarks] = {};
    cuda::StepGraph graph_;
    void* grid_scan_temp_ = nullptr;  // the scan of the grid sort's counters
    size_t grid_scan_temp_bytes_ = 0;
    void* scan_temp_ = nullptr;
    size_t scan_temp_bytes_ = 0;
    double* reduce_out_ = nullptr;  // [error_sum, kinetic_energy, error_max bits]
    uint64_t bytes_ = 0;
    std::string name_;
};

}  // namespace pbf
