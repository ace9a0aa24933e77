// Two-way coupling scenes, shared by the CPU suite (test_coupling.cpp) and its [gpu]
// twin (test_gpu_coupling.cpp): a box in a pool at rest (Archimedes), boxes released in a pool
// and integrated by the test the way an engine integrates its rigid bodies, and a paddle.
// Black-box: only the public header. Particle radius 0.02 m (spacing 0.04 m, h = 0.08 m), or a
// Setup's (resolved(): 0.01 or 0.005 m); every box face and pool level lies on the emission
// lattice, so the water starts at rest density around the box.
#pragma once
#include "support.h"

namespace coupling {

using scene::set3;

constexpr float kR = 0.02f, kSpacing = 2.0f * kR, kG = 9.81f, kRho = 1000.0f;

struct Box {
    float lo[3], hi[3];
};

// A tank of lx x ly x lz at the origin holding water to `depth`, except inside `hole`. With
// open_ends the domain reaches 0.2 m beyond x = 0, x = lx and y = 0, where the caller stands
// dynamic planes in for those walls.
// r: the particle radius (every face of hole and the depth on its lattice of spacing 2 r).
inline pbf_world_id pool(pbf_backend backend, float lx, float ly, float lz, float depth, const Box& hole,
                         const pbf_solver_params* solver = nullptr, bool open_ends = false, float r = kR) {
    const double sites = double(lx) * depth * lz / std::pow(2.0 * r, 3);
    pbf_world_desc d = scene::tank(backend, r, lx, ly, lz, std::max(16384u, uint32_t(1.05 * sites) + 1024u));
    if (solver) d.solver = *solver;
    if (open_ends) {
        d.domain_min[0] = d.domain_min[1] = -0.2f;
        d.domain_max[0] = lx + 0.2f;
    }
    pbf_world_id w;
    REQUIRE_PBF(pbf_world_create(&d, &w));
    const float top = std::min(depth, hole.hi[1]);
    auto fill = [&](float x0, float y0, float z0, float x1, float y1, float z1) {
        if (x1 > x0 + 1e-4f && y1 > y0 + 1e-4f && z1 > z0 + 1e-4f) scene::fill(w, x0, y0, z0, x1, y1, z1);
    };
    fill(0, 0, 0, lx, std::min(hole.lo[1], depth), lz);  // below the hole
    fill(0, hole.hi[1], 0, lx, depth, lz);               // above it
    fill(0, hole.lo[1], 0, hole.lo[0], top, lz);         // beside it in x
    fill(hole.hi[0], hole.lo[1], 0, lx, top, lz);
    fill(hole.lo[0], hole.lo[1], 0, hole.hi[0], top, hole.lo[2]);  // beside it in z
    fill(hole.lo[0], hole.lo[1], hole.hi[2], hole.hi[0], top, lz);
    return w;
}

inline pbf_collider_id add_box(pbf_world_id w, const Box& b, pbf_collider_motion motion) {
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_BOX;
    c.motion = motion;
    c.dynamic = 1;
    for (int a = 0; a < 3; ++a) {
        c.position[a] = 0.5f * (b.lo[a] + b.hi[a]);
        c.half_extents[a] = 0.5f * (b.hi[a] - b.lo[a]);
    }
    pbf_collider_id id;
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &id));
    return id;
}

inline pbf_collider_force force(pbf_world_id w, pbf_collider_id c) {
    pbf_collider_force f;
    REQUIRE_PBF(pbf_collider_get_force(w, c, &f));
    return f;
}

inline float particle_mass(pbf_world_id w) {
    pbf_world_info info;
    std::memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    REQUIRE_PBF(pbf_world_get_info(w, &info));
    return info.particle_mass;
}

// A dynamic plane collider through the origin facing up (a floor that measures its load).
inline pbf_collider_id add_dynamic_floor(pbf_world_id w) {
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_PLANE;
    c.dynamic = 1;
    pbf_collider_id floor;
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &floor));
    return floor;
}

