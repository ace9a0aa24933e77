// Fluid materials scenes, shared by the CPU suite (test_materials.cpp) and its [gpu]
// twin (test_gpu_materials.cpp): a cube relaxing to a sphere under surface tension, two fluids
// stratifying, a drop hanging under a sphere by adhesion, and viscosity at two substep counts.
// Black-box: only the public header. Particle radius 0.02 m (spacing 0.04 m, h = 0.08 m), a few
// thousand particles at most, so the CPU suite stays fast.
#pragma once
#include "support.h"

namespace materials {

using scene::set3;

constexpr float kR = 0.02f, kSpacing = 2.0f * kR;

inline pbf_world_desc box_world(pbf_backend backend, float lx, float ly, float lz, float gravity) {
    pbf_world_desc d = scene::tank(backend, kR, lx, ly, lz, 8192);
    set3(d.gravity, 0.0f, -gravity, 0.0f);
    return d;
}

inline pbf_material_id add_material(pbf_world_id w, const pbf_material_desc& m) {
    pbf_material_id id{0, 0};
    REQUIRE_PBF(pbf_world_create_material(w, &m, &id));
    return id;
}

inline uint32_t fill(pbf_world_id w, pbf_material_id m, const float lo[3], const float hi[3], float vz = 0.0f) {
    pbf_block_desc b = pbf_block_desc_default();
    std::memcpy(b.box_min, lo, sizeof b.box_min);
    std::memcpy(b.box_max, hi, sizeof b.box_max);
    b.velocity[2] = vz;
    b.material = m;
    uint32_t n = 0;
    REQUIRE_PBF(pbf_world_emit_block(w, &b, &n));
    return n;
}

inline std::vector<uint8_t> read_materials(pbf_world_id w, uint32_t count) {
    std::vector<uint8_t> m(count, 0xFF);
    uint32_t n = 0;
    REQUIRE_PBF(pbf_world_copy_buffer(w, PBF_BUFFER_MATERIALS, m.data(), m.size(), &n));
    REQUIRE(n == count);
    return m;
}

inline void run(pbf_world_id w, float seconds) {
    const int steps = int(std::lround(seconds * 60.0f));
    for (int s = 0; s < steps; ++s) REQUIRE_PBF(pbf_world_step(w, 1.0f / 60.0f));
}

// Runs w for `seconds` at 60 Hz, reads its particles (all finite) and destroys it.
inline scene::Particles finish(pbf_world_id w, float seconds) {
    run(w, seconds);
    const scene::Particles p = scene::read(w);
    REQUIRE(scene::all_finite(p));
    pbf_world_destroy(w);
    return p;
}

// ---- a cube in zero gravity -------------------------------------------------------------------
// Sphericity of a particle cloud: the radius of the sphere of its volume (N spacing³) over its
// largest extent from the centroid (a centre's distance plus one radius). 1 for a ball, 0.74 for
// a cube.
struct Shape {
    double sphericity = 0.0;
    double max_distance = 0.0;  // m, largest centre distance from the centroid
    double equal_radius = 0.0;  // m
};
inline Shape shape_of(const scene::Particles& p) {
    Shape s;
    double c[3] = {0, 0, 0};
    for (int a = 0; a < 3; ++a) c[a] = scene::mean_axis(p, a);
    for (uint32_t i = 0; i < p.count; ++i) {
        const double dx = p.pos[4 * i] - c[0], dy = p.pos[4 * i + 1] - c[1], dz = p.pos[4 * i + 2] - c[2];
        s.max_distance = std::max(s.max_distance, std::sqrt(dx * dx + dy * dy + dz * dz));
    }
    const double volume = double(p.count) * kSpacing * kSpacing * kSpacing;
    s.equal_radius = std::cbrt(3.0 * volume / (4.0 * M_PI));
    s.sphericity = s.equal_radius / (s.max_distance + kR);
    return s;
}

// A 12³ cube (1728 particles) in a 1.2 m box without gravity, after `seconds`.
inline Shape cube_in_zero_gravity(pbf_backend backend, float surface_tension, float cohesion, float seconds,
                                  uint32_t substeps = 0) {
    pbf_world_desc d = box_world(backend, 1.2f, 1.2f, 1.2f, 0.0f);
    d.solver.substeps = substeps;
    pbf_world_id w = scene::create(d);
    pbf_material_desc m = pbf_material_desc_default();
    m.surface_tension = surface_tension;
    m.cohesion = cohesion;
    const pbf_material_id drop = add_material(w, m);
    const float lo[3] = {0.36f, 0.36f, 0.36f}, hi[3] = {0.84f, 0.84f, 0.84f};
    REQUIRE(fill(w, drop, lo, hi) == 1728);
    return shape_of(finish(w, seconds));
}

// ---- two fluids in one tank ---------------------------------------------------------------------
struct Stratification {
    double light_above = 0.0;       // fraction of the light fluid above the interface
    double error_mean[2] = {0, 0};  // mean max(ρ/ρ0 - 1, 0) of the heavy [0] and light [1] fluid
    double error_max[2] = {0, 0};
    double depth_mean[2] = {0, 0};  // the same of the lowest kHeavyCount [0] and the other [1] particles
    double depth_max[2] = {0, 0};
};

// A lock exchange in a tank 0.48 x 0.8 x 0.32 m: a 0.64 m column of fluid of rest density
// `light_density` (768 particles) beside one of the default fluid (1000 kg/m³, 768), both on a
// two-layer film of the default fluid (192), released for `seconds`. The interface is the height
// below which the heavy fluid's volume fits: above the lowest N_heavy particles. The film: a
// light fluid's own layer against the floor stays pinned under the heavy one (47 of 768
// particles in the first layer after 3 s without it: a wall supports a single layer whatever
// its weight, and nothing can get beneath it).
inline constexpr uint32_t kHeavyCount = 960, kLightCount = 768;
inline Stratification two_fluids(pbf_backend backend, float light_density, float seconds, uint32_t ldc = 1) {
    pbf_world_desc d = box_world(backend, 0.48f, 0.8f, 0.32f, 9.81f);
    d.solver.ldc_enabled = ldc;
    pbf_world_id w = scene::create(d);
    pbf_material_desc m = pbf_material_desc_default();
    m.rest_density = light_density;
    m.color[0] = 0.9f;
    const pbf_material_id light = add_material(w, m);
    const float lo_l[3] = {0, 0.08f, 0}, hi_l[3] = {0.24f, 0.72f, 0.32f};
    const float lo_h[3] = {0.24f, 0.08f, 0}, hi_h[3] = {0.48f, 0.72f, 0.32f};
    const float lo_f[3] = {0, 0, 0}, hi_f[3] = {0.48f, 0.08f, 0.32f};
    REQUIRE(fill(w, light, lo_l, hi_l) == 768);
    REQUIRE(fill(w, pbf_material_id{0, 0}, lo_h, hi_h) == 768);
    REQUIRE(fill(w, pbf_material_id{0, 0}, lo_f, hi_f) == 192);
    run(w, seconds);
    const scene::Particles p = scene::read(w);
    REQUIRE(scene::all_finite(p));
    const std::vector<uint8_t> mat = read_materials(w, p.count);
    pbf_world_destroy(w);
    REQUIRE(p.count == kHeavyCount + kLightCount);
    struct Sample {
        float y;
        int light;
        double error;
    };
    std::vector<Sample> by_height;
    Stratification s;
    for (uint32_t i = 0; i < p.count; ++i)
        by_height.push_back(
            {p.pos[4 * i + 1], mat[i] == light.index ? 1 : 0, std::max(0.0, double(p.pos[4 * i + 3]) - 1.0)});
    std::sort(by_height.begin(), by_height.end(), [](const Sample& a, const Sample& b) { return a.y < b.y; });
    uint32_t light_above = 0;
    for (size_t i = 0; i < by_height.size(); ++i) {
        const Sample& q = by_height[i];
        const int upper = i >= kHeavyCount ? 1 : 0;
        if (upper) light_above += q.light;
        s.error_mean[q.light] += q.error;
        s.error_max[q.light] = std::max(s.error_max[q.light], q.error);
        s.depth_mean[upper] += q.error;
        s.depth_max[upper] = std::max(s.depth_max[upper], q.error);
    }
    s.error_mean[0] /= kHeavyCount;
    s.error_mean[1] /= kLightCount;
    s.depth_mean[0] /= kHeavyCount;
    s.depth_mean[1] /= kLightCount;
    s.light_above = double(light_above) / kLightCount;
    return s;
}

// ---- a drop under a sphere --------------------------------------------------------------------
struct Drop {
    double centroid_y = 0.0;  // m
};

// A sphere of radius 0.2 m at (0.4, 0.5, 0.4) in a 0.8 m box; a 4 x 3 x 4 block (48 particles)
// hangs under it, its top layer touching it, under gravity for `seconds`.
inline Drop drop_under_sphere(pbf_backend backend, float adhesion, float cohesion, float seconds) {
    const pbf_world_desc d = box_world(backend, 0.8f, 0.8f, 0.8f, 9.81f);
    pbf_world_id w = scene::create(d);
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_SPHERE;
    c.radius = 0.2f;
    set3(c.position, 0.4f, 0.5f, 0.4f);
    pbf_collider_id sphere;
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &sphere));
    pbf_material_desc m = pbf_material_desc_default();
    m.adhesion = adhesion;
    m.cohesion = cohesion;
    const pbf_material_id drop = add_material(w, m);
    const float lo[3] = {0.32f, 0.18f, 0.32f}, hi[3] = {0.48f, 0.30f, 0.48f};
    REQUIRE(fill(w, drop, lo, hi) == 48);
    Drop r;
    r.centroid_y = scene::mean_axis(finish(w, seconds), 1);
    return r;
}

