// How libpbf finds the GPU at run time, through the public header only: the system's driver (or
// none), a driver library that is not there, and the stub driver of tests/stub_driver playing a
// machine without a usable GPU. The driver is opened once per process, so each case runs in its
// own process with its own environment (tests/stub_driver/cases.txt; ctest label `backend`, and
// scripts/check_windows.sh under Wine); a case's test is hidden ([.]) and checks that it was
// started with the environment it expects.
#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "support.h"

#if defined(_WIN32)
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <windows.h>
#else
#include <dlfcn.h>
#endif

namespace {

std::string env(const char* name) {
    const char* v = std::getenv(name);
    return v ? v : "";
}

pbf_backend_info backend_info(pbf_backend backend, int32_t device) {
    pbf_backend_info info{};
    info.struct_size = sizeof info;
    REQUIRE_OK(pbf_get_backend_info(backend, device, &info));
    return info;
}

// The log lines of the calls in between.
struct LogCapture {
    static std::mutex mutex;
    static std::vector<std::string> lines;
    static void PBF_CALL log(pbf_log_level, const char* message, void*) {
        std::lock_guard<std::mutex> lock(mutex);
        lines.emplace_back(message);
    }
    LogCapture() {
        lines.clear();
        pbf_set_log_callback(&LogCapture::log, nullptr);
    }
    ~LogCapture() { pbf_set_log_callback(nullptr, nullptr); }
    bool has(const std::string& line) const {
        std::lock_guard<std::mutex> lock(mutex);
        return std::find(lines.begin(), lines.end(), line) != lines.end();
    }
};
std::mutex LogCapture::mutex;
std::vector<std::string> LogCapture::lines;

float lowest_y(const TestWorld& w) {
    const std::vector<float> p = w.positions();
    float y = 1e9f;
    for (size_t i = 0; i < p.size(); i += 4) y = std::min(y, p[i + 1]);
    return y;
}

// A world of `backend` on device 0 steps a falling block of water: it falls.
void check_world_runs(pbf_backend backend, pbf_backend expected) {
    pbf_world_desc d = small_desc();
    d.backend = backend;
    d.cuda_device = 0;
    TestWorld w(d);
    pbf_world_info info{};
    info.struct_size = sizeof info;
    REQUIRE_OK(pbf_world_get_info(w, &info));
    CHECK(info.backend == expected);
    const uint32_t n = w.emit(block(-0.15f, 0.5f, -0.15f, 0.15f, 0.8f, 0.15f));
    REQUIRE(n == 216u);
    const float y0 = lowest_y(w);
    for (int i = 0; i < 10; ++i) REQUIRE_OK(pbf_world_step(w, kDt));
    REQUIRE(w.count() == n);
    // Free fall for 10/60 s: 0.136 m; the pressure solve spreads the block, so only a part.
    CHECK(lowest_y(w) < y0 - 0.05f);
}

// CUDA device 0 is refused with `status`, the message containing every one of `fragments`; AUTO
// takes the CPU and says why, a CUDA world is refused with that message, and an AUTO world runs.
void check_cuda_refused(pbf_backend_status status, const std::vector<std::string>& fragments) {
    const pbf_backend_info cuda = backend_info(PBF_BACKEND_CUDA, 0);
    INFO("CUDA: status " << int(cuda.status) << ", \"" << cuda.message << "\"");
    CHECK(cuda.backend == PBF_BACKEND_CUDA);
    CHECK(int(cuda.status) == int(status));
    CHECK(cuda.cuda_device == 0);
    for (const std::string& f : fragments) CHECK_THAT(cuda.message, Catch::Contains(f));

    const pbf_backend_info autob = backend_info(PBF_BACKEND_AUTO, 0);
    CHECK(autob.backend == PBF_BACKEND_CPU);
    CHECK(autob.status == PBF_BACKEND_STATUS_AVAILABLE);
    CHECK(autob.cuda_device == -1);
    CHECK_THAT(autob.device_name, Catch::StartsWith("CPU"));
    CHECK(std::string(autob.message) == "CUDA not taken: " + std::string(cuda.message));
    CHECK(autob.driver_version == cuda.driver_version);
    CHECK(autob.device_count == cuda.device_count);
    CHECK(autob.required_driver_version == cuda.required_driver_version);

    pbf_world_desc d = small_desc();
    d.backend = PBF_BACKEND_CUDA;
    pbf_world_id id{4, 4};
    CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_BACKEND_UNAVAILABLE, cuda.message);
    CHECK(id.generation == 0);

