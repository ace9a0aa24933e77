// The error state of the C ABI: the calling thread's last message and validation check, the
// log callback, and the version and result-code calls that read them.
#include <mutex>
#include <string>

#include "api_common.h"

namespace {
thread_local std::string t_last_error;
thread_local pbf::api::Check t_last_check = pbf::api::Check::ok;
std::recursive_mutex g_log_mutex;  // recursive: an error raised inside the callback does not self-deadlock
pbf_log_fn g_log_fn = nullptr;
void* g_log_user = nullptr;
}  // namespace

namespace pbf::api {

void log_message(pbf_log_level level, const std::string& message) {
    std::lock_guard<std::recursive_mutex> lock(g_log_mutex);
    if (g_log_fn) g_log_fn(level, message.c_str(), g_log_user);
}

pbf_result fail(pbf_result code, const std::string& message) {
    t_last_error = std::string(pbf_result_string(code)) + ": " + message;
    t_last_check = Check::ok;
    log_message(PBF_LOG_ERROR, t_last_error);
    return code;
}

pbf_result refuse(const char* fn, const Verdict& v) {
    const pbf_result code = fail(check_code(v.check), std::string(fn) + ": " + check_message(v));
    t_last_check = v.check;
    return code;
}

Check last_validation_check() { return t_last_check; }

pbf_result check_struct(const char* fn, const char* type, const void* p, uint32_t struct_size, size_t expected) {
    if (!p) return fail(PBF_ERROR_INVALID_ARGUMENT, std::string(fn) + ": " + type + " pointer is NULL");
    if (struct_size != expected)
        return fail(PBF_ERROR_STRUCT_SIZE, std::string(fn) + ": " + type + ".struct_size is " +
                                               std::to_string(struct_size) + ", the library's " + type + " is " +
                                               std::to_string(expected) + " bytes (use " + type +
                                               "_default() from the matching header)");
    return PBF_OK;
}

}  // namespace pbf::api

using pbf::api::raw;

extern "C" {

PBF_API uint32_t PBF_CALL pbf_get_version(void) { return PBF_VERSION; }

PBF_API const char* PBF_CALL pbf_last_error_message(void) { return t_last_error.c_str(); }

PBF_API const char* PBF_CALL pbf_result_string(pbf_result r) {
    switch (raw(r)) {  // any int a C caller passes, without an out-of-range enum load
        case PBF_OK:
            return "PBF_OK";
        case PBF_ERROR_INVALID_ARGUMENT:
            return "PBF_ERROR_INVALID_ARGUMENT";
        case PBF_ERROR_INVALID_HANDLE:
            return "PBF_ERROR_INVALID_HANDLE";
        case PBF_ERROR_STRUCT_SIZE:
            return "PBF_ERROR_STRUCT_SIZE";
        case PBF_ERROR_VERSION_MISMATCH:
            return "PBF_ERROR_VERSION_MISMATCH";
        case PBF_ERROR_CAPACITY:
            return "PBF_ERROR_CAPACITY";
        case PBF_ERROR_OUT_OF_MEMORY:
            return "PBF_ERROR_OUT_OF_MEMORY";
        case PBF_ERROR_BACKEND_UNAVAILABLE:
            return "PBF_ERROR_BACKEND_UNAVAILABLE";
        case PBF_ERROR_BACKEND:
            return "PBF_ERROR_BACKEND";
        case PBF_ERROR_INVALID_STATE:
            return "PBF_ERROR_INVALID_STATE";
        case PBF_ERROR_INTERNAL:
            return "PBF_ERROR_INTERNAL";
        default:
            return "PBF_ERROR_UNKNOWN";
    }
}

PBF_API void PBF_CALL pbf_set_log_callback(pbf_log_fn callback, void* user_data) {
    std::lock_guard<std::recursive_mutex> lock(g_log_mutex);
    g_log_fn = callback;
    g_log_user = user_data;
}

}  // extern "C"
