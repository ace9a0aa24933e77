// The step, written once: the order of passes (Meno & Tsuruno Fig. 3 on top of Macklin &
// Müller 2013), instantiated with CpuExec in solver_cpu.cpp and with CudaExec in
// solver_cuda.cpp. Exec supplies memory, for_each(n, op), a key/value sort and reductions.
#pragma once
#include <algorithm>
#include <utility>
#include <vector>

#include "backend.h"
#include "mesh_field.h"
#include "../core/passes.h"
#include "../core/step_ops.h"
#include "../core/diffuse_ops.h"
#include "../core/render_ops.h"
#include "collider_broadphase.h"

namespace pbf {

template <class Exec>
class Solver final : public Backend {
public:
    template <class... ExecArgs>
    explicit Solver(ExecArgs&&... args) : exec_(std::forward<ExecArgs>(args)...) {}
    ~Solver() override {
        exec_.activate();
        release();
    }

    Status init(const BackendConfig& config) {
        config_ = config;
        Status st = exec_.init(config.capacity, config.grid.num_cells);
        if (!st.ok()) return st;
        const size_t n = config.capacity;
        bool ok = true;
        auto alloc = [&](auto*& p, size_t count) {
            using T = std::remove_pointer_t<std::remove_reference_t<decltype(p)>>;
            p = exec_.template alloc<T>(count);
            ok = ok && p != nullptr;
        };
        // Four Vec4 arrays in rotating roles (x, v, x*, spare), one id array (its gather target
        // is the sort's free value buffer), the sort's keys and values, ρ, the neighbour masks.
        for (Vec4*& b : vec4_) alloc(b, n);
        pos_ = vec4_[0];
        vel_ = vec4_[1];
        pred_ = vec4_[2];
        spare_ = vec4_[3];
        alloc(ids_, n);
        alloc(materials_, n);  // 1 B per particle; the sort's gather borrows a free key buffer
        for (int b = 0; b < 2; ++b) {
            alloc(keys_[b], n);
            alloc(order_[b], n);
        }
        alloc(masks_, n * kMaskRows);
        alloc(density_, n);
        alloc(cell_begin_, size_t(config.grid.num_cells) + 2);  // + 1: the grid sort's counters (sort_cells)
        alloc(counters_, 1);
        const size_t colliders = config.max_colliders;
        alloc(collider_shapes_, colliders);
        alloc(collider_keys_, colliders);
        alloc(collider_poses_, colliders * 2);
        alloc(rest_poses_, colliders);
        alloc(collider_impulses_, colliders);
        alloc(collider_forces_, colliders);
        grid_capacity_ = collider_grid_capacity(config.max_colliders);
        if (grid_capacity_.buckets) alloc(collider_grid_, size_t(grid_capacity_.buckets) + 1 + grid_capacity_.entries);
        host_forces_.assign(colliders, ColliderForce{});
        alloc(mesh_table_, kMaxMeshes);
        // Render data only where the world asks for it: nothing at all otherwise.
        const RenderConstants& r = config.render;
        if (r.flags & kRenderSmoothed) alloc(smoothed_, n);
        if (r.flags & kRenderAnisotropy) alloc(anisotropy_, n * 3);
        render_bytes_ = ((r.flags & kRenderSmoothed) ? n : 0) * sizeof(Vec4) +
                        ((r.flags & kRenderAnisotropy) ? n * 3 : 0) * sizeof(Vec4);
        feedback_ = exec_.template alloc_host_visible<StepFeedback>(1);
        ok = ok && feedback_ != nullptr;
        // Diffuse particles only where the world asks for them: nothing at all otherwise.
        const uint64_t before_diffuse = exec_.allocated_bytes();
        const uint32_t dcap = config.diffuse.capacity;
        if (dcap) {
            for (Vec4*& b : diffuse_) alloc(b, dcap);
            alloc(diffuse_flags_, size_t(dcap) + n);
            alloc(diffuse_offsets_, size_t(dcap) + n);
            alloc(diffuse_counters_, 1);
            ok = ok && exec_.reserve_scan(dcap + config.capacity).ok();
        }
        diffuse_bytes_ = exec_.allocated_bytes() - before_diffuse;
        if (!ok) {
            return Status::error(PBF_ERROR_OUT_OF_MEMORY, "cannot allocate " + std::to_string(config.capacity) +
                                                              " particles on " + exec_.device_name() + ": " +
                                                              exec_.last_error_text());
        }
        // Unused slots hold finite data so passes that touch them (they never affect live
        // particles) compute nothing undefined; all counters start at zero.
        for (Vec4* b : vec4_) exec_.zero(b, n * sizeof(Vec4));
        exec_.zero(ids_, n * sizeof(uint32_t));
        exec_.zero(materials_, n);
        for (int b = 0; b < 2; ++b) {
            exec_.zero(keys_[b], n * sizeof(uint32_t));
            exec_.zero(order_[b], n * sizeof(uint32_t));
        }
        exec_.zero(masks_, n * kMaskRows * sizeof(uint32_t));
        exec_.zero(density_, n * sizeof(float));
        exec_.zero(cell_begin_, (size_t(config.grid.num_cells) + 2) * sizeof(uint32_t));
        exec_.zero(counters_, sizeof(DeviceCounters));
        exec_.zero(collider_impulses_, colliders * sizeof(ColliderForce));
        exec_.zero(collider_forces_, colliders * sizeof(ColliderForce));
        exec_.zero(mesh_table_, kMaxMeshes * sizeof(MeshView));
        if (smoothed_) exec_.zero(smoothed_, n * sizeof(Vec4));
        if (anisotropy_) exec_.zero(anisotropy_, n * 3 * sizeof(Vec4));
        if (dcap) {
            for (Vec4* b : diffuse_) exec_.zero(b, size_t(dcap) * sizeof(Vec4));
            exec_.zero(diffuse_flags_, (size_t(dcap) + n) * sizeof(uint32_t));
            exec_.zero(diffuse_counters_, sizeof(DiffuseCounters));
        }
        *feedback_ = StepFeedback{};
        return exec_.check("world initialisation");
    }

