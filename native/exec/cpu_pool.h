// Parallel loops of the CPU executor on Windows, on the process's thread pool (the OS's own).
//
// Elsewhere the CPU executor's loops are OpenMP's. On Windows they are not: pbf.dll is built with
// MinGW-w64, whose OpenMP runtime (libgomp on winpthreads) would be linked into the DLL and start
// a second thread runtime inside the game's process; its team start and barriers wait on
// winpthreads semaphores, a path MinGW programs have been seen to hang in at random. The thread
// pool is Windows' own and needs nothing linked in.
#pragma once
#include <cstdint>

namespace pbf::cpu_pool {

// Loops of at most this many iterations run on the calling thread: splitting them costs more
// than it gains.
constexpr int64_t kParallelMin = 2048;
// The most chunks a loop is split into (reductions keep one partial result per chunk).
constexpr int kMaxChunks = 256;

// Chunks for a loop of n iterations: 1 up to kParallelMin, else one per logical processor (at
// most kMaxChunks).
int chunks_for(int64_t n);
// Logical processors the pool may use.
int worker_count();

// Calls fn(ctx, begin, end, k) for chunk k = 0..chunks-1 of [0, n), chunk k being
// [n·k/chunks, n·(k+1)/chunks), on the pool's threads and the calling thread; returns when
// every chunk has finished. Where the pool cannot take work the chunks run on the calling thread.
using ChunkFn = void (*)(void* ctx, int64_t begin, int64_t end, int chunk);
void run(int64_t n, int chunks, ChunkFn fn, void* ctx);

// for_each over [0, n) with op(i): one call per index.
template <class Op>
void for_each(int64_t n, const Op& op) {
    run(
        n, chunks_for(n),
        [](void* ctx, int64_t begin, int64_t end, int) {
            const Op& o = *static_cast<const Op*>(ctx);
            for (int64_t i = begin; i < end; ++i) o(static_cast<uint32_t>(i));
        },
        const_cast<Op*>(&op));
}

}  // namespace pbf::cpu_pool
