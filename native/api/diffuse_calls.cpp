// The C ABI's diffuse-particle calls (pbf_diffuse_params between steps, pbf_world_add_diffuse).
// Each validates, locks the world and calls World.
#include <string>

#include "api_common.h"

using pbf::api::fail;
using pbf::api::guarded;

extern "C" {

PBF_API pbf_result PBF_CALL pbf_world_get_diffuse_params(pbf_world_id id, pbf_diffuse_params* out) {
    return pbf::api::get_params(__func__, "pbf_diffuse_params", id, out, &pbf::World::diffuse_params);
}

PBF_API pbf_result PBF_CALL pbf_world_set_diffuse_params(pbf_world_id id, const pbf_diffuse_params* p) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_diffuse_params, p);
        PBF_VALIDATE(pbf::api::validate_diffuse_params(*p));
        PBF_LOCK_WORLD(w, id);
        const uint32_t capacity = w->diffuse_params().max_diffuse;
        if (pbf_result r = pbf::api::require_fixed(fn, "diffuse.max_diffuse is", capacity, p->max_diffuse); r != PBF_OK)
            return r;
        w->set_diffuse_params(*p);
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_add_diffuse(pbf_world_id id, const float* positions, const float* velocities,
                                                  uint32_t count, uint32_t* out_added) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        if (out_added) *out_added = 0;
        PBF_REQUIRE_ARG((positions && velocities) || count == 0, "positions or velocities is NULL");
        PBF_VALIDATE(pbf::api::validate_diffuse_rows(positions, velocities, count));
        PBF_LOCK_WORLD(w, id);
        if (pbf_result r = pbf::api::require_buffer(fn, *w, PBF_BUFFER_DIFFUSE_POSITIONS); r != PBF_OK) return r;
        uint32_t added = 0;
        const pbf_result r = fail(fn, w->add_diffuse(positions, velocities, count, &added));
        if (out_added) *out_added = added;
        return r;
    });
}

}  // extern "C"
