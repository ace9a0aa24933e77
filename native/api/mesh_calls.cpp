// The C ABI's mesh calls: a triangle mesh becomes a distance field that mesh
// colliders (PBF_SHAPE_MESH) share.
#include <string>

#include "api_common.h"

using pbf::api::fail;
using pbf::api::guarded;

extern "C" {

PBF_API pbf_result PBF_CALL pbf_world_create_mesh(pbf_world_id id, const pbf_mesh_desc* d, pbf_mesh_id* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_START_CREATE(pbf_mesh_desc, d, out, "out_mesh");
        PBF_VALIDATE(pbf::api::validate_mesh_desc(*d));
        PBF_LOCK_WORLD(w, id);
        PBF_VALIDATE(pbf::api::validate_mesh_voxels(w->mesh_layout(*d).voxels));
        return fail(fn, w->create_mesh(*d, out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_destroy_mesh(pbf_world_id id, pbf_mesh_id m) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_LOCK_WORLD(w, id);
        return fail(fn, w->destroy_mesh(m));
    });
}

}  // extern "C"
