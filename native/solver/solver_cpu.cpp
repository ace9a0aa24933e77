// The solver on the CPU executor, and the names of its stages. In a build without CUDA, also the
// refusal of a CUDA backend.
#include "../exec/cpu_exec.h"
#include "solver.h"

namespace pbf {

const char* stage_name(int stage) {
    static const char* const names[kStageCount] = {
        "emit+drain",  "grid(x)",       "density(x)",      "forces+LDC+predict", "grid(x*)",
        "lambda",      "delta+collide", "omega+xsph",      "vorticity force",    "density(end)",
        "render data", "diffuse",       "material forces", "diffuse advect"};
    return stage >= 0 && stage < kStageCount ? names[stage] : "?";
}

std::unique_ptr<Backend> create_cpu_backend(const BackendConfig& config, Status* status) {
    auto solver = std::make_unique<Solver<CpuExec>>();
    *status = solver->init(config);
    if (!status->ok()) return nullptr;
    return solver;
}

#if !PBF_HAVE_CUDA
std::unique_ptr<Backend> create_cuda_backend(const BackendConfig&, Status* status) {
    *status = Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this libpbf was built without CUDA (PBF_WITH_CUDA=OFF)");
    return nullptr;
}

#endif

}  // namespace pbf
