// Diffuse particles (spray, foam, air bubbles), written once for both backends, after Ihmsen,
// Akinci, Gissler & Teschner 2012, "Unified spray, foam and air bubbles for particle-based
// fluids" (The Visual Computer 28). At the end of a step, from the neighbour data the step
// leaves behind: fluid particles get a surface normal, then a number of new diffuse particles
// from their trapped-air, wave-crest and kinetic-energy potentials; the diffuse particles already
// there are moved by their kind and age; one scan then packs the survivors and the new ones into
// the other buffer. Only in worlds created with a diffuse capacity (DiffuseConstants::capacity).
#pragma once
#include "collide.h"
#include "grid.h"

namespace pbf {

// Kinds, stored as a float in the position's w (the public PBF_DIFFUSE_* values).
constexpr float kDiffuseSpray = 0.0f, kDiffuseFoam = 1.0f, kDiffuseBubble = 2.0f;
// At most this many new diffuse particles per fluid particle and step: keeps the scan's sum
// within 32 bits (2^30 fluid particles x 3 + 2^26 diffuse < 2^32).
constexpr uint32_t kMaxDiffusePerParticle = 3;

// Ihmsen et al.'s constants in this solver's units, translated by the step plan
// (solver/step_plan.cpp, diffuse_constants). capacity 0: no buffers and no pass.
struct DiffuseConstants {
    uint32_t capacity = 0;
    float trapped_air_min = 0.0f, trapped_air_max = 1.0f;   // τ_ta (m/s, weighted sum)
    float wave_crest_min = 0.0f, wave_crest_max = 1.0f;     // τ_wc (weighted sum)
    float energy_min = 0.0f, energy_max = 1.0f;             // τ_k (J/kg: ½|v|²)
    float trapped_air_rate = 0.0f, wave_crest_rate = 0.0f;  // k_ta, k_wc (particles per second)
    float lifetime = 1.0f;                                  // s
    uint32_t spray_max_neighbors = 0;                       // fewer fluid neighbours: spray
    uint32_t bubble_min_neighbors = 0;                      // more: bubble; between: foam
    float buoyancy = 0.0f;                                  // k_b: a bubble accelerates by -k_b g
    float bubble_drag = 0.0f;                               // k_d (1/s): a bubble's velocity relaxes toward the fluid's
    float spray_drag = 0.0f;                                // 1/s: air drag on spray
};

// Ihmsen's clamping Φ(I, τmin, τmax) = (min(I, τmax) - min(I, τmin)) / (τmax - τmin): 0..1.
PBF_HD float diffuse_clamp(float value, float lo, float hi) {
    return (fminf(value, hi) - fminf(value, lo)) / (hi - lo);
}

// Ihmsen's radially symmetric weight W(r) = 1 - r/h within h.
PBF_HD float diffuse_weight(float r2, float h2, float inv_h) { return r2 < h2 ? 1.0f - sqrtf(r2) * inv_h : 0.0f; }

// A well-mixed 32-bit hash (Wellons' lowbias32) and a uniform number in [0, 1) from three keys:
// the same keys give the same number on both backends, so generation is deterministic.
PBF_HD uint32_t diffuse_hash(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}
PBF_HD float diffuse_random(uint32_t a, uint32_t b, uint32_t c) {
    return float(diffuse_hash(a ^ diffuse_hash(b ^ diffuse_hash(c))) >> 8) * (1.0f / 16777216.0f);
}

// The kind a diffuse particle with n fluid neighbours within h is (Ihmsen Sec. 5).
PBF_HD float diffuse_kind(uint32_t n, const DiffuseConstants& d) {
    return n < d.spray_max_neighbors ? kDiffuseSpray : n > d.bubble_min_neighbors ? kDiffuseBubble : kDiffuseFoam;
}

// Per fluid particle: the surface normal, n_i = Σ_j (x_i - x_j) W(r_ij) / (h Σ_j W(r_ij)), the
// normalised offset of the particle from its neighbourhood's weighted centre: about 0 inside an
// even fluid, about 0.2 along the outward normal at a flat surface. Written to normals[i]
// (xyz: the unit normal, w: its length before normalising).
struct DiffuseNormalOp {
    GridDims grid;
    float h2, inv_h;
    const uint32_t* cell_begin;
    NeighborMasks masks;
    const Vec4* positions;
    const uint32_t* count;
    Vec4* normals;
    PBF_HD void operator()(uint32_t i) const {
        if (i >= *count) return;
        const Vec3 xi = xyz(positions[i]);
        Vec3 offset{0.0f, 0.0f, 0.0f};
        float wsum = 0.0f;
        for_each_neighbor_of(grid, cell_begin, masks, i, xi, [&](uint32_t j) {
            const Vec3 d = xi - xyz(positions[j]);
            const float w = diffuse_weight(length_sq(d), h2, inv_h);
            offset += d * w;
            wsum += w;  // itself included (w = 1): wsum >= 1
        });
        const Vec3 n = offset * (inv_h / fmaxf(wsum, 1.0f));
        const float len = length(n);
        normals[i] = make_vec4(len > 1e-6f ? n * (1.0f / len) : Vec3{0.0f, 0.0f, 0.0f}, len);
    }
};

// Per fluid particle: how many diffuse particles it generates this step (Ihmsen Sec. 4),
// n_d = Φ(E_k) (k_ta Φ(I_ta) + k_wc Φ(I_wc)) Δt with the step's Δt, so the count per second does
// not depend on the substeps; the fraction becomes one more with its probability. Writes the
// count (0 past the live count) to generated[i].
// - trapped air: I_ta = Σ_j |v_ij| (1 - v̂_ij · x̂_ij) W(r_ij), fluid meeting at speed;
// - wave crests: I_wc = Σ_j (1 - n̂_i · n̂_j) W(r_ij) over neighbours behind the surface
//   (x̂_ji · n̂_i < 0), for surface particles moving along their normal (v̂_i · n̂_i >= 0.6);
//   a particle is a surface particle when its normal's length exceeds kSurface (interior
//   particles' normals are noise and would make every fast interior particle a crest);
// - kinetic energy per unit mass E_k = ½|v_i|² (Ihmsen's ½ m v² divided by m, so τ_k does not
//   depend on the particle size).
struct DiffuseSourceOp {
    static constexpr float kSurface = 0.05f;
    GridDims grid;
    float h2, inv_h, dt;
    DiffuseConstants d;
    const uint32_t* cell_begin;
    NeighborMasks masks;
    const Vec4* positions;
    const Vec4* velocities;
    const Vec4* normals;
    const uint32_t* ids;
    uint32_t step;
    const uint32_t* count;
    uint32_t* generated;
    PBF_HD void operator()(uint32_t i) const {
        if (i >= *count) {
            generated[i] = 0u;
            return;
        }
        const Vec3 vi = xyz(velocities[i]);
        const float energy = diffuse_clamp(0.5f * length_sq(vi), d.energy_min, d.energy_max);
        if (energy <= 0.0f) {  // too slow: no potential matters
            generated[i] = 0u;
            return;
        }
        const Vec3 xi = xyz(positions[i]);
        const Vec4 ni4 = normals[i];
        const Vec3 ni = xyz(ni4);
        const bool surface = ni4.w > kSurface;
        const float speed = length(vi);
        // Crests only where the particle moves along its normal: the curvature sum is skipped elsewhere.
        const bool crest = surface && dot(vi, ni) >= 0.6f * speed && d.wave_crest_rate > 0.0f;
        float trapped = 0.0f, curvature = 0.0f;
        for_each_neighbor_of(grid, cell_begin, masks, i, xi, [&](uint32_t j) {
            if (j == i) return;
            const Vec3 xij = xi - xyz(positions[j]);
            const float r2 = length_sq(xij);
            const float w = diffuse_weight(r2, h2, inv_h);
            if (w <= 0.0f) return;
            const Vec3 vij = vi - xyz(velocities[j]);
            const float v2 = length_sq(vij);
            if (v2 > 0.0f && r2 > 0.0f) trapped += sqrtf(v2) * (1.0f - dot(vij, xij) * inv_sqrt(v2 * r2)) * w;
            // x_ji · n_i < 0 is x_ij · n_i > 0: j lies behind i's surface.
            if (crest && dot(xij, ni) > 0.0f && normals[j].w > kSurface)
                curvature += (1.0f - dot(ni, xyz(normals[j]))) * w;
        });
        const float rate =
            d.trapped_air_rate * diffuse_clamp(trapped, d.trapped_air_min, d.trapped_air_max) +
            (crest ? d.wave_crest_rate * diffuse_clamp(curvature, d.wave_crest_min, d.wave_crest_max) : 0.0f);
        const float expected = fminf(energy * rate * dt, float(kMaxDiffusePerParticle));
        const float whole = floorf(expected);
        const uint32_t extra = diffuse_random(ids[i], step, 0xD1FFu) < expected - whole ? 1u : 0u;
        generated[i] =
            uint32_t(whole) + extra <= kMaxDiffusePerParticle ? uint32_t(whole) + extra : kMaxDiffusePerParticle;
    }
};

// The fluid around a point: its neighbours within h and their W-weighted mean velocity.
struct FluidSample {
    uint32_t neighbors;
    Vec3 velocity;
};
// The fluid at the end of a step, sampled through its grid (any point, not only particles).
struct FluidSampler {
    GridDims grid;
    float h2, inv_h;
    const uint32_t* cell_begin;
    const Vec4* positions;
    const Vec4* velocities;
    PBF_HD FluidSample at(Vec3 x) const {
        FluidSample f{0u, Vec3{0.0f, 0.0f, 0.0f}};
        float wsum = 0.0f;
        for_each_neighbor(grid, cell_begin, x, [&](uint32_t j) {
            const float w = diffuse_weight(length_sq(x - xyz(positions[j])), h2, inv_h);
            if (w <= 0.0f) return;
            ++f.neighbors;
            f.velocity += xyz(velocities[j]) * w;
            wsum += w;
        });
        if (wsum > 0.0f) f.velocity = f.velocity * (1.0f / wsum);
        return f;
    }
};

// Per diffuse slot i < *diffuse_count: moves the particle by its kind (Ihmsen Sec. 5), from its
// fluid neighbours at the step's end, over the step's Δt:
// - spray (< spray_max_neighbors): ballistic, v ← (v + g Δt) / (1 + c Δt) (gravity and linear
//   air drag c, implicit so any Δt is stable);
// - foam: carried by the fluid, v = ṽ_f (the neighbours' W-weighted mean velocity);
// - bubble (> bubble_min_neighbors): v += -k_b g Δt, then v relaxes toward ṽ_f by
//   1 - exp(-k_d Δt) (Ihmsen's k_d is a fraction per step; a rate keeps it step-independent);
// then x += v Δt, collided with the colliders and walls like a fluid particle. Foam and spray
// age by Δt (bubbles inside the fluid do not; one that surfaces is foam and ages), and a
// particle whose remaining lifetime runs out is dropped: keep[i] = 1 for survivors.
// Storage: position (x, y, z, kind), velocity (vx, vy, vz, remaining lifetime in s).
struct DiffuseAdvectOp {
    WorldConstants s;
    ColliderView colliders;
    FluidSampler fluid;
    float dt;
    DiffuseConstants d;
    const uint32_t* diffuse_count;
    Vec4* positions;
    Vec4* velocities;
    uint32_t* keep;
    PBF_HD void operator()(uint32_t i) const {
        if (i >= *diffuse_count) {
            keep[i] = 0u;
            return;
        }
        const Vec3 x = xyz(positions[i]);
        Vec3 v = xyz(velocities[i]);
        float life = velocities[i].w;
        const FluidSample f = fluid.at(x);
        const float kind = diffuse_kind(f.neighbors, d);
        if (kind == kDiffuseSpray) {
            v = (v + s.gravity * dt) * (1.0f / (1.0f + d.spray_drag * dt));
        } else if (kind == kDiffuseFoam) {
            v = f.velocity;
        } else {
            v += s.gravity * (-d.buoyancy * dt);
            v += (f.velocity - v) * (1.0f - expf(-d.bubble_drag * dt));
        }
        if (kind != kDiffuseBubble) life -= dt;
        const Vec3 moved = collide(s, colliders, x + v * dt, x);
        const bool alive = life > 0.0f && moved.x == moved.x && moved.y == moved.y && moved.z == moved.z;
        positions[i] = make_vec4(moved, kind);
        velocities[i] = make_vec4(v, life);
        keep[i] = alive ? 1u : 0u;
    }
};

// Over D + n slots after the exclusive scan of [keep (D) | generated (n)]: survivor i moves to
// offset[i]; fluid particle j's k-th new diffuse particle goes to offset[D + j] + k while that is
// below D (the rest are dropped for capacity). A new particle starts in a cylinder around the
// fluid particle's velocity (Ihmsen Sec. 4: radius r, length |v| Δt; kept out of colliders and
// inside the walls as the fluid particle moved there), with the fluid particle's velocity (not
// Ihmsen's velocity plus the radial offset, whose units are a length), the kind its
// neighbourhood gives and a lifetime of (0.5..1) x lifetime.
struct DiffuseScatterOp {
    WorldConstants s;
    ColliderView colliders;
    FluidSampler fluid;
    float dt;
    DiffuseConstants d;
    const uint32_t* ids;
    uint32_t step;
    const uint32_t* flags;   // keep | generated
    const uint32_t* offset;  // their exclusive scan
    const Vec4* src_positions;
    const Vec4* src_velocities;
    Vec4* dst_positions;
    Vec4* dst_velocities;
    PBF_HD void operator()(uint32_t i) const {
        const uint32_t n = flags[i];
        if (n == 0u) return;
        const uint32_t base = offset[i];
        if (i < d.capacity) {
            dst_positions[base] = src_positions[i];
            dst_velocities[base] = src_velocities[i];
            return;
        }
        const uint32_t j = i - d.capacity;
        const Vec3 xj = xyz(fluid.positions[j]), vj = xyz(fluid.velocities[j]);
        const float speed = length(vj);
        const Vec3 axis = speed > 1e-6f ? vj * (1.0f / speed) : Vec3{0.0f, 1.0f, 0.0f};
        const Vec3 helper = fabsf(axis.y) < 0.9f ? Vec3{0.0f, 1.0f, 0.0f} : Vec3{1.0f, 0.0f, 0.0f};
        const Vec3 e1 = cross(axis, helper) * inv_sqrt(length_sq(cross(axis, helper)));
        const Vec3 e2 = cross(axis, e1);
        for (uint32_t k = 0; k < n && base + k < d.capacity; ++k) {
            const uint32_t key = ids[j] * 4u + k;
            const float r = s.radius * sqrtf(diffuse_random(key, step, 1u));
            const float angle = 6.2831853f * diffuse_random(key, step, 2u);
            const float along = speed * dt * diffuse_random(key, step, 3u);
            const Vec3 x =
                collide(s, colliders, xj + e1 * (r * cosf(angle)) + e2 * (r * sinf(angle)) + axis * along, xj);
            const FluidSample f = fluid.at(x);
            const float life = d.lifetime * (0.5f + 0.5f * diffuse_random(key, step, 4u));
            dst_positions[base + k] = make_vec4(x, diffuse_kind(f.neighbors, d));
            dst_velocities[base + k] = make_vec4(vj, life);
        }
    }
};

// Counters of the diffuse particles, in backend memory.
struct DiffuseCounters {
    uint32_t count;         // live diffuse particles in slots [0, count)
    uint32_t dropped_step;  // generated in the last step but over capacity
    unsigned long long generated_total;
    unsigned long long dropped_total;
};

// One thread after the scatter: the new count from the scan's total (slots of length n).
struct DiffuseCommitOp {
    DiffuseCounters* c;
    const uint32_t* flags;
    const uint32_t* offset;
    uint32_t n;  // scanned slots: capacity + fluid launch size
    uint32_t capacity;
    PBF_HD void operator()(uint32_t) const {
        const uint32_t total = offset[n - 1] + flags[n - 1];
        const uint32_t survivors = n > capacity ? offset[capacity] : total;
        const uint32_t kept = total < capacity ? total : capacity;
        c->count = kept;
        c->generated_total += kept - survivors;
        c->dropped_step = total - kept;
        c->dropped_total += total - kept;
    }
};

}  // namespace pbf
