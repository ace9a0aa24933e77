// The C ABI's material calls: create, destroy, read and change a world's fluid
// materials, and the table of their handles by per-particle index.
#include <string>

#include "api_common.h"

using pbf::api::fail;
using pbf::api::guarded;
using pbf::api::refuse;
using pbf::api::Verdict;
using Check = pbf::api::Check;

namespace {
// A live, non-zeroed material handle (a zeroed one names the default material only in descs).
bool live(pbf::World& w, pbf_material_id id) { return id.generation != 0 && w.material_slot(id) >= 0; }
}  // namespace

extern "C" {

PBF_API pbf_result PBF_CALL pbf_world_create_material(pbf_world_id id, const pbf_material_desc* d,
                                                      pbf_material_id* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_START_CREATE(pbf_material_desc, d, out, "out_material");
        PBF_LOCK_WORLD(w, id);
        PBF_VALIDATE(pbf::api::validate_material_desc(*d, w->rest_density(), false));
        return fail(fn, w->create_material(*d, out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_destroy_material(pbf_world_id id, pbf_material_id m) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_LOCK_WORLD(w, id);
        if (!live(*w, m)) return refuse(fn, Verdict{Check::MATERIAL_HANDLE});
        if (w->material_slot(m) == 0) return refuse(fn, Verdict{Check::MATERIAL_DEFAULT_DESTROY});
        uint32_t emitters = 0, particles = 0;
        const pbf::Status st = w->destroy_material(m, &emitters, &particles);
        if (emitters > 0 || particles > 0) return refuse(fn, Verdict{Check::MATERIAL_IN_USE, emitters, particles});
        return fail(fn, st);
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_material(pbf_world_id id, pbf_material_id m, pbf_material_desc* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_material_desc, out);
        PBF_LOCK_WORLD(w, id);
        if (!live(*w, m)) return refuse(fn, Verdict{Check::MATERIAL_HANDLE});
        return fail(fn, w->get_material(m, out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_set_material(pbf_world_id id, pbf_material_id m, const pbf_material_desc* d) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_material_desc, d);
        PBF_LOCK_WORLD(w, id);
        if (!live(*w, m)) return refuse(fn, Verdict{Check::MATERIAL_HANDLE});
        PBF_VALIDATE(pbf::api::validate_material_desc(*d, w->rest_density(), w->material_slot(m) == 0));
        return fail(fn, w->set_material(m, *d));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_get_materials(pbf_world_id id, pbf_material_id out[PBF_MAX_MATERIALS]) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(out != nullptr, "out_materials is NULL");
        PBF_LOCK_WORLD(w, id);
        w->material_handles(out);
        return PBF_OK;
    });
}

}  // extern "C"
