// A triangle mesh on its way to the backend: the world prepares it on the host
// (bounds, grid, non-degenerate triangles); the solver builds its distance field on the backend
// with the ops of core/sdf_build.h (mesh_field.h) and keeps it in a row of its mesh table.
#pragma once
#include <cstdint>
#include <vector>

#include "../core/limits.h"
#include "../core/sdf_build.h"

namespace pbf {

struct MeshBuild {
    MeshView grid{};  // values null: the backend allocates them
    std::vector<Vec3> vertices;
    std::vector<uint32_t> indices;  // the non-degenerate triangles, 3 each
    int32_t bricks[3] = {};
    float margin = 0.0f;         // a brick lists the triangles within this distance of its points
    uint64_t listing_bound = 0;  // at least the number of (brick, triangle) pairs (brick_range's)
    uint32_t closed = 1;
    float half_thickness = 0.0f;  // open meshes: the shell's half thickness
    float kernel_radius = 0.0f;   // h, for the boundary shares
};

}  // namespace pbf
