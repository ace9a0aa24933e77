// Constants of one substep, passed by value to every per-particle operation (host and device).
#pragma once
#include <cstdint>
#include "vec.h"

namespace pbf {

// A dead particle (or an unused slot) sorts after every cell: its key is the cell count.
constexpr uint32_t kDeadId = 0xFFFFFFFFu;

// The id of the k-th particle after next_id: ids count 0, 1, ..., 0xFFFFFFFE and wrap to 0, never
// reaching kDeadId (a live particle with that id would be dropped as drained).
PBF_HD uint32_t particle_id(uint32_t next_id, uint64_t k) {
    return static_cast<uint32_t>((uint64_t(next_id) + k) % uint64_t(kDeadId));
}

struct GridDims {
    Vec3 origin;      // lower corner of cell (0,0,0)
    float inv_cell;   // 1 / cell size (cell size = h)
    int32_t nx, ny, nz;
    uint32_t num_cells;  // nx·ny·nz; also the key of dead particles
};

enum ColliderShape : uint32_t { kShapePlane = 1, kShapeSphere = 2, kShapeCapsule = 3, kShapeBox = 4 };

// A collider at the start (prev) and end (cur) of the substep; the solver projects particles
// out of the end pose and uses the motion prev→cur for friction.
struct ColliderPose {
    Vec3 position;
    Mat3 rotation;  // body axes in world space
};

struct Collider {
    uint32_t shape;
    float radius;
    float half_height;
    float friction;
    Vec3 half_extents;
    ColliderPose prev, cur;
};

struct SimConstants {
    // geometry and mass
    float radius;        // particle radius (collision distance to walls and colliders)
    float h, h2;         // kernel radius
    float mass;
    float rest_density, inv_rest_density;
    float poly6_coef, spiky_coef;
    // constraint
    float lambda_epsilon;   // absolute ε of λ
    float scorr_k, scorr_n, scorr_inv_w_dq;
    // velocity post-processing
    float xsph_c, vorticity_epsilon, max_speed;
    // Local Density Calibration: K = gain / Δt² (1/s²)
    uint32_t ldc_enabled;
    float ldc_k;
    // > 0: iterate until the mean compressive density error is below it (iterations = cap)
    float adaptive_target;
    // time and forces
    float dt, inv_dt;
    Vec3 gravity;
    // walls: particle centres stay within [wall_min, wall_max]
    Vec3 wall_min, wall_max;
    GridDims grid;
    uint32_t capacity;
};

// Colliders travel inline in the kernel parameters of the ops that collide, so moving a
// collider needs no host-to-device copy: the step uploads nothing.
constexpr uint32_t kMaxColliders = 32;
struct ColliderSet {
    uint32_t count;
    Collider items[kMaxColliders];
};

}  // namespace pbf
