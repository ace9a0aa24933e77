// The C ABI of zero-copy rendering (the interop section of pbf_c_api.h): validates every
// argument and handle, refuses what this build or the world's backend lacks, and translates the
// calls to the world's interop state (native/interop). The descs' defaults are in defaults.cpp,
// their checks in validate.cpp.
#include <algorithm>
#include <cstring>
#include <exception>
#include <mutex>
#include <string>
#include <vector>

#include "../common/transfers.h"
#include "../interop/interop.h"
#include "api_common.h"
#include "pbf_c_api.h"

using pbf::Interop;
using pbf::Status;
using pbf::World;
using pbf::api::fail;
using pbf::api::guarded;
using pbf::api::raw;

namespace {

bool is_zero(pbf_semaphore_id id) { return id.index == 0 && id.generation == 0; }

// Refuses what this build lacks (PBF_ERROR_BACKEND_UNAVAILABLE).
pbf_result require_support(const char* fn, uint32_t flag) {
    const uint32_t have = pbf::interop_support();
    if (have & flag) return PBF_OK;
    std::string why;
    if (!(have & PBF_INTEROP_SUPPORT_CUDA))
        why = "this libpbf was built without CUDA";
    else if (flag == PBF_INTEROP_SUPPORT_D3D11)
        why = "Direct3D 11 exists only in Windows builds";
    else if (flag == PBF_INTEROP_SUPPORT_EXTERNAL_WIN32)
        why = "win32 handles, D3D11 and D3D12 exist only in Windows builds";
    else if (flag == PBF_INTEROP_SUPPORT_EXTERNAL_FD)
        why = "opaque file descriptors exist only in Linux builds";
    else
        why = "not available in this build";
    return fail(PBF_ERROR_BACKEND_UNAVAILABLE, std::string(fn) + ": " + why);
}

// Refuses an external handle this build cannot import: a file descriptor (fd_type) outside Linux
// builds, a win32 handle outside Windows builds.
pbf_result require_handle_support(const char* fn, bool fd_type) {
    return require_support(fn, fd_type ? PBF_INTEROP_SUPPORT_EXTERNAL_FD : PBF_INTEROP_SUPPORT_EXTERNAL_WIN32);
}

// The world must run on CUDA (PBF_ERROR_INVALID_STATE otherwise).
pbf_result require_cuda_world(const char* fn, World& w) {
    if (w.backend_kind() == PBF_BACKEND_CUDA) return PBF_OK;
    return fail(PBF_ERROR_INVALID_STATE,
                std::string(fn) + ": the world runs on the CPU backend; this call needs a CUDA world");
}

// The world's interop state, created on first use.
pbf_result interop_of(const char* fn, World& w, Interop** out) {
    if (pbf_result r = require_cuda_world(fn, w); r != PBF_OK) return r;
    const Status st = Interop::of(w, out);
    return st.ok() ? PBF_OK : fail(fn, st);
}

// The interop state if the world has one (no handle of it can be valid otherwise).
Interop* existing_interop(World& w) { return Interop::existing(w); }

std::string handle_text(uint32_t index, uint32_t generation) {
    return "{" + std::to_string(index) + ", " + std::to_string(generation) + "}";
}

// The shape of every call on an interop handle: the build supports it, the world is live and the
// handle is one of its interop state's; then body(io).
template <class Id, class Body>
pbf_result on_handle(const char* fn, pbf_world_id id, uint32_t support, bool (Interop::*has)(Id), Id handle,
                     const char* what, Body&& body) {
    return guarded(fn, [&](const char*) -> pbf_result {
        if (pbf_result r = require_support(fn, support); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        Interop* io = existing_interop(*w);
        PBF_REQUIRE(io && (io->*has)(handle), PBF_ERROR_INVALID_HANDLE,
                    std::string(fn) + ": " + what + " " + handle_text(handle.index, handle.generation) +
                        " is not live in this world (released, or never created here)");
        return body(io);
    });
}

#define PBF_INTEROP_OF(io, w) \
    Interop* io = nullptr;    \
    if (pbf_result r_ = interop_of(fn, *w, &io); r_ != PBF_OK) return r_

#define PBF_REQUIRE_HANDLE(io, has, id, what)                                                      \
    PBF_REQUIRE((io) && (io)->has(id), PBF_ERROR_INVALID_HANDLE,                                   \
                std::string(fn) + ": " + (what) + " " + handle_text((id).index, (id).generation) + \
                    " is not live in this world (released, or never created here)")

// ---- worlds with work for the render thread -----------------------------------------------
std::mutex g_render_mutex;
std::vector<pbf_world_id> g_render_worlds;

void add_render_world(pbf_world_id id) {
    std::lock_guard<std::mutex> lock(g_render_mutex);
    for (const pbf_world_id& w : g_render_worlds)
        if (w.index == id.index && w.generation == id.generation) return;
    g_render_worlds.push_back(id);
}

void remove_render_world(pbf_world_id id) {
    std::lock_guard<std::mutex> lock(g_render_mutex);
    g_render_worlds.erase(
        std::remove_if(g_render_worlds.begin(), g_render_worlds.end(),
                       [&](const pbf_world_id& w) { return w.index == id.index && w.generation == id.generation; }),
        g_render_worlds.end());
}

void PBF_CALL render_event(int event_id) {
    try {
        std::vector<pbf_world_id> worlds;
        {
            std::lock_guard<std::mutex> lock(g_render_mutex);
            worlds = g_render_worlds;
        }
        for (const pbf_world_id& id : worlds) {
            if (event_id != PBF_RENDER_EVENT_ALL_WORLDS && int64_t(event_id) != int64_t(id.index) + 1) continue;
            pbf::api::WorldLock w("pbf render event", id, /*quiet=*/true);
            if (!w) {
                remove_render_world(id);  // destroyed since
                continue;
            }
            Interop* io = existing_interop(*w);
            if (!io || !io->wants_render_events()) {
                remove_render_world(id);
                continue;
            }
            const Status st = io->render_event();
            if (!st.ok())
                pbf::api::log_message(PBF_LOG_ERROR, std::string(pbf_result_string(st.code)) +
                                                         ": pbf render event, world " +
                                                         handle_text(id.index, id.generation) + ": " + st.message);
        }
    } catch (const std::exception& e) {
        pbf::api::log_message(PBF_LOG_ERROR, std::string("PBF_ERROR_INTERNAL: pbf render event: ") + e.what());
    } catch (...) {
        pbf::api::log_message(PBF_LOG_ERROR, "PBF_ERROR_INTERNAL: pbf render event: unknown exception");
    }
}

// The shape of a graphics buffer registration (GL, D3D11): the out handle and the desc, what the
// build supports, the world and its source buffer, then the interop state's registration; a
// PBF_COPY_ON_RENDER_EVENT buffer puts its world on the render thread's list.
template <class Desc, class Id>
pbf_result register_graphics(const char* fn, const char* desc_type, pbf_world_id id, const Desc* d, Id* out,
                             uint32_t support, pbf::api::Verdict (*validate)(const Desc&),
                             Status (Interop::*register_buffer)(const Desc&, Id*)) {
    return guarded(fn, [&](const char*) -> pbf_result {
        PBF_REQUIRE_ARG(out != nullptr, "out_buffer is NULL");
        *out = Id{0, 0};
        if (pbf_result r = pbf::api::check_struct(fn, desc_type, d, d ? d->struct_size : 0u, sizeof(Desc)); r != PBF_OK)
            return r;
        PBF_VALIDATE(validate(*d));
        if (pbf_result r = require_support(fn, support); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        if (pbf_result r = pbf::api::require_buffer(fn, *w, d->source); r != PBF_OK) return r;
        PBF_INTEROP_OF(io, w);
        const Status st = (io->*register_buffer)(*d, out);
        if (!st.ok()) return fail(st.code, std::string(fn) + ": " + st.message);
        if (d->mode == PBF_COPY_ON_RENDER_EVENT) add_render_world(id);
        return PBF_OK;
    });
}

pbf_result check_sync(const char* fn, Interop* io, const pbf_external_sync* sync) {
    PBF_CHECK_STRUCT(pbf_external_sync, sync);
    PBF_VALIDATE(pbf::api::validate_external_sync(*sync));
    if (!is_zero(sync->wait_semaphore))
        PBF_REQUIRE_HANDLE(io, has_semaphore, sync->wait_semaphore, "sync.wait_semaphore");
    if (!is_zero(sync->signal_semaphore))
        PBF_REQUIRE_HANDLE(io, has_semaphore, sync->signal_semaphore, "sync.signal_semaphore");
    return PBF_OK;
}

}  // namespace

// =============================================================================================
extern "C" {

PBF_API pbf_result PBF_CALL pbf_get_interop_support(uint32_t* out_flags) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(out_flags != nullptr, "out_flags is NULL");
        *out_flags = pbf::interop_support();
        return PBF_OK;
    });
}

