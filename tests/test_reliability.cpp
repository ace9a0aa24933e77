// Reliability on the CPU backend: regression tests for what the C API fuzzer (tests/fuzz) found,
// out of memory, and emission past capacity. All through the shared library's C ABI. The
// findings were undefined behaviour (float to integer conversions out of range) or NaN state;
// AddressSanitizer + UndefinedBehaviorSanitizer builds (scripts/ci_reliability.sh) turn the
// former into failures, the checks below catch the latter in any build.
#include <catch2/catch.hpp>

#include <cfloat>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#define PBF_TEST_HAVE_SYSCONF 1
#endif

#include "reliability_support.h"
#include "support.h"

extern "C" const char* pbf_test_result_string_of_int(int value);  // reliability_c.c

using scene::set3;

namespace {

pbf_world_desc cpu_desc(uint32_t capacity = 1024) {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = PBF_BACKEND_CPU;
    d.max_particles = capacity;
    d.particle_radius = 0.025f;
    set3(d.domain_min, 0.0f, 0.0f, 0.0f);
    set3(d.domain_max, 0.5f, 0.5f, 0.5f);
    return d;
}

struct OwnedWorld {
    pbf_world_id id{};
    explicit OwnedWorld(const pbf_world_desc& d) { REQUIRE_PBF(pbf_world_create(&d, &id)); }
    ~OwnedWorld() {
        if (id.generation) pbf_world_destroy(id);
    }
    OwnedWorld(const OwnedWorld&) = delete;
    OwnedWorld& operator=(const OwnedWorld&) = delete;
};

// Every particle finite and inside the walls, the accounting exact.
void require_sane(pbf_world_id w, const pbf_world_desc& d) {
    const scene::Particles p = scene::read(w);
    CHECK(scene::all_finite(p));
    const float slack = 1e-5f * (1.0f + std::fabs(d.domain_min[0]) + std::fabs(d.domain_max[0]));
    CHECK(scene::inside(p, d, slack));
    const pbf_step_stats s = scene::stats(w);
    CHECK(s.emitted_total - s.drained_total == s.particle_count);
    CHECK(s.particle_count == p.count);
}

pbf_emitter_id add_nozzle(pbf_world_id w, float radius, float pps, const float pos[3], float speed = 1.0f) {
    pbf_emitter_desc e = pbf_emitter_desc_default();
    e.type = PBF_EMITTER_NOZZLE;
    std::memcpy(e.position, pos, sizeof e.position);
    e.speed = speed;
    e.radius = radius;
    e.particles_per_second = pps;
    pbf_emitter_id id{};
    REQUIRE_PBF(pbf_world_create_emitter(w, &e, &id));
    return id;
}

}  // namespace

// ---- fuzz findings ------------------------------------------------------------------------------
// Finding 1: World::create formatted the refused grid's cell count through a uint64_t cast, out of
// range (undefined) when the domain is astronomically large for the radius. Since open levels,
// a big box gets a hashed grid; what still refuses it is its extent from the origin
// (validation check WORLD_DOMAIN_EXTENT), where float no longer resolves h.
TEST_CASE("fuzz: a domain of more than 2^64 grid cells is refused for its extent", "[reliability][fuzz]") {
    for (float extent : {1e8f, 1e20f, 1e30f, 3e38f}) {  // 3e38: max - min overflows to Inf
        pbf_world_desc d = cpu_desc();
        set3(d.domain_min, -extent, -extent, -extent);
        set3(d.domain_max, extent, extent, extent);
        pbf_world_id id{7, 7};
        INFO("domain +-" << extent);
        CHECK(pbf_world_create(&d, &id) == PBF_ERROR_INVALID_ARGUMENT);
        CHECK(id.generation == 0);
        CHECK_THAT(std::string(pbf_last_error_message()), Catch::Contains("of the origin on every axis"));
    }
}

// Finding 2: the nozzle's disc point count π r²/s² was converted to uint32 unclamped: Inf (or
// above 2^32) for a huge, finite radius.
TEST_CASE("fuzz: a nozzle with a huge radius emits and the world stays sane", "[reliability][fuzz]") {
    const pbf_world_desc d = cpu_desc(512);
    OwnedWorld w(d);
    const float pos[3] = {0.25f, 0.4f, 0.25f};
    add_nozzle(w.id, 1e30f, 600.0f, pos);
    add_nozzle(w.id, 3e38f, 600.0f, pos);
    add_nozzle(w.id, 1e5f, 600.0f, pos);
    for (int k = 0; k < 30; ++k) REQUIRE_PBF(pbf_world_step(w.id, kDt));
    CHECK(scene::stats(w.id).emitted_total > 0u);
    require_sane(w.id, d);
}

