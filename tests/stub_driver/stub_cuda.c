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
 *   layouts        that device "loads" the fatbin: the stub reads the first machine-code image
 *                  (an ELF cubin) in it, finds the kernels and globals the library asks for in
 *                  its symbol table and serves pbf_op_layout's initial data as the global's
 *                  memory, so that the library's check of its ops' layouts against the kernels'
 *                  runs without a GPU (nothing is launched: worlds are not created in this mode)
 *   layout-mismatch  the same, with the first op's size in pbf_op_layout changed
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
typedef void* CUfunction;
typedef unsigned long long CUdeviceptr;
enum {
    CUDA_SUCCESS = 0,
    CUDA_ERROR_INVALID_VALUE = 1,
    CUDA_ERROR_NO_DEVICE = 100,
    CUDA_ERROR_INVALID_DEVICE = 101,
    CUDA_ERROR_INVALID_IMAGE = 200,
    CUDA_ERROR_NO_BINARY_FOR_GPU = 209,
    CUDA_ERROR_NOT_FOUND = 500,
    CUDA_ERROR_INVALID_HANDLE = 400,
    CUDA_ERROR_NOT_SUPPORTED = 801,
    CUDA_ERROR_SYSTEM_DRIVER_MISMATCH = 803,
    CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MAJOR = 75,
    CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MINOR = 76,
    CU_GET_PROC_ADDRESS_SUCCESS = 0,
    CU_GET_PROC_ADDRESS_SYMBOL_NOT_FOUND = 1
};
/* The first word of a fatbin nvcc writes (-fatbin), little-endian. */
#define FATBIN_MAGIC 0xBA55ED50u

enum mode {
    NO_DEVICE,
    OLD_DRIVER,
    INIT_ERROR,
    NO_DEVICES,
    MISSING_ENTRY,
    OLD_GPU,
    NO_BINARY,
    LAYOUTS,
    LAYOUT_MISMATCH,
    UNKNOWN_MODE
};

static enum mode mode(void) {
    static const char* const names[] = {"no-device", "old-driver", "init-error", "no-devices",     "missing-entry",
                                        "old-gpu",   "no-binary",  "layouts",    "layout-mismatch"};
    const char* m = getenv("PBF_STUB_CUDA");
    for (int i = 0; m && i < UNKNOWN_MODE; ++i)
        if (strcmp(m, names[i]) == 0) return (enum mode)i;
    return UNKNOWN_MODE;
}

static int device_count(void) { return mode() >= OLD_GPU && mode() <= LAYOUT_MISMATCH ? 1 : 0; }

static struct { int init, ctx_retain, ctx_release, module_load; } calls;

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
    {CUDA_ERROR_NO_BINARY_FOR_GPU, "CUDA_ERROR_NO_BINARY_FOR_GPU",
     "no kernel image is available for execution on the device"},
    {CUDA_ERROR_NOT_SUPPORTED, "CUDA_ERROR_NOT_SUPPORTED", "operation not supported"},
    {CUDA_ERROR_SYSTEM_DRIVER_MISMATCH, "CUDA_ERROR_SYSTEM_DRIVER_MISMATCH",
     "system has unsupported display driver / cuda driver combination"},
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
    if (attribute == CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MAJOR)
        *v = mode() == OLD_GPU ? 6 : 8;
    else if (attribute == CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MINOR)
        *v = mode() == OLD_GPU ? 1 : 6;
    else
        return CUDA_ERROR_INVALID_VALUE;
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
static CUresult stub_cuCtxSetCurrent(CUcontext c) {
    return c == &the_context ? CUDA_SUCCESS : CUDA_ERROR_INVALID_VALUE;
}

/* Little-endian reads at any alignment. */
static uint64_t rd(const unsigned char* p, int bytes) {
    uint64_t v = 0;
    for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | p[i];
    return v;
}

/* The first ELF image of a fatbin: entries follow its 16-byte header, each with its kind (2:
 * ELF, 1: PTX) at 0, its header's size at 4 and its payload's size at 8. */
static const unsigned char* first_cubin(const unsigned char* fatbin) {
    const uint64_t header = rd(fatbin + 6, 2), body = rd(fatbin + 8, 8);
    const unsigned char *e = fatbin + header, *end = fatbin + header + body;
    while (e + 16 <= end) {
        const uint64_t ehead = rd(e + 4, 4), payload = rd(e + 8, 8);
        if (rd(e, 2) == 2 && memcmp(e + ehead,
                                    "\x7f"
                                    "ELF",
                                    4) == 0)
            return e + ehead;
        e += ehead + payload;
    }
    return NULL;
}