    pbf_backend kind() const override { return Exec::kKind; }
    std::string device_name() const override { return exec_.device_name(); }
    uint64_t device_bytes() const override { return exec_.allocated_bytes(); }

    Status step(const WorldConstants& s, const StepInput& in) override {
        exec_.activate();
        const uint32_t count = static_cast<uint32_t>(in.collider_shapes.size());
        const uint32_t substeps = static_cast<uint32_t>(in.substeps.size());
        if (count > config_.max_colliders || substeps > kMaxSubsteps || in.collider_keys.size() != count)
            return Status::error(PBF_ERROR_INTERNAL, "step input exceeds the solver's collider buffers");
        exec_.timer_begin();
        exec_.profile_reset();
        // The step's colliders go up once, before its first kernel (shapes, where each starts
        // and ends, the broad phase's lists); the substeps' poses are interpolated on the
        // backend, each substep's end into one of two rows that alternate (row k % 2 holds the
        // poses at t = k / substeps).
        if (count > 0) {
            exec_.upload(collider_shapes_, in.collider_shapes.data(), count * sizeof(Collider));
            exec_.upload(collider_keys_, in.collider_keys.data(), count * sizeof(ColliderKey));
        }
        const ColliderGrid grid = upload_collider_grid(in.collider_shapes);
        // From here to the end of the step there are launches only: recorded, they go to the
        // device as one graph.
        exec_.record_begin();
        if (count > 0) exec_.for_each(count, ColliderPoseOp{collider_keys_, collider_poses_, count, substeps, 0});
        const bool dynamic = in.dynamic_count > 0;
        if (dynamic) exec_.zero(collider_impulses_, size_t(config_.max_colliders) * sizeof(ColliderForce));
        exec_.for_each(1, BeginStepOp{counters_});
        for (uint32_t k = 0; k < substeps; ++k) {
            SubstepInput sub = in.substeps[k];
            ColliderView& view = sub.ctx.colliders;
            ColliderPose* end = collider_poses_ + ((k + 1) % 2) * count;
            if (count > 0) exec_.for_each(count, ColliderPoseOp{collider_keys_, end, count, substeps, k + 1});
            view = colliders_view(collider_poses_ + (k % 2) * count, end, count, grid);
            if (dynamic) {
                view.dynamic_count = in.dynamic_count;
                view.impulses = collider_impulses_;
                view.impulse_scale = s.mass * sub.ctx.inv_dt;
            }
            sub.ctx.clamped = &counters_->speed_clamps;
            sub.ctx.materials = materials_;
            substep(s, sub);
        }
        // Between steps the colliders stand at the step's end poses.
        const ColliderPose* reached = collider_poses_ + (substeps % 2) * count;
        rest_colliders_ = colliders_view(reached, reached, count, grid);
        if (dynamic)
            exec_.for_each(count,
                           ColliderForceOp{collider_shapes_, collider_impulses_, collider_forces_, 1.0f / in.frame_dt});
        host_forces_valid_ = false;
        const HeightFrame frame = height_frame(s);
        exec_.reduce_feedback(frame, pos_, vel_, &counters_->count, bound_, &counters_->feedback);
        exec_.for_each(1, PublishFeedbackOp{counters_, frame, feedback_});
        update_diffuse(s, in.simulated_dt);
        update_render_data(s);  // last, so its stage time is the pass alone
        exec_.record_end();
        exec_.feedback_published();
        exec_.profile_mark(kStageCount);
        exec_.timer_end();
        return exec_.check("pbf_world_step");
    }

    StepFeedback feedback() override {
        exec_.activate();
        if (exec_.feedback_ready()) last_feedback_ = *feedback_;
        return last_feedback_;
    }

    // Lists the colliders by coarse cells on the host and uploads the lists (stream-ordered, like
    // the shapes they index); the returned grid points at them.
    ColliderGrid upload_collider_grid(const std::vector<Collider>& shapes) {
        build_collider_grid(shapes, config_.kernel_radius, grid_capacity_, &grid_lists_);
        ColliderGrid g = grid_lists_.grid;  // no lists: null pointers, every query walks all
        if (grid_lists_.bucket_begin.empty()) return g;
        uint32_t* entries = collider_grid_ + grid_capacity_.buckets + 1;
        exec_.upload(collider_grid_, grid_lists_.bucket_begin.data(),
                     grid_lists_.bucket_begin.size() * sizeof(uint32_t));
        exec_.upload(entries, grid_lists_.entries.data(), grid_lists_.entries.size() * sizeof(uint32_t));
        g.bucket_begin = collider_grid_;
        g.entries = entries;
        return g;
    }

