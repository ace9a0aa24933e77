// The world's doors for the API and interop layers (world.h, the block "doors for the API and
// interop layers"): small state changes with their normalisation, mapping, the CUDA stream and
// profiling, so that nothing above the world reaches its backend.
#include <Eigen/Geometry>
#include <cmath>
#include <cstring>

#include "world.h"

#include "../common/c_text.h"

#include "../solver/step_plan.h"

namespace pbf {

Status World::cuda_available(int32_t device) {
    const CudaAvailability cuda = cuda_availability(device);
    return cuda.ok() ? Status{} : Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, cuda.message);
}

void World::describe_backend(pbf_backend backend, int32_t device, pbf_backend_info* out) {
    const uint32_t size = out->struct_size;
    std::memset(out, 0, sizeof *out);
    out->struct_size = size;
    CudaAvailability cuda;
    if (backend != PBF_BACKEND_CPU) {
        cuda = cuda_availability(device);
        out->device_count = cuda.device_count;
        out->driver_version = cuda.driver_version;
        out->required_driver_version = cuda.required_driver_version;
    }
    if (backend == PBF_BACKEND_CUDA || (backend == PBF_BACKEND_AUTO && cuda.ok())) {
        out->backend = PBF_BACKEND_CUDA;
        out->status = cuda.status;
        out->cuda_device = device;
        copy_text(out->device_name, cuda.device_name);
        copy_text(out->message, cuda.message);
        return;
    }
    out->backend = PBF_BACKEND_CPU;
    out->status = PBF_BACKEND_STATUS_AVAILABLE;
    out->cuda_device = -1;
    copy_text(out->device_name, cpu_device_name());
    copy_text(out->message,
              backend == PBF_BACKEND_AUTO ? "CUDA not taken: " + cuda.message : "the CPU backend is always available");
}

pbf_backend World::backend_kind() const { return backend_->kind(); }

bool World::set_emitter_enabled(pbf_emitter_id id, bool enabled) {
    EmitterEntry* e = find_emitter(id);
    if (!e) return false;
    e->desc.enabled = enabled ? 1u : 0u;
    return true;
}

Status World::set_emitter_transform(pbf_emitter_id id, const float a[3], const float b[3]) {
    EmitterEntry* e = find_emitter(id);
    if (!e) return Status::error(PBF_ERROR_INVALID_HANDLE, "emitter is not live");
    if (e->desc.type == PBF_EMITTER_NOZZLE) {
        Status st = check_nozzle(e->desc, Vec3{a[0], a[1], a[2]});
        if (!st.ok()) return st;
        for (int k = 0; k < 3; ++k) e->desc.position[k] = a[k];
        set_nozzle_direction(e->desc, Vec3{b[0], b[1], b[2]});
    } else {
        for (int k = 0; k < 3; ++k) {
            e->desc.box_min[k] = a[k];
            e->desc.box_max[k] = b[k];
        }
    }
    return Status{};
}

namespace {
// A pose from the API: the rotation normalised.
void store_pose(const float position[3], const float rotation[4], Vec3* p, float q_out[4]) {
    const Eigen::Quaternionf q = Eigen::Quaternionf(rotation[3], rotation[0], rotation[1], rotation[2]).normalized();
    *p = Vec3{position[0], position[1], position[2]};
    q_out[0] = q.x();
    q_out[1] = q.y();
    q_out[2] = q.z();
    q_out[3] = q.w();
}
}  // namespace

Status World::set_collider_target(pbf_collider_id id, const float position[3], const float rotation[4]) {
    ColliderEntry* e = find_collider(id);
    if (!e) return Status::error(PBF_ERROR_INVALID_HANDLE, "collider is not live");
    if (e->motion != PBF_MOTION_KINEMATIC)
        return Status::error(PBF_ERROR_INVALID_STATE, "only kinematic colliders can be moved");
    store_pose(position, rotation, &e->target_position, e->target_rotation);
    return Status{};
}

Status World::teleport_collider(pbf_collider_id id, const float position[3], const float rotation[4]) {
    ColliderEntry* e = find_collider(id);
    if (!e) return Status::error(PBF_ERROR_INVALID_HANDLE, "collider is not live");
    store_pose(position, rotation, &e->position, e->rotation);
    e->target_position = e->position;
    std::memcpy(e->target_rotation, e->rotation, sizeof e->rotation);
    overlaps_pending_ = true;
    return colliders_changed();
}

Status World::map_particles(bool wait_for_count, Mapping* out) {
    const bool device = backend_->kind() == PBF_BACKEND_CUDA;
    uint32_t count = PBF_COUNT_ON_DEVICE;
    if (!device || wait_for_count) {
        const Status st = backend_->particle_count(&count);  // on CUDA: waits for the stream
        if (!st.ok()) return st;
    }
    uint32_t diffuse = desc_.diffuse.max_diffuse ? count : 0u;
    if (desc_.diffuse.max_diffuse && count != PBF_COUNT_ON_DEVICE) {
        const Status st = backend_->diffuse_count(&diffuse);
        if (!st.ok()) return st;
    }
    out->live = backend_->live_buffers();
    out->count = count;
    out->diffuse_count = diffuse;
    out->device = device;
    out->cuda_stream = backend_->cuda_stream();
    mapped_ = true;
    return Status{};
}

void World::set_render_params(const pbf_render_params& params) {
    desc_.render = params;
    backend_->set_render_constants(render_constants(params, desc_.particle_radius, constants_.h));
}

LiveBuffers World::live_buffers() { return backend_->live_buffers(); }
void* World::cuda_stream() const { return backend_->cuda_stream(); }
Status World::set_cuda_stream(void* stream) { return backend_->set_cuda_stream(stream); }
void World::set_profiling(bool on) { backend_->set_profiling(on); }

Status World::get_profile(pbf_step_profile* out) {
    StageTimes times;
    const Status st = backend_->stage_times(&times);
    if (!st.ok()) return st;
    out->stage_count = kStageCount;
    for (int k = 0; k < PBF_PROFILE_MAX_STAGES; ++k) out->stage_ms[k] = k < kStageCount ? times.ms[k] : 0.0f;
    return Status{};
}

const char* World::stage_name(uint32_t stage) {
    return stage < static_cast<uint32_t>(kStageCount) ? pbf::stage_name(static_cast<int>(stage)) : nullptr;
}

const void* World::collider_force_table() const { return backend_->collider_force_table(); }
Status World::particle_count(uint32_t* count) { return backend_->particle_count(count); }
Status World::copy_buffer(pbf_buffer source, void* out, uint32_t max, uint32_t* written) {
    return backend_->copy_buffer(source, out, max, written);
}

}  // namespace pbf
