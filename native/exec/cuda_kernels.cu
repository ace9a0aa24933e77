// Every kernel of the CUDA backend, compiled once by nvcc into the fatbin that the library embeds
// (no host code here: the host side is plain C++ that launches these by name through the driver,
// cuda_exec.cpp). Names are extern "C" so that they are the same in every build.
#include <cub/block/block_load.cuh>
#include <cub/block/block_radix_sort.cuh>
#include <cub/block/block_reduce.cuh>
#include <cub/block/block_scan.cuh>
#include <cub/block/block_store.cuh>

#include "cuda_ops.h"

namespace pbf {

// Resident threads per SM of the architecture being compiled (a request beyond it is ignored
// with a warning).
#if defined(__CUDA_ARCH__) && __CUDA_ARCH__ == 750
#define PBF_THREADS_PER_SM 1024
#elif defined(__CUDA_ARCH__) && \
    (__CUDA_ARCH__ == 860 || __CUDA_ARCH__ == 870 || __CUDA_ARCH__ == 890 || __CUDA_ARCH__ >= 1200)
#define PBF_THREADS_PER_SM 1536
#else
#define PBF_THREADS_PER_SM 2048
#endif
constexpr int blocks_that_fit(int wanted) {
    return wanted * PBF_CUDA_BLOCK <= PBF_THREADS_PER_SM ? wanted : PBF_THREADS_PER_SM / PBF_CUDA_BLOCK;
}

// Blocks of PBF_CUDA_BLOCK threads an op's kernel must fit per SM: the register cap that
// __launch_bounds__ derives from it (255 / 1 block unless named here). The passes that walk the
// colliders carry their rare paths (the broad phase's list, the dynamic colliders' warp sums of
// atomics.h) in every world; capped, those paths spill instead of costing every world an
// occupancy step (docs/perf.md).
template <class Op>
struct MinBlocksPerSm {
    static constexpr int value = 1;
};
template <bool kPlain>
struct MinBlocksPerSm<LambdaPass<kPlain>> {
    static constexpr int value = blocks_that_fit(5);  // 48 registers on sm_90
};
template <>
struct MinBlocksPerSm<PredictOp> {
    static constexpr int value = blocks_that_fit(4);  // 64
};
template <bool kPlain, bool kSplit, bool kScorrBounded>
struct MinBlocksPerSm<DeltaPass<kPlain, kSplit, kScorrBounded>> {
    static constexpr int value = blocks_that_fit(4);  // 64
};
template <bool kPlain>
struct MinBlocksPerSm<VorticityXsphPass<kPlain>> {
    static constexpr int value = blocks_that_fit(4);  // 64
};

}  // namespace pbf

using namespace pbf;

// ---- the ops: one thread per index ----------------------------------------------------------
#define PBF_OP_KERNEL(name, ...)                                                                     \
    extern "C" __global__ void __launch_bounds__(PBF_CUDA_BLOCK, MinBlocksPerSm<__VA_ARGS__>::value) \
        pbf_op_##name(uint32_t n, __VA_ARGS__ op) {                                                  \
        const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;                                    \
        if (i < n) op(i);                                                                            \
    }
PBF_CUDA_OPS(PBF_OP_KERNEL)
#undef PBF_OP_KERNEL

// The layout nvcc gave each op (and each struct the utility kernels take by value), for the host's
// check at load (cuda_ops.h).
#define PBF_OP_LAYOUT(name, ...) {uint32_t(sizeof(__VA_ARGS__)), uint32_t(alignof(__VA_ARGS__))},
extern "C" __constant__ CudaOpLayout pbf_op_layout[kCudaOpCount + 3] = {
    PBF_CUDA_OPS(PBF_OP_LAYOUT){uint32_t(sizeof(WorldConstants)), uint32_t(alignof(WorldConstants))},
    {uint32_t(sizeof(HeightFrame)), uint32_t(alignof(HeightFrame))},
    {uint32_t(kCudaOpCount), uint32_t(PBF_CUDA_BLOCK)},
};
#undef PBF_OP_LAYOUT

