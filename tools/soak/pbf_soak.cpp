// pbf_soak: runs a small world with a nozzle and a drain for many steps and checks, every K
// steps, that nothing drifts:
//   - no NaN or Inf in any position or velocity, and every particle inside the domain walls;
//   - particle accounting is exact: emitted_total - drained_total == particle_count <= capacity;
//   - ids are unique;
//   - the process's resident memory (/proc/self/statm) is flat after a warm-up: it may not grow
//     by more than --rss-slack-kb over the value measured when the warm-up ends.
// The scene cycles through its states so that every path runs many times: the nozzle sweeps
// over the tank and is switched off and on (the tank fills to capacity, then drains), and a
// kinematic sphere stirs the pool.
//
//   pbf_soak [--steps N=1000000] [--check-every K=1000] [--capacity C=256]
//            [--warmup W=min(N/10, 20000)] [--rss-slack-kb S=2048] [--backend cpu|cuda]
//            [--substeps 1] [--iterations 2] [--quiet]     (--help lists them with their defaults)
//
// Exit status 0 when every check passed; 1 on the first failed check (with a message).
#include <pbf_c_api.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#if defined(__linux__)
#include <unistd.h>
#endif

namespace {

struct Options {
    uint64_t steps = 1000000;
    uint64_t check_every = 1000;
    uint32_t capacity = 256;
    uint64_t warmup = UINT64_MAX;  // default: min(steps / 10, 20000)
    uint64_t rss_slack_kb = 2048;
    pbf_backend backend = PBF_BACKEND_CPU;
    uint32_t substeps = 1;
    uint32_t iterations = 2;
    bool quiet = false;
};

[[noreturn]] void die(const std::string& message) {
    std::fprintf(stderr, "pbf_soak: FAILED: %s\n", message.c_str());
    std::exit(1);
}

void require(pbf_result r, const char* call) {
    if (r != PBF_OK) die(std::string(call) + " -> " + pbf_result_string(r) + ": " + pbf_last_error_message());
}
#define CALL(x) require((x), #x)

// Resident set size in KiB, or 0 where /proc is not available.
uint64_t rss_kb() {
#if defined(__linux__)
    FILE* f = std::fopen("/proc/self/statm", "r");
    if (!f) return 0;
    unsigned long long size = 0, resident = 0;
    const int got = std::fscanf(f, "%llu %llu", &size, &resident);
    std::fclose(f);
    if (got != 2) return 0;
    return resident * uint64_t(sysconf(_SC_PAGESIZE)) / 1024;
#else
    return 0;
#endif
}

Options parse(int argc, char** argv) {
    Options o;
    // Counts are read as numbers so that 1e6 works as it always has; they are truncated to
    // integers (values 0 .. 1e18).
    double steps = double(o.steps), check_every = double(o.check_every), capacity = double(o.capacity), warmup = 0.0,
           rss_slack_kb = double(o.rss_slack_kb), substeps = double(o.substeps), iterations = double(o.iterations);
    std::string backend = "cpu";
    CLI::App app{
        "pbf_soak: runs a small world with a nozzle, a drain and a kinematic sphere for many steps and "
        "checks every K steps that nothing drifts (no NaN/Inf, particles inside the walls, exact particle "
        "accounting, unique ids, flat resident memory after the warm-up). Exit status 0 when every check "
        "passed; 1 on the first failed check.",
        "pbf_soak"};
    app.option_defaults()->always_capture_default()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    CLI::Validator count = CLI::Range(0.0, 1e18);
    count.description("");  // the type N says enough in --help
    app.add_option("--steps", steps, "steps to run (1e6 notation accepted)")->check(count)->type_name("N");
    app.add_option("--check-every", check_every, "steps between checks (at least 1)")->check(count)->type_name("N");
    app.add_option("--capacity", capacity, "max_particles of the world (at most 2^24)")->check(count)->type_name("N");
    app.add_option("--warmup", warmup, "steps before the resident memory baseline is taken")
        ->check(count)
        ->type_name("N")
        ->default_str("min(steps/10, 20000)");
    app.add_option("--rss-slack-kb", rss_slack_kb, "allowed growth of resident memory after the warm-up, KiB")
        ->check(count)
        ->type_name("N");
    app.add_option("--backend", backend, "cpu or cuda")->check(CLI::IsMember({"cpu", "cuda"}));
    app.add_option("--substeps", substeps, "solver substeps per step")->check(count)->type_name("N");
    app.add_option("--iterations", iterations, "constraint iterations per substep")->check(count)->type_name("N");
    app.add_flag("--quiet", o.quiet, "print only the final line");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        std::exit(rc == 0 ? 0 : 1);  // --help: 0; a bad argument: 1, as before
    }
    o.steps = uint64_t(steps);
    o.check_every = std::max<uint64_t>(1, uint64_t(check_every));
    o.capacity = uint32_t(std::min<uint64_t>(uint64_t(capacity), 1u << 24));
    o.warmup = app.count("--warmup") ? uint64_t(warmup) : std::min<uint64_t>(o.steps / 10, 20000);
    o.rss_slack_kb = uint64_t(rss_slack_kb);
    o.substeps = uint32_t(uint64_t(substeps));
    o.iterations = uint32_t(uint64_t(iterations));
    o.backend = backend == "cuda" ? PBF_BACKEND_CUDA : PBF_BACKEND_CPU;
    return o;
}