    LogCapture log;
    check_world_runs(PBF_BACKEND_AUTO, PBF_BACKEND_CPU);
    CHECK(log.has("CUDA not taken: " + std::string(cuda.message)));
}

// The stub's count of calls to an entry point (tests/stub_driver), from the copy libpbf opened:
// the test does not open it a second time.
int stub_calls(const char* entry) {
    const std::string path = env("PBF_CUDA_DRIVER");
#if defined(_WIN32)
    void* lib = reinterpret_cast<void*>(GetModuleHandleA(path.c_str()));
    auto fn =
        lib ? reinterpret_cast<int (*)(const char*)>(GetProcAddress(static_cast<HMODULE>(lib), "pbf_stub_cuda_calls"))
            : nullptr;
#else
    void* lib = dlopen(path.c_str(), RTLD_NOW | RTLD_NOLOAD);
    auto fn = lib ? reinterpret_cast<int (*)(const char*)>(dlsym(lib, "pbf_stub_cuda_calls")) : nullptr;
#endif
    INFO("the stub driver " << path << " is " << (lib ? "loaded" : "not loaded") << " in this process");
    REQUIRE(fn != nullptr);
    return fn(entry);
}

// The case's environment, as tests/stub_driver/cases.txt gives it.
void require_stub(const char* mode) {
    INFO(
        "run through ctest -L backend (or scripts/check_windows.sh): PBF_CUDA_DRIVER must name the stub driver "
        "and PBF_STUB_CUDA be "
        << mode);
    REQUIRE(!env("PBF_CUDA_DRIVER").empty());
    REQUIRE(env("PBF_STUB_CUDA") == mode);
}

std::string version_text(int v) { return std::to_string(v / 1000) + "." + std::to_string(v % 1000 / 10); }

}  // namespace

#if PBF_TEST_HAVE_CUDA_BACKEND

TEST_CASE("driver: the system's driver, or none", "[.][driver-system]") {
    REQUIRE(env("PBF_CUDA_DRIVER").empty());
    // Whether this machine has a driver, looked up where libpbf looks: the loader's search on
    // Linux, System32 only on Windows.
#if defined(_WIN32)
    const char* name = "nvcuda.dll";
    const bool system_driver = LoadLibraryExA(name, nullptr, LOAD_LIBRARY_SEARCH_SYSTEM32) != nullptr;
#else
    const char* name = "libcuda.so.1";
    const bool system_driver = dlopen(name, RTLD_NOW | RTLD_LOCAL) != nullptr;
#endif
    const pbf_backend_info cuda = backend_info(PBF_BACKEND_CUDA, 0);
    INFO("system driver " << (system_driver ? "present" : "absent") << "; CUDA: status " << int(cuda.status) << ", \""
                          << cuda.message << "\"");
    if (!system_driver) {
        check_cuda_refused(PBF_BACKEND_STATUS_NO_DRIVER, {"no NVIDIA driver", name, "could not be opened"});
        CHECK(cuda.driver_version == 0);
        CHECK(cuda.device_count == 0);
        CHECK(cuda.required_driver_version >= 13000);
    } else if (cuda.status == PBF_BACKEND_STATUS_AVAILABLE) {
        CHECK(cuda.device_count >= 1);
        CHECK(cuda.driver_version >= cuda.required_driver_version);
        CHECK(backend_info(PBF_BACKEND_AUTO, 0).backend == PBF_BACKEND_CUDA);
        check_world_runs(PBF_BACKEND_CUDA, PBF_BACKEND_CUDA);
    } else {
        CHECK(cuda.status != PBF_BACKEND_STATUS_NO_DRIVER);
        check_cuda_refused(cuda.status, {});
    }
#if defined(_WIN32)
    // The build puts the stub driver beside this program as nvcuda.dll, where Windows' default
    // search would find it; libpbf took the system's (or none) instead.
    HMODULE planted = LoadLibraryA(name);
    REQUIRE(planted != nullptr);
    if (!system_driver) CHECK(GetProcAddress(planted, "pbf_stub_cuda_calls") != nullptr);
    CHECK(cuda.status == backend_info(PBF_BACKEND_CUDA, 0).status);
#endif
}

