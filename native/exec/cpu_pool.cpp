// The CPU executor's parallel loops on Windows' thread pool (cpu_pool.h).
#include "cpu_pool.h"

#if defined(_WIN32)
#include <algorithm>
#include <atomic>

#include "../common/windows_lean.h"

namespace pbf::cpu_pool {

int worker_count() {
    static const int count = [] {
        const DWORD n = GetActiveProcessorCount(ALL_PROCESSOR_GROUPS);
        return n > 0 ? static_cast<int>(n) : 1;
    }();
    return count;
}

int chunks_for(int64_t n) { return n <= kParallelMin ? 1 : std::min(worker_count(), kMaxChunks); }

namespace {
struct Job {
    ChunkFn fn;
    void* ctx;
    int64_t n;
    int chunks;
    std::atomic<int> next{0};
};

// Takes chunks until none is left; the pool's callbacks and the calling thread all run this.
void drain(Job& job) {
    for (int k = job.next.fetch_add(1); k < job.chunks; k = job.next.fetch_add(1))
        job.fn(job.ctx, job.n * k / job.chunks, job.n * (k + 1) / job.chunks, k);
}

void CALLBACK work_callback(PTP_CALLBACK_INSTANCE, PVOID job, PTP_WORK) { drain(*static_cast<Job*>(job)); }
}  // namespace

void run(int64_t n, int chunks, ChunkFn fn, void* ctx) {
    if (n <= 0) return;
    chunks = std::clamp(chunks, 1, kMaxChunks);
    Job job{fn, ctx, n, chunks};
    PTP_WORK work = chunks > 1 ? CreateThreadpoolWork(work_callback, &job, nullptr) : nullptr;
    if (work) {
        // One submission per chunk beyond the caller's; a callback that starts after the
        // chunks are gone returns at once.
        for (int k = 1; k < chunks; ++k) SubmitThreadpoolWork(work);
    }
    drain(job);
    if (work) {
        WaitForThreadpoolWorkCallbacks(work, FALSE);
        CloseThreadpoolWork(work);
    }
}

}  // namespace pbf::cpu_pool
#endif
