// The one support header of the Catch2 suites: assertion macros for result codes, small worlds
// and descs for the C ABI tests, and the scenes (tank, fill, read-back) that the CPU scene, [gpu]
// and interop tests share. Black-box: only the public header. reliability_support.h adds the
// thread scenarios on top of it.
#pragma once
#include <catch2/catch.hpp>

#include <pbf_c_api.h>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#define PBF_TEST_HAVE_SYSCONF 1
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

inline void set3(float* v, float x, float y, float z) {
    v[0] = x;
    v[1] = y;
    v[2] = z;
}

// ---- fixtures of the C ABI tests (test_api_*.cpp) --------------------------------------------
inline const float kNaN = std::numeric_limits<float>::quiet_NaN();
inline const float kInf = std::numeric_limits<float>::infinity();
inline const float kBad[] = {kNaN, kInf, -kInf};
inline const char* bad_name(float v) { return std::isnan(v) ? "NaN" : (v > 0 ? "+Inf" : "-Inf"); }
inline const float kDt = 1.0f / 60.0f;

inline std::string last_message() { return pbf_last_error_message(); }

// Asserts the exact result code, that the message names the code (the library prefixes it) and
// that it mentions `needle` (the offending field or object).
#define CHECK_FAILS(call, code, needle)                                                    \
    do {                                                                                   \
        const pbf_result r_ = (call);                                                      \
        INFO(#call << " -> " << pbf_result_string(r_) << " \"" << last_message() << "\""); \
        CHECK(std::string(pbf_result_string(r_)) == std::string(pbf_result_string(code))); \
        if (r_ != PBF_OK) {                                                                \
            CHECK_THAT(last_message(), Catch::Contains(pbf_result_string(code)));          \
            CHECK_THAT(last_message(), Catch::Contains(needle));                           \
        }                                                                                  \
    } while (0)

#define REQUIRE_OK(call)                                                                   \
    do {                                                                                   \
        const pbf_result r_ = (call);                                                      \
        INFO(#call << " -> " << pbf_result_string(r_) << " \"" << last_message() << "\""); \
        REQUIRE(r_ == PBF_OK);                                                             \
    } while (0)

inline bool same_id(pbf_emitter_id a, pbf_emitter_id b) { return a.index == b.index && a.generation == b.generation; }

// A small CPU world: spacing 0.05, h = 0.1, domain 1 x 1 x 1 m (1000 grid cells).
inline pbf_world_desc small_desc(uint32_t max_particles = 4096) {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = PBF_BACKEND_CPU;
    d.max_particles = max_particles;
    d.particle_radius = 0.025f;
    const float lo[3] = {-0.5f, 0.0f, -0.5f}, hi[3] = {0.5f, 1.0f, 0.5f};
    std::memcpy(d.domain_min, lo, sizeof lo);
    std::memcpy(d.domain_max, hi, sizeof hi);
    return d;
}

inline pbf_block_desc block(float x0, float y0, float z0, float x1, float y1, float z1) {
    pbf_block_desc b = pbf_block_desc_default();
    const float lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    std::memcpy(b.box_min, lo, sizeof lo);
    std::memcpy(b.box_max, hi, sizeof hi);
    return b;
}

inline pbf_emitter_desc nozzle_desc() {
    pbf_emitter_desc e = pbf_emitter_desc_default();
    e.type = PBF_EMITTER_NOZZLE;
    e.position[0] = 0.0f;
    e.position[1] = 0.7f;
    e.position[2] = 0.0f;
    e.speed = 1.0f;
    e.radius = 0.15f;
    e.particles_per_second = 500.0f;  // the disc carries π 0.15² / 0.05² x 1 / 0.05 = 565 per second
    return e;
}

inline pbf_emitter_desc drain_desc() {
    pbf_emitter_desc e = pbf_emitter_desc_default();
    e.type = PBF_EMITTER_DRAIN;
    const float lo[3] = {0.4f, 0.0f, 0.4f}, hi[3] = {0.5f, 0.1f, 0.5f};
    std::memcpy(e.box_min, lo, sizeof lo);
    std::memcpy(e.box_max, hi, sizeof hi);
    return e;
}

inline pbf_collider_desc collider_desc(pbf_collider_shape shape, pbf_collider_motion motion = PBF_MOTION_STATIC) {
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = shape;
    c.motion = motion;
    c.position[1] = 0.5f;
    c.radius = 0.1f;
    c.half_height = 0.1f;
    c.half_extents[0] = c.half_extents[1] = c.half_extents[2] = 0.1f;
    return c;
}

// Owns a world for one test case.
struct TestWorld {
    pbf_world_id id{0, 0};
    explicit TestWorld(const pbf_world_desc& d) { REQUIRE_OK(pbf_world_create(&d, &id)); }
    explicit TestWorld(uint32_t max_particles = 4096) : TestWorld(small_desc(max_particles)) {}
    ~TestWorld() {
        if (id.generation != 0) pbf_world_destroy(id);
    }
    TestWorld(const TestWorld&) = delete;
    TestWorld& operator=(const TestWorld&) = delete;
    void release() { id = pbf_world_id{0, 0}; }
    operator pbf_world_id() const { return id; }

    uint32_t count() const {
        uint32_t n = 0xFFFFFFFFu;
        REQUIRE_OK(pbf_world_get_particle_count(id, &n));
        return n;
    }
    uint32_t emit(const pbf_block_desc& b) const {
        uint32_t n = 0;
        REQUIRE_OK(pbf_world_emit_block(id, &b, &n));
        return n;
    }
    // A 0.3 m cube of water (6^3 = 216 particles) resting on the floor.
    uint32_t emit_default_block() const { return emit(block(-0.15f, 0.0f, -0.15f, 0.15f, 0.3f, 0.15f)); }
    std::vector<float> positions() const {
        const uint32_t n = count();
        std::vector<float> p(size_t(n) * 4 + 4, -7.0f);
        uint32_t written = 0;
        REQUIRE_OK(pbf_world_copy_positions(id, p.data(), n, &written));
        REQUIRE(written == n);
        p.resize(size_t(n) * 4);
        return p;
    }
    std::vector<uint32_t> ids() const {
        const uint32_t n = count();
        std::vector<uint32_t> v(n);
        uint32_t written = 0;
        REQUIRE_OK(pbf_world_copy_ids(id, v.data(), n, &written));
        REQUIRE(written == n);
        return v;
    }
    pbf_solver_params params() const {
        pbf_solver_params p = pbf_solver_params_default();
        REQUIRE_OK(pbf_world_get_solver_params(id, &p));
        return p;
    }
    // The world still works: a step succeeds and the particle count is what it was (no emitter
    // or drain in the worlds that call this).
    void require_usable(uint32_t expected_count) const {
        REQUIRE(count() == expected_count);
        REQUIRE_OK(pbf_world_step(id, kDt));
        REQUIRE(count() == expected_count);
        pbf_step_stats s{};
        s.struct_size = sizeof s;
        REQUIRE_OK(pbf_world_get_stats(id, &s));
        REQUIRE(s.particle_count == expected_count);
    }
};

// Every member of the positions is bitwise what it was.
inline bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

inline bool same_params(const pbf_solver_params& a, const pbf_solver_params& b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// d with one edit applied: a desc one field away from a valid one, as a row of a table of refusals.
template <class Desc, class Edit>
inline Desc edited(Desc d, Edit edit) {
    edit(d);
    return d;
}

// REQUIRE_OK under the name the scene tests use.
#define REQUIRE_PBF(call) REQUIRE_OK(call)

// ---- scenes shared by the CPU scene tests, the [gpu] tests and the interop tests --------------

namespace scene {

using ::set3;

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

// An output struct, zeroed with its struct_size set, as get(w, &s) fills it.
template <class T, class Get>
inline T read_struct(pbf_world_id w, Get get) {
    T s;
    std::memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    REQUIRE_PBF(get(w, &s));
    return s;
}

inline pbf_step_stats stats(pbf_world_id w) { return read_struct<pbf_step_stats>(w, pbf_world_get_stats); }

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

// Creates the world of desc d (REQUIRE: it succeeds); the caller destroys it.
inline pbf_world_id create(const pbf_world_desc& d) {
    pbf_world_id w{0, 0};
    REQUIRE_PBF(pbf_world_create(&d, &w));
    return w;
}

// A kinematic box collider centred at (x, y, z) with half extents (hx, hy, hz), created in w: the
// paddles and plates the scenes move by its target pose. dynamic: the fluid's force on it is
// recorded.
inline pbf_collider_id kinematic_box(pbf_world_id w, float x, float y, float z, float hx, float hy, float hz,
                                     bool dynamic = false) {
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_BOX;
    c.motion = PBF_MOTION_KINEMATIC;
    c.dynamic = dynamic ? 1u : 0u;
    set3(c.half_extents, hx, hy, hz);
    set3(c.position, x, y, z);
    pbf_collider_id id{};
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &id));
    return id;
}

// A static sphere of the given radius centred at (x, y, z).
inline pbf_collider_id static_sphere(pbf_world_id w, float radius, float x, float y, float z) {
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_SPHERE;
    c.radius = radius;
    set3(c.position, x, y, z);
    pbf_collider_id id{};
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &id));
    return id;
}

