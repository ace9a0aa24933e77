// Triangle meshes as signed distance fields (issue 13): the build's per-brick and per-voxel ops
// (launched by CpuExec and CudaExec alike) and the sampling the collider code uses.
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

constexpr float kFourPi = 12.566370614359172f;
// Voxels per brick edge: the build bins triangles to bricks of kSdfBrick³ grid points.
constexpr int32_t kSdfBrick = 4;

// A mesh's field in backend memory: one row of the world's mesh table.
struct MeshView {
    Vec3 origin;       // grid point (0, 0, 0), in the mesh's own frame
    float cell, inv_cell;
    int32_t nx, ny, nz;  // grid points per axis (each >= 2)
    float band;          // |values| <= band
    const float* values;  // nx·ny·nz, x fastest
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

// ---- the build -------------------------------------------------------------------------------
// The mesh in backend memory during its build: non-degenerate triangles, and per brick the
// triangles whose bounds, grown by the build margin, meet the brick (compressed rows).
struct SdfSource {
    const Vec3* vertices;
    const uint32_t* indices;  // 3 per triangle
    uint32_t triangle_count;
    const uint32_t* brick_begin;  // bricks + 1
    const uint32_t* brick_triangles;
    int32_t bx, by, bz;  // bricks per axis
};

PBF_HD Vec3 grid_point(const MeshView& m, int32_t x, int32_t y, int32_t z) {
    return m.origin + Vec3{float(x), float(y), float(z)} * m.cell;
}

PBF_HD float triangle_solid_angle(const SdfSource& s, uint32_t t, Vec3 p) {
    const uint32_t* i = s.indices + 3 * t;
    return solid_angle(p, s.vertices[i[0]], s.vertices[i[1]], s.vertices[i[2]]);
}

PBF_HD Vec3 brick_centre(const MeshView& m, int32_t x, int32_t y, int32_t z) {
    const float half = 0.5f * float(kSdfBrick - 1);
    return m.origin + Vec3{float(x * kSdfBrick) + half, float(y * kSdfBrick) + half, float(z * kSdfBrick) + half} * m.cell;
}

// One thread per brick: the winding number at the brick's centre, of all triangles and of those
// NOT in its list. The unlisted ones lie at least the margin away from every point of the
// brick, so their share varies little across it (by at most about brick half-diagonal /
// (2 · margin) for a flat far surface: 0.22 at the build's margin of 8 cells): a voxel near
// the surface adds its listed triangles' share exactly to this one (a first-order far field,
// after Barill et al. 2018's idea of treating far triangles in bulk).
struct SdfBrickWindingOp {
    SdfSource src;
    MeshView grid;
    float* winding;  // 2 per brick: far share, total at the centre
    PBF_HD void operator()(uint32_t b) const {
        const int32_t x = int32_t(b % uint32_t(src.bx)), y = int32_t((b / uint32_t(src.bx)) % uint32_t(src.by)),
                      z = int32_t(b / (uint32_t(src.bx) * uint32_t(src.by)));
        const Vec3 centre = brick_centre(grid, x, y, z);
        float all = 0.0f, listed = 0.0f;
        for (uint32_t t = 0; t < src.triangle_count; ++t) all += triangle_solid_angle(src, t, centre);
        for (uint32_t k = src.brick_begin[b]; k < src.brick_begin[b + 1]; ++k)
            listed += triangle_solid_angle(src, src.brick_triangles[k], centre);
        winding[2 * b] = (all - listed) / kFourPi;
        winding[2 * b + 1] = all / kFourPi;
    }
};

// One thread per grid point: the distance to the nearest listed triangle (none listed: beyond
// the band), signed for closed meshes by the generalised winding number (inside where it
// exceeds 1/2: robust to small holes and overlaps, unlike ray parity); open meshes are a
// shell: |distance| - half_thickness. Clamped to ±band. A point farther from the surface than
// from its brick's centre is on the centre's side (the segment between them crosses no
// surface): it takes the centre's winding number, and only points near the surface sum solid
// angles.
struct SdfVoxelOp {
    SdfSource src;
    MeshView grid;
    const float* winding;
    uint32_t closed;
    float half_thickness;
    float* values;
    PBF_HD void operator()(uint32_t i) const {
        const uint32_t nx = uint32_t(grid.nx), ny = uint32_t(grid.ny);
        const int32_t x = int32_t(i % nx), y = int32_t((i / nx) % ny), z = int32_t(i / (nx * ny));
        const Vec3 p = grid_point(grid, x, y, z);
        const int32_t bx = x / kSdfBrick, by = y / kSdfBrick, bz = z / kSdfBrick;
        const uint32_t b = uint32_t(bx) + uint32_t(src.bx) * (uint32_t(by) + uint32_t(src.by) * uint32_t(bz));
        const uint32_t first = src.brick_begin[b], end = src.brick_begin[b + 1];
        float d2 = 1e30f;
        for (uint32_t k = first; k < end; ++k) {
            const uint32_t* v = src.indices + 3 * src.brick_triangles[k];
            d2 = fminf(d2, triangle_distance_sq(p, src.vertices[v[0]], src.vertices[v[1]], src.vertices[v[2]]));
        }
        const float u = sqrtf(d2);
        float d;
        if (closed) {
            float w = winding[2 * b + 1];
            if (u * u <= length_sq(p - brick_centre(grid, bx, by, bz))) {
                float angle = 0.0f;
                for (uint32_t k = first; k < end; ++k) angle += triangle_solid_angle(src, src.brick_triangles[k], p);
                w = winding[2 * b] + angle / kFourPi;
            }
            d = w > 0.5f ? -u : u;
        } else {
            d = u - half_thickness;
        }
        values[i] = clampf(d, -grid.band, grid.band);
    }
};

// One thread per grid point, after SdfVoxelOp: the solid's share of a poly6 kernel of radius h
// centred there, Σ W·solid / Σ W over the grid points within h, each point solid by the
// fraction clamp(1/2 - d/cell, 0, 1) (a point on the surface counts half). A particle's
// boundary density is then γ times this, sampled trilinearly: exact at edges, corners and
// curved parts, where the flat-at-the-closest-point rule of the analytic shapes sees only the
// nearest face (it under-counts a concave edge of a container by the other face's share).
struct SdfBoundaryOp {
    MeshView grid;
    float h;
    float* boundary;
    PBF_HD static float solid(const MeshView& g, int32_t x, int32_t y, int32_t z) {
        if (x < 0 || y < 0 || z < 0 || x >= g.nx || y >= g.ny || z >= g.nz) return 0.0f;
        const float d = g.values[size_t(x) + size_t(g.nx) * (size_t(y) + size_t(g.ny) * size_t(z))];
        return clampf(0.5f - d * g.inv_cell, 0.0f, 1.0f);
    }
    PBF_HD void operator()(uint32_t i) const {
        const uint32_t nx = uint32_t(grid.nx), ny = uint32_t(grid.ny);
        const int32_t x = int32_t(i % nx), y = int32_t((i / nx) % ny), z = int32_t(i / (nx * ny));
        const float d = grid.values[i];
        if (fabsf(d) > h + grid.cell) {  // the kernel lies wholly on one side
            boundary[i] = d < 0.0f ? 1.0f : 0.0f;
            return;
        }
        const int32_t reach = int32_t(h * grid.inv_cell);
        const float h2 = h * h * grid.inv_cell * grid.inv_cell;  // in grid units²
        float sum = 0.0f, weights = 0.0f;
        for (int32_t dz = -reach; dz <= reach; ++dz)
            for (int32_t dy = -reach; dy <= reach; ++dy)
                for (int32_t dx = -reach; dx <= reach; ++dx) {
                    const float r2 = float(dx * dx + dy * dy + dz * dz);
                    if (r2 >= h2) continue;
                    const float u = h2 - r2, w = u * u * u;
                    weights += w;
                    sum += w * solid(grid, x + dx, y + dy, z + dz);
                }
        boundary[i] = sum / weights;
    }
};

}  // namespace pbf