void set3(float* v, float x, float y, float z) {
    v[0] = x;
    v[1] = y;
    v[2] = z;
}

// The scene: a 0.5 m tank (radius 0.025: 5 x 5 x 5 grid cells), a nozzle near the lid, a drain
// in one corner of the floor, a kinematic sphere.
struct Scene {
    pbf_world_id world{};
    pbf_emitter_id nozzle{}, drain{};
    pbf_collider_id stirrer{};
    pbf_world_desc desc{};
};

Scene build(const Options& o) {
    Scene s;
    s.desc = pbf_world_desc_default();
    s.desc.backend = o.backend;
    s.desc.max_particles = o.capacity;
    s.desc.particle_radius = 0.025f;
    set3(s.desc.domain_min, 0.0f, 0.0f, 0.0f);
    set3(s.desc.domain_max, 0.5f, 0.5f, 0.5f);
    s.desc.solver.substeps = o.substeps;
    s.desc.solver.iterations = o.iterations;
    CALL(pbf_world_create(&s.desc, &s.world));

    pbf_emitter_desc n = pbf_emitter_desc_default();
    n.type = PBF_EMITTER_NOZZLE;
    set3(n.position, 0.25f, 0.42f, 0.25f);
    set3(n.direction, 0.3f, -1.0f, 0.1f);
    n.speed = 4.0f;
    n.radius = 0.1f;  // the disc carries π 0.1² / 0.05² x 4 / 0.05 = 1005 per second
    n.particles_per_second = 900.0f;
    CALL(pbf_world_create_emitter(s.world, &n, &s.nozzle));

    pbf_emitter_desc d = pbf_emitter_desc_default();
    d.type = PBF_EMITTER_DRAIN;
    set3(d.box_min, 0.0f, 0.0f, 0.0f);
    set3(d.box_max, 0.15f, 0.06f, 0.15f);
    CALL(pbf_world_create_emitter(s.world, &d, &s.drain));

    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_SPHERE;
    c.motion = PBF_MOTION_KINEMATIC;
    set3(c.position, 0.25f, 0.1f, 0.25f);
    c.radius = 0.06f;
    c.friction = 0.2f;
    CALL(pbf_world_create_collider(s.world, &c, &s.stirrer));
    return s;
}

// Per-step scene motion: the nozzle sweeps, runs 3 s of every 5 s, the sphere circles.
void animate(const Scene& s, uint64_t step, float dt) {
    const float t = float(double(step) * dt);
    const float a = 0.7f * t;
    const float pos[3] = {0.25f + 0.12f * std::cos(a), 0.42f, 0.25f + 0.12f * std::sin(a)};
    const float dir[3] = {0.2f * std::sin(1.3f * t), -1.0f, 0.2f * std::cos(1.1f * t)};
    CALL(pbf_emitter_set_nozzle(s.world, s.nozzle, pos, dir));
    const uint64_t cycle = step % 300;  // 5 s at 60 Hz
    if (cycle == 0) CALL(pbf_emitter_set_enabled(s.world, s.nozzle, 1));
    if (cycle == 180) CALL(pbf_emitter_set_enabled(s.world, s.nozzle, 0));
    const float b = 1.9f * t;
    const float sp[3] = {0.25f + 0.1f * std::cos(b), 0.1f, 0.25f + 0.1f * std::sin(b)};
    const float q[4] = {0.0f, std::sin(0.5f * b), 0.0f, std::cos(0.5f * b)};
    CALL(pbf_collider_set_target_pose(s.world, s.stirrer, sp, q));
}

struct Buffers {
    std::vector<float> pos, vel;
    std::vector<uint32_t> ids, sorted;
};

