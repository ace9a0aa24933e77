// The CPU executor (cpu_exec.h): memory, the counting sort and the reductions.
#include <cstdlib>
#include <cstring>
#include <new>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "cpu_exec.h"

#include "../common/windows_lean.h"
#if !defined(_WIN32)
#include <unistd.h>
#endif

namespace pbf {

// Physical memory in bytes; 0 where it cannot be found out.
static uint64_t physical_memory_bytes() {
#if defined(_WIN32)
    MEMORYSTATUSEX status;
    status.dwLength = sizeof status;
    return GlobalMemoryStatusEx(&status) ? uint64_t(status.ullTotalPhys) : 0;
#else
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    return (pages > 0 && page > 0) ? uint64_t(pages) * uint64_t(page) : 0;
#endif
}

Status CpuExec::init(uint32_t, uint32_t) {
    // Refuse worlds that would not fit in physical memory rather than let the OS kill the
    // process later when the pages are touched.
    const uint64_t physical = physical_memory_bytes();
    byte_limit_ = physical > 0 ? physical / 4 * 3 : UINT64_MAX;
    return Status{};
}

std::string CpuExec::device_name() const { return cpu_device_name(); }

std::string cpu_device_name() {
#if defined(_WIN32)
    return "CPU (" + std::to_string(cpu_pool::worker_count()) + " threads)";
#elif defined(_OPENMP)
    return "CPU (" + std::to_string(omp_get_max_threads()) + " threads)";
#else
    return "CPU (1 thread)";
#endif
}

void* CpuExec::alloc_bytes(size_t bytes) {
    if (bytes_ + bytes > byte_limit_) {
        last_error_ = "host memory limit (3/4 of physical memory) exceeded";
        return nullptr;
    }
    void* p = ::operator new(bytes == 0 ? 16 : bytes, std::align_val_t(64), std::nothrow);
    if (!p) {
        last_error_ = "host allocation of " + std::to_string(bytes) + " bytes failed";
        return nullptr;
    }
    bytes_ += bytes;
    return p;
}

void CpuExec::release(void* p) {
    if (p) ::operator delete(p, std::align_val_t(64));
}

void CpuExec::zero(void* p, size_t bytes) { std::memset(p, 0, bytes); }
void CpuExec::upload(void* dst, const void* src, size_t bytes) {
    if (bytes) std::memcpy(dst, src, bytes);
}

void CpuExec::reduce_feedback(const HeightFrame& frame, const Vec4* positions, const Vec4* velocities,
                              const uint32_t* count, uint32_t n, FeedbackBits* out) {
    const uint32_t live = std::min(n, *count);
    FeedbackSample m{0.0f, 0.0f, 0.0f};
    for (uint32_t i = 0; i < live; ++i) {
        const FeedbackSample f = feedback_sample(frame, positions[i], velocities[i]);
        m = FeedbackSample{fmaxf(m.speed, f.speed), fmaxf(m.top, f.top), fmaxf(m.below, f.below)};
    }
    *out = FeedbackBits{bits_from_float(m.speed), bits_from_float(m.top), bits_from_float(m.below)};
}
void CpuExec::download(void* dst, const void* src, size_t bytes) {
    if (bytes) std::memcpy(dst, src, bytes);
}

namespace {
// Stable counting sort into buffers [1] with histogram (max key + 2 counters).
void counting_sort(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t* histogram, size_t counters) {
    std::fill(histogram, histogram + counters, 0u);
    for (uint32_t i = 0; i < n; ++i) ++histogram[keys[0][i] + 1];
    for (size_t c = 1; c < counters; ++c) histogram[c] += histogram[c - 1];
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t dst = histogram[keys[0][i]]++;
        keys[1][dst] = keys[0][i];
        values[1][dst] = values[0][i];
    }
}
}  // namespace

void CpuExec::sort_cells(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t num_cells, uint32_t* counters,
                         int* key_sel, int* value_sel) {
    counting_sort(keys, values, n, counters, size_t(num_cells) + 2);
    *key_sel = *value_sel = 1;
}