// ---- streams and events ----------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_get_cuda_stream(pbf_world_id id, void** out_stream) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(out_stream != nullptr, "out_stream is NULL");
        *out_stream = nullptr;
        if (pbf_result r = require_support(fn, PBF_INTEROP_SUPPORT_CUDA); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        if (pbf_result r = require_cuda_world(fn, *w); r != PBF_OK) return r;
        *out_stream = w->cuda_stream();
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_set_cuda_stream(pbf_world_id id, void* stream) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        if (pbf_result r = require_support(fn, PBF_INTEROP_SUPPORT_CUDA); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        if (pbf_result r = require_cuda_world(fn, *w); r != PBF_OK) return r;
        const Status st = w->set_cuda_stream(stream);
        return fail(fn, st);
    });
}

PBF_API pbf_result PBF_CALL pbf_world_record_cuda_event(pbf_world_id id, void** out_event) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(out_event != nullptr, "out_event is NULL");
        *out_event = nullptr;
        if (pbf_result r = require_support(fn, PBF_INTEROP_SUPPORT_CUDA); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        PBF_INTEROP_OF(io, w);
        const Status st = io->record_event(out_event);
        return fail(fn, st);
    });
}

PBF_API pbf_result PBF_CALL pbf_world_wait_cuda_event(pbf_world_id id, void* event) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(event != nullptr, "event is NULL");
        if (pbf_result r = require_support(fn, PBF_INTEROP_SUPPORT_CUDA); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        PBF_INTEROP_OF(io, w);
        const Status st = io->wait_event(event);
        return fail(fn, st);
    });
}

