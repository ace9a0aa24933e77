#include "world.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "../common/c_text.h"
#include "../solver/step_plan.h"

namespace pbf {
namespace {

Vec3 to_vec3(const float v[3]) { return Vec3{v[0], v[1], v[2]}; }

Eigen::Quaternionf to_quat(const float q[4]) { return Eigen::Quaternionf(q[3], q[0], q[1], q[2]).normalized(); }

Quat quat_of(const float q[4]) { return Quat{q[0], q[1], q[2], q[3]}; }

}  // namespace

std::unique_ptr<World> World::create(const pbf_world_desc& desc, Status* status) {
    std::unique_ptr<World> w(new World());
    w->desc_ = desc;
    *status = check_fluid(desc.particle_radius, desc.rest_density);
    if (!status->ok()) return nullptr;
    w->init_materials();
    w->update_constants();
    const WorldConstants& c = w->constants_;
    BackendConfig config{desc.max_particles,
                         desc.max_colliders,
                         c.grid,
                         desc.cuda_device,
                         render_constants(desc.render, desc.particle_radius, c.h),
                         diffuse_constants(desc.diffuse),
                         c.h};
    pbf_backend kind = desc.backend;
    if (kind == PBF_BACKEND_AUTO) kind = cuda_availability(desc.cuda_device).ok() ? PBF_BACKEND_CUDA : PBF_BACKEND_CPU;
    w->backend_ = kind == PBF_BACKEND_CUDA ? create_cuda_backend(config, status) : create_cpu_backend(config, status);
    if (!w->backend_) return nullptr;
    return w;
}

World::~World() = default;

void World::set_solver_params(const pbf_solver_params& p) {
    desc_.solver = p;
    update_constants();
}

void World::set_gravity(const float g[3]) {
    std::memcpy(desc_.gravity, g, sizeof desc_.gravity);
    update_constants();
}

void World::update_constants() { constants_ = derive_constants(desc_, material_table()); }

uint32_t World::gather_colliders(bool moving, std::vector<Collider>* shapes, std::vector<ColliderKey>* keys) {
    uint32_t dynamic = 0;
    colliders_.for_each([&](ColliderEntry& e) {
        ColliderKey k{e.position, moving ? e.target_position : e.position, quat_of(e.rotation),
                      quat_of(moving ? e.target_rotation : e.rotation)};
        if (e.collider.flags & kColliderDynamic) ++dynamic;
        shapes->push_back(place_collider(e.collider, k));
        keys->push_back(k);
    });
    return dynamic;
}

Status World::colliders_changed() {
    ColliderSetAtRest rest;
    gather_colliders(false, &rest.shapes, &rest.keys);
    return backend_->set_colliders_at_rest(rest);
}

bool World::destroy_collider(pbf_collider_id id) {
    const ColliderEntry* e = find_collider(id);
    if (!e) return false;
    if (MeshEntry* m = meshes_.find(e->mesh.index, e->mesh.generation)) --m->users;
    colliders_.erase(id.index, id.generation);
    (void)colliders_changed();  // the step uploads its colliders anyway; this serves stats between steps
    return true;
}

Status World::step(float frame_dt) {
    StepInput input;
    input.dynamic_count = gather_colliders(true, &input.collider_shapes, &input.collider_keys);
    std::vector<EmitterState> emitters;
    emitters.reserve(emitters_.size());
    emitters_.for_each([&](EmitterEntry& e) {
        const uint8_t material = static_cast<uint8_t>(std::max(0, material_slot(e.desc.material)));
        emitters.push_back(EmitterState{e.desc, e.accumulator, e.sequence, material});
    });
    FrameState frame;
    frame.frame_dt = frame_dt;
    frame.feedback = backend_->feedback();  // the substep count and the substep's length read it
    frame.emitted_speed = emitted_speed_;
    frame.emitted_depth = emitted_depth_;
    frame.overlaps_pending = overlaps_pending_;
    frame.carried_dt = carried_dt_;
    plan_step(desc_.solver, constants_, material_table(), frame, &emitters, &input);
    carried_dt_ = input.carried_dt;
    mapped_ = false;  // the mapping is valid until the next step
    if (input.substeps.empty()) {
        // Too short to simulate (plan_step): nothing advances; the colliders keep their targets
        // and the emitters their state for the step that simulates this one's time. No collider
        // felt an impulse: their forces read 0, in pbf_collider_get_force and in the mapped table.
        ++step_index_;
        last_substeps_ = 0;
        last_iterations_ = 0;
        last_simulated_dt_ = 0.0f;
        return input.dynamic_count > 0 ? backend_->clear_collider_forces() : Status{};
    }
    size_t k = 0;
    emitters_.for_each([&](EmitterEntry& e) {
        e.accumulator = emitters[k].accumulator;
        e.sequence = emitters[k].sequence;
        ++k;
    });
    Status st = backend_->step(constants_, input);
    // Kinematic colliders arrived at their targets.
    colliders_.for_each([](ColliderEntry& e) {
        e.position = e.target_position;
        std::memcpy(e.rotation, e.target_rotation, sizeof e.rotation);
    });
    if (st.ok()) {
        const uint32_t substeps = static_cast<uint32_t>(input.substeps.size());
        ++step_index_;
        last_substeps_ = substeps;
        last_iterations_ = 0;
        for (const SubstepInput& sub : input.substeps) last_iterations_ += sub.iterations;
        last_simulated_dt_ = input.simulated_dt;
        emitted_speed_ = 0.0f;
        emitted_depth_ = 0.0f;
        overlaps_pending_ = false;
        if (attachment_) st = attachment_->after_step();  // e.g. copies into graphics buffers
    }
    return st;
}

void World::get_info(pbf_world_info* info) const {
    info->backend = backend_->kind();
    info->max_particles = desc_.max_particles;
    info->particle_radius = desc_.particle_radius;
    info->rest_spacing = rest_spacing();
    info->kernel_radius = constants_.h;
    info->particle_mass = constants_.mass;
    info->grid_cells = constants_.grid.num_cells;
    info->device_bytes = backend_->device_bytes();
    copy_text(info->device_name, backend_->device_name());
    info->render_flags = desc_.render.flags;
    info->reserved0 = 0;
    info->render_bytes = backend_->render_bytes();
    info->render_updates = backend_->render_updates();
    info->diffuse_capacity = desc_.diffuse.max_diffuse;
    info->reserved1 = 0;
    info->diffuse_bytes = backend_->diffuse_bytes();
    info->diffuse_updates = backend_->diffuse_updates();
    info->grid_hashed = constants_.grid.hashed;
    info->reserved2 = 0;
    info->grid_bytes = (uint64_t(constants_.grid.num_cells) + 1) * sizeof(uint32_t);  // the solver's cell_begin
}

Status World::get_stats(pbf_step_stats* out) {
    StatsReadback r;
    // Any substep's constants serve: the density pass and the reduction use no dt.
    Status st = backend_->read_stats(constants_, &r);
    if (!st.ok()) return st;
    float ms = 0.0f;
    st = backend_->last_step_ms(&ms);
    if (!st.ok()) return st;
    out->particle_count = r.count;
    out->step_index = step_index_;
    out->emitted_total = r.emitted_total;
    out->drained_total = r.drained_total;
    out->density_error_mean = r.count ? static_cast<float>(r.error_sum / r.count) : 0.0f;
    out->density_error_max = r.error_max;
    out->kinetic_energy = static_cast<float>(r.kinetic_energy);
    out->step_time_ms = step_index_ ? ms : 0.0f;
    out->iterations = desc_.solver.adaptive_error_target > 0.0f ? r.iterations_used : last_iterations_;
    out->substeps = step_index_ ? last_substeps_ : 0u;
    out->speed_clamps = step_index_ ? r.speed_clamps : 0u;
    out->simulated_dt = step_index_ ? last_simulated_dt_ : 0.0f;
    out->diffuse_count = r.diffuse_count;
    out->diffuse_dropped = step_index_ ? r.diffuse_dropped_step : 0u;
    out->diffuse_generated_total = r.diffuse_generated_total;
    out->diffuse_dropped_total = r.diffuse_dropped_total;
    return Status{};
}

void World::set_nozzle_direction(pbf_emitter_desc& d, Vec3 direction) {
    const Vec3 unit = direction * (1.0f / length(direction));
    d.direction[0] = unit.x;
    d.direction[1] = unit.y;
    d.direction[2] = unit.z;
}

Status World::emit_block(const pbf_block_desc& d, uint32_t* emitted) {
    BlockEmission b{};
    Status st = plan_block(d, constants_, rest_spacing(), desc_.max_particles, &b);
    if (!st.ok()) return st;
    b.material = static_cast<uint8_t>(material_slot(d.material));  // validated: live or zeroed
    st = backend_->emit_block(b, constants_, emitted);
    if (*emitted > 0) {
        mapped_ = false;  // new particles reorder storage; a failed emit keeps the map
        emitted_speed_ = std::fmax(emitted_speed_, length(b.velocity));
        // The block's extent along gravity (what the next step's depth rule needs before any
        // step has measured it).
        emitted_depth_ = std::fmax(emitted_depth_, block_depth(b, constants_.gravity));
        // Into a collider: the next step settles the overlap (Solver::settle). Tested against
        // the colliders' bounds, so that blocks emitted clear of them cost no settling.
        ColliderSetAtRest rest;
        gather_colliders(false, &rest.shapes, &rest.keys);
        overlaps_pending_ = overlaps_pending_ || block_meets(b, desc_.particle_radius, rest.shapes);
    }
    if (st.ok() && *emitted == 0)
        return Status::error(PBF_ERROR_CAPACITY, "world is full (max_particles = " +
                                                     std::to_string(desc_.max_particles) + "); nothing was emitted");
    return st;
}

// A nozzle the solver can honour: its disc centre inside the walls (particles emitted outside
// would be clamped onto a wall and pile up there), and a rate its disc can carry at rest
// spacing (faster, particles would be emitted on top of each other).
Status World::check_nozzle(const pbf_emitter_desc& d, Vec3 position) const {
    if (!inside_walls(constants_, position))
        return Status::error(PBF_ERROR_INVALID_ARGUMENT,
                             "the nozzle's position lies outside the walls (particle centres stay one "
                             "particle_radius inside domain_min..domain_max; without walls, within 2^17 h of the "
                             "origin on each axis)");
    const double carried = nozzle_capacity(d, rest_spacing());
    if (d.particles_per_second > carried * 1.0001) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "particles_per_second %g exceeds what the nozzle carries at rest spacing (%.6g: disc area / "
                      "spacing² x speed / spacing); raise its speed or radius",
                      double(d.particles_per_second), carried);
        return Status::error(PBF_ERROR_INVALID_ARGUMENT, text);
    }
    return Status{};
}