// Finding 3: the grid converted floor((x - origin)/h) to int32 before clamping: undefined for a
// particle far outside the grid (a block or nozzle placed at 1e30 m, binned right after emission).
// Since the real-time work, emission outside the walls is refused (a block is clipped to them, a
// nozzle must sit inside): such a request changes nothing, and a block reaching in from far out
// is clipped to the particles inside. The grid's clamp still guards particles pushed far out.
TEST_CASE("fuzz: emission far outside the grid is refused or clipped to the walls", "[reliability][fuzz]") {
    const float far[][3] = {{1e30f, 0.2f, 0.2f}, {-1e30f, 1e30f, -1e30f}, {0.2f, 3e38f, 0.2f}, {0.2f, 0.2f, -3e38f}};
    for (const auto& p : far) {
        INFO("at " << p[0] << ", " << p[1] << ", " << p[2]);
        const pbf_world_desc d = cpu_desc(512);
        OwnedWorld w(d);
        pbf_block_desc b = pbf_block_desc_default();
        std::memcpy(b.box_min, p, sizeof b.box_min);
        for (int a = 0; a < 3; ++a)
            b.box_max[a] =
                std::fabs(p[a]) > 1.0f ? std::nextafter(p[a], std::numeric_limits<float>::infinity()) : p[a] + 0.1f;
        uint32_t n = 7;
        CHECK(pbf_world_emit_block(w.id, &b, &n) == PBF_ERROR_INVALID_ARGUMENT);
        CHECK(n == 0u);
        pbf_emitter_desc e = pbf_emitter_desc_default();
        e.type = PBF_EMITTER_NOZZLE;
        std::memcpy(e.position, p, sizeof e.position);
        e.speed = 1.0f;
        e.radius = 0.05f;
        e.particles_per_second = 300.0f;
        pbf_emitter_id id{};
        CHECK(pbf_world_create_emitter(w.id, &e, &id) == PBF_ERROR_INVALID_ARGUMENT);
        for (int k = 0; k < 3; ++k) REQUIRE_PBF(pbf_world_step(w.id, kDt));
        CHECK(scene::stats(w.id).emitted_total == 0u);
        // A block from far outside into the domain: the lattice points inside are emitted.
        pbf_block_desc across = pbf_block_desc_default();
        for (int a = 0; a < 3; ++a) {
            across.box_min[a] = std::fmin(p[a], d.domain_min[a]);
            across.box_max[a] = std::fmax(p[a], d.domain_max[a]);
        }
        REQUIRE_PBF(pbf_world_emit_block(w.id, &across, &n));
        CHECK(n > 0u);
        CHECK(std::isfinite(scene::stats(w.id).density_error_max));
        for (int k = 0; k < 3; ++k) REQUIRE_PBF(pbf_world_step(w.id, kDt));
        require_sane(w.id, d);
    }
}

// Finding 4: a tiny dt made 1/dt and the LDC gain / dt² overflow to Inf, and Inf·0 gave NaN
// velocities; a huge gravity or max_speed did the same through |v|² overflowing. clamp_speed now
// never returns Inf or NaN.
TEST_CASE("fuzz: tiny dt, huge gravity and huge max_speed keep every velocity finite", "[reliability][fuzz]") {
    const float tiny[] = {std::numeric_limits<float>::denorm_min(), 3e-40f, FLT_MIN, 1e-30f, 1e-19f, 1e-12f, 1e-6f};
    for (int ldc = 0; ldc <= 1; ++ldc) {
        pbf_world_desc d = cpu_desc(1024);
        d.solver.ldc_enabled = uint32_t(ldc);
        OwnedWorld w(d);
        scene::fill(w.id, 0.0f, 0.0f, 0.0f, 0.3f, 0.3f, 0.3f);
        REQUIRE_PBF(pbf_world_step(w.id, kDt));
        for (float dt : tiny) {
            INFO("ldc " << ldc << ", dt " << dt);
            REQUIRE_PBF(pbf_world_step(w.id, dt));
            require_sane(w.id, d);
        }
        pbf_solver_params p = pbf_solver_params_default();
        REQUIRE_PBF(pbf_world_get_solver_params(w.id, &p));
        p.max_speed = FLT_MAX;
        REQUIRE_PBF(pbf_world_set_solver_params(w.id, &p));
        const float g[3] = {FLT_MAX, -FLT_MAX, 1e38f};
        REQUIRE_PBF(pbf_world_set_gravity(w.id, g));
        for (int k = 0; k < 5; ++k) {
            INFO("ldc " << ldc << ", huge gravity, step " << k);
            REQUIRE_PBF(pbf_world_step(w.id, 1.0f));
            require_sane(w.id, d);
        }
    }
}

