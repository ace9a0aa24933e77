// The neighbour grid: cells of size h, particles sorted by cell key, where the key of cell
// (cx, cy, cz) is linear, (cx + stride_y·cy + stride_z·cz) & key_mask, so the cells x-1..x+1 of
// one row are consecutive keys: one contiguous range of sorted particles (9 ranges, not 27).
//
// Dense: the cells of the domain box (x fastest, keys < nx·ny·nz, no wrap). Its memory grows
// with the box. Hashed (open levels, and boxes with more than 4 cells per hashed key): keys
// modulo num_cells = a power of two >= the capacity (>= 2^12), so memory depends on the fluid,
// not on the level. With stride_x = 1 a row's three cells stay consecutive keys (two ranges
// only where they wrap past num_cells). Cells whose keys collide are those whose difference v
// lies in the lattice {v : v·(1, stride_y, stride_z) ≡ 0 mod num_cells}; the strides below were
// chosen (random search, best of 60..300 per size) so that its shortest non-zero vector is long
// in every direction: ≥ 0.83·num_cells^(1/3) cells (tested). So
//  - the cells of one query (|Δx|, |Δy|, |Δz| ≤ 2 apart) never share a key: no range is visited
//    twice, no particle counted twice, without remembering which buckets a query visited;
//  - a fluid narrower than that (~45 cells at 100k capacity, ~94 at 1M) has no collision at all;
//    a wider one collides about as often as a random hash would (collisions add candidates
//    only: every pass tests the distance);
//  - a neighbour's key follows from the particle's own key (key + dx + stride_y·dy + ...), which
//    the mask replay needs, as it has no position.
// A random hash of (cz, cy, cx >> B) with blocks of 2^B cells was the alternative: it needs a
// per-query list of visited buckets to avoid double counting and splits rows at block edges.
#pragma once
#include "params.h"