// ---- device buffers ----------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_map_device_buffers(pbf_world_id id, uint32_t flags, pbf_device_buffers* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_device_buffers, out);
        PBF_REQUIRE_ARG((flags & ~PBF_MAP_NO_WAIT) == 0, "flags must be 0 or PBF_MAP_NO_WAIT");
        PBF_LOCK_WORLD(w, id);
        World::Mapping m;
        const Status st = w->map_particles(/*wait_for_count=*/!(flags & PBF_MAP_NO_WAIT), &m);
        if (!st.ok()) return fail(st.code, std::string(fn) + ": " + st.message);
        pbf_device_buffers r;
        std::memset(&r, 0, sizeof r);
        r.struct_size = sizeof r;
        r.memory = m.device ? PBF_MEMORY_CUDA_DEVICE : PBF_MEMORY_HOST;
        r.positions = m.live.positions;
        r.velocities = m.live.velocities;
        r.ids = m.live.ids;
        r.density_ratio = static_cast<char*>(m.live.positions) + 12;
        r.count_device = m.live.count;
        r.cuda_stream = m.cuda_stream;
        r.count = m.count;
        r.capacity = m.live.capacity;
        r.vec4_stride_bytes = 16;
        r.id_stride_bytes = 4;
        r.cuda_device = m.device ? m.live.cuda_device : -1;
        r.smoothed_positions = m.live.smoothed_positions;
        r.anisotropy = m.live.anisotropy;
        r.anisotropy_stride_bytes = 48;
        r.render_flags = w->render_flags();
        r.diffuse_positions = m.live.diffuse_positions;
        r.diffuse_velocities = m.live.diffuse_velocities;
        r.diffuse_count_device = m.live.diffuse_count;
        r.diffuse_count = m.diffuse_count;
        r.diffuse_capacity = m.live.diffuse_capacity;
        r.materials = m.live.materials;
        *out = r;
        return PBF_OK;
    });
}

