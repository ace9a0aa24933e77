// Two-way coupling on the CPU backend (issue 13): the fluid's force on dynamic colliders, read
// through pbf_collider_get_force, against Archimedes, floating and sinking boxes, and the
// momentum a paddle gives the water. The scenes and checks are in coupling_scenes.h ([gpu]
// twins in test_gpu_coupling.cpp).
//
// Known failures, tagged [!shouldfail] (they pass while the bound fails; remove the tag when the
// physics meets it). Measured on this branch, CPU backend, defaults (LDC on, its boundary part's
// reaction given to the colliders: passes.h record_ldc_reaction):
// - Archimedes: 139.2 N for rho g V = 135.6 N (1.026, within 5 %), but the largest |torque| over
//   the last second is 0.37 N m for a bound of 0.163 (LDC off: 1.017 and 0.37 N m). Before the
//   reaction: 81.7 N (0.60).
// - Floating at 500 kg/m3: submerged fraction 0.469 (LDC off: 0.465; before the reaction 0.687).
//   At rest the box takes 68 N = m g: 65.4 N on its bottom (head 0.116 m for a geometric depth
//   of 0.112 m: the water column is 1.2 % denser than its emission lattice, PBF's residual
//   compression) and 2.7 N upward on its sides near the bottom edges (the slabs' gradient there;
//   a submerged box has the opposite push at its top edges).
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
