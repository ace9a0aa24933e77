// The C ABI's world calls: create and destroy, step, parameters, info and statistics, and the
// particles (count, copy-out, mapping). Each validates, locks the world and calls World.
#include <algorithm>
#include <cmath>
#include <string>

#include "api_common.h"

using pbf::Status;
using pbf::World;
using pbf::api::fail;
using pbf::api::guarded;
using pbf::api::log_message;
using pbf::api::raw;

namespace {

template <class T, class Copy>
pbf_result copy_out(const char* fn, pbf_world_id id, T* out, uint32_t max_count, uint32_t* written, Copy copy) {
    return guarded(fn, [&](const char*) -> pbf_result {
        if (written) *written = 0;
        PBF_REQUIRE_ARG(out != nullptr || max_count == 0, "output array is NULL");
        PBF_LOCK_WORLD(w, id);
        uint32_t n = 0;
        const pbf_result r = fail(copy(*w, out, max_count, &n));
        if (written) *written = n;
        return r;
    });
}

}  // namespace

extern "C" {

PBF_API pbf_result PBF_CALL pbf_world_create(const pbf_world_desc* d, pbf_world_id* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_START_CREATE(pbf_world_desc, d, out, "out_world");
        PBF_VALIDATE(pbf::api::validate_world_desc(*d));
        PBF_CHECK_STRUCT(pbf_solver_params, &d->solver);
        PBF_VALIDATE(pbf::api::validate_solver_params(d->solver));
        PBF_CHECK_STRUCT(pbf_render_params, &d->render);
        PBF_VALIDATE(pbf::api::validate_render_params(d->render));
        PBF_CHECK_STRUCT(pbf_diffuse_params, &d->diffuse);
        PBF_VALIDATE(pbf::api::validate_diffuse_params(d->diffuse));
        if (d->backend == PBF_BACKEND_CUDA) {
            const Status cuda = World::cuda_available(d->cuda_device);
            if (!cuda.ok())
                return fail(PBF_ERROR_BACKEND_UNAVAILABLE,
                            std::string(fn) + ": PBF_BACKEND_CUDA requested, but CUDA device " +
                                std::to_string(d->cuda_device) + " cannot be used: " + cuda.message);
        }

        Status st;
        std::unique_ptr<World> world = World::create(*d, &st);
        if (!world) return fail(st.code, std::string(fn) + ": " + st.message);
        pbf_world_info info{};
        world->get_info(&info);
        *out = pbf::api::insert_world(std::move(world));
        log_message(PBF_LOG_INFO, std::string("world created on ") + info.device_name + ", capacity " +
                                      std::to_string(d->max_particles));
        if (d->backend == PBF_BACKEND_AUTO && info.backend == PBF_BACKEND_CPU)
            log_message(PBF_LOG_INFO, "CUDA not taken: " + World::cuda_available(d->cuda_device).message);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_destroy(pbf_world_id id) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        std::shared_ptr<pbf::api::WorldEntry> entry = pbf::api::remove_world(id);
        if (!entry) return fail(PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": world is not live (destroyed twice?)");
        std::lock_guard<std::mutex> lock(entry->mutex);  // waits for a call in flight
        entry->world.reset();
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_step(pbf_world_id id, float dt) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(std::isfinite(dt) && dt > 0.0f && dt <= 1.0f,
                        "dt must be finite and in (0, 1] seconds, got " + std::to_string(dt));
        PBF_LOCK_WORLD(w, id);
        return fail(w->step(dt));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_solver_params(pbf_world_id id, pbf_solver_params* out) {
    return pbf::api::get_params(__func__, "pbf_solver_params", id, out, &pbf::World::solver_params);
}

PBF_API pbf_result PBF_CALL pbf_world_set_solver_params(pbf_world_id id, const pbf_solver_params* p) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_solver_params, p);
        PBF_VALIDATE(pbf::api::validate_solver_params(*p));
        PBF_LOCK_WORLD(w, id);
        w->set_solver_params(*p);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_set_gravity(pbf_world_id id, const float g[3]) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_VALIDATE(pbf::api::validate_gravity(g));
        PBF_LOCK_WORLD(w, id);
        w->set_gravity(g);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_render_params(pbf_world_id id, pbf_render_params* out) {
    return pbf::api::get_params(__func__, "pbf_render_params", id, out, &pbf::World::render_params);
}

PBF_API pbf_result PBF_CALL pbf_world_set_render_params(pbf_world_id id, const pbf_render_params* p) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_render_params, p);
        PBF_VALIDATE(pbf::api::validate_render_params(*p));
        PBF_LOCK_WORLD(w, id);
        if (pbf_result r = pbf::api::require_fixed(fn, "render.flags are", w->render_flags(), p->flags); r != PBF_OK)
            return r;
        w->set_render_params(*p);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_get_backend_info(pbf_backend backend, int32_t cuda_device, pbf_backend_info* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_backend_info, out);
        const int32_t b = raw(backend);
        PBF_REQUIRE_ARG(b == PBF_BACKEND_AUTO || b == PBF_BACKEND_CPU || b == PBF_BACKEND_CUDA,
                        "backend must be PBF_BACKEND_AUTO, PBF_BACKEND_CPU or PBF_BACKEND_CUDA");
        PBF_REQUIRE_ARG(b == PBF_BACKEND_CPU || cuda_device >= 0, "cuda_device must be >= 0");
        World::describe_backend(backend, cuda_device, out);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_info(pbf_world_id id, pbf_world_info* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_world_info, out);
        PBF_LOCK_WORLD(w, id);
        w->get_info(out);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_stats(pbf_world_id id, pbf_step_stats* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_step_stats, out);
        PBF_LOCK_WORLD(w, id);
        return fail(w->get_stats(out));
    });
}

