// Fluid materials, written once for both executors: the inverse-mass weights of
// multiphase PBF, and surface tension, cohesion and adhesion as accelerations applied before the
// constraint iterations (as LDC is).
//
// Multiphase density. Every material's particles have the same volume V = m0/ρ0 (slot 0's mass
// and rest density; the lattice a block emits), and mass m_k = ρ0_k V. Then the number density
// of Solenthaler & Pajarola 2008, ρ_i = m_i Σ_j W_ij, over ρ0_i is V Σ_j W_ij whatever the
// neighbours' materials: the constraint C_i = ρ_i/ρ0_i - 1 is the single-fluid one, and a mixed
// neighbourhood has no density jump at an interface (no spurious interface tension). The
// materials differ in mass only, which enters as inverse-mass weights w_k = ρ0_slot0/ρ0_k of
// the position corrections (Macklin et al. 2014, "Unified particle physics", §7.1):
// λ_i = -C_i / Σ_k w_k |∇_k C_i|², Δx_i = w_i Σ (λ_i + λ_j) ∇W. The pressure that holds a
// heavy column then pushes a lighter particle further than gravity pulls it: buoyancy.
//
// Surface tension and cohesion follow Akinci et al. 2013 ("Versatile surface tension and
// adhesion for SPH fluids") between particles of the same material, written as accelerations
// (1/s² times h, so a coefficient means the same at any particle size). Surface tension σ drives
// both of Akinci's terms, as their one γ does; cohesion κ adds to the attraction alone:
//   a_i = -Σ_j K_ij h [(σ + κ) Ĉ(r) x̂_ij + (σ/4) (n_i - n_j)],  K_ij = 2 / (ρ_i/ρ0 + ρ_j/ρ0),
// The curvature term's weight σ/4: with the curvature term at or above the attraction's weight a
// relaxing cube tore its surface off (σ = κ = 100 at 4 substeps: 0.69 m/s, particles at the
// walls); σ/4 held (σ 100, κ 400: 0.29 m from the centre, a ball). Both are explicit forces:
// per substep their coefficients are capped at kCohesionStiffness/Δt² (Σ over a neighbourhood
// makes them ~40 times stiffer than one spring; κ Δt² = 0.083 exploded, 0.028 held) and
// kAdhesionStiffness/Δt², and the automatic substep count keeps Δt within both caps.
// Ĉ = Akinci's cohesion spline scaled to a peak of 1 (at r = h/2; -1 at r = 0), n_i the surface
// normal h Σ_j V ∇_i W_ij (dimensionless, pointing into the fluid; V, not Akinci's m_j/ρ_j, see
// SurfaceNormalOp) and K_ij at most 2. Adhesion pulls a particle within h of
// a wall or collider towards it: a_i = -β h ψ(d/h) n_b, n_b the boundary's normal into the
// fluid at distance d. Approximation: Akinci's adhesion kernel summed over boundary particles is
// replaced by ψ(t) = 1 - t on the continuum boundary of collide.h (strongest in contact).
#pragma once
#include "collide.h"
#include "grid.h"
#include "sph.h"

