// The C ABI's collider calls: create, destroy, the target pose of kinematic colliders, and the
// fluid's force on dynamic ones.
#include <string>

#include "api_common.h"

using pbf::api::fail;
using pbf::api::guarded;

namespace {
// A collider's new pose, validated: its target at the end of the next step, or (teleporting)
// where it stands at once.
pbf_result pose_collider(const char* fn, pbf_world_id id, pbf_collider_id c, const float position[3],
                         const float rotation[4],
                         pbf::Status (pbf::World::*set_pose)(pbf_collider_id, const float*, const float*)) {
    return guarded(fn, [&](const char*) -> pbf_result {
        PBF_VALIDATE(pbf::api::validate_collider_pose(position, rotation));
        PBF_LOCK_WORLD(w, id);
        return fail(fn, ((*w).*set_pose)(c, position, rotation));
    });
}
}  // namespace

extern "C" {

PBF_API pbf_result PBF_CALL pbf_world_create_collider(pbf_world_id id, const pbf_collider_desc* d,
                                                      pbf_collider_id* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_START_CREATE(pbf_collider_desc, d, out, "out_collider");
        PBF_VALIDATE(pbf::api::validate_collider_desc(*d));
        PBF_LOCK_WORLD(w, id);
        return fail(w->create_collider(*d, out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_destroy_collider(pbf_world_id id, pbf_collider_id c) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_LOCK_WORLD(w, id);
        PBF_REQUIRE(w->destroy_collider(c), PBF_ERROR_INVALID_HANDLE, std::string(fn) + ": collider is not live");
        return PBF_OK;
    });
}

PBF_API pbf_result PBF_CALL pbf_collider_set_target_pose(pbf_world_id id, pbf_collider_id c, const float position[3],
                                                         const float rotation[4]) {
    return pose_collider(__func__, id, c, position, rotation, &pbf::World::set_collider_target);
}

PBF_API pbf_result PBF_CALL pbf_collider_teleport(pbf_world_id id, pbf_collider_id c, const float position[3],
                                                  const float rotation[4]) {
    return pose_collider(__func__, id, c, position, rotation, &pbf::World::teleport_collider);
}

PBF_API pbf_result PBF_CALL pbf_collider_get_force(pbf_world_id id, pbf_collider_id c, pbf_collider_force* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_REQUIRE_ARG(out != nullptr, "out_force is NULL");
        PBF_LOCK_WORLD(w, id);
        return fail(fn, w->collider_force(c, out));
    });
}

PBF_API pbf_result PBF_CALL pbf_world_map_collider_forces(pbf_world_id id, pbf_mapped_buffer* out) {
    return guarded(__func__, [&](const char* fn) -> pbf_result {
        PBF_CHECK_STRUCT(pbf_mapped_buffer, out);
        PBF_LOCK_WORLD(w, id);
        out->memory = w->backend_kind() == PBF_BACKEND_CUDA ? PBF_MEMORY_CUDA_DEVICE : PBF_MEMORY_HOST;
        out->data = const_cast<void*>(w->collider_force_table());
        out->count = w->max_colliders();
        out->stride_bytes = sizeof(pbf_collider_force);
        out->reserved0 = out->reserved1 = 0;
        return PBF_OK;
    });
}

}  // extern "C"