// The weight of the world's water (N); *count = its particles.
inline double water_weight(pbf_world_id w, uint32_t* count = nullptr) {
    uint32_t n = 0;
    REQUIRE_PBF(pbf_world_get_particle_count(w, &n));
    if (count) *count = n;
    return n * particle_mass(w) * kG;
}

// The free surface away from a box: the mean over lattice columns farther than `margin` from
// its footprint of the highest particle centre, plus one radius (a rest lattice filled to
// depth d has its top centres at d - r).
inline double surface_level(const scene::Particles& p, const Box& b, float margin, float r = kR) {
    std::map<std::pair<int, int>, float> top;
    for (uint32_t i = 0; i < p.count; ++i) {
        const float x = p.pos[4 * i], y = p.pos[4 * i + 1], z = p.pos[4 * i + 2];
        if (x > b.lo[0] - margin && x < b.hi[0] + margin && z > b.lo[2] - margin && z < b.hi[2] + margin) continue;
        const auto key = std::make_pair(int(std::floor(x / (2.0f * r))), int(std::floor(z / (2.0f * r))));
        auto it = top.find(key);
        if (it == top.end())
            top[key] = y;
        else
            it->second = std::max(it->second, y);
    }
    REQUIRE(!top.empty());
    double sum = 0;
    for (const auto& [key, y] : top) sum += y;
    return sum / double(top.size()) + r;
}

// The solver's defaults, with Local Density Calibration on or off.
inline pbf_solver_params solver(bool ldc) {
    pbf_solver_params s = pbf_world_desc_default().solver;
    s.ldc_enabled = ldc ? 1u : 0u;
    return s;
}

// The particle radius and solver a buoyancy scene runs with.
struct Setup {
    float r = kR;
    pbf_solver_params solver = coupling::solver(true);
};

// The defaults at radius 0.02 m: the 0.24 m box spans 6 particle diameters.
inline Setup coarse(bool ldc = true) { return Setup{kR, solver(ldc)}; }

// What docs/physics.md (Two-way coupling) asks of a scene whose buoyancy should be accurate: the
// body at least 12 particle diameters across (radius r <= 0.01 m for the 0.24 m box), and the
// fluid held near its rest density (adaptive iterations to a 0.3 % mean compression, up to 16
// per substep), since a body feels the weight of the fluid it displaces, compressed or not.
inline Setup resolved(float r) {
    Setup s{r, solver(true)};
    s.solver.iterations = 16;
    s.solver.adaptive_error_target = 0.003f;
    return s;
}

// A pool 0.72 m square, water 0.56 m deep, a 0.24 m box held at rest in its middle, 0.16 m
// (two kernel radii) from the floor and from the surface. Returns the mean upward force over
// the last second of three, and (through *expected) ρ g V.
inline double submerged_box_force(pbf_backend backend, const Setup& setup, double* expected, double* torque) {
    const Box b{{0.24f, 0.16f, 0.24f}, {0.48f, 0.40f, 0.48f}};
    pbf_world_id w = pool(backend, 0.72f, 0.8f, 0.72f, 0.56f, b, &setup.solver, false, setup.r);
    const pbf_collider_id box = add_box(w, b, PBF_MOTION_STATIC);
    double fy = 0, tau = 0;
    int n = 0;
    for (int step = 0; step < 180; ++step) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        if (step < 120) continue;
        const pbf_collider_force f = force(w, box);
        fy += f.force[1];
        tau = std::max(
            tau, double(std::sqrt(f.torque[0] * f.torque[0] + f.torque[1] * f.torque[1] + f.torque[2] * f.torque[2])));
        ++n;
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    *expected = kRho * kG * 0.24 * 0.24 * 0.24;
    *torque = tau;
    return fy / n;
}

