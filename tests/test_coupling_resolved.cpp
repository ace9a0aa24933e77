// Two-way coupling on the CPU backend where docs/physics.md (Two-way coupling) says buoyancy is
// accurate: the box 12 particle diameters across (radius 0.01 m) and the fluid held within 0.3 %
// of its rest density (adaptive iterations, up to 16). The scenes and checks are test_coupling.cpp's
// (coupling_scenes.h); the [gpu] twins also run at 24 diameters. A suite of their own, since each
// runs many minutes on two cores and ctest starts the suite first (tests/CMakeLists.txt).
#include "coupling_scenes.h"

using namespace coupling;

TEST_CASE(
    "coupling: resolved (12 particle diameters, density held within 0.3 %), a submerged box feels rho g V within 5 %",
    "[coupling]") {
    check_archimedes(PBF_BACKEND_CPU, resolved(0.01f));
}

TEST_CASE(
    "coupling: resolved (12 particle diameters, density held within 0.3 %), a box of 500 kg/m3 floats half "
    "submerged within 5 %",
    "[coupling]") {
    check_floating(PBF_BACKEND_CPU, resolved(0.01f));
}
