// Black-box tests of the C ABI (include/pbf_c_api.h) on the CPU backend: argument validation,
// handles, capacity, mapping, logging and the "a failed call changes nothing" contract.
// Only the public header is used; every world here is small so the file runs in seconds.
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

namespace {

const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();
const float kBad[] = {kNaN, kInf, -kInf};
const char* bad_name(float v) { return std::isnan(v) ? "NaN" : (v > 0 ? "+Inf" : "-Inf"); }
const float kDt = 1.0f / 60.0f;

std::string last_message() { return pbf_last_error_message(); }

// Asserts the exact result code, that the message names the code (the library prefixes it) and
// that it mentions `needle` (the offending field or object).
#define CHECK_FAILS(call, code, needle)                                                             \
    do {                                                                                            \
        const pbf_result r_ = (call);                                                               \
        INFO(#call << " -> " << pbf_result_string(r_) << " \"" << last_message() << "\"");         \
        CHECK(std::string(pbf_result_string(r_)) == std::string(pbf_result_string(code)));          \
        if (r_ != PBF_OK) {                                                                         \
            CHECK_THAT(last_message(), Catch::Contains(pbf_result_string(code)));                   \
            CHECK_THAT(last_message(), Catch::Contains(needle));                                    \
        }                                                                                           \
    } while (0)

#define REQUIRE_OK(call)                                                                            \
    do {                                                                                            \
        const pbf_result r_ = (call);                                                               \
        INFO(#call << " -> " << pbf_result_string(r_) << " \"" << last_message() << "\"");         \
        REQUIRE(r_ == PBF_OK);                                                                      \
    } while (0)

bool same_id(pbf_emitter_id a, pbf_emitter_id b) { return a.index == b.index && a.generation == b.generation; }

// A small CPU world: spacing 0.05, h = 0.1, domain 1 x 1 x 1 m (1000 grid cells).
pbf_world_desc small_desc(uint32_t max_particles = 4096) {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = PBF_BACKEND_CPU;
    d.max_particles = max_particles;
    d.particle_radius = 0.025f;
    const float lo[3] = {-0.5f, 0.0f, -0.5f}, hi[3] = {0.5f, 1.0f, 0.5f};
    std::memcpy(d.domain_min, lo, sizeof lo);
    std::memcpy(d.domain_max, hi, sizeof hi);
    return d;
}

pbf_block_desc block(float x0, float y0, float z0, float x1, float y1, float z1) {
    pbf_block_desc b = pbf_block_desc_default();
    const float lo[3] = {x0, y0, z0}, hi[3] = {x1, y1, z1};
    std::memcpy(b.box_min, lo, sizeof lo);
    std::memcpy(b.box_max, hi, sizeof hi);
    return b;
}

pbf_emitter_desc nozzle_desc() {
    pbf_emitter_desc e = pbf_emitter_desc_default();
    e.type = PBF_EMITTER_NOZZLE;
    e.position[0] = 0.0f;
    e.position[1] = 0.7f;
    e.position[2] = 0.0f;
    e.speed = 1.0f;
    e.radius = 0.05f;
    e.particles_per_second = 600.0f;
    return e;
}

pbf_emitter_desc drain_desc() {
    pbf_emitter_desc e = pbf_emitter_desc_default();
    e.type = PBF_EMITTER_DRAIN;
    const float lo[3] = {0.4f, 0.0f, 0.4f}, hi[3] = {0.5f, 0.1f, 0.5f};
    std::memcpy(e.box_min, lo, sizeof lo);
    std::memcpy(e.box_max, hi, sizeof hi);
    return e;
}

pbf_collider_desc collider_desc(pbf_collider_shape shape, pbf_collider_motion motion = PBF_MOTION_STATIC) {
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
bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

bool same_params(const pbf_solver_params& a, const pbf_solver_params& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

// =============================================================================================
TEST_CASE("version: library matches the header, every result code has a name", "[api][version]") {
    CHECK(pbf_get_version() == PBF_VERSION);
    CHECK(PBF_VERSION_GET_MAJOR(pbf_get_version()) == PBF_VERSION_MAJOR);

    const std::pair<pbf_result, const char*> names[] = {
        {PBF_OK, "PBF_OK"},
        {PBF_ERROR_INVALID_ARGUMENT, "PBF_ERROR_INVALID_ARGUMENT"},
        {PBF_ERROR_INVALID_HANDLE, "PBF_ERROR_INVALID_HANDLE"},
        {PBF_ERROR_STRUCT_SIZE, "PBF_ERROR_STRUCT_SIZE"},
        {PBF_ERROR_VERSION_MISMATCH, "PBF_ERROR_VERSION_MISMATCH"},
        {PBF_ERROR_CAPACITY, "PBF_ERROR_CAPACITY"},
        {PBF_ERROR_OUT_OF_MEMORY, "PBF_ERROR_OUT_OF_MEMORY"},
        {PBF_ERROR_BACKEND_UNAVAILABLE, "PBF_ERROR_BACKEND_UNAVAILABLE"},
        {PBF_ERROR_BACKEND, "PBF_ERROR_BACKEND"},
        {PBF_ERROR_INVALID_STATE, "PBF_ERROR_INVALID_STATE"},
        {PBF_ERROR_INTERNAL, "PBF_ERROR_INTERNAL"},
    };
    std::set<std::string> distinct;
    for (const auto& n : names) {
        const char* s = pbf_result_string(n.first);
        REQUIRE(s != nullptr);
        CHECK(std::string(s) == n.second);
        distinct.insert(s);
    }
    CHECK(distinct.size() == sizeof names / sizeof names[0]);
    // Unknown codes still get a static, non-NULL name that is none of the real ones.
    for (int code : {11, 100, -1, 0x7FFFFFFF}) {
        const char* s = pbf_result_string(static_cast<pbf_result>(code));
        REQUIRE(s != nullptr);
        CHECK(distinct.count(s) == 0);
    }
}

TEST_CASE("version: a desc from another header major is refused", "[api][version]") {
    TestWorld other;
    REQUIRE(other.emit_default_block() > 0);
    const uint32_t n = other.count();

    // The majors just below and above this header's, 0, and the largest a version can hold.
    for (uint32_t major : {0u, PBF_VERSION_MAJOR - 1u, PBF_VERSION_MAJOR + 1u, 1023u}) {
        INFO("header major " << major);
        pbf_world_desc d = small_desc();
        d.header_version = PBF_MAKE_VERSION(major, PBF_VERSION_MINOR, PBF_VERSION_PATCH);
        pbf_world_id w{77, 77};
        CHECK_FAILS(pbf_world_create(&d, &w), PBF_ERROR_VERSION_MISMATCH, "header");
        CHECK(w.index == 0);
        CHECK(w.generation == 0);
    }
    // Another minor or patch of the same major is accepted.
    pbf_world_desc d = small_desc();
    d.header_version = PBF_MAKE_VERSION(PBF_VERSION_MAJOR, PBF_VERSION_MINOR + 3, PBF_VERSION_PATCH + 9);
    TestWorld minor(d);
    minor.require_usable(0);
    other.require_usable(n);
}

// =============================================================================================
TEST_CASE("desc_init: wrong struct_size and NULL are refused", "[api][struct_size]") {
    for (int delta : {-4, 4}) {
        INFO("struct_size delta " << delta);
        {
            pbf_world_desc d;
            std::memset(&d, 0xAB, sizeof d);
            CHECK_FAILS(pbf_world_desc_init(&d, uint32_t(sizeof d + delta), PBF_VERSION), PBF_ERROR_STRUCT_SIZE,
                        "struct_size");
            CHECK_FAILS(pbf_world_desc_init(&d, 0, PBF_VERSION), PBF_ERROR_STRUCT_SIZE, "struct_size");
        }
        {
            pbf_solver_params p;
            CHECK_FAILS(pbf_solver_params_init(&p, uint32_t(sizeof p + delta)), PBF_ERROR_STRUCT_SIZE, "struct_size");
            CHECK_FAILS(pbf_solver_params_init(&p, 0), PBF_ERROR_STRUCT_SIZE, "pbf_solver_params");
        }
        {
            pbf_block_desc b;
            CHECK_FAILS(pbf_block_desc_init(&b, uint32_t(sizeof b + delta)), PBF_ERROR_STRUCT_SIZE, "struct_size");
            CHECK_FAILS(pbf_block_desc_init(&b, 0), PBF_ERROR_STRUCT_SIZE, "pbf_block_desc");
        }
        {
            pbf_emitter_desc e;
            CHECK_FAILS(pbf_emitter_desc_init(&e, uint32_t(sizeof e + delta)), PBF_ERROR_STRUCT_SIZE, "struct_size");
            CHECK_FAILS(pbf_emitter_desc_init(&e, 0), PBF_ERROR_STRUCT_SIZE, "pbf_emitter_desc");
        }
        {
            pbf_collider_desc c;
            CHECK_FAILS(pbf_collider_desc_init(&c, uint32_t(sizeof c + delta)), PBF_ERROR_STRUCT_SIZE, "struct_size");
            CHECK_FAILS(pbf_collider_desc_init(&c, 0), PBF_ERROR_STRUCT_SIZE, "pbf_collider_desc");
        }
    }
    CHECK_FAILS(pbf_world_desc_init(nullptr, sizeof(pbf_world_desc), PBF_VERSION), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK_FAILS(pbf_solver_params_init(nullptr, sizeof(pbf_solver_params)), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK_FAILS(pbf_block_desc_init(nullptr, sizeof(pbf_block_desc)), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK_FAILS(pbf_emitter_desc_init(nullptr, sizeof(pbf_emitter_desc)), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK_FAILS(pbf_collider_desc_init(nullptr, sizeof(pbf_collider_desc)), PBF_ERROR_INVALID_ARGUMENT, "NULL");

    // A refused init leaves the struct alone.
    pbf_block_desc b;
    std::memset(&b, 0x5A, sizeof b);
    pbf_block_desc before = b;
    CHECK(pbf_block_desc_init(&b, sizeof b + 4) == PBF_ERROR_STRUCT_SIZE);
    CHECK(std::memcmp(&b, &before, sizeof b) == 0);

    // And the right size gives the documented defaults.
    const pbf_world_desc d = pbf_world_desc_default();
    CHECK(d.struct_size == sizeof d);
    CHECK(d.header_version == PBF_VERSION);
    CHECK(d.backend == PBF_BACKEND_AUTO);
    CHECK(d.max_particles == 65536u);
    CHECK(d.particle_radius == Approx(0.025f));
    CHECK(d.rest_density == Approx(1000.0f));
    CHECK(d.gravity[1] == Approx(-9.81f));
    CHECK(d.solver.struct_size == sizeof(pbf_solver_params));
    CHECK(d.solver.iterations == 4u);
    CHECK(d.solver.substeps == 1u);
    CHECK(d.solver.max_speed == Approx(100.0f));
    const pbf_emitter_desc e = pbf_emitter_desc_default();
    CHECK(e.enabled == 1u);
    CHECK(e.direction[1] == -1.0f);
    const pbf_collider_desc c = pbf_collider_desc_default();
    CHECK(c.motion == PBF_MOTION_STATIC);
    CHECK(c.rotation[3] == 1.0f);
}

TEST_CASE("struct_size: every desc and out struct with a wrong size is refused", "[api][struct_size]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    REQUIRE(n > 0);
    const pbf_solver_params params_before = w.params();
    const std::vector<float> pos_before = w.positions();

    // 0, sizeof - 4 and sizeof + 4 for every struct.
    for (int variant = 0; variant < 3; ++variant) {
        auto size_of = [&](size_t s) { return variant == 0 ? 0u : uint32_t(variant == 1 ? s - 4 : s + 4); };
        INFO("struct_size " << (variant == 0 ? "0" : variant == 1 ? "sizeof - 4" : "sizeof + 4"));

        {  // world desc
            pbf_world_desc d = small_desc();
            d.struct_size = size_of(sizeof d);
            pbf_world_id id{5, 5};
            CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_STRUCT_SIZE, "pbf_world_desc.struct_size");
            CHECK(id.generation == 0);
        }
        {  // the solver params nested in a world desc
            pbf_world_desc d = small_desc();
            d.solver.struct_size = size_of(sizeof d.solver);
            pbf_world_id id{5, 5};
            CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_STRUCT_SIZE, "pbf_solver_params.struct_size");
            CHECK(id.generation == 0);
        }
        {  // solver params in and out
            pbf_solver_params p = w.params();
            p.struct_size = size_of(sizeof p);
            CHECK_FAILS(pbf_world_set_solver_params(w, &p), PBF_ERROR_STRUCT_SIZE, "pbf_solver_params.struct_size");
            pbf_solver_params out;
            std::memset(&out, 0, sizeof out);
            out.struct_size = size_of(sizeof out);
            CHECK_FAILS(pbf_world_get_solver_params(w, &out), PBF_ERROR_STRUCT_SIZE, "pbf_solver_params.struct_size");
            CHECK(out.iterations == 0u);  // not written
        }
        {  // block desc
            pbf_block_desc b = block(0.2f, 0.5f, 0.2f, 0.3f, 0.6f, 0.3f);
            b.struct_size = size_of(sizeof b);
            uint32_t emitted = 99;
            CHECK_FAILS(pbf_world_emit_block(w, &b, &emitted), PBF_ERROR_STRUCT_SIZE, "pbf_block_desc.struct_size");
            CHECK(emitted == 0u);
        }
        {  // emitter desc, both types
            for (pbf_emitter_desc e : {nozzle_desc(), drain_desc()}) {
                e.struct_size = size_of(sizeof e);
                pbf_emitter_id id{5, 5};
                CHECK_FAILS(pbf_world_create_emitter(w, &e, &id), PBF_ERROR_STRUCT_SIZE, "pbf_emitter_desc.struct_size");
                CHECK(id.generation == 0);
            }
        }
        {  // collider desc
            pbf_collider_desc c = collider_desc(PBF_SHAPE_SPHERE);
            c.struct_size = size_of(sizeof c);
            pbf_collider_id id{5, 5};
            CHECK_FAILS(pbf_world_create_collider(w, &c, &id), PBF_ERROR_STRUCT_SIZE, "pbf_collider_desc.struct_size");
            CHECK(id.generation == 0);
        }
        {  // world info
            pbf_world_info info;
            std::memset(&info, 0, sizeof info);
            info.struct_size = size_of(sizeof info);
            CHECK_FAILS(pbf_world_get_info(w, &info), PBF_ERROR_STRUCT_SIZE, "pbf_world_info.struct_size");
            CHECK(info.max_particles == 0u);
        }
        {  // step stats
            pbf_step_stats s;
            std::memset(&s, 0, sizeof s);
            s.struct_size = size_of(sizeof s);
            CHECK_FAILS(pbf_world_get_stats(w, &s), PBF_ERROR_STRUCT_SIZE, "pbf_step_stats.struct_size");
            CHECK(s.particle_count == 0u);
        }
        {  // mapped buffer
            pbf_mapped_buffer m;
            std::memset(&m, 0, sizeof m);
            m.struct_size = size_of(sizeof m);
            CHECK_FAILS(pbf_world_map_positions(w, &m), PBF_ERROR_STRUCT_SIZE, "pbf_mapped_buffer.struct_size");
            CHECK(m.data == nullptr);
            // Nothing got mapped by the refused call.
            CHECK_FAILS(pbf_world_unmap(w), PBF_ERROR_INVALID_STATE, "mapped");
        }
    }
    CHECK(same_params(w.params(), params_before));
    CHECK(same_bits(w.positions(), pos_before));
    w.require_usable(n);
}

// =============================================================================================
TEST_CASE("NULL desc and out pointers are refused by every create, get and copy call", "[api][null]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    const std::vector<float> pos_before = w.positions();

    pbf_world_desc d = small_desc();
    pbf_world_id wid{3, 3};
    CHECK_FAILS(pbf_world_create(nullptr, &wid), PBF_ERROR_INVALID_ARGUMENT, "pbf_world_desc");
    CHECK(wid.generation == 0);
    CHECK_FAILS(pbf_world_create(&d, nullptr), PBF_ERROR_INVALID_ARGUMENT, "out_world");
    CHECK_FAILS(pbf_world_create(nullptr, nullptr), PBF_ERROR_INVALID_ARGUMENT, "NULL");

    CHECK_FAILS(pbf_world_get_solver_params(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "pbf_solver_params");
    CHECK_FAILS(pbf_world_set_solver_params(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "pbf_solver_params");
    CHECK_FAILS(pbf_world_set_gravity(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "gravity");
    CHECK_FAILS(pbf_world_get_info(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "pbf_world_info");
    CHECK_FAILS(pbf_world_get_stats(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "pbf_step_stats");
    CHECK_FAILS(pbf_world_emit_block(w, nullptr, nullptr), PBF_ERROR_INVALID_ARGUMENT, "pbf_block_desc");
    uint32_t emitted = 5;
    CHECK_FAILS(pbf_world_emit_block(w, nullptr, &emitted), PBF_ERROR_INVALID_ARGUMENT, "pbf_block_desc");
    CHECK(emitted == 0u);

    pbf_emitter_desc ed = nozzle_desc();
    pbf_emitter_id eid{3, 3};
    CHECK_FAILS(pbf_world_create_emitter(w, nullptr, &eid), PBF_ERROR_INVALID_ARGUMENT, "pbf_emitter_desc");
    CHECK(eid.generation == 0);
    CHECK_FAILS(pbf_world_create_emitter(w, &ed, nullptr), PBF_ERROR_INVALID_ARGUMENT, "out_emitter");

    pbf_collider_desc cd = collider_desc(PBF_SHAPE_SPHERE);
    pbf_collider_id cid{3, 3};
    CHECK_FAILS(pbf_world_create_collider(w, nullptr, &cid), PBF_ERROR_INVALID_ARGUMENT, "pbf_collider_desc");
    CHECK(cid.generation == 0);
    CHECK_FAILS(pbf_world_create_collider(w, &cd, nullptr), PBF_ERROR_INVALID_ARGUMENT, "out_collider");

    CHECK_FAILS(pbf_world_get_particle_count(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "out_count");
    uint32_t written = 77;
    CHECK_FAILS(pbf_world_copy_positions(w, nullptr, 4, &written), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK(written == 0u);
    written = 77;
    CHECK_FAILS(pbf_world_copy_velocities(w, nullptr, 4, &written), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK(written == 0u);
    written = 77;
    CHECK_FAILS(pbf_world_copy_ids(w, nullptr, 4, &written), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK(written == 0u);
    CHECK_FAILS(pbf_world_map_positions(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "pbf_mapped_buffer");

    // Emitter and collider setters with NULL vectors.
    pbf_emitter_id e{};
    const pbf_emitter_desc drain = drain_desc();
    REQUIRE_OK(pbf_world_create_emitter(w, &drain, &e));
    const float a[3] = {0.3f, 0.0f, 0.3f}, b[3] = {0.5f, 0.1f, 0.5f};
    CHECK_FAILS(pbf_emitter_set_transform(w, e, nullptr, b), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK_FAILS(pbf_emitter_set_transform(w, e, a, nullptr), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    REQUIRE_OK(pbf_world_destroy_emitter(w, e));
    pbf_collider_id c{};
    pbf_collider_desc kin = collider_desc(PBF_SHAPE_SPHERE, PBF_MOTION_KINEMATIC);
    REQUIRE_OK(pbf_world_create_collider(w, &kin, &c));
    const float p[3] = {0, 0.5f, 0}, q[4] = {0, 0, 0, 1};
    CHECK_FAILS(pbf_collider_set_pose(w, c, nullptr, q), PBF_ERROR_INVALID_ARGUMENT, "position");
    CHECK_FAILS(pbf_collider_set_pose(w, c, p, nullptr), PBF_ERROR_INVALID_ARGUMENT, "rotation");
    REQUIRE_OK(pbf_world_destroy_collider(w, c));

    // NULL with max_count 0 is fine (nothing to write), and NULL out_written is allowed.
    written = 77;
    REQUIRE_OK(pbf_world_copy_positions(w, nullptr, 0, &written));
    CHECK(written == 0u);
    std::vector<float> buf(size_t(n) * 4);
    REQUIRE_OK(pbf_world_copy_positions(w, buf.data(), n, nullptr));
    CHECK(same_bits(buf, pos_before));
    const pbf_block_desc more = block(0.3f, 0.5f, 0.3f, 0.46f, 0.66f, 0.46f);  // 3^3 lattice points
    REQUIRE_OK(pbf_world_emit_block(w, &more, nullptr));
    CHECK(w.count() == n + 27);
    w.require_usable(n + 27);
}

// =============================================================================================
TEST_CASE("world desc: NaN, Inf and out-of-range fields are refused", "[api][nan][world]") {
    TestWorld survivor;
    const uint32_t n = survivor.emit_default_block();

    auto refuse = [&](const pbf_world_desc& d, const char* needle) {
        pbf_world_id id{9, 9};
        CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_INVALID_ARGUMENT, needle);
        CHECK(id.index == 0);
        CHECK(id.generation == 0);
    };

    for (float bad : kBad) {
        INFO("value " << bad_name(bad));
        {
            pbf_world_desc d = small_desc();
            d.particle_radius = bad;
            refuse(d, "particle_radius");
        }
        {
            pbf_world_desc d = small_desc();
            d.rest_density = bad;
            refuse(d, "rest_density");
        }
        for (int a = 0; a < 3; ++a) {
            INFO("axis " << a);
            pbf_world_desc d = small_desc();
            d.gravity[a] = bad;
            refuse(d, "gravity");
            d = small_desc();
            d.domain_min[a] = bad;
            refuse(d, "domain");
            d = small_desc();
            d.domain_max[a] = bad;
            refuse(d, "domain");
        }
        // Every float solver parameter.
        const std::pair<float pbf_solver_params::*, const char*> fields[] = {
            {&pbf_solver_params::relaxation, "relaxation"},
            {&pbf_solver_params::scorr_k, "scorr_k"},
            {&pbf_solver_params::scorr_n, "scorr_n"},
            {&pbf_solver_params::scorr_dq, "scorr_dq"},
            {&pbf_solver_params::xsph_c, "xsph_c"},
            {&pbf_solver_params::vorticity_epsilon, "vorticity_epsilon"},
            {&pbf_solver_params::ldc_gain, "ldc_gain"},
            {&pbf_solver_params::max_speed, "max_speed"},
        };
        for (const auto& f : fields) {
            INFO("solver." << f.second);
            pbf_world_desc d = small_desc();
            d.solver.*f.first = bad;
            refuse(d, f.second);
        }
    }

    // Out-of-range values.
    struct Case {
        const char* what;
        void (*edit)(pbf_world_desc&);
        const char* needle;
    };
    const Case cases[] = {
        {"iterations 0", [](pbf_world_desc& d) { d.solver.iterations = 0; }, "iterations"},
        {"iterations 65", [](pbf_world_desc& d) { d.solver.iterations = 65; }, "iterations"},
        {"substeps 0", [](pbf_world_desc& d) { d.solver.substeps = 0; }, "substeps"},
        {"substeps 17", [](pbf_world_desc& d) { d.solver.substeps = 17; }, "substeps"},
        {"ldc_enabled 2", [](pbf_world_desc& d) { d.solver.ldc_enabled = 2; }, "ldc_enabled"},
        {"relaxation 0", [](pbf_world_desc& d) { d.solver.relaxation = 0; }, "relaxation"},
        {"max_speed 0", [](pbf_world_desc& d) { d.solver.max_speed = 0; }, "max_speed"},
        {"scorr_n 9", [](pbf_world_desc& d) { d.solver.scorr_n = 9; }, "scorr_n"},
        {"scorr_dq 1", [](pbf_world_desc& d) { d.solver.scorr_dq = 1; }, "scorr_dq"},
        {"xsph_c -0.1", [](pbf_world_desc& d) { d.solver.xsph_c = -0.1f; }, "xsph_c"},
        {"ldc_gain 2", [](pbf_world_desc& d) { d.solver.ldc_gain = 2; }, "ldc_gain"},
        {"max_particles 0", [](pbf_world_desc& d) { d.max_particles = 0; }, "max_particles"},
        {"max_particles 2^30+1", [](pbf_world_desc& d) { d.max_particles = (1u << 30) + 1; }, "max_particles"},
        {"backend 7", [](pbf_world_desc& d) { d.backend = static_cast<pbf_backend>(7); }, "backend"},
        {"backend -1", [](pbf_world_desc& d) { const int32_t v = -1; std::memcpy(&d.backend, &v, sizeof v); }, "backend"},
        {"cuda_device -1", [](pbf_world_desc& d) { d.cuda_device = -1; }, "cuda_device"},
        {"particle_radius 0", [](pbf_world_desc& d) { d.particle_radius = 0; }, "particle_radius"},
        {"particle_radius -1", [](pbf_world_desc& d) { d.particle_radius = -1; }, "particle_radius"},
        {"rest_density 0", [](pbf_world_desc& d) { d.rest_density = 0; }, "rest_density"},
        {"inverted domain", [](pbf_world_desc& d) { std::swap(d.domain_min[1], d.domain_max[1]); }, "domain"},
        {"flat domain", [](pbf_world_desc& d) { d.domain_max[2] = d.domain_min[2] + 0.01f; }, "domain"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        pbf_world_desc d = small_desc();
        c.edit(d);
        refuse(d, c.needle);
    }
    survivor.require_usable(n);
}

TEST_CASE("block desc: NaN and Inf in every float field are refused", "[api][nan][emit]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    const std::vector<float> before = w.positions();
    for (float bad : kBad) {
        for (int a = 0; a < 3; ++a) {
            INFO(bad_name(bad) << " on axis " << a);
            for (int field = 0; field < 3; ++field) {
                pbf_block_desc b = block(0.2f, 0.5f, 0.2f, 0.4f, 0.7f, 0.4f);
                float* v = field == 0 ? b.box_min : field == 1 ? b.box_max : b.velocity;
                v[a] = bad;
                uint32_t emitted = 123;
                CHECK_FAILS(pbf_world_emit_block(w, &b, &emitted), PBF_ERROR_INVALID_ARGUMENT,
                            field == 2 ? "velocity" : "box_m");
                CHECK(emitted == 0u);
            }
        }
    }
    // An empty or inverted box.
    for (int a = 0; a < 3; ++a) {
        pbf_block_desc b = block(0.2f, 0.5f, 0.2f, 0.4f, 0.7f, 0.4f);
        b.box_max[a] = b.box_min[a];
        CHECK_FAILS(pbf_world_emit_block(w, &b, nullptr), PBF_ERROR_INVALID_ARGUMENT, "box_max");
    }
    CHECK(same_bits(w.positions(), before));
    w.require_usable(n);
}

TEST_CASE("emitter desc: NaN, Inf and out-of-range fields are refused", "[api][nan][emitter]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();

    auto refuse = [&](const pbf_emitter_desc& e, const char* needle) {
        pbf_emitter_id id{9, 9};
        CHECK_FAILS(pbf_world_create_emitter(w, &e, &id), PBF_ERROR_INVALID_ARGUMENT, needle);
        CHECK(id.index == 0);
        CHECK(id.generation == 0);
        if (id.generation != 0) pbf_world_destroy_emitter(w, id);  // accepted by mistake: keep the world clean
    };

    for (float bad : kBad) {
        INFO("value " << bad_name(bad));
        for (pbf_emitter_type type : {PBF_EMITTER_NOZZLE, PBF_EMITTER_DRAIN}) {
            INFO((type == PBF_EMITTER_NOZZLE ? "nozzle" : "drain"));
            const pbf_emitter_desc base = type == PBF_EMITTER_NOZZLE ? nozzle_desc() : drain_desc();
            for (int a = 0; a < 3; ++a) {
                INFO("axis " << a);
                pbf_emitter_desc e = base;
                e.position[a] = bad;
                refuse(e, "position");
                e = base;
                e.direction[a] = bad;
                refuse(e, "direction");
                e = base;
                e.box_min[a] = bad;
                refuse(e, "box");
                e = base;
                e.box_max[a] = bad;
                refuse(e, "box");
            }
            pbf_emitter_desc e = base;
            e.speed = bad;
            refuse(e, "speed");
            e = base;
            e.radius = bad;
            refuse(e, "radius");
            e = base;
            e.particles_per_second = bad;
            refuse(e, "particles_per_second");
        }
    }

    // Out-of-range fields: test_validate.cpp compares the check that refuses each.
    refuse([] { pbf_emitter_desc e = nozzle_desc(); e.speed = 0; return e; }(), "speed");

    // set_enabled and set_transform validate too.
    pbf_emitter_id nz{}, dr{};
    pbf_emitter_desc nd = nozzle_desc();
    nd.enabled = 0;
    REQUIRE_OK(pbf_world_create_emitter(w, &nd, &nz));
    const pbf_emitter_desc drain = drain_desc();
    REQUIRE_OK(pbf_world_create_emitter(w, &drain, &dr));
    REQUIRE_OK(pbf_emitter_set_enabled(w, dr, 0));
    CHECK_FAILS(pbf_emitter_set_enabled(w, nz, 2), PBF_ERROR_INVALID_ARGUMENT, "enabled");
    CHECK_FAILS(pbf_emitter_set_enabled(w, nz, 0xFFFFFFFFu), PBF_ERROR_INVALID_ARGUMENT, "enabled");
    for (float bad : kBad) {
        for (int a = 0; a < 3; ++a) {
            float p[3] = {0, 0.7f, 0}, d[3] = {0, -1, 0};
            p[a] = bad;
            CHECK_FAILS(pbf_emitter_set_transform(w, nz, p, d), PBF_ERROR_INVALID_ARGUMENT, "finite");
            p[a] = 0.1f;
            d[a] = bad;
            CHECK_FAILS(pbf_emitter_set_transform(w, nz, p, d), PBF_ERROR_INVALID_ARGUMENT, "finite");
        }
    }
    const float zero[3] = {0, 0, 0}, pos[3] = {0, 0.7f, 0};
    CHECK_FAILS(pbf_emitter_set_transform(w, nz, pos, zero), PBF_ERROR_INVALID_ARGUMENT, "direction");
    const float lo[3] = {0.4f, 0, 0.4f}, hi[3] = {0.5f, 0.1f, 0.39f};
    CHECK_FAILS(pbf_emitter_set_transform(w, dr, lo, hi), PBF_ERROR_INVALID_ARGUMENT, "box_max");
    // The nozzle is disabled and the drain too: nothing changes the count.
    w.require_usable(n);
}

TEST_CASE("collider desc and set_pose: NaN, Inf and out-of-range fields are refused", "[api][nan][collider]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();

    auto refuse = [&](const pbf_collider_desc& c, const char* needle) {
        pbf_collider_id id{9, 9};
        CHECK_FAILS(pbf_world_create_collider(w, &c, &id), PBF_ERROR_INVALID_ARGUMENT, needle);
        CHECK(id.index == 0);
        CHECK(id.generation == 0);
        if (id.generation != 0) pbf_world_destroy_collider(w, id);  // accepted by mistake: keep the table free
    };

    for (float bad : kBad) {
        INFO("value " << bad_name(bad));
        for (pbf_collider_shape shape : {PBF_SHAPE_PLANE, PBF_SHAPE_SPHERE, PBF_SHAPE_CAPSULE, PBF_SHAPE_BOX}) {
            INFO("shape " << int(shape));
            const pbf_collider_desc base = collider_desc(shape, PBF_MOTION_KINEMATIC);
            for (int a = 0; a < 3; ++a) {
                INFO("axis " << a);
                pbf_collider_desc c = base;
                c.position[a] = bad;
                refuse(c, "position");
                c = base;
                c.half_extents[a] = bad;
                refuse(c, "half_extents");
            }
            for (int a = 0; a < 4; ++a) {
                pbf_collider_desc c = base;
                c.rotation[a] = bad;
                refuse(c, "rotation");
            }
            pbf_collider_desc c = base;
            c.radius = bad;
            refuse(c, "radius");
            c = base;
            c.half_height = bad;
            refuse(c, "half_height");
            c = base;
            c.friction = bad;
            refuse(c, "friction");
        }
    }

    struct Case {
        const char* what;
        pbf_collider_desc (*make)();
        const char* needle;
    };
    const Case cases[] = {
        {"shape 0", [] { return collider_desc(static_cast<pbf_collider_shape>(0)); }, "shape"},
        {"shape 99", [] { return collider_desc(static_cast<pbf_collider_shape>(99)); }, "shape"},
        {"unset shape", [] { return pbf_collider_desc_default(); }, "shape"},
        {"motion 5", [] { return collider_desc(PBF_SHAPE_SPHERE, static_cast<pbf_collider_motion>(5)); }, "motion"},
        {"zero quaternion", [] { pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX); c.rotation[3] = 0; return c; }, "rotation"},
        {"friction 1.5", [] { pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX); c.friction = 1.5f; return c; }, "friction"},
        {"friction -0.5", [] { pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX); c.friction = -0.5f; return c; }, "friction"},
        {"sphere radius 0", [] { pbf_collider_desc c = collider_desc(PBF_SHAPE_SPHERE); c.radius = 0; return c; }, "radius"},
        {"capsule half_height -1", [] { pbf_collider_desc c = collider_desc(PBF_SHAPE_CAPSULE); c.half_height = -1; return c; }, "half_height"},
        {"box half_extents 0", [] { pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX); c.half_extents[1] = 0; return c; }, "half_extents"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        refuse(c.make(), c.needle);
    }

    // set_pose: NaN and Inf in the position, the quaternion, and a zero quaternion.
    pbf_collider_id kin{};
    const pbf_collider_desc kin_desc = collider_desc(PBF_SHAPE_SPHERE, PBF_MOTION_KINEMATIC);
    REQUIRE_OK(pbf_world_create_collider(w, &kin_desc, &kin));
    for (float bad : kBad) {
        INFO("value " << bad_name(bad));
        for (int a = 0; a < 3; ++a) {
            float p[3] = {0, 0.6f, 0};
            const float q[4] = {0, 0, 0, 1};
            p[a] = bad;
            CHECK_FAILS(pbf_collider_set_pose(w, kin, p, q), PBF_ERROR_INVALID_ARGUMENT, "position");
        }
        for (int a = 0; a < 4; ++a) {
            const float p[3] = {0, 0.6f, 0};
            float q[4] = {0, 0, 0, 1};
            q[a] = bad;
            CHECK_FAILS(pbf_collider_set_pose(w, kin, p, q), PBF_ERROR_INVALID_ARGUMENT, "rotation");
        }
    }
    const float p[3] = {0, 0.6f, 0}, q0[4] = {0, 0, 0, 0};
    CHECK_FAILS(pbf_collider_set_pose(w, kin, p, q0), PBF_ERROR_INVALID_ARGUMENT, "rotation");
    // A valid pose (unnormalised quaternion is normalised) still works.
    const float q2[4] = {0, 0, 0, 2};
    REQUIRE_OK(pbf_collider_set_pose(w, kin, p, q2));
    w.require_usable(n);
}

TEST_CASE("set_gravity, set_solver_params and step: NaN, Inf and bad dt are refused", "[api][nan][step]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    const std::vector<float> before = w.positions();
    const pbf_solver_params params_before = w.params();

    for (float bad : kBad) {
        for (int a = 0; a < 3; ++a) {
            INFO(bad_name(bad) << " on axis " << a);
            float g[3] = {0, -9.81f, 0};
            g[a] = bad;
            CHECK_FAILS(pbf_world_set_gravity(w, g), PBF_ERROR_INVALID_ARGUMENT, "gravity");
        }
        const std::pair<float pbf_solver_params::*, const char*> fields[] = {
            {&pbf_solver_params::relaxation, "relaxation"},
            {&pbf_solver_params::scorr_k, "scorr_k"},
            {&pbf_solver_params::scorr_n, "scorr_n"},
            {&pbf_solver_params::scorr_dq, "scorr_dq"},
            {&pbf_solver_params::xsph_c, "xsph_c"},
            {&pbf_solver_params::vorticity_epsilon, "vorticity_epsilon"},
            {&pbf_solver_params::ldc_gain, "ldc_gain"},
            {&pbf_solver_params::max_speed, "max_speed"},
        };
        for (const auto& f : fields) {
            INFO(bad_name(bad) << " in solver." << f.second);
            pbf_solver_params p = params_before;
            p.*f.first = bad;
            CHECK_FAILS(pbf_world_set_solver_params(w, &p), PBF_ERROR_INVALID_ARGUMENT, f.second);
        }
    }
    for (uint32_t it : {0u, 65u}) {
        pbf_solver_params p = params_before;
        p.iterations = it;
        CHECK_FAILS(pbf_world_set_solver_params(w, &p), PBF_ERROR_INVALID_ARGUMENT, "iterations");
    }
    for (uint32_t sub : {0u, 17u}) {
        pbf_solver_params p = params_before;
        p.substeps = sub;
        CHECK_FAILS(pbf_world_set_solver_params(w, &p), PBF_ERROR_INVALID_ARGUMENT, "substeps");
    }
    {
        pbf_solver_params p = params_before;
        p.ldc_enabled = 2;
        CHECK_FAILS(pbf_world_set_solver_params(w, &p), PBF_ERROR_INVALID_ARGUMENT, "ldc_enabled");
    }

    const float bad_dts[] = {kNaN, kInf, -kInf, 0.0f, -0.0f, -kDt, -1.0f, 1.0001f, 2.0f, 1e30f};
    for (float dt : bad_dts) {
        INFO("dt " << dt);
        CHECK_FAILS(pbf_world_step(w, dt), PBF_ERROR_INVALID_ARGUMENT, "dt");
    }
    // Nothing moved, nothing was applied.
    CHECK(same_bits(w.positions(), before));
    CHECK(same_params(w.params(), params_before));
    pbf_step_stats s{};
    s.struct_size = sizeof s;
    REQUIRE_OK(pbf_world_get_stats(w, &s));
    CHECK(s.step_index == 0u);
    // The boundary dt = 1 is accepted.
    REQUIRE_OK(pbf_world_step(w, 1.0f));
    w.require_usable(n);
}

// =============================================================================================
TEST_CASE("stale handles: every world call after destroy is refused", "[api][handle]") {
    pbf_world_desc d = small_desc();
    pbf_world_id w{};
    REQUIRE_OK(pbf_world_create(&d, &w));
    CHECK(w.generation != 0);
    pbf_emitter_id e{};
    pbf_collider_id c{};
    const pbf_emitter_desc nd = nozzle_desc();
    REQUIRE_OK(pbf_world_create_emitter(w, &nd, &e));
    pbf_collider_desc kd = collider_desc(PBF_SHAPE_SPHERE, PBF_MOTION_KINEMATIC);
    REQUIRE_OK(pbf_world_create_collider(w, &kd, &c));
    REQUIRE_OK(pbf_world_destroy(w));

    TestWorld live;  // an unrelated live world must not answer for the dead one
    (void)live;

    auto all_calls_refused = [&](pbf_world_id id, const char* what) {
        INFO(what << " {" << id.index << ", " << id.generation << "}");
        const char* needle = "world";
        pbf_solver_params p = pbf_solver_params_default();
        pbf_world_info info{};
        info.struct_size = sizeof info;
        pbf_step_stats st{};
        st.struct_size = sizeof st;
        pbf_block_desc b = block(0, 0, 0, 0.1f, 0.1f, 0.1f);
        pbf_emitter_desc ed = nozzle_desc();
        pbf_collider_desc cd = collider_desc(PBF_SHAPE_SPHERE);
        pbf_emitter_id eo{};
        pbf_collider_id co{};
        uint32_t u = 7;
        float f4[4];
        uint32_t u1[1];
        pbf_mapped_buffer m{};
        m.struct_size = sizeof m;
        const float g[3] = {0, -1, 0}, q[4] = {0, 0, 0, 1};
        CHECK_FAILS(pbf_world_step(id, kDt), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_get_solver_params(id, &p), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_set_solver_params(id, &p), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_set_gravity(id, g), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_get_info(id, &info), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_get_stats(id, &st), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_emit_block(id, &b, &u), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK(u == 0u);
        CHECK_FAILS(pbf_world_create_emitter(id, &ed, &eo), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK(eo.generation == 0);
        CHECK_FAILS(pbf_world_destroy_emitter(id, e), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_emitter_set_enabled(id, e, 0), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_emitter_set_transform(id, e, g, g), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_create_collider(id, &cd, &co), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK(co.generation == 0);
        CHECK_FAILS(pbf_world_destroy_collider(id, c), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_collider_set_pose(id, c, g, q), PBF_ERROR_INVALID_HANDLE, needle);
        u = 7;
        CHECK_FAILS(pbf_world_get_particle_count(id, &u), PBF_ERROR_INVALID_HANDLE, needle);
        u = 7;
        CHECK_FAILS(pbf_world_copy_positions(id, f4, 1, &u), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK(u == 0u);
        CHECK_FAILS(pbf_world_copy_velocities(id, f4, 1, &u), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_copy_ids(id, u1, 1, &u), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_map_positions(id, &m), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_unmap(id), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_destroy(id), PBF_ERROR_INVALID_HANDLE, needle);
    };
    all_calls_refused(w, "destroyed world");
    all_calls_refused(pbf_world_id{0, 0}, "zeroed handle");
    all_calls_refused(pbf_world_id{12345, 7}, "forged handle");
    all_calls_refused(pbf_world_id{live.id.index, live.id.generation + 1}, "live index, wrong generation");
    all_calls_refused(pbf_world_id{live.id.index, 0}, "live index, generation 0");
    live.require_usable(0);
}

TEST_CASE("stale handles: a reused world slot refuses the old handle", "[api][handle]") {
    pbf_world_desc d = small_desc();
    pbf_world_id a{};
    REQUIRE_OK(pbf_world_create(&d, &a));
    REQUIRE_OK(pbf_world_destroy(a));
    CHECK_FAILS(pbf_world_destroy(a), PBF_ERROR_INVALID_HANDLE, "world");  // destroy twice

    TestWorld b(d);
    INFO("A {" << a.index << ", " << a.generation << "}, B {" << b.id.index << ", " << b.id.generation << "}");
    CHECK_FALSE((a.index == b.id.index && a.generation == b.id.generation));
    const uint32_t n = b.emit_default_block();
    uint32_t count = 0;
    CHECK_FAILS(pbf_world_get_particle_count(a, &count), PBF_ERROR_INVALID_HANDLE, "world");
    CHECK_FAILS(pbf_world_step(a, kDt), PBF_ERROR_INVALID_HANDLE, "world");
    pbf_block_desc blk = block(0.3f, 0.5f, 0.3f, 0.4f, 0.6f, 0.4f);
    CHECK_FAILS(pbf_world_emit_block(a, &blk, nullptr), PBF_ERROR_INVALID_HANDLE, "world");
    CHECK_FAILS(pbf_world_destroy(a), PBF_ERROR_INVALID_HANDLE, "world");
    b.require_usable(n);

    // Many create/destroy cycles: every old handle stays dead.
    std::vector<pbf_world_id> dead;
    for (int i = 0; i < 20; ++i) {
        pbf_world_id x{};
        REQUIRE_OK(pbf_world_create(&d, &x));
        for (const pbf_world_id& old : dead) REQUIRE_FALSE((old.index == x.index && old.generation == x.generation));
        REQUIRE_OK(pbf_world_destroy(x));
        dead.push_back(x);
    }
    for (const pbf_world_id& old : dead) CHECK(pbf_world_step(old, kDt) == PBF_ERROR_INVALID_HANDLE);
    b.require_usable(n);
}

TEST_CASE("stale handles: emitters", "[api][handle][emitter]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    const float lo[3] = {0.4f, 0, 0.4f}, hi[3] = {0.5f, 0.1f, 0.5f};

    pbf_emitter_desc dd = drain_desc();
    dd.enabled = 0;
    pbf_emitter_id e1{};
    REQUIRE_OK(pbf_world_create_emitter(w, &dd, &e1));
    CHECK(e1.generation != 0);
    REQUIRE_OK(pbf_world_destroy_emitter(w, e1));
    CHECK_FAILS(pbf_world_destroy_emitter(w, e1), PBF_ERROR_INVALID_HANDLE, "emitter");
    CHECK_FAILS(pbf_emitter_set_enabled(w, e1, 1), PBF_ERROR_INVALID_HANDLE, "emitter");
    CHECK_FAILS(pbf_emitter_set_transform(w, e1, lo, hi), PBF_ERROR_INVALID_HANDLE, "emitter");

    // The slot is reused by e2; e1 must still be refused and e2 must work.
    pbf_emitter_id e2{};
    REQUIRE_OK(pbf_world_create_emitter(w, &dd, &e2));
    CHECK_FALSE(same_id(e1, e2));
    CHECK_FAILS(pbf_emitter_set_enabled(w, e1, 1), PBF_ERROR_INVALID_HANDLE, "emitter");
    CHECK_FAILS(pbf_world_destroy_emitter(w, e1), PBF_ERROR_INVALID_HANDLE, "emitter");
    REQUIRE_OK(pbf_emitter_set_transform(w, e2, lo, hi));
    REQUIRE_OK(pbf_emitter_set_enabled(w, e2, 0));

    for (pbf_emitter_id forged : {pbf_emitter_id{0, 0}, pbf_emitter_id{12345, 7}, pbf_emitter_id{e2.index, 0},
                                  pbf_emitter_id{e2.index, e2.generation + 1}}) {
        INFO("emitter {" << forged.index << ", " << forged.generation << "}");
        CHECK_FAILS(pbf_emitter_set_enabled(w, forged, 0), PBF_ERROR_INVALID_HANDLE, "emitter");
        CHECK_FAILS(pbf_emitter_set_transform(w, forged, lo, hi), PBF_ERROR_INVALID_HANDLE, "emitter");
        CHECK_FAILS(pbf_world_destroy_emitter(w, forged), PBF_ERROR_INVALID_HANDLE, "emitter");
    }

    // An emitter handle of world A given to world B (which has no emitters) is refused.
    TestWorld other;
    CHECK_FAILS(pbf_emitter_set_enabled(other, e2, 1), PBF_ERROR_INVALID_HANDLE, "emitter");
    CHECK_FAILS(pbf_emitter_set_transform(other, e2, lo, hi), PBF_ERROR_INVALID_HANDLE, "emitter");
    CHECK_FAILS(pbf_world_destroy_emitter(other, e2), PBF_ERROR_INVALID_HANDLE, "emitter");
    REQUIRE_OK(pbf_world_destroy_emitter(w, e2));  // still alive in A
    w.require_usable(n);
    other.require_usable(0);
}

TEST_CASE("stale handles: colliders", "[api][handle][collider]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    const float p[3] = {0, 0.6f, 0}, q[4] = {0, 0, 0, 1};
    pbf_collider_desc kd = collider_desc(PBF_SHAPE_SPHERE, PBF_MOTION_KINEMATIC);
    kd.position[1] = 0.8f;

    pbf_collider_id c1{};
    REQUIRE_OK(pbf_world_create_collider(w, &kd, &c1));
    CHECK(c1.generation != 0);
    REQUIRE_OK(pbf_world_destroy_collider(w, c1));
    CHECK_FAILS(pbf_world_destroy_collider(w, c1), PBF_ERROR_INVALID_HANDLE, "collider");
    CHECK_FAILS(pbf_collider_set_pose(w, c1, p, q), PBF_ERROR_INVALID_HANDLE, "collider");

    pbf_collider_id c2{};
    REQUIRE_OK(pbf_world_create_collider(w, &kd, &c2));
    CHECK_FALSE((c1.index == c2.index && c1.generation == c2.generation));
    CHECK_FAILS(pbf_collider_set_pose(w, c1, p, q), PBF_ERROR_INVALID_HANDLE, "collider");
    CHECK_FAILS(pbf_world_destroy_collider(w, c1), PBF_ERROR_INVALID_HANDLE, "collider");
    REQUIRE_OK(pbf_collider_set_pose(w, c2, p, q));

    for (pbf_collider_id forged : {pbf_collider_id{0, 0}, pbf_collider_id{12345, 7}, pbf_collider_id{c2.index, 0},
                                   pbf_collider_id{c2.index, c2.generation + 1}}) {
        INFO("collider {" << forged.index << ", " << forged.generation << "}");
        CHECK_FAILS(pbf_collider_set_pose(w, forged, p, q), PBF_ERROR_INVALID_HANDLE, "collider");
        CHECK_FAILS(pbf_world_destroy_collider(w, forged), PBF_ERROR_INVALID_HANDLE, "collider");
    }

    TestWorld other;
    CHECK_FAILS(pbf_collider_set_pose(other, c2, p, q), PBF_ERROR_INVALID_HANDLE, "collider");
    CHECK_FAILS(pbf_world_destroy_collider(other, c2), PBF_ERROR_INVALID_HANDLE, "collider");
    REQUIRE_OK(pbf_world_destroy_collider(w, c2));
    w.require_usable(n);
    other.require_usable(0);
}

// Per-world slot tables use the same indices; generations from one process-wide counter keep
// world A's first emitter handle from matching world B's first emitter.
TEST_CASE("handles: an emitter handle of one world is refused by another world that has emitters",
          "[api][handle]") {
    TestWorld a, b;
    pbf_emitter_desc dd = drain_desc();
    dd.enabled = 0;
    pbf_emitter_id ea{}, eb{};
    REQUIRE_OK(pbf_world_create_emitter(a, &dd, &ea));
    REQUIRE_OK(pbf_world_create_emitter(b, &dd, &eb));
    INFO("A's emitter {" << ea.index << ", " << ea.generation << "}, B's {" << eb.index << ", " << eb.generation << "}");
    CHECK_FAILS(pbf_emitter_set_enabled(b, ea, 1), PBF_ERROR_INVALID_HANDLE, "emitter");
    pbf_collider_desc cd = collider_desc(PBF_SHAPE_SPHERE);
    pbf_collider_id ca{}, cb{};
    REQUIRE_OK(pbf_world_create_collider(a, &cd, &ca));
    REQUIRE_OK(pbf_world_create_collider(b, &cd, &cb));
    CHECK_FAILS(pbf_world_destroy_collider(b, ca), PBF_ERROR_INVALID_HANDLE, "collider");
}

// =============================================================================================
TEST_CASE("capacity: a block emits what fits, then PBF_ERROR_CAPACITY", "[api][capacity]") {
    TestWorld w(1000);
    // 10 x 10 x 20 = 2000 lattice points asked for; 1000 fit.
    pbf_block_desc b = block(-0.25f, 0.0f, -0.25f, 0.25f, 0.5f, 0.25f);
    b.box_max[1] = 1.0f;  // 20 layers in y
    uint32_t emitted = 0;
    REQUIRE_OK(pbf_world_emit_block(w, &b, &emitted));
    CHECK(emitted == 1000u);
    CHECK(w.count() == 1000u);

    // ids 0..999, each once.
    std::vector<uint32_t> ids = w.ids();
    std::sort(ids.begin(), ids.end());
    for (uint32_t k = 0; k < ids.size(); ++k) REQUIRE(ids[k] == k);

    const std::vector<float> before = w.positions();
    emitted = 55;
    pbf_block_desc small = block(0.3f, 0.5f, 0.3f, 0.4f, 0.6f, 0.4f);
    CHECK_FAILS(pbf_world_emit_block(w, &small, &emitted), PBF_ERROR_CAPACITY, "max_particles");
    CHECK(emitted == 0u);
    CHECK(w.count() == 1000u);
    CHECK(same_bits(w.positions(), before));

    pbf_step_stats s{};
    s.struct_size = sizeof s;
    REQUIRE_OK(pbf_world_get_stats(w, &s));
    CHECK(s.emitted_total == 1000u);
    w.require_usable(1000);
}

TEST_CASE("capacity: a partial block fills the world exactly", "[api][capacity]") {
    TestWorld w(1000);
    CHECK(w.emit(block(-0.2f, 0.0f, -0.2f, 0.2f, 0.4f, 0.2f)) == 512u);  // 8^3
    // 729 more asked for, 488 fit.
    uint32_t emitted = 0;
    pbf_block_desc b = block(-0.2f, 0.45f, -0.2f, 0.25f, 0.9f, 0.25f);
    REQUIRE_OK(pbf_world_emit_block(w, &b, &emitted));
    CHECK(emitted == 488u);
    CHECK(w.count() == 1000u);
    CHECK_FAILS(pbf_world_emit_block(w, &b, &emitted), PBF_ERROR_CAPACITY, "full");
    CHECK(emitted == 0u);
    w.require_usable(1000);
}

TEST_CASE("capacity: a nozzle in a full world emits nothing", "[api][capacity][emitter]") {
    TestWorld w(1000);
    pbf_block_desc b = block(-0.5f, 0.0f, -0.5f, 0.5f, 0.6f, 0.5f);
    REQUIRE(w.emit(b) == 1000u);
    pbf_emitter_desc nd = nozzle_desc();
    nd.position[1] = 0.9f;
    nd.particles_per_second = 6000.0f;  // 100 per step
    pbf_emitter_id e{};
    REQUIRE_OK(pbf_world_create_emitter(w, &nd, &e));
    for (int i = 0; i < 10; ++i) {
        REQUIRE_OK(pbf_world_step(w, kDt));
        REQUIRE(w.count() == 1000u);
    }
    std::vector<uint32_t> ids = w.ids();
    std::sort(ids.begin(), ids.end());
    CHECK(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
    CHECK(ids.back() == 999u);
    pbf_step_stats s{};
    s.struct_size = sizeof s;
    REQUIRE_OK(pbf_world_get_stats(w, &s));
    CHECK(s.emitted_total == 1000u);
    CHECK(s.particle_count == 1000u);

    // A nozzle in a nearly full world stops exactly at capacity.
    TestWorld v(1000);
    REQUIRE(v.emit(block(-0.5f, 0.0f, -0.5f, 0.5f, 0.15f, 0.25f)) == 20u * 3u * 15u);  // 900
    nd.particles_per_second = 4200.0f;  // ~70 a step: the second step's batch only partly fits
    REQUIRE_OK(pbf_world_create_emitter(v, &nd, &e));
    for (int i = 0; i < 12; ++i) {
        REQUIRE_OK(pbf_world_step(v, kDt));
        REQUIRE(v.count() <= 1000u);
    }
    CHECK(v.count() == 1000u);
    ids = v.ids();
    std::sort(ids.begin(), ids.end());
    CHECK(std::adjacent_find(ids.begin(), ids.end()) == ids.end());
    CHECK(ids.back() == 999u);
}

TEST_CASE("capacity: the collider table holds 32", "[api][capacity][collider]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    std::vector<pbf_collider_id> ids;
    for (int i = 0; i < 32; ++i) {
        pbf_collider_desc c = collider_desc(PBF_SHAPE_SPHERE);
        c.position[0] = -0.45f + 0.028f * i;
        c.position[1] = 0.9f;
        c.radius = 0.01f;
        pbf_collider_id id{};
        INFO("collider " << i);
        REQUIRE_OK(pbf_world_create_collider(w, &c, &id));
        ids.push_back(id);
    }
    pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX);
    pbf_collider_id extra{9, 9};
    CHECK_FAILS(pbf_world_create_collider(w, &c, &extra), PBF_ERROR_CAPACITY, "32");
    CHECK(extra.generation == 0);
    w.require_usable(n);
    // One freed slot makes room for exactly one more.
    REQUIRE_OK(pbf_world_destroy_collider(w, ids[7]));
    REQUIRE_OK(pbf_world_create_collider(w, &c, &extra));
    CHECK_FAILS(pbf_world_create_collider(w, &c, &extra), PBF_ERROR_CAPACITY, "colliders");
    w.require_usable(n);
}

// =============================================================================================
TEST_CASE("state: set_pose on a static collider and unmap without map", "[api][state]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    pbf_collider_desc sd = collider_desc(PBF_SHAPE_BOX);
    sd.position[1] = 0.8f;
    pbf_collider_id s{};
    REQUIRE_OK(pbf_world_create_collider(w, &sd, &s));
    const float p[3] = {0, 0.7f, 0}, q[4] = {0, 0, 0, 1};
    CHECK_FAILS(pbf_collider_set_pose(w, s, p, q), PBF_ERROR_INVALID_STATE, "kinematic");
    CHECK_FAILS(pbf_world_unmap(w), PBF_ERROR_INVALID_STATE, "mapped");
    w.require_usable(n);
}

TEST_CASE("map: host memory, stride 16, same data as copy_positions", "[api][map]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    for (int i = 0; i < 3; ++i) REQUIRE_OK(pbf_world_step(w, kDt));
    const std::vector<float> copy = w.positions();

    pbf_mapped_buffer m;
    std::memset(&m, 0xCD, sizeof m);
    m.struct_size = sizeof m;
    REQUIRE_OK(pbf_world_map_positions(w, &m));
    CHECK(m.struct_size == sizeof m);
    CHECK(m.memory == PBF_MEMORY_HOST);
    CHECK(m.stride_bytes == 16u);
    CHECK(m.count == n);
    REQUIRE(m.data != nullptr);
    std::vector<float> mapped(size_t(m.count) * 4);
    for (uint32_t k = 0; k < m.count; ++k)
        std::memcpy(&mapped[size_t(k) * 4], static_cast<const char*>(m.data) + size_t(k) * m.stride_bytes, 16);
    CHECK(same_bits(mapped, copy));
    REQUIRE_OK(pbf_world_unmap(w));
    CHECK_FAILS(pbf_world_unmap(w), PBF_ERROR_INVALID_STATE, "mapped");

    // An empty world maps with count 0.
    TestWorld empty;
    pbf_mapped_buffer m0{};
    m0.struct_size = sizeof m0;
    REQUIRE_OK(pbf_world_map_positions(empty, &m0));
    CHECK(m0.count == 0u);
    CHECK(m0.memory == PBF_MEMORY_HOST);
    REQUIRE_OK(pbf_world_unmap(empty));
    w.require_usable(n);
}

// =============================================================================================
TEST_CASE("backend: CUDA in a build or machine without it is BACKEND_UNAVAILABLE", "[api][backend]") {
    pbf_world_desc d = small_desc();
    d.backend = PBF_BACKEND_AUTO;
    TestWorld autow(d);
    pbf_world_info info{};
    info.struct_size = sizeof info;
    REQUIRE_OK(pbf_world_get_info(autow, &info));
    CHECK(info.backend != PBF_BACKEND_AUTO);
    if (info.backend != PBF_BACKEND_CPU) {
        WARN("AUTO chose CUDA: this libpbf can use CUDA, so BACKEND_UNAVAILABLE is not asserted");
        return;
    }
    d.backend = PBF_BACKEND_CUDA;
    pbf_world_id id{4, 4};
    CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_BACKEND_UNAVAILABLE, "CUDA");
    CHECK(id.generation == 0);
    autow.require_usable(0);

    // The CPU world reports itself sensibly.
    TestWorld cpu;
    REQUIRE_OK(pbf_world_get_info(cpu, &info));
    CHECK(info.backend == PBF_BACKEND_CPU);
    CHECK(info.max_particles == 4096u);
    CHECK(info.rest_spacing == Approx(0.05f));
    CHECK(info.kernel_radius == Approx(0.1f));
    CHECK(info.grid_cells == 1000u);
    CHECK(info.particle_mass > 0.0f);
    CHECK(info.device_bytes > 0u);
    CHECK_THAT(std::string(info.device_name), Catch::Contains("CPU"));
}

TEST_CASE("memory: a world larger than memory fails cleanly", "[api][memory]") {
    TestWorld survivor;
    const uint32_t n = survivor.emit_default_block();

    // 2^30 particles in a 2 km cube: refused for its grid or its memory, never a crash.
    pbf_world_desc d = small_desc(1u << 30);
    for (int a = 0; a < 3; ++a) {
        d.domain_min[a] = -1000.0f;
        d.domain_max[a] = 1000.0f;
    }
    pbf_world_id id{4, 4};
    pbf_result r = pbf_world_create(&d, &id);
    INFO(pbf_result_string(r) << " \"" << last_message() << "\"");
    CHECK((r == PBF_ERROR_OUT_OF_MEMORY || r == PBF_ERROR_INVALID_ARGUMENT));
    CHECK(id.generation == 0);
    CHECK_THAT(last_message(), Catch::Contains("grid") || Catch::Contains("allocat") || Catch::Contains("memory"));

    // 2^30 particles in a small domain: ~120 bytes a particle is far more than this machine has.
#ifdef PBF_TEST_HAVE_SYSCONF
    const double phys = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGE_SIZE));
#else
    const double phys = 0.0;  // unknown: skip the allocation that may succeed on a large machine
#endif
    if (phys > 0 && phys < 100e9) {
        d = small_desc(1u << 30);
        r = pbf_world_create(&d, &id);
        INFO(pbf_result_string(r) << " \"" << last_message() << "\"");
        CHECK(r == PBF_ERROR_OUT_OF_MEMORY);
        CHECK(id.generation == 0);
        CHECK_THAT(last_message(), Catch::Contains("1073741824"));
    } else {
        WARN("skipped the 2^30-particle allocation: " << phys / 1e9 << " GB of physical memory");
    }
    survivor.require_usable(n);
    TestWorld fresh;  // creation still works
    fresh.require_usable(0);
}

// =============================================================================================
namespace {
struct LogCapture {
    std::vector<std::pair<pbf_log_level, std::string>> entries;
    std::vector<void*> user_data;
};
void PBF_CALL capture_log(pbf_log_level level, const char* message, void* user_data) {
    LogCapture* cap = static_cast<LogCapture*>(user_data);
    cap->entries.emplace_back(level, message ? message : "(null)");
    cap->user_data.push_back(user_data);
}
}  // namespace

TEST_CASE("log callback: receives errors with the message and user_data, and can be removed", "[api][log]") {
    TestWorld w;
    LogCapture cap;
    pbf_set_log_callback(capture_log, &cap);

    CHECK(pbf_world_step(w, -1.0f) == PBF_ERROR_INVALID_ARGUMENT);
    const std::string message = last_message();
    pbf_set_log_callback(nullptr, nullptr);

    REQUIRE(cap.entries.size() == 1u);
    CHECK(cap.entries[0].first == PBF_LOG_ERROR);
    CHECK(cap.entries[0].second == message);
    CHECK_THAT(message, Catch::Contains("dt"));
    CHECK(cap.user_data[0] == &cap);

    // Removed: further errors are not delivered.
    CHECK(pbf_world_step(w, kNaN) == PBF_ERROR_INVALID_ARGUMENT);
    CHECK(pbf_world_step(pbf_world_id{0, 0}, kDt) == PBF_ERROR_INVALID_HANDLE);
    CHECK(cap.entries.size() == 1u);

    // Informational events arrive at a level below ERROR.
    LogCapture info;
    pbf_set_log_callback(capture_log, &info);
    {
        TestWorld x;
        (void)x;
    }
    pbf_set_log_callback(nullptr, nullptr);
    for (const auto& e : info.entries) CHECK(e.first != PBF_LOG_ERROR);
    w.require_usable(0);
}

TEST_CASE("error message is thread-local", "[api][thread]") {
    TestWorld w;
    CHECK(pbf_world_step(w, -5.0f) == PBF_ERROR_INVALID_ARGUMENT);
    const std::string mine = last_message();
    REQUIRE_THAT(mine, Catch::Contains("dt"));

    std::string other_before, other_after;
    pbf_result other_result = PBF_OK;
    std::thread t([&] {
        other_before = pbf_last_error_message();  // a fresh thread has no error
        uint32_t count = 0;
        other_result = pbf_world_get_particle_count(pbf_world_id{12345, 7}, &count);
        other_after = pbf_last_error_message();
    });
    t.join();
    CHECK(other_before.empty());
    CHECK(other_result == PBF_ERROR_INVALID_HANDLE);
    CHECK_THAT(other_after, Catch::Contains("12345"));
    CHECK(last_message() == mine);  // thread B's failure did not overwrite A's message

    // Two threads working on two worlds at once.
    TestWorld w2;
    w.emit_default_block();
    w2.emit_default_block();
    std::thread t1([&] {
        for (int i = 0; i < 5; ++i) pbf_world_step(w, kDt);
    });
    std::thread t2([&] {
        for (int i = 0; i < 5; ++i) pbf_world_step(w2, kDt);
    });
    t1.join();
    t2.join();
    CHECK(w.count() == w2.count());
}

// =============================================================================================
TEST_CASE("copy-out: max_count below count writes exactly max_count", "[api][copy]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    REQUIRE(n > 20);
    REQUIRE_OK(pbf_world_step(w, kDt));
    const std::vector<float> all = w.positions();
    const std::vector<uint32_t> all_ids = w.ids();
    const float guard = -12345.5f;
    const uint32_t guard_id = 0xDEADBEEFu;

    for (uint32_t max_count : {0u, 1u, 10u, n - 1}) {
        INFO("max_count " << max_count);
        std::vector<float> pos(size_t(n) * 4 + 8, guard), vel(size_t(n) * 4 + 8, guard);
        std::vector<uint32_t> ids(n + 2, guard_id);
        uint32_t written = 777;
        REQUIRE_OK(pbf_world_copy_positions(w, pos.data(), max_count, &written));
        CHECK(written == max_count);
        written = 777;
        REQUIRE_OK(pbf_world_copy_velocities(w, vel.data(), max_count, &written));
        CHECK(written == max_count);
        written = 777;
        REQUIRE_OK(pbf_world_copy_ids(w, ids.data(), max_count, &written));
        CHECK(written == max_count);
        for (size_t k = size_t(max_count) * 4; k < pos.size(); ++k) REQUIRE(pos[k] == guard);
        for (size_t k = size_t(max_count) * 4; k < vel.size(); ++k) REQUIRE(vel[k] == guard);
        for (size_t k = max_count; k < ids.size(); ++k) REQUIRE(ids[k] == guard_id);
        // The prefix is the same prefix the full copy gives.
        CHECK(std::memcmp(pos.data(), all.data(), size_t(max_count) * 16) == 0);
        CHECK(std::memcmp(ids.data(), all_ids.data(), size_t(max_count) * 4) == 0);
        for (uint32_t k = 0; k < max_count; ++k) CHECK(vel[size_t(k) * 4 + 3] == 0.0f);
    }
    // More room than particles: exactly count.
    std::vector<float> pos(size_t(n + 5) * 4, guard);
    uint32_t written = 0;
    REQUIRE_OK(pbf_world_copy_positions(w, pos.data(), n + 5, &written));
    CHECK(written == n);
    for (size_t k = size_t(n) * 4; k < pos.size(); ++k) REQUIRE(pos[k] == guard);
    w.require_usable(n);
}

TEST_CASE("ids: unique, stable across steps, particles move continuously", "[api][copy][ids]") {
    pbf_world_desc d = small_desc();
    d.solver.max_speed = 5.0f;
    TestWorld w(d);
    // A block that falls and splashes: particles reorder in storage every step.
    const uint32_t n = w.emit(block(-0.2f, 0.3f, -0.2f, 0.1f, 0.725f, 0.1f));
    REQUIRE(n == 6u * 8u * 6u);
    const float max_step = d.solver.max_speed * kDt;

    auto snapshot = [&](std::map<uint32_t, std::array<float, 3>>& out) {
        const std::vector<float> pos = w.positions();
        const std::vector<uint32_t> ids = w.ids();
        REQUIRE(ids.size() * 4 == pos.size());
        out.clear();
        for (size_t k = 0; k < ids.size(); ++k) {
            const bool inserted =
                out.emplace(ids[k], std::array<float, 3>{pos[k * 4], pos[k * 4 + 1], pos[k * 4 + 2]}).second;
            REQUIRE(inserted);  // unique
        }
    };
    std::map<uint32_t, std::array<float, 3>> prev, cur;
    snapshot(prev);
    std::set<uint32_t> id_set;
    for (const auto& kv : prev) id_set.insert(kv.first);
    CHECK(*id_set.begin() == 0u);
    CHECK(*id_set.rbegin() == n - 1);

    float worst = 0.0f;
    bool reordered = false;
    for (int step = 0; step < 20; ++step) {
        const std::vector<uint32_t> before_ids = w.ids();
        REQUIRE_OK(pbf_world_step(w, kDt));
        if (w.ids() != before_ids) reordered = true;
        snapshot(cur);
        REQUIRE(cur.size() == prev.size());
        for (const auto& kv : cur) {
            const auto it = prev.find(kv.first);
            REQUIRE(it != prev.end());  // same set of ids
            const float dx = kv.second[0] - it->second[0], dy = kv.second[1] - it->second[1],
                        dz = kv.second[2] - it->second[2];
            worst = std::max(worst, std::sqrt(dx * dx + dy * dy + dz * dz));
        }
        std::swap(prev, cur);
    }
    INFO("largest move in one step " << worst << " m, bound max_speed * dt = " << max_step << " m");
    CHECK(worst > 0.0f);
    CHECK(worst <= max_step * 1.001f);
    CHECK(reordered);
}

TEST_CASE("destroy racing with calls on another thread: they finish or get INVALID_HANDLE", "[api][thread][handle]") {
    for (int round = 0; round < 3; ++round) {
        pbf_world_desc d = small_desc();
        pbf_world_id id{};
        REQUIRE_OK(pbf_world_create(&d, &id));
        const pbf_block_desc b = block(-0.15f, 0.0f, -0.15f, 0.15f, 0.3f, 0.15f);
        REQUIRE_OK(pbf_world_emit_block(id, &b, nullptr));
        std::vector<pbf_result> results;
        std::thread worker([&] {
            for (;;) {
                uint32_t n = 0;
                const pbf_result r1 = pbf_world_step(id, kDt);
                const pbf_result r2 = pbf_world_get_particle_count(id, &n);
                results.push_back(r1);
                results.push_back(r2);
                if (r1 != PBF_OK || r2 != PBF_OK) break;
            }
        });
        std::this_thread::sleep_for(std::chrono::milliseconds(5 * round));
        REQUIRE_OK(pbf_world_destroy(id));
        worker.join();
        REQUIRE_FALSE(results.empty());
        for (pbf_result r : results) CHECK((r == PBF_OK || r == PBF_ERROR_INVALID_HANDLE));
        CHECK(results.back() == PBF_ERROR_INVALID_HANDLE);
    }
}

// =============================================================================================
TEST_CASE("robustness: particles emitted outside the domain or with extreme finite inputs stay finite",
          "[api][robust]") {
    pbf_world_desc d = small_desc();
    d.solver.max_speed = 20.0f;
    TestWorld w(d);
    // A block above the domain and one beside it, with an absurd but finite velocity.
    CHECK(w.emit(block(0.0f, 5.0f, 0.0f, 0.11f, 5.11f, 0.11f)) > 0u);
    pbf_block_desc fast = block(-3.0f, 0.2f, -0.1f, -2.89f, 0.31f, 0.01f);
    fast.velocity[0] = 1e30f;
    CHECK(w.emit(fast) > 0u);
    const float g[3] = {1e30f, -1e30f, 0.0f};
    REQUIRE_OK(pbf_world_set_gravity(w, g));
    for (int i = 0; i < 5; ++i) REQUIRE_OK(pbf_world_step(w, 1.0f));
    const uint32_t n = w.count();
    const std::vector<float> pos = w.positions();
    std::vector<float> vel(size_t(n) * 4);
    uint32_t written = 0;
    REQUIRE_OK(pbf_world_copy_velocities(w, vel.data(), n, &written));
    REQUIRE(written == n);
    const float slack = 1e-4f;
    for (uint32_t k = 0; k < n; ++k) {
        for (int a = 0; a < 3; ++a) {
            REQUIRE(std::isfinite(pos[size_t(k) * 4 + a]));
            REQUIRE(pos[size_t(k) * 4 + a] >= d.domain_min[a] - slack);
            REQUIRE(pos[size_t(k) * 4 + a] <= d.domain_max[a] + slack);
        }
        const float* v = &vel[size_t(k) * 4];
        REQUIRE(std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) <= d.solver.max_speed * 1.001f);
    }
    pbf_step_stats s{};
    s.struct_size = sizeof s;
    REQUIRE_OK(pbf_world_get_stats(w, &s));
    CHECK(std::isfinite(s.kinetic_energy));
    CHECK(std::isfinite(s.density_error_max));
}

// =============================================================================================
TEST_CASE("a failed call changes nothing", "[api][atomic]") {
    TestWorld w(1000);
    REQUIRE(w.emit(block(-0.5f, 0.0f, -0.5f, 0.5f, 0.6f, 0.5f)) == 1000u);
    for (int i = 0; i < 3; ++i) REQUIRE_OK(pbf_world_step(w, kDt));

    const std::vector<float> pos = w.positions();
    const std::vector<uint32_t> ids = w.ids();
    const pbf_solver_params params = w.params();
    pbf_step_stats s0{};
    s0.struct_size = sizeof s0;
    REQUIRE_OK(pbf_world_get_stats(w, &s0));

    pbf_block_desc b = block(0.3f, 0.5f, 0.3f, 0.4f, 0.6f, 0.4f);
    uint32_t emitted = 9;
    CHECK_FAILS(pbf_world_emit_block(w, &b, &emitted), PBF_ERROR_CAPACITY, "max_particles");
    b.box_min[0] = kNaN;
    CHECK_FAILS(pbf_world_emit_block(w, &b, &emitted), PBF_ERROR_INVALID_ARGUMENT, "box_min");
    CHECK_FAILS(pbf_world_step(w, 0.0f), PBF_ERROR_INVALID_ARGUMENT, "dt");
    CHECK_FAILS(pbf_world_step(w, kInf), PBF_ERROR_INVALID_ARGUMENT, "dt");
    pbf_solver_params bad = params;
    bad.iterations = 3;    // a valid change ...
    bad.max_speed = -1.0f; // ... in a refused struct must not be applied
    CHECK_FAILS(pbf_world_set_solver_params(w, &bad), PBF_ERROR_INVALID_ARGUMENT, "max_speed");
    const float g[3] = {0, kNaN, 0};
    CHECK_FAILS(pbf_world_set_gravity(w, g), PBF_ERROR_INVALID_ARGUMENT, "gravity");

    CHECK(w.count() == 1000u);
    CHECK(same_bits(w.positions(), pos));
    CHECK(w.ids() == ids);
    CHECK(same_params(w.params(), params));
    pbf_step_stats s1{};
    s1.struct_size = sizeof s1;
    REQUIRE_OK(pbf_world_get_stats(w, &s1));
    CHECK(s1.step_index == s0.step_index);
    CHECK(s1.emitted_total == s0.emitted_total);
    CHECK(s1.particle_count == s0.particle_count);
    CHECK(s1.kinetic_energy == s0.kinetic_energy);

    // The world's evolution is the same as a twin that never saw the failed calls.
    TestWorld twin(1000);
    REQUIRE(twin.emit(block(-0.5f, 0.0f, -0.5f, 0.5f, 0.6f, 0.5f)) == 1000u);
    for (int i = 0; i < 3; ++i) REQUIRE_OK(pbf_world_step(twin, kDt));
    REQUIRE(same_bits(twin.positions(), pos));
    for (int i = 0; i < 3; ++i) {
        REQUIRE_OK(pbf_world_step(w, kDt));
        REQUIRE_OK(pbf_world_step(twin, kDt));
    }
    CHECK(same_bits(w.positions(), twin.positions()));
}

// A refused emit adds no particle, so it must not end a mapping (the header lists the calls that
// do); World::emit_block clears the mapped flag before it knows whether anything fits.
TEST_CASE("a failed emit leaves a mapping in place", "[api][atomic][map]") {
    TestWorld w(1000);
    REQUIRE(w.emit(block(-0.5f, 0.0f, -0.5f, 0.5f, 0.6f, 0.5f)) == 1000u);
    pbf_mapped_buffer m{};
    m.struct_size = sizeof m;
    REQUIRE_OK(pbf_world_map_positions(w, &m));
    pbf_block_desc b = block(0.3f, 0.5f, 0.3f, 0.4f, 0.6f, 0.4f);
    CHECK_FAILS(pbf_world_emit_block(w, &b, nullptr), PBF_ERROR_CAPACITY, "max_particles");
    CHECK(pbf_world_unmap(w) == PBF_OK);
}