// Finding 5: a radius or rest density whose SPH constants over- or underflow in float (a denormal
// rest density, a radius of 1e-30 m in a matching domain, 1e10 m) was accepted: every density
// and velocity NaN. Now refused at creation.
TEST_CASE("fuzz: radius and rest density whose SPH constants leave float range are refused", "[reliability][fuzz]") {
    struct Case {
        float radius, rest_density, span;
    };
    const Case cases[] = {{0.025f, 3.57e-43f, 0.5f}, {0.025f, FLT_MIN, 0.5f}, {0.025f, FLT_MAX, 0.5f},
                          {1e-30f, 1000.0f, 1e-28f}, {1e10f, 1000.0f, 1e11f}, {1e20f, 1000.0f, 1e21f}};
    for (const Case& c : cases) {
        pbf_world_desc d = cpu_desc();
        d.particle_radius = c.radius;
        d.rest_density = c.rest_density;
        set3(d.domain_max, c.span, c.span, c.span);
        pbf_world_id id{3, 3};
        INFO("radius " << c.radius << ", rest_density " << c.rest_density);
        CHECK(pbf_world_create(&d, &id) == PBF_ERROR_INVALID_ARGUMENT);
        CHECK(id.generation == 0);
    }
    // The ends of the usable range still work.
    for (float radius : {1e-3f, 0.025f, 1.0f, 100.0f}) {
        pbf_world_desc d = cpu_desc(256);
        d.particle_radius = radius;
        set3(d.domain_max, 20 * radius, 20 * radius, 20 * radius);
        INFO("radius " << radius);
        OwnedWorld w(d);
        scene::fill(w.id, 0, 0, 0, 8 * radius, 8 * radius, 8 * radius);
        for (int k = 0; k < 5; ++k) REQUIRE_PBF(pbf_world_step(w.id, kDt));
        require_sane(w.id, d);
    }
}

// Finding 6: pbf_result_string switched on its enum argument: a C caller may pass any int, and
// loading an out-of-range value through the C++ enum type is undefined.
TEST_CASE("fuzz: pbf_result_string takes any int from C", "[reliability][fuzz]") {
    for (int v : {-1, 11, 100, 0x7FFFFFFF, int(0x80000000u), int(0xFFFF0053u)})
        CHECK(std::string(pbf_test_result_string_of_int(v)) == "PBF_ERROR_UNKNOWN");
    CHECK(std::string(pbf_test_result_string_of_int(0)) == "PBF_OK");
    CHECK(std::string(pbf_test_result_string_of_int(2)) == "PBF_ERROR_INVALID_HANDLE");
}

// ---- out of memory ----------------------------------------------------------------------------------
TEST_CASE("memory: a world above 3/4 of physical memory fails with OUT_OF_MEMORY; others keep stepping",
          "[reliability][memory]") {
#ifdef PBF_TEST_HAVE_SYSCONF
    const double phys = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
#else
    const double phys = 0.0;
#endif
    // Bytes a particle costs, from two small worlds.
    pbf_world_info a, b;
    std::memset(&a, 0, sizeof a);
    std::memset(&b, 0, sizeof b);
    a.struct_size = b.struct_size = sizeof a;
    {
        OwnedWorld w1(cpu_desc(1000)), w2(cpu_desc(2000));
        REQUIRE_PBF(pbf_world_get_info(w1.id, &a));
        REQUIRE_PBF(pbf_world_get_info(w2.id, &b));
    }
    const double per_particle = double(b.device_bytes - a.device_bytes) / 1000.0;
    REQUIRE(per_particle > 32.0);
    const double wanted = 0.8 * phys / per_particle;  // just above the 3/4 limit
    if (!(phys > 0) || wanted > double(1u << 30)) {
        WARN("skipped: " << phys / 1e9 << " GB of physical memory cannot be exceeded by 2^30 particles");
        return;
    }

    // The survivor: a world with a nozzle and a drain, stepping before and after.
    rel::World survivor;
    REQUIRE(rel::make_world(PBF_BACKEND_CPU, 0, &survivor) == "");
    REQUIRE(rel::drive(survivor, 0, 10) == "");
    rel::Capture before;
    REQUIRE(rel::capture(survivor.id, &before) == "");

    for (double factor : {1.0, 2.0, 1024.0}) {
        pbf_world_desc d = cpu_desc(uint32_t(std::min(wanted * factor, double(1u << 30))));
        pbf_world_id id{5, 5};
        INFO(d.max_particles << " particles, ~" << d.max_particles * per_particle / 1e9 << " GB of " << phys / 1e9
                             << " GB");
        const pbf_result r = pbf_world_create(&d, &id);
        CHECK(r == PBF_ERROR_OUT_OF_MEMORY);
        CHECK(id.generation == 0);
        CHECK_THAT(std::string(pbf_last_error_message()), Catch::Contains("PBF_ERROR_OUT_OF_MEMORY"));
        CHECK_THAT(std::string(pbf_last_error_message()), Catch::Contains(std::to_string(d.max_particles)));
    }

    // The survivor is unaffected: it steps on exactly as a twin that never saw the failures.
    rel::check_like_twin(PBF_BACKEND_CPU, survivor, 10, 20);
    REQUIRE_PBF(pbf_world_destroy(survivor.id));
    // And new worlds can still be made.
    OwnedWorld fresh(cpu_desc(4096));
    CHECK(scene::fill(fresh.id, 0, 0, 0, 0.2f, 0.2f, 0.2f) > 0u);
    REQUIRE_PBF(pbf_world_step(fresh.id, kDt));
}