// ---- profiling -------------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_set_profiling(pbf_world_id id, uint32_t enabled) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(enabled <= 1, "enabled must be 0 or 1");
        PBF_LOCK_WORLD(w, id);
        w->set_profiling(enabled != 0);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_profile(pbf_world_id id, pbf_step_profile* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_step_profile, out);
        PBF_LOCK_WORLD(w, id);
        return fail(w->get_profile(out));
    });
}

PBF_API const char* PBF_CALL pbf_profile_stage_name(uint32_t stage) { return pbf::World::stage_name(stage); }

// ---- particles -------------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_world_get_particle_count(pbf_world_id id, uint32_t* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(out != nullptr, "out_count is NULL");
        PBF_LOCK_WORLD(w, id);
        return fail(w->particle_count(out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_copy_positions(pbf_world_id id, float* out, uint32_t max_count,
                                                     uint32_t* written) {
    return copy_out(__func__, id, out, max_count, written,
                    [](World& w, float* o, uint32_t m, uint32_t* n) { return w.copy_positions(o, m, n); });
}
PBF_API pbf_result PBF_CALL pbf_world_copy_velocities(pbf_world_id id, float* out, uint32_t max_count,
                                                      uint32_t* written) {
    return copy_out(__func__, id, out, max_count, written,
                    [](World& w, float* o, uint32_t m, uint32_t* n) { return w.copy_velocities(o, m, n); });
}
PBF_API pbf_result PBF_CALL pbf_world_copy_ids(pbf_world_id id, uint32_t* out, uint32_t max_count, uint32_t* written) {
    return copy_out(__func__, id, out, max_count, written,
                    [](World& w, uint32_t* o, uint32_t m, uint32_t* n) { return w.copy_ids(o, m, n); });
}

PBF_API pbf_result PBF_CALL pbf_world_copy_buffer(pbf_world_id id, pbf_buffer source, void* out, uint64_t out_bytes,
                                                  uint32_t* written) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        if (written) *written = 0;
        PBF_VALIDATE(pbf::api::validate_copy_out(source, out_bytes));
        PBF_REQUIRE_ARG(out != nullptr || out_bytes == 0, "out is NULL");
        PBF_LOCK_WORLD(w, id);
        if (pbf_result r = pbf::api::require_buffer(fn, *w, source); r != PBF_OK) return r;
        const uint64_t fit = out_bytes / World::element_bytes(source);
        uint32_t n = 0;
        const pbf_result r = fail(fn, w->copy_buffer(source, out, uint32_t(std::min<uint64_t>(fit, UINT32_MAX)), &n));
        if (written) *written = n;
        return r;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_map_positions(pbf_world_id id, pbf_mapped_buffer* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_mapped_buffer, out);
        PBF_LOCK_WORLD(w, id);
        World::Mapping m;
        if (pbf_result r = fail(w->map_particles(/*wait_for_count=*/true, &m)); r != PBF_OK) return r;
        out->memory = m.device ? PBF_MEMORY_CUDA_DEVICE : PBF_MEMORY_HOST;
        out->data = m.live.positions;
        out->count = m.count;
        out->stride_bytes = 16;
        out->reserved0 = out->reserved1 = 0;
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_unmap(pbf_world_id id) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_LOCK_WORLD(w, id);
        PBF_REQUIRE(w->mapped(), PBF_ERROR_INVALID_STATE, std::string(fn) + ": no buffer is mapped");
        w->unmap();
        return PBF_OK;
    });
}

}  // extern "C"
