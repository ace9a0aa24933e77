// Scenes and measurements of the LDC reproduction (docs/paper/README.md), through the public C
// API only. Shared by the driver (tools/paper/pbf_paper.cpp) and the validation test
// (tests/test_validation.cpp), so the test checks exactly what the report plots.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "pbf_c_api.h"

namespace paper {

constexpr float kGravity = 9.81f;

// Two scenes of the same particle count, sized by a (metres) and na (particles across a):
// - dam:  a column a wide and 2a high (Martin & Moyce's n² = 2) at the left end of a tank
//         tank_length·a long and 2.5a high;
// - tank: a resting layer tank_width·a long (default 2a) and a deep in a tank as long and 1.5a
//         high (tank_width small: a narrow deep column).
// Both are nz particle layers deep in z between two frictionless walls.
struct SceneSpec {
    bool dam = true;
    float a = 0.4f;
    uint32_t na = 32;
    uint32_t nz = 6;
    float tank_length = 5.0f;  // dam only, in units of a
    float tank_width = 2.0f;   // tank only, in units of a
    pbf_backend backend = PBF_BACKEND_CPU;

    float spacing() const { return a / float(na); }
    float depth() const { return float(nz) * spacing(); }
    float domain_x() const { return dam ? tank_length * a : tank_width * a; }
    // Lattice columns of the fluid in x (the box is padded by a quarter spacing in emit_fluid).
    uint32_t columns_x() const { return dam ? na : uint32_t(tank_width * float(na) + 0.25f); }
    uint32_t particles() const { return columns_x() * (dam ? 2 * na : na) * nz; }
    float domain_y() const { return dam ? 2.5f * a : 1.5f * a; }
};

// Substeps per 1/60 s frame from the CFL-like rule of samples/dam_break.c: the fastest
// particle of the dam break, about sqrt(2 g · 2a), moves under 0.4 h per substep. The tank uses
// the dam's rule too (same a, na), so both scenes of one resolution share a substep count.
// Clamped to the API's 1..16 unless `clamp` is false (callers that step one substep per call).
inline uint32_t cfl_substeps(const SceneSpec& s, float frame_dt, bool clamp = true) {
    const float h = 2.0f * s.spacing();
    const float v = std::sqrt(2.0f * kGravity * 2.0f * s.a);
    const int n = std::max(1, int(std::ceil(v * frame_dt / (0.4f * h))));
    return uint32_t(clamp ? std::min(n, 16) : n);
}

inline void set3(float* d, float x, float y, float z) {
    d[0] = x;
    d[1] = y;
    d[2] = z;
}

// Fills the world desc (solver parameters left to the caller) for the scene.
inline pbf_world_desc make_desc(const SceneSpec& s) {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = s.backend;
    d.particle_radius = 0.5f * s.spacing();
    const uint32_t n = s.particles();
    d.max_particles = n + n / 16 + 256;
    set3(d.domain_min, 0.0f, 0.0f, 0.0f);
    set3(d.domain_max, s.domain_x(), s.domain_y(), s.depth());
    return d;
}

// Emits the fluid: na × 2na × nz (dam) or columns_x × na × nz (tank) particles on the rest lattice.
// The box is padded by a quarter spacing so float rounding cannot drop a lattice layer.
inline pbf_result emit_fluid(pbf_world_id w, const SceneSpec& s, uint32_t* emitted) {
    pbf_block_desc b = pbf_block_desc_default();
    const float pad = 0.25f * s.spacing();
    const float fx = s.dam ? s.a : s.tank_width * s.a;
    const float fy = s.dam ? 2.0f * s.a : s.a;
    set3(b.box_min, 0.0f, 0.0f, 0.0f);
    set3(b.box_max, fx + pad, fy + pad, s.depth() + pad);
    return pbf_world_emit_block(w, &b, emitted);
}

// Front position: the 99th percentile of x among particles whose centre lies within two
// particle diameters of the floor, plus one particle radius (the fluid's edge, not the last
// centre). At t = 0 this is exactly a. xyzw as from pbf_world_copy_positions.
inline double front_position(const float* xyzw, uint32_t count, float radius, double quantile = 0.99) {
    std::vector<float> xs;
    xs.reserve(count / 4 + 1);
    const float band = 4.0f * radius;  // two diameters
    for (uint32_t i = 0; i < count; ++i)
        if (xyzw[4 * i + 1] < band) xs.push_back(xyzw[4 * i]);
    if (xs.empty()) return 0.0;
    std::sort(xs.begin(), xs.end());
    const double pos = quantile * double(xs.size() - 1);
    const size_t lo = size_t(pos);
    const size_t hi = std::min(lo + 1, xs.size() - 1);
    const double frac = pos - double(lo);
    return double(xs[lo]) * (1.0 - frac) + double(xs[hi]) * frac + radius;
}

// Martin & Moyce (1952), Phil. Trans. R. Soc. A 244, 312–324: surge front of a collapsing
// column with n² = 2, a = 2.25 in. Z = front / a, T = t·sqrt(2g/a). Values as tabulated in
// ../shared/paper/ldc.md.
struct MMPoint {
    double T, Z;
};
inline const std::vector<MMPoint>& martin_moyce() {
    static const std::vector<MMPoint> table = {
        {0.00, 1.00}, {0.41, 1.11}, {0.84, 1.22}, {1.19, 1.44}, {1.43, 1.67}, {1.63, 1.89}, {1.83, 2.11}, {1.98, 2.33},
        {2.20, 2.56}, {2.32, 2.78}, {2.51, 3.00}, {2.65, 3.22}, {2.83, 3.44}, {2.98, 3.67}, {3.11, 3.89}, {3.33, 4.11}};
    return table;
}

// Linear interpolation of a sampled curve (T ascending); clamps at the ends.
inline double interpolate(const std::vector<double>& T, const std::vector<double>& Z, double t) {
    if (T.empty()) return 0.0;
    if (t <= T.front()) return Z.front();
    if (t >= T.back()) return Z.back();
    const size_t k = size_t(std::upper_bound(T.begin(), T.end(), t) - T.begin());
    const double f = (t - T[k - 1]) / (T[k] - T[k - 1]);
    return Z[k - 1] * (1.0 - f) + Z[k] * f;
}

// The comparison with Martin & Moyce over the table points with T in [t_lo, t_hi]: the
// simulation, shifted later by one offset δ in [0, max_shift] (the experiment's gate-release
// lag: Z_exp(T) is compared with Z_sim(T − δ)), chosen to minimise the worst relative error.
struct MMComparison {
    double shift = 0.0;            // the fitted δ
    double worst_rel_error = 1e9;  // max |Z_sim(T − δ)/Z_exp(T) − 1| over the points
    double worst_T = 0.0;          // where it is
    double worst_rel_error_unshifted = 1e9;
    double bound_margin = 1e9;  // min over samples with T > 0 of (1 + 2T) − Z_sim(T)
    int points = 0;
};

inline MMComparison compare_martin_moyce(const std::vector<double>& T, const std::vector<double>& Z,
                                         double max_shift = 0.2, double t_lo = 0.5, double t_hi = 3.0) {
    MMComparison c;
    auto worst = [&](double shift, double* where) {
        double w = 0.0;
        for (const MMPoint& p : martin_moyce()) {
            if (p.T < t_lo || p.T > t_hi) continue;
            const double e = std::fabs(interpolate(T, Z, p.T - shift) / p.Z - 1.0);
            if (e > w) {
                w = e;
                if (where) *where = p.T;
            }
        }
        return w;
    };
    for (const MMPoint& p : martin_moyce())
        if (p.T >= t_lo && p.T <= t_hi) ++c.points;
    c.worst_rel_error_unshifted = worst(0.0, nullptr);
    for (int k = 0; k <= 200; ++k) {  // δ on a 0.001 grid
        const double shift = max_shift * k / 200.0;
        double where = 0.0;
        const double w = worst(shift, &where);
        if (w < c.worst_rel_error) {
            c.worst_rel_error = w;
            c.shift = shift;
            c.worst_T = where;
        }
    }
    for (size_t i = 0; i < T.size(); ++i)
        if (T[i] > 0.0) c.bound_margin = std::min(c.bound_margin, 1.0 + 2.0 * T[i] - Z[i]);
    return c;
}

}  // namespace paper
