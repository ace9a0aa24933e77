// Loading the embedded kernels per device (cuda_module.h) and the availability of a device.
#include "cuda_module.h"

#include <chrono>
#include <map>
#include <memory>
#include <mutex>

extern "C" {
// The fatbin's bytes, placed by the generated cuda_fatbin.c (start and one past the end).
extern const unsigned char pbf_kernels_fatbin[];
extern const unsigned char pbf_kernels_fatbin_end[];
}

namespace pbf::cuda {

const unsigned char* embedded_fatbin() { return pbf_kernels_fatbin; }
size_t embedded_fatbin_bytes() { return size_t(pbf_kernels_fatbin_end - pbf_kernels_fatbin); }

namespace {

constexpr int kMinMajor = 7, kMinMinor = 5;  // the oldest GPU the fatbin carries code for (Turing)

// The host compiler's layout of every op and by-value struct, in the kernels' table order.
CudaOpLayout host_layout(uint32_t row) {
#define PBF_HOST_LAYOUT(name, ...) {uint32_t(sizeof(__VA_ARGS__)), uint32_t(alignof(__VA_ARGS__))},
    static const CudaOpLayout rows[kCudaOpCount + 3] = {
        PBF_CUDA_OPS(PBF_HOST_LAYOUT){uint32_t(sizeof(WorldConstants)), uint32_t(alignof(WorldConstants))},
        {uint32_t(sizeof(HeightFrame)), uint32_t(alignof(HeightFrame))},
        {uint32_t(kCudaOpCount), uint32_t(PBF_CUDA_BLOCK)},
    };
#undef PBF_HOST_LAYOUT
    return rows[row];
}

const char* layout_row_name(uint32_t row) {
#define PBF_LAYOUT_NAME(name, ...) #name,
    static const char* const names[kCudaOpCount + 3] = {PBF_CUDA_OPS(PBF_LAYOUT_NAME) "WorldConstants", "HeightFrame",
                                                        "op count and block size"};
#undef PBF_LAYOUT_NAME
    return names[row];
}

// Loads the module into the device's primary context and checks it; *why says what failed.
std::unique_ptr<Kernels> load(const Driver& cu, int32_t ordinal, CudaAvailability* why) {
    auto fail = [&](pbf_backend_status status, std::string message) -> std::unique_ptr<Kernels> {
        why->status = status;
        why->message = std::move(message);
        return nullptr;
    };
    auto k = std::make_unique<Kernels>();
    const auto t0 = std::chrono::steady_clock::now();
    CUresult e = cu.cuDeviceGet(&k->device, ordinal);
    if (e != CUDA_SUCCESS)
        return fail(PBF_BACKEND_STATUS_NO_DEVICE, "CUDA device " + std::to_string(ordinal) + ": " + error_text(e));
    char name[256] = {};
    cu.cuDeviceGetName(name, int(sizeof name) - 1, k->device);
    k->device_name = name;
    why->device_name = name;
    int major = 0, minor = 0;
    cu.cuDeviceGetAttribute(&major, CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MAJOR, k->device);
    cu.cuDeviceGetAttribute(&minor, CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MINOR, k->device);
    if (major * 10 + minor < kMinMajor * 10 + kMinMinor)
        return fail(PBF_BACKEND_STATUS_DEVICE_UNSUPPORTED, std::string(name) + " has compute capability " +
                                                               std::to_string(major) + "." + std::to_string(minor) +
                                                               "; libpbf's kernels need " + std::to_string(kMinMajor) +
                                                               "." + std::to_string(kMinMinor) + " or newer");
    // Retained for the life of the process: the module lives in this context.
    e = cu.cuDevicePrimaryCtxRetain(&k->context, k->device);
    if (e != CUDA_SUCCESS)
        return fail(PBF_BACKEND_STATUS_DRIVER_ERROR,
                    std::string("creating a context on ") + name + ": " + error_text(e));
    auto drop = [&](pbf_backend_status status, std::string message) {
        if (k->module) cu.cuModuleUnload(k->module);
        cu.cuDevicePrimaryCtxRelease(k->device);
        return fail(status, std::move(message));
    };
    e = cu.cuCtxSetCurrent(k->context);
    if (e == CUDA_SUCCESS) e = cu.cuModuleLoadData(&k->module, embedded_fatbin());
    if (e == CUDA_ERROR_NO_BINARY_FOR_GPU || e == CUDA_ERROR_INVALID_PTX || e == CUDA_ERROR_UNSUPPORTED_PTX_VERSION)
        return drop(PBF_BACKEND_STATUS_DEVICE_UNSUPPORTED, std::string("libpbf's kernels have no code that runs on ") +
                                                               name + " (compute capability " + std::to_string(major) +
                                                               "." + std::to_string(minor) + "): " + error_text(e));
    if (e != CUDA_SUCCESS)
        return drop(PBF_BACKEND_STATUS_DRIVER_ERROR,
                    std::string("loading libpbf's kernels on ") + name + ": " + error_text(e));
    for (uint32_t i = 0; i < kCudaOpCount; ++i) {
        static const char* const kernel_names[kCudaOpCount] = {
#define PBF_KERNEL_NAME(name, ...) "pbf_op_" #name,
            PBF_CUDA_OPS(PBF_KERNEL_NAME)
#undef PBF_KERNEL_NAME
        };
        e = cu.cuModuleGetFunction(&k->op[i], k->module, kernel_names[i]);
        if (e != CUDA_SUCCESS)
            return drop(PBF_BACKEND_STATUS_DRIVER_ERROR, std::string("libpbf's kernels lack ") + kernel_names[i] +
                                                             " (" + error_text(e) + "): a broken build");
    }
#define PBF_GET_KERNEL(name)                                       \
    e = cu.cuModuleGetFunction(&k->name, k->module, "pbf_" #name); \
    if (e != CUDA_SUCCESS)                                         \
        return drop(PBF_BACKEND_STATUS_DRIVER_ERROR,               \
                    "libpbf's kernels lack pbf_" #name " (" + error_text(e) + "): a broken build");
    PBF_CUDA_UTILITY_KERNELS(PBF_GET_KERNEL)
#undef PBF_GET_KERNEL
    // The op layouts nvcc chose must be this compiler's (cuda_ops.h).
    CudaOpLayout device_rows[kCudaOpCount + 3] = {};
    CUdeviceptr table = 0;
    size_t table_bytes = 0;
    e = cu.cuModuleGetGlobal(&table, &table_bytes, k->module, "pbf_op_layout");
    if (e == CUDA_SUCCESS && table_bytes != sizeof device_rows) e = CUDA_ERROR_INVALID_IMAGE;
    if (e == CUDA_SUCCESS) e = cu.cuMemcpyDtoH(device_rows, table, sizeof device_rows);
    if (e != CUDA_SUCCESS)
        return drop(PBF_BACKEND_STATUS_DRIVER_ERROR,
                    "reading the kernels' op layouts: " + error_text(e) + " (a broken build)");
    for (uint32_t r = 0; r < kCudaOpCount + 3; ++r) {
        const CudaOpLayout host = host_layout(r), dev = device_rows[r];
        if (host.size != dev.size || host.align != dev.align)
            return drop(PBF_BACKEND_STATUS_DRIVER_ERROR,
                        std::string("libpbf's kernels and its host code disagree on ") + layout_row_name(r) +
                            " (kernels " + std::to_string(dev.size) + " B aligned " + std::to_string(dev.align) +
                            ", host " + std::to_string(host.size) + " B aligned " + std::to_string(host.align) +
                            "): the library was built from mismatched sources or compilers");
    }
    k->load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return k;
}

}  // namespace

const Kernels* kernels(int32_t device, CudaAvailability* why) {
    *why = driver_availability();
    const Driver* cu = driver();
    if (!cu) return nullptr;
    if (device < 0 || device >= cu->device_count) {
        why->status = PBF_BACKEND_STATUS_NO_DEVICE;
        why->message = "there is no CUDA device " + std::to_string(device) + ": the NVIDIA driver reports " +
                       std::to_string(cu->device_count);
        return nullptr;
    }
    static std::mutex mutex;
    static std::map<int32_t, std::unique_ptr<Kernels>> loaded;
    std::lock_guard<std::mutex> lock(mutex);
    std::unique_ptr<Kernels>& slot = loaded[device];
    if (!slot) slot = load(*cu, device, why);  // a failure is retried on the next call
    if (!slot) return nullptr;
    why->device_name = slot->device_name;
    why->kernel_load_ms = slot->load_ms;
    return slot.get();
}

}  // namespace pbf::cuda

namespace pbf {

CudaAvailability cuda_availability(int32_t device) {
    CudaAvailability a;
    const cuda::Kernels* k = cuda::kernels(device, &a);
    if (k) {
        a.status = PBF_BACKEND_STATUS_AVAILABLE;
        a.message = "CUDA device " + std::to_string(device) + " (" + k->device_name + ") through " + a.message;
    }
    return a;
}

}  // namespace pbf
