// The frame benchmark's verdict rules (samples/common/frame_run.h) on the CPU cut of its scenes:
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
    INFO("verdict " << r.verdict << ": max (KE + dPE) / Mga " << r.max_energy_gain << ", vmax " << r.vmax
                    << " m/s (" << r.vmax_ratio << " x sqrt(2 g 2a)), error mean " << r.err_mean << " max "
                    << r.err_max << ", KE_end " << r.ke_end << " Mga, vmax_end " << r.vmax_end << " m/s, substeps "
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
