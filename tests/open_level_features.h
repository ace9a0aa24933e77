// Open levels with the features that read the walls or the neighbour grid: the boundary's
// density, push and friction (boundary viscosity) and adhesion, which must come from colliders
// only; dynamic colliders' forces; diffuse particles and render data, which walk the hashed grid
// from their own positions; a mesh collider far from the origin. Shared by the CPU suite
// (test_open_levels.cpp) and its [gpu] twin. Black-box: only the public header.
#pragma once
#include "mesh_scenes.h"
#include "open_level_scenes.h"

namespace open_level {

// ---- every push comes from a collider ----------------------------------------------------------
// Water 0.32 m deep at rest in a 0.48 m square box whose floor and sides are five dynamic plane
// colliders lying exactly where the world's walls would be (domain 0..0.48). Returns what the
// planes carry, Σ -F_y / (the water's weight), averaged over the last second of three. LDC off,
// as in the coupling suite's support check (its reaction is not recorded yet). With walls the
// walls share the load; without, the planes must carry all of it.
inline double planes_support(pbf_backend backend, bool walls) {
    const float r = 0.02f, e[3] = {0.48f, 0.6f, 0.48f}, o[3] = {0.0f, 0.0f, 0.0f};
    pbf_world_desc d = scene::tank(backend, r, e[0], e[1], e[2], 4096);
    d.walls = walls ? 1u : 0u;
    d.solver.ldc_enabled = 0;
    const pbf_world_id w = scene::create(d);
    const BoxPlanes planes = add_box_planes(w, o, e, true);
    const uint32_t n = scene::fill(w, 0, 0, 0, e[0], 0.32f, e[2]);
    const double weight = n * double(scene::world_info(w).particle_mass) * 9.81;
    double sum = 0.0;
    int k = 0;
    for (int step = 0; step < 180; ++step) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        if (step < 120) continue;
        for (pbf_collider_id c : planes.id) {
            pbf_collider_force f;
            REQUIRE_PBF(pbf_collider_get_force(w, c, &f));
            sum += -f.force[1] / weight;
        }
        ++k;
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    return sum / k;
}

inline void check_planes_carry_all(pbf_backend backend) {
    const double open = planes_support(backend, false), walled = planes_support(backend, true);
    INFO("planes' share of the water's weight: open level " << open << ", with walls at the planes " << walled);
    CHECK(std::fabs(open - 1.0) <= 0.005);  // the coupling suite's bound for its floor and box
    CHECK(walled < 0.9);                    // the walls there would take a share: the check can fail
}

// ---- adhesion and boundary friction need a boundary ----------------------------------------------
// A block of sticky honey (XSPH 0.9, adhesion 3000, cohesion 200: the materials suite's values)
// released 1.4 m up against the corner edge x = 0, z = 0 of a 0.8 x 2 x 0.8 m domain. Returns
// how far its centre fell in 0.5 s. With walls they hold it (adhesion, boundary viscosity);
// without, nothing is there and it falls freely.
inline double honey_fall(pbf_backend backend, bool walls, int steps) {
    pbf_world_desc d = scene::tank(backend, 0.02f, 0.8f, 2.0f, 0.8f, 4096);
    d.walls = walls ? 1u : 0u;
    const pbf_world_id w = scene::create(d);
    pbf_material_desc m = pbf_material_desc_default();
    m.viscosity = 0.9f;
    m.adhesion = 3000.0f;
    m.cohesion = 200.0f;
    pbf_material_id honey;
    REQUIRE_PBF(pbf_world_create_material(w, &m, &honey));
    pbf_block_desc b = pbf_block_desc_default();
    set3(b.box_min, 0.0f, 1.4f, 0.0f);
    set3(b.box_max, 0.16f, 1.64f, 0.16f);
    b.material = honey;
    uint32_t n = 0;
    REQUIRE_PBF(pbf_world_emit_block(w, &b, &n));
    REQUIRE(n > 0u);
    const double y0 = scene::mean_axis(scene::read(w), 1);
    for (int k = 0; k < steps; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const scene::Particles p = scene::read(w);
    REQUIRE(scene::all_finite(p));
    REQUIRE_PBF(pbf_world_destroy(w));
    return y0 - scene::mean_axis(p, 1);
}

inline void check_honey_falls_freely(pbf_backend backend) {
    const int steps = 30;
    const double t = steps * double(kDt), free = 0.5 * 9.81 * t * t;
    const double open = honey_fall(backend, false, steps), walled = honey_fall(backend, true, steps);
    INFO("honey's centre fell " << open << " m in an open level, " << walled << " m against the walls; free fall "
                                << free << " m");
    CHECK(std::fabs(open - free) < 0.02 * free);  // as the open level's free-fall check
    CHECK(walled < 0.8 * free);                   // the walls would hold it: the check can fail
}

// ---- diffuse particles and render data far out ---------------------------------------------------
// The diffuse suite's dam (0.2 x 0.4 x 0.1 m column at one end of a 0.8 x 0.5 x 0.1 m tank,
// radius 0.0125 m, 2 substeps) with smoothed positions and anisotropy, in the world's walls at
// the origin or in an open level 400 m out, held by five planes. After 1.5 s: the diffuse
// particles (well formed, inside the tank) and the render data (finite, near the particles).
struct Splash {
    uint64_t generated = 0;
    uint32_t diffuse = 0;
    bool diffuse_inside = true, render_ok = true;
};
inline Splash splash(pbf_backend backend, bool open) {
    const float e[3] = {0.8f, 0.5f, 0.1f};
    const float o[3] = {open ? 400.0f : 0.0f, open ? -300.0f : 0.0f, open ? 250.0f : 0.0f};
    pbf_world_desc d = scene::tank(backend, 0.0125f, e[0], e[1], e[2], 4096);
    d.walls = open ? 0u : 1u;
    d.solver.substeps = 2;
    d.diffuse.max_diffuse = 20000;
    d.render.flags = PBF_RENDER_SMOOTHED_POSITIONS | PBF_RENDER_ANISOTROPY;
    const pbf_world_id w = scene::create(d);
    if (open) add_box_planes(w, o, e);
    // A third of a spacing of slack: 400.2 and 250.1 as floats hold slightly fewer spacings.
    const float slack = 0.3f * 0.025f;
    REQUIRE(scene::fill(w, o[0], o[1], o[2], o[0] + 0.2f + slack, o[1] + 0.4f + slack, o[2] + 0.1f + slack) == 512u);
    for (int k = 0; k < 90; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    Splash s;
    s.generated = scene::stats(w).diffuse_generated_total;
    const scene::Diffuse df = scene::read_diffuse(w);
    s.diffuse = df.count;
    const float margin = 1e-3f;  // the planes' and walls' contact keep centres one radius inside
    for (uint32_t i = 0; i < df.count; ++i)
        for (int a = 0; a < 3; ++a) {
            const float x = df.pos[4 * i + a] - o[a];
            if (!(x >= -margin && (a == 1 || x <= e[a] + margin))) s.diffuse_inside = false;  // no lid
        }
    const scene::RenderData r = scene::read_render(w);
    const float h = 4.0f * 0.0125f;
    for (uint32_t i = 0; i < r.count; ++i) {
        float d2 = 0.0f;
        for (int a = 0; a < 3; ++a) {
            const float dx = r.smoothed[4 * i + a] - r.pos[4 * i + a];
            d2 += dx * dx;
        }
        if (!(d2 <= h * h)) s.render_ok = false;  // NaN fails too
        for (int k = 0; k < 3; ++k)
            for (int c = 0; c < 4; ++c)
                if (!std::isfinite(r.row(i, k)[c])) s.render_ok = false;
        for (int k = 0; k < 3; ++k)
            if (!(r.row(i, k)[3] > 0.0f)) s.render_ok = false;
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    return s;
}

inline void check_splash_far_out(pbf_backend backend) {
    const Splash box = splash(backend, false), open = splash(backend, true);
    INFO("diffuse generated / live: walls " << box.generated << " / " << box.diffuse << ", open level 400 m out "
                                            << open.generated << " / " << open.diffuse);
    REQUIRE(box.generated > 0u);
    CHECK(open.diffuse_inside);
    CHECK(open.render_ok);
    CHECK(box.render_ok);
    // The same splash: generation is deterministic per particle, but the two flows part (planes
    // and walls combine their boundary density differently at the tank's edges), so the counts
    // agree in size only.
    CHECK(double(open.generated) >= 0.5 * double(box.generated));
    CHECK(double(open.generated) <= 2.0 * double(box.generated));
}

// ---- a mesh container 1 km from the origin ------------------------------------------------------
// The mesh suite's water settled for 2 s in a closed hollow-box mesh (0.32 m square inside), in
// an open level with the mesh collider at (600, -150, 900), against the same water in the world's
// walls (mesh::settled_in_container): the same density and, from the container's floor, height.
inline void check_mesh_container_far_out(pbf_backend backend) {
    using namespace mesh;
    const float inner = 0.16f, wall = 0.08f, o[3] = {600.0f, -150.0f, 900.0f};
    pbf_world_desc d = scene::tank(backend, mesh::kR, 2 * inner, 0.48f, 2 * inner, 8192);
    d.walls = 0;
    const pbf_world_id w = scene::create(d);
    const pbf_mesh_id id = create_mesh(w, hollow_box(inner, 0.24f, inner, wall).desc());
    const float at[3] = {o[0] + inner, o[1] + 0.24f, o[2] + inner};
    mesh_collider(w, id, at);
    scene::fill(w, o[0], o[1], o[2], o[0] + 2 * inner, o[1] + 0.24f, o[2] + 2 * inner);
    for (int k = 0; k < 120; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    Rest open = rest_of(w);
    open.height -= o[1];
    const scene::Particles p = scene::read(w);
    REQUIRE(scene::all_finite(p));
    uint32_t outside = 0;
    for (uint32_t i = 0; i < p.count; ++i)
        for (int a = 0; a < 3; ++a) {
            const float x = p.pos[4 * i + a] - o[a];
            outside += x < 0.0f || x > (a == 1 ? 0.48f : 2 * inner);
        }
    REQUIRE_PBF(pbf_world_destroy(w));
    const Rest walls = settled_in_container(backend, false);
    INFO("density ratio: walls " << walls.density << ", mesh far out " << open.density << "; mean height: walls "
                                 << walls.height << ", mesh far out " << open.height << "; outside " << outside);
    REQUIRE(open.count == walls.count);
    CHECK(outside == 0u);
    // The mesh suite's bounds for the same container at the origin (check_container_rest).
    CHECK(open.density == Approx(walls.density).epsilon(0.01));
    CHECK(std::fabs(open.height - walls.height) < 0.1 * kSpacing);
}

}  // namespace open_level
