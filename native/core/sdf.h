// Triangle meshes as signed distance fields: the field, its sampling (the collider
// code's) and one triangle's geometry; the build's ops are in sdf_build.h.
//
// The field is a dense grid (first version: no sparse bricks) of float distances and boundary
// shares over the mesh's bounds grown by a pad, sampled at the grid points origin + i·cell.
// Memory: nx·ny·nz·8 bytes, nx = ceil((extent_x + 2·pad) / cell) + 1, pad = band + 2·cell
// (+ half the thickness of an open mesh).
// Values are clamped to ±band (band = h + 2 cells): particles never look farther (contact
// looks one radius out, boundary density h), and a clamped value never overestimates.
#pragma once
#include "params.h"

namespace pbf {

// A mesh's field in backend memory: one row of the world's mesh table.
struct MeshView {
    Vec3 origin;  // grid point (0, 0, 0), in the mesh's own frame
    float cell, inv_cell;
    int32_t nx, ny, nz;     // grid points per axis (each >= 2)
    float band;             // |values| <= band
    const float* values;    // nx·ny·nz, x fastest
    const float* boundary;  // nx·ny·nz: the solid's share of a particle's kernel there (SdfBoundaryOp)
};

// ---- sampling --------------------------------------------------------------------------------
// Trilinear interpolation of a grid field at grid coordinates c (inside the grid) and the
// gradient of the interpolant (per grid unit).
PBF_HD float trilinear(const MeshView& m, const float* field, Vec3 c, Vec3& grad) {
    // The cell's lower corner (the top face's points use the last cell).
    const int32_t ix = int32_t(fminf(c.x, float(m.nx - 2))), iy = int32_t(fminf(c.y, float(m.ny - 2))),
                  iz = int32_t(fminf(c.z, float(m.nz - 2)));
    const float fx = c.x - float(ix), fy = c.y - float(iy), fz = c.z - float(iz);
    const size_t sx = 1, sy = size_t(m.nx), sz = size_t(m.nx) * size_t(m.ny);
    const float* v = field + size_t(ix) + sy * size_t(iy) + sz * size_t(iz);
    const float v000 = v[0], v100 = v[sx], v010 = v[sy], v110 = v[sx + sy];
    const float v001 = v[sz], v101 = v[sx + sz], v011 = v[sy + sz], v111 = v[sx + sy + sz];
    // Along x first, then y, then z; the gradient by differentiating each stage.
    const float a00 = v000 + (v100 - v000) * fx, a10 = v010 + (v110 - v010) * fx;
    const float a01 = v001 + (v101 - v001) * fx, a11 = v011 + (v111 - v011) * fx;
    const float b0 = a00 + (a10 - a00) * fy, b1 = a01 + (a11 - a01) * fy;
    const float dx0 = (v100 - v000) + ((v110 - v010) - (v100 - v000)) * fy;
    const float dx1 = (v101 - v001) + ((v111 - v011) - (v101 - v001)) * fy;
    grad = Vec3{dx0 + (dx1 - dx0) * fz, (a10 - a00) + ((a11 - a01) - (a10 - a00)) * fz, b1 - b0};
    return b0 + (b1 - b0) * fz;
}

// Grid coordinates of q, clamped to the grid; *outside = how far beyond it q lies (grid units).
PBF_HD Vec3 grid_coordinates(const MeshView& m, Vec3 q, Vec3* outside) {
    const Vec3 g = (q - m.origin) * m.inv_cell;
    const Vec3 c = min3(max3(g, Vec3{0.0f, 0.0f, 0.0f}), Vec3{float(m.nx - 1), float(m.ny - 1), float(m.nz - 1)});
    *outside = g - c;
    return c;
}

// Signed distance at q (the mesh's frame) and the outward normal there: trilinear value and the
// gradient of the trilinear interpolant, normalised. Beyond the grid: band plus the distance to
// the grid's box (the mesh lies at least band inside it: never an overestimate).
PBF_HD float mesh_distance(const MeshView& m, Vec3 q, Vec3& normal) {
    Vec3 out;
    const Vec3 c = grid_coordinates(m, q, &out);
    const float out_len = length(out);
    if (out_len > 0.0f) {
        normal = out * (1.0f / out_len);
        return m.band + out_len * m.cell;
    }
    Vec3 grad;
    const float d = trilinear(m, m.values, c, grad);
    const float len = length(grad);
    normal = len > 1e-12f ? grad * (1.0f / len) : Vec3{0.0f, 1.0f, 0.0f};
    return d;
}

// The solid's share of the kernel at q (the mesh's frame) and its gradient (1/m): 0 beyond the
// grid (the solid lies inside it, farther than h from its faces).
PBF_HD float mesh_boundary(const MeshView& m, Vec3 q, Vec3& gradient) {
    Vec3 out;
    const Vec3 c = grid_coordinates(m, q, &out);
    gradient = Vec3{0.0f, 0.0f, 0.0f};
    if (length_sq(out) > 0.0f) return 0.0f;
    const float b = trilinear(m, m.boundary, c, gradient);
    gradient = gradient * m.inv_cell;
    return b;
}

// ---- geometry of one triangle ----------------------------------------------------------------
// Zero area to float precision (|ab x ac| under 1e-7 of the longest edge squared): skipped by
// the build; a mesh of only such triangles is refused.
PBF_HD bool triangle_degenerate(Vec3 a, Vec3 b, Vec3 c) {
    const float longest = fmaxf(length_sq(b - a), fmaxf(length_sq(c - b), length_sq(a - c)));
    return !(length(cross(b - a, c - a)) > 1e-7f * longest);
}

PBF_HD float segment_distance_sq(Vec3 p, Vec3 a, Vec3 b) {
    const Vec3 ab = b - a;
    const float t = clampf(dot(p - a, ab) / fmaxf(dot(ab, ab), 1e-30f), 0.0f, 1.0f);
    return length_sq(p - (a + ab * t));
}

// Squared distance from p to triangle abc (non-degenerate): to its plane where p projects
// inside it, else to the nearest edge.
PBF_HD float triangle_distance_sq(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
    const Vec3 n = cross(b - a, c - a);
    if (dot(cross(b - a, p - a), n) >= 0.0f && dot(cross(c - b, p - b), n) >= 0.0f &&
        dot(cross(a - c, p - c), n) >= 0.0f) {
        const float d = dot(p - a, n);
        return d * d / dot(n, n);
    }
    return fminf(segment_distance_sq(p, a, b), fminf(segment_distance_sq(p, b, c), segment_distance_sq(p, c, a)));
}

// The solid angle triangle abc subtends at p, signed: positive where p sees its back (the side
// its counter-clockwise normal points away from), so a closed outward mesh sums to 4π inside
// (Van Oosterom & Strackee 1983).
PBF_HD float solid_angle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
    a -= p;
    b -= p;
    c -= p;
    const float la = length(a), lb = length(b), lc = length(c);
    const float num = dot(a, cross(b, c));
    const float den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la;
    return 2.0f * atan2f(num, den);
}

}  // namespace pbf