// ---- exclusive scan of uint32: tile sums, a one-block scan of them, then each tile ----------
namespace {
using ScanLoad = cub::BlockLoad<uint32_t, kCudaScanBlock, kCudaScanItems, cub::BLOCK_LOAD_WARP_TRANSPOSE>;
using ScanStore = cub::BlockStore<uint32_t, kCudaScanBlock, kCudaScanItems, cub::BLOCK_STORE_WARP_TRANSPOSE>;
using ScanBlock = cub::BlockScan<uint32_t, kCudaScanBlock>;
using SumBlock = cub::BlockReduce<uint32_t, kCudaScanBlock>;
}  // namespace

// partials[b] = the sum of tile b of in[0, n).
extern "C" __global__ void __launch_bounds__(kCudaScanBlock)
    pbf_scan_reduce(const uint32_t* in, uint32_t n, uint32_t* partials) {
    const uint64_t base = uint64_t(blockIdx.x) * kCudaScanTile;
    uint32_t sum = 0;
#pragma unroll
    for (int k = 0; k < kCudaScanItems; ++k) {
        const uint64_t i = base + uint64_t(k) * kCudaScanBlock + threadIdx.x;
        if (i < n) sum += in[i];
    }
    __shared__ typename SumBlock::TempStorage temp;
    const uint32_t total = SumBlock(temp).Sum(sum);
    if (threadIdx.x == 0) partials[blockIdx.x] = total;
}

namespace {
// data[0, count) := its exclusive scan, by one block, a tile at a time; returns its sum (to every
// thread).
__device__ uint32_t scan_in_place(uint32_t* data, uint32_t count) {
    __shared__ union {
        typename ScanLoad::TempStorage load;
        typename ScanStore::TempStorage store;
        typename ScanBlock::TempStorage scan;
    } temp;
    uint32_t carry = 0;
    for (uint32_t base = 0; base < count; base += kCudaScanTile) {
        const int valid = int(min(count - base, uint32_t(kCudaScanTile)));
        uint32_t items[kCudaScanItems];
        ScanLoad(temp.load).Load(data + base, items, valid, 0u);
        __syncthreads();
        uint32_t aggregate = 0;
        ScanBlock(temp.scan).ExclusiveSum(items, items, aggregate);
        __syncthreads();
#pragma unroll
        for (int k = 0; k < kCudaScanItems; ++k) items[k] += carry;
        ScanStore(temp.store).Store(data + base, items, valid);
        __syncthreads();
        carry += aggregate;
    }
    return carry;
}
}  // namespace

// partials[0, count) := their exclusive scan, by one block.
extern "C" __global__ void __launch_bounds__(kCudaScanBlock) pbf_scan_spine(uint32_t* partials, uint32_t count) {
    scan_in_place(partials, count);
}

// out = the exclusive scan of in[0, n), each tile offset by its scanned partial. out may be in.
extern "C" __global__ void __launch_bounds__(kCudaScanBlock)
    pbf_scan_downsweep(const uint32_t* in, uint32_t* out, uint32_t n, const uint32_t* partials) {
    __shared__ union {
        typename ScanLoad::TempStorage load;
        typename ScanStore::TempStorage store;
        typename ScanBlock::TempStorage scan;
    } temp;
    const uint64_t base = uint64_t(blockIdx.x) * kCudaScanTile;
    const int valid = int(min(uint64_t(n) - base, uint64_t(kCudaScanTile)));
    uint32_t items[kCudaScanItems];
    ScanLoad(temp.load).Load(in + base, items, valid, 0u);
    __syncthreads();
    ScanBlock(temp.scan).ExclusiveSum(items, items);
    __syncthreads();
    const uint32_t offset = partials[blockIdx.x];
#pragma unroll
    for (int k = 0; k < kCudaScanItems; ++k) items[k] += offset;
    ScanStore(temp.store).Store(out + base, items, valid);
}