TEST_CASE("driver: a driver library that is not there -> NO_DRIVER", "[.][driver-absent]") {
    const std::string path = env("PBF_CUDA_DRIVER");
    REQUIRE(!path.empty());
    REQUIRE(std::fopen(path.c_str(), "rb") == nullptr);
    check_cuda_refused(PBF_BACKEND_STATUS_NO_DRIVER, {"no NVIDIA driver: " + path + " could not be opened"});
    CHECK(backend_info(PBF_BACKEND_CUDA, 0).driver_version == 0);
}

TEST_CASE("driver: cuInit finds no device -> NO_DEVICE", "[.][driver-no-device]") {
    require_stub("no-device");
    check_cuda_refused(PBF_BACKEND_STATUS_NO_DEVICE,
                       {"found no CUDA device", "CUDA " + version_text(PBF_TEST_STUB_CUDA_VERSION)});
    CHECK(backend_info(PBF_BACKEND_CUDA, 0).driver_version == PBF_TEST_STUB_CUDA_VERSION);
    CHECK(stub_calls("cuInit") == 1);
}

TEST_CASE("driver: cuGetProcAddress of CUDA 11 (no _v2) serves as well", "[.][driver-v1-no-device]") {
    require_stub("no-device");
    check_cuda_refused(PBF_BACKEND_STATUS_NO_DEVICE, {"found no CUDA device"});
    CHECK(stub_calls("cuInit") == 1);
}

TEST_CASE("driver: a driver older than the kernels -> DRIVER_TOO_OLD", "[.][driver-old-driver]") {
    require_stub("old-driver");
    const pbf_backend_info cuda = backend_info(PBF_BACKEND_CUDA, 0);
    CHECK(cuda.driver_version == 12080);
    CHECK(cuda.required_driver_version > cuda.driver_version);
    check_cuda_refused(PBF_BACKEND_STATUS_DRIVER_TOO_OLD,
                       {"supports CUDA 12.8", "need CUDA " + version_text(cuda.required_driver_version),
                        "update the graphics driver"});
    CHECK(stub_calls("cuInit") == 0);  // refused before starting it
}

TEST_CASE("driver: cuInit fails -> DRIVER_ERROR naming the error", "[.][driver-init-error]") {
    require_stub("init-error");
    check_cuda_refused(PBF_BACKEND_STATUS_DRIVER_ERROR,
                       {"failed to start", "cuInit returned CUDA_ERROR_SYSTEM_DRIVER_MISMATCH"});
}

TEST_CASE("driver: started, zero devices -> NO_DEVICE", "[.][driver-no-devices]") {
    require_stub("no-devices");
    check_cuda_refused(PBF_BACKEND_STATUS_NO_DEVICE, {"found no CUDA device"});
    CHECK(backend_info(PBF_BACKEND_CUDA, 0).device_count == 0);
}

TEST_CASE("driver: an entry point missing -> DRIVER_TOO_OLD naming it", "[.][driver-missing-entry]") {
    require_stub("missing-entry");
    check_cuda_refused(PBF_BACKEND_STATUS_DRIVER_TOO_OLD, {"lacks cuLaunchKernel"});
}

TEST_CASE("driver: no cuGetProcAddress at all -> DRIVER_TOO_OLD", "[.][driver-no-proc-address]") {
    require_stub("no-device");  // what it would say, could libpbf ask it
    check_cuda_refused(PBF_BACKEND_STATUS_DRIVER_TOO_OLD, {"too old", "has no cuGetProcAddress"});
    CHECK(stub_calls("cuInit") == 0);
}

