/* A stand-in for the NVIDIA driver (libcuda.so.1, nvcuda.dll) for the tests of how libpbf finds
 * the GPU at run time: it answers the calls libpbf makes while opening the driver and loading its
 * kernels, the way a machine without a usable GPU would. What it plays is chosen by the
 * environment variable PBF_STUB_CUDA:
 *
 *   no-device      cuInit returns CUDA_ERROR_NO_DEVICE (a driver installed, no NVIDIA GPU)
 *   old-driver     cuDriverGetVersion reports CUDA 12.8, older than the kernels need
 *   init-error     cuInit returns CUDA_ERROR_SYSTEM_DRIVER_MISMATCH (kernel module and library
 *                  of different driver versions)
 *   no-devices     cuInit succeeds, cuDeviceGetCount reports 0
 *   missing-entry  cuGetProcAddress does not know cuLaunchKernel
 *   old-gpu        one device of compute capability 6.1
 *   no-binary      one device of compute capability 8.6 whose cuModuleLoadData answers
 *                  CUDA_ERROR_NO_BINARY_FOR_GPU for a fatbin and CUDA_ERROR_INVALID_IMAGE for
 *                  anything else (so a test tells whether the library handed it a fatbin)
 *
 * Built three ways (tests/CMakeLists.txt): exporting cuGetProcAddress_v2 and cuGetProcAddress
 * (as drivers of CUDA 12 and later do), cuGetProcAddress only (CUDA 11.3 to 11.8), or neither
 * (drivers before 11.3). pbf_stub_cuda_calls(name) counts the calls of a few entry points.
 *
 * The types and values are the driver API's (cuda.h), written out so that the stub builds with
 * any C compiler and needs no CUDA headers. STUB_CUDA_VERSION is the toolkit's CUDA_VERSION, the
 * version a current driver reports. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#if defined(_WIN32)
#define STUB_EXPORT __declspec(dllexport)
#else
#define STUB_EXPORT __attribute__((visibility("default")))
#endif
#ifndef STUB_CUDA_VERSION
#error "STUB_CUDA_VERSION (the toolkit's CUDA_VERSION) must be defined"
#endif

typedef int CUresult;
typedef int CUdevice;
typedef void* CUcontext;
typedef void* CUmodule;
enum {
    CUDA_SUCCESS = 0,
    CUDA_ERROR_INVALID_VALUE = 1,
    CUDA_ERROR_NO_DEVICE = 100,
    CUDA_ERROR_INVALID_DEVICE = 101,
    CUDA_ERROR_INVALID_IMAGE = 200,
    CUDA_ERROR_NO_BINARY_FOR_GPU = 209,
    CUDA_ERROR_NOT_FOUND = 500,
    CUDA_ERROR_NOT_SUPPORTED = 801,
    CUDA_ERROR_SYSTEM_DRIVER_MISMATCH = 803,
    CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MAJOR = 75,
    CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MINOR = 76,
    CU_GET_PROC_ADDRESS_SUCCESS = 0,
    CU_GET_PROC_ADDRESS_SYMBOL_NOT_FOUND = 1
};
/* The first word of a fatbin nvcc writes (-fatbin), little-endian. */
#define FATBIN_MAGIC 0xBA55ED50u

enum mode { NO_DEVICE, OLD_DRIVER, INIT_ERROR, NO_DEVICES, MISSING_ENTRY, OLD_GPU, NO_BINARY, UNKNOWN_MODE };

static enum mode mode(void) {
    static const char* const names[] = {"no-device", "old-driver", "init-error", "no-devices",
                                        "missing-entry", "old-gpu", "no-binary"};
    const char* m = getenv("PBF_STUB_CUDA");
    for (int i = 0; m && i < UNKNOWN_MODE; ++i)
        if (strcmp(m, names[i]) == 0) return (enum mode)i;
    return UNKNOWN_MODE;
}

static int device_count(void) { return mode() == OLD_GPU || mode() == NO_BINARY ? 1 : 0; }

