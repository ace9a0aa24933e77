// The CUDA driver and a device's kernels for the layers above the solver that talk to the driver
// themselves (zero-copy interop, beside the world): the executor's own driver table and loaded
// module, so that interop runs in the same context as the world's work. CUDA builds only.
#pragma once
#include "../exec/cuda_module.h"
