// Uniform grid of cell size h over the domain, particles sorted by cell (x fastest), so the
// cells x-1..x+1 of one row are one contiguous range of sorted particles: 9 ranges, not 27.
#pragma once
#include "params.h"

namespace pbf {

PBF_HD int32_t clamp_cell(int32_t c, int32_t n) { return c < 0 ? 0 : (c >= n ? n - 1 : c); }

PBF_HD void cell_coords(const GridDims& g, Vec3 p, int32_t& cx, int32_t& cy, int32_t& cz) {
    // Clamped, so a particle outside the grid (only possible transiently) still gets a cell.
    cx = clamp_cell(static_cast<int32_t>(floorf((p.x - g.origin.x) * g.inv_cell)), g.nx);
    cy = clamp_cell(static_cast<int32_t>(floorf((p.y - g.origin.y) * g.inv_cell)), g.ny);
    cz = clamp_cell(static_cast<int32_t>(floorf((p.z - g.origin.z) * g.inv_cell)), g.nz);
}

PBF_HD uint32_t cell_key(const GridDims& g, Vec3 p) {
    int32_t cx, cy, cz;
    cell_coords(g, p, cx, cy, cz);
    return (static_cast<uint32_t>(cz) * static_cast<uint32_t>(g.ny) + static_cast<uint32_t>(cy)) *
               static_cast<uint32_t>(g.nx) + static_cast<uint32_t>(cx);
}

// Calls visit(j) for every particle j in the 27 cells around p (including p's own particle).
// cell_begin[c] is the first sorted index whose cell is >= c; cell_begin[num_cells] = count.
template <class Visit>
PBF_HD void for_each_neighbor(const GridDims& g, const uint32_t* cell_begin, Vec3 p, Visit&& visit) {
    int32_t cx, cy, cz;
    cell_coords(g, p, cx, cy, cz);
    const int32_t x0 = cx > 0 ? cx - 1 : 0;
    const int32_t x1 = cx + 1 < g.nx ? cx + 1 : g.nx - 1;
    const int32_t y0 = cy > 0 ? cy - 1 : 0, y1 = cy + 1 < g.ny ? cy + 1 : g.ny - 1;
    const int32_t z0 = cz > 0 ? cz - 1 : 0, z1 = cz + 1 < g.nz ? cz + 1 : g.nz - 1;
    for (int32_t z = z0; z <= z1; ++z) {
        for (int32_t y = y0; y <= y1; ++y) {
            const uint32_t row = (static_cast<uint32_t>(z) * g.ny + static_cast<uint32_t>(y)) * g.nx;
            const uint32_t begin = cell_begin[row + x0];
            const uint32_t end = cell_begin[row + x1 + 1];
            for (uint32_t j = begin; j < end; ++j) visit(j);
        }
    }
}

}  // namespace pbf
