// Helpers shared by the C ABI's translation units: the thread-local error message, the log,
// exception guarding, struct_size checks and the world table with its lock. Internal: nothing
// here is exported.
#pragma once
#include <cstring>
#include <memory>
#include <mutex>
#include <new>
#include <stdexcept>
#include <string>

#include "../world/world.h"
#include "pbf_c_api.h"
#include "validate.h"

namespace pbf::api {

// ---- errors and log (errors.cpp) ------------------------------------------------------------
// Sends message to the log callback (if any).
void log_message(pbf_log_level level, const std::string& message);

// Sets the calling thread's last error ("CODE: message"), logs it and returns code.
pbf_result fail(pbf_result code, const std::string& message);
inline pbf_result fail(const Status& s) { return s.ok() ? PBF_OK : fail(s.code, s.message); }
// The same, naming the C function the failure came from.
inline pbf_result fail(const char* fn, const Status& s) {
    return s.ok() ? PBF_OK : fail(s.code, std::string(fn) + ": " + s.message);
}

// Runs body(fn), mapping exceptions to result codes so nothing unwinds into the caller's C code.
// fn is the C function's name (its __func__), which the messages of its failures start with.
template <class F>
pbf_result guarded(const char* fn, F&& body) {
    try {
        return body(fn);
    } catch (const std::bad_alloc&) {
        return fail(PBF_ERROR_OUT_OF_MEMORY, std::string(fn) + ": host allocation failed");
    } catch (const std::exception& e) {
        return fail(PBF_ERROR_INTERNAL, std::string(fn) + ": " + e.what());
    } catch (...) {
        return fail(PBF_ERROR_INTERNAL, std::string(fn) + ": unknown exception");
    }
}

#define PBF_REQUIRE(cond, code, msg)                         \
    do {                                                     \
        if (!(cond)) return ::pbf::api::fail((code), (msg)); \
    } while (0)
#define PBF_REQUIRE_ARG(cond, msg) PBF_REQUIRE(cond, PBF_ERROR_INVALID_ARGUMENT, std::string(fn) + ": " + (msg))

pbf_result check_struct(const char* fn, const char* type, const void* p, uint32_t struct_size, size_t expected);
#define PBF_CHECK_STRUCT(type, p)                                                                                \
    do {                                                                                                         \
        if (pbf_result r_ = ::pbf::api::check_struct(fn, #type, (p), (p) ? (p)->struct_size : 0u, sizeof(type)); \
            r_ != PBF_OK)                                                                                        \
            return r_;                                                                                           \
    } while (0)

// The start of a call that creates an object from a desc: out must be non-NULL (out_name is its
// parameter's name in the message) and holds the null handle until the call succeeds; d must be
// a `type` of its struct_size.
#define PBF_START_CREATE(type, d, out, out_name)            \
    PBF_REQUIRE_ARG((out) != nullptr, out_name " is NULL"); \
    *(out) = {};                                            \
    PBF_CHECK_STRUCT(type, d)

// The world computes source (a render buffer is only there when desc.render.flags asked for it):
// PBF_ERROR_INVALID_STATE with the flag to set otherwise. source is a valid pbf_buffer.
inline pbf_result require_buffer(const char* fn, World& w, pbf_buffer source) {
    if (w.has_buffer(source)) return PBF_OK;
    if (source == PBF_BUFFER_DIFFUSE_POSITIONS || source == PBF_BUFFER_DIFFUSE_VELOCITIES)
        return fail(PBF_ERROR_INVALID_STATE, std::string(fn) +
                                                 ": diffuse particles are off: this world has no "
                                                 "diffuse capacity (create it with desc.diffuse.max_diffuse > 0)");
    const char* flag = source == PBF_BUFFER_ANISOTROPY ? "PBF_RENDER_ANISOTROPY" : "PBF_RENDER_SMOOTHED_POSITIONS";
    return fail(PBF_ERROR_INVALID_STATE, std::string(fn) + ": render data is off: this world does not compute " +
                                             (source == PBF_BUFFER_ANISOTROPY ? "anisotropy" : "smoothed positions") +
                                             " (create it with desc.render.flags including " + flag + ")");
}

// ---- the world table (world_table.cpp) ------------------------------------------------------
// shared_ptr entries: a call holding an entry keeps it alive while pbf_world_destroy runs on
// another thread; the entry's mutex serialises calls on one world.
struct WorldEntry {
    std::mutex mutex;
    std::unique_ptr<World> world;  // null once destroyed
};

// Adds a world to the table and returns its handle.
pbf_world_id insert_world(std::unique_ptr<World> world);
// Takes the world out of the table (null if the handle is not live); the caller destroys it
// under the entry's mutex.
std::shared_ptr<WorldEntry> remove_world(pbf_world_id id);

// Locks the world for the duration of a call, or explains why the handle is not valid (quiet:
// without setting the thread's error or logging, for callers that expect stale handles).
class WorldLock {
public:
    WorldLock(const char* fn, pbf_world_id id, bool quiet = false);
    explicit operator bool() const { return entry_ != nullptr; }
    pbf_result result() const { return result_; }
    World* operator->() const { return entry_->world.get(); }
    World& operator*() const { return *entry_->world; }

private:
    std::shared_ptr<WorldEntry> entry_;
    std::unique_lock<std::mutex> lock_;
    pbf_result result_ = PBF_OK;
};

#define PBF_LOCK_WORLD(w, id)        \
    ::pbf::api::WorldLock w(fn, id); \
    if (!w) return w.result()

// The shape of a call that reads a world's parameters: out is a `type` of its struct_size; then
// *out = (world.*read)().
template <class P>
pbf_result get_params(const char* fn, const char* type, pbf_world_id id, P* out, const P& (World::*read)() const) {
    return guarded(fn, [&](const char*) -> pbf_result {
        if (pbf_result r = check_struct(fn, type, out, out ? out->struct_size : 0u, sizeof(P)); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        *out = ((*w).*read)();
        return PBF_OK;
    });
}

// A parameter fixed at world creation (the world's buffers were sized by it): `what` ("render.flags
// are") keeps the value `have`, or the call is refused.
inline pbf_result require_fixed(const char* fn, const char* what, uint32_t have, uint32_t got) {
    if (got == have) return PBF_OK;
    return fail(PBF_ERROR_INVALID_STATE, std::string(fn) + ": " + what +
                                             " fixed at world creation (its buffers are allocated then): this world "
                                             "has " +
                                             std::to_string(have) + ", got " + std::to_string(got));
}

}  // namespace pbf::api