// ---- viscosity --------------------------------------------------------------------------------
// Two 0.2 x 0.2 x 0.4 m slabs side by side (250 particles each) sliding past each other at
// ±0.5 m/s along z in zero gravity, far from the walls; the fraction of kinetic energy lost
// after `seconds` at a fixed substep count. s_corr off: in zero gravity it sheds particles from
// a free surface at ~0.5 m/s (a relaxing cube without cohesion shows it), which would swamp the
// viscous loss.
inline double shear_loss(pbf_backend backend, float viscosity, uint32_t substeps, float seconds = 0.25f) {
    pbf_world_desc d = box_world(backend, 0.8f, 0.8f, 1.2f, 0.0f);
    d.solver.substeps = substeps;
    d.solver.scorr_k = 0.0f;
    pbf_world_id w = scene::create(d);
    pbf_material_desc m = pbf_material_desc_default();
    m.viscosity = viscosity;
    const pbf_material_id fluid = add_material(w, m);
    const float lo_a[3] = {0.2f, 0.3f, 0.4f}, hi_a[3] = {0.4f, 0.5f, 0.8f};
    const float lo_b[3] = {0.4f, 0.3f, 0.4f}, hi_b[3] = {0.6f, 0.5f, 0.8f};
    REQUIRE(fill(w, fluid, lo_a, hi_a, 0.5f) + fill(w, fluid, lo_b, hi_b, -0.5f) == 500);
    auto kinetic = [&]() {
        const scene::Particles p = scene::read(w);
        double e = 0;
        for (uint32_t i = 0; i < p.count; ++i)
            e +=
                p.vel[4 * i] * p.vel[4 * i] + p.vel[4 * i + 1] * p.vel[4 * i + 1] + p.vel[4 * i + 2] * p.vel[4 * i + 2];
        return e;
    };
    const double e0 = kinetic();
    run(w, seconds);
    const double e1 = kinetic();
    pbf_world_destroy(w);
    return 1.0 - e1 / e0;
}

