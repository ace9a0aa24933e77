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

// atomic_add_vec3 for many threads adding to few addresses: on the device the lanes of a warp
// that add to the same address sum first and one of them adds the sum. Many particles beside
// one collider (neighbours in the sorted order) otherwise queue their atomics on the same
// words (measured on the H100: 2M same-address reductions per Δ pass with 256 colliders, the
// pass 2.6x slower). The sum's rounding order differs from the atomics' (equally arbitrary).
PBF_HD void atomic_add_vec3_shared(Vec3* addr, Vec3 a) {
#if defined(__CUDA_ARCH__)
    const unsigned peers = __match_any_sync(__activemask(), reinterpret_cast<unsigned long long>(addr));
    const unsigned lane = threadIdx.x & 31u;
    const unsigned first = __ffs(peers) - 1u;
    if (peers != (1u << lane)) {
        const unsigned rank = __popc(peers & ((1u << lane) - 1u)), n = __popc(peers);
        if (((peers >> first) & ((peers >> first) + 1u)) == 0u) {
            // Contiguous lanes (the usual case): a tree, each lane adding the one `offset` above.
            for (unsigned offset = 1; offset < n; offset <<= 1) {
                const float x = __shfl_down_sync(peers, a.x, offset), y = __shfl_down_sync(peers, a.y, offset),
                            z = __shfl_down_sync(peers, a.z, offset);
                if (rank + offset < n) a = a + Vec3{x, y, z};
            }
        } else {  // scattered lanes: the first one gathers the others' values one by one
            Vec3 sum{0.0f, 0.0f, 0.0f};
            for (unsigned m = peers; m; m &= m - 1u) {
                const int src = __ffs(m) - 1;
                sum = sum + Vec3{__shfl_sync(peers, a.x, src), __shfl_sync(peers, a.y, src), __shfl_sync(peers, a.z, src)};
            }
            a = sum;
        }
        if (lane != first) return;
    }
#endif
    atomic_add_vec3(addr, a);
}

}  // namespace pbf