Status World::create_emitter(const pbf_emitter_desc& desc, pbf_emitter_id* out) {
    EmitterEntry e;
    e.desc = desc;
    if (desc.type == PBF_EMITTER_NOZZLE) {
        Status st = check_nozzle(desc, to_vec3(desc.position));
        if (!st.ok()) return st;
        set_nozzle_direction(e.desc, to_vec3(desc.direction));
    }
    const auto h = emitters_.insert(e);
    *out = pbf_emitter_id{h.index, h.generation};
    return Status{};
}

Status World::create_collider(const pbf_collider_desc& d, pbf_collider_id* out) {
    if (colliders_.size() >= desc_.max_colliders)
        return Status::error(PBF_ERROR_CAPACITY,
                             "the world holds max_colliders = " + std::to_string(desc_.max_colliders) +
                                 " colliders already (pbf_world_desc.max_colliders)");
    ColliderEntry e{};
    MeshEntry* mesh = nullptr;
    if (d.shape == PBF_SHAPE_MESH) {
        mesh = meshes_.find(d.mesh.index, d.mesh.generation);
        if (!mesh) return Status::error(PBF_ERROR_INVALID_HANDLE, "mesh is not a live mesh of this world");
        e.mesh = d.mesh;
        e.collider.mesh = d.mesh.index;
    }
    e.collider.shape = static_cast<uint32_t>(d.shape);
    e.collider.radius = mesh ? mesh->reach : d.radius;
    e.collider.half_height = d.half_height;
    e.collider.friction = d.friction;
    e.collider.half_extents = to_vec3(d.half_extents);
    e.collider.flags = d.dynamic ? kColliderDynamic : 0u;
    e.collider.center_local = to_vec3(d.center_of_mass);
    e.motion = static_cast<uint32_t>(d.motion);
    e.position = e.target_position = to_vec3(d.position);
    const Eigen::Quaternionf q = to_quat(d.rotation);
    const float qn[4] = {q.x(), q.y(), q.z(), q.w()};
    std::memcpy(e.rotation, qn, sizeof qn);
    std::memcpy(e.target_rotation, qn, sizeof qn);
    const auto h = colliders_.insert(e);
    // The handle's index is the collider's row of the force tables (indices stay below
    // max_colliders: the table reuses freed ones first).
    colliders_.find(h.index, h.generation)->collider.row = h.index;
    Status st = backend_->clear_collider_force(h.index);
    if (st.ok()) st = colliders_changed();
    if (!st.ok()) {
        colliders_.erase(h.index, h.generation);
        return st;
    }
    if (mesh) ++mesh->users;
    overlaps_pending_ = true;
    *out = pbf_collider_id{h.index, h.generation};
    return st;
}

Status World::collider_force(pbf_collider_id id, pbf_collider_force* out) {
    const ColliderEntry* e = find_collider(id);
    if (!e) return Status::error(PBF_ERROR_INVALID_HANDLE, "collider is not live");
    if (!(e->collider.flags & kColliderDynamic))
        return Status::error(PBF_ERROR_INVALID_STATE,
                             "the collider is not dynamic (pbf_collider_desc.dynamic = 1 records its force)");
    const ColliderForce* rows = nullptr;
    Status st = backend_->collider_forces(&rows);
    if (!st.ok()) return st;
    const ColliderForce& f = rows[e->collider.row];
    const float values[6] = {f.force.x, f.force.y, f.force.z, f.torque.x, f.torque.y, f.torque.z};
    std::memcpy(out->force, values, 3 * sizeof(float));
    std::memcpy(out->torque, values + 3, 3 * sizeof(float));
    return st;
}

}  // namespace pbf
