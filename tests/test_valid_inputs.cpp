// Valid inputs a game sends that the hand-written scenes did not: tiny and huge steps, a fast
// thin plate, two fluids placed heavy over light, small bodies, overlaps no motion made, extreme
// materials, zero gravity, a heavy box on the floor. Black-box through the public header, CPU
// backend. Each bound is a physical one, stated where it is checked (docs/physics_fuzzer.md
// derives the shared ones: the free fall over the scene's height, the at-rest allowance).
#include <algorithm>
#include <array>
#include <initializer_list>
#include <vector>

#include "coupling_scenes.h"
#include "materials_scenes.h"

using namespace scene;

namespace {

constexpr double kG = 9.81;
// The product's at-rest allowance: after any dt a settled pool has no particle faster than
// 1 m/s (README, Physics; tests/test_realtime.cpp).
constexpr double kAtRest = 1.0;

double top_speed(const Particles& p) {
    double top = 0.0;
    for (uint32_t i = 0; i < p.count; ++i)
        top =
            std::max(top, std::sqrt(double(p.vel[4 * i]) * p.vel[4 * i] + double(p.vel[4 * i + 1]) * p.vel[4 * i + 1] +
                                    double(p.vel[4 * i + 2]) * p.vel[4 * i + 2]));
    return top;
}

double top_speed(pbf_world_id w) { return top_speed(read(w)); }

// Ritter's dam-break front, 2√(gH) = √2 · √(2gH): the fastest gravity moves a free surface that
// falls H.
double free_fall_front(double height) { return std::sqrt(2.0) * std::sqrt(2.0 * kG * height); }

// Steps w for `seconds` at dt and returns the fastest particle seen after any of the steps.
double run_top(pbf_world_id w, double seconds, float dt = kDt) {
    double top = 0.0;
    const int steps = int(std::lround(seconds / dt));
    for (int k = 0; k < steps; ++k) {
        REQUIRE_PBF(pbf_world_step(w, dt));
        top = std::max(top, top_speed(w));
    }
    return top;
}

// Emits a block lo..hi moving at v; returns its particle count.
uint32_t throw_block(pbf_world_id w, const float lo[3], const float hi[3], const float v[3]) {
    pbf_block_desc b = pbf_block_desc_default();
    set3(b.box_min, lo[0], lo[1], lo[2]);
    set3(b.box_max, hi[0], hi[1], hi[2]);
    set3(b.velocity, v[0], v[1], v[2]);
    uint32_t n = 0;
    REQUIRE_PBF(pbf_world_emit_block(w, &b, &n));
    return n;
}

// Steps w by each dt in turn and returns the fastest particle seen after any of them.
double top_over(pbf_world_id w, std::initializer_list<float> dts) {
    double top = 0.0;
    for (float dt : dts) {
        REQUIRE_PBF(pbf_world_step(w, dt));
        top = std::max(top, top_speed(w));
    }
    return top;
}

float mass_of(pbf_world_id w) { return world_info(w).particle_mass; }

// A dam break in a 0.6 x 0.6 x 0.15 m tank at 12.5 mm radius (864 particles), 0.4 s in: sloshing.
pbf_world_id stirred_pool() {
    pbf_world_id w = create(tank(PBF_BACKEND_CPU, 0.0125f, 0.6f, 0.6f, 0.15f, 4096));
    fill(w, 0, 0, 0, 0.3f, 0.3f, 0.15f);
    for (int k = 0; k < 24; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    return w;
}

// A pool 0.6 x 0.3 x 0.15 m at 12.5 mm radius (1,728 particles), settled for 1 s.
pbf_world_id settled_pool() {
    pbf_world_id w = create(tank(PBF_BACKEND_CPU, 0.0125f, 0.6f, 0.6f, 0.15f, 4096));
    fill(w, 0, 0, 0, 0.6f, 0.3f, 0.15f);
    for (int k = 0; k < 60; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    return w;
}

// A pool 0.48 x 0.36 x 0.48 m at 0.02 m radius (1,296 particles), settled for 1 s.
pbf_world_id deep_pool() {
    pbf_world_id w = create(tank(PBF_BACKEND_CPU, 0.02f, 0.48f, 0.8f, 0.48f, 4096));
    fill(w, 0, 0, 0, 0.48f, 0.36f, 0.48f);
    for (int k = 0; k < 60; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    return w;
}

// An open level (no walls) in zero gravity on the CPU.
pbf_world_id zero_g_open_world(float radius, uint32_t capacity) {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = PBF_BACKEND_CPU;
    d.particle_radius = radius;
    d.max_particles = capacity;
    d.walls = 0;
    set3(d.gravity, 0, 0, 0);
    return create(d);
}

// A world on the CPU in zero gravity, with a fuzzer world's particles and capacity.
pbf_world_desc zero_g_desc(float radius, float rest_density, uint32_t capacity) {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = PBF_BACKEND_CPU;
    d.particle_radius = radius;
    d.rest_density = rest_density;
    d.max_particles = capacity;
    set3(d.gravity, 0, 0, 0);
    return d;
}

// The same within walls lo..hi.
pbf_world_desc zero_g_box(float radius, float rest_density, uint32_t capacity, const float lo[3], const float hi[3]) {
    pbf_world_desc d = zero_g_desc(radius, rest_density, capacity);
    set3(d.domain_min, lo[0], lo[1], lo[2]);
    set3(d.domain_max, hi[0], hi[1], hi[2]);
    return d;
}

struct Momenta {
    double p[3] = {0, 0, 0}, l[3] = {0, 0, 0}, mass = 0, scale_l = 0, radius = 0;
};

// Linear momentum, and angular momentum about the centre of mass; scale_l = Σ m |x - c| |v|.
Momenta momenta(const Particles& q, double m) {
    Momenta r;
    double c[3] = {0, 0, 0};
    for (uint32_t i = 0; i < q.count; ++i)
        for (int a = 0; a < 3; ++a) c[a] += q.pos[4 * i + a] / double(q.count);
    for (uint32_t i = 0; i < q.count; ++i) {
        const double x[3] = {q.pos[4 * i] - c[0], q.pos[4 * i + 1] - c[1], q.pos[4 * i + 2] - c[2]};
        const double v[3] = {q.vel[4 * i], q.vel[4 * i + 1], q.vel[4 * i + 2]};
        for (int a = 0; a < 3; ++a) r.p[a] += m * v[a];
        r.l[0] += m * (x[1] * v[2] - x[2] * v[1]);
        r.l[1] += m * (x[2] * v[0] - x[0] * v[2]);
        r.l[2] += m * (x[0] * v[1] - x[1] * v[0]);
        const double rx = std::sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]);
        r.scale_l += m * rx * std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        r.radius = std::max(r.radius, rx);
        r.mass += m;
    }
    return r;
}

// Two materials 100 times apart in density, 0.15 m of each in a 0.4 x 0.1 m column (768
// particles at 12.5 mm), stepped 1 s (bounds: the test cases below).
void check_density_ratio_100(bool heavy_on_top) {
    pbf_world_id w = create(tank(PBF_BACKEND_CPU, 0.0125f, 0.4f, 0.6f, 0.1f, 4096));
    pbf_material_desc heavy_desc = pbf_material_desc_default(), light_desc = pbf_material_desc_default();
    heavy_desc.rest_density = 10000.0f;
    light_desc.rest_density = 100.0f;
    pbf_material_id heavy{}, light{};
    REQUIRE_PBF(pbf_world_create_material(w, &heavy_desc, &heavy));
    REQUIRE_PBF(pbf_world_create_material(w, &light_desc, &light));
    const float lower_lo[3] = {0, 0, 0}, lower_hi[3] = {0.4f, 0.15f, 0.1f};
    const float upper_lo[3] = {0, 0.15f, 0}, upper_hi[3] = {0.4f, 0.3f, 0.1f};
    materials::fill(w, heavy_on_top ? light : heavy, lower_lo, lower_hi);
    materials::fill(w, heavy_on_top ? heavy : light, upper_lo, upper_hi);
    const double first = run_top(w, 0.5), last = run_top(w, 0.5);
    const double bound = free_fall_front(0.3) + kAtRest;
    INFO((heavy_on_top ? "heavy over light" : "light over heavy")
         << ": fastest particle over the first 0.5 s " << first << " m/s (bound " << bound << "), over the next 0.5 s "
         << last << " m/s (at rest: " << kAtRest << ")");
    CHECK(std::max(first, last) <= bound);
    if (!heavy_on_top) CHECK(last <= kAtRest);
    REQUIRE_PBF(pbf_world_destroy(w));
}

double norm3(const double* v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

}  // namespace

// One step of 1e-7 s cannot change a velocity by more than g·1e-7: the fluid after it is the
// fluid before it. Checked: the fastest particle right after the step, against the fastest
// before it, and the fastest over the next 0.5 s against a twin pool that never took the tiny
// step (both within the at-rest allowance's half, 0.5 m/s).
TEST_CASE("valid inputs: one step of 1e-7 s on a stirred pool changes nothing", "[valid]") {
    pbf_world_id w = stirred_pool(), twin = stirred_pool();
    const double before = top_speed(w);
    REQUIRE_PBF(pbf_world_step(w, 1e-7f));
    const double after = top_speed(w);
    const double later = run_top(w, 0.5), twin_later = run_top(twin, 0.5);
    INFO("fastest particle before the 1e-7 s step " << before << " m/s, after it " << after
                                                    << " m/s; over the next 0.5 s " << later
                                                    << " m/s (twin without the tiny step: " << twin_later << " m/s)");
    CHECK(after <= before + 0.5);
    CHECK(later <= twin_later + 0.5);
    REQUIRE_PBF(pbf_world_destroy(w));
    REQUIRE_PBF(pbf_world_destroy(twin));
}

// Reading the stats is no input: a world whose stats are read before and after every step takes
// the same steps, bit for bit, as its twin whose stats are never read. The scene has what such a
// read could disturb: a block emitted into a floor plane in zero gravity (the settling's
// reference is the error the particles had before the overlap), and, with LDC and vorticity
// confinement off, steps that leave ρ at the final positions unsummed (the error the next
// substep starts from is the last λ pass's). A world of fewer than 2,048 particles runs
// single-threaded on the CPU, so the twins are bit for bit.
namespace {
Particles steps_with_stats_read(bool read_stats, bool ldc_and_vorticity) {
    pbf_world_desc d = tank(PBF_BACKEND_CPU, 0.02f, 0.4f, 0.6f, 0.4f, 2000);
    set3(d.gravity, 0.0f, 0.0f, 0.0f);
    if (!ldc_and_vorticity) {
        d.solver.ldc_enabled = 0;
        d.solver.vorticity_epsilon = 0.0f;
    }
    pbf_world_id w = create(d);
    pbf_collider_desc floor = collider_desc(PBF_SHAPE_PLANE);
    set3(floor.position, 0.0f, 0.1f, 0.0f);
    pbf_collider_id id{};
    REQUIRE_PBF(pbf_world_create_collider(w, &floor, &id));
    fill(w, 0, 0, 0, 0.4f, 0.25f, 0.4f);
    for (int k = 0; k < 20; ++k) {
        if (read_stats) (void)stats(w);
        REQUIRE_PBF(pbf_world_step(w, kDt));
        if (read_stats) (void)stats(w);
    }
    const Particles p = read(w);
    REQUIRE_PBF(pbf_world_destroy(w));
    return p;
}
}  // namespace

TEST_CASE("valid inputs: reading the stats between steps does not change the steps", "[valid]") {
    for (const bool ldc_and_vorticity : {true, false}) {
        const Particles watched = steps_with_stats_read(true, ldc_and_vorticity);
        const Particles unwatched = steps_with_stats_read(false, ldc_and_vorticity);
        INFO((ldc_and_vorticity ? "LDC and vorticity confinement on" : "LDC and vorticity confinement off")
             << ": " << watched.count << " particles");
        REQUIRE(watched.count == unwatched.count);
        CHECK(watched.count < 2048);
        CHECK(same_bits(watched.pos, unwatched.pos));
        CHECK(same_bits(watched.vel, unwatched.vel));
    }
}

// A block (0.97 x 0.87 x 1.08 m of 5.4 cm particles) thrown at 2.9 m/s onto an open level's floor
// plane, with a stiff constraint (relaxation 0.07) and a fast response (sound speed 294 m/s),
// stepped 4 ms, 0.3 s, then 6.5e-5 s (a fuzzer world, shrunk). The last step can change a
// velocity by what its length gives, not by the depth a particle starts it inside the plane
// divided by 6.5e-5 s. Bound: the fuzzer's (Ritter's front over the block's height, the block's
// speed, the at-rest allowance).
TEST_CASE("valid inputs: a short step after a block lands on a floor plane throws no water", "[valid][collide]") {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = PBF_BACKEND_CPU;
    d.particle_radius = 0.0540677f;
    d.rest_density = 3834.22f;
    d.max_particles = 1719;
    d.walls = 0;
    d.solver.relaxation = 0.0701003f;
    d.solver.sound_speed = 293.804f;
    pbf_world_id w = create(d);
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_PLANE;
    pbf_collider_id floor{};
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &floor));
    const float lo[3] = {-0.44359f, 0.0f, -0.628571f}, hi[3] = {0.529628f, 0.865083f, 0.452783f},
                v[3] = {-2.21037f, -0.948599f, -1.45287f};
    const uint32_t n = throw_block(w, lo, hi, v);
    const double top = top_over(w, {0.00407102f, 0.301231f, 6.47866e-05f});
    const double bound = free_fall_front(0.865083) + 2.81005 + kAtRest;
    INFO(n << " particles; fastest " << top << " m/s (bound " << bound << ")");
    CHECK(top <= bound);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A settled pool around a static sphere sunk into the floor (level geometry meeting the tank's
// floor): the water at its foot is wedged between the sphere's underside and the floor, where
// each contact pushes a particle back into the other. One step of 1e-7 s then changes nothing
// (as for the stirred pool above): a contact a particle starts the substep in is no motion of the
// substep, and turned into velocity it gave depth / 1e-7 s. The projections alternate between
// the sphere and the floor until the particle clears both (core/collide.h, kProjectRounds):
// moved out of one into the other once, it crept along the floor by each projection (100 m/s
// after the step).
TEST_CASE("valid inputs: one step of 1e-7 s on a pool around a sphere sunk into the floor changes nothing",
          "[valid][collide]") {
    pbf_world_id w = create(tank(PBF_BACKEND_CPU, 0.0125f, 0.4f, 0.6f, 0.4f, 8192));
    static_sphere(w, 0.1f, 0.2f, 0.05f, 0.2f);
    fill(w, 0, 0, 0, 0.4f, 0.2f, 0.4f);
    for (int k = 0; k < 60; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const double before = top_speed(w);
    REQUIRE_PBF(pbf_world_step(w, 1e-7f));
    const double after = top_speed(w);
    INFO("fastest particle before the 1e-7 s step " << before << " m/s, after it " << after << " m/s");
    CHECK(after <= before + 0.5);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A settled pool 0.3 m deep on a floor slab (a static box 0.2 m thick across a tank 1 m tall:
// level geometry), then a static sphere of radius 0.2 m created into it, sunk 0.05 m into the
// slab. The water at its foot is wedged between two colliders whose shells overlap: pushed out
// of one into the other once, it stays in contact, and the substep's projection out of it
// becomes velocity, so the pushes alternate until a particle clears both (core/collide.h,
// push_out_in_rounds) and the contact a settling leaves is removed in x. Bound: the fall over
// the surface's rise (the displaced 0.031 m3 over the tank's 0.36 m2) plus the at-rest allowance.
namespace {
struct SunkSphere {
    double top = 0.0;     // m/s, the fastest particle after any step
    double lowest = 1e9;  // m, the lowest particle centre after any step
};
SunkSphere sphere_sunk_into_slab(float dt, double seconds) {
    pbf_world_id w = create(tank(PBF_BACKEND_CPU, 0.02f, 0.6f, 1.0f, 0.6f, 16384));
    pbf_collider_desc slab = pbf_collider_desc_default();
    slab.shape = PBF_SHAPE_BOX;
    set3(slab.half_extents, 0.3f, 0.1f, 0.3f);
    set3(slab.position, 0.3f, 0.1f, 0.3f);
    pbf_collider_id id{};
    REQUIRE_PBF(pbf_world_create_collider(w, &slab, &id));
    fill(w, 0, 0.2f, 0, 0.6f, 0.5f, 0.6f);
    for (int k = 0; k < 60; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    static_sphere(w, 0.2f, 0.3f, 0.35f, 0.3f);
    SunkSphere r;
    const int steps = int(std::lround(seconds / dt));
    for (int k = 0; k < steps; ++k) {
        REQUIRE_PBF(pbf_world_step(w, dt));
        const Particles p = read(w);
        r.top = std::max(r.top, top_speed(p));
        for (uint32_t i = 0; i < p.count; ++i) r.lowest = std::min(r.lowest, double(p.pos[4 * i + 1]));
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    return r;
}
double sunk_sphere_bound() { return free_fall_front(0.0306 / 0.36) + kAtRest; }
}  // namespace

TEST_CASE("valid inputs: a sphere created sunk into a floor slab under a pool flings no water at 1/60 s steps",
          "[valid][collide]") {
    const SunkSphere r = sphere_sunk_into_slab(kDt, 0.25);
    INFO("fastest particle over 0.25 s " << r.top << " m/s (bound " << sunk_sphere_bound() << ")");
    CHECK(r.top <= sunk_sphere_bound());
}

// The same at 1e-3 s steps: what the settling leaves relaxes in too few steps' time (open:
// docs/physics.md, Overlaps).
TEST_CASE("valid inputs: a sphere created sunk into a floor slab under a pool flings no water at 1e-3 s steps",
          "[valid][collide][!shouldfail]") {
    const SunkSphere r = sphere_sunk_into_slab(1e-3f, 0.1);
    INFO("fastest particle over 0.1 s " << r.top << " m/s (bound " << sunk_sphere_bound() << ")");
    CHECK(r.top <= sunk_sphere_bound());
}

// The settling mirrors a particle a depth d inside a collider to d beyond its surface: one deep
// inside the sphere is carried into the slab and pushed out of the slab's far side, onto the
// tank's floor under it (open: docs/physics.md, Overlaps).
TEST_CASE("valid inputs: a sphere created into a pool over a floor slab pushes no water under the slab",
          "[valid][collide][!shouldfail]") {
    const SunkSphere r = sphere_sunk_into_slab(kDt, 0.05);
    INFO("lowest particle centre " << r.lowest << " m (the slab's top: 0.2 m)");
    CHECK(r.lowest >= 0.2);
}

// A block (0.19 x 0.21 x 0.16 m of 1.3 cm particles) thrown at 3.3 m/s at a wall in zero gravity,
// stepped 1.4 ms and 78 ms (it strikes the wall), then 1.6e-7 s (a fuzzer world, shrunk). The
// tiny step can change a velocity by what its length gives: the error each particle starts it
// with is ρ at its position, summed over every neighbour there; summed over the neighbours the
// last substep listed before its corrections moved the struck water together, it fell short,
// and the shortfall, taken for new compression, went into velocity (100 m/s). Bound: the
// fuzzer's (no gravity: the block's speed plus the at-rest allowance).
TEST_CASE("valid inputs: a step of 1.6e-7 s after a block strikes a wall throws no water", "[valid]") {
    const float lo[3] = {-0.15933f, 0.0f, -0.199162f}, hi[3] = {0.15933f, 0.504544f, 0.199162f};
    pbf_world_id w = create(zero_g_box(0.0132775f, 31.5504f, 502, lo, hi));
    const float block_lo[3] = {-0.0942869f, 0.0f, -0.0130677f}, block_hi[3] = {0.0915978f, 0.21244f, 0.146262f},
                v[3] = {-0.294648f, 0.336456f, -3.27287f};
    const uint32_t n = throw_block(w, block_lo, block_hi, v);
    const double top = top_over(w, {0.00140211f, 0.0777713f, 1.62812e-07f});
    const double bound = 3.30328 + kAtRest;
    INFO(n << " particles; fastest " << top << " m/s (bound " << bound << ")");
    CHECK(top <= bound);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A slab two particles thick resting on the floor in zero gravity at 43 fixed substeps per
// 1/60 s frame (a fuzzer world, shrunk), with a stiff density response (sound_speed 300 m/s)
// and with the default's (40 m/s). s_corr pushes pairs at the rest spacing apart a little,
// unbalanced at a free surface, and relaxes with the substep on a time scale no shorter than the
// default response's: the stiffer fluid's push, repeated at full strength every substep, grew per
// second as 1/Δt² and threw the top layer off at 3.2 m/s within 1 s, against 1.1 m/s at the
// default. Bound: the stiff slab no faster than the default one plus 0.1 m/s. (Both exceed the
// at-rest allowance at this substep count: s_corr's push per second still grows with the
// substeps there, docs/physics.md.)
TEST_CASE("valid inputs: a stiffer fluid's s_corr pushes a slab at rest no harder", "[valid]") {
    double top[2] = {0.0, 0.0};
    uint32_t n = 0;
    for (int stiff = 0; stiff < 2; ++stiff) {
        const float lo[3] = {-0.227856f, 0.0f, -0.0792541f}, hi[3] = {0.227856f, 0.396271f, 0.0792541f};
        pbf_world_desc d = zero_g_box(0.00990677f, 499.19f, 213, lo, hi);
        d.solver.substeps = 43;
        if (stiff) d.solver.sound_speed = 301.518f;
        pbf_world_id w = create(d);
        n = fill(w, -0.174485f, 0.0f, -0.074468f, 0.00383684f, 0.0396271f, 0.0642267f);
        top[stiff] = run_top(w, 1.0);
        REQUIRE_PBF(pbf_world_destroy(w));
    }
    INFO(n << " particles; fastest over 1 s at sound_speed 300 m/s " << top[1] << " m/s, at the default " << top[0]
           << " m/s");
    CHECK(top[1] <= top[0] + 0.1);
}

// A thin sheet of water flying at 4.8 m/s in zero gravity on an open level (nothing acts on it),
// at 42 fixed substeps, stepped 7.3e-5 s and then 1.8e-7 s (a fuzzer world, shrunk). Float32
// positions 0.5 m out are resolved to 6e-8 m, so substeps of 4e-9 s rounded each velocity to 0 or
// 13.6 m/s and the sheet lost a quarter of its momentum. Steps shorter than 1e-4 s wait for the
// next (pbf_world_step): both report nothing simulated; a 1/60 s step then simulates their time
// too. Tolerance: the fuzzer's, 1 % of Σ m |v|.
TEST_CASE("valid inputs: steps shorter than 1e-4 s wait, and a flying sheet keeps its momentum through them",
          "[valid]") {
    pbf_world_desc d = zero_g_desc(0.050209f, 20.4684f, 143);
    d.walls = 0;
    d.solver.substeps = 42;
    pbf_world_id w = create(d);
    const float lo[3] = {-0.690196f, 0.0f, -0.555687f}, hi[3] = {0.615237f, 0.100418f, 0.54891f},
                v[3] = {-0.0181908f, -4.20723f, -2.27747f};
    const uint32_t n = throw_block(w, lo, hi, v);
    const double m = mass_of(w);
    const Particles before = read(w);
    const Momenta p0 = momenta(before, m);
    for (float dt : {7.25789e-05f, 1.84365e-07f}) {
        pbf_mapped_buffer mapped{};
        mapped.struct_size = sizeof mapped;
        REQUIRE_PBF(pbf_world_map_positions(w, &mapped));
        REQUIRE_PBF(pbf_world_step(w, dt));
        CHECK(stats(w).simulated_dt == 0.0f);
        CHECK(stats(w).substeps == 0u);
        CHECK(pbf_world_unmap(w) == PBF_ERROR_INVALID_STATE);  // a step ended the mapping, as any step does
    }
    const Particles waited = read(w);
    REQUIRE(waited.count == before.count);
    uint32_t moved_while_waiting = 0;
    for (uint32_t i = 0; i < waited.count; ++i)
        for (uint32_t j = 0; j < before.count; ++j)
            if (before.ids[j] == waited.ids[i])
                for (int a = 0; a < 3; ++a) moved_while_waiting += waited.pos[4 * i + a] != before.pos[4 * j + a];
    CHECK(moved_while_waiting == 0u);  // nothing advanced
    REQUIRE_PBF(pbf_world_step(w, kDt));
    const float carried = 7.25789e-05f + 1.84365e-07f;
    CHECK(stats(w).simulated_dt == Approx(kDt + carried).epsilon(1e-6));
    const Particles after = read(w);
    const Momenta p1 = momenta(after, m);
    double dp[3], scale = 0.0;
    for (int a = 0; a < 3; ++a) dp[a] = p1.p[a] - p0.p[a];
    for (uint32_t i = 0; i < after.count; ++i)
        scale += m * std::sqrt(double(after.vel[4 * i]) * after.vel[4 * i] +
                               double(after.vel[4 * i + 1]) * after.vel[4 * i + 1] +
                               double(after.vel[4 * i + 2]) * after.vel[4 * i + 2]);
    // The sheet moved by its velocity over all three steps' time.
    double moved = 0.0;
    for (uint32_t i = 0; i < after.count; ++i) moved += (after.pos[4 * i + 1] - before.pos[4 * i + 1]) / after.count;
    INFO(n << " particles; |dP| " << norm3(dp) << " of Σ m|v| " << scale << "; mean y travel " << moved << " m");
    CHECK(norm3(dp) <= 0.01 * scale);
    CHECK(moved == Approx(-4.20723 * (kDt + carried)).epsilon(0.01));
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A settled pool stepped for 1 s (valid: dt <= 1) is a settled pool; the next step, of any dt,
// must leave it one: no particle above the at-rest allowance after it or over the 0.25 s of
// 1/60 s steps that follow.
TEST_CASE("valid inputs: one 1 s step, then a step of 1e-7, 1e-3 or 1/60 s, leaves a settled pool at rest", "[valid]") {
    for (float next : {1e-7f, 1e-3f, 1.0f / 60.0f}) {
        pbf_world_id w = settled_pool();
        REQUIRE_PBF(pbf_world_step(w, 1.0f));
        const double after_huge = top_speed(w);
        const float err_huge = stats(w).density_error_max;
        REQUIRE_PBF(pbf_world_step(w, next));
        const double after_next = top_speed(w);
        const double later = run_top(w, 0.25);
        INFO("after 1 s: fastest " << after_huge << " m/s (density error max " << err_huge << "); after the step of "
                                   << next << " s: " << after_next << " m/s; over the next 0.25 s: " << later
                                   << " m/s");
        CHECK(after_huge <= kAtRest);
        CHECK(after_next <= kAtRest);
        CHECK(later <= kAtRest);
        REQUIRE_PBF(pbf_world_destroy(w));
    }
}

// A settled pool carries its weight as a compression that depends on the substep length (about
// 1 % here at 1/60 s). Stepped for 0.1 s in steps of 1e-4 s it must stay a settled pool: no
// particle above the at-rest allowance, and its centre of mass no higher than the release of
// that compression lifts it (its mean density error times its mean height, doubled). Two terms
// of short substeps lift the whole pool instead (docs/physics.md, "Open: a settled pool stepped
// in short steps lifts off"): measured, 2.1 m/s and the centre of mass 3.9 cm higher, against
// 4.8 mm allowed (2.5 m/s and 6.7 cm while the old error relaxed over τ at small Δt).
TEST_CASE("valid inputs: a settled pool stepped at 1e-4 s for 0.1 s stays at rest", "[valid][!shouldfail]") {
    pbf_world_id w = settled_pool();
    const auto mean_height = [](const Particles& p) {
        double y = 0.0;
        for (uint32_t i = 0; i < p.count; ++i) y += p.pos[4 * i + 1];
        return y / p.count;
    };
    const double y0 = mean_height(read(w)), compression = stats(w).density_error_mean;
    const double top = run_top(w, 0.1, 1e-4f);
    const double rise = mean_height(read(w)) - y0, allowed = 2.0 * compression * y0;
    INFO("fastest " << top << " m/s; centre of mass rose " << rise << " m (allowed " << allowed << " m)");
    CHECK(top <= kAtRest);
    CHECK(rise <= allowed);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A drop flying at 5 m/s in zero gravity (no walls: nothing acts on it), then one step of 1 s.
// Sixteen substeps of 1/16 s would carry it 6 h each, past the h/Δt speed limit (which cut its
// speed to 0.8 m/s); the step simulates what its substeps hold instead, says so, and the drop
// keeps its momentum (the fuzzer's tolerance: 1 % of Σ m |v|) and cuts no speed. A 1/60 s step
// is simulated whole.
TEST_CASE("valid inputs: a drop flying at 5 m/s keeps its momentum over one 1 s step", "[valid]") {
    pbf_world_id w = zero_g_open_world(0.0125f, 1024);
    pbf_block_desc b = pbf_block_desc_default();
    set3(b.box_min, -0.05f, -0.05f, -0.05f);
    set3(b.box_max, 0.05f, 0.05f, 0.05f);
    set3(b.velocity, 5.0f, 0.0f, 0.0f);
    uint32_t n = 0;
    REQUIRE_PBF(pbf_world_emit_block(w, &b, &n));
    const double mass = double(mass_of(w)), p0 = mass * n * 5.0;
    REQUIRE_PBF(pbf_world_step(w, kDt));
    CHECK(stats(w).simulated_dt == kDt);
    REQUIRE_PBF(pbf_world_step(w, 1.0f));
    const pbf_step_stats st = stats(w);
    const Momenta mo = momenta(read(w), mass);
    INFO(n << " particles; after the 1 s step: |P| " << norm3(mo.p) << " kg m/s of " << p0 << ", simulated "
           << st.simulated_dt << " s in " << st.substeps << " substeps, " << st.speed_clamps << " speed clamps");
    CHECK(st.simulated_dt > 0.0f);
    CHECK(st.simulated_dt < 1.0f);
    CHECK(st.speed_clamps == 0u);
    CHECK(std::fabs(norm3(mo.p) - p0) <= 0.01 * p0);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A plate 2 cm thick, 0.2 m tall, spanning a channel 0.3 m deep, swept through it at 20 m/s.
// A rigid wall at speed V gives a particle at most 2V (an elastic bounce); the water also falls
// at most Ritter's front over its depth; plus the at-rest allowance.
TEST_CASE("valid inputs: a thin plate swept at 20 m/s throws no particle faster than twice its speed", "[valid]") {
    const float speed = 20.0f, depth = 0.3f;
    pbf_world_id w = create(tank(PBF_BACKEND_CPU, 0.0125f, 1.0f, 0.6f, 0.1f, 4096));
    const uint32_t n = fill(w, 0.2f, 0, 0, 1.0f, depth, 0.1f);
    const pbf_collider_id plate = kinematic_box(w, 0.1f, 0.1f, 0.05f, 0.01f, 0.1f, 0.5f);
    const float identity[4] = {0, 0, 0, 1};
    double top = 0.0;
    float x = 0.1f;
    for (int k = 0; k < 30; ++k) {
        x = std::min(0.9f, x + speed * kDt);
        const float target[3] = {x, 0.1f, 0.05f};
        REQUIRE_PBF(pbf_collider_set_target_pose(w, plate, target, identity));
        REQUIRE_PBF(pbf_world_step(w, kDt));
        top = std::max(top, top_speed(w));
    }
    const double bound = 2.0 * speed + free_fall_front(depth) + kAtRest;
    const Particles p = read(w);
    INFO("fastest particle " << top << " m/s = " << top / speed << " x the plate's speed (bound " << bound << " m/s)");
    CHECK(p.count == n);
    CHECK(top <= bound);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A plate standing in a pool with less than a particle diameter between it and the floor (2 cm
// at 12.5 mm radius) and the back wall (5 mm): the particles under it and beside it cannot be
// pushed out along the nearest face, which the walls block. Swept at 2 m/s in steps of 2e-4 s,
// it threw one at 50 m/s when it passed. Bound as for the fast plate above.
TEST_CASE(
    "valid inputs: a plate swept at 2 m/s in short steps, closer to the floor and a wall than a particle "
    "diameter, throws no particle faster than twice its speed",
    "[valid][collide]") {
    const float speed = 2.0f, depth = 0.2f, dt = 2e-4f;
    pbf_world_id w = create(tank(PBF_BACKEND_CPU, 0.0125f, 0.6f, 0.6f, 0.15f, 4096));
    const uint32_t n = fill(w, 0, 0, 0, 0.6f, depth, 0.15f);
    run_top(w, 1.0);
    const pbf_collider_id plate = kinematic_box(w, 0.1f, 0.1f, 0.075f, 0.02f, 0.08f, 0.07f, true);
    run_top(w, 2.0);
    const float identity[4] = {0, 0, 0, 1};
    double top = 0.0;
    float x = 0.1f;
    for (int k = 0; k < 300; ++k) {
        x += speed * dt;
        const float target[3] = {x, 0.1f, 0.075f};
        REQUIRE_PBF(pbf_collider_set_target_pose(w, plate, target, identity));
        REQUIRE_PBF(pbf_world_step(w, dt));
        top = std::max(top, top_speed(w));
    }
    const double bound = 2.0 * speed + free_fall_front(depth) + kAtRest;
    INFO("fastest particle " << top << " m/s (bound " << bound << " m/s)");
    CHECK(read(w).count == n);
    CHECK(top <= bound);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// Water (1000 kg/m3) placed over oil (800), 896 particles each at 12.5 mm in a 0.4 x 0.1 m
// column, each layer 0.35 m deep. The layer is Rayleigh-Taylor unstable: Atwood number
// A = 0.2/1.8 = 0.11; a blob of it rises at about √(A g L) = 0.6 m/s over L = 0.35 m, and the
// tank's longest mode grows at √(A g k) = 2.9 /s (k = π / 0.4 m), so from the lattice's
// millimetre disturbances the overturn is over within about 2 s. After 4 s, at least 90 % of the
// oil must lie above 0.35 m (where the interface is once the fluids have swapped). The tank
// stands 1 degree off level, as no real one is level: a perfect lattice in a level tank is an
// unstable equilibrium that a deterministic solver could keep forever (the interface then tilts
// by 3.5 mm across the tank, a fraction of a spacing).
TEST_CASE("valid inputs: water placed over oil overturns in the time gravity gives",
          "[valid][materials][!shouldfail]") {
    pbf_world_desc d = tank(PBF_BACKEND_CPU, 0.0125f, 0.4f, 0.9f, 0.1f, 2048);
    set3(d.gravity, float(kG * std::sin(M_PI / 180.0)), float(-kG * std::cos(M_PI / 180.0)), 0.0f);
    pbf_world_id w = create(d);
    pbf_material_desc oil_desc = pbf_material_desc_default();
    oil_desc.rest_density = 800.0f;
    pbf_material_id oil{};
    REQUIRE_PBF(pbf_world_create_material(w, &oil_desc, &oil));
    const float oil_lo[3] = {0, 0, 0}, oil_hi[3] = {0.4f, 0.35f, 0.1f};
    const uint32_t n_oil = materials::fill(w, oil, oil_lo, oil_hi);
    fill(w, 0, 0.35f, 0, 0.4f, 0.7f, 0.1f);
    auto oil_above = [&]() {
        const Particles p = read(w);
        std::vector<uint8_t> m(p.count);
        uint32_t k = 0;
        REQUIRE_PBF(pbf_world_copy_buffer(w, PBF_BUFFER_MATERIALS, m.data(), m.size(), &k));
        uint32_t above = 0, total = 0;
        for (uint32_t i = 0; i < p.count; ++i)
            if (m[i] == oil.index) {
                ++total;
                above += p.pos[4 * i + 1] > 0.35f ? 1u : 0u;
            }
        return total ? double(above) / total : 0.0;
    };
    for (int k = 0; k < 60; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const double at_1s = oil_above();
    for (int k = 0; k < 180; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const double at_4s = oil_above();
    INFO(n_oil << " oil particles; above 0.35 m: " << 100 * at_1s << " % after 1 s, " << 100 * at_4s << " % after 4 s");
    CHECK(at_4s >= 0.9);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A box 6 particle diameters across (0.24 m at 0.02 m radius) held fully submerged in the middle
// of a pool, 0.16 m of water over it: the mean upward force over the last second of three, over
// ρ g V.
double submerged_force_ratio(float pool_width, float under) {
    const float lo = 0.5f * pool_width - 0.12f, hi = lo + 0.24f;
    const coupling::Box b{{lo, under, lo}, {hi, under + 0.24f, hi}};
    pbf_world_id w = coupling::pool(PBF_BACKEND_CPU, pool_width, 0.9f, pool_width, under + 0.24f + 0.16f, b);
    const pbf_collider_id box = coupling::add_box(w, b, PBF_MOTION_STATIC);
    double fy = 0;
    int n = 0;
    for (int step = 0; step < 180; ++step) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        if (step < 120) continue;
        fy += coupling::force(w, box).force[1];
        ++n;
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    return fy / n / (1000.0 * kG * 0.24 * 0.24 * 0.24);
}

// Archimedes: ρ g V within 5 %, whatever water lies under the box (0.2 m or 0.12 m), in a pool
// 0.72 m square (0.24 m of water beside the box).
TEST_CASE("valid inputs: a box 6 particle diameters across feels rho g V within 5 % at any depth",
          "[valid][coupling][!mayfail]") {
    for (float under : {0.20f, 0.12f}) {
        const double ratio = submerged_force_ratio(0.72f, under);
        INFO(under << " m of water under the box, pool 0.72 m square: F = " << ratio << " rho g V");
        CHECK(std::fabs(ratio - 1.0) <= 0.05);
    }
}

// The same in a pool 0.48 m square: three particle layers (0.12 m) between the box and each wall.
// Hydrostatics does not depend on the gap: still ρ g V within 5 %.
TEST_CASE("valid inputs: a box 6 particle diameters across feels rho g V within 5 % three layers from the walls",
          "[valid][coupling][!shouldfail]") {
    const double ratio = submerged_force_ratio(0.48f, 0.20f);
    INFO("0.2 m of water under the box, pool 0.48 m square: F = " << ratio << " rho g V");
    CHECK(std::fabs(ratio - 1.0) <= 0.05);
}

// A 0.16 m box (4 particle diameters) created fully inside a settled pool 0.36 m deep did not
// push the water: the water it displaces rises to the surface, which rises by V/A = 18 mm. No
// particle may move faster than the fall over that rise (Ritter's front) plus the at-rest
// allowance, over the 0.25 s after.
TEST_CASE("valid inputs: a box created fully inside a settled pool flings no water", "[valid][collide]") {
    pbf_world_id w = deep_pool();
    const pbf_collider_id box = kinematic_box(w, 0.24f, 0.16f, 0.24f, 0.08f, 0.08f, 0.08f, true);
    const double rise = 0.16 * 0.16 * 0.16 / (0.48 * 0.48), bound = free_fall_front(rise) + kAtRest;
    const double top = run_top(w, 0.25);
    INFO("fastest particle over 0.25 s after the box appeared: " << top << " m/s (bound " << bound << " m/s)");
    CHECK(top <= bound);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A plane created 0.1 m above the floor of a settled pool 0.36 m deep: the water under it moves
// above it, and the surface rises by 0.1 m. No particle may move faster than the fall over that
// rise (Ritter's front) plus the at-rest allowance, over 0.25 s of 1/60 s steps or 0.02 s of
// 1e-4 s steps.
namespace {
void check_plane_created_under_surface(float dt) {
    pbf_world_id w = deep_pool();
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_PLANE;
    set3(c.position, 0.24f, 0.1f, 0.24f);
    pbf_collider_id plane{};
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &plane));
    const double bound = free_fall_front(0.1) + kAtRest;
    const double top = run_top(w, dt > 1e-3f ? 0.25 : 0.02, dt);
    INFO("steps of " << dt << " s: fastest particle " << top << " m/s after the plane appeared (bound " << bound
                     << " m/s)");
    CHECK(top <= bound);
    REQUIRE_PBF(pbf_world_destroy(w));
}
}  // namespace

TEST_CASE("valid inputs: a plane created under the surface of a pool flings no water at 1/60 s steps",
          "[valid][collide]") {
    check_plane_created_under_surface(1.0f / 60.0f);
}

// Open (docs/physics.md, Overlaps): at 1e-4 s steps the water the settling could not move
// leaves faster than gravity would move it.
TEST_CASE("valid inputs: a plane created under the surface of a pool flings no water at 1e-4 s steps",
          "[valid][collide][!shouldfail]") {
    check_plane_created_under_surface(1e-4f);
}

// Two materials 100 times apart in density (100 and 10,000 kg/m3, both within 0.1..10 x the
// world's 1,000), 0.15 m of each. Layered stably, light over heavy, they are a pool at rest: no
// particle may outrun Ritter's front over the pool's depth (plus the at-rest allowance) in the
// first half second, and the pool is at rest in the next.
TEST_CASE("valid inputs: two fluids 100 times apart in density rest in layers", "[valid][materials]") {
    check_density_ratio_100(false);
}

// Placed heavy over light, the heavy fluid falls through the light one: nothing falls faster than
// gravity, so over the first second no particle outruns Ritter's front over the pool's depth
// (plus the at-rest allowance).
TEST_CASE("valid inputs: a fluid 100 times denser placed over another falls through it no faster than gravity",
          "[valid][materials][!shouldfail]") {
    check_density_ratio_100(true);
}

// A 0.2 m cube of a material with surface tension and cohesion at their documented maximum
// (10,000 /s2 each) in zero gravity, no walls: it pulls itself into a drop, whose oscillations the
// viscosity damps. Over the last half second of two it is at rest (the at-rest allowance) and its
// momentum is what it was (zero).
TEST_CASE("valid inputs: surface tension and cohesion at their maximum in zero gravity come to rest",
          "[valid][materials][!shouldfail]") {
    pbf_world_id w = zero_g_open_world(0.0125f, 1024);
    pbf_material_desc m = pbf_material_desc_default();
    m.surface_tension = 10000.0f;
    m.cohesion = 10000.0f;
    pbf_material_id sticky{};
    REQUIRE_PBF(pbf_world_create_material(w, &m, &sticky));
    const float lo[3] = {-0.1f, -0.1f, -0.1f}, hi[3] = {0.1f, 0.1f, 0.1f};
    const uint32_t n = materials::fill(w, sticky, lo, hi);
    const double mass = double(mass_of(w));  // every particle has the world's volume; this one the world's density too
    for (int k = 0; k < 90; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const double last = run_top(w, 0.5);
    const Momenta mo = momenta(read(w), mass);
    INFO(n << " particles; fastest over the last 0.5 s of 2 s: " << last << " m/s; |P| " << norm3(mo.p)
           << " kg m/s (scale " << mo.mass * last << ")");
    CHECK(last <= kAtRest);
    CHECK(norm3(mo.p) <= 0.01 * mo.mass * std::max(last, 1e-2));
    REQUIRE_PBF(pbf_world_destroy(w));
}

// s_corr at the ends of its documented ranges (k up to 1, n from 1, Δq up to 0.99 h) on a cube
// of water emitted at rest in zero gravity with no walls (512 particles): nothing acts on it, so
// over 1 s it stays at rest (the at-rest allowance), and no setting stirs it more than the
// defaults' own slight push at its surface does (10 % and 1 mm/s over the defaults' fastest
// particle). Pairs at and beyond the rest spacing feel no more of s_corr than at the defaults:
// inside the lattice the pushes cancel, at its surface they are the defaults' slight push.
// Before that bound, k = 1 at Δq = 0.95 h stirred the drop to 0.41 m/s, and at the defaults'
// shape to 0.22 m/s (the defaults: 0.07 m/s).
TEST_CASE("valid inputs: s_corr at its extremes leaves a drop at rest in zero gravity at rest", "[valid]") {
    struct Setting {
        float k, n, dq;
    };
    const pbf_solver_params defaults = pbf_solver_params_default();
    double reference = 0;
    for (const Setting c : {Setting{defaults.scorr_k, defaults.scorr_n, defaults.scorr_dq}, Setting{1.0f, 4.0f, 0.95f},
                            Setting{1.0f, 1.0f, 0.2f}, Setting{0.1f, 4.0f, 0.99f}, Setting{1.0f, 8.0f, 0.3f},
                            Setting{1.0f, 4.0f, 0.2f}}) {
        pbf_world_id w = zero_g_open_world(0.0125f, 1024);
        pbf_solver_params p = pbf_solver_params_default();
        REQUIRE_PBF(pbf_world_get_solver_params(w, &p));
        p.scorr_k = c.k;
        p.scorr_n = c.n;
        p.scorr_dq = c.dq;
        REQUIRE_PBF(pbf_world_set_solver_params(w, &p));
        const uint32_t n = fill(w, -0.1f, -0.1f, -0.1f, 0.1f, 0.1f, 0.1f);
        const double top = run_top(w, 1.0);
        if (reference == 0) reference = top;  // the defaults, first
        INFO("k " << c.k << ", n " << c.n << ", dq " << c.dq << " h: " << n << " particles, fastest over 1 s " << top
                  << " m/s (at the defaults " << reference << " m/s)");
        CHECK(top <= kAtRest);
        CHECK(top <= 1.1 * reference + 1e-3);
        REQUIRE_PBF(pbf_world_destroy(w));
    }
}

// A nozzle's stream at a strong s_corr (k 0.96, Δq 0.4 h, relaxation 0.27) in zero gravity with
// no walls: a stream is too sparse for λ, so s_corr alone acts on it, and a particle the nozzle
// emits near one the stream turned aside meets the rise of s_corr inside the rest spacing. Nothing
// else acts, so no particle may leave faster than the nozzle's speed plus the at-rest allowance.
// Before the rise was limited to bringing such a pair to the rest spacing, the pair left at
// 10-19 m/s and the fastest particle reached the h/Δt limit, 23.8 m/s, within 0.5 s (11.8 in the
// first step).
TEST_CASE("valid inputs: a nozzle's stream at a strong s_corr in zero gravity stays a stream", "[valid]") {
    pbf_world_id w = zero_g_open_world(0.0061934f, 2048);
    pbf_solver_params p = pbf_solver_params_default();
    REQUIRE_PBF(pbf_world_get_solver_params(w, &p));
    p.scorr_k = 0.964958f;
    p.scorr_dq = 0.400136f;
    p.relaxation = 0.272752f;
    p.substep_travel = 0.10378f;  // 16 substeps a frame
    REQUIRE_PBF(pbf_world_set_solver_params(w, &p));
    pbf_emitter_desc e = pbf_emitter_desc_default();
    e.type = PBF_EMITTER_NOZZLE;
    set3(e.position, 0.0f, 1.0f, 0.0f);
    set3(e.direction, 0.783414f, -0.610192f, -0.11802f);
    e.speed = 2.2733f;
    e.radius = 0.0371604f;
    e.particles_per_second = 2626.58f;
    pbf_emitter_id nozzle;
    REQUIRE_PBF(pbf_world_create_emitter(w, &e, &nozzle));
    const double top = run_top(w, 0.5);
    uint32_t n = 0;
    REQUIRE_PBF(pbf_world_get_particle_count(w, &n));
    INFO(n << " particles emitted; fastest over 0.5 s " << top << " m/s (nozzle " << e.speed << " m/s)");
    CHECK(n > 1000);
    CHECK(top <= e.speed + kAtRest);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A dam break at a strong s_corr (k 0.87) with few iterations (an adaptive target of 62 % mean
// compression stops them after one): a block 0.21 m high collapsing in a walled tank at the
// frame times of a game whose frames vary from 6 to 46 ms. No particle may move faster than the
// fall of its surface allows (Ritter's front, √2 · √(2gH)) plus the at-rest allowance. Before
// s_corr's rise above the defaults' push moved positions without giving velocity, it threw
// particles at 25.6 m/s against the 3.9 m/s bound.
TEST_CASE("valid inputs: a dam break at a strong s_corr is no faster than its fall", "[valid]") {
    const float r = 0.0178569f;
    pbf_world_desc d = tank(PBF_BACKEND_CPU, r, 0.714276f, 0.535707f, 0.357138f, 1024);
    d.solver.scorr_k = 0.867011f;
    d.solver.adaptive_error_target = 0.617641f;
    pbf_world_id w = create(d);
    const float height = 0.214283f;
    const uint32_t n = fill(w, 0.116126f, 0.0f, 0.033026f, 0.330408f, height, 0.318736f);
    double top = 0;
    for (const float dt : {0.0155869f, 0.00580735f, 0.0398069f, 0.0150338f, 0.0223471f, 0.0275087f, 0.034977f,
                           0.0384465f, 0.0154455f, 0.0455812f, 0.0288575f, 0.00598828f}) {
        REQUIRE_PBF(pbf_world_step(w, dt));
        top = std::max(top, top_speed(w));
    }
    top = std::max(top, run_top(w, 0.5));
    const double bound = free_fall_front(height) + kAtRest;
    INFO(n << " particles; fastest over 0.8 s " << top << " m/s, bound " << bound << " m/s");
    CHECK(top <= bound);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A nozzle whose disc reaches into a box collider (the engine placed it against a wall, half its
// disc inside): the points inside emit nothing, and what it emits is a stream like any other.
// At 1/60 s and at 1 ms steps no particle may move faster than the nozzle's speed plus its fall
// to the floor (Ritter's front) plus the at-rest allowance, none may be inside the box, and the
// emitted total is what the world holds. Emitted inside the box, the particles were projected
// out as velocity: 66.6 m/s at 1/60 s steps.
TEST_CASE("valid inputs: a nozzle half inside a collider emits only where the water has room", "[valid]") {
    for (const float dt : {kDt, 1e-3f}) {
        pbf_world_id w = create(tank(PBF_BACKEND_CPU, 0.02f, 0.6f, 0.8f, 0.6f, 4096));
        pbf_collider_desc c = pbf_collider_desc_default();
        c.shape = PBF_SHAPE_BOX;
        set3(c.position, 0.15f, 0.6f, 0.3f);
        set3(c.half_extents, 0.15f, 0.05f, 0.3f);
        pbf_collider_id box;
        REQUIRE_PBF(pbf_world_create_collider(w, &c, &box));
        pbf_emitter_desc e = pbf_emitter_desc_default();
        e.type = PBF_EMITTER_NOZZLE;
        set3(e.position, 0.3f, 0.6f, 0.3f);  // on the box's face: half the disc inside
        set3(e.direction, 0.0f, -1.0f, 0.0f);
        e.speed = 1.5f;
        e.radius = 0.15f;
        e.particles_per_second = 600.0f;
        pbf_emitter_id nozzle;
        REQUIRE_PBF(pbf_world_create_emitter(w, &e, &nozzle));
        const double seconds = dt == kDt ? 1.0 : 0.25;
        const double top = run_top(w, seconds, dt);
        const Particles p = read(w);
        double deepest = -1.0;  // how far the deepest particle centre lies inside the box (< 0: none)
        for (uint32_t i = 0; i < p.count; ++i) {
            const double x = p.pos[4 * i], y = p.pos[4 * i + 1], z = p.pos[4 * i + 2];
            deepest = std::max(deepest, std::min({x - 0.0, 0.3 - x, y - 0.55, 0.65 - y, z - 0.0, 0.6 - z}));
        }
        const pbf_step_stats st = stats(w);
        const double bound = e.speed + free_fall_front(0.6) + kAtRest;
        INFO("dt " << dt << ": " << p.count << " particles, " << st.emitted_total << " emitted of "
                   << e.particles_per_second * seconds << "; fastest " << top << " m/s (bound " << bound
                   << "), deepest inside the box " << deepest << " m");
        CHECK(top <= bound);
        CHECK(deepest < 0.0);
        CHECK(st.emitted_total == p.count);
        CHECK(p.count > 0.25 * e.particles_per_second * seconds);  // the open half of the disc emits
        CHECK(p.count < 0.75 * e.particles_per_second * seconds);
        REQUIRE_PBF(pbf_world_destroy(w));
    }
}

// A drop of water (a 0.15 m cube, 1,728 particles) at rest in zero gravity with no walls: nothing
// acts on it from outside, so its angular momentum about its centre stays zero. Tolerance, as
// the fuzzer's: 1 % of Σ m |x - c| |v| at its largest (a drop spinning rigidly has |L| equal to
// that sum) plus a floor of M R · 1e-4 m/s; over 2 s.
TEST_CASE("valid inputs: a drop at rest in zero gravity does not spin up", "[valid]") {
    pbf_world_id w = zero_g_open_world(0.00625f, 2048);
    const uint32_t n = fill(w, -0.075f, -0.075f, -0.075f, 0.075f, 0.075f, 0.075f);
    const double mass = double(mass_of(w));
    double scale = 0, worst = 0, radius = 0, top = 0;
    for (int k = 0; k < 120; ++k) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        const Particles p = read(w);
        const Momenta mo = momenta(p, mass);
        scale = std::max(scale, mo.scale_l);
        radius = std::max(radius, mo.radius);
        worst = std::max(worst, norm3(mo.l));
        top = std::max(top, top_speed(p));
    }
    const double tolerance = 0.01 * scale + mass * n * radius * 1e-4;
    INFO(n << " particles; largest |L| " << worst << " kg m2/s, tolerance " << tolerance << " (sum m|x-c||v| up to "
           << scale << "); fastest particle " << top << " m/s");
    CHECK(worst <= tolerance);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A 0.24 m box of 2,000 kg/m3 released in a pool 0.48 m square and 0.36 m deep (0.02 m particles;
// the box raises it to 0.42 m), integrated as an
// engine integrates a body (upright, vertical only; the engine's floor stops it). Once it rests
// on the floor, the water's push (about its buoyancy, half its weight) cannot lift it: over the
// last second of three it stays on the floor.
TEST_CASE("valid inputs: a heavy box resting on the floor of a pool does not chatter",
          "[valid][coupling][!shouldfail]") {
    const float half = 0.12f;
    const coupling::Box hole{{0.12f, 1.0f, 0.12f}, {0.36f, 1.0f, 0.36f}};  // above the water: nothing left out
    pbf_world_id w = coupling::pool(PBF_BACKEND_CPU, 0.48f, 0.8f, 0.48f, 0.36f, hole);
    const coupling::Box b{{0.12f, 0.37f, 0.12f}, {0.36f, 0.37f + 2 * half, 0.36f}};
    const pbf_collider_id box = coupling::add_box(w, b, PBF_MOTION_KINEMATIC);
    const double mass = 2000.0 * std::pow(2.0 * half, 3);
    double y = 0.37 + half, vy = 0, highest = 0, peak_force = 0;
    int lifts = 0;
    for (int step = 0; step < 180; ++step) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        const pbf_collider_force f = coupling::force(w, box);
        vy += (f.force[1] / mass - kG) * kDt;
        y += vy * kDt;
        if (y - half < 0) {  // the engine's floor contact
            y = half;
            vy = 0;
        }
        if (step >= 120) {
            highest = std::max(highest, y - half);
            lifts += y - half > 0 ? 1 : 0;
            peak_force = std::max(peak_force, double(f.force[1]) / (mass * kG));
        }
        const float pos[3] = {0.24f, float(y), 0.24f}, rot[4] = {0, 0, 0, 1};
        REQUIRE_PBF(pbf_collider_set_target_pose(w, box, pos, rot));
    }
    INFO("over the last second: the box left the floor in "
         << lifts << " of 60 steps, up to " << highest << " m; peak upward push " << peak_force << " x its weight");
    CHECK(lifts == 0);
    REQUIRE_PBF(pbf_world_destroy(w));
}

// A light fluid (20.7 kg/m3) under one 2.9 times denser, with a strong s_corr and a low speed
// limit, at jittery frame steps (a fuzzer world, shrunk): the heavy fluid sinks through the light
// one and presses it into the edges of the floor. Two particles may never end a step on one
// position (nothing then tells them apart: no direction between them, a zero kernel gradient).
// A plain clamp put two pressed into an edge on one point of it; the walls' restitution keeps
// distinct depths apart (core/collide.h, clamp_to_walls).
TEST_CASE("valid inputs: water pressed into the edges of the walls leaves no two particles on one position",
          "[valid][collide]") {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = PBF_BACKEND_CPU;
    d.particle_radius = 0.00610506f;
    d.rest_density = 20.6683f;
    d.max_particles = 1423;
    set3(d.domain_min, -0.0671557f, 0.0f, -0.134311f);
    set3(d.domain_max, 0.0671557f, 0.146522f, 0.134311f);
    d.solver.iterations = 8;
    d.solver.relaxation = 0.890937f;
    d.solver.scorr_k = 0.780025f;
    d.solver.vorticity_epsilon = 0.000139263f;
    d.solver.max_speed = 1.62922f;
    d.solver.substep_travel = 0.909818f;
    pbf_world_id w = create(d);
    pbf_material_desc heavy_desc = pbf_material_desc_default();
    heavy_desc.rest_density = 59.1325f;
    pbf_material_id heavy{};
    REQUIRE_PBF(pbf_world_create_material(w, &heavy_desc, &heavy));
    const float light_lo[3] = {-0.0651477f, 0.0f, -0.0819779f}, light_hi[3] = {0.0569536f, 0.0610506f, 0.00349305f};
    const float heavy_lo[3] = {-0.0604479f, 0.0814049f, 0.00124491f}, heavy_hi[3] = {0.0616534f, 0.105825f, 0.0622956f};
    fill(w, light_lo[0], light_lo[1], light_lo[2], light_hi[0], light_hi[1], light_hi[2]);
    materials::fill(w, heavy, heavy_lo, heavy_hi);
    const float dts[] = {0.0365198f, 0.0393469f, 0.0312274f, 0.0347434f, 0.00848505f,
                         0.038358f,  0.040161f,  0.0324548f, 0.0223943f, 0.00825044f};
    uint32_t shared = 0;
    for (float dt : dts) {
        REQUIRE_PBF(pbf_world_step(w, dt));
        const Particles p = read(w);
        std::vector<std::array<float, 3>> xs(p.count);
        for (uint32_t i = 0; i < p.count; ++i) xs[i] = {p.pos[4 * i], p.pos[4 * i + 1], p.pos[4 * i + 2]};
        std::sort(xs.begin(), xs.end());
        for (size_t i = 1; i < xs.size(); ++i) shared += xs[i] == xs[i - 1] ? 1u : 0u;
    }
    INFO("pairs on one position after any of the steps: " << shared);
    CHECK(shared == 0u);
    REQUIRE_PBF(pbf_world_destroy(w));
}