namespace pbf {

// Hashed cell coordinates are clamped to ±2^30 (no float-to-int overflow at 1e30 m or inf;
// coordinates ±1 still fit in int32). Positions never get that far (the open limit box,
// solver/step_plan.cpp); only data an engine wrote straight into the device buffers could.
constexpr int32_t kHashCellLimit = 1 << 30;
constexpr uint32_t kMinHashBits = 12, kMaxHashBits = 30;

// floor(x) as a cell index clamped to lo..hi. The clamp happens before the conversion, so a
// particle far outside the grid (an emission at 1e30 m, say) converts no out-of-range float to
// int (undefined behaviour); NaN gives lo.
PBF_HD int32_t cell_of(float x, int32_t lo, int32_t hi) {
    const float f = floorf(x);
    if (!(f > static_cast<float>(lo))) return lo;
    if (f >= static_cast<float>(hi)) return hi;
    const int32_t c = static_cast<int32_t>(f);
    return c < hi ? c : hi;
}

PBF_HD void cell_coords(const GridDims& g, Vec3 p, int32_t& cx, int32_t& cy, int32_t& cz) {
    // Clamped, so a particle outside a dense grid (only possible transiently) still gets a cell.
    cx = cell_of((p.x - g.origin.x) * g.inv_cell, g.lo_x, g.hi_x);
    cy = cell_of((p.y - g.origin.y) * g.inv_cell, g.lo_y, g.hi_y);
    cz = cell_of((p.z - g.origin.z) * g.inv_cell, g.lo_z, g.hi_z);
}

// Unsigned arithmetic: exact modulo 2^32, hence modulo num_cells (a power of two) when hashed.
PBF_HD uint32_t key_of_cell(const GridDims& g, int32_t cx, int32_t cy, int32_t cz) {
    return (static_cast<uint32_t>(cx) + g.stride_y * static_cast<uint32_t>(cy) +
            g.stride_z * static_cast<uint32_t>(cz)) &
           g.key_mask;
}

PBF_HD uint32_t cell_key(const GridDims& g, Vec3 p) {
    int32_t cx, cy, cz;
    cell_coords(g, p, cx, cy, cz);
    return key_of_cell(g, cx, cy, cz);
}

// The rows around cell coordinate c: c-1..c+1, clipped to a dense grid's cells.
PBF_HD int32_t first_row(const GridDims& g, int32_t c, int32_t lo) { return g.hashed || c > lo ? c - 1 : c; }
PBF_HD int32_t last_row(const GridDims& g, int32_t c, int32_t hi) { return g.hashed || c < hi ? c + 1 : c; }

// Distance from coordinate l (in cell units) to the cell [c, c + 1]: 0 inside it.
PBF_HD float cell_gap(float l, int32_t c) { return fmaxf(0.0f, fmaxf(float(c) - l, l - float(c + 1))); }

// The cells x0..x1 of a row that the cutoff sphere around lx (cell units, radius 1) cuts, the
// row lying ey and ez (cell_gap) away in y and z; false when the whole row is beyond the cutoff.
PBF_HD bool row_chord(const GridDims& g, float lx, float ey, float ez, int32_t& x0, int32_t& x1) {
    const float chord2 = 1.0f - ey * ey - ez * ez;
    if (chord2 <= 0.0f) return false;
    const float rx = sqrtf(chord2);
    x0 = cell_of(lx - rx, g.lo_x, g.hi_x);
    x1 = cell_of(lx + rx, g.lo_x, g.hi_x);
    return true;
}

// The sorted particles of `cells` consecutive keys from `key`: indices begin..begin+first-1,
// then, where the keys wrap past num_cells (hashed grids only), 0..count-first-1.
struct KeyRun {
    uint32_t begin, first, count;
};
PBF_HD KeyRun key_run(const GridDims& g, const uint32_t* cell_begin, uint32_t key, uint32_t cells) {
    const uint32_t begin = cell_begin[key];
    const uint32_t end = key + cells;
    if (end <= g.num_cells) {
        const uint32_t c = cell_begin[end] - begin;
        return KeyRun{begin, c, c};
    }
    const uint32_t first = cell_begin[g.num_cells] - begin;
    return KeyRun{begin, first, first + cell_begin[end - g.num_cells]};  // cell_begin[0] = 0
}
// The t-th particle of a run.
PBF_HD uint32_t run_at(const KeyRun& r, uint32_t t) { return t < r.first ? r.begin + t : t - r.first; }
template <class Visit>
PBF_HD void visit_run(const KeyRun& r, Visit&& visit) {
    for (uint32_t j = r.begin; j < r.begin + r.first; ++j) visit(j);
    for (uint32_t j = 0; j < r.count - r.first; ++j) visit(j);
}

// Calls visit(j) for every particle j that can lie within the cutoff h of p (p's own particle
// included), each once. Cell size is h, so that is at most the 3x3x3 cells around p; rows
// (y, z) whose cells lie farther than h from p are skipped, and each row's x range is trimmed to
// the chord the cutoff sphere cuts through it: about 3/4 of the 27 cells are visited on average.
// cell_begin[k] is the first sorted index whose key is >= k; cell_begin[num_cells] = count.
template <class Visit>
PBF_HD void for_each_neighbor(const GridDims& g, const uint32_t* cell_begin, Vec3 p, Visit&& visit) {
    // Position in cell units (cell size = h, so the cutoff radius is 1).
    const float lx = (p.x - g.origin.x) * g.inv_cell;
    const float ly = (p.y - g.origin.y) * g.inv_cell;
    const float lz = (p.z - g.origin.z) * g.inv_cell;
    int32_t cx, cy, cz;
    cell_coords(g, p, cx, cy, cz);
    const int32_t y0 = first_row(g, cy, g.lo_y), y1 = last_row(g, cy, g.hi_y);
    const int32_t z0 = first_row(g, cz, g.lo_z), z1 = last_row(g, cz, g.hi_z);
    for (int32_t z = z0; z <= z1; ++z) {
        const float ez = cell_gap(lz, z);
        for (int32_t y = y0; y <= y1; ++y) {
            int32_t x0, x1;
            if (!row_chord(g, lx, cell_gap(ly, y), ez, x0, x1)) continue;  // the whole row is beyond the cutoff
            visit_run(key_run(g, cell_begin, key_of_cell(g, x0, y, z), static_cast<uint32_t>(x1 - x0 + 1)), visit);
        }
    }
}

// ---- building the grid's dimensions (host) ---------------------------------------------------
// (stride_y, stride_z) of the hashed grid with 2^bits keys, bits = 12..30, and the shortest
// non-zero vector of its collision lattice in cells (max(|x|, |y|, |z|)), which the unit test
// "[grid]" recomputes.
struct HashStrides {
    uint32_t stride_y, stride_z, shortest;
};
constexpr HashStrides kHashStrides[kMaxHashBits - kMinHashBits + 1] = {
    {3757u, 3771u, 14u},
    {7173u, 3119u, 18u},
    {12321u, 13925u, 24u},
    {29857u, 13881u, 29u},
    {50753u, 65157u, 39u},
    {75091u, 96967u, 45u},
    {104671u, 145331u, 58u},
    {466195u, 260861u, 73u},
    {292519u, 874927u, 94u},
    {1917459u, 737077u, 111u},
    {3354285u, 2891931u, 150u},
    {4015013u, 6714323u, 173u},
    {10595411u, 9113583u, 215u},
    {26381581u, 28592505u, 285u},
    {56440183u, 29345705u, 351u},
    {61239953u, 102398999u, 484u},
    {89459147u, 171532297u, 564u},
    {355679585u, 432332709u, 728u},
    {380173525u, 451261529u, 926u},
};

// Key bits of a hashed grid for a capacity: num_cells = the power of two >= capacity (4 to 8
// B per particle of cell_begin). A fluid at rest fills ~1/8 of the keys (8 particles a cell).
inline uint32_t hashed_grid_bits(uint32_t capacity) {
    uint32_t bits = kMinHashBits;
    while (bits < kMaxHashBits && (uint64_t(1) << bits) < capacity) ++bits;
    return bits;
}

inline GridDims dense_grid(Vec3 origin, float inv_cell, int32_t nx, int32_t ny, int32_t nz) {
    GridDims g{};
    g.origin = origin;
    g.inv_cell = inv_cell;
    g.hi_x = nx - 1;
    g.hi_y = ny - 1;
    g.hi_z = nz - 1;
    g.stride_y = static_cast<uint32_t>(nx);
    g.stride_z = static_cast<uint32_t>(nx) * static_cast<uint32_t>(ny);
    g.key_mask = 0xFFFFFFFFu;
    g.num_cells = g.stride_z * static_cast<uint32_t>(nz);
    return g;
}

inline GridDims hashed_grid(Vec3 origin, float inv_cell, uint32_t bits) {
    GridDims g{};
    g.origin = origin;
    g.inv_cell = inv_cell;
    g.lo_x = g.lo_y = g.lo_z = -kHashCellLimit;
    g.hi_x = g.hi_y = g.hi_z = kHashCellLimit;
    const HashStrides& st = kHashStrides[bits - kMinHashBits];
    g.stride_y = st.stride_y;
    g.stride_z = st.stride_z;
    g.num_cells = 1u << bits;
    g.key_mask = g.num_cells - 1u;
    g.hashed = 1u;
    return g;
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
    // any capacity, where r * capacity + i would need 64-bit arithmetic in every pass.
    uint32_t* row[kMaskRows] = {};
    const uint32_t* keys = nullptr;  // sorted cell keys: the cell of x* each particle was binned in
    NeighborMasks() = default;
    PBF_HD NeighborMasks(uint32_t* storage, const uint32_t* sorted_keys, uint32_t capacity) : keys(sorted_keys) {
        for (int r = 0; r < kMaskRows; ++r) row[r] = storage ? storage + size_t(r) * capacity : nullptr;
    }
};

// Cell coordinates of a dense grid's key (keys of live particles are < num_cells).
PBF_HD void key_cell(const GridDims& g, uint32_t key, int32_t& cx, int32_t& cy, int32_t& cz) {
    const uint32_t z = key / g.stride_z, rest = key - z * g.stride_z;
    const uint32_t y = rest / g.stride_y;
    cx = static_cast<int32_t>(rest - y * g.stride_y);
    cy = static_cast<int32_t>(y);
    cz = static_cast<int32_t>(z);
}

// The x range [cx-1, cx+1] of the rows of a particle binned under key: the key of its first
// cell in the particle's own row, and its length. A hashed row is never clipped; a dense one is
// clipped to the grid, which takes the cell's x (decoded from the key).
PBF_HD void mask_window(const GridDims& g, uint32_t key, uint32_t& base, uint32_t& cells) {
    if (g.hashed) {
        base = (key - 1u) & g.key_mask;
        cells = 3u;
        return;
    }
    int32_t cx, cy, cz;
    key_cell(g, key, cx, cy, cz);
    const int32_t xlo = first_row(g, cx, g.lo_x), xhi = last_row(g, cx, g.hi_x);
    base = key - static_cast<uint32_t>(cx - xlo);
    cells = static_cast<uint32_t>(xhi - xlo + 1);
}

// The key of the window's first cell in row r = (dz + 1) * 3 + (dy + 1).
PBF_HD uint32_t mask_row_key(const GridDims& g, uint32_t base, int r) {
    const int32_t dy = r % 3 - 1, dz = r / 3 - 1;
    return (base + g.stride_y * static_cast<uint32_t>(dy) + g.stride_z * static_cast<uint32_t>(dz)) & g.key_mask;
}

// Like for_each_neighbor around p = x*_i (binned under key), but calls visit(j) only for the
// candidates within h (tested against pos) and records them in masks for particle i: bit t of a
// row is the t-th particle of the row's window run (key_run), which a replay rebuilds from the key.
template <class Visit>
PBF_HD void for_each_neighbor_recording(const GridDims& g, const uint32_t* cell_begin, const Vec4* pos, float h2,
                                        const NeighborMasks& masks, uint32_t i, Vec3 p, Visit&& visit) {
    const uint32_t key = masks.keys[i];
    if (key >= g.num_cells) {  // a dead slot past the live count: no neighbours
        for (int r = 0; r < kMaskRows; ++r) masks.row[r][i] = 0u;
        return;
    }
    // The binned cell: decoded from a dense key; a hashed key cannot be decoded, but p is the
    // position it was binned at (the same float expression gives the same cell).
    int32_t cx, cy, cz;
    if (g.hashed)
        cell_coords(g, p, cx, cy, cz);
    else
        key_cell(g, key, cx, cy, cz);
    uint32_t base, cells;
    mask_window(g, key, base, cells);
    const int32_t xlo = first_row(g, cx, g.lo_x), xhi = xlo + static_cast<int32_t>(cells) - 1;
    const float lx = (p.x - g.origin.x) * g.inv_cell;
    const float ly = (p.y - g.origin.y) * g.inv_cell;
    const float lz = (p.z - g.origin.z) * g.inv_cell;
    for (int r = 0; r < kMaskRows; ++r) {
        const int32_t y = cy + r % 3 - 1, z = cz + r / 3 - 1;
        uint32_t mask = 0u;
        int32_t c0, c1;
        const bool in_grid = g.hashed || (y >= g.lo_y && y <= g.hi_y && z >= g.lo_z && z <= g.hi_z);
        if (in_grid && row_chord(g, lx, cell_gap(ly, y), cell_gap(lz, z), c0, c1)) {
            const uint32_t row_key = mask_row_key(g, base, r);
            const KeyRun window = key_run(g, cell_begin, row_key, cells);
            const bool listed = window.count <= 32u;
            // Only the chord of the cutoff sphere can hold neighbours; it lies within [xlo, xhi]:
            // the window's particles t0..t1-1.
            const int32_t x0 = c0 > xlo ? c0 : xlo, x1 = c1 < xhi ? c1 : xhi;
            if (x0 <= x1) {
                const uint32_t t0 = x0 > xlo ? key_run(g, cell_begin, row_key, uint32_t(x0 - xlo)).count : 0u;
                const uint32_t t1 = key_run(g, cell_begin, row_key, uint32_t(x1 - xlo + 1)).count;
                for (uint32_t t = t0; t < t1; ++t) {
                    const uint32_t j = run_at(window, t);
                    if (length_sq(p - xyz(pos[j])) >= h2) continue;
                    if (listed) mask |= 1u << t;
                    visit(j);
                }
            }
            if (!listed) mask = kRowUnlisted;
        }
        masks.row[r][i] = mask;
    }
}

// Calls visit(j) for every neighbour recorded for particle i (and every candidate of an
// unlisted row). visit tests the distance itself, as with for_each_neighbor.
// The row loop is unrolled so the 9 mask and row-start loads issue together; the variants
// measured against it are in docs/perf.md (version 5).
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
    uint32_t base, cells;
    mask_window(g, masks.keys[i], base, cells);
    PBF_UNROLL
    for (int r = 0; r < kMaskRows; ++r) {
        uint32_t m = masks.row[r][i];
        if (m == 0u) continue;  // also every row outside the grid, and every row of a dead slot
        const uint32_t row_key = mask_row_key(g, base, r);
        if (row_key + cells <= g.num_cells) {  // always on a dense grid: the loads of version 5
            const uint32_t begin = cell_begin[row_key];
            if (m == kRowUnlisted) {
                const uint32_t end = cell_begin[row_key + cells];
                if (end - begin > 32u) {
                    for (uint32_t j = begin; j < end; ++j) visit(j);
                    continue;
                }
            }
            do {
                visit(begin + lowest_bit(m));
                m &= m - 1u;
            } while (m != 0u);
            continue;
        }
        // A hashed window whose keys wrap past num_cells: its run is in two pieces.
        const KeyRun window = key_run(g, cell_begin, row_key, cells);
        if (m == kRowUnlisted && window.count > 32u) {
            visit_run(window, visit);
            continue;
        }
        do {
            visit(run_at(window, lowest_bit(m)));
            m &= m - 1u;
        } while (m != 0u);
    }
}

// Replays the masks when there are any (row pointers non-null), else walks the grid around xi.
template <class Visit>
PBF_HD void for_each_neighbor_of(const GridDims& g, const uint32_t* cell_begin, const NeighborMasks& masks, uint32_t i,
                                 Vec3 xi, Visit&& visit) {
    if (masks.row[0])
        for_each_listed_neighbor(g, cell_begin, masks, i, visit);
    else
        for_each_neighbor(g, cell_begin, xi, visit);
}

}  // namespace pbf
