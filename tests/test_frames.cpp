// The frame benchmark's verdict rules (harness/frame_run.h) on the CPU cut of its scenes:
// the dam break and the resting tank of the frame matrix at ~12k particles (32 particles
// across a = 0.4 m, 6 layers deep: h = 25 mm), 2 s of 1/60 s frames. These are the settings that
// must hold; docs/perf.md ("Frames") has the whole matrix on the GPU.
#include <catch2/catch.hpp>

#include "frame_run.h"

namespace {

frames::FrameResult run_cut(bool dam, uint32_t substeps, uint32_t iterations, bool ldc) {
    frames::FrameCase c;
    c.scene.dam = dam;
    c.scene.a = 0.4f;
    c.scene.na = 32;
    c.scene.nz = 6;
    c.scene.tank_length = 4.0f;
    c.scene.backend = PBF_BACKEND_CPU;
    c.substeps = substeps;
    c.iterations = iterations;
    c.ldc = ldc;
    return frames::run_frames(c);
}

void check_ok(const frames::FrameResult& r) {
    INFO("verdict " << r.verdict << ": max (KE + dPE) / Mga " << r.max_energy_gain << ", vmax " << r.vmax << " m/s ("
                    << r.vmax_ratio << " x sqrt(2 g 2a)), error mean " << r.err_mean << " max " << r.err_max
                    << ", KE_end " << r.ke_end << " Mga, vmax_end " << r.vmax_end << " m/s, substeps "
                    << r.substeps_mean << " (max " << r.substeps_max << "), clamped " << r.clamp_fraction);
    CHECK(r.particles == 2u * 32u * 32u * 6u);
    CHECK(r.frames_run == 120);
    CHECK(r.verdict == "ok");
}

}  // namespace

TEST_CASE("frames: the defaults (automatic substeps, 4 iterations, LDC) hold the dam break at 60 Hz",
          "[frames][realtime]") {
    check_ok(run_cut(true, 0, 4, true));
}

TEST_CASE("frames: the defaults hold the resting tank at 60 Hz and it ends at rest", "[frames][realtime]") {
    check_ok(run_cut(false, 0, 4, true));
}

TEST_CASE("frames: conventional PBF (LDC off), 2 iterations, automatic substeps holds the dam break",
          "[frames][realtime]") {
    check_ok(run_cut(true, 0, 2, false));
}

TEST_CASE("frames: conventional PBF (LDC off), 4 iterations, automatic substeps holds the resting tank",
          "[frames][realtime]") {
    check_ok(run_cut(false, 0, 4, false));
}

TEST_CASE("frames: LDC with 2 iterations, automatic substeps holds the dam break", "[frames][realtime]") {
    check_ok(run_cut(true, 0, 2, true));
}

// The 1M tank's depth (a = 0.4 m, 100 layers, h = 8 mm) in a narrow column, 12 x 100 x 4
// particles: the tank at that resolution, whose first rebound gained energy (KE + ΔPE up to
// 0.2 M g a at frame 10) before the automatic substeps had a depth rule (docs/perf.md, Frames).
TEST_CASE("frames: the defaults hold a resting column 100 layers deep at 60 Hz and it ends at rest",
          "[frames][realtime]") {
    frames::FrameCase c;
    c.scene.dam = false;
    c.scene.a = 0.4f;
    c.scene.na = 100;
    c.scene.nz = 4;
    c.scene.tank_width = 0.12f;  // 12 particles across
    c.scene.backend = PBF_BACKEND_CPU;
    c.substeps = 0;
    c.iterations = 4;
    c.ldc = true;
    const frames::FrameResult r = frames::run_frames(c);
    INFO("verdict " << r.verdict << ": max (KE + dPE) / Mga " << r.max_energy_gain << ", error mean " << r.err_mean
                    << " max " << r.err_max << ", KE_end " << r.ke_end << " Mga, vmax_end " << r.vmax_end
                    << " m/s, substeps " << r.substeps_mean << " (max " << r.substeps_max << ")");
    CHECK(r.particles == 12u * 100u * 4u);
    CHECK(r.frames_run == 120);
    CHECK(r.verdict == "ok");
}
