// A collider that appears in a settled pool (created there, or teleported from elsewhere), shared
// by the CPU suite (test_realtime.cpp) and its [gpu] twin (test_gpu.cpp). Black-box: only the
// public header.
#pragma once
#include "support.h"

namespace scene {

// A 0.2 m dynamic box appearing half in a settled pool 0.72 x 0.36 x 0.72 m (0.02 m particles),
// its top 4 cm above the water, then 0.1 s of steps of dt. Checks that its first step left no
// particle centre within r of it, that nothing was lost or collapsed onto a shared position, and
// the fastest particle over the 0.1 s (bounds: test_realtime.cpp).
inline void check_collider_appears(pbf_backend backend, bool teleported, float dt) {
    const float half = 0.1f, centre[3] = {0.36f, 0.3f, 0.36f}, identity[4] = {0, 0, 0, 1};
    pbf_world_desc d = tank(backend, 0.02f, 0.72f, 0.8f, 0.72f, 8192);
    pbf_world_id w = create(d);
    const uint32_t n = fill(w, 0, 0, 0, 0.72f, 0.36f, 0.72f);
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_BOX;
    c.motion = PBF_MOTION_KINEMATIC;
    c.dynamic = 1;
    set3(c.half_extents, half, half, half);
    set3(c.position, centre[0], teleported ? 5.0f : centre[1], centre[2]);  // 5 m up: out of the domain's reach
    pbf_collider_id box{};
    if (teleported) REQUIRE_PBF(pbf_world_create_collider(w, &c, &box));
    for (int k = 0; k < 60; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    if (teleported)
        REQUIRE_PBF(pbf_collider_teleport(w, box, centre, identity));
    else
        REQUIRE_PBF(pbf_world_create_collider(w, &c, &box));
    const int steps = int(std::lround(0.1 / dt));
    double fastest = 0.0;
    uint32_t inside_box = 0;
    for (int k = 0; k < steps; ++k) {
        REQUIRE_PBF(pbf_world_step(w, dt));
        const Particles p = read(w);
        for (uint32_t i = 0; i < p.count; ++i) {
            const double v2 = double(p.vel[4 * i]) * p.vel[4 * i] + double(p.vel[4 * i + 1]) * p.vel[4 * i + 1] +
                              double(p.vel[4 * i + 2]) * p.vel[4 * i + 2];
            fastest = std::max(fastest, std::sqrt(v2));
            if (k > 0) continue;
            double outside2 = 0.0;  // squared distance from the box (0 inside it)
            for (int a = 0; a < 3; ++a) {
                const double e = std::max(0.0, std::fabs(double(p.pos[4 * i + a]) - centre[a]) - half);
                outside2 += e * e;
            }
            inside_box += std::sqrt(outside2) < 0.02 - 1e-3 ? 1u : 0u;
        }
    }
    const Particles p = read(w);
    std::set<std::array<float, 3>> positions;
    for (uint32_t i = 0; i < p.count; ++i) positions.insert({p.pos[4 * i], p.pos[4 * i + 1], p.pos[4 * i + 2]});
    pbf_collider_force f{};
    REQUIRE_PBF(pbf_collider_get_force(w, box, &f));
    INFO((teleported ? "teleported" : "created")
         << " into the pool, steps of " << dt << " s: fastest particle " << fastest << " m/s over 0.1 s, " << inside_box
         << " particles within r of the box after its first step, " << positions.size() << " distinct positions of "
         << p.count << ", force on it " << f.force[1] << " N");
    CHECK(inside_box == 0u);
    CHECK(p.count == n);
    CHECK(positions.size() == p.count);
    CHECK(all_finite(p));
    CHECK(fastest < (dt > 1e-3f ? 2.0 : 8.0));
    REQUIRE_PBF(pbf_world_destroy(w));
}

}  // namespace scene
