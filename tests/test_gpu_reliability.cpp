// [gpu] reliability: the CUDA twins of the CPU tests in test_threads.cpp and test_reliability.cpp.
//   - out of device memory: worlds are created until the device cannot hold the next one; that
//     creation fails with PBF_ERROR_OUT_OF_MEMORY, every existing world keeps stepping, and the
//     memory of the failed world is not leaked (the same worlds fit again after a cleanup);
//   - emitting past capacity is refused cleanly (blocks and nozzles);
//   - N worlds stepped on N threads give bit-identical results to the same worlds stepped one
//     after another; concurrent calls on one world; destroy racing with calls.
// Runs only where a CUDA device is (gpu_main.cpp skips the suite otherwise); it compiles
// everywhere. scripts/gpu/reliability.sh runs it under compute-sanitizer.
#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

#include "reliability_support.h"
#include "support.h"

TEST_CASE("CUDA out of memory: creation fails with OUT_OF_MEMORY, other worlds step on, nothing leaks",
          "[gpu][reliability][memory]") {
    // The survivor: a small world with a nozzle and a drain.
    rel::World survivor;
    REQUIRE(rel::make_world(PBF_BACKEND_CUDA, 0, &survivor) == "");
    REQUIRE(rel::drive(survivor, 0, 10) == "");

    // 2^28 particles (~32 GB each) until the device is full: at most 12 (384 GB) on any GPU.
    auto fill_device = [](std::vector<pbf_world_id>* big, std::string* last_message) -> pbf_result {
        pbf_world_desc d = pbf_world_desc_default();
        d.backend = PBF_BACKEND_CUDA;
        d.max_particles = 1u << 28;
        d.particle_radius = 0.025f;
        scene::set3(d.domain_min, 0.0f, 0.0f, 0.0f);
        scene::set3(d.domain_max, 1.0f, 1.0f, 1.0f);
        for (int k = 0; k < 12; ++k) {
            pbf_world_id id{9, 9};
            const pbf_result r = pbf_world_create(&d, &id);
            if (r != PBF_OK) {
                *last_message = pbf_last_error_message();
                if (id.generation != 0) return PBF_ERROR_INTERNAL;  // a failed create must zero the handle
                return r;
            }
            big->push_back(id);
        }
        return PBF_OK;
    };
    std::vector<pbf_world_id> big;
    std::string message;
    const pbf_result r = fill_device(&big, &message);
    INFO("worlds of 2^28 particles that fitted: " << big.size() << "; the failure: " << message);
    CHECK(r == PBF_ERROR_OUT_OF_MEMORY);
    CHECK_THAT(message, Catch::Contains("PBF_ERROR_OUT_OF_MEMORY"));
    const size_t fitted = big.size();

    // Every existing world still works: the big ones take a step, the survivor steps on
    // exactly like a twin that never saw the failure.
    for (pbf_world_id id : big) {
        pbf_block_desc b = pbf_block_desc_default();
        scene::set3(b.box_min, 0.1f, 0.0f, 0.1f);
        scene::set3(b.box_max, 0.3f, 0.2f, 0.3f);
        REQUIRE_PBF(pbf_world_emit_block(id, &b, nullptr));
        REQUIRE_PBF(pbf_world_step(id, 1.0f / 60.0f));
        CHECK(scene::all_finite(scene::read(id)));
    }
    rel::check_like_twin(PBF_BACKEND_CUDA, survivor, 10, 30);

    // Nothing of the failed creation leaked: after destroying the big worlds, as many fit again.
    for (pbf_world_id id : big) REQUIRE_PBF(pbf_world_destroy(id));
    big.clear();
    const pbf_result again = fill_device(&big, &message);
    CHECK(again == PBF_ERROR_OUT_OF_MEMORY);
    CHECK(big.size() == fitted);
    for (pbf_world_id id : big) REQUIRE_PBF(pbf_world_destroy(id));
    REQUIRE(rel::drive(survivor, 30, 5) == "");
    REQUIRE_PBF(pbf_world_destroy(survivor.id));
}

TEST_CASE("CUDA capacity: emitting past capacity is refused cleanly", "[gpu][reliability][capacity]") {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = PBF_BACKEND_CUDA;
    d.max_particles = 300;
    scene::set3(d.domain_min, 0.0f, 0.0f, 0.0f);
    scene::set3(d.domain_max, 0.5f, 0.5f, 0.5f);
    pbf_world_id w{};
    REQUIRE_PBF(pbf_world_create(&d, &w));
    pbf_block_desc b = pbf_block_desc_default();
    scene::set3(b.box_min, 0.0f, 0.0f, 0.0f);
    scene::set3(b.box_max, 0.5f, 0.5f, 0.5f);
    uint32_t emitted = 0;
    REQUIRE_PBF(pbf_world_emit_block(w, &b, &emitted));
    CHECK(emitted == 300u);
    const scene::Particles full = scene::read(w);
    emitted = 77;
    CHECK(pbf_world_emit_block(w, &b, &emitted) == PBF_ERROR_CAPACITY);
    CHECK(emitted == 0u);
    const scene::Particles again = scene::read(w);
    CHECK(again.ids == full.ids);
    CHECK(std::memcmp(again.pos.data(), full.pos.data(), full.pos.size() * sizeof(float)) == 0);
    // Speed 5000 m/s so that the disc carries 10^6 per second.
    const pbf_emitter_desc n = scene::nozzle_at(0.25f, 0.45f, 0.25f, 5000.0f, 0.1f, 1e6f);
    pbf_emitter_id nozzle{};
    REQUIRE_PBF(pbf_world_create_emitter(w, &n, &nozzle));
    for (int k = 0; k < 20; ++k) {
        REQUIRE_PBF(pbf_world_step(w, 1.0f / 60.0f));
        const pbf_step_stats s = scene::stats(w);
        REQUIRE(s.particle_count == 300u);
        REQUIRE(s.emitted_total == 300u);
    }
    CHECK(scene::all_finite(scene::read(w)));
    REQUIRE_PBF(pbf_world_destroy(w));
}