// The same pool and box without LDC, on a floor that is a dynamic plane collider (the domain's
// floor 0.2 m lower): returns the mean of (box + floor force) / (the water's weight) over the
// last second of three. Every push the water receives comes from them, so it is 1 when every
// push is recorded and nothing else holds the water up.
inline double support_over_weight(pbf_backend backend, bool ldc) {
    const Box b{{0.24f, 0.16f, 0.24f}, {0.48f, 0.40f, 0.48f}};
    pbf_world_desc d = scene::tank(backend, kR, 0.72f, 0.8f, 0.72f, 16384);
    d.domain_min[1] = -0.2f;
    d.solver = solver(ldc);
    pbf_world_id w;
    REQUIRE_PBF(pbf_world_create(&d, &w));
    scene::fill(w, 0, 0, 0, 0.72f, 0.16f, 0.72f);
    scene::fill(w, 0, 0.40f, 0, 0.72f, 0.56f, 0.72f);
    scene::fill(w, 0, 0.16f, 0, 0.24f, 0.40f, 0.72f);
    scene::fill(w, 0.48f, 0.16f, 0, 0.72f, 0.40f, 0.72f);
    scene::fill(w, 0.24f, 0.16f, 0, 0.48f, 0.40f, 0.24f);
    scene::fill(w, 0.24f, 0.16f, 0.48f, 0.48f, 0.40f, 0.72f);
    const pbf_collider_id box = add_box(w, b, PBF_MOTION_STATIC);
    const pbf_collider_id floor = add_dynamic_floor(w);
    const double weight = water_weight(w);
    double sum = 0;
    int k = 0;
    for (int step = 0; step < 180; ++step) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        if (step < 120) continue;
        sum += -(force(w, box).force[1] + force(w, floor).force[1]) / weight;  // they push the water up
        ++k;
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    return sum / k;
}

// A 0.24 m cube of the given density released with its bottom 1 cm above a pool 0.36 m deep,
// integrated as an engine integrates a body: after each step it reads the fluid's force,
// v += (F/m - g) Δt, y += v Δt (upright, vertical motion only; the floor stops it), and sets the
// next target pose. Records the bottom height and the submerged fraction (surface level minus
// bottom, over the height) averaged over the last `average_s` seconds of `seconds`.
struct Release {
    double bottom = 0, submerged = 0, min_bottom = 1e9;
    double submerged_force_over_weight = 0;  // mean F_y / (m g) while fully under water, clear of the floor
};
inline Release release_box(pbf_backend backend, const Setup& setup, float density, float seconds, float average_s) {
    const float half = 0.12f, lx = 0.72f;
    const Box hole{{0.24f, 1.0f, 0.24f}, {0.48f, 1.0f, 0.48f}};  // above the water: nothing left out
    pbf_world_id w = pool(backend, lx, 0.8f, lx, 0.36f, hole, &setup.solver, false, setup.r);
    Box b{{0.24f, 0.37f, 0.24f}, {0.48f, 0.37f + 2 * half, 0.48f}};
    const pbf_collider_id box = add_box(w, b, PBF_MOTION_KINEMATIC);
    const double mass = density * std::pow(2.0 * half, 3);
    double y = 0.37 + half, vy = 0;
    Release r;
    int submerged_steps = 0;
    const int steps = int(std::lround(seconds / kDt)), averaged = int(std::lround(average_s / kDt));
    for (int step = 0; step < steps; ++step) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        const double reached = y;  // where the step left the box
        const pbf_collider_force f = force(w, box);
        if (reached + half < 0.34 && reached - half > 0.08) {  // top below the surface, two layers above the floor
            r.submerged_force_over_weight += f.force[1] / (mass * kG);
            ++submerged_steps;
        }
        vy += (f.force[1] / mass - kG) * kDt;
        y += vy * kDt;
        if (y - half < 0) {  // the engine's floor contact
            y = half;
            vy = 0;
        }
        const float pos[3] = {0.36f, float(y), 0.36f}, rot[4] = {0, 0, 0, 1};
        REQUIRE_PBF(pbf_collider_set_target_pose(w, box, pos, rot));
        r.min_bottom = std::min(r.min_bottom, y - half);
        if (step >= steps - averaged) {  // the particles and the box at the same instant
            const scene::Particles p = scene::read(w);
            r.bottom += (reached - half) / averaged;
            r.submerged += (surface_level(p, b, 0.12f, setup.r) - (reached - half)) / (2 * half) / averaged;
        }
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    if (submerged_steps) r.submerged_force_over_weight /= submerged_steps;
    return r;
}