// ---- LSD radix sort of (key, value) pairs, kCudaRadixBits a pass ----------------------------
// A pass: each tile counts its digits (counts[digit · tiles + tile]); one block per digit scans
// that digit's row across the tiles (each tile's first slot among the digit's pairs) and writes
// the digit's total; each tile then ranks its pairs by the digit, stably (CUB's block radix
// sort), and writes each to its digit's base (the totals' exclusive scan, which every tile
// computes itself) + its tile's offset + its rank. Stable passes from the lowest digit up sort by
// the whole key, equal keys in input order: deterministic.
namespace {
using RadixLoad = cub::BlockLoad<uint32_t, kCudaScanBlock, kCudaScanItems, cub::BLOCK_LOAD_WARP_TRANSPOSE>;
using RadixSort = cub::BlockRadixSort<uint32_t, kCudaScanBlock, kCudaScanItems, uint32_t>;
using DigitScan = cub::BlockScan<uint32_t, kCudaScanBlock>;
static_assert(kCudaRadixDigits == kCudaScanBlock, "one digit counter per thread");

__device__ __forceinline__ uint32_t digit_of(uint32_t key, uint32_t shift) {
    return (key >> shift) & (kCudaRadixDigits - 1);
}

}  // namespace

extern "C" __global__ void __launch_bounds__(kCudaScanBlock)
    pbf_radix_upsweep(const uint32_t* keys, uint32_t n, uint32_t shift, uint32_t* counts) {
    __shared__ uint32_t histogram[kCudaRadixDigits];
    histogram[threadIdx.x] = 0;
    __syncthreads();
    const uint64_t base = uint64_t(blockIdx.x) * kCudaScanTile;
#pragma unroll
    for (int k = 0; k < kCudaScanItems; ++k) {
        const uint64_t i = base + uint64_t(k) * kCudaScanBlock + threadIdx.x;
        if (i < n) atomicAdd(&histogram[digit_of(keys[i], shift)], 1u);
    }
    __syncthreads();
    counts[uint64_t(threadIdx.x) * gridDim.x + blockIdx.x] = histogram[threadIdx.x];
}

// Block d: counts[d · tiles .. (d + 1) · tiles) := their exclusive scan; totals[d] := their sum.
extern "C" __global__ void __launch_bounds__(kCudaScanBlock)
    pbf_radix_scan_rows(uint32_t* counts, uint32_t tiles, uint32_t* totals) {
    const uint32_t total = scan_in_place(counts + uint64_t(blockIdx.x) * tiles, tiles);
    if (threadIdx.x == 0) totals[blockIdx.x] = total;
}

extern "C" __global__ void __launch_bounds__(kCudaScanBlock)
    pbf_radix_downsweep(const uint32_t* keys_in, const uint32_t* values_in, uint32_t* keys_out, uint32_t* values_out,
                        uint32_t n, uint32_t shift, const uint32_t* offsets, const uint32_t* totals) {
    __shared__ union {
        typename RadixLoad::TempStorage load;
        typename RadixSort::TempStorage sort;
        typename DigitScan::TempStorage scan;
    } temp;
    __shared__ uint32_t histogram[kCudaRadixDigits], first[kCudaRadixDigits], slot_base[kCudaRadixDigits];
    const uint64_t base = uint64_t(blockIdx.x) * kCudaScanTile;
    const int valid = int(min(uint64_t(n) - base, uint64_t(kCudaScanTile)));
    uint32_t keys[kCudaScanItems], values[kCudaScanItems];
    // Past the end: the largest key, which the stable sort keeps after every valid pair of the
    // last digit, where the counts below leave it unwritten.
    RadixLoad(temp.load).Load(keys_in + base, keys, valid, 0xFFFFFFFFu);
    __syncthreads();
    RadixLoad(temp.load).Load(values_in + base, values, valid, 0u);
    histogram[threadIdx.x] = 0;
    __syncthreads();
#pragma unroll
    for (int k = 0; k < kCudaScanItems; ++k)
        if (int(threadIdx.x) * kCudaScanItems + k < valid) atomicAdd(&histogram[digit_of(keys[k], shift)], 1u);
    RadixSort(temp.sort).Sort(keys, values, int(shift), int(shift) + kCudaRadixBits);
    __syncthreads();
    // Thread t owns digit t: its first slot in this tile's sorted order, and in the output.
    uint32_t start = 0, digit_base = 0;
    DigitScan(temp.scan).ExclusiveSum(histogram[threadIdx.x], start);
    __syncthreads();
    DigitScan(temp.scan).ExclusiveSum(totals[threadIdx.x], digit_base);
    first[threadIdx.x] = start;
    slot_base[threadIdx.x] = digit_base + offsets[uint64_t(threadIdx.x) * gridDim.x + blockIdx.x];
    __syncthreads();
#pragma unroll
    for (int k = 0; k < kCudaScanItems; ++k) {
        const uint32_t d = digit_of(keys[k], shift);
        const uint32_t rank = threadIdx.x * kCudaScanItems + k - first[d];
        if (rank < histogram[d]) {
            const uint32_t slot = slot_base[d] + rank;
            keys_out[slot] = keys[k];
            values_out[slot] = values[k];
        }
    }
}

