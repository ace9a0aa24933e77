// A solver's colliders and meshes in backend memory: the shapes and where each starts and ends a
// step, the substeps' poses (interpolated on the backend), the broad phase's lists, the dynamic
// colliders' impulses and forces, and the mesh table with each mesh's distance field.
#pragma once
#include <cstdint>
#include <vector>

#include "backend.h"
#include "collider_broadphase.h"
#include "mesh_field.h"
#include "solver_buffers.h"
#include "../core/passes.h"

namespace pbf {

template <class Exec>
class SolverColliders {
public:
    explicit SolverColliders(Exec& exec) : exec_(exec) {}

    void allocate(Allocations<Exec>& alloc, uint32_t max_colliders, float kernel_radius) {
        max_colliders_ = max_colliders;
        kernel_radius_ = kernel_radius;
        alloc(shapes_, max_colliders);
        alloc(keys_, max_colliders);
        alloc(poses_, size_t(max_colliders) * 2);
        alloc(rest_poses_, max_colliders);
        alloc(impulses_, max_colliders);
        alloc(forces_, max_colliders);
        grid_capacity_ = collider_grid_capacity(max_colliders);
        if (grid_capacity_.buckets) alloc(grid_, size_t(grid_capacity_.buckets) + 1 + grid_capacity_.entries);
        host_forces_.assign(max_colliders, ColliderForce{});
        alloc(mesh_table_, kMaxMeshes);
    }
    void zero() {
        exec_.zero(impulses_, max_colliders_ * sizeof(ColliderForce));
        exec_.zero(forces_, max_colliders_ * sizeof(ColliderForce));
        exec_.zero(mesh_table_, kMaxMeshes * sizeof(MeshView));
    }
    void release() {
        exec_.release(shapes_);
        exec_.release(keys_);
        exec_.release(poses_);
        exec_.release(grid_);
        exec_.release(rest_poses_);
        exec_.release(impulses_);
        exec_.release(forces_);
        exec_.release(mesh_table_);
        for (float*& v : mesh_values_) exec_.release(v);
    }

    bool fits(uint32_t count, size_t keys) const { return count <= max_colliders_ && keys == count; }

    // ---- a step: each collider moves from its key's start to its end --------------------------
    // The step's colliders go up once, before its first kernel (shapes, where each starts and
    // ends, the broad phase's lists); the substeps' poses are interpolated on the backend, each
    // substep's end into one of two rows that alternate (row k % 2 holds the poses at
    // t = k / substeps).
    void upload_step(const StepInput& in) {
        count_ = static_cast<uint32_t>(in.collider_shapes.size());
        substeps_ = static_cast<uint32_t>(in.substeps.size());
        dynamic_count_ = in.dynamic_count;
        if (count_ > 0) {
            exec_.upload(shapes_, in.collider_shapes.data(), count_ * sizeof(Collider));
            exec_.upload(keys_, in.collider_keys.data(), count_ * sizeof(ColliderKey));
        }
        step_ = view_of(count_, upload_grid(in.collider_shapes));
    }
    // The step's first launches: the start poses, and no impulses yet.
    void begin_step() {
        if (count_ > 0) exec_.for_each(count_, ColliderPoseOp{keys_, poses_, count_, substeps_, 0});
        if (dynamic_count_ > 0) exec_.zero(impulses_, size_t(max_colliders_) * sizeof(ColliderForce));
    }
    // Substep k's colliders, from its start poses to its end poses (interpolated first); dynamic
    // colliders record their impulses, scaled by impulse_scale.
    ColliderView substep(uint32_t k, float impulse_scale) {
        ColliderPose* end = poses_ + ((k + 1) % 2) * count_;
        if (count_ > 0) exec_.for_each(count_, ColliderPoseOp{keys_, end, count_, substeps_, k + 1});
        ColliderView view = step_;
        view.prev = poses_ + (k % 2) * count_;
        view.cur = end;
        if (dynamic_count_ > 0) {
            view.dynamic_count = dynamic_count_;
            view.impulses = impulses_;
            view.impulse_scale = impulse_scale;
        }
        return view;
    }
    // Between steps the colliders stand at the step's end poses; the dynamic ones' impulses
    // become the step's mean forces.
    void end_step(float frame_dt) {
        at_rest_ = step_;
        at_rest_.prev = at_rest_.cur = poses_ + (substeps_ % 2) * count_;
        if (dynamic_count_ > 0) exec_.for_each(count_, ColliderForceOp{shapes_, impulses_, forces_, 1.0f / frame_dt});
        host_forces_valid_ = false;
    }

    // ---- between steps ----------------------------------------------------------------------
    // The colliders outside a step (densities for the statistics, diffuse particles).
    const ColliderView& at_rest() const { return at_rest_; }

