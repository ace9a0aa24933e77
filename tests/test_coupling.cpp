// Two-way coupling on the CPU backend (issue 13): the fluid's force on dynamic colliders, read
// through pbf_collider_get_force, against Archimedes, floating and sinking boxes, and the
// momentum a paddle gives the water. The scenes and checks are in coupling_scenes.h ([gpu]
// twins in test_gpu_coupling.cpp).
//
// Known failures, tagged [!shouldfail] (they pass while the bound fails; remove the tag when the
// physics meets it), with the box 6 particle diameters across. Both errors shrink with the
// particle size; the "resolved" cases at the end (12 diameters, density held within 0.3 %) pass:
// Archimedes 1.03 ρ0gV, floating 0.49 (README, Physics, Two-way coupling, has the table from 6
// to 24 diameters). Measured on this branch, CPU backend, defaults (LDC on, its boundary part's
// reaction given to the colliders: passes.h record_ldc_reaction); the CPU runs are chaotic, so
// repeated runs of the floating scene spread by about ±0.005:
// - Archimedes: 140.0 N for rho g V = 135.6 N (1.032, within 5 %; a white-box run of the same
//   scene: 1.031 with LDC, 0.986 without), but the largest |torque| over the last second is
//   0.50 N m for a bound of 0.163, and the torque's mean over that second is 0.20 N m with LDC,
//   0.18 without, 0.31 with vorticity confinement off (with a mean sideways force of 1-3 N): not
//   only step-to-step noise, so the statistic is kept. It is torque about the vertical axis
//   (tau_y 0.2-0.6 N m, decaying slowly over 6 s; 0.12-0.29 with vorticity confinement off,
//   0.23-0.27 with XSPH, and so the boundary viscosity, off), while the water has no net swirl
//   (its angular momentum about the box's axis over its sum of m r^2 stays within +-0.002 rad/s)
//   and jitters at a v_rms of 2 cm/s: normal forces of a stress the particle packing holds, not
//   a circulation (white-box runs, 1 thread).
// - Floating at 500 kg/m3: submerged fraction 0.462-0.468 (before the box edge term,
//   collide.h box_boundary: 0.464-0.472; the term fixed the share beyond the bottom edges,
//   which had pushed the water off them: held still at half depth without LDC the box felt
//   1.071 rho g V_sub before it, 0.994 after). Two causes remain, measured with the box held
//   still or released from inside the water instead of dropped:
//   * LDC: a box emitted in place at half depth and released floats 0.504 submerged without LDC
//     but 0.459-0.462 with it (1-thread white-box runs; 0.481 at half LDC's gain: the error scales
//     with it). Not LDC's reaction: with LDC the box and a floor collider carry 1.0056 of the
//     water's weight, the excess being LDC's unreacted own parts at the free surface and static
//     walls (< 1 N of them next to the box), and the surface level does not move (0.3557 m with
//     LDC, 0.3546 without). It is the boundary's pressure: Eq. 1 over fluid neighbours alone makes
//     a boundary mirror each particle's P, and the position solve leaves the layer under a box's
//     bottom ~0.13 % denser than the water at its depth and the layer on its top ~0.12 % lighter
//     (with or without LDC), which the mirror passes to the box as pressure (the size fits).
//     Tried (branch float2, reverted): boundaries as Eq. 1's neighbours at rest density (P_b = 0,
//     reacted) float it 0.506 (Archimedes 1.014, this dropped box 0.470) but pull compressed
//     fluid toward every wall: the two-fluid stratification fell to 0.947-0.949 of the light fluid
//     above the interface (bound 0.95; 0.967-0.970 before). No LDC push next to boundaries: 0.516
//     (Archimedes 0.992). P extrapolated linearly into the boundary (Adami et al. 2012's wall
//     pressure): 0.452-0.454, no help, since the bias is in the layer's own P.
//   * the drop: released from 1 cm above the water as here, without LDC, it floats 0.465-0.479
//     (0.504 from inside the water); held still where it came to rest it feels 1.065 times
//     rho g A times its depth: the water it pushed down stays packed under it (with the rest
//     density boundary above, still 0.467 after 12 s: it does not relax).
#include "coupling_scenes.h"

using namespace coupling;

TEST_CASE("coupling: a submerged box at rest feels rho g V upward within 5 %", "[coupling][!shouldfail]") {
    check_archimedes(PBF_BACKEND_CPU);
}

