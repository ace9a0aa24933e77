// The step, written once: the order of passes (Meno & Tsuruno Fig. 3 on top of Macklin &
// Müller 2013), instantiated with CpuExec in solver_cpu.cpp and with CudaExec in
// solver_cuda.cpp. Exec supplies memory, for_each(n, op), a key/value sort and reductions.
// The step's working arrays are the particle buffers (solver_buffers.h); the colliders and
// meshes (solver_colliders.h), what is computed for drawing only, render data and diffuse
// particles (solver_render.h), and what the host reads back, feedback, statistics and profile
// (solver_stats.h), keep their own memory and passes.
#pragma once
#include <algorithm>
#include <utility>

#include "backend.h"
#include "solver_buffers.h"
#include "solver_colliders.h"
#include "solver_render.h"
#include "solver_stats.h"
#include "../core/passes.h"
#include "../core/step_ops.h"

namespace pbf {

template <class Exec>
class Solver final : public Backend, private ParticleBuffers {
public:
    template <class... ExecArgs>
    explicit Solver(ExecArgs&&... args) : exec_(std::forward<ExecArgs>(args)...) {}
    ~Solver() override {
        exec_.activate();
        ParticleBuffers::release(exec_);
        colliders_.release();
        render_.release();
        diffuse_.release();
        stats_.release();
    }

    Status init(const BackendConfig& config) {
        config_ = config;
        Status st = exec_.init(config.capacity, config.grid.num_cells);
        if (!st.ok()) return st;
        const size_t n = config.capacity;
        Allocations<Exec> alloc{exec_};
        ParticleBuffers::allocate(alloc, n, config.grid.num_cells);
        colliders_.allocate(alloc, config.max_colliders, config.kernel_radius);
        render_.allocate(alloc, config.render, n);
        stats_.allocate(alloc);
        diffuse_.allocate(alloc, config.diffuse, config.capacity);
        if (!alloc.ok) {
            return Status::error(PBF_ERROR_OUT_OF_MEMORY, "cannot allocate " + std::to_string(config.capacity) +
                                                              " particles on " + exec_.device_name() + ": " +
                                                              exec_.last_error_text());
        }
        ParticleBuffers::zero(exec_, n, config.grid.num_cells);
        colliders_.zero();
        render_.zero();
        diffuse_.zero();
        stats_.zero();
        return exec_.check("world initialisation");
    }

    pbf_backend kind() const override { return Exec::kKind; }
    std::string device_name() const override { return exec_.device_name(); }
    uint64_t device_bytes() const override { return exec_.allocated_bytes(); }

