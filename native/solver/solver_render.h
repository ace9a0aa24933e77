// What a solver computes for drawing only, each part where the world asks for it and nothing at
// all otherwise: render data (smoothed positions and anisotropy, render_ops.h) and diffuse
// particles (foam, spray and bubbles, diffuse_ops.h). Both run at the end of a step, from the
// step's last grid and neighbour masks.
#pragma once
#include <algorithm>
#include <cstdint>
#include <utility>

#include "backend.h"
#include "solver_buffers.h"
#include "../core/diffuse_ops.h"
#include "../core/render_ops.h"

namespace pbf {

// New tunables with the creation's value of `fixed` kept (the buffers were sized by it).
template <class T, class F>
void replace_keeping(T& current, const T& next, F T::*fixed) {
    const F kept = current.*fixed;
    current = next;
    current.*fixed = kept;
}

template <class Exec>
class SolverRenderData {
public:
    explicit SolverRenderData(Exec& exec) : exec_(exec) {}

    // For n particles, the buffers constants.flags asks for.
    void allocate(Allocations<Exec>& alloc, const RenderConstants& constants, size_t n) {
        const bool smoothed = constants.flags & kRenderSmoothed, anisotropy = constants.flags & kRenderAnisotropy;
        if (smoothed) alloc(smoothed_, n);
        if (anisotropy) alloc(anisotropy_, n * 3);
        bytes_ = ((smoothed ? n : 0) + (anisotropy ? n * 3 : 0)) * sizeof(Vec4);
        constants_ = constants;
        particles_ = n;
    }
    void zero() {
        if (smoothed_) exec_.zero(smoothed_, particles_ * sizeof(Vec4));
        if (anisotropy_) exec_.zero(anisotropy_, particles_ * 3 * sizeof(Vec4));
    }
    void release() {
        exec_.release(smoothed_);
        exec_.release(anisotropy_);
    }

    // New constants from the next pass on (flags unchanged: the buffers are the creation's).
    void set_constants(const RenderConstants& next) { replace_keeping(constants_, next, &RenderConstants::flags); }
    uint64_t updates() const { return updates_; }
    uint64_t bytes() const { return bytes_; }
    Vec4* smoothed() const { return smoothed_; }
    Vec4* anisotropy() const { return anisotropy_; }

    // Smoothed positions and anisotropy of the first n particles from the current grid (one
    // pass; none when the world computes no render data). After a step the last substep's masks
    // serve as neighbour lists.
    void update(const WorldConstants& s, const ParticleBuffers& p, uint32_t n, const NeighborMasks& masks) {
        if (!constants_.flags) return;
        exec_.profile_mark(kStageRender);
        exec_.for_each(n, RenderDataOp{s.grid, s.h2, constants_, p.cell_begin_, masks, p.pos_, smoothed_, anisotropy_});
        ++updates_;
    }

private:
    Exec& exec_;
    RenderConstants constants_{};
    size_t particles_ = 0;
    Vec4* smoothed_ = nullptr;    // null unless the world asks for it
    Vec4* anisotropy_ = nullptr;  // 3 per particle
    uint64_t bytes_ = 0;
    uint64_t updates_ = 0;
};

template <class Exec>
class SolverDiffuse {
public:
    explicit SolverDiffuse(Exec& exec) : exec_(exec) {}

    // constants.capacity diffuse particles beside n fluid particles (whose generation the scan
    // packs with them).
    void allocate(Allocations<Exec>& alloc, const DiffuseConstants& constants, uint32_t n) {
        constants_ = constants;
        particles_ = n;
        const uint64_t before = exec_.allocated_bytes();
        const uint32_t capacity = constants.capacity;
        if (capacity) {
            for (Vec4*& b : buffers_) alloc(b, capacity);
            alloc(flags_, size_t(capacity) + n);
            alloc(offsets_, size_t(capacity) + n);
            alloc(counters_, 1);
            alloc.ok = alloc.ok && exec_.reserve_scan(capacity + n).ok();
        }
        bytes_ = exec_.allocated_bytes() - before;
    }
    void zero() {
        const uint32_t capacity = constants_.capacity;
        if (!capacity) return;
        for (Vec4* b : buffers_) exec_.zero(b, size_t(capacity) * sizeof(Vec4));
        exec_.zero(flags_, (size_t(capacity) + particles_) * sizeof(uint32_t));
        exec_.zero(counters_, sizeof(DiffuseCounters));
    }
    void release() {
        for (Vec4* b : buffers_) exec_.release(b);
        exec_.release(flags_);
        exec_.release(offsets_);
        exec_.release(counters_);
    }

