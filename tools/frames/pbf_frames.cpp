// pbf_frames: the frame benchmark. What one 1/60 s frame costs and whether the solver holds,
// over a matrix of scenes, sizes, substeps, iterations and LDC on/off; the verdict rules are in
// frame_run.h. Public C API only.
//
//   pbf_frames matrix --backend cuda --csv docs/perf/h100_frames.csv
//   pbf_frames run --scene dam --scale game --particles 262144 --substeps auto --iterations 2 --ldc 1
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "frame_run.h"

namespace {

// Scene sizes. fine: a = 0.4 m, na = cbrt(N) particles across a, nz = na/2 layers (262,144 =
// 64 x 32; 1M = 100 x 50; h = 0.8 a / na). game: the library's default particle radius
// (2.5 cm): a = 1.6 m, na = 32, nz = N / 2048 (262,144: nz = 128).
paper::SceneSpec scene_for(const std::string& scene, const std::string& scale, uint32_t particles, uint32_t na,
                           uint32_t nz, pbf_backend backend) {
    paper::SceneSpec s;
    s.dam = scene != "tank";
    s.tank_length = 4.0f;
    s.backend = backend;
    if (scale == "game") {
        s.a = 1.6f;
        s.na = 32;
        s.nz = std::max(1u, particles / 2048u);
    } else {
        s.a = 0.4f;
        s.na = uint32_t(std::lround(std::cbrt(double(particles))));
        s.nz = std::max(1u, s.na / 2);
    }
    if (na) s.na = na;
    if (nz) s.nz = nz;
    return s;
}

uint32_t parse_substeps(const std::string& s) { return s == "auto" ? 0u : uint32_t(std::stoul(s)); }

void print_header(FILE* f) {
    std::fprintf(f,
                 "scene,scale,particles,substeps,iterations,ldc,verdict,ms_per_frame,device,substeps_mean,"
                 "substeps_max,frames_run,max_energy_gain,vmax,vmax_ratio,err_mean,err_max,ke_end,vmax_end,"
                 "clamp_fraction,wall_s\n");
}

void print_row(FILE* f, const std::string& scene, const std::string& scale, const frames::FrameCase& c,
               const frames::FrameResult& r) {
    std::fprintf(f, "%s,%s,%u,%s,%u,%u,%s,%.3f,%s,%.2f,%u,%d,%.4f,%.3f,%.3f,%.5f,%.4f,%.2e,%.3f,%.2e,%.1f\n",
                 scene.c_str(), scale.c_str(), r.particles, c.substeps ? std::to_string(c.substeps).c_str() : "auto",
                 c.iterations, c.ldc ? 1u : 0u, r.verdict.c_str(), r.ms_per_frame, r.device.c_str(), r.substeps_mean,
                 r.substeps_max, r.frames_run, r.max_energy_gain, r.vmax, r.vmax_ratio, r.err_mean, r.err_max, r.ke_end,
                 r.vmax_end, r.clamp_fraction, r.wall_s);
    std::fflush(f);
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"pbf_frames: the frame benchmark (1/60 s frames, verdict per run)"};
    app.require_subcommand(1);
    std::string backend_name = "cpu", csv_path;
    int frames = 120;
    uint32_t na = 0, nz = 0, max_substeps = 16;
    double budget = 60.0;
    float tank_width = 2.0f;
    float scorr_k = -1.0f, relaxation = -1.0f, travel = -1.0f, sound_speed = -1.0f;

    auto* run = app.add_subcommand("run", "one run; prints its CSV row");
    std::string scene = "dam", scale = "fine", substeps = "auto";
    uint32_t particles = 262144, iterations = 2, ldc = 1;
    run->add_option("--scene", scene, "dam or tank")->check(CLI::IsMember({"dam", "tank"}));
    run->add_option("--scale", scale, "fine or game")->check(CLI::IsMember({"fine", "game"}));
    run->add_option("--particles", particles, "particle count (sets na, nz)");
    run->add_option("--substeps", substeps, "substeps per frame, or auto");
    run->add_option("--iterations", iterations, "constraint iterations per substep");
    run->add_option("--ldc", ldc, "Local Density Calibration 0/1");

    auto* matrix = app.add_subcommand("matrix", "the benchmark matrix; one CSV row per run, then the cheapest ok");
    std::vector<std::string> scales{"fine:262144", "fine:1000000", "game:262144"};
    std::vector<std::string> substep_list{"1", "2", "3", "4", "7", "auto"};
    std::vector<uint32_t> iteration_list{1, 2, 3, 4}, ldc_list{0, 1};
    matrix->add_option("--sizes", scales, "scale:particles entries")->delimiter(',');
    matrix->add_option("--substeps", substep_list, "substep settings")->delimiter(',');
    matrix->add_option("--iterations", iteration_list, "iteration counts")->delimiter(',');
    matrix->add_option("--ldc", ldc_list, "LDC settings")->delimiter(',');

