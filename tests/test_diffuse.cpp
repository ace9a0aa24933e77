// Diffuse particles (pbf_diffuse_params, Ihmsen et al. 2012) through the C ABI, CPU backend: they
// appear at a breaking dam's front and never in a resting tank, respect their capacity and
// lifetime, move by their kind, cost nothing when off, and bad input is refused. The CUDA twins
// are in test_gpu_diffuse.cpp ([gpu]).
#include "support.h"

using namespace scene;

namespace {

// small_desc (a 1 m box of CPU fluid) with a diffuse capacity.
pbf_world_desc with_diffuse(uint32_t capacity) {
    pbf_world_desc d = small_desc(4096);
    d.diffuse.max_diffuse = capacity;
    return d;
}

// A still tank of 432 particles (0.6 x 0.3 x 0.3 m of water, spacing 0.05 m) with diffuse
// capacity, settled for 30 steps; no diffuse particle is generated in it.
pbf_world_id still_tank(uint32_t capacity) {
    pbf_world_desc d = tank(PBF_BACKEND_CPU, 0.025f, 0.6f, 0.8f, 0.3f, 4096);
    d.diffuse.max_diffuse = capacity;
    pbf_world_id w = create(d);
    REQUIRE(fill(w, 0, 0, 0, 0.6f, 0.3f, 0.3f) == 432u);
    for (int s = 0; s < 30; ++s) REQUIRE_PBF(pbf_world_step(w, kDt));
    return w;
}

pbf_diffuse_params diffuse_params(pbf_world_id w) {
    pbf_diffuse_params p = pbf_diffuse_params_default();
    REQUIRE_PBF(pbf_world_get_diffuse_params(w, &p));
    return p;
}

// Mean of one coordinate over the fluid particles or the diffuse particles.
double mean_of(const std::vector<float>& rows, uint32_t count, int axis) {
    double s = 0;
    for (uint32_t i = 0; i < count; ++i) s += rows[4 * i + axis];
    return count ? s / count : 0.0;
}

// Every diffuse particle is finite, of a known kind, inside the domain (a radius inside the
// walls) and has 0 < remaining lifetime <= lifetime.
void check_well_formed(const Diffuse& d, float lifetime, const float lo[3], const float hi[3]) {
    for (uint32_t i = 0; i < d.count; ++i) {
        INFO("diffuse particle " << i);
        for (int c = 0; c < 4; ++c) REQUIRE(std::isfinite(d.pos[4 * i + c]));
        for (int c = 0; c < 4; ++c) REQUIRE(std::isfinite(d.vel[4 * i + c]));
        const float kind = d.pos[4 * i + 3];
        CHECK((kind == PBF_DIFFUSE_SPRAY || kind == PBF_DIFFUSE_FOAM || kind == PBF_DIFFUSE_BUBBLE));
        CHECK(d.vel[4 * i + 3] > 0.0f);
        CHECK(d.vel[4 * i + 3] <= lifetime);
        for (int a = 0; a < 3; ++a) {
            CHECK(d.pos[4 * i + a] >= lo[a]);
            CHECK(d.pos[4 * i + a] <= hi[a]);
        }
    }
}

}  // namespace

