// The build of a mesh's distance field on either executor: uploads the prepared mesh, runs
// SdfBrickWindingOp per brick, SdfVoxelOp and SdfBoundaryOp per grid point (core/sdf.h), waits for them and
// frees everything but the field.
#pragma once
#include <string>

#include "mesh_input.h"
#include "../common/status.h"

namespace pbf {

template <class Exec>
Status build_mesh_field(Exec& exec, const MeshBuild& b, float** out_values) {
    const size_t voxels = size_t(b.grid.nx) * size_t(b.grid.ny) * size_t(b.grid.nz);
    const size_t bricks = size_t(b.bricks[0]) * size_t(b.bricks[1]) * size_t(b.bricks[2]);
    Vec3* vertices = exec.template alloc<Vec3>(b.vertices.size());
    uint32_t* indices = exec.template alloc<uint32_t>(b.indices.size());
    uint32_t* begin = exec.template alloc<uint32_t>(b.brick_begin.size());
    uint32_t* listed = exec.template alloc<uint32_t>(b.brick_triangles.size() + 1);
    float* winding = exec.template alloc<float>(2 * bricks);
    float* values = exec.template alloc<float>(2 * voxels);  // distances, then the boundary shares
    auto release_build = [&] {
        exec.release(vertices);
        exec.release(indices);
        exec.release(begin);
        exec.release(listed);
        exec.release(winding);
    };
    if (!vertices || !indices || !begin || !listed || !winding || !values) {
        release_build();
        exec.release(values);
        return Status::error(PBF_ERROR_OUT_OF_MEMORY, "cannot allocate a mesh's distance field of " +
                                                           std::to_string(voxels) + " voxels on " + exec.device_name() +
                                                           ": " + exec.last_error_text());
    }
    exec.upload(vertices, b.vertices.data(), b.vertices.size() * sizeof(Vec3));
    exec.upload(indices, b.indices.data(), b.indices.size() * sizeof(uint32_t));
    exec.upload(begin, b.brick_begin.data(), b.brick_begin.size() * sizeof(uint32_t));
    exec.upload(listed, b.brick_triangles.data(), b.brick_triangles.size() * sizeof(uint32_t));
    const SdfSource src{vertices, indices, uint32_t(b.indices.size() / 3), begin, listed,
                        b.bricks[0], b.bricks[1], b.bricks[2]};
    exec.for_each(uint32_t(bricks), SdfBrickWindingOp{src, b.grid, winding});
    exec.for_each(uint32_t(voxels), SdfVoxelOp{src, b.grid, winding, b.closed, b.half_thickness, values});
    MeshView field = b.grid;
    field.values = values;
    exec.for_each(uint32_t(voxels), SdfBoundaryOp{field, b.kernel_radius, values + voxels});
    // Waits for the build (a download is a host wait): the temporaries are then free to go, and
    // the creation call returns with the field complete.
    float probe = 0.0f;
    exec.download(&probe, values, sizeof probe);
    release_build();
    Status st = exec.check("building a mesh's distance field");
    if (!st.ok()) {
        exec.release(values);
        return st;
    }
    *out_values = values;
    return st;
}

}  // namespace pbf
