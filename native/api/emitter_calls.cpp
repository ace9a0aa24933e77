// The C ABI's emission calls: block fills, and nozzle and drain emitters.
#include <string>

#include "api_common.h"

using pbf::api::fail;
using pbf::api::guarded;

namespace {
// A desc's material: live, or zeroed (the default material).
pbf::api::Verdict material_verdict(pbf::World& w, pbf_material_id m) {
    return w.material_slot(m) >= 0 ? pbf::api::Verdict{} : pbf::api::Verdict{pbf::api::Check::MATERIAL_HANDLE};
}
}  // namespace

extern "C" {

PBF_API pbf_result PBF_CALL pbf_world_emit_block(pbf_world_id id, const pbf_block_desc* d, uint32_t* out_emitted) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        if (out_emitted) *out_emitted = 0;
        PBF_CHECK_STRUCT(pbf_block_desc, d);
        PBF_VALIDATE(pbf::api::validate_block_desc(*d));
        PBF_LOCK_WORLD(w, id);
        PBF_VALIDATE(material_verdict(*w, d->material));
        uint32_t emitted = 0;
        const pbf_result r = fail(w->emit_block(*d, &emitted));
        if (out_emitted) *out_emitted = emitted;
        return r;
    });
}

PBF_API pbf_result PBF_CALL pbf_world_create_emitter(pbf_world_id id, const pbf_emitter_desc* d, pbf_emitter_id* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_START_CREATE(pbf_emitter_desc, d, out, "out_emitter");
        PBF_VALIDATE(pbf::api::validate_emitter_desc(*d));
        PBF_LOCK_WORLD(w, id);
        PBF_VALIDATE(material_verdict(*w, d->material));
        return fail(w->create_emitter(*d, out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_destroy_emitter(pbf_world_id id, pbf_emitter_id e) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_LOCK_WORLD(w, id);
        PBF_REQUIRE(w->destroy_emitter(e), PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": emitter is not live");
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_emitter_set_enabled(pbf_world_id id, pbf_emitter_id e, uint32_t enabled) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(enabled <= 1, "enabled must be 0 or 1");
        PBF_LOCK_WORLD(w, id);
        PBF_REQUIRE(w->set_emitter_enabled(e, enabled != 0), PBF_ERROR_INVALID_HANDLE,
                    std::string(fn) + ": emitter is not live");
        return PBF_OK;
    });
}

}  // extern "C"

namespace {
// Moves a nozzle (a, b: position, direction) or a drain (a, b: box_min, box_max) of type `kind`.
pbf_result move_emitter(const char* fn, pbf_world_id id, pbf_emitter_id e, const float a[3], const float b[3],
                        pbf_emitter_type kind) {
    return guarded(fn, [&](const char*) -> pbf_result {
        PBF_VALIDATE(pbf::api::validate_emitter_transform(nullptr, a, b));
        PBF_LOCK_WORLD(w, id);
        const pbf::EmitterEntry* entry = w->find_emitter(e);
        PBF_REQUIRE(entry, PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": emitter is not live");
        PBF_VALIDATE(pbf::api::validate_emitter_kind(kind, entry->desc.type));
        PBF_VALIDATE(pbf::api::validate_emitter_transform(&entry->desc.type, a, b));
        return fail(fn, w->set_emitter_transform(e, a, b));
    });
}
}  // namespace

extern "C" {

PBF_API pbf_result PBF_CALL pbf_emitter_set_nozzle(pbf_world_id id, pbf_emitter_id e, const float position[3],
                                                   const float direction[3]) {
    return move_emitter(__func__, id, e, position, direction, PBF_EMITTER_NOZZLE);
}

PBF_API pbf_result PBF_CALL pbf_emitter_set_drain_box(pbf_world_id id, pbf_emitter_id e, const float box_min[3],
                                                      const float box_max[3]) {
    return move_emitter(__func__, id, e, box_min, box_max, PBF_EMITTER_DRAIN);
}

}  // extern "C"