TEST_CASE("diffuse: defaults; a breaking dam makes them at its front, a resting tank none", "[api][diffuse]") {
    const pbf_diffuse_params p = pbf_diffuse_params_default();
    CHECK(p.struct_size == sizeof p);
    CHECK(p.max_diffuse == 0u);
    CHECK(p.lifetime == 2.0f);
    CHECK(p.spray_max_neighbors == 6u);
    CHECK(p.bubble_min_neighbors == 20u);
    CHECK(pbf_world_desc_default().diffuse.struct_size == sizeof p);
    CHECK(pbf_world_desc_default().diffuse.max_diffuse == 0u);

    pbf_world_id dam = diffuse_dam(PBF_BACKEND_CPU, 20000);
    const float lo[3] = {0.0125f, 0.0125f, 0.0125f}, hi[3] = {0.7875f, 0.4875f, 0.0875f};
    // The front runs along the floor and hits the far wall (x = 0.8 m) after about 0.3 s.
    uint32_t first_step = 0;
    double front_lead = 0.0;
    for (int step = 1; step <= 90; ++step) {
        REQUIRE_PBF(pbf_world_step(dam, kDt));
        const Diffuse d = read_diffuse(dam);
        if (d.count > 0 && first_step == 0) {
            first_step = step;
            // Where the first ones appear: ahead of the fluid's mass, where it moves fastest.
            const Particles f = read(dam);
            front_lead = mean_of(d.pos, d.count, 0) - mean_of(f.pos, f.count, 0);
        }
        if (step % 15 == 0) check_well_formed(d, 2.0f, lo, hi);
    }
    const pbf_step_stats s = stats(dam);
    const Diffuse d = read_diffuse(dam);
    INFO("first diffuse particles at step "
         << first_step << ", " << front_lead << " m ahead of the fluid's centre; " << d.count
         << " live after 90 steps (" << d.of_kind(PBF_DIFFUSE_SPRAY) << " spray, " << d.of_kind(PBF_DIFFUSE_FOAM)
         << " foam, " << d.of_kind(PBF_DIFFUSE_BUBBLE) << " bubbles), " << s.diffuse_generated_total << " generated");
    CHECK(first_step > 0);
    CHECK(first_step < 30);
    CHECK(front_lead > 0.05);
    CHECK(d.count >= 100u);  // measured 376: a few hundred from 512 fluid particles
    CHECK(d.count <= s.diffuse_generated_total);
    CHECK(s.diffuse_dropped_total == 0u);
    CHECK(d.of_kind(PBF_DIFFUSE_FOAM) > 0u);
    CHECK(d.of_kind(PBF_DIFFUSE_BUBBLE) > 0u);
    REQUIRE_PBF(pbf_world_destroy(dam));

    // A resting tank: no motion, no potential, nothing generated in 2 s.
    pbf_world_id rest = still_tank(1000);
    for (int step = 0; step < 120; ++step) REQUIRE_PBF(pbf_world_step(rest, kDt));
    CHECK(stats(rest).diffuse_count == 0u);
    CHECK(stats(rest).diffuse_generated_total == 0u);
    REQUIRE_PBF(pbf_world_destroy(rest));
}

TEST_CASE("diffuse: never more than the capacity; what did not fit is counted", "[api][diffuse]") {
    pbf_world_id w = diffuse_dam(PBF_BACKEND_CPU, 40);
    uint32_t most = 0, dropped_steps = 0;
    for (int step = 0; step < 60; ++step) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        const pbf_step_stats s = stats(w);
        REQUIRE(s.diffuse_count <= 40u);
        most = std::max(most, s.diffuse_count);
        if (s.diffuse_dropped > 0) ++dropped_steps;
    }
    const pbf_step_stats s = stats(w);
    INFO(s.diffuse_dropped_total << " dropped over " << dropped_steps << " steps");
    CHECK(most == 40u);
    CHECK(dropped_steps > 0u);
    CHECK(s.diffuse_dropped_total >= dropped_steps);
    // The buffers hold exactly the count.
    const Diffuse d = read_diffuse(w);
    CHECK(d.count == s.diffuse_count);
    std::vector<float> big(4 * 100, -7.0f);
    uint32_t written = 0;
    REQUIRE_PBF(
        pbf_world_copy_buffer(w, PBF_BUFFER_DIFFUSE_POSITIONS, big.data(), big.size() * sizeof(float), &written));
    CHECK(written == s.diffuse_count);
    REQUIRE_PBF(pbf_world_destroy(w));
}

