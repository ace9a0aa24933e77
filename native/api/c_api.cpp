// The C ABI: validates every argument, translates handles to worlds, turns exceptions and
// failures into result codes with a thread-local message. Nothing else lives here.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <new>
#include <string>

#include "../world/world.h"
#include "api_common.h"
#include "pbf_c_api.h"

using pbf::Status;
using pbf::World;
using pbf::api::fail;
using pbf::api::guarded;
using pbf::api::check_struct;
using pbf::api::log_message;
using pbf::api::WorldEntry;
using pbf::api::WorldLock;
using pbf::api::raw;

namespace {

// ---- errors and logging --------------------------------------------------------------------
thread_local std::string t_last_error;
std::recursive_mutex g_log_mutex;  // recursive: an error raised inside the callback does not self-deadlock
pbf_log_fn g_log_fn = nullptr;
void* g_log_user = nullptr;

// ---- the world table -----------------------------------------------------------------------
std::mutex g_worlds_mutex;
pbf::SlotTable<std::shared_ptr<WorldEntry>> g_worlds;

}  // namespace

namespace pbf::api {

void log_message(pbf_log_level level, const std::string& message) {
    std::lock_guard<std::recursive_mutex> lock(g_log_mutex);
    if (g_log_fn) g_log_fn(level, message.c_str(), g_log_user);
}

pbf_result fail(pbf_result code, const std::string& message) {
    t_last_error = std::string(pbf_result_string(code)) + ": " + message;
    log_message(PBF_LOG_ERROR, t_last_error);
    return code;
}

pbf_result check_struct(const char* fn, const char* type, const void* p, uint32_t struct_size, size_t expected) {
    if (!p) return fail(PBF_ERROR_INVALID_ARGUMENT, std::string(fn) + ": " + type + " pointer is NULL");
    if (struct_size != expected)
        return fail(PBF_ERROR_STRUCT_SIZE, std::string(fn) + ": " + type + ".struct_size is " +
                                               std::to_string(struct_size) + ", the library's " + type + " is " +
                                               std::to_string(expected) + " bytes (use " + type +
                                               "_default() from the matching header)");
    return PBF_OK;
}

WorldLock::WorldLock(const char* fn, pbf_world_id id, bool quiet) {
    {
        std::lock_guard<std::mutex> lock(g_worlds_mutex);
        if (auto* e = g_worlds.find(id.index, id.generation)) entry_ = *e;
    }
    if (entry_) {
        lock_ = std::unique_lock<std::mutex>(entry_->mutex);
        if (!entry_->world) {
            // Destroyed meanwhile: this may be the entry's last reference, so unlock before
            // letting it go (the mutex goes with it).
            lock_.unlock();
            entry_.reset();
        }
    }
    if (!entry_) {
        const std::string message = std::string(fn) + ": world {" + std::to_string(id.index) + ", " +
                                    std::to_string(id.generation) +
                                    "} is not a live world (destroyed or never created)";
        result_ = quiet ? PBF_ERROR_INVALID_HANDLE : fail(PBF_ERROR_INVALID_HANDLE, message);
    }
}

}  // namespace pbf::api

