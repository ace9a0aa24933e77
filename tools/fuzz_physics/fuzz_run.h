// Running one fuzz world and checking the physics invariants after every step
// (docs/physics_fuzzer.md states each bound and why it holds). Public C API only.
#pragma once
#include "fuzz_world.h"

#include <string>

namespace fuzz {

struct RunResult {
    bool failed = false;
    bool setup_refused = false;  // a call the world's spec makes was refused: a fuzzer bug, reported as a failure
    int frame = -1;              // the frame whose step broke an invariant
    std::string invariant;       // its name (finite, accounting, coincident, density, speed, energy, momentum, ...)
    std::string detail;
    int frames_run = 0;
    uint32_t peak_particles = 0;
    double seconds = 0;
    bool energy_checked = false, momentum_checked = false;
};

RunResult run_world(const WorldSpec& spec);

}  // namespace fuzz