TEST_CASE("coupling: without LDC the box and the floor carry exactly the water's weight", "[coupling]") {
    check_support(PBF_BACKEND_CPU);
}

TEST_CASE("coupling: a box of 500 kg/m3 floats half submerged within 5 %", "[coupling][!shouldfail]") {
    check_floating(PBF_BACKEND_CPU);
}

TEST_CASE("coupling: a box of 2000 kg/m3 sinks to the floor", "[coupling]") { check_sinking(PBF_BACKEND_CPU); }

TEST_CASE("coupling: a paddle feels the reaction of the momentum it gives the water within 5 %", "[coupling]") {
    check_paddle(PBF_BACKEND_CPU);
}

TEST_CASE("coupling: force calls refuse what they cannot answer", "[coupling][api]") {
    pbf_world_desc d = small_desc();
    TestWorld w(d);
    pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX);
    pbf_collider_id plain{}, dyn{};
    REQUIRE_OK(pbf_world_create_collider(w, &c, &plain));
    c.dynamic = 1;
    c.position[0] = 0.3f;
    REQUIRE_OK(pbf_world_create_collider(w, &c, &dyn));
    pbf_collider_force f;
    CHECK_FAILS(pbf_collider_get_force(w, plain, &f), PBF_ERROR_INVALID_STATE, "dynamic");
    CHECK_FAILS(pbf_collider_get_force(w, dyn, nullptr), PBF_ERROR_INVALID_ARGUMENT, "out_force");
    CHECK_FAILS(pbf_collider_get_force(w, pbf_collider_id{dyn.index, dyn.generation + 1000}, &f),
                PBF_ERROR_INVALID_HANDLE, "collider");
    // Before its first step a collider has felt nothing.
    set3(f.force, 7, 7, 7);
    REQUIRE_OK(pbf_collider_get_force(w, dyn, &f));
    CHECK(f.force[0] == 0.0f);
    CHECK(f.force[1] == 0.0f);
    // The device table: max_colliders rows of 24 bytes, the dynamic collider's row by its index.
    pbf_mapped_buffer m;
    std::memset(&m, 0, sizeof m);
    m.struct_size = sizeof m;
    REQUIRE_OK(pbf_world_map_collider_forces(w, &m));
    CHECK(m.memory == PBF_MEMORY_HOST);
    CHECK(m.count == d.max_colliders);
    CHECK(m.stride_bytes == sizeof(pbf_collider_force));
    REQUIRE(m.data != nullptr);
    // A block dropped on the dynamic box: after a step its row holds what pbf_collider_get_force says.
    w.emit(block(0.2f, 0.65f, -0.1f, 0.4f, 0.85f, 0.1f));
    for (int k = 0; k < 30; ++k) REQUIRE_OK(pbf_world_step(w, kDt));
    REQUIRE_OK(pbf_collider_get_force(w, dyn, &f));
    const pbf_collider_force* rows = static_cast<const pbf_collider_force*>(m.data);
    CHECK(f.force[1] < 0.0f);  // water resting on it pushes it down
    CHECK(rows[dyn.index].force[1] == f.force[1]);
    m.struct_size = 3;
    CHECK_FAILS(pbf_world_map_collider_forces(w, &m), PBF_ERROR_STRUCT_SIZE, "pbf_mapped_buffer");
}

TEST_CASE("coupling: 256 dynamic kinematic boxes each record their own push, and with the floor carry the water",
          "[coupling][colliders]") {
    check_many_boxes(PBF_BACKEND_CPU);
}

// The same checks where README (Physics, Two-way coupling) says buoyancy is accurate: the box 12
// particle diameters across (radius 0.01 m) and the fluid held within 0.3 % of its rest density
// (adaptive iterations, up to 16). The [gpu] twins also run at 24 diameters.
TEST_CASE("coupling: resolved (12 particle diameters, density held within 0.3 %), a submerged box feels rho g V within 5 %",
          "[coupling]") {
    check_archimedes(PBF_BACKEND_CPU, resolved(0.01f));
}

TEST_CASE("coupling: resolved (12 particle diameters, density held within 0.3 %), a box of 500 kg/m3 floats half "
          "submerged within 5 %",
          "[coupling]") {
    check_floating(PBF_BACKEND_CPU, resolved(0.01f));
}
