// SPH smoothing kernels of Müller et al. 2003 as used by Macklin & Müller 2013 (PBF):
// poly6 for densities, the spiky gradient for constraint gradients.
#pragma once
#include "vec.h"

namespace pbf {

constexpr float kPi = 3.14159265358979323846f;

PBF_HD float poly6_coefficient(float h) { return 315.0f / (64.0f * kPi * powf(h, 9.0f)); }
// Magnitude coefficient of ∇W_spiky: ∇W = -spiky_grad_coefficient · (h - r)² · r̂.
PBF_HD float spiky_grad_coefficient(float h) { return 45.0f / (kPi * powf(h, 6.0f)); }

// W_poly6(r) from r² (avoids a square root in the hot density loop); 0 outside h.
PBF_HD float poly6(float r2, float h2, float coefficient) {
    if (r2 >= h2) return 0.0f;
    const float d = h2 - r2;
    return coefficient * d * d * d;
}

// ∇_i W_spiky(x_i - x_j) for d = x_i - x_j at squared distance r² (0 < r² < h²): points from i
// toward j (towards the neighbour), scaled by the kernel slope; one reciprocal square root
// instead of a square root and a division.
PBF_HD Vec3 spiky_gradient_r2(Vec3 d, float r2, float h, float coefficient) {
    if (r2 <= 1e-24f || r2 >= h * h) return Vec3{0.0f, 0.0f, 0.0f};
    const float inv_r = inv_sqrt(r2);
    const float t = h - r2 * inv_r;
    return d * (-coefficient * t * t * inv_r);
}

// ∇_i W_spiky for the pair (i, j) at d = x_i - x_j (r² < h²). Particles closer than 1e-3 h
// (two clamped into the same wall corner, say) have no defined direction and a zero spiky
// gradient, so nothing would ever separate them: such a pair uses the kernel's slope at r = 0
// along a direction fixed per pair (a hash of the two indices), opposite for i and j.
PBF_HD Vec3 pair_gradient(Vec3 d, float r2, float h, float coefficient, uint32_t i, uint32_t j) {
    if (r2 >= 1e-6f * h * h) return spiky_gradient_r2(d, r2, h, coefficient);
    const uint32_t lo = i < j ? i : j, hi = i < j ? j : i;
    uint32_t u = lo * 0x9E3779B1u ^ (hi + 0x7F4A7C15u) * 0x85EBCA77u;
    u ^= u >> 15;
    u *= 0x2C1B3C6Du;
    u ^= u >> 13;
    const Vec3 dir{float(u & 1023u) - 511.5f, float((u >> 10) & 1023u) - 511.5f, float((u >> 20) & 1023u) - 511.5f};
    const float sign = i < j ? 1.0f : -1.0f;
    return dir * (sign * -coefficient * h * h * inv_sqrt(length_sq(dir)));
}

// ratio^n; the default n = 4 (and any whole n) by multiplication, since powf costs a log and
// an exp per neighbour in the hottest loop.
PBF_HD float scorr_power(float ratio, float n) {
    if (n == 4.0f) {
        const float r2 = ratio * ratio;
        return r2 * r2;
    }
    if (n == floorf(n)) {
        float result = 1.0f;
        for (int k = 0; k < static_cast<int>(n); ++k) result *= ratio;
        return result;
    }
    return powf(ratio, n);
}

// s_corr's (W(r)/W(Δq))^n is at most this: with Δq near h, W(Δq) is tiny and the term reached
// 1e20 (a dam break at Δq = 0.7 h exploded; docs/physics.md). The defaults' largest value, at
// r = 0, is 1.63 (below the cap: unchanged).
constexpr float kScorrPowerCap = 2.0f;

// The slowest response s_corr's relaxation with the substep assumes (m/s; the default
// sound_speed): its time scale is h / sound_speed or h / this, whichever is longer
// (solver/step_plan.cpp, substep_context).
constexpr float kScorrResponseSpeed = 40.0f;

// s_corr's reference shape (Macklin & Müller 2013): Δq = 0.2 h, n = 4, and k = 0.1: the defaults.
constexpr float kScorrReferenceDq = 0.2f;
constexpr float kScorrReferenceN = 4.0f;
constexpr float kScorrReferenceK = 0.1f;

// s_corr's weight for a pair whose W(r)/W(Δq) is ratio: min(ratio^n, cap) less `excess`, never
// below 0, where excess is how far the weight at the rest spacing s exceeds the reference
// shape's there (0.052), so that no Δq or n pushes pairs at the rest spacing harder than the
// reference does. That push is not balanced at a free surface (inside a lattice the pushes
// cancel by symmetry): it lifts a resting surface layer a little at the reference shape, and at
// Δq near h or a small n, up to 2 k, it pushed a fresh block's surface layer off. The reference
// shape and the defaults have no excess and are unchanged.
// Computed as (cap - excess) sat(ratio^n a + b), a = 1/(cap - excess), b = -excess a, with the
// factor cap - excess in k (ScorrShape): on the GPU one multiply-add that saturates, the cost
// of the cap alone. At the defaults a = 1/2, b = 0 and the scale 2, all exact, so s_corr is bit
// for bit -k min(ratio^n, 2).
struct ScorrShape {
    float a, b;   // sat(ratio^n a + b)
    float scale;  // cap - excess, which multiplies k
};

PBF_HD float saturate(float x) {
#ifdef __CUDA_ARCH__
    return __saturatef(x);
#else
    return fminf(fmaxf(x, 0.0f), 1.0f);  // NaN -> 0, as __saturatef
#endif
}

PBF_HD float scorr_weight(float ratio, float n, float a, float b) { return saturate(scorr_power(ratio, n) * a + b); }

// The shape for a weight at the rest spacing of `at_rest` (min(ratio^n, cap) there).
inline ScorrShape scorr_shape(float at_rest, float reference_at_rest) {
    const float excess = fmaxf(at_rest - reference_at_rest, 0.0f);
    const float scale = kScorrPowerCap - excess;
    return ScorrShape{1.0f / scale, -excess / scale, scale};
}

}  // namespace pbf