namespace pbf {

// The material slot of particle i (0 where the solver keeps none).
PBF_HD uint32_t material_of(const StepContext& ctx, uint32_t i) {
    return kMaterialsBuilt && ctx.materials ? ctx.materials[i] : 0u;
}

// Whether some material's rest density differs from slot 0's.
PBF_HD bool multiphase(const WorldConstants& s) { return kMaterialsBuilt && (s.materials.flags & kMaterialMultiphase); }

// w_i = ρ0_slot0 / ρ0_i in a multiphase world, else exactly 1.
PBF_HD float inverse_mass(const WorldConstants& s, const StepContext& ctx, uint32_t i) {
    return multiphase(s) ? s.materials.inv_mass[material_of(ctx, i)] : 1.0f;
}

// What the hot passes read of the world's colliders and materials. A pass is compiled twice:
// Features<false> reads them from the step, Features<true> is the pass for a world that has
// neither (no collider this step, every particle of the default material, no material forces),
// whose answers are constants, so that the colliders' walks and the materials' loads and
// branches are not in its kernel at all (a feature that is off costs no register either).
template <bool kPlain>
struct Features;
template <>
struct Features<false> {
    PBF_HD static const ColliderView& colliders(const StepContext& ctx) { return ctx.colliders; }
    PBF_HD static uint32_t material(const StepContext& ctx, uint32_t i) { return material_of(ctx, i); }
    PBF_HD static float inv_mass(const WorldConstants& s, const StepContext& ctx, uint32_t i) {
        return inverse_mass(s, ctx, i);
    }
    PBF_HD static bool multiphase(const WorldConstants& s) { return pbf::multiphase(s); }
};
template <>
struct Features<true> {
    PBF_HD static ColliderView colliders(const StepContext&) { return ColliderView{}; }
    PBF_HD static uint32_t material(const StepContext&, uint32_t) { return 0u; }
    PBF_HD static float inv_mass(const WorldConstants&, const StepContext&, uint32_t) { return 1.0f; }
    PBF_HD static bool multiphase(const WorldConstants&) { return false; }
};

// A collider view whose recorded impulses use particle i's mass (m_i = m0 / w_i).
PBF_HD ColliderView colliders_for_mass(const ColliderView& cv, float inverse_mass) {
    ColliderView v = cv;
    v.impulse_scale = cv.impulse_scale / inverse_mass;
    return v;
}

// Slot m's XSPH factor and LDC K this substep (slot 0's are the context's own).
PBF_HD float material_xsph_c(const StepContext& ctx, uint32_t m) {
    return m == 0 ? ctx.xsph_c : ctx.material_xsph_c[m];
}
PBF_HD float material_ldc_k(const StepContext& ctx, uint32_t m) { return m == 0 ? ctx.ldc_k : ctx.material_ldc_k[m]; }

// Whether any material smooths velocities this substep (the XSPH pass runs).
PBF_HD bool any_viscosity(const StepContext& ctx) {
    for (uint32_t k = 0; k < kMaxMaterials; ++k)
        if (material_xsph_c(ctx, k) > 0.0f) return true;
    return false;
}

// Akinci et al. 2013's cohesion spline C(r) scaled by 2πh³ (peak 1 at r = h/2, -1 at r = 0).
PBF_HD float cohesion_spline(float r, float h) {
    if (r >= h || r <= 0.0f) return 0.0f;
    const float inv_h = 1.0f / h;
    const float a = (h - r) * inv_h, b = r * inv_h;
    const float p = a * a * a * b * b * b;
    return 64.0f * (2.0f * r > h ? p : 2.0f * p - 1.0f / 64.0f);
}

// Stability caps of the explicit surface forces per substep (coefficient · Δt²), and the
// substeps per second that keep every material's coefficients within them.
constexpr float kCohesionStiffness = 0.025f;
constexpr float kAdhesionStiffness = 0.5f;
PBF_HD float surface_substep_rate(const MaterialConstants& m) {
    float rate2 = 0.0f;
    for (uint32_t k = 0; k < kMaxMaterials; ++k) {
        rate2 = fmaxf(rate2, (m.surface_tension[k] + m.cohesion[k]) / kCohesionStiffness);
        rate2 = fmaxf(rate2, m.adhesion[k] / kAdhesionStiffness);
    }
    return sqrtf(rate2);
}

// One neighbour's part of a surface normal, from ∇_i W_ij. ∇_i W points from i toward j: at a
// surface n points into the fluid, as Akinci's normal does (the opposite sign, tried first, pumped
// energy into a relaxing cube: 3 m/s at σ = 50). Each neighbour counts at the rest volume V, not
// m_j/ρ_j: a stray particle of tiny ρ_j would otherwise get a huge normal and force.
PBF_HD Vec3 surface_normal_term(const WorldConstants& s, Vec3 grad_w) { return grad_w * (s.mass * s.inv_rest_density); }

// Pass 1 (only with kMaterialSurface, when the last substep's VorticityForcePass did not already
// sum the normals at these positions): the surface normal of each particle (into the fluid) from
// the neighbours of its own material.
struct SurfaceNormalOp {
    WorldConstants s;
    StepContext ctx;
    const uint32_t* cell_begin;
    NeighborMasks masks;
    const Vec4* positions;
    Vec4* normals;
    PBF_HD void operator()(uint32_t i) const {
        const uint32_t m = material_of(ctx, i);
        const Vec3 xi = xyz(positions[i]);
        Vec3 n{0.0f, 0.0f, 0.0f};
        if (s.materials.surface_tension[m] > 0.0f) {
            for_each_neighbor_of(s.grid, cell_begin, masks, i, xi, [&](uint32_t j) {
                if (j == i || material_of(ctx, j) != m) return;
                const Vec4 pj = positions[j];
                const Vec3 d = xi - xyz(pj);
                const float r2 = length_sq(d);
                if (r2 >= s.h2) return;
                n += surface_normal_term(s, spiky_gradient_r2(d, r2, s.h, s.spiky_coef));
            });
        }
        normals[i] = make_vec4(n * s.h, 0.0f);
    }
};

// Adhesion's falloff with the distance to a boundary, t = d/h: 1 in contact, 0 at h.
PBF_HD float adhesion_falloff(float t) { return t >= 1.0f ? 0.0f : 1.0f - fmaxf(t, 0.0f); }

// -Σ ψ(d/h) n over the walls and the colliders (at the substep's start poses) within h of p.
PBF_HD Vec3 adhesion_pull(const WorldConstants& s, const ColliderView& cv, Vec3 p) {
    Vec3 a{0.0f, 0.0f, 0.0f};
    const Vec3 lo = p - s.boundary_min, hi = s.boundary_max - p;
    const float inv_h = 1.0f / s.h;
    a.x += adhesion_falloff(hi.x * inv_h) - adhesion_falloff(lo.x * inv_h);
    a.y += adhesion_falloff(hi.y * inv_h) - adhesion_falloff(lo.y * inv_h);
    a.z += adhesion_falloff(hi.z * inv_h) - adhesion_falloff(lo.z * inv_h);
    for_each_collider_near(cv, p, s.h, [&](uint32_t k) {
        Vec3 n;
        const float d = collider_distance(cv.shapes[k], cv.prev[k], p, n, cv.meshes);
        if (d < s.h) a -= n * adhesion_falloff(d * inv_h);
    });
    return a;
}

// Pass 2: v_i += Δt (cohesion + curvature + adhesion), in place (no thread reads another's
// velocity). Particles of a material without any of them are left alone.
struct SurfaceForceOp {
    WorldConstants s;
    StepContext ctx;
    const uint32_t* cell_begin;
    NeighborMasks masks;
    const Vec4* positions;
    const Vec4* normals;
    Vec4* velocities;
    PBF_HD void operator()(uint32_t i) const {
        const uint32_t m = material_of(ctx, i);
        float sigma = s.materials.surface_tension[m], kappa = s.materials.cohesion[m];
        if (sigma <= 0.0f && kappa <= 0.0f && s.materials.adhesion[m] <= 0.0f) return;
        // The stability caps (a substep too long for the coefficients: fixed substeps).
        const float inv_dt2 = ctx.inv_dt * ctx.inv_dt;
        const float attraction = fminf(sigma + kappa, kCohesionStiffness * inv_dt2);
        const float scale = sigma + kappa > 0.0f ? attraction / (sigma + kappa) : 0.0f;
        sigma *= scale;
        const float beta = fminf(s.materials.adhesion[m], kAdhesionStiffness * inv_dt2);
        const Vec4 pi = positions[i];
        const Vec3 xi = xyz(pi), ni = xyz(normals[i]);
        Vec3 a{0.0f, 0.0f, 0.0f};
        if (attraction > 0.0f) {
            for_each_neighbor_of(s.grid, cell_begin, masks, i, xi, [&](uint32_t j) {
                if (j == i || material_of(ctx, j) != m) return;
                const Vec4 pj = positions[j];
                const Vec3 d = xi - xyz(pj);
                const float r2 = length_sq(d);
                if (r2 >= s.h2 || r2 <= 1e-20f) return;
                const float inv_r = inv_sqrt(r2);
                // Akinci's K_ij = 2ρ0/(ρ_i + ρ_j) makes up for the missing neighbours of surface
                // particles; capped at 2 so that stray particles are not pulled harder still.
                const float k_ij = 2.0f / fmaxf(pi.w + pj.w, 1.0f);
                const Vec3 cohesion = d * (attraction * cohesion_spline(r2 * inv_r, s.h) * inv_r);
                a -= (cohesion + (ni - xyz(normals[j])) * (0.25f * sigma)) * k_ij;
            });
        }
        if (beta > 0.0f) a += adhesion_pull(s, ctx.colliders, xi) * beta;
        const Vec4 v = velocities[i];
        velocities[i] = make_vec4(xyz(v) + a * (s.h * ctx.dt), v.w);
    }
};

// ---- boundary viscosity ------------------------------------------------------------------------
// XSPH couples fluid velocities only, so every wall was free-slip: a viscous column slid on its
// base and slumped by extensional flow (viscosity 0.9: spread 0.75 m in 0.5 s against water's
// 0.99 m). Walls and colliders therefore join the smoothing as one more neighbour that moves with
// the boundary, as boundary particles do in Akinci et al. 2012's boundary friction: particle i
// gets c Σ_b V_b W_ib (v_b - v_i), with the same factor c as its fluid neighbours (the
// material's, per substep: the same physical viscosity at any substep count). Approximation:
// Σ_b V_b W_ib over the solid is the boundary's density share γΦ(d/h) of collide.h (a flat
// half-space filled at rest density, walls combined at edges and corners), and a collider moves
// as one body over the substep (v_b: the motion of the surface point at p from the substep's
// start pose to its end pose). An explicit smoothing, it is capped so that particle i at most
// takes its whole neighbourhood's mean velocity (c Σ_j V_j W_ij + c_b Σ_b V_b W_ib ≤ 1), never
// overshoots it. A dynamic collider receives the opposite of the impulse it gives.

// Where the surface point of a collider at p (end pose cur) was at the substep's start (prev).
PBF_HD Vec3 point_at_start(const ColliderPose& prev, const ColliderPose& cur, Vec3 p) {
    return prev.position + mul(prev.rotation, mul_transpose(cur.rotation, p - cur.position));
}

// c: the particle's XSPH factor this substep; fluid_weight: c Σ_j V_j W_ij of its fluid
// neighbours. Returns the velocity change the boundary gives particle i at p with velocity v.
PBF_HD Vec3 boundary_viscosity(const WorldConstants& s, const ColliderView& cv, float inv_dt, float c,
                               float fluid_weight, Vec3 p, Vec3 v) {
    // One walk over the colliders sums what boundary_at would (Σ_b V_b W_ib) and the share-weighted
    // boundary velocity; the walls stand still. A dynamic collider's part of the change, as the
    // displacement it would have made in the substep, is recorded in the same walk at the
    // uncapped factor c, and corrected by a second walk in the rare case that the cap below cuts it.
    const bool react = cv.impulses && cv.dynamic_count > 0;
    float share = walls_boundary(s, p).density_ratio;
    Vec3 moving{0.0f, 0.0f, 0.0f};
    auto walk = [&](float factor, bool sum) {
        for_each_collider_near(cv, p, s.h, [&](uint32_t k) {
            const Collider& col = cv.shapes[k];
            const bool dynamic = react && (col.flags & kColliderDynamic);
            if (!sum && !dynamic) return;
            Vec3 n;
            const float d = collider_distance(col, cv.cur[k], p, n, cv.meshes);
            if (d >= s.h) return;
            const float ck = collider_boundary(s, col, cv.cur[k], p, d, n, cv.meshes).density_ratio;
            const Vec3 vb = (p - point_at_start(cv.prev[k], cv.cur[k], p)) * inv_dt;
            if (sum) {
                share += ck;
                moving += vb * ck;
            }
            if (dynamic) record_push(cv, col, cv.cur[k], p, (vb - v) * (factor * ck / inv_dt));
        });
    };
    walk(c, true);
    if (share <= 0.0f) return Vec3{0.0f, 0.0f, 0.0f};
    const float cb = fminf(c, fmaxf(1.0f - fluid_weight, 0.0f) / share);
    if (react && cb < c) walk(cb - c, false);
    return (moving - v * share) * cb;
}

// The sort's gather puts the materials in a scratch buffer; this brings them home.
struct CopyMaterialsOp {
    const uint8_t* from;
    uint8_t* to;
    PBF_HD void operator()(uint32_t i) const { to[i] = from[i]; }
};

}  // namespace pbf
