// The live particles' buffers in backend memory: which memory each pbf_buffer names, its live
// count and its element size. The solver fills it (Backend::live_buffers); the world passes it on
// to the layers above (World::Mapping, World::live_buffers). It lives in common/ because both
// sides use it and it names only the public header's types, so the layers above the world read
// it without reaching into the solver.
#pragma once
#include <cstdint>

#include "pbf_c_api.h"

namespace pbf {

// Backend memory of the live particles (device memory on CUDA, host memory on the CPU).
struct LiveBuffers {
    void* positions = nullptr;   // Vec4 x, y, z, density ratio
    void* velocities = nullptr;  // Vec4 vx, vy, vz, 0
    uint32_t* ids = nullptr;
    void* smoothed_positions = nullptr;  // Vec4 x̄, ȳ, z̄, density ratio; null when not computed
    void* anisotropy = nullptr;          // 3 Vec4 per particle (axis, radius); null when not computed
    uint8_t* materials = nullptr;        // one byte per particle: its material slot
    const uint32_t* count = nullptr;     // the live count, in the same memory
    uint32_t capacity = 0;
    int32_t cuda_device = -1;  // -1 on the CPU
    // Diffuse particles (null without a diffuse capacity): Vec4 x, y, z, kind and vx, vy, vz,
    // remaining lifetime; their own count and capacity.
    void* diffuse_positions = nullptr;
    void* diffuse_velocities = nullptr;
    const uint32_t* diffuse_count = nullptr;
    uint32_t diffuse_capacity = 0;
};

// The buffer of source (a pbf_buffer) in b; null when the world does not compute it.
inline const void* live_buffer(const LiveBuffers& b, pbf_buffer source) {
    switch (source) {
        case PBF_BUFFER_POSITIONS:
            return b.positions;
        case PBF_BUFFER_VELOCITIES:
            return b.velocities;
        case PBF_BUFFER_IDS:
            return b.ids;
        case PBF_BUFFER_SMOOTHED_POSITIONS:
            return b.smoothed_positions;
        case PBF_BUFFER_ANISOTROPY:
            return b.anisotropy;
        case PBF_BUFFER_DIFFUSE_POSITIONS:
            return b.diffuse_positions;
        case PBF_BUFFER_DIFFUSE_VELOCITIES:
            return b.diffuse_velocities;
        case PBF_BUFFER_MATERIALS:
            return b.materials;
        default:
            return nullptr;
    }
}
inline bool is_diffuse_buffer(pbf_buffer source) {
    return source == PBF_BUFFER_DIFFUSE_POSITIONS || source == PBF_BUFFER_DIFFUSE_VELOCITIES;
}
// The live count of source's particles (the diffuse count for the diffuse buffers).
inline const uint32_t* live_count(const LiveBuffers& b, pbf_buffer source) {
    return is_diffuse_buffer(source) ? b.diffuse_count : b.count;
}
// Bytes per particle of source: 1 (materials), 4 (ids), 48 (anisotropy) or 16.
inline uint32_t buffer_element_bytes(pbf_buffer source) {
    return source == PBF_BUFFER_MATERIALS    ? 1u
           : source == PBF_BUFFER_IDS        ? 4u
           : source == PBF_BUFFER_ANISOTROPY ? 48u
                                             : 16u;
}

}  // namespace pbf
