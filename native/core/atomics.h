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

}  // namespace pbf
