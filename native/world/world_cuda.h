// The world's door to the CUDA driver for zero-copy interop (native/interop): the driver's entry
// points and the kernels of the device a world runs on (World::live_buffers().cuda_device).
// CUDA builds only: it needs cuda.h.
#pragma once
#include "../solver/backend_cuda.h"
