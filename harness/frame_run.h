// The frame benchmark's runs (tools/frames/pbf_frames.cpp) and the CPU verdict tests
// (tests/test_frames.cpp), through the public C API only: one scene stepped at 1/60 s frames
// for a simulated time, and its verdict by fixed rules.
#pragma once
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "paper_scene.h"
#include "pbf_c_api.h"
#include "tool_support.h"

namespace frames {

struct FrameCase {
    paper::SceneSpec scene;
    uint32_t substeps = 0;  // 0: automatic
    uint32_t max_substeps = 16;
    uint32_t iterations = 2;
    bool ldc = true;
    int frames = 120;  // 2 s at 60 Hz
    float frame_dt = 1.0f / 60.0f;
    double wall_budget_s = 1e9;    // a run past it stops (as unstable: it is crawling)
    float scorr_k = -1.0f;         // < 0: the library's default
    float relaxation = -1.0f;      // < 0: the library's default
    float substep_travel = -1.0f;  // < 0: the library's default (automatic substeps)
    float sound_speed = -1.0f;     // < 0: the library's default
};

struct FrameResult {
    std::string verdict;  // "ok", or why not
    bool ok = false;
    int frames_run = 0;
    uint32_t particles = 0;
    double ms_per_frame = 0.0;  // the backend's step time summed over a frame, mean over frames
    double substeps_mean = 0.0;
    uint32_t substeps_max = 0;
    double max_energy_gain = 0.0;  // max over frames of (KE + ΔPE) / (M g a)
    double vmax = 0.0;             // fastest particle over the run (m/s)
    double vmax_ratio = 0.0;       // over sqrt(2 g · 2a), the free-fall speed of the column's top
    double err_mean = 0.0;         // mean over frames of the mean compressive density error
    double err_max = 0.0;          // max over frames of the max
    double ke_end = 0.0;           // KE / (M g a) at the end
    double vmax_end = 0.0;
    double clamp_fraction = 0.0;  // speed-limited particle-substeps over all particle-substeps
    double wall_s = 0.0;
    std::string device;
};

// The rules (the same for every backend and size): unstable if anything is non-finite, the
// max density error exceeds 3, or KE + ΔPE ever exceeds 0.05 M g a (energy from nowhere); a run
// whose speed limits cut more than 0.1 % of particle-substeps is "clamped" (the step was too
// coarse for its motion and the limit slowed the fluid); the tank must end at rest (KE < 1e-3
// M g a and no particle faster than 0.5 m/s).
inline FrameResult run_frames(const FrameCase& fc) {
    FrameResult r;
    const auto wall0 = std::chrono::steady_clock::now();
    pbf_world_desc d = paper::make_desc(fc.scene);
    d.solver.iterations = fc.iterations;
    d.solver.ldc_enabled = fc.ldc ? 1u : 0u;
    d.solver.substeps = fc.substeps;
    d.solver.max_substeps = fc.max_substeps;
    if (fc.scorr_k >= 0.0f) d.solver.scorr_k = fc.scorr_k;
    if (fc.relaxation > 0.0f) d.solver.relaxation = fc.relaxation;
    if (fc.substep_travel > 0.0f) d.solver.substep_travel = fc.substep_travel;
    if (fc.sound_speed > 0.0f) d.solver.sound_speed = fc.sound_speed;
    pbf_world_id w;
    if (pbf_world_create(&d, &w) != PBF_OK) {
        r.verdict = std::string("create failed: ") + pbf_last_error_message();
        return r;
    }
    pbf_world_info info;
    tool::read_info(w, &info);
    r.device = info.device_name;
    uint32_t n = 0;
    if (paper::emit_fluid(w, fc.scene, &n) != PBF_OK) {
        r.verdict = std::string("emit failed: ") + pbf_last_error_message();
        pbf_world_destroy(w);
        return r;
    }
    r.particles = n;
    const double mass = double(info.particle_mass) * n;
    const double mga = mass * paper::kGravity * fc.scene.a;
    const double v_ref = std::sqrt(2.0 * paper::kGravity * 2.0 * fc.scene.a);
    std::vector<float> x(size_t(n) * 4), v(size_t(n) * 4);
    double pe0 = 0.0, ms_total = 0.0, substeps_total = 0.0, clamps = 0.0, particle_substeps = 0.0;
    std::string failure;
    for (int f = 0; f <= fc.frames && failure.empty(); ++f) {
        if (f > 0 && pbf_world_step(w, fc.frame_dt) != PBF_OK) {
            failure = std::string("step failed: ") + pbf_last_error_message();
            break;
        }
        pbf_step_stats st;
        std::memset(&st, 0, sizeof st);
        st.struct_size = sizeof st;
        pbf_world_get_stats(w, &st);
        uint32_t count = 0, written = 0;
        pbf_world_get_particle_count(w, &count);
        count = std::min(count, n);
        pbf_world_copy_positions(w, x.data(), count, &written);
        pbf_world_copy_velocities(w, v.data(), count, &written);
        double pe = 0.0, vmax = 0.0;
        bool finite = std::isfinite(st.kinetic_energy) && std::isfinite(st.density_error_max);
        for (uint32_t i = 0; i < count; ++i) {
            pe += double(info.particle_mass) * paper::kGravity * x[4 * i + 1];
            const double s2 =
                double(v[4 * i]) * v[4 * i] + double(v[4 * i + 1]) * v[4 * i + 1] + double(v[4 * i + 2]) * v[4 * i + 2];
            vmax = std::max(vmax, std::sqrt(s2));
            finite = finite && std::isfinite(x[4 * i]) && std::isfinite(x[4 * i + 1]) && std::isfinite(x[4 * i + 2]);
        }
        if (f == 0) {
            pe0 = pe;
            continue;
        }
        r.frames_run = f;
        ms_total += st.step_time_ms;
        substeps_total += st.substeps;
        r.substeps_max = std::max(r.substeps_max, st.substeps);
        clamps += st.speed_clamps;
        particle_substeps += double(count) * st.substeps;
        r.err_mean += st.density_error_mean;
        r.err_max = std::max(r.err_max, double(st.density_error_max));
        r.vmax = std::max(r.vmax, vmax);
        r.max_energy_gain = std::max(r.max_energy_gain, (st.kinetic_energy + pe - pe0) / mga);
        r.ke_end = st.kinetic_energy / mga;
        r.vmax_end = vmax;
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
        if (!finite)
            failure = "non-finite @frame " + std::to_string(f);
        else if (st.density_error_max > 3.0f)
            failure = "errmax>3 @frame " + std::to_string(f);
        else if ((st.kinetic_energy + pe - pe0) / mga > 0.05)
            failure = "energy gain @frame " + std::to_string(f);
        else if (wall > fc.wall_budget_s)
            failure = "wall time @frame " + std::to_string(f);
    }
    pbf_world_destroy(w);
    const int frames = std::max(1, r.frames_run);
    r.ms_per_frame = ms_total / frames;
    r.substeps_mean = substeps_total / frames;
    r.err_mean /= frames;
    r.vmax_ratio = r.vmax / v_ref;
    r.clamp_fraction = particle_substeps > 0.0 ? clamps / particle_substeps : 0.0;
    r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (!failure.empty())
        r.verdict = "unstable (" + failure + ")";
    else if (r.clamp_fraction > 1e-3)
        r.verdict = "clamped";
    else if (!fc.scene.dam && !(r.ke_end < 1e-3 && r.vmax_end < 0.5))
        r.verdict = "not at rest";
    else
        r.verdict = "ok";
    r.ok = r.verdict == "ok";
    return r;
}

}  // namespace frames