// A dynamic plane through (at_x, 0, 0) whose fluid side faces +x (normal_x 1), -x (-1) or +y (0).
inline pbf_collider_id dynamic_plane(pbf_world_id w, float at_x, float normal_x) {
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_PLANE;
    c.dynamic = 1;
    c.position[0] = at_x;
    if (normal_x != 0.0f) {  // the plane's +y turned onto ±x: a quarter turn about z
        c.rotation[2] = -0.70710678f * normal_x;
        c.rotation[3] = 0.70710678f;
    }
    pbf_collider_id id;
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &id));
    return id;
}

// A paddle spanning a 2 m channel's width, in water 0.24 m deep, pushed along x at 0.5 m/s for
// 0.3 s after the water settled. Returns the impulse the fluid gave the paddle (Σ F_x Δt), the
// impulse it gave the channel's ends and floor, and the x momentum the water gained (Σ m v_x after
// minus before): the paddle gave the water that momentum less what the ends and floor gave it.
// The ends and the floor are dynamic planes, so their pushes are measured: though a
// shallow-water wave travels only 0.46 m in 0.3 s, the position solve passes the paddle's push
// through the whole channel within a step (measured, LDC off: the ends took 8.2 N s of the
// paddle's 52), and the floor's boundary viscosity drags on the flow (0.4 N s). Vorticity
// confinement is off: it adds forces that conserve no momentum, by design.
struct PaddleImpulses {
    double paddle = 0, walls = 0, water_momentum = 0;
};
inline PaddleImpulses paddle(pbf_backend backend, bool ldc) {
    pbf_solver_params s = solver(ldc);
    s.vorticity_epsilon = 0.0f;
    const float lx = 2.0f;
    const Box b{{0.96f, 0.0f, -0.1f}, {1.04f, 0.4f, 0.5f}};
    pbf_world_id w = pool(backend, lx, 0.6f, 0.4f, 0.24f, b, &s, true);
    const pbf_collider_id paddle = add_box(w, b, PBF_MOTION_KINEMATIC);
    const pbf_collider_id walls[3] = {dynamic_plane(w, 0.0f, 1.0f), dynamic_plane(w, lx, -1.0f),
                                      dynamic_plane(w, 0.0f, 0.0f)};
    const double m = particle_mass(w);
    auto momentum = [&]() {
        const scene::Particles p = scene::read(w);
        double px = 0;
        for (uint32_t i = 0; i < p.count; ++i) px += m * p.vel[4 * i];
        return px;
    };
    for (int step = 0; step < 90; ++step) REQUIRE_PBF(pbf_world_step(w, kDt));
    const double before = momentum();
    PaddleImpulses r;
    double x = 1.0;
    for (int step = 0; step < 18; ++step) {
        x += 0.5 * kDt;
        const float pos[3] = {float(x), 0.2f, 0.2f}, rot[4] = {0, 0, 0, 1};
        REQUIRE_PBF(pbf_collider_set_target_pose(w, paddle, pos, rot));
        REQUIRE_PBF(pbf_world_step(w, kDt));
        r.paddle += force(w, paddle).force[0] * kDt;
        for (pbf_collider_id c : walls) r.walls += force(w, c).force[0] * kDt;
    }
    r.water_momentum = momentum() - before;
    REQUIRE_PBF(pbf_world_destroy(w));
    return r;
}

