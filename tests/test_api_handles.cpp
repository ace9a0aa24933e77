// Black-box tests of the C ABI (include/pbf_c_api.h) on the CPU backend. Handles: stale, reused and foreign world, emitter and collider handles are refused.
// Fixtures: support.h.
#include "support.h"

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
        CHECK_FAILS(pbf_emitter_set_nozzle(id, e, g, g), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_world_create_collider(id, &cd, &co), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK(co.generation == 0);
        CHECK_FAILS(pbf_world_destroy_collider(id, c), PBF_ERROR_INVALID_HANDLE, needle);
        CHECK_FAILS(pbf_collider_set_target_pose(id, c, g, q), PBF_ERROR_INVALID_HANDLE, needle);
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
    CHECK_FAILS(pbf_emitter_set_drain_box(w, e1, lo, hi), PBF_ERROR_INVALID_HANDLE, "emitter");

    // The slot is reused by e2; e1 must still be refused and e2 must work.
    pbf_emitter_id e2{};
    REQUIRE_OK(pbf_world_create_emitter(w, &dd, &e2));
    CHECK_FALSE(same_id(e1, e2));
    CHECK_FAILS(pbf_emitter_set_enabled(w, e1, 1), PBF_ERROR_INVALID_HANDLE, "emitter");
    CHECK_FAILS(pbf_world_destroy_emitter(w, e1), PBF_ERROR_INVALID_HANDLE, "emitter");
    REQUIRE_OK(pbf_emitter_set_drain_box(w, e2, lo, hi));
    REQUIRE_OK(pbf_emitter_set_enabled(w, e2, 0));

    for (pbf_emitter_id forged : {pbf_emitter_id{0, 0}, pbf_emitter_id{12345, 7}, pbf_emitter_id{e2.index, 0},
                                  pbf_emitter_id{e2.index, e2.generation + 1}}) {
        INFO("emitter {" << forged.index << ", " << forged.generation << "}");
        CHECK_FAILS(pbf_emitter_set_enabled(w, forged, 0), PBF_ERROR_INVALID_HANDLE, "emitter");
        CHECK_FAILS(pbf_emitter_set_drain_box(w, forged, lo, hi), PBF_ERROR_INVALID_HANDLE, "emitter");
        CHECK_FAILS(pbf_world_destroy_emitter(w, forged), PBF_ERROR_INVALID_HANDLE, "emitter");
    }

    // An emitter handle of world A given to world B (which has no emitters) is refused.
    TestWorld other;
    CHECK_FAILS(pbf_emitter_set_enabled(other, e2, 1), PBF_ERROR_INVALID_HANDLE, "emitter");
    CHECK_FAILS(pbf_emitter_set_drain_box(other, e2, lo, hi), PBF_ERROR_INVALID_HANDLE, "emitter");
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
    CHECK_FAILS(pbf_collider_set_target_pose(w, c1, p, q), PBF_ERROR_INVALID_HANDLE, "collider");

    pbf_collider_id c2{};
    REQUIRE_OK(pbf_world_create_collider(w, &kd, &c2));
    CHECK_FALSE((c1.index == c2.index && c1.generation == c2.generation));
    CHECK_FAILS(pbf_collider_set_target_pose(w, c1, p, q), PBF_ERROR_INVALID_HANDLE, "collider");
    CHECK_FAILS(pbf_world_destroy_collider(w, c1), PBF_ERROR_INVALID_HANDLE, "collider");
    REQUIRE_OK(pbf_collider_set_target_pose(w, c2, p, q));

    for (pbf_collider_id forged : {pbf_collider_id{0, 0}, pbf_collider_id{12345, 7}, pbf_collider_id{c2.index, 0},
                                   pbf_collider_id{c2.index, c2.generation + 1}}) {
        INFO("collider {" << forged.index << ", " << forged.generation << "}");
        CHECK_FAILS(pbf_collider_set_target_pose(w, forged, p, q), PBF_ERROR_INVALID_HANDLE, "collider");
        CHECK_FAILS(pbf_world_destroy_collider(w, forged), PBF_ERROR_INVALID_HANDLE, "collider");
    }

    TestWorld other;
    CHECK_FAILS(pbf_collider_set_target_pose(other, c2, p, q), PBF_ERROR_INVALID_HANDLE, "collider");
    CHECK_FAILS(pbf_world_destroy_collider(other, c2), PBF_ERROR_INVALID_HANDLE, "collider");
    REQUIRE_OK(pbf_world_destroy_collider(w, c2));
    w.require_usable(n);
    other.require_usable(0);
}

// Per-world slot tables use the same indices; generations from one process-wide counter keep
// world A's first emitter handle from matching world B's first emitter.
TEST_CASE("handles: an emitter handle of one world is refused by another world that has emitters", "[api][handle]") {
    TestWorld a, b;
    pbf_emitter_desc dd = drain_desc();
    dd.enabled = 0;
    pbf_emitter_id ea{}, eb{};
    REQUIRE_OK(pbf_world_create_emitter(a, &dd, &ea));
    REQUIRE_OK(pbf_world_create_emitter(b, &dd, &eb));
    INFO("A's emitter {" << ea.index << ", " << ea.generation << "}, B's {" << eb.index << ", " << eb.generation
                         << "}");
    CHECK_FAILS(pbf_emitter_set_enabled(b, ea, 1), PBF_ERROR_INVALID_HANDLE, "emitter");
    pbf_collider_desc cd = collider_desc(PBF_SHAPE_SPHERE);
    pbf_collider_id ca{}, cb{};
    REQUIRE_OK(pbf_world_create_collider(a, &cd, &ca));
    REQUIRE_OK(pbf_world_create_collider(b, &cd, &cb));
    CHECK_FAILS(pbf_world_destroy_collider(b, ca), PBF_ERROR_INVALID_HANDLE, "collider");
}
