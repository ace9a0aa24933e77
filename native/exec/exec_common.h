// What both executors (CpuExec, CudaExec) share with the solver above them: the statistics a
// reduction reads back, and whether a CUDA device is usable.
#pragma once
#include <cstdint>
#include <string>

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

// What was found when looking for the CUDA backend on one device: PBF_BACKEND_STATUS_AVAILABLE,
// or why not, in words an engine can show.
struct CudaAvailability {
    pbf_backend_status status = PBF_BACKEND_STATUS_NOT_BUILT;
    std::string message;
    int driver_version = 0;           // the driver's CUDA version (0: no driver)
    int required_driver_version = 0;  // what the embedded kernels need (0: none built in)
    int device_count = 0;
    std::string device_name;      // the device asked about, where it exists
    double kernel_load_ms = 0.0;  // the load of the kernels into its context, when done
    bool ok() const { return status == PBF_BACKEND_STATUS_AVAILABLE; }
};

// Whether CUDA device `device` can run a world: the driver is opened and the kernels loaded into
// the device's context on the first call for it (cuda_module.cpp; in builds without CUDA,
// cuda_unavailable.cpp says NOT_BUILT).
CudaAvailability cuda_availability(int32_t device);

// The CPU backend's device, e.g. "CPU (8 threads)" (cpu_exec.cpp).
std::string cpu_device_name();

}  // namespace pbf