// ---- OpenGL ----------------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_register_gl_buffer(pbf_world_id id, const pbf_gl_buffer_desc* d,
                                                         pbf_gl_buffer_id* out) {
    return register_graphics(__func__, "pbf_gl_buffer_desc", id, d, out, PBF_INTEROP_SUPPORT_OPENGL,
                             &pbf::api::validate_gl_buffer_desc, &Interop::register_gl_buffer);
}

PBF_API pbf_result PBF_CALL pbf_world_unregister_gl_buffer(pbf_world_id id, pbf_gl_buffer_id buffer) {
    const char* fn = __func__;
    return on_handle(fn, id, PBF_INTEROP_SUPPORT_OPENGL, &Interop::has_gl_buffer, buffer, "GL buffer",
                     [&](Interop* io) { return fail(fn, io->unregister_gl_buffer(buffer)); });
}

PBF_API pbf_result PBF_CALL pbf_world_copy_to_gl_buffer(pbf_world_id id, pbf_gl_buffer_id buffer) {
    const char* fn = __func__;
    return on_handle(fn, id, PBF_INTEROP_SUPPORT_OPENGL, &Interop::has_gl_buffer, buffer, "GL buffer",
                     [&](Interop* io) -> pbf_result {
                         PBF_REQUIRE(
                             io->gl_buffer_mode(buffer) != PBF_COPY_ON_RENDER_EVENT, PBF_ERROR_INVALID_STATE,
                             std::string(fn) +
                                 ": the buffer was registered with PBF_COPY_ON_RENDER_EVENT: the render thread copies");
                         const Status st = io->copy_to_gl_buffer(buffer);
                         return fail(fn, st);
                     });
}

// ---- Direct3D 11 -----------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_register_d3d11_buffer(pbf_world_id id, const pbf_d3d11_buffer_desc* d,
                                                            pbf_d3d11_buffer_id* out) {
    return register_graphics(__func__, "pbf_d3d11_buffer_desc", id, d, out, PBF_INTEROP_SUPPORT_D3D11,
                             &pbf::api::validate_d3d11_buffer_desc, &Interop::register_d3d11_buffer);
}

PBF_API pbf_result PBF_CALL pbf_world_unregister_d3d11_buffer(pbf_world_id id, pbf_d3d11_buffer_id buffer) {
    const char* fn = __func__;
    return on_handle(fn, id, PBF_INTEROP_SUPPORT_D3D11, &Interop::has_d3d11_buffer, buffer, "D3D11 buffer",
                     [&](Interop* io) { return fail(fn, io->unregister_d3d11_buffer(buffer)); });
}

// ---- external memory and semaphores ----------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_import_external_buffer(pbf_world_id id, const pbf_external_buffer_desc* d,
                                                             pbf_external_buffer_id* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_START_CREATE(pbf_external_buffer_desc, d, out, "out_buffer");
        PBF_VALIDATE(pbf::api::validate_external_buffer_desc(*d));
        const bool fd_type = raw(d->type) == PBF_EXTERNAL_MEMORY_OPAQUE_FD;
        if (pbf_result r = require_handle_support(fn, fd_type); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        if (pbf_result r = pbf::api::require_buffer(fn, *w, d->source); r != PBF_OK) return r;
        PBF_INTEROP_OF(io, w);
        const Status st = io->import_external_buffer(*d, out);
        if (!st.ok()) return fail(st.code, std::string(fn) + ": " + st.message);
        if (d->mode == PBF_COPY_ON_RENDER_EVENT) add_render_world(id);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_release_external_buffer(pbf_world_id id, pbf_external_buffer_id buffer) {
    const char* fn = __func__;
    return on_handle(fn, id, PBF_INTEROP_SUPPORT_CUDA, &Interop::has_external_buffer, buffer, "external buffer",
                     [&](Interop* io) { return fail(fn, io->release_external_buffer(buffer)); });
}

PBF_API pbf_result PBF_CALL pbf_world_import_semaphore(pbf_world_id id, const pbf_semaphore_desc* d,
                                                       pbf_semaphore_id* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_START_CREATE(pbf_semaphore_desc, d, out, "out_semaphore");
        PBF_VALIDATE(pbf::api::validate_semaphore_desc(*d));
        const bool fd_type =
            raw(d->type) == PBF_SEMAPHORE_VULKAN_BINARY_FD || raw(d->type) == PBF_SEMAPHORE_VULKAN_TIMELINE_FD;
        if (pbf_result r = require_handle_support(fn, fd_type); r != PBF_OK) return r;
        PBF_LOCK_WORLD(w, id);
        PBF_INTEROP_OF(io, w);
        const Status st = io->import_semaphore(*d, out);
        return fail(fn, st);
    });
}

