// Vectors stored in 8 bytes per particle: the length as a float, the direction as two 16-bit
// octahedral coordinates (the unit sphere mapped onto the octahedron |x| + |y| + |z| = 1, its
// lower half folded over the upper, and that projected onto the square [-1, 1]²; Meyer et al.
// 2010, "On floating-point normal vectors"). Quantised to 16 bits, a coordinate moves the
// direction by at most about 5e-5 rad, so a stored vector is within 1e-4 of its length.
// They carry a pass's result to a later pass in two 4-byte buffers that are free meanwhile.
#pragma once
#include "vec.h"

namespace pbf {

// ±1 with the sign of v (+1 for ±0), as the octahedral fold needs.
PBF_HD float sign_not_zero(float v) { return v < 0.0f ? -1.0f : 1.0f; }

// A non-zero direction as two 16-bit octahedral coordinates.
PBF_HD uint32_t pack_direction(Vec3 v) {
    const float inv_l1 = 1.0f / (fabsf(v.x) + fabsf(v.y) + fabsf(v.z));
    float u = v.x * inv_l1, w = v.y * inv_l1;
    if (v.z < 0.0f) {  // the lower half folds over the diagonals
        const float u0 = u;
        u = (1.0f - fabsf(w)) * sign_not_zero(u0);
        w = (1.0f - fabsf(u0)) * sign_not_zero(w);
    }
    const int32_t qu = static_cast<int32_t>(rintf(clampf(u, -1.0f, 1.0f) * 32767.0f));
    const int32_t qw = static_cast<int32_t>(rintf(clampf(w, -1.0f, 1.0f) * 32767.0f));
    return (static_cast<uint32_t>(qu) & 0xffffu) | (static_cast<uint32_t>(qw) << 16);
}

// The unit direction that pack_direction stored.
PBF_HD Vec3 unpack_direction(uint32_t bits) {
    const float u = static_cast<float>(static_cast<int16_t>(bits & 0xffffu)) * (1.0f / 32767.0f);
    const float w = static_cast<float>(static_cast<int16_t>(bits >> 16)) * (1.0f / 32767.0f);
    Vec3 n{u, w, 1.0f - fabsf(u) - fabsf(w)};
    if (n.z < 0.0f) {
        n.x = (1.0f - fabsf(w)) * sign_not_zero(u);
        n.y = (1.0f - fabsf(u)) * sign_not_zero(w);
    }
    return n * inv_sqrt(length_sq(n));
}

struct PackedVectors {
    uint32_t* directions = nullptr;
    float* lengths = nullptr;
    PBF_HD void store(uint32_t i, Vec3 v) const {
        const float len = length(v);
        lengths[i] = len;
        if (len > 0.0f) directions[i] = pack_direction(v);
    }
    PBF_HD Vec3 load(uint32_t i) const {
        const float len = lengths[i];
        return len > 0.0f ? unpack_direction(directions[i]) * len : Vec3{0.0f, 0.0f, 0.0f};
    }
};

}  // namespace pbf
