// Black-box tests of the C ABI (include/pbf_c_api.h) on the CPU backend. Capacity, state and resources: full worlds, the collider table, map/unmap, backends and memory.
// Fixtures: support.h.
#include "support.h"

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
    nd.speed = 12.0f;                   // so that the disc carries it (6780 per second)
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

TEST_CASE("capacity: the collider table holds max_colliders, 300 of them rest particles", "[api][capacity][collider]") {
    pbf_world_desc d = small_desc();
    d.max_colliders = 300;
    TestWorld w(d);
    // 300 small boxes tiling the floor of the domain, a block of water dropped on them.
    std::vector<pbf_collider_id> ids;
    for (int i = 0; i < 300; ++i) {
        pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX);
        c.position[0] = -0.475f + 0.05f * float(i % 20);
        c.position[1] = 0.05f;
        c.position[2] = -0.35f + 0.05f * float(i / 20);
        c.half_extents[0] = c.half_extents[2] = 0.025f;
        c.half_extents[1] = 0.05f;
        pbf_collider_id id{};
        INFO("collider " << i);
        REQUIRE_OK(pbf_world_create_collider(w, &c, &id));
        ids.push_back(id);
    }
    pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX);
    pbf_collider_id extra{9, 9};
    CHECK_FAILS(pbf_world_create_collider(w, &c, &extra), PBF_ERROR_CAPACITY, "max_colliders = 300");
    CHECK(extra.generation == 0);
    const uint32_t n = w.emit(block(-0.2f, 0.2f, -0.2f, 0.2f, 0.4f, 0.2f));
    for (int k = 0; k < 60; ++k) REQUIRE_OK(pbf_world_step(w, 1.0f / 60.0f));
    // Every particle above the boxes (|z| < 0.375) rests on their tops (y = 0.1), none flies off.
    const std::vector<float> p = w.positions();
    REQUIRE(p.size() == size_t(n) * 4);
    const float r = 0.025f;
    for (uint32_t i = 0; i < n; ++i) {
        const float x = p[4 * i], y = p[4 * i + 1], z = p[4 * i + 2];
        INFO("particle " << i << " at " << x << ", " << y << ", " << z);
        if (std::fabs(z) < 0.375f - r) REQUIRE(y >= 0.1f + r - 1e-3f);
        REQUIRE(y <= 0.5f);
    }
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
    CHECK_FAILS(pbf_collider_set_target_pose(w, s, p, q), PBF_ERROR_INVALID_STATE, "kinematic");
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