// A 10 x 3 x 10 slab (300 particles) resting on a kinematic plate (a 0.5 x 0.04 x 0.6 m box) in
// zero gravity, the plate sliding along x at `speed` for `seconds`: the fluid's mean velocity
// along x. No contact presses the fluid on the plate (no friction): only the boundary
// viscosity carries it. s_corr off, as in shear_loss.
inline double carried_by_plate(pbf_backend backend, float viscosity, float speed, float seconds) {
    pbf_world_desc d = box_world(backend, 0.8f, 0.8f, 0.8f, 0.0f);
    d.solver.scorr_k = 0.0f;
    pbf_world_id w = scene::create(d);
    const pbf_collider_id plate = scene::kinematic_box(w, 0.4f, 0.3f, 0.4f, 0.25f, 0.02f, 0.3f);
    pbf_material_desc m = pbf_material_desc_default();
    m.viscosity = viscosity;
    const pbf_material_id fluid = add_material(w, m);
    const float lo[3] = {0.2f, 0.32f, 0.2f}, hi[3] = {0.6f, 0.44f, 0.6f};
    REQUIRE(fill(w, fluid, lo, hi) == 300);
    const int steps = int(std::lround(seconds * 60.0f));
    const float identity[4] = {0, 0, 0, 1};
    for (int k = 1; k <= steps; ++k) {
        const float at[3] = {0.4f + speed * float(k) / 60.0f, 0.3f, 0.4f};
        REQUIRE_PBF(pbf_collider_set_target_pose(w, plate, at, identity));
        REQUIRE_PBF(pbf_world_step(w, 1.0f / 60.0f));
    }
    const scene::Particles p = scene::read(w);
    REQUIRE(scene::all_finite(p));
    pbf_world_destroy(w);
    double vx = 0.0;
    for (uint32_t i = 0; i < p.count; ++i) vx += p.vel[4 * i] / p.count;
    return vx;
}