TEST_CASE("driver: a GPU older than the kernels -> DEVICE_UNSUPPORTED; a device that is not there -> NO_DEVICE",
          "[.][driver-old-gpu]") {
    require_stub("old-gpu");
    check_cuda_refused(PBF_BACKEND_STATUS_DEVICE_UNSUPPORTED,
                       {"Stub GPU 61 has compute capability 6.1", "need 7.5 or newer"});
    const pbf_backend_info cuda = backend_info(PBF_BACKEND_CUDA, 0);
    CHECK(cuda.device_count == 1);
    CHECK(std::string(cuda.device_name) == "Stub GPU 61");
    CHECK(stub_calls("cuDevicePrimaryCtxRetain") == 0);  // refused before making a context

    const pbf_backend_info second = backend_info(PBF_BACKEND_CUDA, 1);
    CHECK(second.status == PBF_BACKEND_STATUS_NO_DEVICE);
    CHECK(second.cuda_device == 1);
    CHECK_THAT(second.message, Catch::Contains("there is no CUDA device 1"));
    pbf_world_desc d = small_desc();
    d.backend = PBF_BACKEND_CUDA;
    d.cuda_device = 1;
    pbf_world_id id{4, 4};
    CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_BACKEND_UNAVAILABLE, "there is no CUDA device 1");
}

TEST_CASE("driver: the embedded fatbin reaches the driver; no code for the GPU -> DEVICE_UNSUPPORTED",
          "[.][driver-no-binary]") {
    require_stub("no-binary");
    // The stub answers NO_BINARY_FOR_GPU only for an image that starts as a fatbin does
    // (INVALID_IMAGE otherwise, which would be DRIVER_ERROR).
    check_cuda_refused(
        PBF_BACKEND_STATUS_DEVICE_UNSUPPORTED,
        {"have no code that runs on Stub GPU 86 (compute capability 8.6)", "CUDA_ERROR_NO_BINARY_FOR_GPU"});
    CHECK(stub_calls("cuModuleLoadData") >= 1);
    // Each failed load gives back the context it took.
    CHECK(stub_calls("cuDevicePrimaryCtxRetain") == stub_calls("cuModuleLoadData"));
    CHECK(stub_calls("cuDevicePrimaryCtxRelease") == stub_calls("cuDevicePrimaryCtxRetain"));
}

TEST_CASE("driver: the kernels' op layouts agree with this compiler's; every kernel is in the fatbin",
          "[.][driver-layouts]") {
    require_stub("layouts");
    // The stub serves the kernels and pbf_op_layout from the fatbin's first cubin: the load
    // succeeds only if every kernel the library asks for is there and the layouts nvcc chose are
    // this host compiler's (on Windows: MinGW's LLP64 against nvcc's LP64).
    const pbf_backend_info cuda = backend_info(PBF_BACKEND_CUDA, 0);
    INFO("CUDA: status " << int(cuda.status) << ", \"" << cuda.message << "\"");
    CHECK(cuda.status == PBF_BACKEND_STATUS_AVAILABLE);
    CHECK(std::string(cuda.device_name) == "Stub GPU 86");
    CHECK_THAT(cuda.message, Catch::StartsWith("CUDA device 0 (Stub GPU 86) through NVIDIA driver"));
    CHECK(backend_info(PBF_BACKEND_AUTO, 0).backend == PBF_BACKEND_CUDA);
    CHECK(stub_calls("cuModuleLoadData") == 1);  // loaded once, kept
    CHECK(stub_calls("cuDevicePrimaryCtxRelease") == 0);
}

TEST_CASE("driver: an op whose layout differs from the kernels' -> DRIVER_ERROR", "[.][driver-layout-mismatch]") {
    require_stub("layout-mismatch");
    check_cuda_refused(PBF_BACKEND_STATUS_DRIVER_ERROR,
                       {"libpbf's kernels and its host code disagree on", "mismatched sources or compilers"});
    CHECK(stub_calls("cuDevicePrimaryCtxRelease") == stub_calls("cuDevicePrimaryCtxRetain"));
}

#else

TEST_CASE("driver: a build without CUDA -> NOT_BUILT", "[.][driver-not-built]") {
    check_cuda_refused(PBF_BACKEND_STATUS_NOT_BUILT, {"built without CUDA"});
    CHECK(backend_info(PBF_BACKEND_CUDA, 0).required_driver_version == 0);
}

#endif
