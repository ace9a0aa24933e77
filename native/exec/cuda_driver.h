// The CUDA driver, opened at run time: libpbf links neither the CUDA runtime nor the driver, so one
// binary loads on machines without an NVIDIA driver and runs its CPU backend there. The driver
// library (libcuda.so.1, nvcuda.dll) is opened once per process and every entry point is taken
// through cuGetProcAddress at the ABI version this code was written against, so a newer driver
// keeps serving the same signatures. Where anything is missing, cuda_availability() says which of
// the reasons below it was, in words an engine can show.
#pragma once
#include <cudaTypedefs.h>

#include <cstdint>
#include <string>

#include "exec_common.h"

namespace pbf::cuda {

// Signatures the toolkit headers do not declare without the graphics APIs' own headers
// (cudaGL.h needs GL's, cudaD3D11.h is not shipped outside Windows): the driver's documented
// C signatures, with the graphics objects as opaque pointers / names.
typedef CUresult(CUDAAPI* PFN_cuGraphicsGLRegisterBuffer_v3000)(CUgraphicsResource* resource, unsigned int buffer,
                                                                unsigned int flags);
typedef CUresult(CUDAAPI* PFN_cuGraphicsD3D11RegisterResource_v3000)(CUgraphicsResource* resource, void* d3d11_resource,
                                                                     unsigned int flags);

// Entry points every CUDA world needs: a driver lacking one is too old.
#define PBF_CUDA_REQUIRED_ENTRY_POINTS(X) \
    X(cuGetErrorName, 6000)               \
    X(cuGetErrorString, 6000)             \
    X(cuDeviceGet, 2000)                  \
    X(cuDeviceGetCount, 2000)             \
    X(cuDeviceGetName, 2000)              \
    X(cuDeviceGetAttribute, 2000)         \
    X(cuDeviceGetUuid, 11040)             \
    X(cuDeviceTotalMem, 3020)             \
    X(cuDevicePrimaryCtxRetain, 7000)     \
    X(cuDevicePrimaryCtxRelease, 11000)   \
    X(cuCtxSetCurrent, 4000)              \
    X(cuCtxGetCurrent, 4000)              \
    X(cuModuleLoadData, 2000)             \
    X(cuModuleUnload, 2000)               \
    X(cuModuleGetFunction, 2000)          \
    X(cuModuleGetGlobal, 3020)            \
    X(cuMemAlloc, 3020)                   \
    X(cuMemFree, 3020)                    \
    X(cuMemHostAlloc, 2020)               \
    X(cuMemFreeHost, 2000)                \
    X(cuMemGetInfo, 3020)                 \
    X(cuMemcpyDtoH, 3020)                 \
    X(cuMemcpyHtoDAsync, 3020)            \
    X(cuMemcpyDtoHAsync, 3020)            \
    X(cuMemsetD8Async, 3020)              \
    X(cuStreamCreate, 2000)               \
    X(cuStreamDestroy, 4000)              \
    X(cuStreamSynchronize, 2000)          \
    X(cuStreamWaitEvent, 3020)            \
    X(cuEventCreate, 2000)                \
    X(cuEventDestroy, 4000)               \
    X(cuEventRecord, 2000)                \
    X(cuEventQuery, 2000)                 \
    X(cuEventSynchronize, 2000)           \
    X(cuEventElapsedTime, 2000)           \
    X(cuLaunchKernel, 4000)

// Entry points of optional features (graphics interop, graphs): where the driver lacks one, only
// the calls that need it are refused.
#define PBF_CUDA_OPTIONAL_ENTRY_POINTS(X)       \
    X(cuGraphCreate, 10000)                     \
    X(cuGraphAddKernelNode, 12000)              \
    X(cuGraphAddMemsetNode, 10000)              \
    X(cuGraphExecKernelNodeSetParams, 12000)    \
    X(cuGraphExecMemsetNodeSetParams, 10020)    \
    X(cuGraphInstantiateWithFlags, 11040)       \
    X(cuGraphLaunch, 10000)                     \
    X(cuGraphExecDestroy, 10000)                \
    X(cuGraphDestroy, 10000)                    \
    X(cuGraphicsUnregisterResource, 3000)       \
    X(cuGraphicsMapResources, 3000)             \
    X(cuGraphicsUnmapResources, 3000)           \
    X(cuGraphicsResourceGetMappedPointer, 3020) \
    X(cuGraphicsGLRegisterBuffer, 3000)         \
    X(cuGraphicsD3D11RegisterResource, 3000)    \
    X(cuImportExternalMemory, 10000)            \
    X(cuExternalMemoryGetMappedBuffer, 10000)   \
    X(cuDestroyExternalMemory, 10000)           \
    X(cuImportExternalSemaphore, 10000)         \
    X(cuSignalExternalSemaphoresAsync, 10000)   \
    X(cuWaitExternalSemaphoresAsync, 10000)     \
    X(cuDestroyExternalSemaphore, 10000)        \
    X(cuDeviceGetLuid, 10000)

// The driver's entry points; optional ones are null where the driver lacks them.
struct Driver {
#define PBF_CUDA_MEMBER(name, version) PFN_##name##_v##version name = nullptr;
    PBF_CUDA_REQUIRED_ENTRY_POINTS(PBF_CUDA_MEMBER)
    PBF_CUDA_OPTIONAL_ENTRY_POINTS(PBF_CUDA_MEMBER)
#undef PBF_CUDA_MEMBER
    int version = 0;       // cuDriverGetVersion: 1000 * major + 10 * minor
    int device_count = 0;  // devices cuInit found
};

// The driver version the embedded kernels need (the toolkit's major release that built them).
constexpr int kRequiredDriverVersion = (CUDA_VERSION / 1000) * 1000;

// Opens the driver the first time (thread-safe) and returns it; null where there is none usable
// (driver_availability() says why). The library named by the environment variable
// PBF_CUDA_DRIVER, when set, is opened instead of the system's (diagnostics and tests).
const Driver* driver();
// Why driver() is null, or AVAILABLE with the driver's version and device count.
const CudaAvailability& driver_availability();

// "CUDA_ERROR_X (text)" for a driver result.
std::string error_text(CUresult e);

}  // namespace pbf::cuda