TEST_CASE("diffuse: lifetimes run down; with generation off every one dissolves", "[api][diffuse]") {
    pbf_world_id w = diffuse_dam(PBF_BACKEND_CPU, 20000);
    pbf_diffuse_params p = diffuse_params(w);
    p.lifetime = 0.5f;
    REQUIRE_PBF(pbf_world_set_diffuse_params(w, &p));
    CHECK(diffuse_params(w).lifetime == 0.5f);
    const float lo[3] = {0.0125f, 0.0125f, 0.0125f}, hi[3] = {0.7875f, 0.4875f, 0.0875f};
    for (int step = 0; step < 60; ++step) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        if (step % 10 == 9) check_well_formed(read_diffuse(w), 0.5f, lo, hi);
    }
    REQUIRE(stats(w).diffuse_count > 0u);
    // Foam and spray age by every step's dt: one step later each has lost kDt.
    const Diffuse before = read_diffuse(w);
    p.trapped_air_rate = p.wave_crest_rate = 0.0f;
    REQUIRE_PBF(pbf_world_set_diffuse_params(w, &p));
    REQUIRE_PBF(pbf_world_step(w, kDt));
    const Diffuse after = read_diffuse(w);
    REQUIRE(after.count <= before.count);
    double aged = 0.0;
    for (uint32_t i = 0; i < after.count; ++i) aged += after.vel[4 * i + 3];
    double was = 0.0;
    for (uint32_t i = 0; i < before.count; ++i) was += before.vel[4 * i + 3];
    INFO("remaining lifetime summed: " << was << " s over " << before.count << " -> " << aged << " s over "
                                       << after.count);
    CHECK(aged < was);
    // No generation: bubbles surface, everything dissolves within a few lifetimes.
    const uint64_t generated = stats(w).diffuse_generated_total;
    for (int step = 0; step < 180; ++step) REQUIRE_PBF(pbf_world_step(w, kDt));
    CHECK(stats(w).diffuse_generated_total == generated);
    CHECK(stats(w).diffuse_count == 0u);
    REQUIRE_PBF(pbf_world_destroy(w));
}

TEST_CASE("diffuse: kinds behave: spray falls, bubbles rise, foam rides a still surface", "[api][diffuse]") {
    pbf_world_id w = still_tank(16);
    // The water's surface is at y = 0.3 m.
    const float pos[] = {0.3f, 0.6f,  0.15f, PBF_DIFFUSE_SPRAY,   // in the air
                         0.3f, 0.1f,  0.15f, PBF_DIFFUSE_BUBBLE,  // 0.2 m deep
                         0.3f, 0.29f, 0.15f, PBF_DIFFUSE_FOAM};   // on the surface
    const float vel[] = {0, 0, 0, 5.0f, 0, 0, 0, 5.0f, 0, 0, 0, 5.0f};
    uint32_t added = 0;
    REQUIRE_PBF(pbf_world_add_diffuse(w, pos, vel, 3, &added));
    REQUIRE(added == 3u);
    REQUIRE(stats(w).diffuse_count == 3u);
    for (int step = 0; step < 10; ++step) REQUIRE_PBF(pbf_world_step(w, kDt));
    const Diffuse d = read_diffuse(w);
    REQUIRE(d.count == 3u);  // survivors keep their order
    INFO("spray y " << d.pos[1] << " vy " << d.vel[1] << "; bubble y " << d.pos[5] << " vy " << d.vel[5] << "; foam y "
                    << d.pos[9] << " v " << d.vel[8] << ", " << d.vel[9] << ", " << d.vel[10]);
    // Spray, 1/6 s after its release: ballistic, ½ g t² = 0.136 m down (drag 0.5/s takes ~5 %).
    CHECK(d.pos[3] == PBF_DIFFUSE_SPRAY);
    CHECK(d.vel[1] < -1.4f);
    CHECK(d.pos[1] < 0.6f - 0.12f);
    CHECK(d.pos[1] > 0.6f - 0.16f);
    // The bubble rises toward its terminal speed k_b g / k_d ≈ 0.25 m/s.
    CHECK(d.pos[7] == PBF_DIFFUSE_BUBBLE);
    CHECK(d.vel[5] > 0.15f);
    CHECK(d.pos[5] > 0.1f + 0.02f);
    // Foam on still water barely moves.
    CHECK(d.pos[11] == PBF_DIFFUSE_FOAM);
    CHECK(std::fabs(d.pos[9] - 0.29f) < 0.02f);
    CHECK(std::fabs(d.vel[9]) < 0.1f);
    // Lifetimes: spray and foam aged 10 steps, the bubble none.
    CHECK(d.vel[3] == Approx(5.0f - 10 * kDt).epsilon(1e-4));
    CHECK(d.vel[7] == 5.0f);
    CHECK(d.vel[11] == Approx(5.0f - 10 * kDt).epsilon(1e-4));
    REQUIRE_PBF(pbf_world_destroy(w));
}

