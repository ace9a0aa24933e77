// Built instead of the CUDA executor when libpbf is configured without CUDA.
#include "exec_common.h"

namespace pbf {

CudaAvailability cuda_availability(int32_t) {
    CudaAvailability a;
    a.status = PBF_BACKEND_STATUS_NOT_BUILT;
    a.message = "this libpbf was built without CUDA (PBF_WITH_CUDA=OFF)";
    return a;
}

}  // namespace pbf