    // New constants from the next step on (capacity unchanged: the buffers are the creation's).
    void set_constants(const DiffuseConstants& next) { replace_keeping(constants_, next, &DiffuseConstants::capacity); }
    uint32_t capacity() const { return constants_.capacity; }
    uint64_t updates() const { return updates_; }
    uint64_t bytes() const { return bytes_; }
    Vec4* positions() const { return buffers_[0]; }
    Vec4* velocities() const { return buffers_[1]; }
    // The live count in backend memory; null without a diffuse capacity.
    const uint32_t* count_in_memory() const { return counters_ ? &counters_->count : nullptr; }

    Status count(uint32_t* count) {
        exec_.activate();
        *count = 0;
        if (!counters_) return Status{};
        exec_.download(count, &counters_->count, sizeof(uint32_t));
        return exec_.check("reading the diffuse count");
    }
    Status add(const Vec4* rows, uint32_t n, uint32_t* added) {
        *added = 0;
        uint32_t live = 0;
        Status st = count(&live);
        if (!st.ok() || !counters_) return st;
        const uint32_t fit = std::min(n, constants_.capacity - live);
        if (fit == 0) return Status{};
        exec_.upload(buffers_[0] + live, rows, size_t(fit) * sizeof(Vec4));
        exec_.upload(buffers_[1] + live, rows + n, size_t(fit) * sizeof(Vec4));
        const uint32_t total = live + fit;
        exec_.upload(&counters_->count, &total, sizeof total);
        *added = fit;
        return exec_.check("pbf_world_add_diffuse");
    }
    // The diffuse counters into out (nothing without a diffuse capacity).
    void read_stats(StatsReadback* out) {
        if (!counters_) return;
        DiffuseCounters dc{};
        exec_.download(&dc, counters_, sizeof dc);
        out->diffuse_count = dc.count;
        out->diffuse_dropped_step = dc.dropped_step;
        out->diffuse_generated_total = dc.generated_total;
        out->diffuse_dropped_total = dc.dropped_total;
    }

    // At the end of a step, from its last grid and the neighbour masks over the first n fluid
    // particles: normals (into p.spare_, free at the end of a step), how many each fluid
    // particle generates, the diffuse particles moved; one scan of [survivors | generated] packs
    // both into the back buffers, which become the front. No pass without a diffuse capacity.
    void update(const WorldConstants& s, float dt, const ParticleBuffers& p, uint32_t n, const NeighborMasks& masks,
                const ColliderView& colliders) {
        const DiffuseConstants& d = constants_;
        if (!d.capacity) return;
        exec_.profile_mark(kStageDiffuse);
        const uint32_t total = d.capacity + n;
        const float inv_h = 1.0f / s.h;
        if (n > 0) {
            Vec4* normals = p.spare_;
            exec_.for_each(
                n, DiffuseNormalOp{s.grid, s.h2, inv_h, p.cell_begin_, masks, p.pos_, &p.counters_->count, normals});
            exec_.for_each(n, DiffuseSourceOp{s.grid, s.h2, inv_h, dt, d, p.cell_begin_, masks, p.pos_, p.vel_, normals,
                                              p.ids_, steps_, &p.counters_->count, flags_ + d.capacity});
        }
        exec_.profile_mark(kStageDiffuseAdvect);
        const FluidSampler fluid{s.grid, s.h2, inv_h, p.cell_begin_, p.pos_, p.vel_};
        exec_.for_each(d.capacity, DiffuseAdvectOp{s, colliders, fluid, dt, d, &counters_->count, buffers_[0],
                                                   buffers_[1], flags_});
        exec_.exclusive_scan(flags_, offsets_, total);
        exec_.for_each(total, DiffuseScatterOp{s, colliders, fluid, dt, d, p.ids_, steps_, flags_, offsets_,
                                               buffers_[0], buffers_[1], buffers_[2], buffers_[3]});
        exec_.for_each(1, DiffuseCommitOp{counters_, flags_, offsets_, total, d.capacity});
        std::swap(buffers_[0], buffers_[2]);
        std::swap(buffers_[1], buffers_[3]);
        ++steps_;
        ++updates_;
    }

private:
    Exec& exec_;
    DiffuseConstants constants_{};
    uint32_t particles_ = 0;
    Vec4* buffers_[4] = {};        // positions, velocities (front), then the back pair
    uint32_t* flags_ = nullptr;    // capacity + max_particles: keep | generated
    uint32_t* offsets_ = nullptr;  // their exclusive scan
    DiffuseCounters* counters_ = nullptr;
    uint64_t bytes_ = 0;
    uint64_t updates_ = 0;
    uint32_t steps_ = 0;  // the generator's random stream: one per step
};

}  // namespace pbf