    ColliderView colliders_view(const ColliderPose* prev, const ColliderPose* cur, uint32_t count,
                                const ColliderGrid& grid) const {
        ColliderView v;
        v.shapes = collider_shapes_;
        v.prev = prev;
        v.cur = cur;
        v.count = count;
        v.meshes = mesh_table_;
        v.grid = grid;
        return v;
    }

    Status set_colliders_at_rest(const ColliderSetAtRest& c) override {
        exec_.activate();
        const uint32_t count = static_cast<uint32_t>(c.shapes.size());
        if (count > config_.max_colliders || c.keys.size() != count)
            return Status::error(PBF_ERROR_INTERNAL, "collider set exceeds the solver's collider buffers");
        // The shapes table is also the steps': rewritten here, ordered after earlier steps.
        if (count > 0) {
            exec_.upload(collider_shapes_, c.shapes.data(), count * sizeof(Collider));
            exec_.upload(collider_keys_, c.keys.data(), count * sizeof(ColliderKey));
            exec_.for_each(count, ColliderPoseOp{collider_keys_, rest_poses_, count, 0});
        }
        const ColliderGrid grid = upload_collider_grid(c.shapes);
        rest_colliders_ = colliders_view(rest_poses_, rest_poses_, count, grid);
        density_valid_ = false;
        return exec_.check("updating colliders");
    }

    Status collider_forces(const ColliderForce** rows) override {
        exec_.activate();
        if (!host_forces_valid_) {
            exec_.download(host_forces_.data(), collider_forces_, host_forces_.size() * sizeof(ColliderForce));
            Status st = exec_.check("reading collider forces");
            if (!st.ok()) return st;
            host_forces_valid_ = true;
        }
        *rows = host_forces_.data();
        return Status{};
    }
    const ColliderForce* collider_force_table() const override { return collider_forces_; }
    Status clear_collider_force(uint32_t row) override {
        exec_.activate();
        if (row >= config_.max_colliders) return Status::error(PBF_ERROR_INTERNAL, "collider row out of range");
        exec_.zero(collider_forces_ + row, sizeof(ColliderForce));
        host_forces_valid_ = false;
        return exec_.check("clearing a collider's force");
    }