    Status set_at_rest(const ColliderSetAtRest& c) {
        const uint32_t count = static_cast<uint32_t>(c.shapes.size());
        if (!fits(count, c.keys.size()))
            return Status::error(PBF_ERROR_INTERNAL, "collider set exceeds the solver's collider buffers");
        // The shapes table is also the steps': rewritten here, ordered after earlier steps.
        if (count > 0) {
            exec_.upload(shapes_, c.shapes.data(), count * sizeof(Collider));
            exec_.upload(keys_, c.keys.data(), count * sizeof(ColliderKey));
            exec_.for_each(count, ColliderPoseOp{keys_, rest_poses_, count, 0});
        }
        at_rest_ = view_of(count, upload_grid(c.shapes));
        at_rest_.prev = at_rest_.cur = rest_poses_;
        return exec_.check("updating colliders");
    }

    Status forces(const ColliderForce** rows) {
        if (!host_forces_valid_) {
            exec_.download(host_forces_.data(), forces_, host_forces_.size() * sizeof(ColliderForce));
            Status st = exec_.check("reading collider forces");
            if (!st.ok()) return st;
            host_forces_valid_ = true;
        }
        *rows = host_forces_.data();
        return Status{};
    }
    const ColliderForce* force_table() const { return forces_; }
    Status clear_forces() {
        exec_.zero(forces_, max_colliders_ * sizeof(ColliderForce));
        host_forces_valid_ = false;
        return exec_.check("clearing the collider forces");
    }
    Status clear_force(uint32_t row) {
        if (row >= max_colliders_) return Status::error(PBF_ERROR_INTERNAL, "collider row out of range");
        exec_.zero(forces_ + row, sizeof(ColliderForce));
        host_forces_valid_ = false;
        return exec_.check("clearing a collider's force");
    }

    // ---- meshes: a field per mesh, its view in a row of the mesh table -------------------------
    Status create_mesh(const MeshBuild& b, uint32_t row) {
        if (row >= kMaxMeshes || mesh_values_[row]) return Status::error(PBF_ERROR_INTERNAL, "mesh row in use");
        float* values = nullptr;
        Status st = build_mesh_field(exec_, b, &values);
        if (!st.ok()) return st;
        MeshView v = b.grid;
        v.values = values;
        v.boundary = values + size_t(v.nx) * size_t(v.ny) * size_t(v.nz);
        mesh_values_[row] = values;
        exec_.upload(mesh_table_ + row, &v, sizeof v);
        return exec_.check("pbf_world_create_mesh");
    }
    void destroy_mesh(uint32_t row) {
        if (row >= kMaxMeshes) return;
        exec_.release(mesh_values_[row]);  // a CUDA free waits for the steps that may still read it
        mesh_values_[row] = nullptr;
    }

private:
    // Lists the colliders by coarse cells on the host and uploads the lists (stream-ordered, like
    // the shapes they index); the returned grid points at them.
    ColliderGrid upload_grid(const std::vector<Collider>& shapes) {
        build_collider_grid(shapes, kernel_radius_, grid_capacity_, &grid_lists_);
        ColliderGrid g = grid_lists_.grid;  // no lists: null pointers, every query walks all
        if (grid_lists_.bucket_begin.empty()) return g;
        uint32_t* entries = grid_ + grid_capacity_.buckets + 1;
        exec_.upload(grid_, grid_lists_.bucket_begin.data(), grid_lists_.bucket_begin.size() * sizeof(uint32_t));
        exec_.upload(entries, grid_lists_.entries.data(), grid_lists_.entries.size() * sizeof(uint32_t));
        g.bucket_begin = grid_;
        g.entries = entries;
        return g;
    }

    // The first count colliders, listed by grid; their poses are the caller's to set.
    ColliderView view_of(uint32_t count, const ColliderGrid& grid) const {
        ColliderView v;
        v.shapes = shapes_;
        v.count = count;
        v.meshes = mesh_table_;
        v.grid = grid;
        return v;
    }

    Exec& exec_;
    uint32_t max_colliders_ = 0;
    float kernel_radius_ = 0.0f;          // h: the reach of the broad phase's queries
    Collider* shapes_ = nullptr;          // max_colliders
    ColliderKey* keys_ = nullptr;         // max_colliders: where each starts and ends the step
    ColliderPose* poses_ = nullptr;       // 2 rows of the step's colliders: a substep's start and end
    ColliderPose* rest_poses_ = nullptr;  // max_colliders, set between steps
    ColliderGridCapacity grid_capacity_;
    uint32_t* grid_ = nullptr;                // the broad phase's bucket offsets, then its entries
    ColliderGridLists grid_lists_;            // the host's build, kept to reuse its storage
    ColliderForce* impulses_ = nullptr;       // max_colliders rows: the running step's impulses
    ColliderForce* forces_ = nullptr;         // max_colliders rows: the last step's mean forces
    std::vector<ColliderForce> host_forces_;  // the host's copy of forces_
    bool host_forces_valid_ = false;
    MeshView* mesh_table_ = nullptr;       // kMaxMeshes rows
    float* mesh_values_[kMaxMeshes] = {};  // each live mesh's field (its row's values)
    ColliderView at_rest_{};               // the colliders outside a step
    // The running step's colliders (upload_step): its view without poses.
    ColliderView step_{};
    uint32_t count_ = 0;
    uint32_t substeps_ = 0;
    uint32_t dynamic_count_ = 0;
};

}  // namespace pbf
