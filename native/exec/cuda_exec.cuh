// CUDA executor: one stream per world, every buffer allocated at creation, kernels launched
// asynchronously; errors are recorded (first one wins) and returned, never fatal.
#pragma once
#include <cuda_runtime.h>

#include <string>

#include "../core/passes.h"
#include "exec_common.h"

namespace pbf {

#ifndef PBF_CUDA_BLOCK
#define PBF_CUDA_BLOCK 256
#endif

// Resident threads per SM of the architecture being compiled (a request beyond it is ignored
// with a warning).
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ == 750
#define PBF_THREADS_PER_SM 1024
#elif defined(__CUDA_ARCH__) && (__CUDA_ARCH__ == 860 || __CUDA_ARCH__ == 870 || __CUDA_ARCH__ == 890 || __CUDA_ARCH__ >= 1200)
#define PBF_THREADS_PER_SM 1536
#else
#define PBF_THREADS_PER_SM 2048
#endif
constexpr int blocks_that_fit(int wanted) {
    return wanted * PBF_CUDA_BLOCK <= PBF_THREADS_PER_SM ? wanted : PBF_THREADS_PER_SM / PBF_CUDA_BLOCK;
}

// Blocks of PBF_CUDA_BLOCK threads an op's kernel must fit per SM: the register cap that
// __launch_bounds__ derives from it (255 / 1 block unless named here). The passes that walk the
// colliders carry their rare paths (the broad phase's list, the dynamic colliders' warp sums
// of atomics.h) in every world; capped, those paths spill instead of costing every world an
// occupancy step (H100, docs/perf.md: caps at the counts the passes had before the broad phase).
template <class Op>
struct MinBlocksPerSm {
    static constexpr int value = 1;
};
template <>
struct MinBlocksPerSm<LambdaOp> {
    static constexpr int value = blocks_that_fit(5);  // 48 registers on sm_90
};
template <>
struct MinBlocksPerSm<PredictOp> {
    static constexpr int value = blocks_that_fit(4);  // 64
};
template <>
struct MinBlocksPerSm<DeltaOp> {
    static constexpr int value = blocks_that_fit(4);  // 64
};
template <>
struct MinBlocksPerSm<VorticityXsphOp> {
    static constexpr int value = blocks_that_fit(4);  // 64
};

template <class Op>
__global__ void __launch_bounds__(PBF_CUDA_BLOCK, MinBlocksPerSm<Op>::value) for_each_kernel(uint32_t n, Op op) {
    const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < n) op(i);
}

class CudaExec {
public:
    static constexpr pbf_backend kKind = PBF_BACKEND_CUDA;
    static constexpr int kBlock = PBF_CUDA_BLOCK;

    explicit CudaExec(int device = 0) : device_(device) {}
    ~CudaExec();

    Status init(uint32_t capacity, uint32_t num_cells);
    void activate() { record(cudaSetDevice(device_)); }
    std::string device_name() const { return name_; }
    std::string last_error_text() const {
        return cudaGetErrorString(first_error_ != cudaSuccess ? first_error_ : refused_alloc_);
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
    void zero(void* p, size_t bytes) { record(cudaMemsetAsync(p, 0, bytes, stream_)); }
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
    void release_host_visible(void* p) {
        if (p) cudaFreeHost(p);
    }
    // Marks the end of a step's feedback writes; feedback_ready() says, without waiting,
    // whether the latest marked step has finished.
    void feedback_published() { record(cudaEventRecord(feedback_event_, stream_)); }
    bool feedback_ready();
    // *out (device memory) = the max over live particles (i < *count) of each field of feedback_sample.
    void reduce_feedback(const HeightFrame& frame, const Vec4* positions, const Vec4* velocities,
                         const uint32_t* count, uint32_t n, FeedbackBits* out);
    void* native_stream() const { return stream_; }
    // Runs on stream from now on (null: the world's own); work queued before is ordered first.
    Status use_stream(void* stream);

    template <class Op>
    void for_each(uint32_t n, const Op& op) {
        if (n == 0) return;
        for_each_kernel<<<(n + kBlock - 1) / kBlock, kBlock, 0, stream_>>>(n, op);
        record(cudaGetLastError());
    }

    void sort_pairs(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t max_key, int* key_sel,
                    int* value_sel);
    // The same sort and scan for builds outside a step (a mesh's field), of any length, with
    // temporary storage the caller allocates (alloc) of the size these return.
    size_t sort_temp_bytes(uint32_t n, uint32_t max_key);
    size_t scan_temp_bytes(uint32_t n);
    void sort_pairs(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t max_key, int* key_sel,
                    int* value_sel, void* temp, size_t temp_bytes);
    void exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n, void* temp, size_t temp_bytes);
    // out[i] = Σ_{k<i} in[k] on the stream (CUB); reserve_scan allocates the temporary storage
    // of the longest scan once, at world creation.
    Status reserve_scan(uint32_t max_n);
    void exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n);
    void reduce_stats(const WorldConstants& s, const float* density, const Vec4* velocities, uint32_t n,
                      StatsReadback* out);
    // *out += Σ over live particles (i < *count) of max(ρ/ρ0 - 1, 0); on the stream, no wait.
    void sum_compressive_error(const WorldConstants& s, const float* density, const uint32_t* count, uint32_t n,
                               float* out);

    void timer_begin() { record(cudaEventRecord(start_, stream_)); }
    void timer_end() {
        record(cudaEventRecord(stop_, stream_));
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
        record(cudaEventRecord(mark_event_[marks_++], stream_));
    }
    void profile_read(float* ms, int stages);

private:
    static constexpr int kMaxMarks = 1024;
    static constexpr int kStagingSlots = 8;
    static constexpr size_t kStagingBytes = 256 * 1024;
    void* alloc_bytes(size_t bytes);
    void* try_alloc_bytes(size_t bytes);
    void* malloc_counted(size_t bytes, cudaError_t* error);
    cudaError_t refused_alloc_ = cudaSuccess;  // the last try_alloc failure
    void* alloc_host_bytes(size_t bytes);
    void* staging_[kStagingSlots] = {};
    cudaEvent_t staging_event_[kStagingSlots] = {};
    int staging_next_ = 0;
    cudaEvent_t feedback_event_ = nullptr;
    bool profiling_ = false;
    int marks_ = 0;
    int mark_stage_[kMaxMarks] = {};
    cudaEvent_t mark_event_[kMaxMarks] = {};
    void record(cudaError_t e) {
        if (e != cudaSuccess && first_error_ == cudaSuccess) first_error_ = e;
    }
    int device_ = 0;
    cudaStream_t stream_ = nullptr;      // where work is queued: own_stream_ or the caller's
    cudaStream_t own_stream_ = nullptr;  // created and destroyed by the world
    cudaEvent_t switch_event_ = nullptr;
    cudaEvent_t start_ = nullptr, stop_ = nullptr;
    bool timed_ = false;
    void* sort_temp_ = nullptr;
    size_t sort_temp_bytes_ = 0;
    void* scan_temp_ = nullptr;
    size_t scan_temp_bytes_ = 0;
    double* reduce_out_ = nullptr;  // [error_sum, kinetic_energy, error_max bits]
    uint64_t bytes_ = 0;
    std::string name_;
    cudaError_t first_error_ = cudaSuccess;
};

}  // namespace pbf