// Hundreds of dynamic colliders: 256 boxes of one lattice site (0.04 m cubes) on an 8 x 4 x 8
// lattice (every other site: one particle of water between neighbours, which keeps the scene
// small enough for the CPU suite) in a pool 0.64 m square and 0.4 m deep, LDC off, on a dynamic plane floor (the domain's floor 0.2 m lower). The boxes are
// kinematic and held still the way an engine holds bodies: every frame sets all 256 target
// poses, steps, and reads all 257 forces back. Returns, over the last half second of 1.5 s, the mean
// of (everything's push on the water) / (its weight), and each box's mean upward force.
struct ManyBoxes {
    double support_over_weight = 0;
    std::vector<double> box_up;  // N, per box, in creation order
    double buoyancy = 0;         // ρ g V of one box
};

inline ManyBoxes many_boxes(pbf_backend backend) {
    constexpr int kSites = 16, kDepth = 10, kPer = 8, kLayers = 4;
    const float s = kSpacing;
    pbf_world_desc d = scene::tank(backend, kR, kSites * s, 1.0f, kSites * s, 16384);
    d.domain_min[1] = -0.2f;
    d.solver = solver(false);
    d.max_colliders = 300;
    pbf_world_id w;
    REQUIRE_PBF(pbf_world_create(&d, &w));
    // A site holds a box when its indices are odd (y below 8: two layers of water above).
    auto is_box = [](int x, int y, int z) { return x % 2 == 1 && z % 2 == 1 && y % 2 == 1 && y < 2 * kLayers; };
    for (int y = 0; y < kDepth; ++y)
        for (int z = 0; z < kSites; ++z)
            for (int x = 0; x < kSites;) {  // runs of water sites along x
                if (is_box(x, y, z)) {
                    ++x;
                    continue;
                }
                int end = x;
                while (end < kSites && !is_box(end, y, z)) ++end;
                scene::fill(w, x * s, y * s, z * s, end * s, (y + 1) * s, (z + 1) * s);
                x = end;
            }
    std::vector<pbf_collider_id> boxes;
    std::vector<std::array<float, 3>> at;
    for (int y = 0; y < kDepth; ++y)
        for (int z = 0; z < kSites; ++z)
            for (int x = 0; x < kSites; ++x) {
                if (!is_box(x, y, z)) continue;
                const Box b{{x * s, y * s, z * s}, {(x + 1) * s, (y + 1) * s, (z + 1) * s}};
                boxes.push_back(add_box(w, b, PBF_MOTION_KINEMATIC));
                at.push_back({(x + 0.5f) * s, (y + 0.5f) * s, (z + 0.5f) * s});
            }
    REQUIRE(boxes.size() == size_t(kPer * kLayers * kPer));
    const pbf_collider_id floor = add_dynamic_floor(w);
    uint32_t n = 0;
    const double weight = water_weight(w, &n);
    REQUIRE(n == uint32_t(kSites * kSites * kDepth) - uint32_t(boxes.size()));
    ManyBoxes r;
    r.box_up.assign(boxes.size(), 0.0);
    r.buoyancy = kRho * kG * s * s * s;
    const float still[4] = {0, 0, 0, 1};
    int k = 0;
    for (int step = 0; step < 90; ++step) {
        for (size_t b = 0; b < boxes.size(); ++b)
            REQUIRE_PBF(pbf_collider_set_target_pose(w, boxes[b], at[b].data(), still));
        REQUIRE_PBF(pbf_world_step(w, kDt));
        double push = -force(w, floor).force[1];
        for (size_t b = 0; b < boxes.size(); ++b) {
            const double up = force(w, boxes[b]).force[1];
            push -= up;
            if (step >= 60) r.box_up[b] += up;
        }
        if (step < 60) continue;
        r.support_over_weight += push / weight;
        ++k;
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    r.support_over_weight /= k;
    for (double& f : r.box_up) f /= k;
    return r;
}

}  // namespace coupling