/* A symbol's bytes in a 64-bit ELF image (its section's data at the symbol's value), or NULL. */
static const unsigned char* elf_symbol(const unsigned char* elf, const char* name, uint64_t* size) {
    const unsigned char* sh = elf + rd(elf + 40, 8);
    const uint64_t shentsize = rd(elf + 58, 2), shnum = rd(elf + 60, 2);
    for (uint64_t i = 0; i < shnum; ++i) {
        const unsigned char* s = sh + i * shentsize;
        if (rd(s + 4, 4) != 2) continue; /* SHT_SYMTAB */
        const unsigned char* strtab = elf + rd(sh + rd(s + 40, 4) * shentsize + 24, 8);
        const unsigned char* sym = elf + rd(s + 24, 8);
        for (uint64_t k = 0; k < rd(s + 32, 8) / 24; ++k, sym += 24) {
            const uint64_t shndx = rd(sym + 6, 2);
            if (shndx == 0 || shndx >= shnum || strcmp((const char*)strtab + rd(sym, 4), name) != 0) continue;
            *size = rd(sym + 16, 8);
            return elf + rd(sh + shndx * shentsize + 24, 8) + rd(sym + 8, 8);
        }
    }
    return NULL;
}

static const unsigned char* loaded_cubin;
static CUresult stub_cuModuleLoadData(CUmodule* m, const void* image) {
    ++calls.module_load;
    *m = NULL;
    uint32_t magic = 0;
    if (image) memcpy(&magic, image, sizeof magic);
    if (magic != FATBIN_MAGIC) return CUDA_ERROR_INVALID_IMAGE;
    if (mode() != LAYOUTS && mode() != LAYOUT_MISMATCH) return CUDA_ERROR_NO_BINARY_FOR_GPU;
    loaded_cubin = first_cubin((const unsigned char*)image);
    if (!loaded_cubin) return CUDA_ERROR_NO_BINARY_FOR_GPU;
    *m = (CUmodule)&loaded_cubin;
    return CUDA_SUCCESS;
}
static CUresult stub_cuModuleUnload(CUmodule m) {
    return m == (CUmodule)&loaded_cubin ? CUDA_SUCCESS : CUDA_ERROR_INVALID_HANDLE;
}
static CUresult stub_cuModuleGetFunction(CUfunction* f, CUmodule m, const char* name) {
    uint64_t size = 0;
    if (m != (CUmodule)&loaded_cubin) return CUDA_ERROR_INVALID_HANDLE;
    *f = (CUfunction)elf_symbol(loaded_cubin, name, &size);
    return *f ? CUDA_SUCCESS : CUDA_ERROR_NOT_FOUND;
}
/* A global's "device memory" is its initial data in the image. */
static CUresult stub_cuModuleGetGlobal(CUdeviceptr* p, size_t* bytes, CUmodule m, const char* name) {
    uint64_t size = 0;
    if (m != (CUmodule)&loaded_cubin) return CUDA_ERROR_INVALID_HANDLE;
    const unsigned char* data = elf_symbol(loaded_cubin, name, &size);
    if (!data) return CUDA_ERROR_NOT_FOUND;
    if (p) *p = (CUdeviceptr)(uintptr_t)data;
    if (bytes) *bytes = (size_t)size;
    return CUDA_SUCCESS;
}
static CUresult stub_cuMemcpyDtoH(void* dst, CUdeviceptr src, size_t n) {
    memcpy(dst, (const void*)(uintptr_t)src, n);
    if (mode() == LAYOUT_MISMATCH && n >= 4) { /* pbf_op_layout's first row: {size, align} */
        uint32_t size;
        memcpy(&size, dst, 4);
        size += 8;
        memcpy(dst, &size, 4);
    }
    return CUDA_SUCCESS;
}
/* Every other entry point: present, and refusing (none is called in the modes above). */
static CUresult stub_not_supported(void) { return CUDA_ERROR_NOT_SUPPORTED; }

#define STUB_ENTRY(name) \
    { #name, (void*)stub_##name }
static const struct {
    const char* name;
    void* fn;
} entries[] = {
    STUB_ENTRY(cuDriverGetVersion),       STUB_ENTRY(cuInit),
    STUB_ENTRY(cuGetErrorName),           STUB_ENTRY(cuGetErrorString),
    STUB_ENTRY(cuDeviceGetCount),         STUB_ENTRY(cuDeviceGet),
    STUB_ENTRY(cuDeviceGetName),          STUB_ENTRY(cuDeviceGetAttribute),
    STUB_ENTRY(cuDevicePrimaryCtxRetain), STUB_ENTRY(cuDevicePrimaryCtxRelease),
    STUB_ENTRY(cuCtxSetCurrent),          STUB_ENTRY(cuModuleLoadData),
    STUB_ENTRY(cuModuleUnload),           STUB_ENTRY(cuModuleGetFunction),
    STUB_ENTRY(cuModuleGetGlobal),        STUB_ENTRY(cuMemcpyDtoH),
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