    // ---- one frame step: its substeps, then what the host and the renderer read ---------------
    Status step(const WorldConstants& s, const StepInput& in) override {
        exec_.activate();
        const uint32_t substeps = static_cast<uint32_t>(in.substeps.size());
        if (!colliders_.fits(static_cast<uint32_t>(in.collider_shapes.size()), in.collider_keys.size()) ||
            substeps > kMaxSubsteps)
            return Status::error(PBF_ERROR_INTERNAL, "step input exceeds the solver's collider buffers");
        exec_.timer_begin();
        exec_.profile_reset();
        colliders_.upload_step(in);  // before the step's first kernel
        // From here to the end of the step there are launches only: recorded, they go to the
        // device as one graph.
        exec_.record_begin();
        colliders_.begin_step();
        exec_.for_each(1, BeginStepOp{counters_});
        for (uint32_t k = 0; k < substeps; ++k) {
            SubstepInput sub = in.substeps[k];
            sub.ctx.colliders = colliders_.substep(k, s.mass * sub.ctx.inv_dt);
            sub.ctx.clamped = &counters_->speed_clamps;
            sub.ctx.materials = materials_;
            substep(s, sub);
        }
        colliders_.end_step(in.frame_dt);
        stats_.publish(s, particles(), bound_);
        diffuse_.update(s, in.simulated_dt, particles(), bound_, valid_masks(), colliders_.at_rest());
        render_.update(s, particles(), bound_, valid_masks());  // last, so its stage time is the pass alone
        exec_.record_end();
        exec_.feedback_published();
        exec_.profile_mark(kStageCount);
        exec_.timer_end();
        return exec_.check("pbf_world_step");
    }

private:
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
                            nz.material,
                            s,
                            ctx.colliders,
                            &counters_->blocked};
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
        // What they leave is removed in the positions in this substep, without LDC's push (its
        // context: step_plan.cpp, plan_step).
        if (in.settle_overlaps) settle(s, ctx, in.iterations);
        // 0b. Contact penetration a particle starts the substep with (a wall or a second
        // collider pushed it back in, or a mesh field's approximate projection left it short) is
        // no motion of the substep: projected out in the prediction it became velocity, depth /
        // Δt (100 m/s from a step of 1e-7 s). So where old errors move positions (γ > 2,
        // passes.h old_error_weight) it is removed in x by the same weight, as pre-stabilization
        // removes contacts (Macklin et al. 2014), with no reaction recorded. After a settling too:
        // its iterations move x, and where a wedge between colliders has no room near, they
        // leave some particles in contact, which are mirrored out as the settling's own were.
        const float contact_weight = ctx.positional_weight;
        if (contact_weight > 0.0f && ctx.colliders.count > 0) {
            exec_.for_each(bound_, SettleOverlapOp{s, ctx.colliders, pos_, contact_weight, in.settle_overlaps});
            grid_valid_ = density_valid_ = masks_valid_ = false;
        }
        // 1. ρ at the current positions (grid of x): LDC needs it, and so does the λ pass's error
        // damping for particles emitted since the last density pass, and at γ > 1 for all, where
        // the prediction may move C₀ toward it (passes.h, old_error_weight: from γ = 2; a density
        // pass run here also writes ρ/ρ0 to positions.w itself). Emitted particles' positions.w,
        // the error C₀ a particle starts the substep with, is still the emission's 1: the
        // compression they were emitted into would count as new and go in one substep, at a tiny
        // Δt a velocity of error · spacing / Δt (16 m/s for a block at 1e-5 s with LDC off).
        // Where old errors move positions (γ > 2), that ρ is summed anew over a grid of x: the
        // last substep's, summed over the neighbours listed at x* before its corrections, misses
        // those the corrections brought within h, and the λ pass, walking the new grid, took
        // the difference for compression this substep's motion made (new error, removed as
        // velocity in one substep: 100 m/s from a step of 1.6e-7 s after a block struck a wall).
        if (ctx.positional_weight > 0.0f) grid_valid_ = density_valid_ = false;
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
        // read old_push.w in it. A world whose s_corr is bounded keeps the split at every Δt: its
        // rise above the defaults' push moves positions without velocity (scorr_push). Elsewhere
        // (every game frame's substeps) the split is skipped, its shares all 0, and Δp runs its
        // kernel compiled without it (DeltaNoSplit).
        Vec4* const old_push = ctx.positional_weight > 0.0f || s.scorr_bounded ? vel_ : nullptr;
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
            if (s.scorr_bounded)
                exec_.for_each(bound_, DeltaBounded{s, ctx, cell_begin_, masks, pos_, pred_, spare_, control,
                                                    last ? pos_ : nullptr, last ? spare_ : nullptr, density_,
                                                    colliders_gradient, old_push});
            else if (old_push)
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

    // Pre-stabilization (passes.h): the particles move out of the colliders they overlap, then
    // constraint iterations run on x itself, each particle's target being the error C₀ it ended
    // the last substep with (its positions.w), so that only what the move and a new boundary
    // added is removed, and none of it becomes velocity. The move gives no momentum to the
    // colliders (no impulses recorded) and s_corr stays out (it would move resting fluid). The
    // density pass of the substep then takes what is left as the error the particles start
    // with, which relaxes over τ (docs/physics.md, Overlaps).
    void settle(const WorldConstants& s, const StepContext& ctx, uint32_t iterations) {
        if (ctx.colliders.count > 0) exec_.for_each(bound_, SettleOverlapOp{s, ctx.colliders, pos_, 1.0f, true});
        StepContext settling = ctx;
        settling.colliders.impulses = nullptr;
        settling.error_damping = kSettleDamping;
        settling.scorr_k = 0.0f;
        const uint32_t settle_iterations = std::max(iterations, kSettleIterations);
        for (uint32_t done = 0; done < settle_iterations; done += kSettleRound) {
            // Each round starts from x, binned anew, so the particles it moves meet the
            // neighbours they are moving into.
            if (done > 0) exec_.for_each(bound_, AdoptSettledOp{pred_, pos_});
            build_grid(s, false);
            exec_.for_each(bound_, CopyPositionsOp{pos_, pred_});
            const NeighborMasks masks{masks_, sorted_keys_, config_.capacity};
            const PackedVectors colliders_gradient{order_[0], reinterpret_cast<float*>(order_[1])};
            const uint32_t round = std::min(kSettleRound, settle_iterations - done);
            for (uint32_t it = 0; it < round; ++it) {
                exec_.for_each(bound_, LambdaOp{s, settling, cell_begin_, masks, it == 0 ? 1u : 0u, pos_, pred_,
                                                density_, nullptr, denominator_, colliders_gradient});
                exec_.for_each(bound_, DeltaOp{s, settling, cell_begin_, masks, pos_, pred_, spare_, nullptr, nullptr,
                                               nullptr, density_, colliders_gradient});
                std::swap(pred_, spare_);
            }
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
                                           &counters_->blocked, config_.capacity, requested});
        grid_valid_ = density_valid_ = false;
        emitted_since_density_ = true;
    }

    Status read_count(uint32_t* count) {
        exec_.download(count, &counters_->count, sizeof(uint32_t));
        Status st = exec_.check("reading the particle count");
        if (st.ok()) bound_ = *count;  // exact again: launches shrink back to the live count
        return st;
    }

    const ParticleBuffers& particles() const { return *this; }