static struct {
    int init, ctx_retain, ctx_release, module_load;
} calls;

STUB_EXPORT int pbf_stub_cuda_calls(const char* name) {
    if (strcmp(name, "cuInit") == 0) return calls.init;
    if (strcmp(name, "cuDevicePrimaryCtxRetain") == 0) return calls.ctx_retain;
    if (strcmp(name, "cuDevicePrimaryCtxRelease") == 0) return calls.ctx_release;
    if (strcmp(name, "cuModuleLoadData") == 0) return calls.module_load;
    return -1;
}

static CUresult stub_cuDriverGetVersion(int* v) {
    if (!v) return CUDA_ERROR_INVALID_VALUE;
    *v = mode() == OLD_DRIVER ? 12080 : STUB_CUDA_VERSION;
    return CUDA_SUCCESS;
}

static CUresult stub_cuInit(unsigned int flags) {
    (void)flags;
    ++calls.init;
    if (mode() == NO_DEVICE) return CUDA_ERROR_NO_DEVICE;
    if (mode() == INIT_ERROR || mode() == UNKNOWN_MODE) return CUDA_ERROR_SYSTEM_DRIVER_MISMATCH;
    return CUDA_SUCCESS;
}

static const struct {
    CUresult code;
    const char *name, *text;
} errors[] = {
    {CUDA_SUCCESS, "CUDA_SUCCESS", "no error"},
    {CUDA_ERROR_INVALID_VALUE, "CUDA_ERROR_INVALID_VALUE", "invalid argument"},
    {CUDA_ERROR_NO_DEVICE, "CUDA_ERROR_NO_DEVICE", "no CUDA-capable device is detected"},
    {CUDA_ERROR_INVALID_DEVICE, "CUDA_ERROR_INVALID_DEVICE", "invalid device ordinal"},
    {CUDA_ERROR_INVALID_IMAGE, "CUDA_ERROR_INVALID_IMAGE", "device kernel image is invalid"},
    {CUDA_ERROR_NO_BINARY_FOR_GPU, "CUDA_ERROR_NO_BINARY_FOR_GPU", "no kernel image is available for execution on the device"},
    {CUDA_ERROR_NOT_SUPPORTED, "CUDA_ERROR_NOT_SUPPORTED", "operation not supported"},
    {CUDA_ERROR_SYSTEM_DRIVER_MISMATCH, "CUDA_ERROR_SYSTEM_DRIVER_MISMATCH", "system has unsupported display driver / cuda driver combination"},
};

static CUresult error_entry(CUresult e, const char** out, int text) {
    for (size_t i = 0; i < sizeof errors / sizeof errors[0]; ++i)
        if (errors[i].code == e) {
            *out = text ? errors[i].text : errors[i].name;
            return CUDA_SUCCESS;
        }
    *out = NULL;
    return CUDA_ERROR_INVALID_VALUE;
}
static CUresult stub_cuGetErrorName(CUresult e, const char** out) { return error_entry(e, out, 0); }
static CUresult stub_cuGetErrorString(CUresult e, const char** out) { return error_entry(e, out, 1); }

