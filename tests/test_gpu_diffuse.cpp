// [gpu] diffuse particles: the CUDA backend runs the same diffuse passes as the CPU backend
// (test_diffuse.cpp): the same moves of injected particles in a still tank, comparable
// generation at a breaking dam, capacity and lifetime kept, nothing allocated or run when off.
#include "support.h"

using namespace scene;

namespace {

// A still tank of 432 particles (as test_diffuse.cpp's) on `backend`, three diffuse particles
// added after 30 steps (spray in the air, a bubble 0.2 m deep, foam on the surface), then 10
// steps; also the fluid then, which foam and bubbles follow.
struct KindsRun {
    Diffuse diffuse;
    Particles fluid;
};
KindsRun kinds_after_10_steps(pbf_backend backend) {
    pbf_world_desc d = tank(backend, 0.025f, 0.6f, 0.8f, 0.3f, 4096);
    d.diffuse.max_diffuse = 16;
    pbf_world_id w = create(d);
    REQUIRE(fill(w, 0, 0, 0, 0.6f, 0.3f, 0.3f) == 432u);
    for (int s = 0; s < 30; ++s) REQUIRE_PBF(pbf_world_step(w, kDt));
    const float pos[] = {0.3f, 0.6f,  0.15f, PBF_DIFFUSE_SPRAY, 0.3f, 0.1f, 0.15f, PBF_DIFFUSE_BUBBLE,
                         0.3f, 0.29f, 0.15f, PBF_DIFFUSE_FOAM};
    const float vel[] = {0, 0, 0, 5.0f, 0, 0, 0, 5.0f, 0, 0, 0, 5.0f};
    REQUIRE_PBF(pbf_world_add_diffuse(w, pos, vel, 3, nullptr));
    for (int s = 0; s < 10; ++s) REQUIRE_PBF(pbf_world_step(w, kDt));
    KindsRun r{read_diffuse(w), read(w)};
    REQUIRE_PBF(pbf_world_destroy(w));
    return r;
}

// The largest difference of a fluid velocity component between two runs, particle by particle (by id).
double fluid_velocity_difference(const Particles& a, const Particles& b) {
    std::vector<int64_t> row(a.count + b.count + 1, -1);
    for (uint32_t i = 0; i < b.count; ++i)
        if (b.ids[i] < row.size()) row[b.ids[i]] = i;
    double worst = 0.0;
    for (uint32_t i = 0; i < a.count; ++i) {
        REQUIRE(a.ids[i] < row.size());
        const int64_t j = row[a.ids[i]];
        REQUIRE(j >= 0);
        for (int c = 0; c < 3; ++c)
            worst = std::max(worst, double(std::fabs(a.vel[4 * i + c] - b.vel[4 * size_t(j) + c])));
    }
    return worst;
}

}  // namespace

TEST_CASE("CUDA and CPU agree on diffuse particles: injected kinds move alike", "[gpu][diffuse]") {
    const KindsRun ra = kinds_after_10_steps(PBF_BACKEND_CPU), rb = kinds_after_10_steps(PBF_BACKEND_CUDA);
    const Diffuse &a = ra.diffuse, &b = rb.diffuse;
    REQUIRE(a.count == 3u);
    REQUIRE(b.count == 3u);
    for (int i = 0; i < 3; ++i) CHECK(a.pos[4 * i + 3] == b.pos[4 * i + 3]);  // the same kinds, in the same order
    // Spray flies on its own (gravity and drag): the backends agree to rounding. Foam and
    // bubbles follow the fluid's velocity, and the two backends' fluids differ after 40 steps
    // (float sums in another order): theirs may differ by as much as the fluid's velocities
    // do, carried over the 10 steps (1/6 s), and no more.
    const double dv_fluid = fluid_velocity_difference(ra.fluid, rb.fluid);
    for (int i = 0; i < 3; ++i) {
        const bool spray = a.pos[4 * i + 3] == PBF_DIFFUSE_SPRAY;
        const double dv = spray ? 1e-3 : dv_fluid + 1e-3, dx = spray ? 1e-3 : dv * (10.0 * kDt) + 1e-3;
        for (int c = 0; c < 3; ++c) {
            INFO("diffuse particle " << i << " (kind " << a.pos[4 * i + 3] << ") axis " << c << ": position CPU "
                                     << a.pos[4 * i + c] << " CUDA " << b.pos[4 * i + c] << ", velocity CPU "
                                     << a.vel[4 * i + c] << " CUDA " << b.vel[4 * i + c]
                                     << "; the fluids' largest velocity difference " << dv_fluid);
            CHECK(std::fabs(a.vel[4 * i + c] - b.vel[4 * i + c]) <= dv);
            CHECK(std::fabs(a.pos[4 * i + c] - b.pos[4 * i + c]) <= dx);
        }
        CHECK(std::fabs(a.vel[4 * i + 3] - b.vel[4 * i + 3]) <= 1e-5);  // the same lifetimes
    }
}