void CpuExec::sort_pairs(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t max_key, int* key_sel,
                         int* value_sel, void* temp, size_t temp_bytes) {
    (void)temp_bytes;
    counting_sort(keys, values, n, static_cast<uint32_t*>(temp), size_t(max_key) + 2);
    *key_sel = *value_sel = 1;
}

void CpuExec::exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n) {
    uint32_t sum = 0;
    for (uint32_t i = 0; i < n; ++i) {
        const uint32_t v = in[i];
        out[i] = sum;
        sum += v;
    }
}

void CpuExec::reduce_stats(const WorldConstants& s, const float* density, const Vec4* velocities, uint32_t n,
                           StatsReadback* out) {
    double error_sum = 0.0, ke = 0.0;
    float error_max = 0.0f;
    const int64_t count = n;
#if defined(_WIN32)
    // One partial per chunk, summed in chunk order.
    struct Part {
        const WorldConstants* s;
        const float* density;
        const Vec4* velocities;
        double error_sum, ke;
        float error_max;
    };
    Part parts[cpu_pool::kMaxChunks];
    const int chunks = cpu_pool::chunks_for(count);
    for (int k = 0; k < chunks; ++k) parts[k] = Part{&s, density, velocities, 0.0, 0.0, 0.0f};
    cpu_pool::run(
        count, chunks,
        [](void* ctx, int64_t begin, int64_t end, int k) {
            Part& p = static_cast<Part*>(ctx)[k];
            for (int64_t i = begin; i < end; ++i) {
                const ParticleStats ps = particle_stats(*p.s, p.density[i], p.velocities[i]);
                p.error_sum += ps.compressive_error;
                p.ke += ps.kinetic_energy;
                p.error_max = fmaxf(p.error_max, ps.compressive_error);
            }
        },
        parts);
    for (int k = 0; k < chunks; ++k) {
        error_sum += parts[k].error_sum;
        ke += parts[k].ke;
        error_max = fmaxf(error_max, parts[k].error_max);
    }
#else
    // The maximum is taken per thread and merged in a critical section rather than with
    // reduction(max:), which needs OpenMP 3.1 (MSVC's /openmp is 2.0); the result is the same.
#pragma omp parallel if (count > cpu_pool::kParallelMin)
    {
        float thread_max = 0.0f;
#pragma omp for reduction(+ : error_sum, ke)
        for (int64_t i = 0; i < count; ++i) {
            const ParticleStats ps = particle_stats(s, density[i], velocities[i]);
            error_sum += ps.compressive_error;
            ke += ps.kinetic_energy;
            thread_max = fmaxf(thread_max, ps.compressive_error);
        }
#pragma omp critical(pbf_reduce_stats_max)
        error_max = fmaxf(error_max, thread_max);
    }
#endif
    out->error_sum = error_sum;
    out->kinetic_energy = ke;
    out->error_max = error_max;
}

void CpuExec::sum_compressive_error(const WorldConstants& s, const float* density, const uint32_t* count, uint32_t n,
                                    float* out) {
    const int64_t live = std::min(n, *count);
    double sum = 0.0;
#if defined(_WIN32)
    struct Part {
        const float* density;
        float inv_rest_density;
        double sum;
    };
    Part parts[cpu_pool::kMaxChunks];
    const int chunks = cpu_pool::chunks_for(live);
    for (int k = 0; k < chunks; ++k) parts[k] = Part{density, s.inv_rest_density, 0.0};
    cpu_pool::run(
        live, chunks,
        [](void* ctx, int64_t begin, int64_t end, int k) {
            Part& p = static_cast<Part*>(ctx)[k];
            for (int64_t i = begin; i < end; ++i) p.sum += fmaxf(p.density[i] * p.inv_rest_density - 1.0f, 0.0f);
        },
        parts);
    for (int k = 0; k < chunks; ++k) sum += parts[k].sum;
#else
#pragma omp parallel for reduction(+ : sum) if (live > cpu_pool::kParallelMin)
    for (int64_t i = 0; i < live; ++i) sum += fmaxf(density[i] * s.inv_rest_density - 1.0f, 0.0f);
#endif
    *out += static_cast<float>(sum);
}

}  // namespace pbf