TEST_CASE("diffuse: the CPU backend is deterministic", "[api][diffuse]") {
    pbf_world_id a = diffuse_dam(PBF_BACKEND_CPU, 20000), b = diffuse_dam(PBF_BACKEND_CPU, 20000);
    step_both(a, b, 40);
    const Diffuse da = read_diffuse(a), db = read_diffuse(b);
    REQUIRE(da.count > 0u);
    CHECK(da.count == db.count);
    CHECK(same_bits(da.pos, db.pos));
    CHECK(same_bits(da.vel, db.vel));
    REQUIRE_PBF(pbf_world_destroy(a));
    REQUIRE_PBF(pbf_world_destroy(b));
}

TEST_CASE("diffuse: off costs nothing; on, its bytes, passes and pointers are accounted for", "[api][diffuse]") {
    TestWorld off(with_diffuse(0)), on(with_diffuse(1000));
    for (TestWorld* t : {&off, &on}) {
        t->emit_default_block();
        for (int s = 0; s < 3; ++s) REQUIRE_OK(pbf_world_step(*t, kDt));
    }
    const pbf_world_info i0 = world_info(off), i1 = world_info(on);
    CHECK(i0.diffuse_capacity == 0u);
    CHECK(i0.diffuse_bytes == 0u);
    CHECK(i0.diffuse_updates == 0u);  // no diffuse pass ran
    CHECK(i1.diffuse_capacity == 1000u);
    // 4 float4 buffers (front and back) per diffuse slot, 2 scan words per slot of diffuse +
    // fluid capacity, the counters.
    CHECK(i1.diffuse_bytes == 1000u * 64u + (1000u + 4096u) * 8u + 24u);
    CHECK(i1.device_bytes == i0.device_bytes + i1.diffuse_bytes);
    CHECK(i1.diffuse_updates == 3u);
    // Profiled, the "diffuse" (sources) and "diffuse advect" stages take no time when off.
    CHECK(profiled_stage_ms(off, "diffuse") == 0.0f);
    CHECK(profiled_stage_ms(off, "diffuse advect") == 0.0f);
    CHECK(profiled_stage_ms(on, "diffuse") > 0.0f);
    CHECK(profiled_stage_ms(on, "diffuse advect") > 0.0f);
    CHECK(world_info(off).diffuse_updates == 0u);
    // Device pointers (host memory on the CPU backend): none when off, the copy-out's data when on.
    const float pos[] = {0.0f, 0.8f, 0.0f, PBF_DIFFUSE_SPRAY, 0.1f, 0.8f, 0.0f, PBF_DIFFUSE_SPRAY};
    const float vel[] = {1.0f, 0.0f, 0.0f, 1.0f, -1.0f, 0.0f, 0.0f, 1.0f};
    REQUIRE_OK(pbf_world_add_diffuse(on, pos, vel, 2, nullptr));
    const pbf_device_buffers m0 = map_buffers(off);
    CHECK(m0.diffuse_positions == nullptr);
    CHECK(m0.diffuse_velocities == nullptr);
    CHECK(m0.diffuse_count_device == nullptr);
    CHECK(m0.diffuse_count == 0u);
    CHECK(m0.diffuse_capacity == 0u);
    const pbf_device_buffers m1 = map_buffers(on);
    const Diffuse r = read_diffuse(on);
    REQUIRE(r.count == 2u);
    CHECK(m1.diffuse_count == 2u);
    CHECK(*m1.diffuse_count_device == 2u);
    CHECK(m1.diffuse_capacity == 1000u);
    REQUIRE(m1.diffuse_positions != nullptr);
    CHECK(std::memcmp(m1.diffuse_positions, r.pos.data(), 32) == 0);
    CHECK(std::memcmp(m1.diffuse_velocities, r.vel.data(), 32) == 0);
    CHECK(std::memcmp(r.pos.data(), pos, sizeof pos) == 0);
    REQUIRE_OK(pbf_world_unmap(off));
    REQUIRE_OK(pbf_world_unmap(on));
}

