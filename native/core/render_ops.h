// Render data, written once for both backends: smoothed positions and anisotropy after Yu & Turk
// 2013 ("Reconstructing surfaces of particle-based fluids using anisotropic kernels", ACM TOG
// 32(1)), from the neighbour grid the step leaves behind. One pass per step, only when a world
// asks for it (RenderConstants::flags).
#pragma once
#include "grid.h"

namespace pbf {

// What the world computes (PBF_RENDER_* of the C API) and Yu & Turk's constants, translated to
// this solver's units by the step plan (solver/step_plan.cpp, render_constants).
constexpr uint32_t kRenderSmoothed = 0x1u;
constexpr uint32_t kRenderAnisotropy = 0x2u;
struct RenderConstants {
    uint32_t flags = 0;                // kRender*; 0: no buffers, no pass
    uint32_t min_neighbors = 0;        // N_ε: fewer neighbours (itself included) keep a particle round
    float smoothing = 0.0f;            // λ: x̄ = (1 - λ) x + λ x_w (the weighted mean)
    float max_stretch = 1.0f;          // k_r: no radius below the longest / k_r
    float radius_per_variance = 0.0f;  // radius (m) per eigenvalue of the covariance (m²): k_s r / σ_rest
    float isolated_radius = 0.0f;      // k_n r (m): the radius of a particle with few neighbours
};

// A symmetric 3x3 matrix, row-major in a[3][3] (both triangles kept).
struct Sym3 {
    float a[3][3];
};

// One Jacobi rotation zeroing a[P][Q] (R is the third index); v accumulates the rotations, its
// columns become the eigenvectors. Indices are template arguments so the arrays stay in
// registers on the GPU.
template <int P, int Q, int R>
PBF_HD void jacobi_rotate(Sym3& m, Sym3& v) {
    float(&a)[3][3] = m.a;
    const float apq = a[P][Q];
    if (fabsf(apq) <= 1e-7f * (fabsf(a[P][P]) + fabsf(a[Q][Q])) + 1e-30f) {
        a[P][Q] = a[Q][P] = 0.0f;
        return;
    }
    // tan of the rotation angle: the smaller root of t² + 2θt - 1 = 0 (Golub & Van Loan 8.4).
    const float theta = (a[Q][Q] - a[P][P]) / (2.0f * apq);
    const float t = (theta >= 0.0f ? 1.0f : -1.0f) / (fabsf(theta) + sqrtf(theta * theta + 1.0f));
    const float c = 1.0f / sqrtf(t * t + 1.0f), s = t * c;
    a[P][P] -= t * apq;
    a[Q][Q] += t * apq;
    a[P][Q] = a[Q][P] = 0.0f;
    const float arp = a[R][P], arq = a[R][Q];
    a[R][P] = a[P][R] = c * arp - s * arq;
    a[R][Q] = a[Q][R] = s * arp + c * arq;
    for (int k = 0; k < 3; ++k) {
        const float vkp = v.a[k][P], vkq = v.a[k][Q];
        v.a[k][P] = c * vkp - s * vkq;
        v.a[k][Q] = s * vkp + c * vkq;
    }
}

// Eigenvalues (descending) and unit eigenvectors of a symmetric 3x3 matrix by cyclic Jacobi
// sweeps: at most 8, stopping once the off-diagonal part is below float precision of the
// diagonal (3x3 matrices converge in 3 to 5). Runs on host and device alike.
PBF_HD void symmetric_eigen(Sym3 m, float value[3], Vec3 axis[3]) {
    Sym3 v{{{1.0f, 0.0f, 0.0f}, {0.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 1.0f}}};
    for (int sweep = 0; sweep < 8; ++sweep) {
        const float off = m.a[0][1] * m.a[0][1] + m.a[0][2] * m.a[0][2] + m.a[1][2] * m.a[1][2];
        const float diag = m.a[0][0] * m.a[0][0] + m.a[1][1] * m.a[1][1] + m.a[2][2] * m.a[2][2];
        if (off <= 1e-14f * diag || off <= 1e-36f) break;
        jacobi_rotate<0, 1, 2>(m, v);
        jacobi_rotate<0, 2, 1>(m, v);
        jacobi_rotate<1, 2, 0>(m, v);
    }
    float d[3] = {m.a[0][0], m.a[1][1], m.a[2][2]};
    Vec3 e[3] = {Vec3{v.a[0][0], v.a[1][0], v.a[2][0]}, Vec3{v.a[0][1], v.a[1][1], v.a[2][1]},
                 Vec3{v.a[0][2], v.a[1][2], v.a[2][2]}};
    // Sort descending (three compare-swaps, fixed indices).
    auto order = [&](int p, int q) {
        if (d[p] >= d[q]) return;
        const float td = d[p];
        d[p] = d[q];
        d[q] = td;
        const Vec3 te = e[p];
        e[p] = e[q];
        e[q] = te;
    };
    order(0, 1);
    order(1, 2);
    order(0, 1);
    for (int k = 0; k < 3; ++k) {
        value[k] = d[k];
        axis[k] = e[k];
    }
}

// Yu & Turk's isotropic weight w(r) = 1 - (r/h)³ within h (Eq. 11 with r_i = h: the step's
// neighbour radius, not their 2h; the step has no wider neighbour list).
PBF_HD float render_weight(float r2, float h2) {
    if (r2 >= h2) return 0.0f;
    const float q2 = r2 / h2;
    return 1.0f - q2 * sqrtf(q2);
}

// Per particle: the weighted mean x_w and covariance C of its neighbours (Yu & Turk Eq. 6-7),
// then smoothed[i] = x + λ (x_w - x) (Eq. 5, w = the position's ρ/ρ0) and anisotropy[3i..3i+2]
// = the principal axes of C, longest first, as (unit axis, radius in m). The eigenvalues are
// clamped so that none is below the largest / k_r (Eq. 15); a particle with fewer than N_ε
// neighbours is a sphere of radius k_n r. Radii are linear in the eigenvalues, as in Yu &
// Turk's G; k_s is expressed relative to a rest lattice (see RenderConstants).
// Neighbours: the last substep's recorded masks (or the grid when none), with the distance test
// at the final positions: a particle that moved into range during the substep's iterations is
// missed, as in the step's own passes.
struct RenderDataOp {
    GridDims grid;
    float h2;
    RenderConstants r;
    const uint32_t* cell_begin;
    NeighborMasks masks;
    const Vec4* positions;
    Vec4* smoothed;    // null: not computed
    Vec4* anisotropy;  // 3 per particle; null: not computed
    PBF_HD void operator()(uint32_t i) const {
        const Vec4 pi = positions[i];
        const Vec3 xi = xyz(pi);
        // Offsets from x_i keep the float sums small (|d| < h) wherever the fluid is.
        float wsum = 0.0f, cxx = 0.0f, cxy = 0.0f, cxz = 0.0f, cyy = 0.0f, cyz = 0.0f, czz = 0.0f;
        Vec3 dsum{0.0f, 0.0f, 0.0f};
        uint32_t n = 0;
        for_each_neighbor_of(grid, cell_begin, masks, i, xi, [&](uint32_t j) {
            const Vec3 d = xyz(positions[j]) - xi;
            const float r2 = length_sq(d);
            if (r2 >= h2) return;
            const float w = render_weight(r2, h2);
            ++n;
            wsum += w;
            dsum += d * w;
            cxx += w * d.x * d.x;
            cxy += w * d.x * d.y;
            cxz += w * d.x * d.z;
            cyy += w * d.y * d.y;
            cyz += w * d.y * d.z;
            czz += w * d.z * d.z;
        });
        // Itself is always a neighbour (w = 1), so wsum >= 1 for a live particle.
        const float inv_w = wsum > 0.0f ? 1.0f / wsum : 0.0f;
        const Vec3 mean = dsum * inv_w;
        if (smoothed) smoothed[i] = make_vec4(xi + mean * r.smoothing, pi.w);
        if (!anisotropy) return;
        Sym3 c{{{cxx * inv_w - mean.x * mean.x, cxy * inv_w - mean.x * mean.y, cxz * inv_w - mean.x * mean.z},
                {0.0f, cyy * inv_w - mean.y * mean.y, cyz * inv_w - mean.y * mean.z},
                {0.0f, 0.0f, czz * inv_w - mean.z * mean.z}}};
        c.a[1][0] = c.a[0][1];
        c.a[2][0] = c.a[0][2];
        c.a[2][1] = c.a[1][2];
        float sigma[3];
        Vec3 axis[3];
        symmetric_eigen(c, sigma, axis);
        Vec4* out = anisotropy + size_t(i) * 3u;
        if (n < r.min_neighbors || !(sigma[0] > 1e-30f)) {
            out[0] = Vec4{1.0f, 0.0f, 0.0f, r.isolated_radius};
            out[1] = Vec4{0.0f, 1.0f, 0.0f, r.isolated_radius};
            out[2] = Vec4{0.0f, 0.0f, 1.0f, r.isolated_radius};
            return;
        }
        const float floor_sigma = sigma[0] / r.max_stretch;
        for (int k = 0; k < 3; ++k) {
            const Vec3 a = axis[k] * inv_sqrt(fmaxf(length_sq(axis[k]), 1e-24f));
            out[k] = make_vec4(a, fmaxf(sigma[k], floor_sigma) * r.radius_per_variance);
        }
    }
};

}  // namespace pbf