// Every check on the world's state; returns the particle count.
uint32_t check(const Scene& s, Buffers& b, uint64_t step) {
    pbf_step_stats st;
    std::memset(&st, 0, sizeof st);
    st.struct_size = sizeof st;
    CALL(pbf_world_get_stats(s.world, &st));
    uint32_t count = 0;
    CALL(pbf_world_get_particle_count(s.world, &count));
    char where[64];
    std::snprintf(where, sizeof where, "step %llu: ", static_cast<unsigned long long>(step));
    if (st.step_index != step) die(std::string(where) + "step_index " + std::to_string(st.step_index));
    if (st.particle_count != count) die(std::string(where) + "stats count differs from pbf_world_get_particle_count");
    if (count > s.desc.max_particles) die(std::string(where) + "count above capacity");
    if (st.emitted_total < st.drained_total || st.emitted_total - st.drained_total != count)
        die(std::string(where) + "accounting: emitted " + std::to_string(st.emitted_total) + " - drained " +
            std::to_string(st.drained_total) + " != count " + std::to_string(count));
    if (!std::isfinite(st.kinetic_energy) || !std::isfinite(st.density_error_max))
        die(std::string(where) + "non-finite stats");

    b.pos.resize(size_t(count) * 4);
    b.vel.resize(size_t(count) * 4);
    b.ids.resize(count);
    uint32_t written = 0;
    CALL(pbf_world_copy_positions(s.world, b.pos.data(), count, &written));
    if (written != count) die(std::string(where) + "copy_positions wrote " + std::to_string(written));
    CALL(pbf_world_copy_velocities(s.world, b.vel.data(), count, &written));
    if (written != count) die(std::string(where) + "copy_velocities wrote " + std::to_string(written));
    CALL(pbf_world_copy_ids(s.world, b.ids.data(), count, &written));
    if (written != count) die(std::string(where) + "copy_ids wrote " + std::to_string(written));
    for (uint32_t i = 0; i < count; ++i) {
        for (int k = 0; k < 4; ++k) {
            if (!std::isfinite(b.pos[4 * size_t(i) + k])) die(std::string(where) + "non-finite position");
            if (!std::isfinite(b.vel[4 * size_t(i) + k])) die(std::string(where) + "non-finite velocity");
        }
        for (int a = 0; a < 3; ++a) {
            const float x = b.pos[4 * size_t(i) + a];
            if (x < s.desc.domain_min[a] - 1e-5f || x > s.desc.domain_max[a] + 1e-5f)
                die(std::string(where) + "particle outside the domain");
        }
    }
    b.sorted = b.ids;
    std::sort(b.sorted.begin(), b.sorted.end());
    if (std::adjacent_find(b.sorted.begin(), b.sorted.end()) != b.sorted.end())
        die(std::string(where) + "duplicate particle ids");
    if (count && b.sorted.back() >= st.emitted_total) die(std::string(where) + "id beyond emitted_total");
    return count;
}

}  // namespace

int main(int argc, char** argv) {
    const Options o = parse(argc, argv);
    const float dt = 1.0f / 60.0f;
    Scene s = build(o);
    pbf_world_info info;
    std::memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    CALL(pbf_world_get_info(s.world, &info));
    std::printf(
        "pbf_soak: %llu steps, check every %llu, capacity %u, %u grid cells, %s, warm-up %llu steps, "
        "RSS slack %llu KiB\n",
        static_cast<unsigned long long>(o.steps), static_cast<unsigned long long>(o.check_every), o.capacity,
        info.grid_cells, info.device_name, static_cast<unsigned long long>(o.warmup),
        static_cast<unsigned long long>(o.rss_slack_kb));
    std::fflush(stdout);

    Buffers buffers;
    uint64_t rss_base = 0, rss_max = 0, checks = 0;
    uint32_t count_min = UINT32_MAX, count_max = 0, full_checks = 0;
    const auto t0 = std::chrono::steady_clock::now();
    auto last_report = t0;
    for (uint64_t step = 1; step <= o.steps; ++step) {
        animate(s, step, dt);
        CALL(pbf_world_step(s.world, dt));
        if (step % o.check_every != 0 && step != o.steps) continue;
        const uint32_t n = check(s, buffers, step);
        ++checks;
        if (step >= o.warmup) {
            count_min = std::min(count_min, n);
            count_max = std::max(count_max, n);
            if (n == o.capacity) ++full_checks;
        }
        const uint64_t rss = rss_kb();
        if (rss && step >= o.warmup) {
            if (rss_base == 0) rss_base = rss;
            rss_max = std::max(rss_max, rss);
            if (rss > rss_base + o.rss_slack_kb)
                die("step " + std::to_string(step) + ": resident memory grew from " + std::to_string(rss_base) +
                    " KiB (end of warm-up) to " + std::to_string(rss) + " KiB");
        }
        const auto now = std::chrono::steady_clock::now();
        if (!o.quiet && std::chrono::duration<double>(now - last_report).count() >= 10.0) {
            last_report = now;
            const double secs = std::chrono::duration<double>(now - t0).count();
            std::printf("  step %llu: %u particles, %.0f steps/s, RSS %llu KiB\n",
                        static_cast<unsigned long long>(step), n, double(step) / secs,
                        static_cast<unsigned long long>(rss));
            std::fflush(stdout);
        }
    }
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    pbf_step_stats st;
    std::memset(&st, 0, sizeof st);
    st.struct_size = sizeof st;
    CALL(pbf_world_get_stats(s.world, &st));
    CALL(pbf_world_destroy(s.world));
    std::printf(
        "pbf_soak: OK: %llu steps in %.1f s (%.0f steps/s), %llu checks; particles %u..%u after warm-up "
        "(at capacity in %u checks); emitted %llu, drained %llu; RSS %llu KiB at warm-up end, max %llu KiB\n",
        static_cast<unsigned long long>(o.steps), secs, double(o.steps) / secs, static_cast<unsigned long long>(checks),
        count_min == UINT32_MAX ? 0 : count_min, count_max, full_checks,
        static_cast<unsigned long long>(st.emitted_total), static_cast<unsigned long long>(st.drained_total),
        static_cast<unsigned long long>(rss_base), static_cast<unsigned long long>(rss_max));
    return 0;
}