    // ---- meshes: a field per mesh, its view in a row of the mesh table -------------
    Status create_mesh(const MeshBuild& b, uint32_t row) override {
        exec_.activate();
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
    void destroy_mesh(uint32_t row) override {
        exec_.activate();
        if (row >= kMaxMeshes) return;
        exec_.release(mesh_values_[row]);  // a CUDA free waits for the steps that may still read it
        mesh_values_[row] = nullptr;
    }

    Status emit_block(const BlockEmission& b, const WorldConstants& s, uint32_t* emitted) override {
        exec_.activate();
        uint32_t count = 0;
        Status st = read_count(&count);
        if (!st.ok()) return st;
        const uint64_t requested = uint64_t(b.nx) * b.ny * b.nz;
        const uint32_t fit = uint32_t(std::min<uint64_t>(requested, config_.capacity - count));
        if (fit > 0) {
            EmitBlockOp op{&counters_->count,
                           &counters_->next_id,
                           config_.capacity,
                           b.origin,
                           b.spacing,
                           b.nx,
                           b.ny,
                           b.velocity,
                           pos_,
                           vel_,
                           ids_,
                           materials_,
                           b.material};
            exec_.for_each(fit, op);
            commit_emission(fit);
            materials_moved_ |= b.material != 0;
            bound_ = count + fit;
            // Keep the grid valid between API calls (stats and LDC rely on it).
            build_grid(s, false);
            density_valid_ = false;
            update_render_data(s);  // the particles moved in memory: keep the render data in their order
        }
        *emitted = fit;
        return exec_.check("pbf_world_emit_block");
    }

    Status particle_count(uint32_t* count) override {
        exec_.activate();
        return read_count(count);
    }

    Status copy_buffer(pbf_buffer source, void* out, uint32_t max_count, uint32_t* written) override {
        exec_.activate();
        const void* src = live_buffer(live_buffers(), source);
        if (!src) return Status::error(PBF_ERROR_INVALID_STATE, "copy-out: the world does not compute this buffer");
        uint32_t count = 0;
        Status st = is_diffuse_buffer(source) ? diffuse_count(&count) : read_count(&count);
        if (!st.ok()) return st;
        const uint32_t n = std::min(count, max_count);
        exec_.download(out, src, size_t(n) * buffer_element_bytes(source));
        *written = n;
        return exec_.check("copy-out");
    }

    void set_render_constants(const RenderConstants& render) override {
        replace_keeping(config_.render, render, &RenderConstants::flags);
    }
    uint64_t render_updates() const override { return render_updates_; }
    uint64_t render_bytes() const override { return render_bytes_; }

    void set_diffuse_constants(const DiffuseConstants& diffuse) override {
        replace_keeping(config_.diffuse, diffuse, &DiffuseConstants::capacity);
    }
    uint64_t diffuse_updates() const override { return diffuse_updates_; }
    uint64_t diffuse_bytes() const override { return diffuse_bytes_; }
    Status diffuse_count(uint32_t* count) override {
        exec_.activate();
        *count = 0;
        if (!diffuse_counters_) return Status{};
        exec_.download(count, &diffuse_counters_->count, sizeof(uint32_t));
        return exec_.check("reading the diffuse count");
    }
    Status add_diffuse(const Vec4* rows, uint32_t n, uint32_t* added) override {
        *added = 0;
        uint32_t count = 0;
        Status st = diffuse_count(&count);
        if (!st.ok() || !diffuse_counters_) return st;
        const uint32_t fit = std::min(n, config_.diffuse.capacity - count);
        if (fit == 0) return Status{};
        exec_.upload(diffuse_[0] + count, rows, size_t(fit) * sizeof(Vec4));
        exec_.upload(diffuse_[1] + count, rows + n, size_t(fit) * sizeof(Vec4));
        const uint32_t total = count + fit;
        exec_.upload(&diffuse_counters_->count, &total, sizeof total);
        *added = fit;
        return exec_.check("pbf_world_add_diffuse");
    }

    Status read_stats(const WorldConstants& s, StatsReadback* out) override {
        exec_.activate();
        if (!density_valid_) {  // the grid is valid between API calls: one density pass suffices
            exec_.for_each(bound_, DensityOp{s, rest_colliders_, cell_begin_, pos_, density_, valid_masks()});
            density_valid_ = true;
            emitted_since_density_ = false;
        }
        DeviceCounters c{};
        exec_.download(&c, counters_, sizeof c);
        Status st = exec_.check("pbf_world_get_stats");
        if (!st.ok()) return st;
        out->count = c.count;
        out->iterations_used = c.control.iterations_used;
        out->speed_clamps = c.speed_clamps;
        out->emitted_total = c.emitted_total;
        out->drained_total = c.drained_total;
        if (diffuse_counters_) {
            DiffuseCounters dc{};
            exec_.download(&dc, diffuse_counters_, sizeof dc);
            out->diffuse_count = dc.count;
            out->diffuse_dropped_step = dc.dropped_step;
            out->diffuse_generated_total = dc.generated_total;
            out->diffuse_dropped_total = dc.dropped_total;
        }
        exec_.reduce_stats(s, density_, vel_, c.count, out);
        return exec_.check("pbf_world_get_stats");
    }

    Status last_step_ms(float* ms) override {
        exec_.activate();
        *ms = exec_.timer_ms();
        return exec_.check("step timer");
    }

    void* cuda_stream() const override { return exec_.native_stream(); }
    LiveBuffers live_buffers() override {
        LiveBuffers b;
        b.positions = pos_;
        b.velocities = vel_;
        b.ids = ids_;
        b.materials = materials_;
        b.smoothed_positions = smoothed_;
        b.anisotropy = anisotropy_;
        b.count = &counters_->count;
        b.capacity = config_.capacity;
        b.cuda_device = Exec::kKind == PBF_BACKEND_CUDA ? config_.cuda_device : -1;
        b.diffuse_positions = diffuse_[0];
        b.diffuse_velocities = diffuse_[1];
        b.diffuse_count = diffuse_counters_ ? &diffuse_counters_->count : nullptr;
        b.diffuse_capacity = config_.diffuse.capacity;
        return b;
    }
    Status set_cuda_stream(void* stream) override {
        exec_.activate();
        return exec_.use_stream(stream);
    }
    void set_profiling(bool on) override { exec_.profile_enable(on); }
    Status stage_times(StageTimes* out) override {
        exec_.activate();
        exec_.profile_read(out->ms, kStageCount);
        return exec_.check("stage timing");
    }

private:
    // New tunables with the creation's value of `fixed` kept (the buffers were sized by it).
    template <class T, class F>
    static void replace_keeping(T& current, const T& next, F T::*fixed) {
        const F kept = current.*fixed;
        current = next;
        current.*fixed = kept;
    }

    void substep(const WorldConstants& s, const SubstepInput& in) {
        const StepContext& ctx = in.ctx;
        exec_.profile_mark(kStageEmitDrain);
        // Emission and drains first, so the grid builds below drop drained particles.
        for (const NozzleEmission& nz : in.nozzles) {
            if (nz.count == 0) continue;
            EmitNozzleOp op{&counters_->count,
                            &counters_->next_id,
                            config_.capacity,
                            nz.count,
                            nz.sequence,
                            nz.disc_points,
                            nz.center,
                            nz.direction,
                            nz.tangent,
                            nz.bitangent,
                            nz.radius,
                            nz.speed,
                            ctx.dt,
                            pos_,
                            vel_,
                            ids_,
                            materials_,
                            nz.material};
            exec_.for_each(nz.count, op);
            commit_emission(nz.count);
            materials_moved_ |= nz.material != 0;
            bound_ = std::min<uint64_t>(config_.capacity, uint64_t(bound_) + nz.count);
        }
        for (const DrainBox& d : in.drains) {
            exec_.for_each(bound_, DrainOp{&counters_->count, pos_, d.box_min, d.box_max, ids_, &counters_->drained});
        }
        if (!in.drains.empty()) exec_.for_each(1, CommitDrainOp{&counters_->drained, &counters_->drained_total});
        if (!in.nozzles.empty() || !in.drains.empty()) grid_valid_ = density_valid_ = false;

        // 0. Overlaps no motion made (a collider created or teleported into the fluid, a block
        // emitted into one): settled in x, which gives no velocity.
        if (in.settle_overlaps) settle(s, ctx, in.iterations);
        // 0b. Contact penetration a particle starts the substep with (a wall or a second
        // collider pushed it back in, or a mesh field's approximate projection left it short) is
        // no motion of the substep: projected out in the prediction it became velocity, depth /
        // Δt (100 m/s from a step of 1e-7 s). So where old errors move positions (γ > 2,
        // passes.h old_error_weight) it is removed in x by the same weight, as pre-stabilization
        // removes contacts (Macklin et al. 2014), with no reaction recorded.
        const float contact_weight = old_error_weight(ctx.error_damping);
        if (contact_weight > 0.0f && ctx.colliders.count > 0 && !in.settle_overlaps) {
            exec_.for_each(bound_, SettleOverlapOp{s, ctx.colliders, pos_, contact_weight});
            grid_valid_ = density_valid_ = masks_valid_ = false;
        }
        // 1. ρ at the current positions (grid of x): LDC needs it, and so does the λ pass's error
        // damping for particles emitted since the last density pass, and at γ > 1 for all, where
        // the prediction may move C₀ toward it (passes.h, old_error_weight: from γ = 2; a density
        // pass run here also writes ρ/ρ0 to positions.w itself). Emitted particles' positions.w,
        // the error C₀ a particle starts the substep with, is still the emission's 1: the
        // compression they were emitted into would count as new and go in one substep, at a tiny
        // Δt a velocity of error · spacing / Δt (16 m/s for a block at 1e-5 s with LDC off).
        if (s.ldc_enabled || emitted_since_density_ || ctx.error_damping > 1.0f) {
            exec_.profile_mark(kStageGridX);
            if (!grid_valid_) build_grid(s, false);
            exec_.profile_mark(kStageDensityX);
            if (!density_valid_)
                exec_.for_each(bound_, DensityOp{s, ctx.colliders, cell_begin_, pos_, density_, valid_masks()});
            emitted_since_density_ = false;
        }
        // 1b. surface tension, cohesion and adhesion (material_ops.h) at the current positions.
        if (s.materials.flags & kMaterialSurface) {
            exec_.profile_mark(kStageMaterialForces);
            if (!grid_valid_) build_grid(s, false);
            // pred_ and spare_ are free until the prediction. The last substep's vorticity pass
            // left the normals at these positions in pred_ unless something moved or reordered
            // the particles since; otherwise they are summed here, into spare_.
            const Vec4* normals = pred_;
            if (!surface_normals_valid_) {
                exec_.for_each(bound_, SurfaceNormalOp{s, ctx, cell_begin_, valid_masks(), pos_, spare_});
                normals = spare_;
            }
            exec_.for_each(bound_, SurfaceForceOp{s, ctx, cell_begin_, valid_masks(), pos_, normals, vel_});
        }
        surface_normals_valid_ = false;  // pred_ is overwritten next
        exec_.profile_mark(kStageForcesPredict);
        // 2. forces (gravity + LDC), predict x*.
        exec_.for_each(bound_, PredictOp{s, ctx, cell_begin_, density_, pos_, vel_, pred_, valid_masks()});
        // 3. neighbours: grid of x*.
        exec_.profile_mark(kStageGridPredicted);
        build_grid(s, true);
        // 4. constraint iterations (Jacobi: Δp reads pred, writes the other pred buffer).
        // Adaptive: after each λ pass the device sums the error and decides; launches after
        // convergence return at once (iterations is the cap).
        const bool adaptive = s.adaptive_target > 0.0f;
        IterationControl* control = adaptive ? &counters_->control : nullptr;
        if (adaptive) exec_.for_each(1, ResetControlOp{control});
        // iterations >= 1 (the API refuses 0): the first λ pass records the neighbour masks and
        // the last Δp pass updates v and x.
        const NeighborMasks masks{masks_, sorted_keys_, config_.capacity};
        // Without colliders this substep and with every particle of the default material, the
        // hot passes run their kernels compiled without either (Features, material_ops.h).
        const bool plain = ctx.colliders.count == 0 && !materials_moved_;
        // The sort's value buffers are free until the next grid build: λ leaves the colliders'
        // boundary gradient there for Δ.
        const PackedVectors colliders_gradient{order_[0], reinterpret_cast<float*>(order_[1])};
        // v is dead until the velocity update (the grid build of x* wrote over it): where old
        // errors move positions (γ > 2: passes.h, old_error_weight) the iterations keep the old
        // error's share of λ and its displacement there, and the last Δ pass writes the
        // velocities into spare_, the Jacobi buffer that pass does not use, as neighbours still
        // read old_push.w in it. Elsewhere (every game frame's substeps) the split is skipped, its
        // shares all 0, and Δp runs its kernel compiled without it (DeltaNoSplit).
        Vec4* const old_push = old_error_weight(ctx.error_damping) > 0.0f ? vel_ : nullptr;
        for (uint32_t it = 0; it < in.iterations; ++it) {
            exec_.profile_mark(kStageLambda);
            for_each_pass<LambdaPass>(plain, bound_, s, ctx, cell_begin_, masks, it == 0 ? 1u : 0u, pos_, pred_,
                                      density_, control, denominator_, colliders_gradient, old_push);
            if (adaptive) {
                exec_.sum_compressive_error(s, density_, &counters_->count, bound_, &control->error_sum);
                exec_.for_each(1, ConvergenceOp{control, &counters_->count, s.adaptive_target, it == 0 ? 1u : 0u});
            }
            exec_.profile_mark(kStageDeltaCollide);
            // The last iteration also updates v and x (no separate velocity pass).
            const bool last = it + 1 == in.iterations;
            if (old_push)
                exec_.for_each(bound_,
                               DeltaOp{s, ctx, cell_begin_, masks, pos_, pred_, spare_, control, last ? pos_ : nullptr,
                                       last ? spare_ : nullptr, density_, colliders_gradient, old_push});
            else
                for_each_pass<DeltaNoSplit>(plain, bound_, s, ctx, cell_begin_, masks, pos_, pred_, spare_, control,
                                            last ? pos_ : nullptr, last ? spare_ : nullptr, density_,
                                            colliders_gradient);
            if (!last) std::swap(pred_, spare_);  // Jacobi: the corrected positions are the next input
        }
        std::swap(vel_, spare_);  // the last Δ pass wrote v into spare_; old_push is dead
        masks_valid_ = true;      // recorded by the first λ pass
        // 5. vorticity confinement and XSPH.
        if (s.vorticity_epsilon > 0.0f || any_viscosity(ctx)) {
            // x* now lives in x: pred_ and spare_ are free until the next substep.
            Vec4* omega = spare_;
            exec_.profile_mark(kStageVorticity);
            for_each_pass<VorticityXsphPass>(plain, bound_, s, ctx, cell_begin_, masks, pos_, vel_, omega, pred_);
            exec_.profile_mark(kStageVorticityXsph);
            // The old velocities (vel_) are dead now: with surface tension the pass sums the
            // surface normals there, which the swap leaves in pred_ for the next substep.
            if (s.materials.flags & kMaterialSurface) {
                exec_.for_each(
                    bound_, VorticityForcePass<true>{s, ctx, cell_begin_, masks, pos_, omega, pred_, density_, vel_});
                surface_normals_valid_ = true;
            } else {
                for_each_pass<VorticityForceOnly>(plain, bound_, s, ctx, cell_begin_, masks, pos_, omega, pred_,
                                                  density_);
            }
            std::swap(vel_, pred_);
            density_valid_ = true;  // that pass also summed ρ at the final positions
        } else {
            density_valid_ = false;
        }
        grid_valid_ = true;  // built on x*, which the positions now are
        // With LDC the next substep needs ρ(x); computing it now also serves the stats.
        if (s.ldc_enabled && !density_valid_) {
            exec_.profile_mark(kStageDensityEnd);
            exec_.for_each(bound_, DensityOp{s, ctx.colliders, cell_begin_, pos_, density_, masks});
            density_valid_ = true;
        }
    }

    // Launches Pass<true> (plain) or Pass<false> with the same fields.
    template <template <bool> class Pass, class... Args>
    void for_each_pass(bool plain, uint32_t n, const Args&... args) {
        if (plain)
            exec_.for_each(n, Pass<true>{args...});
        else
            exec_.for_each(n, Pass<false>{args...});
    }

    // Smoothed positions and anisotropy from the current grid (one pass; none when the world
    // computes no render data). After a step the last substep's masks serve as neighbour lists.
    void update_render_data(const WorldConstants& s) {
        if (!config_.render.flags) return;
        exec_.profile_mark(kStageRender);
        exec_.for_each(bound_, RenderDataOp{s.grid, s.h2, config_.render, cell_begin_, valid_masks(), pos_, smoothed_,
                                            anisotropy_});
        ++render_updates_;
    }

    // Diffuse particles (diffuse_ops.h), at the end of a step from its last grid and neighbour
    // masks: normals (into spare_, free at the end of a step), how many each fluid particle
    // generates, the diffuse particles moved; one scan of [survivors | generated] packs both into
    // the back buffers, which become the front. No pass without a diffuse capacity.
    void update_diffuse(const WorldConstants& s, float dt) {
        const DiffuseConstants& d = config_.diffuse;
        if (!d.capacity) return;
        exec_.profile_mark(kStageDiffuse);
        const uint32_t n = bound_, total = d.capacity + bound_;
        const float inv_h = 1.0f / s.h;
        const NeighborMasks masks = valid_masks();
        if (n > 0) {
            Vec4* normals = spare_;
            exec_.for_each(n,
                           DiffuseNormalOp{s.grid, s.h2, inv_h, cell_begin_, masks, pos_, &counters_->count, normals});
            exec_.for_each(n, DiffuseSourceOp{s.grid, s.h2, inv_h, dt, d, cell_begin_, masks, pos_, vel_, normals, ids_,
                                              diffuse_steps_, &counters_->count, diffuse_flags_ + d.capacity});
        }
        exec_.profile_mark(kStageDiffuseAdvect);
        const FluidSampler fluid{s.grid, s.h2, inv_h, cell_begin_, pos_, vel_};
        exec_.for_each(d.capacity, DiffuseAdvectOp{s, rest_colliders_, fluid, dt, d, &diffuse_counters_->count,
                                                   diffuse_[0], diffuse_[1], diffuse_flags_});
        exec_.exclusive_scan(diffuse_flags_, diffuse_offsets_, total);
        exec_.for_each(total, DiffuseScatterOp{s, rest_colliders_, fluid, dt, d, ids_, diffuse_steps_, diffuse_flags_,
                                               diffuse_offsets_, diffuse_[0], diffuse_[1], diffuse_[2], diffuse_[3]});
        exec_.for_each(1, DiffuseCommitOp{diffuse_counters_, diffuse_flags_, diffuse_offsets_, total, d.capacity});
        std::swap(diffuse_[0], diffuse_[2]);
        std::swap(diffuse_[1], diffuse_[3]);
        ++diffuse_steps_;
        ++diffuse_updates_;
    }

    // Pre-stabilization (passes.h): the particles move out of the colliders they overlap, then
    // constraint iterations run on x itself, each particle's target being the error C₀ it ended
    // the last substep with (its positions.w), so that only what the move and a new boundary
    // added is removed, and none of it becomes velocity. The move gives no momentum to the
    // colliders (no impulses recorded) and s_corr stays out (it would move resting fluid). The
    // density pass of the substep then takes what is left as the error the particles start
    // with, which relaxes over τ (docs/physics.md, Overlaps).
    void settle(const WorldConstants& s, const StepContext& ctx, uint32_t iterations) {
        if (ctx.colliders.count > 0) exec_.for_each(bound_, SettleOverlapOp{s, ctx.colliders, pos_});
        build_grid(s, false);
        StepContext settling = ctx;
        settling.colliders.impulses = nullptr;
        settling.error_damping = kSettleDamping;
        settling.scorr_k = 0.0f;
        exec_.for_each(bound_, CopyPositionsOp{pos_, pred_});
        const NeighborMasks masks{masks_, sorted_keys_, config_.capacity};
        const PackedVectors colliders_gradient{order_[0], reinterpret_cast<float*>(order_[1])};
        const uint32_t settle_iterations = std::max(iterations, kSettleIterations);
        for (uint32_t it = 0; it < settle_iterations; ++it) {
            exec_.for_each(bound_, LambdaOp{s, settling, cell_begin_, masks, it == 0 ? 1u : 0u, pos_, pred_, density_,
                                            nullptr, denominator_, colliders_gradient});
            exec_.for_each(bound_, DeltaOp{s, settling, cell_begin_, masks, pos_, pred_, spare_, nullptr, nullptr,
                                           nullptr, density_, colliders_gradient});
            std::swap(pred_, spare_);
        }
        exec_.for_each(bound_, AdoptSettledOp{pred_, pos_});
        grid_valid_ = density_valid_ = masks_valid_ = false;
        emitted_since_density_ = true;
    }

    // Sorts particles by the cell of x (by_predicted false) or of x*, moves their data into
    // that order and rebuilds cell_begin; drops dead particles from the count.
    void build_grid(const WorldConstants& s, bool by_predicted) {
        const uint32_t n = bound_;
        const Vec4* binned = by_predicted ? pred_ : pos_;
        exec_.for_each(n, CellKeyOp{binned, ids_, &counters_->count, s.grid, keys_[0], order_[0]});
        int key_sel = 0, order_sel = 0;
        // cell_begin is the sort's counters until CellBeginOp writes it from the sorted keys.
        exec_.sort_cells(keys_, order_, n, s.grid.num_cells, cell_begin_, &key_sel, &order_sel);
        exec_.for_each(n + 1, CellBeginOp{keys_[key_sel], n, s.grid.num_cells, cell_begin_, &counters_->count});
        sorted_keys_ = keys_[key_sel];
        // The sort's other key buffer is free until the next build: λ's denominators live there.
        denominator_ = reinterpret_cast<float*>(keys_[1 - key_sel]);
        masks_valid_ = false;
        surface_normals_valid_ = false;  // they were in the old order (and pred_ is rewritten)
        // Gather x into spare_ and the second stream (v; or x* when binning x*, as v is dead
        // then until the velocity update) into the array free besides: x* when binning x, v when
        // binning x*. The ids go to the sort's free value buffer.
        Vec4*& second = by_predicted ? pred_ : vel_;
        Vec4*& free_slot = by_predicted ? vel_ : pred_;
        uint32_t*& id_out = order_[1 - order_sel];
        // The materials go through the free key buffer (λ's denominators later) and back; while
        // every particle is of the default material (all bytes 0) there is nothing to move.
        uint8_t* material_scratch = materials_moved_ ? reinterpret_cast<uint8_t*>(keys_[1 - key_sel]) : nullptr;
        exec_.for_each(n, GatherOp{order_[order_sel], pos_, second, ids_, spare_, free_slot, id_out, materials_,
                                   material_scratch});
        if (materials_moved_) exec_.for_each(n, CopyMaterialsOp{material_scratch, materials_});
        std::swap(pos_, spare_);
        std::swap(second, free_slot);
        std::swap(ids_, id_out);
        grid_valid_ = true;
    }

    // The last substep's neighbour masks while the particle order they index is unchanged (no
    // grid build since); null rows otherwise, and the passes walk the grid.
    NeighborMasks valid_masks() const {
        return masks_valid_ && grid_valid_ ? NeighborMasks{masks_, sorted_keys_, config_.capacity} : NeighborMasks{};
    }

    void commit_emission(uint32_t requested) {
        exec_.for_each(1, CommitEmissionOp{&counters_->count, &counters_->next_id, &counters_->emitted_total,
                                           config_.capacity, requested});
        grid_valid_ = density_valid_ = false;
        emitted_since_density_ = true;
    }

    Status read_count(uint32_t* count) {
        exec_.download(count, &counters_->count, sizeof(uint32_t));
        Status st = exec_.check("reading the particle count");
        if (st.ok()) bound_ = *count;  // exact again: launches shrink back to the live count
        return st;
    }

    void release() {
        // The role pointers (pos_, ids_, ...) alias the arrays: release each array once.
        for (Vec4* b : vec4_) exec_.release(b);
        exec_.release(ids_);
        exec_.release(materials_);
        for (int b = 0; b < 2; ++b) {
            exec_.release(keys_[b]);
            exec_.release(order_[b]);
        }
        exec_.release(masks_);
        exec_.release(density_);
        exec_.release(cell_begin_);
        exec_.release(counters_);
        exec_.release(collider_shapes_);
        exec_.release(collider_keys_);
        exec_.release(collider_poses_);
        exec_.release(collider_grid_);
        exec_.release(rest_poses_);
        exec_.release(collider_impulses_);
        exec_.release(collider_forces_);
        exec_.release(mesh_table_);
        for (float*& v : mesh_values_) exec_.release(v);
        exec_.release(smoothed_);
        exec_.release(anisotropy_);
        for (Vec4* b : diffuse_) exec_.release(b);
        exec_.release(diffuse_flags_);
        exec_.release(diffuse_offsets_);
        exec_.release(diffuse_counters_);
        exec_.release_host_visible(feedback_);
    }

    Exec exec_;
    BackendConfig config_{};
    Vec4* vec4_[4] = {};  // the allocations; the roles below point into them and rotate
    Vec4* pos_ = nullptr;
    Vec4* vel_ = nullptr;
    Vec4* pred_ = nullptr;
    Vec4* spare_ = nullptr;
    uint32_t* ids_ = nullptr;       // rotates with the sort's value buffers
    uint8_t* materials_ = nullptr;  // each particle's material slot (fixed: the gather copies back)
    uint32_t* keys_[2] = {};
    uint32_t* order_[2] = {};
    const uint32_t* sorted_keys_ = nullptr;  // the cell of each particle at the last grid build
    uint32_t* masks_ = nullptr;              // kMaskRows x capacity neighbour masks
    float* denominator_ = nullptr;           // λ's Σ|∇C|² + ε per particle (aliases a sort buffer)
    float* density_ = nullptr;
    uint32_t* cell_begin_ = nullptr;
    DeviceCounters* counters_ = nullptr;
    Collider* collider_shapes_ = nullptr;     // max_colliders
    ColliderKey* collider_keys_ = nullptr;    // max_colliders: where each starts and ends the step
    ColliderPose* collider_poses_ = nullptr;  // 2 rows of the step's colliders: a substep's start and end
    ColliderPose* rest_poses_ = nullptr;      // max_colliders, set between steps
    ColliderGridCapacity grid_capacity_;
    uint32_t* collider_grid_ = nullptr;           // the broad phase's bucket offsets, then its entries
    ColliderGridLists grid_lists_;                // the host's build, kept to reuse its storage
    ColliderForce* collider_impulses_ = nullptr;  // max_colliders rows: the running step's impulses
    ColliderForce* collider_forces_ = nullptr;    // max_colliders rows: the last step's mean forces
    std::vector<ColliderForce> host_forces_;      // the host's copy of collider_forces_
    MeshView* mesh_table_ = nullptr;              // kMaxMeshes rows
    float* mesh_values_[kMaxMeshes] = {};         // each live mesh's field (its row's values)
    bool host_forces_valid_ = false;
    ColliderView rest_colliders_{};  // the colliders outside a step
    Vec4* smoothed_ = nullptr;       // render data: null unless the world asks for it
    Vec4* anisotropy_ = nullptr;     // 3 per particle
    uint64_t render_bytes_ = 0;
    uint64_t render_updates_ = 0;
    Vec4* diffuse_[4] = {};                // diffuse particles: positions, velocities (front), then the back pair
    uint32_t* diffuse_flags_ = nullptr;    // capacity + max_particles: keep | generated
    uint32_t* diffuse_offsets_ = nullptr;  // their exclusive scan
    DiffuseCounters* diffuse_counters_ = nullptr;
    uint64_t diffuse_bytes_ = 0;
    uint64_t diffuse_updates_ = 0;
    uint32_t diffuse_steps_ = 0;        // the generator's random stream: one per step
    StepFeedback* feedback_ = nullptr;  // host-visible; written by the step's last op
    StepFeedback last_feedback_{};
    uint32_t bound_ = 0;  // upper bound of the live count known on the host (launch size)
    bool grid_valid_ = true;
    bool density_valid_ = false;
    bool emitted_since_density_ = false;  // positions.w of some particles is the emission's 1, not ρ/ρ0
    bool masks_valid_ = false;
    bool surface_normals_valid_ = false;  // pred_ holds the normals at pos_ (VorticityForcePass<true>)
                                          // until the next grid build (emission and drains force one)
    bool materials_moved_ = false;        // a particle of another material than the default was emitted
};

}  // namespace pbf
