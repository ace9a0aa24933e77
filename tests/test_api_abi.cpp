// Black-box tests of the C ABI (include/pbf_c_api.h) on the CPU backend. The C ABI's contract: versions, struct sizes and NULL pointers.
// Fixtures: support.h.
#include "support.h"

namespace {

// init(&desc, size) refuses sizeof + delta (naming struct_size) and 0 (naming the struct).
template <class Desc, class Init>
void check_init_size_refused(Init init, int delta, const char* name) {
    Desc d;
    CHECK_FAILS(init(&d, uint32_t(sizeof d + delta)), PBF_ERROR_STRUCT_SIZE, "struct_size");
    CHECK_FAILS(init(&d, 0), PBF_ERROR_STRUCT_SIZE, name);
}

// get(w, &out) refuses an out struct whose struct_size is `size` (the rest zero), naming `name`,
// and leaves its `field` unwritten.
template <class Out, class Field, class Get>
void check_out_size_refused(pbf_world_id w, Get get, uint32_t size, Field Out::*field, const char* name) {
    Out out;
    std::memset(&out, 0, sizeof out);
    out.struct_size = size;
    CHECK_FAILS(get(w, &out), PBF_ERROR_STRUCT_SIZE, name);
    CHECK(out.*field == Field{});
}

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
        check_init_size_refused<pbf_solver_params>(pbf_solver_params_init, delta, "pbf_solver_params");
        check_init_size_refused<pbf_block_desc>(pbf_block_desc_init, delta, "pbf_block_desc");
        check_init_size_refused<pbf_emitter_desc>(pbf_emitter_desc_init, delta, "pbf_emitter_desc");
        check_init_size_refused<pbf_collider_desc>(pbf_collider_desc_init, delta, "pbf_collider_desc");
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
    CHECK(d.solver.substeps == 0u);  // automatic
    CHECK(d.solver.max_substeps == 16u);
    CHECK(d.solver.substep_travel == Approx(0.5f));
    CHECK(d.solver.sound_speed == Approx(40.0f));
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
            check_out_size_refused(w, pbf_world_get_solver_params, size_of(sizeof(pbf_solver_params)),
                                   &pbf_solver_params::iterations, "pbf_solver_params.struct_size");
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
                CHECK_FAILS(pbf_world_create_emitter(w, &e, &id), PBF_ERROR_STRUCT_SIZE,
                            "pbf_emitter_desc.struct_size");
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
        // Out structs: refused, and not written.
        check_out_size_refused(w, pbf_world_get_info, size_of(sizeof(pbf_world_info)), &pbf_world_info::max_particles,
                               "pbf_world_info.struct_size");
        check_out_size_refused(w, pbf_world_get_stats, size_of(sizeof(pbf_step_stats)), &pbf_step_stats::particle_count,
                               "pbf_step_stats.struct_size");
        check_out_size_refused(w, pbf_world_map_positions, size_of(sizeof(pbf_mapped_buffer)), &pbf_mapped_buffer::data,
                               "pbf_mapped_buffer.struct_size");
        CHECK_FAILS(pbf_world_unmap(w), PBF_ERROR_INVALID_STATE, "mapped");  // nothing got mapped
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
    CHECK_FAILS(pbf_emitter_set_drain_box(w, e, nullptr, b), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    CHECK_FAILS(pbf_emitter_set_drain_box(w, e, a, nullptr), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    REQUIRE_OK(pbf_world_destroy_emitter(w, e));
    pbf_collider_id c{};
    pbf_collider_desc kin = collider_desc(PBF_SHAPE_SPHERE, PBF_MOTION_KINEMATIC);
    REQUIRE_OK(pbf_world_create_collider(w, &kin, &c));
    const float p[3] = {0, 0.5f, 0}, q[4] = {0, 0, 0, 1};
    CHECK_FAILS(pbf_collider_set_target_pose(w, c, nullptr, q), PBF_ERROR_INVALID_ARGUMENT, "position");
    CHECK_FAILS(pbf_collider_set_target_pose(w, c, p, nullptr), PBF_ERROR_INVALID_ARGUMENT, "rotation");
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
