// CPU executor: the same ops as the GPU, run by a parallel loop over particles (OpenMP; on
// Windows the OS's thread pool, cpu_pool.h).
#pragma once
#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

#include "../core/passes.h"
#include "cpu_pool.h"
#include "exec_common.h"

namespace pbf {

class CpuExec {
public:
    static constexpr pbf_backend kKind = PBF_BACKEND_CPU;

    Status init(uint32_t capacity, uint32_t num_cells);
    void activate() {}
    std::string device_name() const;
    std::string last_error_text() const { return last_error_; }
    uint64_t allocated_bytes() const { return bytes_; }

    template <class T>
    T* alloc(size_t count) {
        return static_cast<T*>(alloc_bytes(count * sizeof(T)));
    }
    // An allocation the caller may refuse (a mesh's build); as alloc here: a failure never
    // stops the world.
    template <class T>
    T* try_alloc(size_t count) {
        return alloc<T>(count);
    }
    void release(void* p);
    void zero(void* p, size_t bytes);
    void download(void* dst, const void* src, size_t bytes);
    void upload(void* dst, const void* src, size_t bytes);
    // Memory both the host and the backend read and write (here: any host memory).
    template <class T>
    T* alloc_host_visible(size_t count) {
        return alloc<T>(count);
    }
    void release_host_visible(void* p) { release(p); }
    // The step's feedback is complete when for_each returns: always ready.
    void feedback_published() {}
    // The CPU runs each op as it is called: nothing to record.
    void record_begin() {}
    void record_end() {}
    bool feedback_ready() const { return true; }
    // *out = the max over live particles (i < *count) of each field of feedback_sample.
    void reduce_feedback(const HeightFrame& frame, const Vec4* positions, const Vec4* velocities, const uint32_t* count,
                         uint32_t n, FeedbackBits* out);
    void* native_stream() const { return nullptr; }
    Status use_stream(void*) {
        return Status::error(PBF_ERROR_INVALID_STATE, "the world runs on the CPU backend: it has no CUDA stream");
    }

    template <class Op>
    void for_each(uint32_t n, const Op& op) {
        const int64_t count = n;
#if defined(_WIN32)
        cpu_pool::for_each(count, op);
#else
#pragma omp parallel for schedule(static) if (count > cpu_pool::kParallelMin)
        for (int64_t i = 0; i < count; ++i) op(static_cast<uint32_t>(i));
#endif
    }

    // The grid's sort: (cell, slot) pairs by cell, cells in 0..num_cells, a stable counting sort
    // with `counters` (num_cells + 2 words, clobbered) as its histogram; result in buffers [1].
    void sort_cells(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t num_cells, uint32_t* counters,
                    int* key_sel, int* value_sel);
    // A stable sort and a scan for builds outside a step (a mesh's field), of any length, with
    // temporary storage the caller allocates (alloc) of the size these return.
    size_t sort_temp_bytes(uint32_t, uint32_t max_key) const { return (size_t(max_key) + 2) * sizeof(uint32_t); }
    size_t scan_temp_bytes(uint32_t) const { return 16; }
    void sort_pairs(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t max_key, int* key_sel, int* value_sel,
                    void* temp, size_t temp_bytes);
    void exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n, void*, size_t) { exclusive_scan(in, out, n); }
    // out[i] = Σ_{k<i} in[k] (sequential: the same result every run). reserve_scan sizes the
    // temporary storage of the longest scan up front (none needed here).
    Status reserve_scan(uint32_t) { return Status{}; }
    void exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n);
    void reduce_stats(const WorldConstants& s, const float* density, const Vec4* velocities, uint32_t n,
                      StatsReadback* out);
    // *out += Σ over live particles (i < *count) of max(ρ/ρ0 - 1, 0).
    void sum_compressive_error(const WorldConstants& s, const float* density, const uint32_t* count, uint32_t n,
                               float* out);

    void timer_begin() { t0_ = std::chrono::steady_clock::now(); }
    void timer_end() {
        last_ms_ = std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - t0_).count();
    }
    float timer_ms() const { return last_ms_; }
    Status check(const char*) const { return Status{}; }

    // Stage timeline: a mark starts a stage (and ends the previous one).
    void profile_enable(bool on) { profiling_ = on; }
    void profile_reset() { marks_ = 0; }
    void profile_mark(int stage) {
        if (!profiling_ || marks_ >= kMaxMarks) return;
        mark_stage_[marks_] = stage;
        mark_time_[marks_++] = std::chrono::steady_clock::now();
    }
    void profile_read(float* ms, int stages) const {
        for (int k = 0; k < stages; ++k) ms[k] = 0.0f;
        for (int k = 0; k + 1 < marks_; ++k)
            if (mark_stage_[k] < stages)
                ms[mark_stage_[k]] +=
                    std::chrono::duration<float, std::milli>(mark_time_[k + 1] - mark_time_[k]).count();
    }

private:
    static constexpr int kMaxMarks = 1024;
    void* alloc_bytes(size_t bytes);
    bool profiling_ = false;
    int marks_ = 0;
    int mark_stage_[kMaxMarks] = {};
    std::chrono::steady_clock::time_point mark_time_[kMaxMarks];
    uint64_t bytes_ = 0;
    uint64_t byte_limit_ = 0;
    std::string last_error_;
    std::chrono::steady_clock::time_point t0_{};
    float last_ms_ = 0.0f;
};

}  // namespace pbf
