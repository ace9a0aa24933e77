// The rest lattice's calibration: sums over a cubic lattice at rest spacing around one particle,
// which turn the continuum kernels into the discrete fluid's constants (a world's particle mass,
// the rest gradient norm, the walls' γ and the box edges' κ, the render scale's reference).
// Host-only, in double: each runs once per world or parameter change.
#pragma once
#include <cmath>

#include "collide.h"
#include "render_ops.h"

namespace pbf {

// Mass and ε scale for a rest lattice, so that a lattice at rest spacing has rest density.
struct LatticeCalibration {
    double kernel_sum;      // Σ_j W_poly6(|x_j|) over the lattice around one particle (incl. itself)
    double gradient_norm2;  // Σ_j |∇W_ij|² around one particle
};

inline LatticeCalibration calibrate_lattice(float spacing, float h) {
    const double d = spacing, hh = h;
    const int reach = static_cast<int>(std::ceil(hh / d));
    const double poly6 = 315.0 / (64.0 * M_PI * std::pow(hh, 9));
    const double spiky = 45.0 / (M_PI * std::pow(hh, 6));
    LatticeCalibration c{0.0, 0.0};
    for (int z = -reach; z <= reach; ++z)
        for (int y = -reach; y <= reach; ++y)
            for (int x = -reach; x <= reach; ++x) {
                const double r = d * std::sqrt(double(x * x + y * y + z * z));
                if (r >= hh) continue;
                c.kernel_sum += poly6 * std::pow(hh * hh - r * r, 3);
                if (r > 0) c.gradient_norm2 += std::pow(spiky * (hh - r) * (hh - r), 2);
            }
    return c;
}

// γ of the boundary density: the density a rest lattice's first layer misses at a wall (the
// lattice layers beyond it), over the continuum half-space integral Φ at its distance (one
// radius): so a rest lattice against a wall has rest density in its first layer.
inline float boundary_lattice_scale(float spacing, float h) {
    // The first layer lies one radius (spacing / 2) from the wall; the layers it misses lie
    // k·spacing below it (k >= 1), each a square lattice.
    const double d = spacing, hh = h;
    const int reach = static_cast<int>(std::ceil(hh / d));
    double missing = 0.0;
    for (int k = 1; k <= reach; ++k)
        for (int z = -reach; z <= reach; ++z)
            for (int x = -reach; x <= reach; ++x) {
                const double r2 = d * d * double(x * x + k * k + z * z);
                if (r2 < hh * hh) missing += std::pow(hh * hh - r2, 3);
            }
    const LatticeCalibration c = calibrate_lattice(spacing, h);
    const double poly6 = 315.0 / (64.0 * M_PI * std::pow(hh, 9));
    return static_cast<float>(missing * poly6 / c.kernel_sum / boundary_phi(0.5f * spacing / h));
}

// κ of a box's edges (collide.h box_boundary): chosen so that a rest lattice around a box edge
// has rest density at the edge's diagonal site (one radius outside both faces), as γ gives it at
// a face. gamma: boundary_lattice_scale.
inline float box_edge_scale(float spacing, float h, float gamma) {
    // The lattice sites a particle at the edge's diagonal site misses: those beyond both faces
    // (the edge's quadrant), at k·spacing and l·spacing (k, l >= 1) from it.
    const double d = spacing, hh = h;
    const int reach = static_cast<int>(std::ceil(hh / d));
    double missing = 0.0;
    for (int k = 1; k <= reach; ++k)
        for (int l = 1; l <= reach; ++l)
            for (int z = -reach; z <= reach; ++z) {
                const double r2 = d * d * double(k * k + l * l + z * z);
                if (r2 < hh * hh) missing += std::pow(hh * hh - r2, 3);
            }
    const LatticeCalibration c = calibrate_lattice(spacing, h);
    const double poly6 = 315.0 / (64.0 * M_PI * std::pow(hh, 9));
    // γ (Φ(t)² - κ g(t)²) = missing, t = radius / h (box_boundary's share there).
    const float t = 0.5f * spacing / h;
    float slope;
    const double phi = boundary_phi(t), g = box_edge_term(0.5f * spacing, 1.0f / h, slope);
    return static_cast<float>((phi * phi - missing * poly6 / c.kernel_sum / gamma) / (g * g));
}

// The eigenvalue (m²) of the render covariance of a rest lattice around one particle (isotropic
// by the lattice's symmetry): the reference the render scale k_s is given against.
inline double rest_render_variance(float spacing, float h) {
    const double d = spacing, hh = h;
    const int reach = static_cast<int>(std::ceil(hh / d));
    double wsum = 0.0, wxx = 0.0;
    for (int z = -reach; z <= reach; ++z)
        for (int y = -reach; y <= reach; ++y)
            for (int x = -reach; x <= reach; ++x) {
                const double r2 = d * d * double(x * x + y * y + z * z);
                const double w = render_weight(float(r2), float(hh * hh));
                wsum += w;
                wxx += w * d * d * double(x * x);
            }
    return wxx / wsum;
}

}  // namespace pbf