namespace {

// ---- argument checks -----------------------------------------------------------------------
bool finite3(const float v[3]) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

pbf_result check_solver_params(const char* fn, const pbf_solver_params* params) {
    PBF_CHECK_STRUCT(pbf_solver_params, params);
    const pbf_solver_params& p = *params;
    PBF_REQUIRE_ARG(p.iterations >= 1 && p.iterations <= 64, "solver.iterations must be 1..64");
    PBF_REQUIRE_ARG(p.substeps >= 1 && p.substeps <= 16, "solver.substeps must be 1..16");
    PBF_REQUIRE_ARG(std::isfinite(p.relaxation) && p.relaxation > 0.0f, "solver.relaxation must be finite and > 0");
    PBF_REQUIRE_ARG(std::isfinite(p.scorr_k) && p.scorr_k >= 0.0f && p.scorr_k <= 1.0f, "solver.scorr_k must be 0..1");
    PBF_REQUIRE_ARG(std::isfinite(p.scorr_n) && p.scorr_n >= 1.0f && p.scorr_n <= 8.0f, "solver.scorr_n must be 1..8");
    PBF_REQUIRE_ARG(std::isfinite(p.scorr_dq) && p.scorr_dq > 0.0f && p.scorr_dq < 1.0f,
                    "solver.scorr_dq must be in (0, 1) (a fraction of h)");
    PBF_REQUIRE_ARG(std::isfinite(p.xsph_c) && p.xsph_c >= 0.0f && p.xsph_c <= 1.0f, "solver.xsph_c must be 0..1");
    PBF_REQUIRE_ARG(std::isfinite(p.vorticity_epsilon) && p.vorticity_epsilon >= 0.0f && p.vorticity_epsilon <= 100.0f,
                    "solver.vorticity_epsilon must be 0..100");
    PBF_REQUIRE_ARG(p.ldc_enabled <= 1, "solver.ldc_enabled must be 0 or 1");
    PBF_REQUIRE_ARG(std::isfinite(p.ldc_gain) && p.ldc_gain >= 0.0f && p.ldc_gain <= 1.0f, "solver.ldc_gain must be 0..1");
    PBF_REQUIRE_ARG(std::isfinite(p.max_speed) && p.max_speed > 0.0f, "solver.max_speed must be finite and > 0");
    PBF_REQUIRE_ARG(std::isfinite(p.adaptive_error_target) && p.adaptive_error_target >= 0.0f &&
                        p.adaptive_error_target < 1.0f,
                    "solver.adaptive_error_target must be in [0, 1)");
    return PBF_OK;
}

template <class T, class Copy>
pbf_result copy_out(const char* fn, pbf_world_id id, T* out, uint32_t max_count, uint32_t* written, Copy copy) {
    return guarded(fn, [&]() -> pbf_result {
        if (written) *written = 0;
        PBF_REQUIRE_ARG(out != nullptr || max_count == 0, "output array is NULL");
        PBF_LOCK_WORLD(w, id);
        uint32_t n = 0;
        const pbf_result r = fail(copy(*w.operator->(), out, max_count, &n));
        if (written) *written = n;
        return r;
    });
}

}  // namespace