// ---- capacity -----------------------------------------------------------------------------------------
TEST_CASE("capacity: emitting past capacity is refused cleanly, by blocks and by nozzles", "[reliability][capacity]") {
    const pbf_world_desc d = cpu_desc(300);
    OwnedWorld w(d);
    // A block of 10^3 lattice points: 300 fit, the call says so.
    pbf_block_desc b = pbf_block_desc_default();
    set3(b.box_min, 0.0f, 0.0f, 0.0f);
    set3(b.box_max, 0.5f, 0.5f, 0.5f);
    uint32_t emitted = 0;
    REQUIRE_PBF(pbf_world_emit_block(w.id, &b, &emitted));
    CHECK(emitted == 300u);
    const scene::Particles full = scene::read(w.id);
    // Full: refused with CAPACITY, nothing changes.
    emitted = 77;
    CHECK(pbf_world_emit_block(w.id, &b, &emitted) == PBF_ERROR_CAPACITY);
    CHECK(emitted == 0u);
    const scene::Particles again = scene::read(w.id);
    CHECK(again.count == 300u);
    CHECK(again.ids == full.ids);
    CHECK(std::memcmp(again.pos.data(), full.pos.data(), full.pos.size() * sizeof(float)) == 0);
    // A nozzle at 10^6 particles/s into the full world: steps succeed, nothing is emitted.
    const float pos[3] = {0.25f, 0.45f, 0.25f};
    add_nozzle(w.id, 0.1f, 1e6f, pos, 5000.0f);  // fast enough that the disc carries the rate
    for (int k = 0; k < 20; ++k) {
        REQUIRE_PBF(pbf_world_step(w.id, kDt));
        const pbf_step_stats s = scene::stats(w.id);
        REQUIRE(s.particle_count == 300u);
        REQUIRE(s.emitted_total == 300u);
    }
    require_sane(w.id, d);
    // A drain makes room; the nozzle refills exactly what was drained, never past capacity.
    pbf_emitter_desc dr = pbf_emitter_desc_default();
    dr.type = PBF_EMITTER_DRAIN;
    set3(dr.box_min, 0.0f, 0.0f, 0.0f);
    set3(dr.box_max, 0.5f, 0.1f, 0.5f);
    pbf_emitter_id drain{};
    REQUIRE_PBF(pbf_world_create_emitter(w.id, &dr, &drain));
    for (int k = 0; k < 60; ++k) {
        REQUIRE_PBF(pbf_world_step(w.id, kDt));
        const pbf_step_stats s = scene::stats(w.id);
        REQUIRE(s.particle_count <= 300u);
        REQUIRE(s.emitted_total - s.drained_total == s.particle_count);
    }
    CHECK(scene::stats(w.id).drained_total > 0u);
    CHECK(scene::stats(w.id).emitted_total > 300u);
    require_sane(w.id, d);
}

// A block whose lattice is wider than 2^16 x 2^16 points in x and y: the op's x*y product must
// not overflow 32 bits (k / (nx*ny) would divide by zero).
TEST_CASE("capacity: a huge block into a 65536-particle world fills it exactly", "[reliability][capacity]") {
    pbf_world_desc d = cpu_desc(65536);
    set3(d.domain_min, -2000.0f, -2000.0f, -4.0f);
    set3(d.domain_max, 2000.0f, 2000.0f, 4.0f);
    d.particle_radius = 1.0f;  // a modest grid: h = 4 m
    OwnedWorld w(d);
    pbf_block_desc b = pbf_block_desc_default();
    set3(b.box_min, -1e6f, -1e6f, -0.5f);
    set3(b.box_max, 1e6f, 1e6f, 0.5f);
    uint32_t emitted = 0;
    REQUIRE_PBF(pbf_world_emit_block(w.id, &b, &emitted));
    CHECK(emitted == 65536u);
    const scene::Particles p = scene::read(w.id);
    CHECK(p.count == 65536u);
    CHECK(scene::all_finite(p));
}
