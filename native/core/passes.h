// The physics, written once: each struct is one per-particle operation, called as op(i) for
// every particle i by the CPU backend (a parallel loop) and the CUDA backend (one thread each).
// Ops hold raw pointers into the backend's buffers and the substep's constants by value.
#pragma once
#include "atomics.h"
#include "collide.h"
#include "grid.h"
#include "material_ops.h"
#include "packed_vectors.h"
#include "sph.h"

namespace pbf {

// ---- grid build ------------------------------------------------------------------------------
// Sort key of each slot: its cell, or num_cells for dead particles and slots past the count.
struct CellKeyOp {
    const Vec4* positions;
    const uint32_t* ids;
    const uint32_t* count;
    GridDims grid;
    uint32_t* keys;
    uint32_t* order;
    PBF_HD void operator()(uint32_t i) const {
        const bool alive = i < *count && ids[i] != kDeadId;
        keys[i] = alive ? cell_key(grid, xyz(positions[i])) : grid.num_cells;
        order[i] = i;
    }
};

// After sorting over n slots: cell_begin[c] = first sorted index with key >= c, for every c in
// 0..num_cells, and *count = cell_begin[num_cells] (dead particles are dropped here).
struct CellBeginOp {
    const uint32_t* sorted_keys;
    uint32_t n;
    uint32_t num_cells;
    uint32_t* cell_begin;
    uint32_t* count;
    PBF_HD void operator()(uint32_t i) const {  // i in 0..n inclusive
        const uint32_t prev = i == 0 ? 0u : sorted_keys[i - 1] + 1u;
        const uint32_t cur = i == n ? num_cells : sorted_keys[i];
        for (uint32_t c = prev; c <= cur; ++c) cell_begin[c] = i;
        if (prev <= num_cells && num_cells <= cur) *count = i;
    }
};

// Moves particle data into sorted order: the ids and two Vec4 streams (x and v when binning x;
// x and x* when binning x*, when v is dead until the velocity update rewrites it).
struct GatherOp {
    const uint32_t* order;
    const Vec4 *a_in, *b_in;
    const uint32_t* id_in;
    Vec4 *a_out, *b_out;
    uint32_t* id_out;
    const uint8_t* material_in = nullptr;  // the particles' material slots (null: none kept)
    uint8_t* material_out = nullptr;
    PBF_HD void operator()(uint32_t i) const {
        const uint32_t src = order[i];
        a_out[i] = a_in[src];
        b_out[i] = b_in[src];
        id_out[i] = id_in[src];
        if (material_out) material_out[i] = material_in[src];
    }
};

// ---- adaptive iterations -------------------------------------------------------------------------
// Lives in backend memory: the device decides when a substep's iterations have converged, and
// every later λ/Δp launch of that substep returns at once, so the host never waits for it.
struct IterationControl {
    uint32_t converged;        // this substep reached the target
    uint32_t iterations_used;  // λ/Δp iterations run in the current step (all substeps)
    float error_sum;           // Σ max(ρ/ρ0 - 1, 0) of the last λ pass
    uint32_t pad;
};

// One thread at each adaptive substep's start (the step's start, which also clears the
// iteration count, is the solver's BeginStepOp).
struct ResetControlOp {
    IterationControl* control;
    PBF_HD void operator()(uint32_t) const {
        control->converged = 0;
        control->error_sum = 0.0f;
    }
};

// One thread, after the λ pass's error sum: stop once the mean error is below target. The
// first iteration of a substep always runs (first = 1): with LDC as the warm start, substeps
// without any correction let LDC alone push the fluid and gained energy (docs/paper §9).
struct ConvergenceOp {
    IterationControl* control;
    const uint32_t* count;
    float target;
    uint32_t first;
    PBF_HD void operator()(uint32_t) const {
        if (control->converged) return;
        const float mean = *count ? control->error_sum / static_cast<float>(*count) : 0.0f;
        if (mean < target && !first)
            control->converged = 1;
        else
            ++control->iterations_used;
        control->error_sum = 0.0f;
    }
};

// ---- densities ---------------------------------------------------------------------------------
// SPH density of the particles plus the walls' and colliders' share (boundary_at).
PBF_HD float density_at(const WorldConstants& s, const ColliderView& colliders, const uint32_t* cell_begin,
                        const NeighborMasks& masks, const Vec4* pos, uint32_t i, Vec3 xi) {
    float rho = 0.0f;
    for_each_neighbor_of(s.grid, cell_begin, masks, i, xi, [&](uint32_t j) {
        const Vec3 d = xi - xyz(pos[j]);
        rho += poly6(length_sq(d), s.h2, s.poly6_coef);
    });
    return rho * s.mass + boundary_at(s, colliders, xi).density_ratio * s.rest_density;
}

// SPH density at the current positions; in the step it also stores ρ/ρ0 in positions' w (the
// error C₀ the next substep starts from, and the colour). A read of the stats between steps
// sums ρ alone (`store_ratio` false): the w the step left is that C₀, and a read must not change
// what the next step does.
// With masks (the last substep's, while the particle order is unchanged) it replays them.
struct DensityOp {
    WorldConstants s;
    ColliderView colliders;  // at the current poses
    const uint32_t* cell_begin;
    Vec4* positions;
    float* density;
    NeighborMasks masks;  // rows null: walk the grid
    bool store_ratio = true;
    PBF_HD void operator()(uint32_t i) const {
        const float rho = density_at(s, colliders, cell_begin, masks, positions, i, xyz(positions[i]));
        density[i] = rho;
        if (store_ratio) positions[i].w = rho * s.inv_rest_density;
    }
};

// ---- pre-stabilization (Macklin et al. 2014, Unified Particle Physics: constraints applied to x
// before the prediction resolve initial overlaps without adding energy) ------------------------
// For overlaps no motion made: a collider created or teleported into the fluid, a block emitted
// into one. The solver runs these on the first substep after such a change (Solver::settle).
// x moves out of the colliders it overlaps at the start poses: mirrored (project_out_at_start)
// all the way (`mirror`: the settling and the contacts its iterations leave, which a plain
// projection would pile onto the surface the settling cleared), or by `weight` of a plain
// projection (the substeps' contact pre-stabilization, Solver::substep, whose penetrations are a
// contact's, a fraction of a radius).
struct SettleOverlapOp {
    WorldConstants s;
    ColliderView colliders;
    Vec4* positions;
    float weight = 1.0f;
    bool mirror = false;
    PBF_HD void operator()(uint32_t i) const {
        const Vec4 x = positions[i];
        const Vec3 out = project_out_at_start(s, colliders, xyz(x), mirror);
        positions[i] = make_vec4(weight == 1.0f ? out : xyz(x) + (out - xyz(x)) * weight, x.w);
    }
};

// The settling iterations' error damping γ: this large, the λ pass's target is each particle's
// own C₀. At least kSettleIterations of them run (docs/physics.md, Overlaps, has what fewer
// left), in rounds of kSettleRound with the neighbour grid built anew before each: the water a
// collider displaces has to travel several spacings to where there is room, and iterations
// that keep the neighbours found at the start push only against those, however many run.
constexpr float kSettleDamping = 1e6f;
constexpr uint32_t kSettleIterations = 32;
constexpr uint32_t kSettleRound = 8;

// x* = x, the starting point of the settling iterations.
struct CopyPositionsOp {
    const Vec4* from;
    Vec4* to;
    PBF_HD void operator()(uint32_t i) const { to[i] = from[i]; }
};

// x takes the settled x*; its w (ρ/ρ0 when the last substep ended) stays.
struct AdoptSettledOp {
    const Vec4* settled;
    Vec4* positions;
    PBF_HD void operator()(uint32_t i) const { positions[i] = make_vec4(xyz(settled[i]), positions[i].w); }
};

// ---- Local Density Calibration + external forces + prediction ----------------------------------
// Meno & Tsuruno, Eq. 1-2: f_i = -K Σ_j ((ρ_j - ρ_i)/ρ0) h (1 - r/h) n_ij, n_ij = (x_j - x_i)/r.
// The paper prints a scalar sum; its text fixes the direction: a particle is pushed toward
// less dense neighbours and away from denser ones. With n_ij pointing from i to j, the minus
// sign does exactly that (a denser j, ρ_ij > 0, pushes i along -n_ij, away from j). The unit
// test "LDC force points from denser toward less dense" pins this reading.
// A pair pushes both of its particles the same way, so LDC alone does not conserve momentum:
// with P = ρ̃ - ρ0 (ρ̃ as below) and w_ij = h (1 - r/h) n_ij, f_i splits exactly into pair forces
// -K (P_i + P_j)/ρ0 w_ij, equal and opposite (a pressure), and a part of particle i alone,
// 2K P_i/ρ0 Σ_j w_ij, zero in a full neighbourhood. *own_part receives that part (null: not
// wanted): record_ldc_reaction gives the colliders its reaction.
PBF_HD Vec3 ldc_force(const WorldConstants& s, float k, const uint32_t* cell_begin, const Vec4* pos,
                      const float* density, uint32_t i, const NeighborMasks& masks = NeighborMasks{},
                      Vec3* own_part = nullptr) {
    const Vec3 xi = xyz(pos[i]);
    // Densities below ρ0 count as ρ0: LDC smooths compression only. Read literally, Eq. 1 also
    // evens out the density deficit of free-surface and wall particles (too few neighbours, not
    // real expansion), pushing the fluid outward and boiling a resting tank.
    const float rho_i = fmaxf(density[i], s.rest_density);
    Vec3 f{0.0f, 0.0f, 0.0f}, deficit{0.0f, 0.0f, 0.0f};
    for_each_neighbor_of(s.grid, cell_begin, masks, i, xi, [&](uint32_t j) {
        const Vec3 d = xyz(pos[j]) - xi;  // from i to j
        const float r2 = length_sq(d);
        if (r2 >= s.h2 || r2 <= 1e-20f) return;
        const float inv_r = inv_sqrt(r2);
        const float rho_ij = (fmaxf(density[j], s.rest_density) - rho_i) * s.inv_rest_density;
        // ρ_ij h (1 - r/h) n_ij with n_ij = d / r:  ρ_ij (h/r - 1) d
        f += d * (rho_ij * (s.h * inv_r - 1.0f));
        if (own_part) deficit += d * (s.h * inv_r - 1.0f);
    });
    if (own_part) *own_part = deficit * (2.0f * k * (rho_i - s.rest_density) * s.inv_rest_density);
    return f * -k;
}

// LDC's reaction on dynamic colliders. Next to a wall or collider, ldc_force's own part is the
// push of the missing neighbours: the boundary acts as neighbours b that mirror the particle's
// pressure (as Akinci et al. 2012's boundary particles do; P_b = P_i adds nothing to f_i), whose
// pair forces -2K P_i/ρ0 Σ_b w_ib on the particle the boundary feels back. At a free surface the
// missing neighbours are air, with nothing to push back on: reacting the whole part (an earlier
// attempt) also pushed a floating box up by the compression at its waterline. So the colliders
// take the part's component against the boundaries' density gradient G = Σ_k G_k (boundary_at;
// it points into the boundary), shared as -G_k: part·G/|G|² G_k each. Approximation: the
// boundary's push on a particle lies along G (exact at a flat boundary; edges, corners and air
// beside a boundary are split by direction); a part pointing into a boundary is not reacted.
// x is where the substep starts, with the colliders at their start poses; displacement_per_accel
// turns the acceleration into the substep's displacement (w_i Δt²).
PBF_HD void record_ldc_reaction(const WorldConstants& s, const ColliderView& cv, Vec3 x, Vec3 own_part,
                                float displacement_per_accel) {
    if (!cv.impulses || cv.dynamic_count == 0 || length_sq(own_part) == 0.0f) return;
    ColliderView start = cv;
    start.cur = cv.prev;
    const ColliderShares colliders = collider_shares(s, start, x);
    if (colliders.reacting >= kStaticNear) return;  // no dynamic collider within h
    const Vec3 g = walls_boundary(s, x).gradient + colliders.gradient;
    const float g2 = length_sq(g), along = -dot(own_part, g);
    if (!(g2 > 0.0f) || !(along > 0.0f)) return;
    record_shares_push(s, start, x, colliders, -(along / g2) * displacement_per_accel);
}

// Limits |v| to max_speed, and never returns Inf or NaN, whatever it is given: every velocity
// the solver stores passes through here. A velocity whose |v|² overflowed (a tiny dt, a huge
// gravity or max_speed) keeps its direction at max_speed; NaN components count as 0.
PBF_HD Vec3 clamp_speed(Vec3 v, float max_speed) {
    const float kFloatMax = 3.402823466e38f;
    const float sp2 = length_sq(v);
    if (sp2 <= fminf(max_speed * max_speed, kFloatMax)) return v;  // the common case (false for NaN)
    if (sp2 <= kFloatMax) return v * (max_speed / sqrtf(sp2));
    // Rare: NaN -> 0, ±Inf -> ±FLT_MAX, then scale by 2^-100 so that |u|² is finite.
    const Vec3 u = Vec3{v.x == v.x ? clampf(v.x, -kFloatMax, kFloatMax) : 0.0f,
                        v.y == v.y ? clampf(v.y, -kFloatMax, kFloatMax) : 0.0f,
                        v.z == v.z ? clampf(v.z, -kFloatMax, kFloatMax) : 0.0f} *
                   7.88860905e-31f;
    const float len = length(u);
    return len > 0.0f ? u * (max_speed / len) : Vec3{0.0f, 0.0f, 0.0f};
}

// The substep's speed limit (max_speed, and the travel cap that keeps every particle within
// the neighbour search's reach); each particle-substep it cuts is counted for the stats.
PBF_HD Vec3 limit_speed(const StepContext& ctx, Vec3 v) {
    const float limit = ctx.speed_limit;
    if (length_sq(v) <= limit * limit) return v;  // false for NaN: clamp_speed zeroes it
    atomic_add_u32(ctx.clamped, 1u);
    return clamp_speed(v, limit);
}

// The old error's share of a particle's λ. The λ pass's target c + γ (c - c₀) is
// (1 + γ)(c - c₀), the compression this substep's motion added, plus c₀, the error the particle
// started the substep with (the denominator carries the 1 + γ, so 1/(1 + γ) of the old error is
// removed per substep). PBF turns a correction into velocity (÷Δt): for new compression that is
// the impulse that stops the motion that made it, but an old error is no motion of this substep.
// Converted, it gave c₀ h / (Δt + τ) per layer of a compressed column, so at Δt ≪ τ a single
// step released c₀ · sound_speed, whatever its length (28 m/s from a step of 2.5e-7 s after a
// splash, 12 m/s from 1e-5 s after a capped huge step). So at γ > 2 the old error is removed
// mostly in the positions only, as pre-stabilization does (Macklin et al. 2014): the first λ pass
// of the substep keeps each particle's share, u² min(c₀, target) / target with u = 1 - 2/γ (the
// new compression counted first), the Δ passes sum the displacement those shares of λ give
// (share_i λ_i + share_j λ_j along the same pair gradient, plus the boundary's share) and the
// velocity update leaves it out. The part still converted, 1 - u² ≈ 4Δt/τ of the old share,
// changes a velocity by about 4 c₀ h Δt / τ² per substep, an acceleration: a step changes the
// velocities by what its length allows. At γ ≤ 2 nothing changes (the default substeps, γ ≈
// 0.3-0.6, and 16 fixed substeps of a 1/60 s frame at h = 8 cm), and the weight u² rises from
// there without a step: the persistent error is how a resting fluid carries weight (its removal
// holds up what lies on it; removed in the positions at every γ, one-site boxes in a pool were
// pushed down by the water above them with nothing pushing back from below; from γ = 1, a
// resting pool at 16 fixed substeps, γ = 1.9, rose a particle 3 mm higher, over its test's
// bound). Approximation: the share is fixed over the substep's iterations
// (they are taken to remove both parts in proportion, exact for a linear solve).
PBF_HD float old_error_weight(float gamma) {
    const float u = gamma > 2.0f ? 1.0f - 2.0f / gamma : 0.0f;
    return u * u;
}
PBF_HD float old_error_share(float target, float c0, float weight) {
    if (!(target > 0.0f)) return 0.0f;
    return fminf(c0, target) / target * weight;
}

// v += (g + f_ldc) Δt ; x* = x + v Δt, projected out of colliders and walls.
struct PredictOp {
    WorldConstants s;
    StepContext ctx;
    const uint32_t* cell_begin;  // used only with LDC
    const float* density;        // ρ at the current positions, used with LDC and at γ > 2
    Vec4* positions;             // w: C₀, moved toward ρ/ρ0 at γ > 2 (old_error_weight)
    Vec4* velocities;
    Vec4* predicted;
    NeighborMasks masks;  // the last substep's, while the particle order is unchanged; else null
    PBF_HD void operator()(uint32_t i) const {
        // The λ pass's C₀ is ρ/ρ0 of the last substep's last λ pass, before its last correction
        // (positions.w): usually a slight overestimate. But that correction can compress a
        // particle further, and at Δt ≪ τ the rise counted as new error went into velocity in one
        // substep (at 1e-5 s, 24 m/s per 1 % of compression). So C₀ moves toward the error at x
        // itself where that is larger, by the weight old_error_share gives positions
        // (StepContext::positional_weight: 0 at γ ≤ 2 outside a substep that settles overlaps).
        const float positional = ctx.positional_weight;
        if (positional > 0.0f) {
            const float w = positions[i].w;
            positions[i].w = w + positional * fmaxf(density[i] * s.inv_rest_density - w, 0.0f);
        }
        Vec3 accel = s.gravity;
        const uint32_t m = material_of(ctx, i);
        const float w_i = inverse_mass(s, ctx, i);
        const ColliderView cv = colliders_for_mass(ctx.colliders, w_i);
        const Vec3 x = xyz(positions[i]);
        // LDC's push is a force per particle: a multiphase world divides it by the particle's mass.
        if (s.ldc_enabled) {
            const float k = material_ldc_k(ctx, m);
            const bool react = cv.impulses && cv.dynamic_count > 0;
            Vec3 own_part;
            accel += ldc_force(s, k, cell_begin, positions, density, i, masks, react ? &own_part : nullptr) * w_i;
            if (react) record_ldc_reaction(s, cv, x, own_part, w_i * ctx.dt * ctx.dt);
        }
        const Vec3 v = limit_speed(ctx, xyz(velocities[i]) + accel * ctx.dt);
        velocities[i] = make_vec4(v, 0.0f);
        predicted[i] = make_vec4(collide(s, cv, x + v * ctx.dt, x), 0.0f);
    }
};

// ---- density constraint (Macklin & Müller 2013, Eq. 1-11) --------------------------------------

// λ_i = -C_i / (Σ_k |∇_k C_i|² + ε) with C_i = ρ_i/ρ0 - 1. The constraint is unilateral
// (C clamped at 0): particles at the free surface are not pulled together, which with few
// iterations otherwise causes clumping. λ is stored in predicted[i].w for the Δp pass.
// The substep's first λ pass walks the grid and records the neighbour masks (record = 1);
// every later neighbour pass of the substep replays them. The first pass also stores the
// denominator Σ_k |∇_k C_i|² + ε; later λ passes reuse it and sum only ρ (the constraint value
// C_i stays exact each iteration; its gradient norm, the step's scaling, is frozen within the
// substep, where positions move by a small fraction of h).
// With colliders, the pass also keeps their share's gradient at x* for the iteration's Δ pass
// (which reads it instead of walking the colliders again: x* and the poses are the same there)
// and records the dynamic colliders' reaction to the push ∇C_k·λ_i that pass gives particle i.
template <bool kPlain>
struct LambdaPass {
    using F = Features<kPlain>;
    WorldConstants s;
    StepContext ctx;
    const uint32_t* cell_begin;
    NeighborMasks masks;
    uint32_t record;
    const Vec4* positions;  // x; w = ρ/ρ0 when the last substep ended (the error it left)
    Vec4* predicted;
    float* density;
    const IterationControl* control;     // null: fixed iteration count
    float* denominator = nullptr;        // null: every pass computes its own
    PackedVectors colliders_gradient{};  // written when the world has colliders
    Vec4* old_push = nullptr;            // w: the old error's share (old_error_share); null: no split
    PBF_HD void operator()(uint32_t i) const {
        if (control && control->converged) return;
        const Vec3 xi = xyz(predicted[i]);
        float rho = 0.0f, sum_grad2 = 0.0f;
        Vec3 grad_i{0.0f, 0.0f, 0.0f};
        // Multiphase: each particle's share of the correction weighted by its inverse mass.
        const bool multiphase = F::multiphase(s);
        const bool first = record || !denominator;
        if (first) {
            const float scale = s.mass * s.inv_rest_density;
            auto visit = [&](uint32_t j) {
                const Vec3 d = xi - xyz(predicted[j]);
                const float r2 = length_sq(d);
                if (r2 >= s.h2) return;
                rho += poly6(r2, s.h2, s.poly6_coef);
                if (j == i) return;
                const Vec3 g = pair_gradient(d, r2, s.h, s.spiky_coef, i, j) * scale;
                grad_i += g;
                sum_grad2 += multiphase ? length_sq(g) * F::inv_mass(s, ctx, j) : length_sq(g);
            };
            if (record)
                for_each_neighbor_recording(s.grid, cell_begin, predicted, s.h2, masks, i, xi, visit);
            else
                for_each_listed_neighbor(s.grid, cell_begin, masks, i, visit);
        } else {
            for_each_listed_neighbor(s.grid, cell_begin, masks, i, [&](uint32_t j) {
                const float r2 = length_sq(xi - xyz(predicted[j]));
                if (r2 < s.h2) rho += poly6(r2, s.h2, s.poly6_coef);
            });
        }
        // The colliders once: their density, their gradient (the denominator's, and the Δ
        // pass's), and which dynamic ones are within h (the reaction below).
        const ColliderShares colliders = collider_shares(s, F::colliders(ctx), xi);
        const BoundarySample walls = walls_boundary(s, xi);
        float denom;
        if (first) {
            // The walls' and colliders' density moves with x_i too (they carry no λ of their own).
            const float self = length_sq(grad_i + walls.gradient + colliders.gradient);
            denom = (1.0f + ctx.error_damping) * (sum_grad2 + (multiphase ? self * F::inv_mass(s, ctx, i) : self)) +
                    ctx.lambda_epsilon;
            if (denominator) denominator[i] = denom;
        } else {
            denom = denominator[i];
        }
        rho = rho * s.mass + (walls.density_ratio + colliders.density_ratio) * s.rest_density;
        density[i] = rho;
        // Error damping (XPBD's constraint damping with the substep's start as reference): the
        // target is C + γ (C - C₀) = 0, C₀ the error the particle started the substep with. New
        // compression (C₀ = 0) is removed in full; an old error shrinks by 1/(1 + γ) per
        // substep, γ = τ/Δt, so it relaxes over τ whatever Δt is and the velocity its removal
        // creates stays bounded (the step turns every correction into velocity).
        const float c = fmaxf(rho * s.inv_rest_density - 1.0f, 0.0f);
        const float c0 = fmaxf(positions[i].w - 1.0f, 0.0f);
        const float target = fmaxf(c + ctx.error_damping * (c - c0), 0.0f);
        const float lambda = -target / denom;
        predicted[i].w = lambda;
        // The old error's share of λ (old_error_share), fixed by the first pass of the substep,
        // which also clears the displacement the Δ passes sum from it. That share moves x without
        // velocity, so the colliders feel only the rest of the push (no impulse changes hands).
        float lambda_moving = lambda;
        if (old_push) {
            float share;
            if (record) {
                share = old_error_share(target, c0, ctx.positional_weight);
                old_push[i] = make_vec4(Vec3{0.0f, 0.0f, 0.0f}, share);
            } else {
                share = old_push[i].w;
            }
            lambda_moving -= share * lambda;
        }
        if (F::colliders(ctx).count == 0) return;
        // Packed, the Δ pass's push differs from the reaction below by at most 1e-4 of it.
        colliders_gradient.store(i, colliders.gradient);
        if (colliders.reacting < kStaticNear && ctx.colliders.impulses)
            record_shares_push(s, colliders_for_mass(ctx.colliders, F::inv_mass(s, ctx, i)), xi, colliders,
                               lambda_moving);
    }
};
using LambdaOp = LambdaPass<false>;

// s_corr's push k·weight for a pair of kernel value w. With k, Δq or n other than the defaults
// (WorldConstants::scorr_bounded): at and beyond the rest spacing s s_corr separates nothing
// that clumps; it pushes a free surface outward, which in zero gravity nothing holds back, so
// that push is energy the fluid never had. A resting pool needs the defaults' push there (it
// holds the surface up against the solver's residual compression), so the push is at most the
// defaults', k_ref · min((W/W(0.2 h))^4, 2), plus what the given term rises above its own value
// at s: pairs closer than s, which clump, still meet the given term's rise, and the push stays
// continuous in r.
// What the push adds above the defaults' k_ref w₀(r) is returned in *beyond as well: the Δ pass
// moves positions by that part without giving it velocity. s_corr is not a constraint with a
// state to reach but a push repeated every substep: a large k's rise, taken as velocity, throws
// pairs apart faster than anything in the scene moves (in compressed water too, where λ already
// pushes them apart). Moved in x alone it still undoes clumping and brings neither momentum nor
// kinetic energy, and the defaults' part acts as it does in every world.
// Compiled only into the Δ pass of such worlds (DeltaBounded): in the others' kernels even an
// untaken branch took registers the hot loop needs.
template <bool kBounded>
PBF_HD float scorr_push(const WorldConstants& s, const StepContext& ctx, float w, float r2, float grad_len,
                        float lambda_sum, float* beyond = nullptr) {
    const float weight = scorr_weight(w * s.scorr_inv_w_dq, s.scorr_n, s.scorr_a, s.scorr_b);
    if (!kBounded) return ctx.scorr_k * weight;
    const float ratio = w * s.scorr_ref_inv_w_dq;
    const float reference = ctx.scorr_ref_k * fminf(ratio * ratio * ratio * ratio, kScorrPowerCap);
    // The rise answers a pair closer than the rest spacing. Where neither particle is compressed
    // (λ_i + λ_j = 0: in a stream too sparse for λ, where a nozzle emits a particle near another)
    // s_corr alone moves the pair, and there the rise moves each of the two at most half their
    // gap to the rest spacing per substep, relaxed as the whole term is: the pair is brought to
    // the rest spacing over s_corr's time scale instead of being thrown apart in one substep.
    // In compressed water the rise adds to λ's push, stiffening it against clumping.
    float rise = ctx.scorr_k * fmaxf(weight - s.scorr_rest_weight, 0.0f);
    if (lambda_sum == 0.0f)
        rise = fminf(rise, fmaxf(2.0f * s.radius - sqrtf(r2), 0.0f) * ctx.scorr_gap_push / fmaxf(grad_len, 1e-30f));
    const float push = fminf(ctx.scorr_k * weight, reference + rise);
    if (beyond) *beyond = fmaxf(push - reference, 0.0f);
    return push;
}

// Δp_i = (1/ρ0) Σ_j (λ_i + λ_j + s_corr) ∇W(x_i - x_j), s_corr = -k scorr_weight (sph.h); Jacobi:
// reads predicted, writes the corrected, collided position to corrected. The substep's last
// iteration does the velocity update in the same pass (finish_positions set): v = (x* - x)/Δt
// and x = x*, each particle writing only its own x and v, which no other thread reads here.
template <bool kPlain, bool kSplit = true, bool kScorrBounded = false>
struct DeltaPass {
    using F = Features<kPlain>;
    WorldConstants s;
    StepContext ctx;
    const uint32_t* cell_begin;
    NeighborMasks masks;
    const Vec4* positions;  // x at the start of the substep (for friction)
    const Vec4* predicted;
    Vec4* corrected;
    const IterationControl* control;   // null: fixed iteration count
    Vec4* finish_positions = nullptr;  // = positions, on the last iteration
    Vec4* finish_velocities = nullptr;
    const float* density = nullptr;      // ρ of the last λ pass, for x's w (ρ/ρ0)
    PackedVectors colliders_gradient{};  // the λ pass's, when the world has colliders
    // The old error's share of λ (w) and the displacement it gave over the substep's iterations
    // (xyz), which the velocity update leaves out (old_error_share); null: no split.
    // Compiled without the split (kSplit false: substeps no shorter than τ, where it is 0) the
    // pass carries none of its loads or its second contact.
    Vec4* old_push = nullptr;
    PBF_HD void operator()(uint32_t i) const {
        const bool split = kSplit && old_push != nullptr;
        const Vec4 pi = predicted[i];
        const Vec3 xi = xyz(pi);
        const float lambda_i = pi.w;
        Vec3 c = xi;
        Vec4 old = split ? old_push[i] : Vec4{0.0f, 0.0f, 0.0f, 0.0f};
        if (!(control && control->converged)) {  // converged: x* carries over unchanged
            Vec3 dp{0.0f, 0.0f, 0.0f}, dp_old{0.0f, 0.0f, 0.0f};
            // s_corr's k relaxes with Δt (StepContext::scorr_k, solver/step_plan.cpp).
            for_each_listed_neighbor(s.grid, cell_begin, masks, i, [&](uint32_t j) {
                if (j == i) return;
                const Vec4 pj = predicted[j];
                const Vec3 d = xi - xyz(pj);
                const float r2 = length_sq(d);
                if (r2 >= s.h2) return;
                const Vec3 grad = pair_gradient(d, r2, s.h, s.spiky_coef, i, j);
                float beyond = 0.0f;
                const float scorr =
                    -scorr_push<kScorrBounded>(s, ctx, poly6(r2, s.h2, s.poly6_coef), r2,
                                               kScorrBounded ? length(grad) : 0.0f, lambda_i + pj.w, &beyond);
                dp += grad * (lambda_i + pj.w + scorr);
                if (split) dp_old += grad * (old.w * lambda_i + old_push[j].w * pj.w - beyond);
            });
            // The boundary's share of ∇C_i, weighted by λ_i alone (the boundary has no λ): the
            // walls', and the colliders' from the λ pass, which recorded their reaction
            // (multiphase: Δx_i = w_i ∇_i C λ, the reaction with particle i's own mass).
            const float w_i = F::inv_mass(s, ctx, i);
            const ColliderView cv = colliders_for_mass(F::colliders(ctx), w_i);
            Vec3 boundary_grad = walls_boundary(s, xi).gradient;
            if (cv.count > 0) boundary_grad += colliders_gradient.load(i);
            dp = dp * (s.mass * s.inv_rest_density) + boundary_grad * lambda_i;
            dp_old = dp_old * (s.mass * s.inv_rest_density) + boundary_grad * (old.w * lambda_i);
            if (F::multiphase(s)) {
                dp = dp * w_i;
                dp_old = dp_old * w_i;
            }
            const Vec3 x = xyz(positions[i]);
            if (split && length_sq(dp_old) > 0.0f) {
                // The moving share first, whose contacts push the colliders; then the old
                // error's, as far as the walls and colliders let it go, with no reaction recorded
                // (it gives no velocity). What it moved is kept out of v.
                ColliderView quiet = cv;
                quiet.impulses = nullptr;
                const Vec3 moving = collide(s, cv, xi + (dp - dp_old), x);
                c = collide(s, quiet, moving + dp_old, x);
                old = make_vec4(xyz(old) + (c - moving), old.w);
            } else {
                c = collide(s, cv, xi + dp, x);
            }
        }
        if (finish_positions) {
            const Vec3 x = xyz(positions[i]);
            const Vec3 moved = (c - x - xyz(old)) * ctx.inv_dt;
            const Vec3 v = limit_speed(ctx, moved);
            // The speed limit holds the position as well as the velocity: no particle crosses more
            // than the limit allows in a substep (the neighbour search's reach). Cut in v alone,
            // the position kept a move its velocity no longer had, and the next substep met
            // neighbours closer than the motion explains, whose push drove a jet along a wall on
            // at the limit. Where the limit cuts, the position is taken back along the same move
            // and projected again (no reaction recorded: the contacts were).
            if (v.x != moved.x || v.y != moved.y || v.z != moved.z) {
                ColliderView quiet = F::colliders(ctx);
                quiet.impulses = nullptr;
                c = collide(s, quiet, x + xyz(old) + v * ctx.dt, x);
            }
            finish_velocities[i] = make_vec4(v, 0.0f);
            if (!kPlain && ctx.colliders.count > 0) c = free_from_walls(s, ctx.colliders, c);
            finish_positions[i] = make_vec4(c, density[i] * s.inv_rest_density);
        } else {
            corrected[i] = make_vec4(c, lambda_i);
            if (split) old_push[i] = old;
        }
    }
};

using DeltaOp = DeltaPass<false>;
// The Δ pass without the old-error split, compiled with or without the features.
template <bool kPlain>
using DeltaNoSplit = DeltaPass<kPlain, false>;
// The Δ pass of a world whose s_corr is bounded (WorldConstants::scorr_bounded, scorr_push),
// with every feature and the split read at run time.
using DeltaBounded = DeltaPass<false, true, true>;

// ---- velocity update, vorticity confinement, XSPH ---------------------------------------------
// Pass 1 after the iterations: ω_i = Σ_j (m/ρ_j) v_ij × ∇_j W_ij (Macklin & Müller Eq. 15) and
// XSPH, v_i + c Σ_j (m/ρ_j) v_ij W_ij (Eq. 17), v_ij = v_j - v_i; both read the velocities of the
// velocity update, so one walk serves both. The smoothed velocity goes to velocities_out.
template <bool kPlain>
struct VorticityXsphPass {
    using F = Features<kPlain>;
    WorldConstants s;
    StepContext ctx;
    const uint32_t* cell_begin;
    NeighborMasks masks;
    const Vec4* positions;
    const Vec4* velocities;
    Vec4* omega;
    Vec4* velocities_out;
    PBF_HD void operator()(uint32_t i) const {
        const Vec3 xi = xyz(positions[i]);
        const Vec3 vi = xyz(velocities[i]);
        Vec3 w{0.0f, 0.0f, 0.0f}, xsph{0.0f, 0.0f, 0.0f};
        float weight = 0.0f;  // Σ_j V_j W_ij
        for_each_listed_neighbor(s.grid, cell_begin, masks, i, [&](uint32_t j) {
            if (j == i) return;
            const Vec4 pj = positions[j];
            const Vec3 d = xi - xyz(pj);
            const float r2 = length_sq(d);
            if (r2 >= s.h2) return;
            const float vol = fast_div(s.mass, fmaxf(pj.w, 1e-6f) * s.rest_density);
            const Vec3 vij = xyz(velocities[j]) - vi;
            // ∇_j W(x_i - x_j) = -∇_i W(x_i - x_j)
            w += cross(vij, -spiky_gradient_r2(d, r2, s.h, s.spiky_coef)) * vol;
            const float vw = poly6(r2, s.h2, s.poly6_coef) * vol;
            xsph += vij * vw;
            weight += vw;
        });
        omega[i] = make_vec4(w, length(w));
        // The walls and colliders smooth too (no-slip for a viscous fluid: material_ops.h).
        const float c = material_xsph_c(ctx, F::material(ctx, i));
        Vec3 dv = xsph * c;
        if (c > 0.0f) {
            const ColliderView cv = colliders_for_mass(F::colliders(ctx), F::inv_mass(s, ctx, i));
            dv += boundary_viscosity(s, cv, ctx.inv_dt, c, c * weight, xi, vi);
        }
        velocities_out[i] = make_vec4(vi + dv, 0.0f);
    }
};

// Pass 2: f_vort = ε (N × ω), N = η/|η|, η = ∇|ω| (Eq. 16), added to each particle's own
// smoothed velocity in place (no thread reads another's velocity in this pass). The same walk
// sums ρ at the final positions (a poly6 it computes anyway): the next step's LDC and the stats
// read it, so no separate density pass runs at the end of a step. In worlds with surface tension
// (kSurfaceNormals) it also sums each particle's surface normal from the same gradients, as
// SurfaceNormalOp does, into surface_normals: the next substep's surface forces then need no
// normal pass of their own (its positions are these, unless something moved them in between).
template <bool kSurfaceNormals, bool kPlain = false>
struct VorticityForcePass {
    using F = Features<kPlain>;
    WorldConstants s;
    StepContext ctx;
    const uint32_t* cell_begin;
    NeighborMasks masks;
    const Vec4* positions;
    const Vec4* omega;
    Vec4* velocities;
    float* density;
    Vec4* surface_normals = nullptr;  // only read with kSurfaceNormals; not aliasing the others
    PBF_HD void operator()(uint32_t i) const {
        const Vec3 xi = xyz(positions[i]);
        const float wi = omega[i].w;
        const uint32_t mi = kSurfaceNormals ? material_of(ctx, i) : 0u;
        Vec3 eta{0.0f, 0.0f, 0.0f}, normal{0.0f, 0.0f, 0.0f};
        float rho = 0.0f;
        for_each_listed_neighbor(s.grid, cell_begin, masks, i, [&](uint32_t j) {
            const Vec4 pj = positions[j];
            const Vec3 d = xi - xyz(pj);
            const float r2 = length_sq(d);
            if (r2 >= s.h2) return;
            rho += poly6(r2, s.h2, s.poly6_coef);
            if (j == i) return;
            const float vol = fast_div(s.mass, fmaxf(pj.w, 1e-6f) * s.rest_density);
            const Vec3 grad = spiky_gradient_r2(d, r2, s.h, s.spiky_coef);
            eta += grad * ((omega[j].w - wi) * vol);
            if (kSurfaceNormals && material_of(ctx, j) == mi) normal += surface_normal_term(s, grad);
        });
        if (kSurfaceNormals) surface_normals[i] = make_vec4(normal * s.h, 0.0f);
        density[i] = rho * s.mass + boundary_at(s, F::colliders(ctx), xi).density_ratio * s.rest_density;
        Vec3 v = xyz(velocities[i]);
        const float eta_len = length(eta);
        if (s.vorticity_epsilon > 0.0f && eta_len > 1e-9f) {
            const Vec3 n = eta * (1.0f / eta_len);
            v += cross(n, xyz(omega[i])) * (s.vorticity_epsilon * ctx.dt);
        }
        velocities[i] = make_vec4(limit_speed(ctx, v), 0.0f);
    }
};

using VorticityForceOp = VorticityForcePass<false>;
using VorticityXsphOp = VorticityXsphPass<false>;
// The vorticity force without the surface normals, compiled with or without the features.
template <bool kPlain>
using VorticityForceOnly = VorticityForcePass<false, kPlain>;

// ---- emission and drains -------------------------------------------------------------------
// Fills slots count..count+n-1 (as far as capacity allows) with a lattice block.
struct EmitBlockOp {
    const uint32_t* count;
    const uint32_t* next_id;
    uint32_t capacity;
    Vec3 origin;  // centre of the first particle
    float spacing;
    uint32_t nx, ny;  // lattice extent in x and y (z follows)
    Vec3 velocity;
    Vec4 *positions, *velocities;
    uint32_t* ids;
    uint8_t* materials = nullptr;  // null: the solver keeps none
    uint8_t material = 0;
    PBF_HD void operator()(uint32_t k) const {
        const uint32_t slot = *count + k;
        if (slot >= capacity) return;
        // nx * ny in 64 bits: a block 65536 x 65536 points wide wraps it to 0 in 32 (k / 0).
        const uint32_t ix = k % nx, iy = (k / nx) % ny, iz = static_cast<uint32_t>(k / (uint64_t(nx) * ny));
        positions[slot] = make_vec4(origin + Vec3{ix * spacing, iy * spacing, iz * spacing}, 1.0f);
        velocities[slot] = make_vec4(velocity, 0.0f);
        ids[slot] = particle_id(*next_id, k);
        if (materials) materials[slot] = material;
    }
};

// Nozzle: n particles spread over a disc by a golden-angle spiral, and along the direction by
// how far they would have travelled since their emission time within the substep. Where the
// disc reaches into a collider, a point closer than one radius to its inside (at the substep's
// start pose) emits nothing: the water has no room there. Its slot is marked dead, as a drain
// marks one, so the next grid build drops it, and *blocked counts it, which the commit leaves
// out of the emitted total. Emitted inside, the prediction projected the particle out as a
// velocity of depth / Δt; moved out at emission, the points of the disc inside piled onto the
// collider's surface, where they overlapped.
struct EmitNozzleOp {
    const uint32_t* count;
    const uint32_t* next_id;
    uint32_t capacity;
    uint32_t n;            // particles this substep
    uint32_t sequence;     // running index for the spiral, so successive substeps interleave
    uint32_t disc_points;  // spiral points that fill the disc at rest spacing
    Vec3 center, direction, tangent, bitangent;
    float radius, speed, dt;
    Vec4 *positions, *velocities;
    uint32_t* ids;
    uint8_t* materials = nullptr;
    uint8_t material = 0;
    WorldConstants s{};
    ColliderView colliders{};  // at the substep's poses; none: every point emits
    uint32_t* blocked = nullptr;
    PBF_HD void operator()(uint32_t k) const {
        const uint32_t slot = *count + k;
        if (slot >= capacity) return;
        const uint32_t m = (sequence + k) % disc_points;
        const float r = radius * sqrtf((m + 0.5f) / static_cast<float>(disc_points));
        const float angle = 2.39996323f * static_cast<float>(m);  // golden angle
        const float travelled = speed * dt * (1.0f - (k + 0.5f) / static_cast<float>(n));
        const Vec3 p = center + tangent * (r * cosf(angle)) + bitangent * (r * sinf(angle)) + direction * travelled;
        positions[slot] = make_vec4(p, 1.0f);
        velocities[slot] = make_vec4(direction * speed, 0.0f);
        Vec3 out = p;
        if (colliders.count > 0 && push_out_of_colliders(s, colliders, colliders.prev, out)) {
            ids[slot] = kDeadId;
            atomic_add_u32(blocked, 1u);
            return;
        }
        ids[slot] = particle_id(*next_id, k);
        if (materials) materials[slot] = material;
    }
};

// Run as one thread after an emission of `requested` particles: advances count and ids. The
// slots a nozzle left dead (*blocked) count until the next grid build drops them, but were never
// emitted.
struct CommitEmissionOp {
    uint32_t* count;
    uint32_t* next_id;
    unsigned long long* emitted_total;
    uint32_t* blocked;
    uint32_t capacity;
    uint32_t requested;
    PBF_HD void operator()(uint32_t) const {
        const uint32_t room = capacity - *count;
        const uint32_t added = requested < room ? requested : room;
        *count += added;
        *next_id = particle_id(*next_id, added);
        *emitted_total += added - *blocked;
        *blocked = 0;
    }
};

// Marks particles inside the box as dead; the next grid build drops them.
struct DrainOp {
    const uint32_t* count;
    const Vec4* positions;
    Vec3 box_min, box_max;
    uint32_t* ids;
    uint32_t* drained;
    PBF_HD void operator()(uint32_t i) const {
        if (i >= *count || ids[i] == kDeadId) return;
        const Vec3 p = xyz(positions[i]);
        if (p.x < box_min.x || p.y < box_min.y || p.z < box_min.z || p.x > box_max.x || p.y > box_max.y ||
            p.z > box_max.z)
            return;
        ids[i] = kDeadId;
        atomic_add_u32(drained, 1u);
    }
};

// Run as one thread after drains: folds the step's drained count into the total.
struct CommitDrainOp {
    uint32_t* drained;
    unsigned long long* drained_total;
    PBF_HD void operator()(uint32_t) const {
        *drained_total += *drained;
        *drained = 0;
    }
};

// ---- step feedback (read by the host, without waiting, to choose the next step's substeps) ------
// Heights along -g are measured from the wall box's corner lowest along -g, so every particle's
// lies in [0, extent] and the float bits of these non-negative values order like the values
// (the executors reduce them with integer max). The box of particle centres (wall_*), which an
// open level also has (its limit box), where boundary_* lies at ±FLT_MAX.
struct HeightFrame {
    Vec3 up;       // -g / |g|; zero without gravity (every height is then 0)
    float base;    // up · (the box corner lowest along up)
    float extent;  // the box's extent along up
};
PBF_HD HeightFrame height_frame(const WorldConstants& s) {
    HeightFrame f{Vec3{0.0f, 0.0f, 0.0f}, 0.0f, 0.0f};
    const float g = length(s.gravity);
    if (!(g > 0.0f)) return f;
    f.up = s.gravity * (-1.0f / g);
    const Vec3 lo = s.wall_min, hi = s.wall_max;
    const Vec3 corner{f.up.x >= 0.0f ? lo.x : hi.x, f.up.y >= 0.0f ? lo.y : hi.y, f.up.z >= 0.0f ? lo.z : hi.z};
    f.base = dot(f.up, corner);
    f.extent = fabsf(f.up.x) * (hi.x - lo.x) + fabsf(f.up.y) * (hi.y - lo.y) + fabsf(f.up.z) * (hi.z - lo.z);
    return f;
}

// The step's feedback as float bits, each the max over live particles of one particle's value:
// its speed, its height, and extent minus its height (whose max gives the lowest height).
struct FeedbackBits {
    uint32_t speed;
    uint32_t top;
    uint32_t below;  // extent - the lowest height
};
struct FeedbackSample {
    float speed, top, below;
};
PBF_HD FeedbackSample feedback_sample(const HeightFrame& f, const Vec4& x, const Vec4& v) {
    const float y = clampf(dot(f.up, xyz(x)) - f.base, 0.0f, f.extent);
    return FeedbackSample{length(xyz(v)), y, f.extent - y};
}
// The fluid's extent along gravity (top minus bottom particle centre); 0 with no particles.
PBF_HD float fluid_depth(const HeightFrame& f, const FeedbackBits& b) {
    return fmaxf(float_from_bits(b.top) - (f.extent - float_from_bits(b.below)), 0.0f);
}

// ---- statistics --------------------------------------------------------------------------------
struct ParticleStats {
    float compressive_error;  // max(ρ/ρ0 - 1, 0)
    float kinetic_energy;     // ½ m v²
};
PBF_HD ParticleStats particle_stats(const WorldConstants& s, float density, Vec4 velocity) {
    return ParticleStats{fmaxf(density * s.inv_rest_density - 1.0f, 0.0f), 0.5f * s.mass * length_sq(xyz(velocity))};
}

}  // namespace pbf
