// Every limit of a world, in one place, each checked against the public header's PBF_MAX_*
// macro where a user needs it (so the two cannot drift apart). Why each has its value is said
// beside it.
#pragma once
#include <cstdint>

#include "pbf_c_api.h"

namespace pbf {

// Materials a world holds (the default one included). Each particle carries its slot as one
// byte; eight keep the per-slot tables small enough to travel by value with every op.
constexpr uint32_t kMaxMaterials = 8;
static_assert(kMaxMaterials == PBF_MAX_MATERIALS, "the public header states the material limit");

// Substeps per frame step (solver.substeps and solver.max_substeps).
constexpr uint32_t kMaxSubsteps = 64;
static_assert(kMaxSubsteps == PBF_MAX_SUBSTEPS, "the public header states the substep limit");

// The shortest time a step or substep simulates (s). Positions are float32: a particle 1 m from
// the origin is resolved to 1.2e-7 m, so its velocity, the motion of a substep over its length,
// to 1.2e-7 m / Δt: 1.2 m/s at 1e-7 s (a drop in zero gravity stepped so lost a quarter of its
// momentum, its velocities rounded to 0 or 13.6 m/s), 1.2e-3 m/s at this limit, 0.012 m/s 10 m
// out. A frame step shorter than this advances nothing and carries its dt into the next step's;
// no frame step is split into substeps shorter than this.
constexpr float kMinStepDt = 1e-4f;
static_assert(kMinStepDt == PBF_MIN_STEP_DT, "the public header states the shortest step");

// The largest max_colliders a world may ask for. Each step uploads its colliders' shapes (76 B
// each) and start and end poses (56 B each) through pinned staging slots of 256 KB without a
// host wait: 2048 keep each upload within one slot. On the backend a world holds 2 pose rows
// of 48 B per collider (a substep's start and end, interpolated as the substeps run: 196 KB at
// 2048); every particle pass tests the colliders its coarse cell lists (collider_grid.h).
constexpr uint32_t kMaxColliderCapacity = 2048;
static_assert(kMaxColliderCapacity == PBF_MAX_COLLIDERS, "the public header states the collider limit");

// Rows of a world's mesh table (MeshView, 48 B each, allocated with the world): meshes alive at
// once. The fields themselves are allocated per mesh at its creation.
constexpr uint32_t kMaxMeshes = 256;
static_assert(kMaxMeshes == PBF_MAX_MESHES, "the public header states the mesh limit");

// The largest field a mesh may have (8 bytes per voxel: a distance and a boundary share; its
// build also holds its triangles and their brick lists for the time of the build).
constexpr uint64_t kMaxMeshFieldBytes = 256ull << 20;
static_assert(kMaxMeshFieldBytes == PBF_MAX_MESH_FIELD_BYTES, "the public header states the mesh field limit");

}  // namespace pbf