// ---- the checks, run by the CPU suite and its [gpu] twin --------------------------------------
namespace coupling {

inline void check_archimedes(pbf_backend backend, const Setup& setup = coarse()) {
    double expected = 0, torque = 0;
    const double fy = submerged_box_force(backend, setup, &expected, &torque);
    INFO("mean upward force " << fy << " N, rho g V = " << expected << " N, largest |torque| " << torque << " N m");
    CHECK(std::fabs(fy - expected) <= 0.05 * expected);
    // A box symmetric about its centre: no torque beyond noise (1 % of rho g V at half its width).
    CHECK(torque <= 0.01 * expected * 0.12);
}

inline void check_support(pbf_backend backend) {
    const double ratio = support_over_weight(backend, false);
    INFO("(box + floor) / weight of the water, LDC off: " << ratio);
    CHECK(std::fabs(ratio - 1.0) <= 0.005);
}

inline void check_floating(pbf_backend backend, const Setup& setup = coarse()) {
    const Release r = release_box(backend, setup, 500.0f, 5.0f, 2.0f);
    INFO("submerged fraction " << r.submerged << ", bottom " << r.bottom << " m");
    CHECK(std::fabs(r.submerged - 0.5) <= 0.05 * 0.5);
    CHECK(r.min_bottom > 0.05);  // it never touched the floor
}

inline void check_sinking(pbf_backend backend) {
    const Release r = release_box(backend, coarse(), 2000.0f, 3.0f, 0.5f);
    INFO("lowest bottom " << r.min_bottom << " m, mean upward force / weight under water "
                          << r.submerged_force_over_weight);
    // On the floor, with at most one layer of water trapped under it (centres one radius above
    // the floor and one below the box: a gap of one diameter, 0.04 m).
    CHECK(r.min_bottom <= 0.05);
    // Under water the fluid carries about half its weight (rho_w / rho), plus drag: less than all of it.
    CHECK(r.submerged_force_over_weight > 0.3);
    CHECK(r.submerged_force_over_weight < 1.0);
}

inline void check_paddle(pbf_backend backend) {
    const PaddleImpulses r = paddle(backend, true);
    const double given = r.water_momentum + r.walls;  // what the paddle gave the water
    INFO("impulse on the paddle " << r.paddle << " N s, on the ends and floor " << r.walls
                                  << " N s, water momentum gained " << r.water_momentum << " kg m/s");
    CHECK(given > 1.0);  // it did push the water
    CHECK(std::fabs(given + r.paddle) <= 0.05 * given);
}

inline void check_many_boxes(pbf_backend backend) {
    const ManyBoxes r = many_boxes(backend);
    const auto [lo, hi] = std::minmax_element(r.box_up.begin(), r.box_up.end());
    double mean = 0;
    for (double f : r.box_up) mean += f / double(r.box_up.size());
    INFO("(256 boxes + floor) / weight of the water, LDC off: " << r.support_over_weight << "; boxes' upward force "
                                                                << *lo << " .. " << *hi << " N, mean " << mean
                                                                << " N (rho g V = " << r.buoyancy << " N)");
    // Every push lands on its own collider's row: the 257 rows together carry the water exactly
    // (a push lost, or counted on two rows, would show here).
    CHECK(std::fabs(r.support_over_weight - 1.0) <= 0.005);
    // Submerged, the boxes are buoyant as a group (one box of one site is too small for its own
    // force to settle: measured -1.2 .. 1.6 N each on the CPU, mean 0.37 N = 0.59 rho g V).
    CHECK(mean > 0.0);
    // Water touches every box: each row recorded pushes.
    for (size_t b = 0; b < r.box_up.size(); ++b) {
        INFO("box " << b);
        CHECK(r.box_up[b] != 0.0);
    }
}

}  // namespace coupling