PBF_API pbf_result PBF_CALL pbf_world_release_semaphore(pbf_world_id id, pbf_semaphore_id semaphore) {
    const char* fn = __func__;
    return on_handle(fn, id, PBF_INTEROP_SUPPORT_CUDA, &Interop::has_semaphore, semaphore, "semaphore",
                     [&](Interop* io) { return fail(fn, io->release_semaphore(semaphore)); });
}

PBF_API pbf_result PBF_CALL pbf_world_copy_to_external_buffer(pbf_world_id id, pbf_external_buffer_id buffer,
                                                              const pbf_external_sync* sync) {
    const char* fn = __func__;
    return on_handle(
        fn, id, PBF_INTEROP_SUPPORT_CUDA, &Interop::has_external_buffer, buffer, "external buffer",
        [&](Interop* io) -> pbf_result {
            if (sync)
                if (pbf_result r = check_sync(fn, io, sync); r != PBF_OK) return r;
            PBF_REQUIRE(
                io->external_buffer_mode(buffer) != PBF_COPY_ON_RENDER_EVENT, PBF_ERROR_INVALID_STATE,
                std::string(fn) + ": the buffer was imported with PBF_COPY_ON_RENDER_EVENT: the render thread copies");
            const Status st = io->copy_to_external_buffer(buffer, sync);
            return fail(fn, st);
        });
}

PBF_API pbf_result PBF_CALL pbf_world_set_external_sync(pbf_world_id id, pbf_external_buffer_id buffer,
                                                        const pbf_external_sync* sync) {
    const char* fn = __func__;
    return on_handle(fn, id, PBF_INTEROP_SUPPORT_CUDA, &Interop::has_external_buffer, buffer, "external buffer",
                     [&](Interop* io) -> pbf_result {
                         if (sync)
                             if (pbf_result r = check_sync(fn, io, sync); r != PBF_OK) return r;
                         PBF_REQUIRE(io->external_buffer_mode(buffer) != PBF_COPY_MANUAL, PBF_ERROR_INVALID_STATE,
                                     std::string(fn) +
                                         ": the buffer was imported with PBF_COPY_MANUAL: pass the sync to "
                                         "pbf_world_copy_to_external_buffer");
                         io->set_external_sync(buffer, sync);
                         return PBF_OK;
                     });
}

// ---- render thread -----------------------------------------------------------------------------
PBF_API pbf_render_event_fn PBF_CALL pbf_get_render_event_func(void) { return &render_event; }

PBF_API pbf_result PBF_CALL pbf_world_get_render_event_id(pbf_world_id id, int32_t* out_event_id) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(out_event_id != nullptr, "out_event_id is NULL");
        *out_event_id = 0;
        PBF_LOCK_WORLD(w, id);
        PBF_REQUIRE(id.index < 0x7FFFFFFEu, PBF_ERROR_CAPACITY,
                    std::string(fn) + ": world index too large for an event id");
        *out_event_id = int32_t(id.index + 1);
        return PBF_OK;
    });
}

// ---- info and debug ----------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_get_interop_info(pbf_world_id id, pbf_interop_info* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_interop_info, out);
        PBF_LOCK_WORLD(w, id);
        pbf_interop_info info;
        std::memset(&info, 0, sizeof info);
        info.struct_size = sizeof info;
        info.cuda_device = -1;
        info.last_render_event_result = PBF_OK;
        if (w->backend_kind() == PBF_BACKEND_CUDA) {
            PBF_INTEROP_OF(io, w);
            io->get_info(&info);
        }
        *out = info;
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_debug_get_transfer_count(uint64_t* out_transfers, uint64_t* out_bytes) {
    return guarded(__func__, [&](const char*) -> pbf_result {
        uint64_t transfers = 0, bytes = 0;
        pbf::host_device_transfers(&transfers, &bytes);
        if (out_transfers) *out_transfers = transfers;
        if (out_bytes) *out_bytes = bytes;
        return PBF_OK;
    });
}

}  // extern "C"
