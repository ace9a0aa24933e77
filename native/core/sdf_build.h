// The build of a mesh's distance field: the per-triangle, per-brick and per-voxel ops
// that solver/mesh_field.h launches in order on either executor (CpuExec, CudaExec), so the
// whole build runs where the world runs.
//
//   SdfCornersOp        per triangle: its corners, gathered once (3 aligned loads a triangle)
//   SdfBinCountOp       per triangle: how many bricks list it       -> exclusive scan
//   SdfBinFillOp        per triangle: (brick, triangle) pairs        -> sort by brick (stable)
//   SdfBrickBeginOp     per brick:    where its list starts in the sorted pairs
//   SdfWindingPartOp    per (brick, chunk of triangles): solid angles at the brick's centre
//   SdfBrickWindingOp   per brick:    total and far winding numbers
//   SdfVoxelOp          per grid point, brick by brick: distance and sign
//   SdfBoundaryOp       per grid point: the solid's share of the kernel
#pragma once
#include "sdf.h"

namespace pbf {

constexpr float kFourPi = 12.566370614359172f;
// Grid points per brick edge: the build lists triangles per brick of kSdfBrick³ points.
constexpr int32_t kSdfBrick = 4;
constexpr uint32_t kSdfBrickPoints = uint32_t(kSdfBrick * kSdfBrick * kSdfBrick);
// The sum over all triangles at every brick's centre is split into chunks of triangles so that
// about this many threads share it (a GPU needs ~300k resident threads; a brick per thread
// alone would leave most of it idle). A function of the mesh only: both executors sum alike.
constexpr uint32_t kSdfWindingThreads = 1u << 20;

// The grid's bricks, and how far from a brick's points a triangle is still listed in it.
struct SdfBricks {
    MeshView grid;
    int32_t bx, by, bz;  // bricks per axis
    float margin;
};

PBF_HD uint32_t brick_count(const SdfBricks& s) { return uint32_t(s.bx) * uint32_t(s.by) * uint32_t(s.bz); }

PBF_HD Vec3 grid_point(const MeshView& m, int32_t x, int32_t y, int32_t z) {
    return m.origin + Vec3{float(x), float(y), float(z)} * m.cell;
}

PBF_HD Vec3 brick_centre(const MeshView& m, int32_t x, int32_t y, int32_t z) {
    const float half = 0.5f * float(kSdfBrick - 1);
    return m.origin +
           Vec3{float(x * kSdfBrick) + half, float(y * kSdfBrick) + half, float(z * kSdfBrick) + half} * m.cell;
}

// The bricks with a grid point inside the triangle's bounds grown by the margin, per axis
// (first..last); false when there is none.
PBF_HD bool brick_range(const SdfBricks& s, Vec3 a, Vec3 b, Vec3 c, int32_t first[3], int32_t last[3]) {
    const Vec3 m{s.margin, s.margin, s.margin};
    const Vec3 lo = (min3(a, min3(b, c)) - m - s.grid.origin) * s.grid.inv_cell;
    const Vec3 hi = (max3(a, max3(b, c)) + m - s.grid.origin) * s.grid.inv_cell;
    const float lo_a[3] = {lo.x, lo.y, lo.z}, hi_a[3] = {hi.x, hi.y, hi.z};
    const int32_t points[3] = {s.grid.nx, s.grid.ny, s.grid.nz};
    for (int k = 0; k < 3; ++k) {
        const float p0 = fmaxf(ceilf(lo_a[k]), 0.0f), p1 = fminf(floorf(hi_a[k]), float(points[k] - 1));
        if (!(p1 >= p0)) return false;
        first[k] = int32_t(p0) / kSdfBrick;
        last[k] = int32_t(p1) / kSdfBrick;
    }
    return true;
}

// Calls f(brick, k) for the k-th brick that lists the triangle abc and returns how many do:
// those of brick_range whose centre lies within margin + the brick's half diagonal of the
// triangle (the ball around the brick's points). So every grid point within the margin of the
// triangle lies in a brick that lists it, and a brick's unlisted triangles are farther than the
// margin from all its points; the ball test drops the bounds' corners (about half the bricks of
// a small triangle).
template <class F>
PBF_HD uint32_t for_each_brick_near(const SdfBricks& s, Vec3 a, Vec3 b, Vec3 c, F&& f) {
    int32_t first[3], last[3];
    if (!brick_range(s, a, b, c, first, last)) return 0;
    const float reach = s.margin + 0.8660254f * float(kSdfBrick - 1) * s.grid.cell;  // √3/2 · brick span
    const float reach2 = reach * reach;
    uint32_t listed = 0;
    for (int32_t z = first[2]; z <= last[2]; ++z)
        for (int32_t y = first[1]; y <= last[1]; ++y)
            for (int32_t x = first[0]; x <= last[0]; ++x) {
                if (triangle_distance_sq(brick_centre(s.grid, x, y, z), a, b, c) > reach2) continue;
                f(uint32_t(x) + uint32_t(s.bx) * (uint32_t(y) + uint32_t(s.by) * uint32_t(z)), listed);
                ++listed;
            }
    return listed;
}

// The mesh in backend memory during its build: the non-degenerate triangles' corners (3 per
// triangle, w unused) and per brick the triangles it lists (compressed rows, ascending).
struct SdfSource {
    const Vec4* corners;
    uint32_t triangle_count;
    const uint32_t* brick_begin;  // bricks + 1
    const uint32_t* brick_triangles;
    SdfBricks bricks;
};

PBF_HD float triangle_solid_angle(const Vec4* corners, uint32_t t, Vec3 p) {
    return solid_angle(p, xyz(corners[3 * t]), xyz(corners[3 * t + 1]), xyz(corners[3 * t + 2]));
}

PBF_HD float triangle_distance_sq(const Vec4* corners, uint32_t t, Vec3 p) {
    return triangle_distance_sq(p, xyz(corners[3 * t]), xyz(corners[3 * t + 1]), xyz(corners[3 * t + 2]));
}

// One thread per triangle: its corners from the vertex and index arrays.
struct SdfCornersOp {
    const Vec3* vertices;
    const uint32_t* indices;
    Vec4* corners;
    PBF_HD void operator()(uint32_t t) const {
        for (uint32_t k = 0; k < 3; ++k) corners[3 * t + k] = make_vec4(vertices[indices[3 * t + k]], 0.0f);
    }
};

// One thread per triangle: how many bricks list it.
struct SdfBinCountOp {
    SdfBricks bricks;
    const Vec4* corners;
    uint32_t* counts;
    PBF_HD void operator()(uint32_t t) const {
        counts[t] = for_each_brick_near(bricks, xyz(corners[3 * t]), xyz(corners[3 * t + 1]), xyz(corners[3 * t + 2]),
                                        [](uint32_t, uint32_t) {});
    }
};

// One thread per triangle, after the scan of the counts: its (brick, triangle) pairs from its
// offset on (triangle order: a stable sort by brick leaves each list ascending).
struct SdfBinFillOp {
    SdfBricks bricks;
    const Vec4* corners;
    const uint32_t* offsets;
    uint32_t* keys;
    uint32_t* triangles;
    PBF_HD void operator()(uint32_t t) const {
        uint32_t* key = keys + offsets[t];
        uint32_t* tri = triangles + offsets[t];
        for_each_brick_near(bricks, xyz(corners[3 * t]), xyz(corners[3 * t + 1]), xyz(corners[3 * t + 2]),
                            [&](uint32_t brick, uint32_t k) {
                                key[k] = brick;
                                tri[k] = t;
                            });
    }
};

// One thread per brick and one more: where brick b's list starts among the `listed` pairs
// sorted by brick (the first key >= b), and the end of the last list.
struct SdfBrickBeginOp {
    const uint32_t* sorted_keys;
    uint32_t listed;
    uint32_t* begin;
    PBF_HD void operator()(uint32_t b) const {
        uint32_t lo = 0, hi = listed;
        while (lo < hi) {
            const uint32_t mid = lo + (hi - lo) / 2;
            if (sorted_keys[mid] < b)
                lo = mid + 1;
            else
                hi = mid;
        }
        begin[b] = lo;
    }
};

// The chunks of triangles the sum at the brick centres is split into (sdf_winding_chunk each).
inline uint32_t sdf_winding_chunks(uint32_t bricks, uint32_t triangles) {
    const uint32_t by_threads = kSdfWindingThreads / (bricks > 0 ? bricks : 1);
    const uint32_t by_length = (triangles + 63) / 64;  // at least 64 triangles a chunk
    const uint32_t chunks = by_threads < by_length ? by_threads : by_length;
    return chunks > 0 ? chunks : 1;
}
inline uint32_t sdf_winding_chunk(uint32_t chunks, uint32_t triangles) { return (triangles + chunks - 1) / chunks; }

// One thread per (brick, chunk), consecutive threads on consecutive bricks (a warp reads the
// same triangle): the solid angles of the chunk's triangles at the brick's centre.
struct SdfWindingPartOp {
    SdfSource src;
    uint32_t chunk;  // triangles per chunk
    float* parts;    // bricks × chunks, chunk-major
    PBF_HD void operator()(uint32_t i) const {
        const SdfBricks& s = src.bricks;
        const uint32_t bricks = brick_count(s), b = i % bricks, c = i / bricks;
        const int32_t x = int32_t(b % uint32_t(s.bx)), y = int32_t((b / uint32_t(s.bx)) % uint32_t(s.by)),
                      z = int32_t(b / (uint32_t(s.bx) * uint32_t(s.by)));
        const Vec3 centre = brick_centre(s.grid, x, y, z);
        const uint32_t first = c * chunk, end = first + chunk < src.triangle_count ? first + chunk : src.triangle_count;
        float sum = 0.0f;
        for (uint32_t t = first; t < end; ++t) sum += triangle_solid_angle(src.corners, t, centre);
        parts[i] = sum;
    }
};

// One thread per brick: the winding number at the brick's centre, of all triangles (the chunks'
// sums in order) and of those NOT in its list. The unlisted ones lie farther than the margin
// from every point of the brick, so their share varies little across it (by at most about brick
// half-diagonal / (2 · margin) for a flat far surface: 0.22 at the build's margin of 8 cells):
// a voxel near the surface adds its listed triangles' share exactly to this one (a first-order
// far field, after Barill et al. 2018's idea of treating far triangles in bulk).
struct SdfBrickWindingOp {
    SdfSource src;
    uint32_t chunks;
    const float* parts;
    float* winding;  // 2 per brick: far share, total at the centre
    PBF_HD void operator()(uint32_t b) const {
        const SdfBricks& s = src.bricks;
        const uint32_t bricks = brick_count(s);
        const int32_t x = int32_t(b % uint32_t(s.bx)), y = int32_t((b / uint32_t(s.bx)) % uint32_t(s.by)),
                      z = int32_t(b / (uint32_t(s.bx) * uint32_t(s.by)));
        const Vec3 centre = brick_centre(s.grid, x, y, z);
        float all = 0.0f, listed = 0.0f;
        for (uint32_t c = 0; c < chunks; ++c) all += parts[size_t(c) * bricks + b];
        for (uint32_t k = src.brick_begin[b]; k < src.brick_begin[b + 1]; ++k)
            listed += triangle_solid_angle(src.corners, src.brick_triangles[k], centre);
        winding[2 * b] = (all - listed) / kFourPi;
        winding[2 * b + 1] = all / kFourPi;
    }
};

// One thread per grid point, numbered brick by brick (kSdfBrickPoints threads a brick, points
// past the grid's end idle): a warp walks one brick's list together. The distance to the
// nearest listed triangle (none listed: beyond the band), signed for closed meshes by the
// generalised winding number (inside where it exceeds 1/2: robust to small holes and overlaps,
// unlike ray parity); open meshes are a shell: |distance| - half_thickness. Clamped to ±band.
// A point farther from the surface than from its brick's centre is on the centre's side (the
// segment between them crosses no surface): it takes the centre's winding number, and only
// points near the surface sum solid angles.
struct SdfVoxelOp {
    SdfSource src;
    const float* winding;
    uint32_t closed;
    float half_thickness;
    float* values;
    PBF_HD void operator()(uint32_t i) const {
        const SdfBricks& s = src.bricks;
        const MeshView& grid = s.grid;
        const uint32_t b = i / kSdfBrickPoints, local = i % kSdfBrickPoints;
        const int32_t bx = int32_t(b % uint32_t(s.bx)), by = int32_t((b / uint32_t(s.bx)) % uint32_t(s.by)),
                      bz = int32_t(b / (uint32_t(s.bx) * uint32_t(s.by)));
        const int32_t x = bx * kSdfBrick + int32_t(local % kSdfBrick),
                      y = by * kSdfBrick + int32_t((local / kSdfBrick) % kSdfBrick),
                      z = bz * kSdfBrick + int32_t(local / (kSdfBrick * kSdfBrick));
        if (x >= grid.nx || y >= grid.ny || z >= grid.nz) return;
        const Vec3 p = grid_point(grid, x, y, z);
        const uint32_t first = src.brick_begin[b], end = src.brick_begin[b + 1];
        float d2 = 1e30f;
        for (uint32_t k = first; k < end; ++k)
            d2 = fminf(d2, triangle_distance_sq(src.corners, src.brick_triangles[k], p));
        const float u = sqrtf(d2);
        float d;
        if (closed) {
            float w = winding[2 * b + 1];
            if (u * u <= length_sq(p - brick_centre(grid, bx, by, bz))) {
                float angle = 0.0f;
                for (uint32_t k = first; k < end; ++k)
                    angle += triangle_solid_angle(src.corners, src.brick_triangles[k], p);
                w = winding[2 * b] + angle / kFourPi;
            }
            d = w > 0.5f ? -u : u;
        } else {
            d = u - half_thickness;
        }
        values[size_t(x) + size_t(grid.nx) * (size_t(y) + size_t(grid.ny) * size_t(z))] =
            clampf(d, -grid.band, grid.band);
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
