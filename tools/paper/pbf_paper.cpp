// pbf_paper: the runs behind docs/paper/README.md (the LDC reproduction), public C API only.
//
//   pbf_paper run    [scene options] [solver options] --frames N --csv FILE
//                    [--snap-times 0.25,0.5,1.0 --snap-prefix PATH] [--per-substep 1]
//       One simulation. Writes one CSV row per 1/60 s frame (or per substep with --per-substep 1,
//       which drives the world with dt = frame/S and one substep per call: the same physics):
//       time, compressive density error (mean, max), kinetic and potential energy, the
//       dam-break front, the step time (the backend's, and the host's wall time of the step
//       call plus the stats read that waits for it), the constraint iterations the step ran
//       (all its substeps) and per substep, the substeps the step ran, the particle-substeps a
//       speed limit cut, and the backend. --snap-times writes x,y,z,w (w = ρ/ρ0) of every
//       particle at those times (seconds) to PATH_t<time>.csv for the splat renders.
//   pbf_paper timing [scene options] --iterations 1,2,...,6 --ldc 0,1 [--gain 0.1]
//                    [--adaptive-target 0,0.01,...] [--steps 100 --warmup 20] --csv FILE
//       Time per step against iterations, on a 3D column a × 2a × a/2 (as pbf_bench's dam):
//       --particles N picks na = cbrt(N). One substep per step, dt keeps the front under 0.4 h.
//       The LDC-off and LDC-on worlds of one iteration count are stepped alternately. With
//       --adaptive-target, every listed target (0: fixed iterations) is timed with every
//       iteration count as the cap; the CSV adds the iterations run per step (mean, max).
//
// Scene options: --scene dam|tank  --a METRES (0.4)  --na N (32, particles across a)
//                --nz N (6, layers in z)  --length L (5, dam tank length in a)
//                --backend cpu|cuda (cpu)  --particles N (timing only)
// Solver options: --iterations N (4)  --ldc 0|1 (1)  --gain G (K·Δt²; default 0.1, the library's
//                default when the report's runs were made, kept so they rerun alike; the
//                library's is 0.3 now)  --substeps S (0: the CFL-like rule of
//                samples/dam_break.c; auto: the library's automatic substeps, README
//                Physics, capped by --max-substeps, library default 16)  --frame-dt DT (1/60)
//                --adaptive-target ETA (0: off; > 0: iterate until the mean compressive
//                density error is below ETA, with --iterations as the cap)
//                Diagnostics (library defaults otherwise): --relaxation E --scorr-k K --xsph C
//                --vorticity EPS
//
// `pbf_paper run --help` and `pbf_paper timing --help` list the options with their defaults.
// Exit status: 0 ok, 1 a libpbf error, 2 bad arguments. A run that diverges (non-finite
// energy) still writes its rows and exits 0 with "diverged" on stdout: divergence is a result.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "paper_scene.h"
#include "tool_support.h"

