// Two-way coupling on the CPU backend (issue 13): the fluid's force on dynamic colliders, read
// through pbf_collider_get_force, against Archimedes, floating and sinking boxes, and the
// momentum a paddle gives the water. The scenes and checks are in coupling_scenes.h ([gpu]
// twins in test_gpu_coupling.cpp).
//
// Known failures, tagged [!shouldfail] (they pass while the bound fails; remove the tag when the
// physics meets it). Measured on this branch, CPU backend, defaults (LDC on, walls and colliders
// among its neighbours at rest density, their reaction given to the colliders: passes.h
// ldc_force, record_ldc_reaction); the CPU runs are chaotic: a change in the last bit of one
// sum moves a held box's force by ±3 % and the floating fraction by about ±0.005, so compare
// averages, not single runs.
// - Archimedes: 137.6 N for rho g V = 135.6 N (1.014, within 5 %; 1.03 before LDC took the box
//   as neighbours at rest density, when a boundary mirrored each particle's P; 0.99 without LDC),
//   but the largest |torque| over the last second is 0.50 N m for a bound of 0.163, and the
//   torque's mean over that second was 0.20 N m with LDC, 0.18 without, 0.31 with vorticity
//   confinement off (with a mean sideways force of 1-3 N): a slow circulation around the box, not
//   only step-to-step noise, so the statistic is kept.
// - Floating at 500 kg/m3: submerged fraction 0.470 (0.462-0.468 before the change above). LDC
//   is no longer the cause: emitted in place at half depth and released (1-thread white-box
//   runs) the box floats 0.506 submerged with LDC, 0.504 without (0.459-0.462 with the mirrored
//   boundary, and its error scaled with LDC's gain: 0.481 at half the gain). What remains is the
//   drop: released from 1 cm above the water as here, without LDC, it floats 0.465-0.479, and held
//   still where it came to rest it feels 1.065 times rho g A times its depth: the water it pushed
//   down stays packed under it.
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
