#include "collider_broadphase.h"

#include <algorithm>
#include <cmath>

#include "../core/collider_grid.h"

namespace pbf {

namespace {

constexpr uint32_t kMaxBuckets = 16384;  // 64 KB of offsets
constexpr uint32_t kMaxEntries = 65536;  // 256 KB of collider indices

uint32_t next_pow2(uint32_t v) {
    uint32_t p = 1;
    while (p < v) p <<= 1;
    return p;
}

// The cells [lo, hi] (inclusive) in which a collider with step bounds b is listed: those its
// bounds grown by the pad meet.
struct CellRange {
    int32_t lo[3], hi[3];
};
CellRange collider_cells(const Bounds& b, float pad, float inv_cell) {
    const Vec3 lo = b.lo - Vec3{pad, pad, pad}, hi = b.hi + Vec3{pad, pad, pad};
    return CellRange{{coarse_cell(lo.x, inv_cell), coarse_cell(lo.y, inv_cell), coarse_cell(lo.z, inv_cell)},
                     {coarse_cell(hi.x, inv_cell), coarse_cell(hi.y, inv_cell), coarse_cell(hi.z, inv_cell)}};
}

bool bounded(const Bounds& b) {
    const float far = 0.5f * kUnbounded;
    return b.lo.x > -far && b.lo.y > -far && b.lo.z > -far && b.hi.x < far && b.hi.y < far && b.hi.z < far;
}

// Cells in r, or more than kMaxCellsPerCollider when any side alone has more (a product of three
// sides of up to 2e9 cells would overflow).
uint64_t cell_count(const CellRange& r) {
    uint64_t n = 1;
    for (int a = 0; a < 3; ++a) {
        const int64_t side = int64_t(r.hi[a]) - r.lo[a] + 1;
        if (side > int64_t(kMaxCellsPerCollider)) return uint64_t(kMaxCellsPerCollider) + 1;
        n *= uint64_t(side);
    }
    return n;
}

// Calls f(bucket) once for every bucket that collider range r hashes into (a bucket met twice
// by r is skipped the second time: `last` holds, per bucket, the last collider listed there).
template <class F>
void for_each_bucket(const CellRange& r, uint32_t mask, uint32_t k, std::vector<uint32_t>& last, F&& f) {
    for (int32_t z = r.lo[2]; z <= r.hi[2]; ++z)
        for (int32_t y = r.lo[1]; y <= r.hi[1]; ++y)
            for (int32_t x = r.lo[0]; x <= r.hi[0]; ++x) {
                const uint32_t b = coarse_bucket(x, y, z, mask);
                if (last[b] == k) continue;
                last[b] = k;
                f(b);
            }
}

}  // namespace

ColliderGridCapacity collider_grid_capacity(uint32_t max_colliders) {
    ColliderGridCapacity c;
    if (max_colliders <= kLinearColliders) return c;
    c.entries = uint32_t(std::min<uint64_t>(kMaxEntries, uint64_t(max_colliders) * 32));
    c.buckets = std::min(kMaxBuckets, next_pow2(2 * c.entries));
    return c;
}

void build_collider_grid(const std::vector<Collider>& shapes, float query_reach, const ColliderGridCapacity& cap,
                         ColliderGridLists* out) {
    out->grid = ColliderGrid{};
    out->bucket_begin.clear();
    out->entries.clear();
    const uint32_t n = uint32_t(shapes.size());
    if (n <= kLinearColliders || cap.buckets == 0) return;
    // The pad exceeds the queries' reach by 5 %, and by 1e-5 of the farthest coordinate: the
    // rounding of a query's shrunk box far from the origin (float: ~1e-7 relative per operation).
    float far = 0.0f;
    std::vector<float> sides;
    for (const Collider& c : shapes) {
        if (!bounded(c.bounds)) continue;
        const Bounds& b = c.bounds;
        far = std::max({far, std::fabs(b.lo.x), std::fabs(b.lo.y), std::fabs(b.lo.z), std::fabs(b.hi.x),
                        std::fabs(b.hi.y), std::fabs(b.hi.z)});
        sides.push_back(std::max({b.hi.x - b.lo.x, b.hi.y - b.lo.y, b.hi.z - b.lo.z}));
    }
    if (sides.size() <= kLinearColliders) return;
    ColliderGrid& g = out->grid;
    g.query_reach = query_reach;
    const float pad = 1.05f * query_reach + 1e-5f * far;
    // Cells half as large as the median collider's padded box: a typical collider is listed in
    // 8-27 cells, and a cell's list holds few more colliders than meet it (with cells as large
    // as the box, about 7 for 1 in a lattice of boxes).
    std::nth_element(sides.begin(), sides.begin() + sides.size() / 2, sides.end());
    g.inv_cell = 2.0f / (sides[sides.size() / 2] + 2.0f * pad);

    // Which colliders are listed: bounded ones within kMaxCellsPerCollider cells, while the
    // entries last (each listed collider takes at most its cell count).
    // n entries stay in reserve for the colliders that end up walked by every query.
    std::vector<uint8_t> listed(n, 0);
    std::vector<CellRange> ranges(n);
    uint64_t budget = cap.entries > n ? cap.entries - n : 0, unbinned = 0, listed_cells = 0;
    for (uint32_t k = 0; k < n; ++k) {
        if (bounded(shapes[k].bounds)) {
            ranges[k] = collider_cells(shapes[k].bounds, pad, g.inv_cell);
            const uint64_t cells = cell_count(ranges[k]);
            if (cells <= kMaxCellsPerCollider && cells <= budget) {
                listed[k] = 1;
                budget -= cells;
                listed_cells += cells;
                continue;
            }
        }
        ++unbinned;
    }
    if (listed_cells == 0) {
        out->grid = ColliderGrid{};
        return;
    }
    g.bucket_mask = std::min(cap.buckets, next_pow2(uint32_t(2 * listed_cells))) - 1;
    g.unbinned = uint32_t(unbinned);
    const uint32_t buckets = g.bucket_mask + 1;

    // Count, scan, fill (the always-walked colliders first).
    std::vector<uint32_t> counts(buckets, 0), last(buckets, ~0u);
    for (uint32_t k = 0; k < n; ++k) {
        if (listed[k])
            for_each_bucket(ranges[k], g.bucket_mask, k, last, [&](uint32_t b) { ++counts[b]; });
        else
            out->entries.push_back(k);
    }
    out->bucket_begin.resize(buckets + 1);
    uint32_t offset = g.unbinned;
    for (uint32_t b = 0; b < buckets; ++b) {
        out->bucket_begin[b] = offset;
        offset += counts[b];
    }
    out->bucket_begin[buckets] = offset;
    out->entries.resize(offset);
    std::fill(last.begin(), last.end(), ~0u);
    std::vector<uint32_t> cursor(out->bucket_begin.begin(), out->bucket_begin.end() - 1);
    for (uint32_t k = 0; k < n; ++k)
        if (listed[k])
            for_each_bucket(ranges[k], g.bucket_mask, k, last, [&](uint32_t b) { out->entries[cursor[b]++] = k; });
}

}  // namespace pbf