    for (CLI::App* sub : {run, matrix}) {
        sub->add_option("--backend", backend_name, "cpu or cuda")->check(CLI::IsMember({"cpu", "cuda"}));
        sub->add_option("--frames", frames, "1/60 s frames per run (120 = 2 s)");
        sub->add_option("--na", na, "override: particles across a");
        sub->add_option("--nz", nz, "override: layers in z");
        sub->add_option("--tank-width", tank_width,
                        "tank: its length in x in units of a (default 2; small: a deep column)");
        sub->add_option("--max-substeps", max_substeps, "cap of automatic substeps");
        sub->add_option("--budget-s", budget, "wall-clock seconds per run before it counts as unstable");
        sub->add_option("--csv", csv_path, "CSV output (default stdout)");
        sub->add_option("--scorr-k", scorr_k, "diagnostic: s_corr k (default: the library's)");
        sub->add_option("--relaxation", relaxation, "diagnostic: relaxation (default: the library's)");
        sub->add_option("--sound-speed", sound_speed,
                        "diagnostic: the error response speed, m/s (default: the library's)");
        sub->add_option("--travel", travel, "automatic substeps' travel per substep in h (default: the library's)");
    }
    CLI11_PARSE(app, argc, argv);

    const pbf_backend backend = backend_name == "cuda" ? PBF_BACKEND_CUDA : PBF_BACKEND_CPU;
    FILE* csv = csv_path.empty() ? stdout : std::fopen(csv_path.c_str(), "w");
    if (!csv) {
        std::fprintf(stderr, "pbf_frames: cannot write %s\n", csv_path.c_str());
        return 1;
    }
    print_header(csv);
    auto make_case = [&](const std::string& sc, const std::string& sl, uint32_t n, const std::string& s, uint32_t it,
                         uint32_t l) {
        frames::FrameCase c;
        c.scene = scene_for(sc, sl, n, na, nz, backend);
        c.scene.tank_width = tank_width;
        c.substeps = parse_substeps(s);
        c.max_substeps = max_substeps;
        c.iterations = it;
        c.ldc = l != 0;
        c.frames = frames;
        c.wall_budget_s = budget;
        c.scorr_k = scorr_k;
        c.relaxation = relaxation;
        c.substep_travel = travel;
        c.sound_speed = sound_speed;
        return c;
    };
    if (run->parsed()) {
        const frames::FrameCase c = make_case(scene, scale, particles, substeps, iterations, ldc);
        print_row(csv, scene, scale, c, frames::run_frames(c));
    } else {
        // Per scale and size: the cheapest setting that is ok in both scenes (cost: the dearer
        // of the two).
        struct Best {
            double ms = 1e30;
            std::string setting;
        };
        std::map<std::string, Best> best;
        for (const std::string& entry : scales) {
            const size_t colon = entry.find(':');
            const std::string sl = entry.substr(0, colon);
            const uint32_t n = uint32_t(std::stoul(entry.substr(colon + 1)));
            for (uint32_t l : ldc_list)
                for (uint32_t it : iteration_list)
                    for (const std::string& s : substep_list) {
                        frames::FrameResult res[2];
                        const char* names[2] = {"dam", "tank"};
                        for (int k = 0; k < 2; ++k) {
                            const frames::FrameCase c = make_case(names[k], sl, n, s, it, l);
                            res[k] = frames::run_frames(c);
                            print_row(csv, names[k], sl, c, res[k]);
                            std::fprintf(stderr, "%s %s %u S=%s it=%u ldc=%u: %s, %.3f ms/frame\n", names[k],
                                         sl.c_str(), res[k].particles, s.c_str(), it, l, res[k].verdict.c_str(),
                                         res[k].ms_per_frame);
                        }
                        if (res[0].ok && res[1].ok) {
                            const double ms = std::max(res[0].ms_per_frame, res[1].ms_per_frame);
                            Best& b = best[entry];
                            if (ms < b.ms)
                                b = Best{ms, "S=" + s + " it=" + std::to_string(it) + " ldc=" + std::to_string(l)};
                        }
                    }
        }
        for (const auto& [entry, b] : best)
            std::fprintf(stderr, "cheapest ok (dam and tank) %s: %s, %.3f ms/frame\n", entry.c_str(), b.setting.c_str(),
                         b.ms);
    }
    if (csv != stdout) std::fclose(csv);
    return 0;
}
