// Built instead of cuda_exec.cu when libpbf is configured without CUDA.
#include "exec_common.h"

namespace pbf {

bool cuda_device_available(int32_t) { return false; }

}  // namespace pbf
