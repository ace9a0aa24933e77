// The solver on the CUDA executor.
#include "../exec/cuda_exec.h"
#include "solver.h"

namespace pbf {

std::unique_ptr<Backend> create_cuda_backend(const BackendConfig& config, Status* status) {
    auto solver = std::make_unique<Solver<CudaExec>>(config.cuda_device);
    *status = solver->init(config);
    if (!status->ok()) return nullptr;
    return solver;
}

}  // namespace pbf
