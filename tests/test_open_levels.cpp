// Open levels: worlds without walls, the hashed neighbour grid through the C ABI, its
// memory, far and non-finite positions, emitters and drains far from the origin, and the
// features that read the walls or the grid (coupling, materials, diffuse, render, meshes). The
// scenes shared with the [gpu] twin live in open_level_scenes.h and open_level_features.h; the
// grid itself is tested white-box in test_neighbors.cpp.
#include "open_level_features.h"

using namespace open_level;

TEST_CASE("open level: a puddle 1 km out, held by planes, settles as in a walled 2 m box", "[open]") {
    check_puddle_open_like_box(PBF_BACKEND_CPU);
}

TEST_CASE("open level: a walled puddle flows the same on the dense and the hashed grid", "[open]") {
    check_dense_like_hashed(PBF_BACKEND_CPU);
}

TEST_CASE("open level: without walls a block falls freely until a collider catches it", "[open]") {
    check_free_fall(PBF_BACKEND_CPU);
}

TEST_CASE("open level: grid memory follows the capacity, not the level", "[open]") {
    // 100k particles of radius 0.01 m (h = 0.04 m): a 2 m box has 50^3 = 125000 cells (dense);
    // the open level's hashed grid has 2^17 = 131072 keys, whatever its extent.
    pbf_world_desc d = scene::tank(PBF_BACKEND_CPU, 0.01f, 2, 2, 2, 100000);
    const pbf_world_id box = scene::create(d);
    d.walls = 0;
    const pbf_world_id open = scene::create(d);
    set3(d.domain_min, -500, -500, -500);  // a walled 1 km box: too many cells to be dense
    set3(d.domain_max, 500, 500, 500);
    d.walls = 1;
    const pbf_world_id walled_km = scene::create(d);
    const pbf_world_info a = scene::world_info(box), b = scene::world_info(open), c = scene::world_info(walled_km);
    CHECK(a.grid_hashed == 0u);
    CHECK(a.grid_cells == 125000u);
    CHECK(a.grid_bytes == 4u * (125000u + 1u));
    CHECK(b.grid_hashed == 1u);
    CHECK(b.grid_cells == 131072u);
    CHECK(b.grid_bytes == 4u * (131072u + 1u));
    CHECK(c.grid_hashed == 1u);
    CHECK(c.grid_bytes == b.grid_bytes);
    INFO("grid bytes: box " << a.grid_bytes << ", open " << b.grid_bytes);
    CHECK(double(b.grid_bytes) <= 1.1 * double(a.grid_bytes));  // the goal
    CHECK(double(b.device_bytes) <= 1.01 * double(a.device_bytes));
    for (pbf_world_id w : {box, open, walled_km}) REQUIRE_PBF(pbf_world_destroy(w));
}

TEST_CASE("open level: walls is validated, and an open level ignores its domain", "[open]") {
    pbf_world_desc d = scene::tank(PBF_BACKEND_CPU, 0.025f, 1, 1, 1, 1024);
    CHECK(d.walls == 1u);  // the default keeps the walls
    pbf_world_id w{0, 0};
    d.walls = 2;
    CHECK_FAILS(pbf_world_create(&d, &w), PBF_ERROR_INVALID_ARGUMENT, "walls must be 0");
    d.walls = 1;
    d.hashed_grid = 2;
    CHECK_FAILS(pbf_world_create(&d, &w), PBF_ERROR_INVALID_ARGUMENT, "hashed_grid must be 0");
    d.hashed_grid = 1;
    w = scene::create(d);
    CHECK(scene::world_info(w).grid_hashed == 1u);
    REQUIRE_PBF(pbf_world_destroy(w));
    d.hashed_grid = 0;
    d.walls = 0;
    set3(d.domain_min, kNaN, 0, 0);
    set3(d.domain_max, -1, -1, -1);
    w = scene::create(d);
    REQUIRE_PBF(pbf_world_destroy(w));
    d.walls = 1;
    CHECK_FAILS(pbf_world_create(&d, &w), PBF_ERROR_INVALID_ARGUMENT, "domain bounds must be finite");
}

