// Black-box tests of the C ABI (include/pbf_c_api.h) on the CPU backend. Particles: copy-out, ids, destroy racing with calls, robustness, and "a failed call changes nothing".
// Fixtures: support.h.
#include "support.h"

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
    // A block above the domain is refused; one across its side wall is clipped to the walls,
    // and one inside has an absurd but finite velocity.
    pbf_block_desc above = block(0.0f, 5.0f, 0.0f, 0.11f, 5.11f, 0.11f);
    uint32_t none = 3;
    CHECK(pbf_world_emit_block(w, &above, &none) == PBF_ERROR_INVALID_ARGUMENT);
    CHECK(none == 0u);
    CHECK(w.emit(block(-3.0f, 0.2f, -0.1f, -0.39f, 0.31f, 0.01f)) > 0u);
    pbf_block_desc fast = block(0.1f, 0.2f, -0.1f, 0.21f, 0.31f, 0.01f);
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
    bad.iterations = 3;     // a valid change ...
    bad.max_speed = -1.0f;  // ... in a refused struct must not be applied
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
