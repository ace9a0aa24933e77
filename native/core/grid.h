// Uniform grid of cell size h over the domain, particles sorted by cell (x fastest), so the
// cells x-1..x+1 of one row are one contiguous range of sorted particles: 9 ranges, not 27.
#pragma once
#include "params.h"

namespace pbf {

PBF_HD int32_t clamp_cell(int32_t c, int32_t n) { return c < 0 ? 0 : (c >= n ? n - 1 : c); }

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
        const float ez = fmaxf(0.0f, fmaxf(float(z) - lz, lz - float(z + 1)));
        for (int32_t y = y0; y <= y1; ++y) {
            const float ey = fmaxf(0.0f, fmaxf(float(y) - ly, ly - float(y + 1)));
            const float chord2 = 1.0f - ey * ey - ez * ez;
            if (chord2 <= 0.0f) continue;  // the whole row is beyond the cutoff
            const float rx = sqrtf(chord2);
            const int32_t x0 = cell_of(lx - rx, g.nx);
            const int32_t x1 = cell_of(lx + rx, g.nx);
            const uint32_t row = (static_cast<uint32_t>(z) * g.ny + static_cast<uint32_t>(y)) * g.nx;
            const uint32_t begin = cell_begin[row + x0];
            const uint32_t end = cell_begin[row + x1 + 1];
            for (uint32_t j = begin; j < end; ++j) visit(j);
        }
    }
}

}  // namespace pbf
