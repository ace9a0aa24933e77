// Atomic adds usable from both backends (CUDA atomics on the device, GCC builtins on the host).
#pragma once
#include <cstdint>

#include "vec.h"

namespace pbf {

PBF_HD uint32_t atomic_add_u32(uint32_t* addr, uint32_t v) {
#if defined(__CUDA_ARCH__)
    return atomicAdd(addr, v);
#else
    return __atomic_fetch_add(addr, v, __ATOMIC_RELAXED);
#endif
}

PBF_HD void atomic_add_f32(float* addr, float v) {
#if defined(__CUDA_ARCH__)
    atomicAdd(addr, v);
#else
    uint32_t* bits = reinterpret_cast<uint32_t*>(addr);
    uint32_t expected = __atomic_load_n(bits, __ATOMIC_RELAXED);
    for (;;) {
        const uint32_t desired = bits_from_float(float_from_bits(expected) + v);
        if (__atomic_compare_exchange_n(bits, &expected, desired, true, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) return;
    }
#endif
}

PBF_HD void atomic_add_vec3(Vec3* addr, Vec3 v) {
    atomic_add_f32(&addr->x, v.x);
    atomic_add_f32(&addr->y, v.y);
    atomic_add_f32(&addr->z, v.z);
}

// atomic_add_vec3 of a and b for many threads adding to few rows (a collider's force and
// torque): on the device the lanes of a warp that add to the same row (a_addr) sum first and
// one of them adds the sums. Many particles beside one collider (neighbours in the sorted
// order) otherwise queue their atomics on the same words (docs/perf.md, the colliders' broad
// phase); one match for both vectors halves the grouping's cost. The sums' rounding order differs from the atomics'
// (equally arbitrary).
PBF_HD void atomic_add_vec3_pair_shared(Vec3* a_addr, Vec3 a, Vec3* b_addr, Vec3 b) {
#if defined(__CUDA_ARCH__)
    const unsigned peers = __match_any_sync(__activemask(), reinterpret_cast<unsigned long long>(a_addr));
    const unsigned lane = threadIdx.x & 31u;
    const unsigned first = __ffs(peers) - 1u;
    if (peers != (1u << lane)) {
        float v[6] = {a.x, a.y, a.z, b.x, b.y, b.z};
        const unsigned rank = __popc(peers & ((1u << lane) - 1u)), n = __popc(peers);
        if (((peers >> first) & ((peers >> first) + 1u)) == 0u) {
            // Contiguous lanes (the usual case): a tree, each lane adding the one `offset` above.
            for (unsigned offset = 1; offset < n; offset <<= 1) {
                float above[6];
#pragma unroll
                for (int c = 0; c < 6; ++c) above[c] = __shfl_down_sync(peers, v[c], offset);
                if (rank + offset < n) {
#pragma unroll
                    for (int c = 0; c < 6; ++c) v[c] += above[c];
                }
            }
        } else {  // scattered lanes: the first one gathers the others' values one by one
            float sum[6] = {0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
            for (unsigned m = peers; m; m &= m - 1u) {
                const int src = __ffs(m) - 1;
#pragma unroll
                for (int c = 0; c < 6; ++c) sum[c] += __shfl_sync(peers, v[c], src);
            }
#pragma unroll
            for (int c = 0; c < 6; ++c) v[c] = sum[c];
        }
        if (lane != first) return;
        a = Vec3{v[0], v[1], v[2]};
        b = Vec3{v[3], v[4], v[5]};
    }
#endif
    atomic_add_vec3(a_addr, a);
    atomic_add_vec3(b_addr, b);
}

}  // namespace pbf