TEST_CASE("CUDA diffuse particles at a breaking dam: comparable to the CPU, capacity and lifetime kept",
          "[gpu][diffuse]") {
    pbf_world_id cpu = diffuse_dam(PBF_BACKEND_CPU, 20000), gpu = diffuse_dam(PBF_BACKEND_CUDA, 20000);
    step_both(cpu, gpu, 60);
    // A splashing flow is chaotic: rounding makes the backends' particles differ after a few
    // dozen steps, so compare aggregates.
    const pbf_step_stats sc = stats(cpu), sg = stats(gpu);
    INFO("diffuse count CPU " << sc.diffuse_count << ", CUDA " << sg.diffuse_count << "; generated CPU "
                              << sc.diffuse_generated_total << ", CUDA " << sg.diffuse_generated_total);
    REQUIRE(sc.diffuse_count > 0u);
    CHECK(sg.diffuse_count > sc.diffuse_count / 2);
    CHECK(sg.diffuse_count < sc.diffuse_count * 2);
    const Diffuse d = read_diffuse(gpu);
    for (uint32_t i = 0; i < d.count; ++i) {
        INFO("diffuse particle " << i);
        for (int c = 0; c < 4; ++c) REQUIRE(std::isfinite(d.pos[4 * i + c]));
        CHECK(d.vel[4 * i + 3] > 0.0f);
        CHECK(d.vel[4 * i + 3] <= 2.0f);
        CHECK(d.pos[4 * i] >= 0.0f);
        CHECK(d.pos[4 * i] <= 0.8f);
    }
    REQUIRE_PBF(pbf_world_destroy(cpu));
    REQUIRE_PBF(pbf_world_destroy(gpu));

    // Capacity 40 on CUDA: never more, the rest counted as dropped.
    pbf_world_id small = diffuse_dam(PBF_BACKEND_CUDA, 40);
    for (int s = 0; s < 60; ++s) {
        REQUIRE_PBF(pbf_world_step(small, kDt));
        REQUIRE(stats(small).diffuse_count <= 40u);
    }
    CHECK(stats(small).diffuse_count == 40u);
    CHECK(stats(small).diffuse_dropped_total > 0u);
    REQUIRE_PBF(pbf_world_destroy(small));
}

TEST_CASE("CUDA without diffuse particles: no diffuse bytes, no diffuse pass", "[gpu][diffuse]") {
    pbf_world_desc d = tank(PBF_BACKEND_CUDA, 0.0125f, 0.8f, 0.5f, 0.2f, 8192);
    pbf_world_id off = create(d);
    d.diffuse.max_diffuse = 100000;
    pbf_world_id on = create(d);
    for (pbf_world_id w : {off, on}) {
        fill(w, 0, 0, 0, 0.2f, 0.4f, 0.2f);
        for (int s = 0; s < 3; ++s) REQUIRE_PBF(pbf_world_step(w, kDt));
    }
    const pbf_world_info a = world_info(off), b = world_info(on);
    CHECK(a.diffuse_bytes == 0u);
    CHECK(a.diffuse_updates == 0u);
    // 64 bytes per diffuse slot, 8 per scan slot, the counters and CUB's scan storage.
    CHECK(b.diffuse_bytes >= 100000u * 64u + (100000u + 8192u) * 8u);
    CHECK(b.device_bytes == a.device_bytes + b.diffuse_bytes);
    CHECK(b.diffuse_updates == 3u);
    REQUIRE_PBF(pbf_world_destroy(off));
    REQUIRE_PBF(pbf_world_destroy(on));
}