// A nozzle at (x, y, z), pointing down (the default direction), with the given speed, disc
// radius and rate.
inline pbf_emitter_desc nozzle_at(float x, float y, float z, float speed, float radius, float particles_per_second) {
    pbf_emitter_desc e = pbf_emitter_desc_default();
    e.type = PBF_EMITTER_NOZZLE;
    set3(e.position, x, y, z);
    e.speed = speed;
    e.radius = radius;
    e.particles_per_second = particles_per_second;
    return e;
}

// A drain removing what enters the box (x0, y0, z0)-(x1, y1, z1).
inline pbf_emitter_desc drain_box(float x0, float y0, float z0, float x1, float y1, float z1) {
    pbf_emitter_desc e = pbf_emitter_desc_default();
    e.type = PBF_EMITTER_DRAIN;
    set3(e.box_min, x0, y0, z0);
    set3(e.box_max, x1, y1, z1);
    return e;
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

// ---- render data (pbf_render_params) --------------------------------------------------------
// The positions with the render buffers the world computes (empty where it computes none).
struct RenderData {
    std::vector<float> pos, smoothed, aniso;  // 4 floats per particle; aniso 12 (3 rows)
    uint32_t count = 0;
    const float* row(uint32_t i, int k) const { return &aniso[size_t(i) * 12 + size_t(k) * 4]; }
};

inline pbf_world_info world_info(pbf_world_id w) { return read_struct<pbf_world_info>(w, pbf_world_get_info); }

// Profiling on, one step of w; the milliseconds of the stage named `name` in it.
inline float profiled_stage_ms(pbf_world_id w, const char* name, float dt = 1.0f / 60.0f) {
    uint32_t stage = 0;
    while (pbf_profile_stage_name(stage) && std::string(pbf_profile_stage_name(stage)) != name) ++stage;
    REQUIRE(pbf_profile_stage_name(stage) != nullptr);
    REQUIRE_PBF(pbf_world_set_profiling(w, 1));
    REQUIRE_PBF(pbf_world_step(w, dt));
    return read_struct<pbf_step_profile>(w, pbf_world_get_profile).stage_ms[stage];
}

// pbf_world_map_device_buffers(w, flags) into a zeroed struct.
inline pbf_device_buffers map_buffers(pbf_world_id w, uint32_t flags = 0) {
    return read_struct<pbf_device_buffers>(
        w, [flags](pbf_world_id id, pbf_device_buffers* out) { return pbf_world_map_device_buffers(id, flags, out); });
}

// Steps both worlds n times.
inline void step_both(pbf_world_id a, pbf_world_id b, int n, float dt = 1.0f / 60.0f) {
    for (int k = 0; k < n; ++k) {
        REQUIRE_PBF(pbf_world_step(a, dt));
        REQUIRE_PBF(pbf_world_step(b, dt));
    }
}

inline RenderData read_render(pbf_world_id w) {
    RenderData r;
    REQUIRE_PBF(pbf_world_get_particle_count(w, &r.count));
    const uint32_t flags = world_info(w).render_flags;
    auto copy = [&](pbf_buffer source, std::vector<float>& out, size_t floats) {
        out.assign(size_t(r.count) * floats, -7.0f);
        uint32_t n = 0;
        REQUIRE_PBF(pbf_world_copy_buffer(w, source, out.data(), out.size() * sizeof(float), &n));
        REQUIRE(n == r.count);
    };
    copy(PBF_BUFFER_POSITIONS, r.pos, 4);
    if (flags & PBF_RENDER_SMOOTHED_POSITIONS) copy(PBF_BUFFER_SMOOTHED_POSITIONS, r.smoothed, 4);
    if (flags & PBF_RENDER_ANISOTROPY) copy(PBF_BUFFER_ANISOTROPY, r.aniso, 12);
    return r;
}

// Particle i's ellipsoid Σ_k r_k² a_k a_kᵀ (xx, xy, xz, yy, yz, zz): independent of the axes'
// signs and of the basis chosen for equal radii, so two backends' results compare entry-wise.
inline std::array<double, 6> ellipsoid(const RenderData& r, uint32_t i) {
    std::array<double, 6> e{};
    for (int k = 0; k < 3; ++k) {
        const float* a = r.row(i, k);
        const double r2 = double(a[3]) * a[3];
        e[0] += r2 * a[0] * a[0];
        e[1] += r2 * a[0] * a[1];
        e[2] += r2 * a[0] * a[2];
        e[3] += r2 * a[1] * a[1];
        e[4] += r2 * a[1] * a[2];
        e[5] += r2 * a[2] * a[2];
    }
    return e;
}

// ---- diffuse particles (pbf_diffuse_params) -------------------------------------------------
// The diffuse particles: position (x, y, z, kind) and velocity (vx, vy, vz, remaining lifetime).
struct Diffuse {
    std::vector<float> pos, vel;
    uint32_t count = 0;
    uint32_t of_kind(float kind) const {
        uint32_t n = 0;
        for (uint32_t i = 0; i < count; ++i) n += pos[4 * i + 3] == kind ? 1u : 0u;
        return n;
    }
};

inline Diffuse read_diffuse(pbf_world_id w) {
    Diffuse d;
    d.count = stats(w).diffuse_count;
    d.pos.assign(size_t(d.count) * 4, -7.0f);
    d.vel.assign(size_t(d.count) * 4, -7.0f);
    uint32_t n = 0;
    REQUIRE_PBF(pbf_world_copy_buffer(w, PBF_BUFFER_DIFFUSE_POSITIONS, d.pos.data(), d.pos.size() * sizeof(float), &n));
    REQUIRE(n == d.count);
    REQUIRE_PBF(
        pbf_world_copy_buffer(w, PBF_BUFFER_DIFFUSE_VELOCITIES, d.vel.data(), d.vel.size() * sizeof(float), &n));
    REQUIRE(n == d.count);
    return d;
}

// The dam break of the diffuse tests: a 0.2 x 0.4 x 0.1 m column (512 particles) at one end of a
// 0.8 x 0.5 x 0.1 m tank, diffuse capacity `capacity`.
inline pbf_world_id diffuse_dam(pbf_backend backend, uint32_t capacity) {
    pbf_world_desc d = tank(backend, 0.0125f, 0.8f, 0.5f, 0.1f, 4096);
    d.solver.substeps = 2;
    d.diffuse.max_diffuse = capacity;
    pbf_world_id w = create(d);
    REQUIRE(fill(w, 0, 0, 0, 0.2f, 0.4f, 0.1f) == 512u);
    return w;
}

}  // namespace scene
