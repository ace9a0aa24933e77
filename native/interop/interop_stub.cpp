// Built instead of interop_cuda.cu when libpbf is configured without CUDA: no interop is
// available, and the C API refuses every interop call with PBF_ERROR_BACKEND_UNAVAILABLE.
#include "interop.h"

namespace pbf {

uint32_t interop_support() { return 0; }

std::unique_ptr<Interop> Interop::create(World&, Status* status) {
    *status = Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this libpbf was built without CUDA: no interop");
    return nullptr;
}

}  // namespace pbf
