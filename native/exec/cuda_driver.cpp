// Opening the CUDA driver at run time (cuda_driver.h).
#include "cuda_driver.h"

#include <cstdlib>

#include "../common/windows_lean.h"
#if !defined(_WIN32)
#include <dlfcn.h>
#endif

namespace pbf::cuda {
namespace {

#if defined(_WIN32)
constexpr const char* kDriverLibrary = "nvcuda.dll";

void* open_library(const char* path, bool system_only, std::string* error) {
    // The system's driver is taken from System32 only, so that a DLL of that name planted beside
    // the game is never loaded in its place; a path named by PBF_CUDA_DRIVER is loaded as given.
    HMODULE h = system_only ? LoadLibraryExA(path, nullptr, LOAD_LIBRARY_SEARCH_SYSTEM32) : LoadLibraryA(path);
    if (!h) *error = "Windows error " + std::to_string(GetLastError());
    return reinterpret_cast<void*>(h);
}
void* find_symbol(void* library, const char* name) {
    return reinterpret_cast<void*>(GetProcAddress(static_cast<HMODULE>(library), name));
}
#else
constexpr const char* kDriverLibrary = "libcuda.so.1";

void* open_library(const char* path, bool, std::string* error) {
    void* h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char* e = dlerror();
        *error = e ? e : "dlopen failed";
    }
    return h;
}
void* find_symbol(void* library, const char* name) { return dlsym(library, name); }
#endif

std::string version_text(int v) { return std::to_string(v / 1000) + "." + std::to_string(v % 1000 / 10); }

struct Loaded {
    Driver driver;
    CudaAvailability availability;
};

Loaded load() {
    Loaded l;
    CudaAvailability& a = l.availability;
    a.required_driver_version = kRequiredDriverVersion;
    const char* chosen = std::getenv("PBF_CUDA_DRIVER");
    const bool system = chosen == nullptr || *chosen == '\0';
    const std::string path = system ? kDriverLibrary : chosen;
    auto refuse = [&](pbf_backend_status status, std::string why) {
        a.status = status;
        a.message = std::move(why);
        return l;
    };
    std::string error;
    // Never closed: the driver's entry points stay valid for the life of the process.
    void* library = open_library(path.c_str(), system, &error);
    if (!library)
        return refuse(PBF_BACKEND_STATUS_NO_DRIVER,
                      "no NVIDIA driver: " + path + " could not be opened (" + error + ")");

    // cuGetProcAddress (CUDA 11.3) hands out each entry point at the ABI version asked for;
    // CUDA 12 added a fifth argument and named that version _v2.
    auto get_v2 = reinterpret_cast<PFN_cuGetProcAddress_v12000>(find_symbol(library, "cuGetProcAddress_v2"));
    auto get_v1 = reinterpret_cast<PFN_cuGetProcAddress_v11030>(find_symbol(library, "cuGetProcAddress"));
    if (!get_v2 && !get_v1)
        return refuse(
            PBF_BACKEND_STATUS_DRIVER_TOO_OLD,
            "the NVIDIA driver " + path + " is too old: it has no cuGetProcAddress (CUDA 11.3 and later have)");
    auto get = [&](const char* name, int version, void** out) {
        *out = nullptr;
        CUresult e;
        if (get_v2) {
            CUdriverProcAddressQueryResult found = CU_GET_PROC_ADDRESS_SYMBOL_NOT_FOUND;
            e = get_v2(name, out, version, CU_GET_PROC_ADDRESS_DEFAULT, &found);
            if (found != CU_GET_PROC_ADDRESS_SUCCESS) *out = nullptr;
        } else {
            e = get_v1(name, out, version, CU_GET_PROC_ADDRESS_DEFAULT);
        }
        if (e != CUDA_SUCCESS) *out = nullptr;
        return *out != nullptr;
    };

    PFN_cuDriverGetVersion_v2020 get_version = nullptr;
    PFN_cuInit_v2000 init = nullptr;
    Driver& d = l.driver;
    if (!get("cuDriverGetVersion", 2020, reinterpret_cast<void**>(&get_version)) ||
        !get("cuInit", 2000, reinterpret_cast<void**>(&init)) ||
        !get("cuGetErrorName", 6000, reinterpret_cast<void**>(&d.cuGetErrorName)))
        return refuse(PBF_BACKEND_STATUS_DRIVER_TOO_OLD,
                      "the NVIDIA driver " + path + " does not provide cuDriverGetVersion, cuInit and cuGetErrorName");
    if (get_version(&a.driver_version) != CUDA_SUCCESS) a.driver_version = 0;
    if (a.driver_version < kRequiredDriverVersion)
        return refuse(PBF_BACKEND_STATUS_DRIVER_TOO_OLD,
                      "the NVIDIA driver supports CUDA " + version_text(a.driver_version) +
                          "; libpbf's kernels need CUDA " + version_text(kRequiredDriverVersion) +
                          " or newer: update the graphics driver");
    const CUresult started = init(0);
    if (started == CUDA_ERROR_NO_DEVICE)
        return refuse(PBF_BACKEND_STATUS_NO_DEVICE,
                      "the NVIDIA driver (CUDA " + version_text(a.driver_version) + ") found no CUDA device");
    if (started != CUDA_SUCCESS) {
        const char* name = nullptr;
        d.cuGetErrorName(started, &name);
        return refuse(PBF_BACKEND_STATUS_DRIVER_ERROR,
                      std::string("the NVIDIA driver failed to start: cuInit returned ") +
                          (name ? name : std::to_string(int(started)).c_str()));
    }
#define PBF_CUDA_REQUIRE(name, version)                          \
    if (!get(#name, version, reinterpret_cast<void**>(&d.name))) \
        return refuse(PBF_BACKEND_STATUS_DRIVER_TOO_OLD,         \
                      "the NVIDIA driver (CUDA " + version_text(a.driver_version) + ") lacks " #name);
    PBF_CUDA_REQUIRED_ENTRY_POINTS(PBF_CUDA_REQUIRE)
#undef PBF_CUDA_REQUIRE
#define PBF_CUDA_OPTIONAL(name, version) get(#name, version, reinterpret_cast<void**>(&d.name));
    PBF_CUDA_OPTIONAL_ENTRY_POINTS(PBF_CUDA_OPTIONAL)
#undef PBF_CUDA_OPTIONAL
    if (d.cuDeviceGetCount(&a.device_count) != CUDA_SUCCESS) a.device_count = 0;
    d.version = a.driver_version;
    d.device_count = a.device_count;
    if (a.device_count == 0)
        return refuse(PBF_BACKEND_STATUS_NO_DEVICE,
                      "the NVIDIA driver (CUDA " + version_text(a.driver_version) + ") found no CUDA device");
    a.status = PBF_BACKEND_STATUS_AVAILABLE;
    a.message = "NVIDIA driver " + path + " (CUDA " + version_text(a.driver_version) + "), " +
                std::to_string(a.device_count) + " CUDA device" + (a.device_count == 1 ? "" : "s");
    return l;
}

const Loaded& loaded() {
    static const Loaded l = load();  // once per process; concurrent first calls wait for it
    return l;
}

}  // namespace

const Driver* driver() { return loaded().availability.ok() ? &loaded().driver : nullptr; }

const CudaAvailability& driver_availability() { return loaded().availability; }

std::string error_text(CUresult e) {
    const Driver* d = driver();
    const char* name = nullptr;
    const char* text = nullptr;
    if (d) {
        d->cuGetErrorName(e, &name);
        d->cuGetErrorString(e, &text);
    }
    std::string s = name ? name : "CUDA error " + std::to_string(int(e));
    if (text) s += std::string(" (") + text + ")";
    return s;
}

}  // namespace pbf::cuda