// ---- counting sort of the grid's (cell, slot) pairs ---------------------------------------------
// Keys are cells (0..max_key, max_key: the dead) and values the slots in their current order.
// counts[k] = pairs of key k; their exclusive scan gives each key's first slot, one past it the
// next key's; the scatter takes slots from the end of each key's range down (atomicSub), which
// leaves begin[k + 1] = the first slot of key k; each key's few pairs are then put back in input
// order by their values (an insertion sort per key: a cell holds a handful of particles).
extern "C" __global__ void pbf_count_keys(const uint32_t* keys, uint32_t n, uint32_t* counts) {
    const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < n) atomicAdd(&counts[keys[i]], 1u);
}

extern "C" __global__ void pbf_scatter_keys(const uint32_t* keys_in, const uint32_t* values_in, uint32_t* keys_out,
                                            uint32_t* values_out, uint32_t n, uint32_t* begin) {
    const uint32_t i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i >= n) return;
    const uint32_t key = keys_in[i];
    const uint32_t slot = atomicSub(&begin[key + 1], 1u) - 1u;
    keys_out[slot] = key;
    values_out[slot] = values_in[i];
}

// Thread k < max_key: the pairs of key k, [begin[k + 1], begin[k + 2]), in value order. The dead
// (max_key) stay in scatter order: nothing reads them.
extern "C" __global__ void pbf_order_keys(const uint32_t* begin, uint32_t max_key, uint32_t* values) {
    const uint32_t k = blockIdx.x * blockDim.x + threadIdx.x;
    if (k >= max_key) return;
    const uint32_t first = begin[k + 1], end = begin[k + 2];
    for (uint32_t i = first + 1; i < end; ++i) {
        const uint32_t v = values[i];
        uint32_t j = i;
        for (; j > first && values[j - 1] > v; --j) values[j] = values[j - 1];
        values[j] = v;
    }
}

// ---- reductions ---------------------------------------------------------------------------------
namespace {
using ReduceD = cub::BlockReduce<double, kCudaReduceBlock>;
using ReduceF = cub::BlockReduce<float, kCudaReduceBlock>;
__device__ float fmax_op(float a, float b) { return fmaxf(a, b); }
}  // namespace

// out[0] += Σ compressive error, out[1] += Σ kinetic energy, out[2] (float bits) max error.
extern "C" __global__ void __launch_bounds__(kCudaReduceBlock)
    pbf_reduce_stats(WorldConstants s, const float* density, const Vec4* velocities, uint32_t n, double* out) {
    double err = 0.0, ke = 0.0;
    float max_err = 0.0f;
    for (uint32_t i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += gridDim.x * blockDim.x) {
        const ParticleStats ps = particle_stats(s, density[i], velocities[i]);
        err += ps.compressive_error;
        ke += ps.kinetic_energy;
        max_err = fmaxf(max_err, ps.compressive_error);
    }
    __shared__ typename ReduceD::TempStorage t0;
    __shared__ typename ReduceD::TempStorage t1;
    __shared__ typename ReduceF::TempStorage t2;
    const double block_err = ReduceD(t0).Sum(err);
    const double block_ke = ReduceD(t1).Sum(ke);
    const float block_max = ReduceF(t2).Reduce(max_err, fmax_op);
    if (threadIdx.x == 0) {
        atomicAdd(&out[0], block_err);
        atomicAdd(&out[1], block_ke);
        // Non-negative floats order like their bit patterns.
        atomicMax(reinterpret_cast<unsigned int*>(&out[2]), __float_as_uint(block_max));
    }
}

