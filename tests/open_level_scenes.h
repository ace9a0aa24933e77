// Open levels: scenes shared by the CPU suite (test_open_levels.cpp) and its [gpu]
// twin (test_gpu_open_levels.cpp). A block of water collapses into a puddle inside a 2 m box:
// once held by the world's walls, once in an open level (walls 0) 1 km across, 300-450 m from
// the origin, held by five plane colliders where the walls were. Black-box: only the public
// header. Particle radius 0.04 m (spacing 0.08 m, h = 0.16 m): 4000 particles.
#pragma once
#include "support.h"

namespace open_level {

using scene::set3;

constexpr float kR = 0.04f, kBox = 2.0f;

struct Puddle {
    pbf_step_stats stats;  // after the last step
    double mean[3] = {};   // the fluid's centre relative to the box's lower corner
    double spread = 0.0;   // rms distance from that centre in x-z
    double top = 0.0;      // the highest particle above the floor
    uint32_t count = 0;
    bool finite = false;
};

// A plane collider through p whose solid lies against the normal rotation·(0, 1, 0) = n;
// dynamic: the library records the fluid's force on it.
inline pbf_collider_id add_plane(pbf_world_id w, const float p[3], const float q[4], bool dynamic = false) {
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_PLANE;
    c.dynamic = dynamic ? 1u : 0u;
    std::memcpy(c.position, p, sizeof c.position);
    std::memcpy(c.rotation, q, sizeof c.rotation);
    pbf_collider_id id;
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &id));
    return id;
}

// The floor and four sides of the box [o, o + e] as planes (the lid open), floor first.
struct BoxPlanes {
    pbf_collider_id id[5];
};
inline BoxPlanes add_box_planes(pbf_world_id w, const float o[3], const float e[3], bool dynamic = false) {
    const float s = 0.70710678f;
    const float floor_p[3] = {o[0], o[1], o[2]}, floor_q[4] = {0, 0, 0, 1};
    const float lx_p[3] = {o[0], o[1], o[2]}, lx_q[4] = {0, 0, -s, s};         // normal +x
    const float hx_p[3] = {o[0] + e[0], o[1], o[2]}, hx_q[4] = {0, 0, s, s};   // normal -x
    const float lz_p[3] = {o[0], o[1], o[2]}, lz_q[4] = {s, 0, 0, s};          // normal +z
    const float hz_p[3] = {o[0], o[1], o[2] + e[2]}, hz_q[4] = {-s, 0, 0, s};  // normal -z
    return BoxPlanes{{add_plane(w, floor_p, floor_q, dynamic), add_plane(w, lx_p, lx_q, dynamic),
                      add_plane(w, hx_p, hx_q, dynamic), add_plane(w, lz_p, lz_q, dynamic),
                      add_plane(w, hz_p, hz_q, dynamic)}};
}
inline BoxPlanes add_box_planes(pbf_world_id w, const float o[3]) {
    const float e[3] = {kBox, kBox, kBox};
    return add_box_planes(w, o, e);
}

