// Built instead of cuda_backend.cu when libpbf is configured without CUDA.
#include "backend.h"

namespace pbf {

bool cuda_device_available(int32_t) { return false; }

std::unique_ptr<Backend> create_cuda_backend(const BackendConfig&, Status* status) {
    *status = Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this libpbf was built without CUDA (PBF_WITH_CUDA=OFF)");
    return nullptr;
}

}  // namespace pbf
