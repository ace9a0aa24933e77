// Scenes built through the public C API, shared by the CPU scene tests and the [gpu] tests.
#pragma once
#include <catch2/catch.hpp>
#include <cmath>
#include <algorithm>
#include <cstring>
#include <vector>

#include "pbf_c_api.h"

#define REQUIRE_PBF(call)                                             \
    do {                                                              \
        const pbf_result r_ = (call);                                 \
        INFO(#call << " -> " << pbf_result_string(r_) << ": " << pbf_last_error_message()); \
        REQUIRE(r_ == PBF_OK);                                        \
    } while (0)

namespace scene {

inline void set3(float* dst, float x, float y, float z) {
    dst[0] = x;
    dst[1] = y;
    dst[2] = z;
}

struct Particles {
    std::vector<float> pos, vel;  // xyzw
    std::vector<uint32_t> ids;
    uint32_t count = 0;
};

inline Particles read(pbf_world_id w) {
    Particles p;
    REQUIRE_PBF(pbf_world_get_particle_count(w, &p.count));
    p.pos.resize(size_t(p.count) * 4);
    p.vel.resize(size_t(p.count) * 4);
    p.ids.resize(p.count);
    uint32_t n = 0;
    REQUIRE_PBF(pbf_world_copy_positions(w, p.pos.data(), p.count, &n));
    REQUIRE_PBF(pbf_world_copy_velocities(w, p.vel.data(), p.count, &n));
    REQUIRE_PBF(pbf_world_copy_ids(w, p.ids.data(), p.count, &n));
    return p;
}

inline pbf_step_stats stats(pbf_world_id w) {
    pbf_step_stats s;
    std::memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    REQUIRE_PBF(pbf_world_get_stats(w, &s));
    return s;
}

// A tank of size (lx, ly, lz) at the origin, particle radius r.
inline pbf_world_desc tank(pbf_backend backend, float r, float lx, float ly, float lz, uint32_t capacity) {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = backend;
    d.particle_radius = r;
    d.max_particles = capacity;
    set3(d.domain_min, 0, 0, 0);
    set3(d.domain_max, lx, ly, lz);
    return d;
}

inline uint32_t fill(pbf_world_id w, float x0, float y0, float z0, float x1, float y1, float z1) {
    pbf_block_desc b = pbf_block_desc_default();
    set3(b.box_min, x0, y0, z0);
    set3(b.box_max, x1, y1, z1);
    uint32_t emitted = 0;
    REQUIRE_PBF(pbf_world_emit_block(w, &b, &emitted));
    return emitted;
}

inline bool all_finite(const Particles& p) {
    for (float v : p.pos)
        if (!std::isfinite(v)) return false;
    for (float v : p.vel)
        if (!std::isfinite(v)) return false;
    return true;
}

inline bool inside(const Particles& p, const pbf_world_desc& d, float tolerance) {
    for (uint32_t i = 0; i < p.count; ++i)
        for (int a = 0; a < 3; ++a) {
            const float x = p.pos[4 * i + a];
            if (x < d.domain_min[a] - tolerance || x > d.domain_max[a] + tolerance) return false;
        }
    return true;
}

inline double mean_axis(const Particles& p, int axis) {
    double s = 0;
    for (uint32_t i = 0; i < p.count; ++i) s += p.pos[4 * i + axis];
    return p.count ? s / p.count : 0.0;
}

}  // namespace scene