// The puddle after `steps` steps of 1/60 s: in a walled 2 m box at the origin (open = false) or
// in an open level, the box's planes at `origin`; hashed_grid as pbf_world_desc.hashed_grid.
inline Puddle puddle(pbf_backend backend, bool open, int steps, uint32_t hashed_grid = 0) {
    const float o[3] = {open ? 300.0f : 0.0f, open ? -200.0f : 0.0f, open ? 450.0f : 0.0f};
    pbf_world_desc d = scene::tank(backend, kR, kBox, kBox, kBox, 8192);
    d.walls = open ? 0u : 1u;
    d.hashed_grid = hashed_grid;
    const pbf_world_id w = scene::create(d);
    if (open) add_box_planes(w, o);
    // A 1.6 m x 0.8 m x 1.6 m block (4000 particles) 0.16 m above the floor: a puddle ~0.5 m deep.
    // Half a spacing of slack on each axis: 300.2 and 301.8 as floats hold 19.99 spacings.
    scene::fill(w, o[0] + 0.2f, o[1] + 0.16f, o[2] + 0.2f, o[0] + 1.84f, o[1] + 1.0f, o[2] + 1.84f);
    for (int k = 0; k < steps; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    Puddle r;
    r.stats = scene::stats(w);
    const scene::Particles p = scene::read(w);
    r.count = p.count;
    r.finite = scene::all_finite(p);
    for (int a = 0; a < 3; ++a) r.mean[a] = scene::mean_axis(p, a) - o[a];
    for (uint32_t i = 0; i < p.count; ++i) {
        const double dx = p.pos[4 * i] - o[0] - r.mean[0], dz = p.pos[4 * i + 2] - o[2] - r.mean[2];
        r.spread += dx * dx + dz * dz;
        r.top = std::max(r.top, double(p.pos[4 * i + 1] - o[1]));
    }
    r.spread = p.count ? std::sqrt(r.spread / p.count) : 0.0;
    REQUIRE_PBF(pbf_world_destroy(w));
    return r;
}

// The same puddle settles the same with walls and in the open level: the walls' boundary density
// and the planes' are the same half-space integral (the corners differ: walls combine as
// 1 - Π(1 - φ), colliders add), and the hashed grid finds the same neighbours as the dense one.
inline void check_puddle_open_like_box(pbf_backend backend) {
    const int steps = 150;  // 2.5 s: the block collapses, reaches the sides and comes to rest
    const Puddle box = puddle(backend, false, steps), open = puddle(backend, true, steps);
    INFO("box: err " << box.stats.density_error_mean << " max " << box.stats.density_error_max << " ke "
                     << box.stats.kinetic_energy << " mean y " << box.mean[1] << " spread " << box.spread << " top "
                     << box.top);
    INFO("open: err " << open.stats.density_error_mean << " max " << open.stats.density_error_max << " ke "
                      << open.stats.kinetic_energy << " mean y " << open.mean[1] << " spread " << open.spread << " top "
                      << open.top);
    REQUIRE(box.finite);
    REQUIRE(open.finite);
    REQUIRE(open.count == box.count);
    const double spacing = 2.0 * kR;
    // Settled alike: the same height, spread and centre to a fraction of the spacing...
    CHECK(std::fabs(open.mean[1] - box.mean[1]) < 0.1 * spacing);
    CHECK(std::fabs(open.spread - box.spread) < 0.25 * spacing);
    CHECK(std::fabs(open.mean[0] - box.mean[0]) < 0.25 * spacing);
    CHECK(std::fabs(open.mean[2] - box.mean[2]) < 0.25 * spacing);
    CHECK(std::fabs(open.top - box.top) < 0.5 * spacing);
    // ...at the same compression (a double-counted neighbour would show here) and at rest.
    CHECK(std::fabs(open.stats.density_error_mean - box.stats.density_error_mean) <
          0.25 * box.stats.density_error_mean + 1e-3);
    // At rest: under 1 % of the potential energy released (the block's centre started at 0.56 m).
    const double released = box.count * 1000.0 * std::pow(spacing, 3) * 9.81 * (0.56 - box.mean[1]);  // J
    CHECK(box.stats.kinetic_energy < 0.01 * released);
    CHECK(open.stats.kinetic_energy < 0.01 * released);
}

// The same walled puddle on the dense and on the hashed grid: the same neighbours, so the same
// flow up to the order of float sums (the sorted order differs).
inline void check_dense_like_hashed(pbf_backend backend) {
    const int steps = 60;
    const Puddle dense = puddle(backend, false, steps, 0), hashed = puddle(backend, false, steps, 1);
    INFO("dense: err " << dense.stats.density_error_mean << " mean y " << dense.mean[1] << " spread " << dense.spread);
    INFO("hashed: err " << hashed.stats.density_error_mean << " mean y " << hashed.mean[1] << " spread "
                        << hashed.spread);
    REQUIRE(hashed.count == dense.count);
    const double spacing = 2.0 * kR;
    CHECK(std::fabs(hashed.mean[1] - dense.mean[1]) < 0.02 * spacing);
    CHECK(std::fabs(hashed.spread - dense.spread) < 0.05 * spacing);
    CHECK(std::fabs(hashed.stats.density_error_mean - dense.stats.density_error_mean) <
          0.05 * dense.stats.density_error_mean + 1e-5);
}

// Without walls nothing stops a falling block but a collider: free fall (no floor at the old
// domain's y = 0), and a plane collider far below catches it.
inline void check_free_fall(pbf_backend backend) {
    pbf_world_desc d = scene::tank(backend, 0.025f, 1, 1, 1, 4096);
    d.walls = 0;
    const pbf_world_id w = scene::create(d);
    scene::fill(w, 0.0f, 0.5f, 0.0f, 0.4f, 0.9f, 0.4f);
    const double y0 = scene::mean_axis(scene::read(w), 1);
    const int steps = 60;
    for (int k = 0; k < steps; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const scene::Particles p = scene::read(w);
    REQUIRE(scene::all_finite(p));
    const double t = steps * double(kDt), fallen = y0 - scene::mean_axis(p, 1);
    INFO("fell " << fallen << " m in " << t << " s");
    CHECK(std::fabs(fallen - 0.5 * 9.81 * t * t) < 0.02 * 0.5 * 9.81 * t * t);
    for (uint32_t i = 0; i < p.count; ++i) REQUIRE(p.pos[4 * i + 1] < -3.0f);  // all of it below y = 0
    // A floor 20 m down catches it.
    const float floor_p[3] = {0.0f, -20.0f, 0.0f}, up[4] = {0, 0, 0, 1};
    add_plane(w, floor_p, up);
    for (int k = 0; k < 180; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const scene::Particles q = scene::read(w);
    REQUIRE(scene::all_finite(q));
    for (uint32_t i = 0; i < q.count; ++i) REQUIRE(q.pos[4 * i + 1] >= -20.0f + 0.025f * 0.99f);
    CHECK(scene::mean_axis(q, 1) < -20.0 + 0.5);  // lying on it (spreading over an endless floor)
    REQUIRE_PBF(pbf_world_destroy(w));
}

}  // namespace open_level