// A 0.2 x 0.32 x 0.24 m column (5 x 8 x 6 = 240 particles) at the left of a 1.6 x 0.5 x 0.24
// tank collapses for `seconds`: how far its front reached (m) and how high it still stands.
struct Spread {
    double front = 0.0, height = 0.0;
};
inline Spread collapse(pbf_backend backend, float viscosity, float seconds) {
    const pbf_world_desc d = box_world(backend, 1.6f, 0.5f, 0.24f, 9.81f);
    pbf_world_id w = scene::create(d);
    pbf_material_desc m = pbf_material_desc_default();
    m.viscosity = viscosity;
    const pbf_material_id fluid = add_material(w, m);
    const float lo[3] = {0, 0, 0}, hi[3] = {0.2f, 0.32f, 0.24f};
    fill(w, fluid, lo, hi);
    const scene::Particles p = finish(w, seconds);
    Spread s;
    for (uint32_t i = 0; i < p.count; ++i) {
        s.front = std::max(s.front, double(p.pos[4 * i]));
        s.height = std::max(s.height, double(p.pos[4 * i + 1]));
    }
    return s;
}

// ---- the checks, run by both suites --------------------------------------------------------------
inline void check_sphere(pbf_backend backend) {
    const Shape with = cube_in_zero_gravity(backend, 100.0f, 100.0f, 3.0f);
    INFO("with surface tension: sphericity " << with.sphericity << ", farthest " << with.max_distance << " m, R "
                                             << with.equal_radius << " m");
    CHECK(with.sphericity >= 0.95);
    CHECK(with.max_distance <= 1.2 * with.equal_radius);
    const Shape without = cube_in_zero_gravity(backend, 0.0f, 0.0f, 3.0f);
    INFO("without: sphericity " << without.sphericity << ", farthest " << without.max_distance << " m");
    CHECK(without.sphericity < 0.95);
}

inline void check_stratification(pbf_backend backend) {
    const Stratification two = two_fluids(backend, 500.0f, 4.0f);
    const Stratification one = two_fluids(backend, 1000.0f, 4.0f);  // the same scene, one fluid
    INFO("light fluid above the interface " << two.light_above);
    INFO("two fluids: mean error heavy " << two.error_mean[0] << " light " << two.error_mean[1] << ", max "
                                         << two.error_max[0] << " / " << two.error_max[1]);
    INFO("one fluid at the same depths: mean " << one.depth_mean[0] << " / " << one.depth_mean[1] << ", max "
                                               << one.depth_max[0] << " / " << one.depth_max[1]);
    CHECK(two.light_above >= 0.95);
    // Each fluid's density error within the single fluid's at the depths it ends up at.
    CHECK(two.error_mean[0] <= one.depth_mean[0]);
    CHECK(two.error_mean[1] <= one.depth_mean[1]);
    CHECK(two.error_max[0] <= one.depth_max[0]);
    CHECK(two.error_max[1] <= one.depth_max[1]);
}

inline void check_adhesion(pbf_backend backend) {
    const Drop with = drop_under_sphere(backend, 3000.0f, 200.0f, 2.0f);
    const Drop without = drop_under_sphere(backend, 0.0f, 200.0f, 2.0f);
    INFO("centroid height after 2 s (started at 0.24 m, floor at 0): with adhesion "
         << with.centroid_y << " m, without " << without.centroid_y << " m");
    CHECK(with.centroid_y >= 0.20);
    CHECK(without.centroid_y < 0.10);
}

inline void check_viscosity_substeps(pbf_backend backend) {
    const double loss2 = shear_loss(backend, 0.2f, 2), loss8 = shear_loss(backend, 0.2f, 8);
    const double inviscid = shear_loss(backend, 0.0f, 8);
    INFO("energy lost in 0.25 s: " << loss2 << " at 2 substeps, " << loss8 << " at 8, " << inviscid
                                   << " without viscosity");
    CHECK(std::fabs(loss2 - loss8) <= 0.1 * std::max(loss2, loss8));
    CHECK(loss8 > inviscid + 0.1);  // the viscosity, not the solver, dissipates
}

inline void check_honey(pbf_backend backend) {
    const Spread water = collapse(backend, 0.01f, 0.5f), honey = collapse(backend, 0.9f, 0.5f);
    INFO("front after 0.5 s: water " << water.front << " m, honey " << honey.front
                                     << " m (column 0.2 m); highest: water " << water.height << " m, honey "
                                     << honey.height << " m (column 0.32 m)");
    CHECK(honey.front - 0.2 <= 0.5 * (water.front - 0.2));
}

// The boundary viscosity's collider side: a plate sliding under a slab carries honey along and
// leaves water nearly behind.
inline void check_plate_drag(pbf_backend backend) {
    const float speed = 0.1f;
    const double water = carried_by_plate(backend, 0.01f, speed, 1.0f),
                 honey = carried_by_plate(backend, 0.9f, speed, 1.0f);
    INFO("mean velocity along the plate after 1 s (plate " << speed << " m/s): water " << water << ", honey " << honey
                                                           << " m/s");
    CHECK(honey >= 0.5 * speed);
    CHECK(water <= 0.1 * speed);
    CHECK(water >= 0.0);
}

}  // namespace materials
