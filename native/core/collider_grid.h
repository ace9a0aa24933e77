// The colliders' broad phase: a hashed grid of coarse cells, built on the host once per step
// from the colliders' step bounds (solver/collider_broadphase.cpp) and read by every particle
// query (collision, boundary density, boundary viscosity, adhesion, the reactions), so a
// particle tests the colliders listed in its cell instead of all of them.
//
// Each binned collider is listed in every cell that its bounds grown by a pad wider than the
// query reach meet (once per bucket: cells that hash alike share a bucket, which only adds candidates). A query
// (a box around a particle or its path, grown by at most ColliderGrid::query_reach: the kernel
// radius h) reads the cell of the box shrunk by that reach.
// Colliders with unbounded or large bounds (planes, a level's mesh) are walked by every query.
#pragma once
#include "bodies.h"

namespace pbf {

// A coarse cell index along one axis; clamped so that far-away or unbounded coordinates
// (kUnbounded) stay finite integers.
// (fmaxf returns the bound for NaN, so no input converts out of range).
PBF_HD int32_t coarse_cell(float x, float inv_cell) {
    const float c = fminf(fmaxf(x * inv_cell, -1.0e9f), 1.0e9f);
#ifdef __CUDA_ARCH__
    return __float2int_rd(c);  // floor and convert in one instruction
#else
    return static_cast<int32_t>(floorf(c));
#endif
}

// Bucket of a cell: a multiplicative hash of its coordinates (three large odd constants, as in
// Teschner et al. 2003's hash for deformable-body collision), masked to the table size.
PBF_HD uint32_t coarse_bucket(int32_t x, int32_t y, int32_t z, uint32_t mask) {
    return ((uint32_t(x) * 73856093u) ^ (uint32_t(y) * 19349663u) ^ (uint32_t(z) * 83492791u)) & mask;
}

// Calls f(k) for the colliders listed for cell (x, y, z) (in_grid) or, without a grid or for
// a query outside one cell (!in_grid), for every collider: the always-walked ones, then the
// cell's list, each in ascending order. One loop for both keeps f inlined once.
template <class F>
PBF_HD void for_each_candidate(const ColliderView& cv, bool in_grid, int32_t x, int32_t y, int32_t z, F&& f) {
    if constexpr (!kCollidersBuilt) return;
    const ColliderGrid& g = cv.grid;
    uint32_t total = cv.count, listed = 0;
    if (in_grid) {
        const uint32_t bucket = coarse_bucket(x, y, z, g.bucket_mask);
        listed = g.bucket_begin[bucket];
        total = g.unbinned + (g.bucket_begin[bucket + 1] - listed);
    }
    for (uint32_t t = 0; t < total; ++t) f(in_grid ? g.entries[t < g.unbinned ? t : listed + (t - g.unbinned)] : t);
}

// Calls f(k) once for every collider k whose step bounds meet the box p ± reach, for a reach
// up to the grid's query reach (the kernel radius): p's cell lists every such collider, since
// the pad exceeds the reach.
template <class F>
PBF_HD void for_each_collider_near(const ColliderView& cv, Vec3 p, float reach, F&& f) {
    const ColliderGrid& g = cv.grid;
    const Vec3 r{reach, reach, reach};
    for_each_candidate(cv, g.bucket_begin != nullptr, coarse_cell(p.x, g.inv_cell), coarse_cell(p.y, g.inv_cell),
                       coarse_cell(p.z, g.inv_cell), [&](uint32_t k) {
                           if (overlaps(cv.shapes[k].bounds, p - r, p + r)) f(k);
                       });
}

// Calls f(k) for every collider k whose step bounds may meet the box of the path from a to b
// grown by reach (up to the query reach; f tests the bounds): the colliders listed for the cell
// of the path's box shrunk by the query reach's excess over reach (to its centre where
// narrower; every point of the grown box is then within the query reach of it), when that lies
// in one cell; else every collider (a path longer than about 2h - 2 reach: rare).
template <class F>
PBF_HD void for_each_collider_on_path(const ColliderView& cv, Vec3 a, Vec3 b, float reach, F&& f) {
    const ColliderGrid& g = cv.grid;
    const float slack = g.query_reach - reach;
    const Vec3 lo = min3(a, b), hi = max3(a, b), mid = (lo + hi) * 0.5f, in{slack, slack, slack};
    const Vec3 c0 = min3(lo + in, mid), c1 = max3(hi - in, mid);
    const int32_t x = coarse_cell(c0.x, g.inv_cell), y = coarse_cell(c0.y, g.inv_cell),
                  z = coarse_cell(c0.z, g.inv_cell);
    const bool one_cell =
        x == coarse_cell(c1.x, g.inv_cell) && y == coarse_cell(c1.y, g.inv_cell) && z == coarse_cell(c1.z, g.inv_cell);
    for_each_candidate(cv, g.bucket_begin != nullptr && one_cell, x, y, z, f);
}

}  // namespace pbf