TEST_CASE("open level: particles far out are held at the open limit, beyond it nothing is emitted", "[open]") {
    pbf_world_desc d = scene::tank(PBF_BACKEND_CPU, 0.025f, 1, 1, 1, 4096);
    d.walls = 0;
    d.gravity[1] = 0.0f;
    const pbf_world_id w = scene::create(d);
    const float limit = std::ldexp(0.1f, 17);  // 2^17 h, h = 0.1 m: 13107.2 m
    pbf_block_desc b = pbf_block_desc_default();
    set3(b.box_min, limit - 0.6f, 0.0f, -1e3f);
    set3(b.box_max, limit - 0.2f, 0.4f, -1e3f + 0.4f);
    set3(b.velocity, 50.0f, 0.0f, 0.0f);  // towards the limit
    uint32_t emitted = 0;
    REQUIRE_PBF(pbf_world_emit_block(w, &b, &emitted));
    REQUIRE(emitted > 0u);
    for (int k = 0; k < 30; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const scene::Particles p = scene::read(w);
    REQUIRE(p.count == emitted);
    REQUIRE(scene::all_finite(p));
    for (uint32_t i = 0; i < p.count; ++i) REQUIRE(p.pos[4 * i] <= limit);
    CHECK(std::isfinite(scene::stats(w).density_error_mean));
    // Beyond the limit (or at 1e30 m) a block is refused, and nothing is lost.
    for (float x : {2.0f * limit, 1e30f}) {
        set3(b.box_min, x, 0.0f, 0.0f);
        set3(b.box_max, x * 1.0001f, 0.4f, 0.4f);
        CHECK_FAILS(pbf_world_emit_block(w, &b, &emitted), PBF_ERROR_INVALID_ARGUMENT, "without walls");
    }
    CHECK(scene::read(w).count == p.count);
    const pbf_emitter_desc far_nozzle = scene::nozzle_at(3.0f * limit, 0.0f, 0.0f, 2.0f, 0.1f, 100.0f);
    pbf_emitter_id e;
    CHECK_FAILS(pbf_world_create_emitter(w, &far_nozzle, &e), PBF_ERROR_INVALID_ARGUMENT, "without walls");
    REQUIRE_PBF(pbf_world_destroy(w));
}

TEST_CASE("open level: a nozzle and a drain 700 m from the origin work", "[open]") {
    pbf_world_desc d = scene::tank(PBF_BACKEND_CPU, 0.025f, 1, 1, 1, 8192);
    d.walls = 0;
    const pbf_world_id w = scene::create(d);
    pbf_emitter_id nozzle, drain;
    const pbf_emitter_desc n = scene::nozzle_at(700.0f, 100.0f, -700.0f, 2.0f, 0.1f, 400.0f);
    REQUIRE_PBF(pbf_world_create_emitter(w, &n, &nozzle));
    const pbf_emitter_desc dr = scene::drain_box(699.0f, 97.0f, -701.0f, 701.0f, 98.0f, -699.0f);
    REQUIRE_PBF(pbf_world_create_emitter(w, &dr, &drain));
    for (int k = 0; k < 90; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const pbf_step_stats s = scene::stats(w);
    CHECK(s.emitted_total > 400u);
    CHECK(s.drained_total > 0u);  // the stream fell 2 m into the drain
    const scene::Particles p = scene::read(w);
    REQUIRE(scene::all_finite(p));
    for (uint32_t i = 0; i < p.count; ++i) CHECK(p.pos[4 * i + 1] > 97.0f);  // nothing got past it
    REQUIRE_PBF(pbf_world_destroy(w));
}

// ---- the features that read the walls or the grid, in an open level (open_level_features.h) -----
TEST_CASE("open level: every push comes from colliders (five dynamic planes carry all the weight)", "[open]") {
    check_planes_carry_all(PBF_BACKEND_CPU);
}

TEST_CASE("open level: sticky honey where the walls would be falls freely (no adhesion, no boundary friction)",
          "[open]") {
    check_honey_falls_freely(PBF_BACKEND_CPU);
}

TEST_CASE("open level: diffuse particles and render data 400 m out, as in the walls", "[open]") {
    check_splash_far_out(PBF_BACKEND_CPU);
}

TEST_CASE("open level: a mesh container 1 km out holds water as the walls do", "[open]") {
    check_mesh_container_far_out(PBF_BACKEND_CPU);
}
