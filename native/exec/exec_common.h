// What both executors (CpuExec, CudaExec) share with the solver above them: the statistics a
// reduction reads back, and whether a CUDA device is usable.
#pragma once
#include <cstdint>

#include "../common/status.h"

namespace pbf {

struct StatsReadback {
    uint32_t count = 0;
    uint32_t speed_clamps = 0;     // particle-substeps whose speed a limit cut in the last step
    uint32_t iterations_used = 0;  // adaptive mode: iterations run in the last step
    uint64_t emitted_total = 0, drained_total = 0;
    double error_sum = 0.0, kinetic_energy = 0.0;
    float error_max = 0.0f;
    // diffuse particles (worlds with a diffuse capacity)
    uint32_t diffuse_count = 0, diffuse_dropped_step = 0;
    uint64_t diffuse_generated_total = 0, diffuse_dropped_total = 0;
};

// Whether a CUDA device is usable (false in CPU-only builds: cuda_unavailable.cpp).
bool cuda_device_available(int32_t device);

}  // namespace pbf