// =============================================================================================
extern "C" {

PBF_API uint32_t PBF_CALL pbf_get_version(void) { return PBF_VERSION; }

PBF_API const char* PBF_CALL pbf_last_error_message(void) { return t_last_error.c_str(); }

PBF_API const char* PBF_CALL pbf_result_string(pbf_result r) {
    switch (raw(r)) {  // any int a C caller passes, without an out-of-range enum load
        case PBF_OK: return "PBF_OK";
        case PBF_ERROR_INVALID_ARGUMENT: return "PBF_ERROR_INVALID_ARGUMENT";
        case PBF_ERROR_INVALID_HANDLE: return "PBF_ERROR_INVALID_HANDLE";
        case PBF_ERROR_STRUCT_SIZE: return "PBF_ERROR_STRUCT_SIZE";
        case PBF_ERROR_VERSION_MISMATCH: return "PBF_ERROR_VERSION_MISMATCH";
        case PBF_ERROR_CAPACITY: return "PBF_ERROR_CAPACITY";
        case PBF_ERROR_OUT_OF_MEMORY: return "PBF_ERROR_OUT_OF_MEMORY";
        case PBF_ERROR_BACKEND_UNAVAILABLE: return "PBF_ERROR_BACKEND_UNAVAILABLE";
        case PBF_ERROR_BACKEND: return "PBF_ERROR_BACKEND";
        case PBF_ERROR_INVALID_STATE: return "PBF_ERROR_INVALID_STATE";
        case PBF_ERROR_INTERNAL: return "PBF_ERROR_INTERNAL";
        default: return "PBF_ERROR_UNKNOWN";
    }
}

PBF_API void PBF_CALL pbf_set_log_callback(pbf_log_fn callback, void* user_data) {
    std::lock_guard<std::recursive_mutex> lock(g_log_mutex);
    g_log_fn = callback;
    g_log_user = user_data;
}

// ---- defaults --------------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_solver_params_init(pbf_solver_params* p, uint32_t struct_size) {
    const char* fn = "pbf_solver_params_init";
    if (pbf_result r = check_struct(fn, "pbf_solver_params", p, struct_size, sizeof(pbf_solver_params)); r != PBF_OK)
        return r;
    std::memset(p, 0, sizeof *p);
    p->struct_size = sizeof *p;
    p->iterations = 4;
    p->substeps = 1;
    p->relaxation = 1.0f;
    p->scorr_k = 0.1f;
    p->scorr_n = 4.0f;
    p->scorr_dq = 0.2f;
    p->xsph_c = 0.01f;
    p->vorticity_epsilon = 0.0005f;
    p->ldc_enabled = 1;
    p->ldc_gain = 0.3f;
    p->max_speed = 100.0f;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_world_desc_init(pbf_world_desc* d, uint32_t struct_size, uint32_t header_version) {
    const char* fn = "pbf_world_desc_init";
    if (pbf_result r = check_struct(fn, "pbf_world_desc", d, struct_size, sizeof(pbf_world_desc)); r != PBF_OK)
        return r;
    std::memset(d, 0, sizeof *d);
    d->struct_size = sizeof *d;
    d->header_version = header_version;
    d->backend = PBF_BACKEND_AUTO;
    d->cuda_device = 0;
    d->max_particles = 65536;
    d->particle_radius = 0.025f;
    d->rest_density = 1000.0f;
    d->gravity[1] = -9.81f;
    const float lo[3] = {-1.0f, 0.0f, -1.0f}, hi[3] = {1.0f, 2.0f, 1.0f};
    std::memcpy(d->domain_min, lo, sizeof lo);
    std::memcpy(d->domain_max, hi, sizeof hi);
    d->solver.struct_size = sizeof d->solver;
    return pbf_solver_params_init(&d->solver, d->solver.struct_size);
}

PBF_API pbf_result PBF_CALL pbf_block_desc_init(pbf_block_desc* d, uint32_t struct_size) {
    const char* fn = "pbf_block_desc_init";
    if (pbf_result r = check_struct(fn, "pbf_block_desc", d, struct_size, sizeof(pbf_block_desc)); r != PBF_OK)
        return r;
    std::memset(d, 0, sizeof *d);
    d->struct_size = sizeof *d;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_emitter_desc_init(pbf_emitter_desc* d, uint32_t struct_size) {
    const char* fn = "pbf_emitter_desc_init";
    if (pbf_result r = check_struct(fn, "pbf_emitter_desc", d, struct_size, sizeof(pbf_emitter_desc)); r != PBF_OK)
        return r;
    std::memset(d, 0, sizeof *d);
    d->struct_size = sizeof *d;
    d->enabled = 1;
    d->direction[1] = -1.0f;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_collider_desc_init(pbf_collider_desc* d, uint32_t struct_size) {
    const char* fn = "pbf_collider_desc_init";
    if (pbf_result r = check_struct(fn, "pbf_collider_desc", d, struct_size, sizeof(pbf_collider_desc)); r != PBF_OK)
        return r;
    std::memset(d, 0, sizeof *d);
    d->struct_size = sizeof *d;
    d->motion = PBF_MOTION_STATIC;
    d->rotation[3] = 1.0f;
    return PBF_OK;
}

// ---- world -----------------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_create(const pbf_world_desc* d, pbf_world_id* out) {
    const char* fn = "pbf_world_create";
    return guarded(fn, [&]() -> pbf_result {
        PBF_REQUIRE_ARG(out != nullptr, "out_world is NULL");
        *out = pbf_world_id{0, 0};
        PBF_CHECK_STRUCT(pbf_world_desc, d);
        PBF_REQUIRE(PBF_VERSION_GET_MAJOR(d->header_version) == PBF_VERSION_MAJOR, PBF_ERROR_VERSION_MISMATCH,
                    std::string(fn) + ": header major version " + std::to_string(PBF_VERSION_GET_MAJOR(d->header_version)) +
                        " does not match the library's " + std::to_string(PBF_VERSION_MAJOR) +
                        " (desc.header_version must be PBF_VERSION; use pbf_world_desc_default())");
        PBF_REQUIRE_ARG(raw(d->backend) == PBF_BACKEND_AUTO || raw(d->backend) == PBF_BACKEND_CPU || raw(d->backend) == PBF_BACKEND_CUDA,
                        "backend must be PBF_BACKEND_AUTO, _CPU or _CUDA");
        PBF_REQUIRE_ARG(d->cuda_device >= 0, "cuda_device must be >= 0");
        PBF_REQUIRE_ARG(d->max_particles >= 1 && d->max_particles <= (1u << 30), "max_particles must be 1..2^30");
        PBF_REQUIRE_ARG(std::isfinite(d->particle_radius) && d->particle_radius > 0.0f,
                        "particle_radius must be finite and > 0");
        PBF_REQUIRE_ARG(std::isfinite(d->rest_density) && d->rest_density > 0.0f, "rest_density must be finite and > 0");
        PBF_REQUIRE_ARG(finite3(d->gravity), "gravity must be finite");
        PBF_REQUIRE_ARG(finite3(d->domain_min) && finite3(d->domain_max), "domain bounds must be finite");
        for (int a = 0; a < 3; ++a)
            PBF_REQUIRE_ARG(d->domain_max[a] - d->domain_min[a] >= 4.0f * d->particle_radius,
                            "domain_max must exceed domain_min by at least 2 particle diameters on every axis");
        if (pbf_result r = check_solver_params(fn, &d->solver); r != PBF_OK) return r;
        if (d->backend == PBF_BACKEND_CUDA && !pbf::cuda_device_available(d->cuda_device))
            return fail(PBF_ERROR_BACKEND_UNAVAILABLE,
                        std::string(fn) + ": PBF_BACKEND_CUDA requested but CUDA device " +
                            std::to_string(d->cuda_device) + " is not available (no device, no driver, or a CPU-only build)");

        Status st;
        std::unique_ptr<World> world = World::create(*d, &st);
        if (!world) return fail(st.code, std::string(fn) + ": " + st.message);
        auto entry = std::make_shared<WorldEntry>();
        entry->world = std::move(world);
        pbf_world_info info{};
        entry->world->get_info(&info);
        {
            std::lock_guard<std::mutex> lock(g_worlds_mutex);
            const auto h = g_worlds.insert(entry);
            *out = pbf_world_id{h.index, h.generation};
        }
        log_message(PBF_LOG_INFO, std::string("world created on ") + info.device_name + ", capacity " +
                                      std::to_string(d->max_particles));
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_destroy(pbf_world_id id) {
    const char* fn = "pbf_world_destroy";
    return guarded(fn, [&]() -> pbf_result {
        std::shared_ptr<WorldEntry> entry;
        {
            std::lock_guard<std::mutex> lock(g_worlds_mutex);
            if (auto* e = g_worlds.find(id.index, id.generation)) entry = *e;
            if (entry) g_worlds.erase(id.index, id.generation);
        }
        if (!entry) return fail(PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": world is not live (destroyed twice?)");
        std::lock_guard<std::mutex> lock(entry->mutex);  // waits for a call in flight
        entry->world.reset();
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_step(pbf_world_id id, float dt) {
    const char* fn = "pbf_world_step";
    return guarded(fn, [&]() -> pbf_result {
        PBF_REQUIRE_ARG(std::isfinite(dt) && dt > 0.0f && dt <= 1.0f, "dt must be finite and in (0, 1] seconds, got " +
                                                                          std::to_string(dt));
        PBF_LOCK_WORLD(w, id);
        return fail(w->step(dt));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_solver_params(pbf_world_id id, pbf_solver_params* out) {
    const char* fn = "pbf_world_get_solver_params";
    return guarded(fn, [&]() -> pbf_result {
        PBF_CHECK_STRUCT(pbf_solver_params, out);
        PBF_LOCK_WORLD(w, id);
        *out = w->solver_params();
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_set_solver_params(pbf_world_id id, const pbf_solver_params* p) {
    const char* fn = "pbf_world_set_solver_params";
    return guarded(fn, [&]() -> pbf_result {
        if (pbf_result r = check_solver_params(fn, p); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        w->set_solver_params(*p);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_set_gravity(pbf_world_id id, const float g[3]) {
    const char* fn = "pbf_world_set_gravity";
    return guarded(fn, [&]() -> pbf_result {
        PBF_REQUIRE_ARG(g != nullptr && finite3(g), "gravity must be non-NULL and finite");
        PBF_LOCK_WORLD(w, id);
        w->set_gravity(pbf::Vec3{g[0], g[1], g[2]});
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_info(pbf_world_id id, pbf_world_info* out) {
    const char* fn = "pbf_world_get_info";
    return guarded(fn, [&]() -> pbf_result {
        PBF_CHECK_STRUCT(pbf_world_info, out);
        PBF_LOCK_WORLD(w, id);
        w->get_info(out);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_stats(pbf_world_id id, pbf_step_stats* out) {
    const char* fn = "pbf_world_get_stats";
    return guarded(fn, [&]() -> pbf_result {
        PBF_CHECK_STRUCT(pbf_step_stats, out);
        PBF_LOCK_WORLD(w, id);
        return fail(w->get_stats(out));
    });
}

// ---- emitters --------------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_emit_block(pbf_world_id id, const pbf_block_desc* d, uint32_t* out_emitted) {
    const char* fn = "pbf_world_emit_block";
    return guarded(fn, [&]() -> pbf_result {
        if (out_emitted) *out_emitted = 0;
        PBF_CHECK_STRUCT(pbf_block_desc, d);
        PBF_REQUIRE_ARG(finite3(d->box_min) && finite3(d->box_max) && finite3(d->velocity),
                        "box_min, box_max and velocity must be finite");
        for (int a = 0; a < 3; ++a) PBF_REQUIRE_ARG(d->box_max[a] > d->box_min[a], "box_max must exceed box_min on every axis");
        PBF_LOCK_WORLD(w, id);
        uint32_t emitted = 0;
        const pbf_result r = fail(w->emit_block(*d, &emitted));
        if (out_emitted) *out_emitted = emitted;
        return r;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_create_emitter(pbf_world_id id, const pbf_emitter_desc* d, pbf_emitter_id* out) {
    const char* fn = "pbf_world_create_emitter";
    return guarded(fn, [&]() -> pbf_result {
        PBF_REQUIRE_ARG(out != nullptr, "out_emitter is NULL");
        *out = pbf_emitter_id{0, 0};
        PBF_CHECK_STRUCT(pbf_emitter_desc, d);
        PBF_REQUIRE_ARG(d->enabled <= 1, "enabled must be 0 or 1");
        if (raw(d->type) == PBF_EMITTER_NOZZLE) {
            PBF_REQUIRE_ARG(finite3(d->position) && finite3(d->direction), "nozzle position and direction must be finite");
            const float len2 = d->direction[0] * d->direction[0] + d->direction[1] * d->direction[1] +
                               d->direction[2] * d->direction[2];
            PBF_REQUIRE_ARG(len2 > 1e-12f, "nozzle direction must be non-zero");
            PBF_REQUIRE_ARG(std::isfinite(d->speed) && d->speed > 0.0f, "nozzle speed must be finite and > 0");
            PBF_REQUIRE_ARG(std::isfinite(d->radius) && d->radius > 0.0f, "nozzle radius must be finite and > 0");
            PBF_REQUIRE_ARG(std::isfinite(d->particles_per_second) && d->particles_per_second > 0.0f &&
                                d->particles_per_second <= 1e9f,
                            "nozzle particles_per_second must be in (0, 1e9]");
        } else if (raw(d->type) == PBF_EMITTER_DRAIN) {
            PBF_REQUIRE_ARG(finite3(d->box_min) && finite3(d->box_max), "drain box must be finite");
            for (int a = 0; a < 3; ++a) PBF_REQUIRE_ARG(d->box_max[a] > d->box_min[a], "drain box_max must exceed box_min");
        } else {
            return fail(PBF_ERROR_INVALID_ARGUMENT, std::string(fn) + ": type must be PBF_EMITTER_NOZZLE or PBF_EMITTER_DRAIN");
        }
        PBF_REQUIRE_ARG(finite3(d->position) && finite3(d->direction) && std::isfinite(d->speed) && std::isfinite(d->radius) && std::isfinite(d->particles_per_second) && finite3(d->box_min) && finite3(d->box_max), "position, direction, speed, radius, particles_per_second, box_min and box_max must be finite, also where the type does not use them");
        PBF_LOCK_WORLD(w, id);
        return fail(w->create_emitter(*d, out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_destroy_emitter(pbf_world_id id, pbf_emitter_id e) {
    const char* fn = "pbf_world_destroy_emitter";
    return guarded(fn, [&]() -> pbf_result {
        PBF_LOCK_WORLD(w, id);
        PBF_REQUIRE(w->destroy_emitter(e), PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": emitter is not live");
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_emitter_set_enabled(pbf_world_id id, pbf_emitter_id e, uint32_t enabled) {
    const char* fn = "pbf_emitter_set_enabled";
    return guarded(fn, [&]() -> pbf_result {
        PBF_REQUIRE_ARG(enabled <= 1, "enabled must be 0 or 1");
        PBF_LOCK_WORLD(w, id);
        pbf::EmitterEntry* entry = w->find_emitter(e);
        PBF_REQUIRE(entry, PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": emitter is not live");
        entry->desc.enabled = enabled;
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_emitter_set_transform(pbf_world_id id, pbf_emitter_id e, const float a[3], const float b[3]) {
    const char* fn = "pbf_emitter_set_transform";
    return guarded(fn, [&]() -> pbf_result {
        PBF_REQUIRE_ARG(a && b && finite3(a) && finite3(b), "both vectors must be non-NULL and finite");
        PBF_LOCK_WORLD(w, id);
        pbf::EmitterEntry* entry = w->find_emitter(e);
        PBF_REQUIRE(entry, PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": emitter is not live");
        if (entry->desc.type == PBF_EMITTER_NOZZLE) {
            const float len = std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
            PBF_REQUIRE_ARG(len > 1e-6f, "nozzle direction must be non-zero");
            for (int k = 0; k < 3; ++k) {
                entry->desc.position[k] = a[k];
                entry->desc.direction[k] = b[k] / len;
            }
        } else {
            for (int k = 0; k < 3; ++k) PBF_REQUIRE_ARG(b[k] > a[k], "drain box_max must exceed box_min");
            for (int k = 0; k < 3; ++k) {
                entry->desc.box_min[k] = a[k];
                entry->desc.box_max[k] = b[k];
            }
        }
        return PBF_OK;
    });
}

// ---- colliders -------------------------------------------------------------------------------
static bool finite_unit_quat(const float q[4]) {
    if (!(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]) && std::isfinite(q[3]))) return false;
    const float n2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    return n2 > 1e-6f;
}

PBF_API pbf_result PBF_CALL pbf_world_create_collider(pbf_world_id id, const pbf_collider_desc* d, pbf_collider_id* out) {
    const char* fn = "pbf_world_create_collider";
    return guarded(fn, [&]() -> pbf_result {
        PBF_REQUIRE_ARG(out != nullptr, "out_collider is NULL");
        *out = pbf_collider_id{0, 0};
        PBF_CHECK_STRUCT(pbf_collider_desc, d);
        PBF_REQUIRE_ARG(raw(d->shape) >= PBF_SHAPE_PLANE && raw(d->shape) <= PBF_SHAPE_BOX,
                        "shape must be PBF_SHAPE_PLANE, _SPHERE, _CAPSULE or _BOX");
        PBF_REQUIRE_ARG(raw(d->motion) == PBF_MOTION_STATIC || raw(d->motion) == PBF_MOTION_KINEMATIC,
                        "motion must be PBF_MOTION_STATIC or PBF_MOTION_KINEMATIC");
        PBF_REQUIRE_ARG(finite3(d->position) && finite_unit_quat(d->rotation),
                        "position must be finite and rotation a finite, non-zero quaternion");
        PBF_REQUIRE_ARG(std::isfinite(d->friction) && d->friction >= 0.0f && d->friction <= 1.0f, "friction must be 0..1");
        if (d->shape == PBF_SHAPE_SPHERE || d->shape == PBF_SHAPE_CAPSULE)
            PBF_REQUIRE_ARG(std::isfinite(d->radius) && d->radius > 0.0f, "radius must be finite and > 0");
        if (d->shape == PBF_SHAPE_CAPSULE)
            PBF_REQUIRE_ARG(std::isfinite(d->half_height) && d->half_height >= 0.0f, "half_height must be finite and >= 0");
        if (d->shape == PBF_SHAPE_BOX)
            PBF_REQUIRE_ARG(finite3(d->half_extents) && d->half_extents[0] > 0.0f && d->half_extents[1] > 0.0f &&
                                d->half_extents[2] > 0.0f,
                            "half_extents must be finite and > 0");
        PBF_REQUIRE_ARG(std::isfinite(d->radius) && std::isfinite(d->half_height) && finite3(d->half_extents), "radius, half_height and half_extents must be finite, also where the shape does not use them");
        PBF_LOCK_WORLD(w, id);
        return fail(w->create_collider(*d, out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_destroy_collider(pbf_world_id id, pbf_collider_id c) {
    const char* fn = "pbf_world_destroy_collider";
    return guarded(fn, [&]() -> pbf_result {
        PBF_LOCK_WORLD(w, id);
        PBF_REQUIRE(w->destroy_collider(c), PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": collider is not live");
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_collider_set_pose(pbf_world_id id, pbf_collider_id c, const float position[3],
                                                 const float rotation[4]) {
    const char* fn = "pbf_collider_set_pose";
    return guarded(fn, [&]() -> pbf_result {
        PBF_REQUIRE_ARG(position && rotation && finite3(position) && finite_unit_quat(rotation),
                        "position must be finite and rotation a finite, non-zero quaternion");
        PBF_LOCK_WORLD(w, id);
        pbf::ColliderEntry* entry = w->find_collider(c);
        PBF_REQUIRE(entry, PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": collider is not live");
        PBF_REQUIRE(entry->motion == PBF_MOTION_KINEMATIC, PBF_ERROR_INVALID_STATE,
                    std::string(fn) + ": only kinematic colliders can be moved");
        const float n = std::sqrt(rotation[0] * rotation[0] + rotation[1] * rotation[1] + rotation[2] * rotation[2] +
                                  rotation[3] * rotation[3]);
        entry->target_position = pbf::Vec3{position[0], position[1], position[2]};
        for (int k = 0; k < 4; ++k) entry->target_rotation[k] = rotation[k] / n;
        return PBF_OK;
    });
}

// ---- particles -------------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_get_particle_count(pbf_world_id id, uint32_t* out) {
    const char* fn = "pbf_world_get_particle_count";
    return guarded(fn, [&]() -> pbf_result {
        PBF_REQUIRE_ARG(out != nullptr, "out_count is NULL");
        PBF_LOCK_WORLD(w, id);
        return fail(w->particle_count(out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_copy_positions(pbf_world_id id, float* out, uint32_t max_count, uint32_t* written) {
    return copy_out("pbf_world_copy_positions", id, out, max_count, written,
                    [](World& w, float* o, uint32_t m, uint32_t* n) { return w.copy_positions(o, m, n); });
}
PBF_API pbf_result PBF_CALL pbf_world_copy_velocities(pbf_world_id id, float* out, uint32_t max_count, uint32_t* written) {
    return copy_out("pbf_world_copy_velocities", id, out, max_count, written,
                    [](World& w, float* o, uint32_t m, uint32_t* n) { return w.copy_velocities(o, m, n); });
}
PBF_API pbf_result PBF_CALL pbf_world_copy_ids(pbf_world_id id, uint32_t* out, uint32_t max_count, uint32_t* written) {
    return copy_out("pbf_world_copy_ids", id, out, max_count, written,
                    [](World& w, uint32_t* o, uint32_t m, uint32_t* n) { return w.copy_ids(o, m, n); });
}

PBF_API pbf_result PBF_CALL pbf_world_map_positions(pbf_world_id id, pbf_mapped_buffer* out) {
    const char* fn = "pbf_world_map_positions";
    return guarded(fn, [&]() -> pbf_result {
        PBF_CHECK_STRUCT(pbf_mapped_buffer, out);
        PBF_LOCK_WORLD(w, id);
        return fail(w->map_positions(out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_unmap(pbf_world_id id) {
    const char* fn = "pbf_world_unmap";
    return guarded(fn, [&]() -> pbf_result {
        PBF_LOCK_WORLD(w, id);
        PBF_REQUIRE(w->mapped(), PBF_ERROR_INVALID_STATE, std::string(fn) + ": no buffer is mapped");
        w->unmap();
        return PBF_OK;
    });
}

}  // extern "C"

// ---- internal hooks (not exported) -----------------------------------------------------------
#include "internal.h"

namespace pbf {
pbf_result internal_set_profiling(pbf_world_id id, bool on) {
    const char* fn = "internal_set_profiling";
    PBF_LOCK_WORLD(w, id);
    w->backend().set_profiling(on);
    return PBF_OK;
}
pbf_result internal_stage_times(pbf_world_id id, StageTimes* out) {
    const char* fn = "internal_stage_times";
    PBF_LOCK_WORLD(w, id);
    return fail(w->backend().stage_times(out));
}
}  // namespace pbf