TEST_CASE("CUDA threads: N worlds stepped on N threads give bit-identical results to one after another",
          "[gpu][reliability][threads]") {
    const rel::ParallelResult r = rel::parallel_vs_sequential(PBF_BACKEND_CUDA, 6, 60);
    rel::check_parallel(r);
}

TEST_CASE("CUDA threads: concurrent calls on ONE world stay consistent", "[gpu][reliability][threads]") {
    const rel::SharedWorldResult r = rel::shared_world(PBF_BACKEND_CUDA, 1.5);
    rel::check_shared_world(r);
}

TEST_CASE("CUDA threads: destroy racing with calls returns OK or INVALID_HANDLE", "[gpu][reliability][threads]") {
    const rel::DestroyRaceResult r = rel::destroy_race(PBF_BACKEND_CUDA, 10, 4);
    INFO("calls that completed " << r.ok << ", refused after destroy " << r.invalid);
    CHECK(r.error == "");
    CHECK(r.invalid == 10u * 4u);
}

// Every kernel path of a step, a few times each, on a small world: what compute-sanitizer's
// slower tools (racecheck above all) run over in scripts/gpu/reliability.sh. LDC on and off,
// vorticity/XSPH on and off, adaptive iterations, 2 substeps, nozzle, drain, block, colliders of
// every shape (one kinematic), stats, copies, map/unmap, device buffers.
TEST_CASE("CUDA: every kernel path briefly (the compute-sanitizer run)", "[gpu][reliability][quick]") {
    rel::World w;
    REQUIRE(rel::make_world(PBF_BACKEND_CUDA, 0, &w) == "");  // block, nozzle, drain, kinematic sphere
    const float shapes[][3] = {{0.1f, 0.05f, 0.1f}, {0.5f, 0.1f, 0.3f}, {0.2f, 0.1f, 0.3f}};
    for (int k = 0; k < 3; ++k) {
        pbf_collider_desc c = pbf_collider_desc_default();
        c.shape = k == 0 ? PBF_SHAPE_BOX : k == 1 ? PBF_SHAPE_CAPSULE : PBF_SHAPE_PLANE;
        std::memcpy(c.position, shapes[k], sizeof c.position);
        c.radius = 0.04f;
        c.half_height = 0.05f;
        scene::set3(c.half_extents, 0.04f, 0.04f, 0.04f);
        if (k == 2) c.position[1] = 0.01f;
        c.friction = 0.3f;
        pbf_collider_id id{};
        REQUIRE_PBF(pbf_world_create_collider(w.id, &c, &id));
    }
    pbf_solver_params p = pbf_solver_params_default();
    REQUIRE_PBF(pbf_world_get_solver_params(w.id, &p));
    int first = 0;
    for (int phase = 0; phase < 3; ++phase) {
        p.ldc_enabled = phase != 1;
        p.vorticity_epsilon = phase == 1 ? 0.0f : 0.0005f;
        p.xsph_c = phase == 1 ? 0.0f : 0.01f;
        p.substeps = 2;
        p.adaptive_error_target = phase == 2 ? 0.01f : 0.0f;
        REQUIRE_PBF(pbf_world_set_solver_params(w.id, &p));
        REQUIRE(rel::drive(w, first, 3) == "");
        first += 3;
        rel::Capture c;
        REQUIRE(rel::capture(w.id, &c) == "");
        CHECK(rel::consistent(c, 1500) == "");
    }
    pbf_mapped_buffer m;
    std::memset(&m, 0, sizeof m);
    m.struct_size = sizeof m;
    REQUIRE_PBF(pbf_world_map_positions(w.id, &m));
    REQUIRE_PBF(pbf_world_unmap(w.id));
    pbf_device_buffers b;
    std::memset(&b, 0, sizeof b);
    b.struct_size = sizeof b;
    REQUIRE_PBF(pbf_world_map_device_buffers(w.id, 0, &b));
    CHECK(b.memory == PBF_MEMORY_CUDA_DEVICE);
    REQUIRE_PBF(pbf_world_unmap(w.id));
    REQUIRE_PBF(pbf_world_destroy(w.id));
}