TEST_CASE("diffuse: bad params, rows and buffers are refused, and nothing is lost", "[api][diffuse]") {
    TestWorld off(with_diffuse(0)), on(with_diffuse(4));
    on.emit_default_block();
    (void)stats(on);  // the stats' density pass writes the positions' w (ρ/ρ0) once
    const std::vector<float> before = on.positions();
    pbf_world_id id{0, 0};

    SECTION("world desc") {
        auto refuses = [&](auto change, const char* needle) {
            pbf_world_desc bad = small_desc(4096);
            bad.diffuse.max_diffuse = 100;
            change(bad.diffuse);
            CHECK_FAILS(pbf_world_create(&bad, &id), PBF_ERROR_INVALID_ARGUMENT, needle);
        };
        refuses([](pbf_diffuse_params& p) { p.max_diffuse = uint32_t(-1); }, "max_diffuse");  // a negative int
        refuses([](pbf_diffuse_params& p) { p.max_diffuse = (1u << 26) + 1; }, "max_diffuse");
        for (float v : kBad) {
            INFO(bad_name(v));
            refuses([v](pbf_diffuse_params& p) { p.trapped_air_min = v; }, "thresholds");
            refuses([v](pbf_diffuse_params& p) { p.energy_max = v; }, "thresholds");
            refuses([v](pbf_diffuse_params& p) { p.wave_crest_rate = v; }, "wave_crest_rate");
            refuses([v](pbf_diffuse_params& p) { p.lifetime = v; }, "lifetime");
            refuses([v](pbf_diffuse_params& p) { p.buoyancy = v; }, "buoyancy");
            refuses([v](pbf_diffuse_params& p) { p.spray_drag = v; }, "buoyancy");
        }
        refuses([](pbf_diffuse_params& p) { p.wave_crest_min = p.wave_crest_max; }, "min < max");
        refuses([](pbf_diffuse_params& p) { p.trapped_air_min = -1.0f; }, "thresholds");
        refuses([](pbf_diffuse_params& p) { p.trapped_air_rate = -1.0f; }, "trapped_air_rate");
        refuses([](pbf_diffuse_params& p) { p.lifetime = 0.0f; }, "lifetime");
        refuses([](pbf_diffuse_params& p) { p.spray_max_neighbors = 30; }, "spray_max_neighbors");
        refuses([](pbf_diffuse_params& p) { p.bubble_min_neighbors = 1001; }, "bubble_min_neighbors");
        refuses([](pbf_diffuse_params& p) { p.bubble_drag = -1.0f; }, "bubble_drag");
        pbf_world_desc bad = small_desc(4096);
        bad.diffuse.struct_size = 8;
        CHECK_FAILS(pbf_world_create(&bad, &id), PBF_ERROR_STRUCT_SIZE, "pbf_diffuse_params");
    }
    SECTION("params between steps") {
        pbf_diffuse_params p = diffuse_params(on);
        CHECK(p.max_diffuse == 4u);
        pbf_diffuse_params bad = p;
        bad.lifetime = kNaN;
        CHECK_FAILS(pbf_world_set_diffuse_params(on, &bad), PBF_ERROR_INVALID_ARGUMENT, "lifetime");
        bad = p;
        bad.max_diffuse = 8;
        CHECK_FAILS(pbf_world_set_diffuse_params(on, &bad), PBF_ERROR_INVALID_STATE, "fixed at world creation");
        CHECK(diffuse_params(on).lifetime == p.lifetime);
        CHECK_FAILS(pbf_world_get_diffuse_params(on, nullptr), PBF_ERROR_INVALID_ARGUMENT, "NULL");
        CHECK_FAILS(pbf_world_set_diffuse_params(pbf_world_id{77, 3}, &p), PBF_ERROR_INVALID_HANDLE,
                    "pbf_world_set_diffuse_params");
        p.buoyancy = 1.0f;
        REQUIRE_OK(pbf_world_set_diffuse_params(on, &p));
        CHECK(diffuse_params(on).buoyancy == 1.0f);
    }
    SECTION("added rows") {
        float pos[4 * 6] = {}, vel[4 * 6] = {};
        for (int i = 0; i < 6; ++i) {
            pos[4 * i + 1] = 0.5f;
            pos[4 * i + 3] = PBF_DIFFUSE_FOAM;
            vel[4 * i + 3] = 1.0f;
        }
        uint32_t added = 99;
        for (float v : kBad) {
            INFO(bad_name(v));
            pos[4] = v;
            CHECK_FAILS(pbf_world_add_diffuse(on, pos, vel, 2, &added), PBF_ERROR_INVALID_ARGUMENT, "finite");
            pos[4] = 0.0f;
            vel[7] = v;
            CHECK_FAILS(pbf_world_add_diffuse(on, pos, vel, 2, &added), PBF_ERROR_INVALID_ARGUMENT, "lifetimes > 0");
            vel[7] = 1.0f;
        }
        CHECK(added == 0u);
        pos[7] = 3.0f;  // no such kind
        CHECK_FAILS(pbf_world_add_diffuse(on, pos, vel, 2, &added), PBF_ERROR_INVALID_ARGUMENT, "kinds");
        pos[7] = PBF_DIFFUSE_FOAM;
        vel[3] = 0.0f;  // no lifetime left
        CHECK_FAILS(pbf_world_add_diffuse(on, pos, vel, 2, &added), PBF_ERROR_INVALID_ARGUMENT, "lifetimes > 0");
        vel[3] = 1.0f;
        CHECK_FAILS(pbf_world_add_diffuse(on, nullptr, vel, 2, &added), PBF_ERROR_INVALID_ARGUMENT, "NULL");
        CHECK(stats(on).diffuse_count == 0u);
        CHECK_FAILS(pbf_world_add_diffuse(off, pos, vel, 2, &added), PBF_ERROR_INVALID_STATE, "max_diffuse > 0");
        // Capacity 4: 6 rows add 4; then none fit.
        REQUIRE_OK(pbf_world_add_diffuse(on, pos, vel, 6, &added));
        CHECK(added == 4u);
        CHECK_FAILS(pbf_world_add_diffuse(on, pos, vel, 1, &added), PBF_ERROR_CAPACITY, "max_diffuse");
        CHECK(added == 0u);
        CHECK(stats(on).diffuse_count == 4u);
        REQUIRE_OK(pbf_world_add_diffuse(on, nullptr, nullptr, 0, &added));
    }
    SECTION("diffuse buffers of a world without them") {
        std::vector<float> out(64, -7.0f);
        uint32_t written = 99;
        CHECK_FAILS(pbf_world_copy_buffer(off, PBF_BUFFER_DIFFUSE_POSITIONS, out.data(), 16, &written),
                    PBF_ERROR_INVALID_STATE, "max_diffuse");
        CHECK_FAILS(pbf_world_copy_buffer(off, PBF_BUFFER_DIFFUSE_VELOCITIES, out.data(), 16, &written),
                    PBF_ERROR_INVALID_STATE, "diffuse particles are off");
        CHECK(written == 0u);
        CHECK_FAILS(pbf_world_copy_buffer(on, PBF_BUFFER_DIFFUSE_VELOCITIES, out.data(), 15, &written),
                    PBF_ERROR_INVALID_ARGUMENT, "element size 16");
        CHECK_FAILS(pbf_world_copy_buffer(on, static_cast<pbf_buffer>(9), out.data(), 16, &written),
                    PBF_ERROR_INVALID_ARGUMENT, "_DIFFUSE_VELOCITIES");
        CHECK(out[0] == -7.0f);
    }
    CHECK(same_bits(on.positions(), before));
    on.require_usable(216);
}
