// Uniform grid of cell size h over the domain, particles sorted by cell (x fastest), so the
// cells x-1..x+1 of one row are one contiguous range of sorted particles: 9 ranges, not 27.
#pragma once
#include "params.h"

namespace pbf {


// floor(x) as a cell index clamped to 0..n-1. The clamp happens before the conversion, so a
// particle far outside the grid (an emission at 1e30 m, say) converts no out-of-range float to
// int (undefined behaviour); NaN gives 0.
PBF_HD int32_t cell_of(float x, int32_t n) {
    const float f = floorf(x);
    return f >= 0.0f ? (f < static_cast<float>(n) ? static_cast<int32_t>(f) : n - 1) : 0;
}

PBF_HD void cell_coords(const GridDims& g, Vec3 p, int32_t& cx, int32_t& cy, int32_t& cz) {
    // Clamped, so a particle outside the grid (only possible transiently) still gets a cell.
    cx = cell_of((p.x - g.origin.x) * g.inv_cell, g.nx);
    cy = cell_of((p.y - g.origin.y) * g.inv_cell, g.ny);
    cz = cell_of((p.z - g.origin.z) * g.inv_cell, g.nz);
}

PBF_HD uint32_t cell_key(const GridDims& g, Vec3 p) {
    int32_t cx, cy, cz;
    cell_coords(g, p, cx, cy, cz);
    return (static_cast<uint32_t>(cz) * static_cast<uint32_t>(g.ny) + static_cast<uint32_t>(cy)) *
               static_cast<uint32_t>(g.nx) + static_cast<uint32_t>(cx);
}

// Distance from coordinate l (in cell units) to the cell [c, c + 1]: 0 inside it.
PBF_HD float cell_gap(float l, int32_t c) { return fmaxf(0.0f, fmaxf(float(c) - l, l - float(c + 1))); }

// The cells x0..x1 of a row that the cutoff sphere around lx (cell units, radius 1) cuts, the
// row lying ey and ez (cell_gap) away in y and z; false when the whole row is beyond the cutoff.
PBF_HD bool row_chord(const GridDims& g, float lx, float ey, float ez, int32_t& x0, int32_t& x1) {
    const float chord2 = 1.0f - ey * ey - ez * ez;
    if (chord2 <= 0.0f) return false;
    const float rx = sqrtf(chord2);
    x0 = cell_of(lx - rx, g.nx);
    x1 = cell_of(lx + rx, g.nx);
    return true;
}

// Calls visit(j) for every particle j that can lie within the cutoff h of p (p's own particle
// included). Cell size is h, so that is at most the 3x3x3 cells around p; rows (y, z) whose
// cells lie farther than h from p are skipped, and each row's x range is trimmed to the chord
// the cutoff sphere cuts through it: about 3/4 of the 27 cells are visited on average.
// cell_begin[c] is the first sorted index whose cell is >= c; cell_begin[num_cells] = count.
template <class Visit>
PBF_HD void for_each_neighbor(const GridDims& g, const uint32_t* cell_begin, Vec3 p, Visit&& visit) {
    // Position in cell units (cell size = h, so the cutoff radius is 1).
    const float lx = (p.x - g.origin.x) * g.inv_cell;
    const float ly = (p.y - g.origin.y) * g.inv_cell;
    const float lz = (p.z - g.origin.z) * g.inv_cell;
    int32_t cx, cy, cz;
    cell_coords(g, p, cx, cy, cz);
    const int32_t y0 = cy > 0 ? cy - 1 : 0, y1 = cy + 1 < g.ny ? cy + 1 : g.ny - 1;
    const int32_t z0 = cz > 0 ? cz - 1 : 0, z1 = cz + 1 < g.nz ? cz + 1 : g.nz - 1;
    for (int32_t z = z0; z <= z1; ++z) {
        const float ez = cell_gap(lz, z);
        for (int32_t y = y0; y <= y1; ++y) {
            int32_t x0, x1;
            if (!row_chord(g, lx, cell_gap(ly, y), ez, x0, x1)) continue;  // the whole row is beyond the cutoff
            const uint32_t row = (static_cast<uint32_t>(z) * g.ny + static_cast<uint32_t>(y)) * g.nx;
            const uint32_t begin = cell_begin[row + x0];
            const uint32_t end = cell_begin[row + x1 + 1];
            for (uint32_t j = begin; j < end; ++j) visit(j);
        }
    }
}

// ---- neighbour masks ------------------------------------------------------------------------
// The particles stay in x*'s cell order for the rest of a substep, so its neighbourhoods can be
// recorded once (the first λ pass) and replayed by every later pass: for each of the 9 rows
// (dy, dz) of the particle's 3x3x3 block, one bit per sorted candidate of the row's x range
// [cx-1, cx+1] says "within h of x* at the build". A replay then touches ~35 neighbours instead
// of ~160 candidates, in 36 bytes per particle. Neighbours are fixed per substep, as in Macklin
// & Müller's solver; passes still test the distance at the current positions.
constexpr int kMaskRows = 9;
// A row with more than 32 candidates (an over-packed block) is not recorded: its mask reads
// all ones and the replay walks the whole row with the distance test.
constexpr uint32_t kRowUnlisted = 0xFFFFFFFFu;

struct NeighborMasks {
    // row[r][i]: particle i's mask for row r = (dz + 1) * 3 + (dy + 1). One base pointer per row
    // (rows lie capacity entries apart in one allocation) keeps the per-particle index 32-bit at
    // any capacity: computing r * capacity + i in 64 bits cost 2 % of a 1M step on an H100.
    uint32_t* row[kMaskRows] = {};
    const uint32_t* keys = nullptr;  // sorted cell keys: the cell of x* each particle was binned in
    NeighborMasks() = default;
    PBF_HD NeighborMasks(uint32_t* storage, const uint32_t* sorted_keys, uint32_t capacity) : keys(sorted_keys) {
        for (int r = 0; r < kMaskRows; ++r) row[r] = storage ? storage + size_t(r) * capacity : nullptr;
    }
};

// Cell coordinates of a sorted key (keys of live particles are < num_cells).
PBF_HD void key_cell(const GridDims& g, uint32_t key, int32_t& cx, int32_t& cy, int32_t& cz) {
    const uint32_t row = key / static_cast<uint32_t>(g.nx);
    cx = static_cast<int32_t>(key - row * static_cast<uint32_t>(g.nx));
    cy = static_cast<int32_t>(row % static_cast<uint32_t>(g.ny));
    cz = static_cast<int32_t>(row / static_cast<uint32_t>(g.ny));
}

// Like for_each_neighbor around p = x*_i (binned under key), but calls visit(j) only for the
// candidates within h (tested against pos) and records them in masks for particle i.
template <class Visit>
PBF_HD void for_each_neighbor_recording(const GridDims& g, const uint32_t* cell_begin, const Vec4* pos, float h2,
                                        const NeighborMasks& masks, uint32_t i, Vec3 p, Visit&& visit) {
    const uint32_t key = masks.keys[i];
    if (key >= g.num_cells) {  // a dead slot past the live count: no neighbours
        for (int r = 0; r < kMaskRows; ++r) masks.row[r][i] = 0u;
        return;
    }
    int32_t cx, cy, cz;
    key_cell(g, key, cx, cy, cz);
    const float lx = (p.x - g.origin.x) * g.inv_cell;
    const float ly = (p.y - g.origin.y) * g.inv_cell;
    const float lz = (p.z - g.origin.z) * g.inv_cell;
    const int32_t xlo = cx > 0 ? cx - 1 : 0, xhi = cx + 1 < g.nx ? cx + 1 : g.nx - 1;
    for (int32_t dz = -1; dz <= 1; ++dz) {
        const int32_t z = cz + dz;
        const float ez = cell_gap(lz, z);
        for (int32_t dy = -1; dy <= 1; ++dy) {
            const int32_t y = cy + dy;
            uint32_t mask = 0u;
            int32_t c0, c1;
            if (y >= 0 && y < g.ny && z >= 0 && z < g.nz && row_chord(g, lx, cell_gap(ly, y), ez, c0, c1)) {
                const uint32_t row = (static_cast<uint32_t>(z) * g.ny + static_cast<uint32_t>(y)) * g.nx;
                const uint32_t row_begin = cell_begin[row + xlo];
                const bool listed = cell_begin[row + xhi + 1] - row_begin <= 32u;
                // Only the chord of the cutoff sphere can hold neighbours; it lies within [xlo, xhi].
                const int32_t x0 = c0 > xlo ? c0 : xlo, x1 = c1 < xhi ? c1 : xhi;
                const uint32_t end = x0 <= x1 ? cell_begin[row + x1 + 1] : 0u;
                for (uint32_t j = x0 <= x1 ? cell_begin[row + x0] : 0u; j < end; ++j) {
                    if (length_sq(p - xyz(pos[j])) >= h2) continue;
                    if (listed) mask |= 1u << (j - row_begin);
                    visit(j);
                }
                if (!listed) mask = kRowUnlisted;
            }
            masks.row[(dz + 1) * 3 + (dy + 1)][i] = mask;
        }
    }
}

// Calls visit(j) for every neighbour recorded for particle i (and every candidate of an
// unlisted row). visit tests the distance itself, as with for_each_neighbor.
// The row loop is unrolled so the 9 mask and row-start loads issue together (H100, 1M: Δp
// pass 0.174 → 0.166 ms). Measured and dropped (docs/perf.md, version 5): visiting bits in
// pairs, one loop over all rows' bits (with or without the rows opened first), untrimmed rows
// when recording, masks anchored at each row's chord (fewer unlisted rows in a compressed tank).
#if defined(__CUDACC__)  // nvcc, both its device and host passes
#define PBF_UNROLL _Pragma("unroll")
#elif defined(__clang__)
#define PBF_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define PBF_UNROLL _Pragma("GCC unroll 9")
#else
#define PBF_UNROLL
#endif
template <class Visit>
PBF_HD void for_each_listed_neighbor(const GridDims& g, const uint32_t* cell_begin, const NeighborMasks& masks,
                                     uint32_t i, Visit&& visit) {
    int32_t cx, cy, cz;
    key_cell(g, masks.keys[i], cx, cy, cz);
    const uint32_t xlo = static_cast<uint32_t>(cx > 0 ? cx - 1 : 0);
    const uint32_t xend = static_cast<uint32_t>(cx + 1 < g.nx ? cx + 1 : g.nx - 1) + 1u;
    PBF_UNROLL
    for (int r = 0; r < kMaskRows; ++r) {
        uint32_t m = masks.row[r][i];
        if (m == 0u) continue;  // also every row outside the grid
        const uint32_t y = static_cast<uint32_t>(cy + r % 3 - 1), z = static_cast<uint32_t>(cz + r / 3 - 1);
        const uint32_t row = (z * g.ny + y) * g.nx;
        const uint32_t begin = cell_begin[row + xlo];
        if (m == kRowUnlisted) {
            const uint32_t end = cell_begin[row + xend];
            if (end - begin > 32u) {
                for (uint32_t j = begin; j < end; ++j) visit(j);
                continue;
            }
        }
        do {
            visit(begin + lowest_bit(m));
            m &= m - 1u;
        } while (m != 0u);
    }
}

// Replays the masks when there are any (row pointers non-null), else walks the grid around xi.
template <class Visit>
PBF_HD void for_each_neighbor_of(const GridDims& g, const uint32_t* cell_begin, const NeighborMasks& masks,
                                 uint32_t i, Vec3 xi, Visit&& visit) {
    if (masks.row[0]) for_each_listed_neighbor(g, cell_begin, masks, i, visit);
    else for_each_neighbor(g, cell_begin, xi, visit);
}

}  // namespace pbf