static CUresult stub_cuDeviceGetCount(int* n) {
    *n = device_count();
    return CUDA_SUCCESS;
}
static CUresult stub_cuDeviceGet(CUdevice* d, int ordinal) {
    if (ordinal < 0 || ordinal >= device_count()) return CUDA_ERROR_INVALID_DEVICE;
    *d = ordinal;
    return CUDA_SUCCESS;
}
static CUresult stub_cuDeviceGetName(char* name, int len, CUdevice d) {
    (void)d;
    const char* n = mode() == OLD_GPU ? "Stub GPU 61" : "Stub GPU 86";
    if (len <= 0) return CUDA_ERROR_INVALID_VALUE;
    strncpy(name, n, (size_t)len - 1);
    name[len - 1] = '\0';
    return CUDA_SUCCESS;
}
static CUresult stub_cuDeviceGetAttribute(int* v, int attribute, CUdevice d) {
    (void)d;
    if (attribute == CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MAJOR) *v = mode() == OLD_GPU ? 6 : 8;
    else if (attribute == CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MINOR) *v = mode() == OLD_GPU ? 1 : 6;
    else return CUDA_ERROR_INVALID_VALUE;
    return CUDA_SUCCESS;
}
static int the_context;
static CUresult stub_cuDevicePrimaryCtxRetain(CUcontext* c, CUdevice d) {
    (void)d;
    ++calls.ctx_retain;
    *c = &the_context;
    return CUDA_SUCCESS;
}
static CUresult stub_cuDevicePrimaryCtxRelease(CUdevice d) {
    (void)d;
    ++calls.ctx_release;
    return CUDA_SUCCESS;
}
static CUresult stub_cuCtxSetCurrent(CUcontext c) { return c == &the_context ? CUDA_SUCCESS : CUDA_ERROR_INVALID_VALUE; }
static CUresult stub_cuModuleLoadData(CUmodule* m, const void* image) {
    ++calls.module_load;
    *m = NULL;
    uint32_t magic = 0;
    if (image) memcpy(&magic, image, sizeof magic);
    return magic == FATBIN_MAGIC ? CUDA_ERROR_NO_BINARY_FOR_GPU : CUDA_ERROR_INVALID_IMAGE;
}
/* Every other entry point: present, and refusing (none is called in the modes above). */
static CUresult stub_not_supported(void) { return CUDA_ERROR_NOT_SUPPORTED; }

#define STUB_ENTRY(name) {#name, (void*)stub_##name}
static const struct {
    const char* name;
    void* fn;
} entries[] = {
    STUB_ENTRY(cuDriverGetVersion), STUB_ENTRY(cuInit), STUB_ENTRY(cuGetErrorName), STUB_ENTRY(cuGetErrorString),
    STUB_ENTRY(cuDeviceGetCount), STUB_ENTRY(cuDeviceGet), STUB_ENTRY(cuDeviceGetName), STUB_ENTRY(cuDeviceGetAttribute),
    STUB_ENTRY(cuDevicePrimaryCtxRetain), STUB_ENTRY(cuDevicePrimaryCtxRelease), STUB_ENTRY(cuCtxSetCurrent),
    STUB_ENTRY(cuModuleLoadData),
};

static void* find(const char* symbol) {
    if (!symbol || strncmp(symbol, "cu", 2) != 0) return NULL;
    if (mode() == MISSING_ENTRY && strcmp(symbol, "cuLaunchKernel") == 0) return NULL;
    for (size_t i = 0; i < sizeof entries / sizeof entries[0]; ++i)
        if (strcmp(entries[i].name, symbol) == 0) return entries[i].fn;
    return (void*)stub_not_supported;
}

#if STUB_EXPORT_GET_PROC_ADDRESS_V2
STUB_EXPORT CUresult cuGetProcAddress_v2(const char* symbol, void** pfn, int version, uint64_t flags, int* status) {
    (void)version;
    (void)flags;
    *pfn = find(symbol);
    if (status) *status = *pfn ? CU_GET_PROC_ADDRESS_SUCCESS : CU_GET_PROC_ADDRESS_SYMBOL_NOT_FOUND;
    return *pfn ? CUDA_SUCCESS : CUDA_ERROR_NOT_FOUND;
}
#endif
#if STUB_EXPORT_GET_PROC_ADDRESS
STUB_EXPORT CUresult cuGetProcAddress(const char* symbol, void** pfn, int version, uint64_t flags) {
    (void)version;
    (void)flags;
    *pfn = find(symbol);
    return *pfn ? CUDA_SUCCESS : CUDA_ERROR_NOT_FOUND;
}
#endif
/* A driver too old for cuGetProcAddress still exports its functions by name. */
STUB_EXPORT CUresult cuInit(unsigned int flags) { return stub_cuInit(flags); }