public:
    // ---- between steps: emission and read-outs ------------------------------------------------
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
            // The particles moved in memory: keep the render data in their order.
            render_.update(s, particles(), bound_, valid_masks());
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
        Status st = is_diffuse_buffer(source) ? diffuse_.count(&count) : read_count(&count);
        if (!st.ok()) return st;
        const uint32_t n = std::min(count, max_count);
        exec_.download(out, src, size_t(n) * buffer_element_bytes(source));
        *written = n;
        return exec_.check("copy-out");
    }

    Status read_stats(const WorldConstants& s, StatsReadback* out) override {
        exec_.activate();
        // The grid is valid between API calls: one density pass suffices. It leaves positions.w
        // and the step's own density bookkeeping as they were (DensityOp, store_ratio): reading
        // the stats or not gives the same next step.
        if (!density_valid_) {
            exec_.for_each(bound_,
                           DensityOp{s, colliders_.at_rest(), cell_begin_, pos_, density_, valid_masks(), false});
        }
        return stats_.read(s, particles(), diffuse_, out);
    }
    StepFeedback feedback() override { return stats_.feedback(); }

    LiveBuffers live_buffers() override {
        LiveBuffers b;
        b.positions = pos_;
        b.velocities = vel_;
        b.ids = ids_;
        b.materials = materials_;
        b.smoothed_positions = render_.smoothed();
        b.anisotropy = render_.anisotropy();
        b.count = &counters_->count;
        b.capacity = config_.capacity;
        b.cuda_device = Exec::kKind == PBF_BACKEND_CUDA ? config_.cuda_device : -1;
        b.diffuse_positions = diffuse_.positions();
        b.diffuse_velocities = diffuse_.velocities();
        b.diffuse_count = diffuse_.count_in_memory();
        b.diffuse_capacity = diffuse_.capacity();
        return b;
    }

    // ---- colliders and meshes, render data, diffuse particles, profile: their parts' own ------
    Status set_colliders_at_rest(const ColliderSetAtRest& c) override {
        exec_.activate();
        density_valid_ = false;  // the densities were summed against the old colliders
        return colliders_.set_at_rest(c);
    }
    Status collider_forces(const ColliderForce** rows) override {
        exec_.activate();
        return colliders_.forces(rows);
    }
    const ColliderForce* collider_force_table() const override { return colliders_.force_table(); }
    Status clear_collider_force(uint32_t row) override {
        exec_.activate();
        return colliders_.clear_force(row);
    }
    Status clear_collider_forces() override {
        exec_.activate();
        return colliders_.clear_forces();
    }
    Status create_mesh(const MeshBuild& b, uint32_t row) override {
        exec_.activate();
        return colliders_.create_mesh(b, row);
    }
    void destroy_mesh(uint32_t row) override {
        exec_.activate();
        colliders_.destroy_mesh(row);
    }
    void set_render_constants(const RenderConstants& render) override { render_.set_constants(render); }
    uint64_t render_updates() const override { return render_.updates(); }
    uint64_t render_bytes() const override { return render_.bytes(); }
    void set_diffuse_constants(const DiffuseConstants& diffuse) override { diffuse_.set_constants(diffuse); }
    uint64_t diffuse_updates() const override { return diffuse_.updates(); }
    uint64_t diffuse_bytes() const override { return diffuse_.bytes(); }
    Status diffuse_count(uint32_t* count) override { return diffuse_.count(count); }
    Status add_diffuse(const Vec4* rows, uint32_t n, uint32_t* added) override { return diffuse_.add(rows, n, added); }

    Status last_step_ms(float* ms) override { return stats_.last_step_ms(ms); }
    void set_profiling(bool on) override { stats_.set_profiling(on); }
    Status stage_times(StageTimes* out) override { return stats_.stage_times(out); }

    // ---- the executor's stream ----------------------------------------------------------------
    void* cuda_stream() const override { return exec_.native_stream(); }
    Status set_cuda_stream(void* stream) override {
        exec_.activate();
        return exec_.use_stream(stream);
    }

private:
    Exec exec_;
    BackendConfig config_{};  // the creation's; render and diffuse constants live in their parts
    SolverColliders<Exec> colliders_{exec_};
    SolverRenderData<Exec> render_{exec_};
    SolverDiffuse<Exec> diffuse_{exec_};
    SolverStats<Exec> stats_{exec_};
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
