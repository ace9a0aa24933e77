// Meshes of a world: the layout of a mesh's distance field, the host's part of its
// build (bounds, the non-degenerate triangles; the backend bins and builds), and the mesh
// table's slots.
#include <algorithm>
#include <cmath>
#include <string>

#include "world.h"

#include "../solver/backend.h"

namespace pbf {

MeshLayout World::mesh_layout(const pbf_mesh_desc& d) const {
    return pbf::mesh_layout(d, desc_.particle_radius, constants_.h);
}

MeshLayout mesh_layout(const pbf_mesh_desc& d, float r, float h) {
    MeshLayout l;
    Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t k = 0; k < d.vertex_count; ++k) {
        const Vec3 v{d.vertices[3 * k], d.vertices[3 * k + 1], d.vertices[3 * k + 2]};
        lo = min3(lo, v);
        hi = max3(hi, v);
    }
    const float cell = d.cell_size > 0.0f ? d.cell_size : r;
    l.half_thickness = d.closed ? 0.0f : 0.5f * (d.thickness > 0.0f ? d.thickness : 2.0f * r);
    // Contact looks one radius out and boundary density h: band = h + 2 cells keeps every cell a
    // particle within h samples free of clamped corners.
    const float band = h + 2.0f * cell;
    const float pad = band + l.half_thickness + 2.0f * cell;
    // Distances need the triangles within the band; the margin is wider because far triangles
    // are summed per brick (SdfBrickWindingOp): 2 bricks keep their error small.
    l.margin = std::max(band + l.half_thickness, 2.0f * float(kSdfBrick) * cell);
    double voxels = 1.0;
    int32_t n[3];
    const float extent[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
    for (int a = 0; a < 3; ++a) {
        const double points = std::ceil((double(extent[a]) + 2.0 * pad) / cell) + 1.0;
        voxels *= points;
        n[a] = int32_t(std::min(points, 2.0e9));
        l.bricks[a] = (n[a] + kSdfBrick - 1) / kSdfBrick;
    }
    l.voxels = uint64_t(std::min(voxels, 1.8e19));
    l.grid.origin = lo - Vec3{pad, pad, pad};
    l.grid.cell = cell;
    l.grid.inv_cell = 1.0f / cell;
    l.grid.nx = n[0];
    l.grid.ny = n[1];
    l.grid.nz = n[2];
    l.grid.band = band;
    l.kernel_radius = h;
    return l;
}

MeshBuild prepare_mesh(const pbf_mesh_desc& d, const MeshLayout& l, float* reach) {
    MeshBuild b;
    b.grid = l.grid;
    std::copy(l.bricks, l.bricks + 3, b.bricks);
    b.margin = l.margin;
    b.closed = d.closed;
    b.half_thickness = l.half_thickness;
    b.kernel_radius = l.kernel_radius;
    *reach = 0.0f;
    b.vertices.resize(d.vertex_count);
    for (uint32_t k = 0; k < d.vertex_count; ++k) {
        b.vertices[k] = Vec3{d.vertices[3 * k], d.vertices[3 * k + 1], d.vertices[3 * k + 2]};
        *reach = std::max(*reach, length(b.vertices[k]));
    }
    *reach += l.half_thickness;
    // The brick lists' length is known on the backend only; this bound (the bricks of each
    // triangle's grown bounds) lets the build refuse lists beyond 2^31 entries up front.
    const SdfBricks bricks{l.grid, l.bricks[0], l.bricks[1], l.bricks[2], l.margin};
    b.indices.reserve(size_t(d.triangle_count) * 3);
    for (uint32_t t = 0; t < d.triangle_count; ++t) {
        const uint32_t* i = d.indices + 3 * t;
        const Vec3 v0 = b.vertices[i[0]], v1 = b.vertices[i[1]], v2 = b.vertices[i[2]];
        if (triangle_degenerate(v0, v1, v2)) continue;
        b.indices.insert(b.indices.end(), i, i + 3);
        int32_t first[3], last[3];
        if (brick_range(bricks, v0, v1, v2, first, last))
            b.listing_bound +=
                uint64_t(last[0] - first[0] + 1) * uint64_t(last[1] - first[1] + 1) * uint64_t(last[2] - first[2] + 1);
    }
    return b;
}

Status World::create_mesh(const pbf_mesh_desc& d, pbf_mesh_id* out) {
    if (meshes_.size() >= kMaxMeshes)
        return Status::error(PBF_ERROR_CAPACITY, "the world holds " + std::to_string(kMaxMeshes) + " meshes already");
    MeshEntry entry;
    const MeshBuild b = prepare_mesh(d, mesh_layout(d), &entry.reach);
    const auto h = meshes_.insert(entry);
    Status st = backend_->create_mesh(b, h.index);
    if (!st.ok()) {
        meshes_.erase(h.index, h.generation);
        return st;
    }
    *out = pbf_mesh_id{h.index, h.generation};
    return st;
}

Status World::destroy_mesh(pbf_mesh_id id) {
    const MeshEntry* m = meshes_.find(id.index, id.generation);
    if (!m) return Status::error(PBF_ERROR_INVALID_HANDLE, "mesh is not live");
    if (m->users > 0)
        return Status::error(PBF_ERROR_INVALID_STATE,
                             std::to_string(m->users) + " collider(s) use the mesh: destroy them first");
    backend_->destroy_mesh(id.index);
    meshes_.erase(id.index, id.generation);
    return Status{};
}

}  // namespace pbf