namespace {

using paper::SceneSpec;

struct Args {
    std::map<std::string, std::string> kv;
    std::string get(const std::string& k, const std::string& def) const {
        auto it = kv.find(k);
        return it == kv.end() ? def : it->second;
    }
    double num(const std::string& k, double def) const {
        auto it = kv.find(k);
        return it == kv.end() ? def : std::atof(it->second.c_str());
    }
};

using tool::split_list;

bool check(pbf_result r, const char* what) {
    if (r == PBF_OK) return true;
    std::fprintf(stderr, "pbf_paper: %s failed: %s (%s)\n", what, pbf_result_string(r), pbf_last_error_message());
    return false;
}

SceneSpec scene_from(const Args& a) {
    SceneSpec s;
    s.dam = a.get("--scene", "dam") != "tank";
    s.a = float(a.num("--a", 0.4));
    s.na = uint32_t(a.num("--na", 32));
    s.nz = uint32_t(a.num("--nz", 6));
    s.tank_length = float(a.num("--length", 5.0));
    s.backend = a.get("--backend", "cpu") == "cuda" ? PBF_BACKEND_CUDA : PBF_BACKEND_CPU;
    return s;
}

pbf_step_stats read_stats(pbf_world_id w, bool* ok) {
    pbf_step_stats st;
    std::memset(&st, 0, sizeof st);
    st.struct_size = sizeof st;
    *ok = check(pbf_world_get_stats(w, &st), "pbf_world_get_stats");
    return st;
}

int cmd_run(const Args& args) {
    const SceneSpec sc = scene_from(args);
    const float frame_dt = float(args.num("--frame-dt", 1.0 / 60.0));
    const int frames = int(args.num("--frames", 90));
    const bool per_substep = args.num("--per-substep", 0) != 0;
    pbf_world_desc d = paper::make_desc(sc);
    d.solver.iterations = uint32_t(args.num("--iterations", 4));
    d.solver.ldc_enabled = uint32_t(args.num("--ldc", 1));
    d.solver.ldc_gain = float(args.num("--gain", 0.1));
    d.solver.relaxation = float(args.num("--relaxation", d.solver.relaxation));
    d.solver.scorr_k = float(args.num("--scorr-k", d.solver.scorr_k));
    d.solver.xsph_c = float(args.num("--xsph", d.solver.xsph_c));
    d.solver.vorticity_epsilon = float(args.num("--vorticity", d.solver.vorticity_epsilon));
    d.solver.adaptive_error_target = float(args.num("--adaptive-target", 0.0));
    // auto: the library picks S every step (stats report it); the substeps column is then 0.
    const bool auto_substeps = args.get("--substeps", "0") == "auto";
    d.solver.max_substeps = uint32_t(args.num("--max-substeps", d.solver.max_substeps));
    if (auto_substeps && per_substep) {
        std::fprintf(stderr, "pbf_paper: --substeps auto needs whole frames (not --per-substep 1)\n");
        return 2;
    }
    uint32_t substeps = auto_substeps ? 0u : uint32_t(args.num("--substeps", 0));
    if (substeps == 0 && !auto_substeps) substeps = paper::cfl_substeps(sc, frame_dt, !per_substep);
    if (!per_substep && substeps > d.solver.max_substeps) {
        std::fprintf(stderr, "pbf_paper: substeps must be 1..%u (--max-substeps, or use --per-substep 1)\n",
                     d.solver.max_substeps);
        return 2;
    }
    d.solver.substeps = per_substep ? 1u : substeps;
    const float call_dt = per_substep ? frame_dt / float(substeps) : frame_dt;
    const int calls_per_frame = per_substep ? int(substeps) : 1;

    pbf_world_id w;
    if (!check(pbf_world_create(&d, &w), "pbf_world_create")) return 1;
    pbf_world_info info;
    if (!check(tool::read_info(w, &info), "pbf_world_get_info")) return 1;
    uint32_t n = 0;
    if (!check(paper::emit_fluid(w, sc, &n), "emit")) return 1;

    const std::string csv_path = args.get("--csv", "");
    FILE* csv = csv_path.empty() ? stdout : std::fopen(csv_path.c_str(), "w");
    if (!csv) {
        std::fprintf(stderr, "pbf_paper: cannot write %s\n", csv_path.c_str());
        return 1;
    }
    std::vector<double> snap_times;
    for (const std::string& t : split_list(args.get("--snap-times", "")))
        if (!t.empty()) snap_times.push_back(std::atof(t.c_str()));
    const std::string snap_prefix = args.get("--snap-prefix", "");

    const double mass_total = double(info.particle_mass) * n;
    const double energy_scale = mass_total * paper::kGravity * sc.a;    // M g a
    const double time_scale = std::sqrt(2.0 * paper::kGravity / sc.a);  // T = t·sqrt(2g/a)
    std::fprintf(csv,
                 "scene,na,nz,a,particles,substeps,iterations,ldc,gain,step,t,T,density_error_mean,"
                 "density_error_max,kinetic_energy,ke_norm,pe_norm,front,Z,max_speed,step_ms,adaptive_target,"
                 "iterations_used,iterations_per_substep,wall_ms,substeps_used,speed_clamps,backend\n");
    std::printf(
        "run: %s na=%u nz=%u a=%.3f m, %u particles, spacing %.5f m, h %.5f m, %s substeps (%.5f s), "
        "%u iterations%s, LDC %s gain %.3f, adaptive target %g, %s\n",
        sc.dam ? "dam" : "tank", sc.na, sc.nz, sc.a, n, info.rest_spacing, info.kernel_radius,
        auto_substeps ? "auto" : std::to_string(substeps).c_str(), auto_substeps ? 0.0 : frame_dt / substeps,
        d.solver.iterations, d.solver.adaptive_error_target > 0.0f ? " (cap)" : "", d.solver.ldc_enabled ? "on" : "off",
        d.solver.ldc_gain, double(d.solver.adaptive_error_target), info.device_name);

    std::vector<float> xyzw(size_t(d.max_particles) * 4), vel(size_t(d.max_particles) * 4);
    double pe0 = 0.0;
    bool diverged = false;
    double total_ms = 0.0, max_ke_norm = 0.0, total_iterations = 0.0, total_substeps = 0.0;
    size_t next_snap = 0;
    const int total_calls = frames * calls_per_frame;
    for (int k = 0; k <= total_calls; ++k) {
        double step_ms = 0.0, wall_ms = 0.0;
        const auto t0 = std::chrono::steady_clock::now();
        if (k > 0) {
            if (!check(pbf_world_step(w, call_dt), "pbf_world_step")) return 1;
        }
        bool ok = true;
        const pbf_step_stats st = read_stats(w, &ok);  // first: the density pass also sets w
        if (!ok) return 1;
        if (k > 0) {
            step_ms = st.step_time_ms;
            wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        }
        total_ms += step_ms;
        // Iterations the call ran, over its substeps (all zero before the first step).
        const uint32_t iterations_used = k > 0 ? st.iterations : 0u;
        const uint32_t substeps_used = k > 0 ? st.substeps : 0u;
        const double substeps_per_call = std::max(1.0, double(substeps_used));
        total_iterations += iterations_used;
        total_substeps += substeps_used;
        uint32_t count = 0, written = 0;
        if (!check(pbf_world_get_particle_count(w, &count), "count")) return 1;
        if (!check(pbf_world_copy_positions(w, xyzw.data(), count, &written), "copy positions")) return 1;
        if (!check(pbf_world_copy_velocities(w, vel.data(), count, &written), "copy velocities")) return 1;
        double pe = 0.0, vmax = 0.0;
        for (uint32_t i = 0; i < count; ++i) {
            pe += double(info.particle_mass) * paper::kGravity * xyzw[4 * i + 1];
            const double v2 = double(vel[4 * i]) * vel[4 * i] + double(vel[4 * i + 1]) * vel[4 * i + 1] +
                              double(vel[4 * i + 2]) * vel[4 * i + 2];
            vmax = std::max(vmax, std::sqrt(v2));
        }
        if (k == 0) pe0 = pe;
        const double t = double(k) * call_dt;
        const double front = paper::front_position(xyzw.data(), count, info.particle_radius);
        const double ke_norm = st.kinetic_energy / energy_scale;
        max_ke_norm = std::max(max_ke_norm, ke_norm);
        const bool finite = std::isfinite(st.kinetic_energy) && std::isfinite(pe);
        std::fprintf(csv,
                     "%s,%u,%u,%.4f,%u,%u,%u,%u,%.4f,%d,%.6f,%.5f,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.5f,%.5g,%.4f,%g,%u,"
                     "%.4g,%.4f,%u,%u,%s\n",
                     sc.dam ? "dam" : "tank", sc.na, sc.nz, sc.a, count, substeps, d.solver.iterations,
                     d.solver.ldc_enabled, d.solver.ldc_gain, k, t, t * time_scale, st.density_error_mean,
                     st.density_error_max, st.kinetic_energy, ke_norm, (pe - pe0) / energy_scale, front, front / sc.a,
                     vmax, step_ms, double(d.solver.adaptive_error_target), iterations_used,
                     double(iterations_used) / substeps_per_call, wall_ms, substeps_used, k > 0 ? st.speed_clamps : 0u,
                     info.backend == PBF_BACKEND_CUDA ? "cuda" : "cpu");
        // Snapshots at whole frames, the first frame at or after each requested time.
        while (next_snap < snap_times.size() && k % calls_per_frame == 0 &&
               t + 0.25 * frame_dt >= snap_times[next_snap]) {
            if (!snap_prefix.empty()) {
                char name[64];
                std::snprintf(name, sizeof name, "_t%.3f.csv", snap_times[next_snap]);
                FILE* f = std::fopen((snap_prefix + name).c_str(), "w");
                if (f) {
                    std::fprintf(f, "x,y,z,w\n");
                    for (uint32_t i = 0; i < count; ++i)
                        std::fprintf(f, "%.5f,%.5f,%.5f,%.4f\n", xyzw[4 * i], xyzw[4 * i + 1], xyzw[4 * i + 2],
                                     xyzw[4 * i + 3]);
                    std::fclose(f);
                }
            }
            ++next_snap;
        }
        if (!finite) {
            diverged = true;
            break;
        }
    }
    if (csv != stdout) std::fclose(csv);
    std::printf("  %s; max KE/(M g a) %.3f; mean step %.2f ms; %.2f substeps per call; %.2f iterations per substep\n",
                diverged ? "diverged" : "finished", max_ke_norm, total_ms / std::max(1, total_calls),
                total_substeps / double(std::max(1, total_calls)), total_iterations / std::max(1.0, total_substeps));
    return check(pbf_world_destroy(w), "pbf_world_destroy") ? 0 : 1;
}

int cmd_timing(const Args& args) {
    SceneSpec sc = scene_from(args);
    // pbf_bench's dam: a column a × 2a × a/2 in a 4a × 2.5a × a/2 tank; na³ particles.
    if (args.kv.count("--particles")) {
        const double particles = args.num("--particles", 65536);
        sc.na = uint32_t(std::lround(std::cbrt(particles)));
        sc.nz = std::max(1u, sc.na / 2);
        sc.tank_length = 4.0f;
    }
    const int steps = int(args.num("--steps", 100)), warmup = int(args.num("--warmup", 20));
    const float h = 2.0f * sc.spacing();
    const float dt = std::min(1.0f / 60.0f, 0.4f * h / std::sqrt(2.0f * paper::kGravity * 2.0f * sc.a));
    const std::string csv_path = args.get("--csv", "");
    FILE* csv = csv_path.empty() ? stdout : std::fopen(csv_path.c_str(), "w");
    if (!csv) return 1;
    std::fprintf(csv,
                 "backend,device,particles,iterations,ldc,gain,dt,steps,ms_median,ms_p10,ms_p90,ms_mean,"
                 "density_error_mean,adaptive_target,iterations_mean,iterations_max,wall_ms_median\n");
    // For each iteration count, one world per LDC setting, stepped alternately (A B A B ...): on a
    // shared machine, load from other jobs then hits both methods alike and their difference
    // (LDC's cost) stays meaningful.
    // With --adaptive-target, each target (0: fixed) is timed with each iteration count as the cap.
    const std::vector<std::string> ldcs = split_list(args.get("--ldc", "0,1"));
    for (const std::string& target : split_list(args.get("--adaptive-target", "0"))) {
        for (const std::string& it : split_list(args.get("--iterations", "1,2,3,4,5,6"))) {
            struct Entry {
                pbf_world_desc d;
                pbf_world_id w;
                pbf_world_info info;
                uint32_t n = 0;
                std::vector<double> ms, wall;
                double err = 0.0, iters = 0.0;
                uint32_t iters_max = 0;
            };
            std::vector<Entry> worlds(ldcs.size());
            for (size_t k = 0; k < ldcs.size(); ++k) {
                Entry& e = worlds[k];
                e.d = paper::make_desc(sc);
                e.d.solver.iterations = uint32_t(std::atoi(it.c_str()));
                e.d.solver.ldc_enabled = uint32_t(std::atoi(ldcs[k].c_str()));
                e.d.solver.ldc_gain = float(args.num("--gain", 0.1));
                e.d.solver.substeps = 1;
                e.d.solver.adaptive_error_target = float(std::atof(target.c_str()));
                if (!check(pbf_world_create(&e.d, &e.w), "pbf_world_create")) return 1;
                if (!check(tool::read_info(e.w, &e.info), "info")) return 1;
                if (!check(paper::emit_fluid(e.w, sc, &e.n), "emit")) return 1;
            }
            for (int k = 0; k < warmup + steps; ++k)
                for (Entry& e : worlds) {
                    const auto t0 = std::chrono::steady_clock::now();
                    if (!check(pbf_world_step(e.w, dt), "pbf_world_step")) return 1;
                    bool ok = true;
                    const pbf_step_stats st = read_stats(e.w, &ok);  // waits for the step
                    if (!ok) return 1;
                    const double wall =
                        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
                    if (k < warmup) continue;
                    e.ms.push_back(st.step_time_ms);
                    e.wall.push_back(wall);
                    e.err += st.density_error_mean;
                    e.iters += st.iterations;  // one substep per step: iterations per substep
                    e.iters_max = std::max(e.iters_max, st.iterations);
                }
            for (Entry& e : worlds) {
                std::vector<double> sorted = e.ms;
                std::sort(sorted.begin(), sorted.end());
                double mean = 0.0;
                for (double v : e.ms) mean += v;
                mean /= double(e.ms.size());
                auto q = [&](double f) { return sorted[size_t(f * double(sorted.size() - 1))]; };
                std::vector<double> wall = e.wall;
                std::sort(wall.begin(), wall.end());
                std::fprintf(csv, "%s,%s,%u,%u,%u,%.3f,%.6f,%d,%.4f,%.4f,%.4f,%.4f,%.6f,%g,%.4f,%u,%.4f\n",
                             e.info.backend == PBF_BACKEND_CUDA ? "cuda" : "cpu", e.info.device_name, e.n,
                             e.d.solver.iterations, e.d.solver.ldc_enabled, e.d.solver.ldc_gain, dt, steps, q(0.5),
                             q(0.1), q(0.9), mean, e.err / double(steps), double(e.d.solver.adaptive_error_target),
                             e.iters / double(steps), e.iters_max, wall[wall.size() / 2]);
                std::fflush(csv);
                std::printf(
                    "timing: %u particles, %u iterations%s, LDC %u, adaptive target %g: median %.3f ms/step, "
                    "%.2f iterations/step, mean error %.4f\n",
                    e.n, e.d.solver.iterations, e.d.solver.adaptive_error_target > 0.0f ? " (cap)" : "",
                    e.d.solver.ldc_enabled, double(e.d.solver.adaptive_error_target), q(0.5), e.iters / double(steps),
                    e.err / double(steps));
                std::fflush(stdout);
                if (!check(pbf_world_destroy(e.w), "pbf_world_destroy")) return 1;
            }
        }
    }
    if (csv != stdout) std::fclose(csv);
    return 0;
}

// The options of each command. Values are kept as text, as given, and read by cmd_run and
// cmd_timing through Args with their defaults there; `def` is what --help shows.
struct OptionSpec {
    const char* name;
    const char* def;
    const char* help;
    bool number;    // a single number (checked by CLI11); else free text or a comma-separated list
    unsigned cmds;  // 1: run, 2: timing
};
const OptionSpec kOptions[] = {
    {"--scene", "dam", "dam or tank", false, 3},
    {"--a", "0.4", "scale a, metres", true, 3},
    {"--na", "32", "particles across a", true, 3},
    {"--nz", "6", "particle layers in z", true, 3},
    {"--length", "5", "dam tank length, in units of a", true, 3},
    {"--backend", "cpu", "cpu or cuda", false, 3},
    {"--csv", "stdout", "CSV file to write", false, 3},
    {"--gain", "0.1", "LDC gain K*dt^2 (0.1: the library's default when the report's runs were made; it is 0.3 now)",
     true, 3},
    {"--frames", "90", "frames to run", true, 1},
    {"--frame-dt", "1/60", "frame length, seconds", true, 1},
    {"--per-substep", "0", "1: one substep per pbf_world_step call and one CSV row per substep (same physics)", true,
     1},
    {"--iterations", "4", "constraint iterations (the cap with --adaptive-target)", true, 1},
    {"--ldc", "1", "Local Density Calibration: 0 off, 1 on", true, 1},
    {"--substeps", "0",
     "substeps per frame (0: the CFL-like rule of samples/dam_break.c; auto: the library's "
     "automatic substeps)",
     false, 1},
    {"--max-substeps", "library default", "cap of the automatic substeps (and of a fixed count)", true, 1},
    {"--adaptive-target", "0", "0: fixed iterations; > 0: iterate until the mean compressive density error is below it",
     true, 1},
    {"--relaxation", "library default", "diagnostics: constraint relaxation", true, 1},
    {"--scorr-k", "library default", "diagnostics: tensile instability k", true, 1},
    {"--xsph", "library default", "diagnostics: XSPH viscosity c", true, 1},
    {"--vorticity", "library default", "diagnostics: vorticity confinement epsilon", true, 1},
    {"--snap-times", "", "comma-separated times (s) at which to write every particle's x,y,z,w", false, 1},
    {"--snap-prefix", "", "snapshot files: PREFIX_t<time>.csv", false, 1},
    {"--particles", "na^3 of the scene", "particle count: na = cbrt(N), pbf_bench's dam column", true, 2},
    {"--iterations", "1,2,3,4,5,6", "iteration counts (comma-separated; the caps with --adaptive-target)", false, 2},
    {"--ldc", "0,1", "LDC settings, stepped alternately (comma-separated)", false, 2},
    {"--adaptive-target", "0", "adaptive targets (comma-separated; 0: fixed iterations)", false, 2},
    {"--steps", "100", "timed steps", true, 2},
    {"--warmup", "20", "untimed steps before them", true, 2},
};

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{
        "pbf_paper: the runs behind docs/paper/README.md (the LDC reproduction), public C API only. "
        "Exit status: 0 ok, 1 a libpbf error, 2 bad arguments.",
        "pbf_paper"};
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.require_subcommand(1);
    app.footer("Run `pbf_paper run --help` or `pbf_paper timing --help` for the options of each command.");
    CLI::App* run = app.add_subcommand("run", "one simulation: one CSV row per frame (or per substep)");
    CLI::App* timing =
        app.add_subcommand("timing", "time per step against iterations, LDC off and on stepped alternately");
    std::map<std::string, std::string> run_values, timing_values;
    CLI::Validator number = CLI::Number;
    number.description("");  // the type X says enough in --help
    for (const OptionSpec& o : kOptions) {
        for (unsigned bit = 1; bit <= 2; ++bit) {
            if (!(o.cmds & bit)) continue;
            CLI::App* cmd = bit == 1 ? run : timing;
            std::string& value = (bit == 1 ? run_values : timing_values)[o.name];
            CLI::Option* opt = cmd->add_option(o.name, value, o.help);
            if (*o.def) opt->default_str(o.def);
            if (o.number) opt->check(number)->type_name("X");
            if (std::string(o.name) == "--scene") opt->check(CLI::IsMember({"dam", "tank"}));
            if (std::string(o.name) == "--backend") opt->check(CLI::IsMember({"cpu", "cuda"}));
            if (std::string(o.name) == "--substeps") opt->check(CLI::NonNegativeNumber | CLI::IsMember({"auto"}));
        }
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;
    }
    Args args;
    CLI::App* cmd = run->parsed() ? run : timing;
    for (const auto& [name, value] : cmd == run ? run_values : timing_values)
        if (cmd->count(name)) args.kv[name] = value;
    return cmd == run ? cmd_run(args) : cmd_timing(args);
}