// *out += Σ over live particles (i < *count) of max(ρ/ρ0 - 1, 0).
extern "C" __global__ void __launch_bounds__(kCudaReduceBlock)
    pbf_sum_error(WorldConstants s, const float* density, const uint32_t* count, uint32_t n, float* out) {
    const uint32_t live = min(n, *count);
    float sum = 0.0f;
    for (uint32_t i = blockIdx.x * blockDim.x + threadIdx.x; i < live; i += gridDim.x * blockDim.x)
        sum += fmaxf(density[i] * s.inv_rest_density - 1.0f, 0.0f);
    __shared__ typename ReduceF::TempStorage temp;
    const float block_sum = ReduceF(temp).Sum(sum);
    if (threadIdx.x == 0 && block_sum != 0.0f) atomicAdd(out, block_sum);
}

// *out = max (as float bits) over live particles of each field of feedback_sample.
extern "C" __global__ void __launch_bounds__(kCudaReduceBlock)
    pbf_feedback(HeightFrame frame, const Vec4* positions, const Vec4* velocities, const uint32_t* count, uint32_t n,
                 FeedbackBits* out) {
    const uint32_t live = min(n, *count);
    FeedbackSample m{0.0f, 0.0f, 0.0f};
    for (uint32_t i = blockIdx.x * blockDim.x + threadIdx.x; i < live; i += gridDim.x * blockDim.x) {
        const FeedbackSample f = feedback_sample(frame, positions[i], velocities[i]);
        m = FeedbackSample{fmaxf(m.speed, f.speed), fmaxf(m.top, f.top), fmaxf(m.below, f.below)};
    }
    __shared__ typename ReduceF::TempStorage temp;
    const float speed = ReduceF(temp).Reduce(m.speed, fmax_op);
    __syncthreads();  // temp is reused
    const float top = ReduceF(temp).Reduce(m.top, fmax_op);
    __syncthreads();
    const float below = ReduceF(temp).Reduce(m.below, fmax_op);
    if (threadIdx.x != 0) return;
    // Non-negative floats order like their bits: an integer max is a float max.
    if (speed > 0.0f) atomicMax(&out->speed, __float_as_uint(speed));
    if (top > 0.0f) atomicMax(&out->top, __float_as_uint(top));
    if (below > 0.0f) atomicMax(&out->below, __float_as_uint(below));
}

// ---- the render copy: min(*count, capacity) elements of `words` T each into dst; block 0's
// thread 0 writes the draw arguments (in elements) where draw_args is not null -------------------
namespace {
template <class T>
__device__ void copy_live(const T* __restrict__ src, T* __restrict__ dst, uint32_t words,
                          const uint32_t* __restrict__ count, uint32_t capacity, uint32_t* __restrict__ draw_args,
                          uint32_t draw_vertices) {
    const uint32_t n = min(*count, capacity);
    const uint64_t total = uint64_t(n) * words;
    for (uint64_t i = blockIdx.x * uint64_t(blockDim.x) + threadIdx.x; i < total; i += uint64_t(gridDim.x) * blockDim.x)
        dst[i] = src[i];
    if (draw_args && blockIdx.x == 0 && threadIdx.x == 0) {
        draw_args[0] = draw_vertices ? draw_vertices : n;
        draw_args[1] = draw_vertices ? n : 1u;
        draw_args[2] = 0u;
        draw_args[3] = 0u;
    }
}
}  // namespace

extern "C" __global__ void pbf_copy_live_u32(const uint32_t* src, uint32_t* dst, uint32_t words, const uint32_t* count,
                                             uint32_t capacity, uint32_t* draw_args, uint32_t draw_vertices) {
    copy_live(src, dst, words, count, capacity, draw_args, draw_vertices);
}

extern "C" __global__ void pbf_copy_live_f4(const float4* src, float4* dst, uint32_t words, const uint32_t* count,
                                            uint32_t capacity, uint32_t* draw_args, uint32_t draw_vertices) {
    copy_live(src, dst, words, count, capacity, draw_args, draw_vertices);
}
