// What every per-particle operation receives by value (host and device): the world's constants,
// computed once when the world is created or its parameters change, and the step context of
// one substep (Δt and everything derived from it); the step plan (solver/step_plan.h) derives both.
#pragma once
#include <cstdint>
#include "limits.h"
#include "vec.h"

namespace pbf {

// A dead particle (or an unused slot) sorts after every cell: its key is the cell count.
constexpr uint32_t kDeadId = 0xFFFFFFFFu;

// The id of the k-th particle after next_id: ids count 0, 1, ..., 0xFFFFFFFE and wrap to 0, never
// reaching kDeadId (a live particle with that id would be dropped as drained).
PBF_HD uint32_t particle_id(uint32_t next_id, uint64_t k) {
    return static_cast<uint32_t>((uint64_t(next_id) + k) % uint64_t(kDeadId));
}

// The neighbour grid (grid.h): cells of size h; a cell's key is
// (cx + stride_y·cy + stride_z·cz) & key_mask. Dense: the cells of the domain box, x fastest
// (stride_y = nx, stride_z = nx·ny, key_mask all ones). Hashed (open levels, huge boxes): the
// same linear form modulo num_cells, a power of two sized from the capacity (grid.h says why).
struct GridDims {
    Vec3 origin;               // lower corner of cell (0,0,0)
    float inv_cell;            // 1 / cell size (cell size = h)
    int32_t lo_x, lo_y, lo_z;  // binning clamps cell coordinates to [lo, hi]
    int32_t hi_x, hi_y, hi_z;
    uint32_t stride_y, stride_z;
    uint32_t key_mask;
    uint32_t num_cells;  // keys are 0..num_cells-1; num_cells is also the key of dead particles
    uint32_t hashed;     // 1: keys wrap modulo num_cells and neighbour rows are never clipped
};

enum ColliderShape : uint32_t { kShapePlane = 1, kShapeSphere = 2, kShapeCapsule = 3, kShapeBox = 4, kShapeMesh = 5 };

struct MeshView;  // a mesh's distance field (sdf.h)

struct ColliderPose {
    Vec3 position;
    Mat3 rotation;  // body axes in world space
};

// A quaternion (x, y, z, w); unit length wherever it describes a rotation.
struct Quat {
    float x, y, z, w;
};

// Collider flags.
constexpr uint32_t kColliderDynamic = 1u;  // the fluid's force and torque on it are accumulated

// An axis-aligned box in world space.
struct Bounds {
    Vec3 lo, hi;
};

// A collider's shape and what a step knows about it; its poses live beside it (ColliderView).
struct Collider {
    uint32_t shape;
    float radius;  // sphere, capsule; mesh: the reach of its solid from its origin
    float half_height;
    float friction;  // Coulomb coefficient μ
    Vec3 half_extents;
    uint32_t flags;     // kCollider*
    uint32_t row;       // its row of the force tables (the collider handle's index)
    Vec3 center_local;  // the point torques are taken about, in the body frame
    Bounds bounds;      // contains the collider at every pose of the step (the broad phase)
    uint32_t mesh;      // kShapeMesh: its row of the mesh table (ColliderView::meshes)
};

// Where a collider starts and ends a step (or, between steps, stands: from = to).
struct ColliderKey {
    Vec3 from_position, to_position;
    Quat from_rotation, to_rotation;
};

// What the fluid gave a dynamic collider: an impulse and its moment during a step (N·s, N·m·s),
// or, once the step is over, their mean rate (N, N·m). Rows as pbf_collider_force.
struct ColliderForce {
    Vec3 force;
    Vec3 torque;
};

// The colliders' broad phase (collider_grid.h), in backend memory: entries[0, unbinned) are
// walked by every query; bucket b lists entries[bucket_begin[b], bucket_begin[b + 1]).
// bucket_begin null: no grid (few colliders), every query walks them all.
struct ColliderGrid {
    const uint32_t* bucket_begin = nullptr;  // bucket_mask + 2 offsets into entries
    const uint32_t* entries = nullptr;       // collider indices
    uint32_t bucket_mask = 0;                // buckets - 1 (a power of two)
    uint32_t unbinned = 0;
    float inv_cell = 0.0f;     // 1 / the coarse cell's side
    float query_reach = 0.0f;  // the widest query margin (h); the lists' pad exceeds it
};

// What the passes carry. A measurement build (cmake -DPBF_FEATURELESS=ON, never shipped)
// compiles colliders and materials out of every pass, so that a world using neither can be timed
// against kernels that never had them: what those features cost a world that leaves them off.
#ifdef PBF_FEATURELESS
constexpr bool kCollidersBuilt = false, kMaterialsBuilt = false;
#else
constexpr bool kCollidersBuilt = true, kMaterialsBuilt = true;
#endif

// The colliders of one substep, in backend memory: shapes[k] moves from prev[k] (the substep's
// start) to cur[k] (its end). Outside a step, prev = cur = the poses the last step reached.
// impulses: where position corrections of dynamic colliders' contacts go (null: nowhere, e.g.
// outside a step); impulse_scale = m / Δt turns a particle's displacement into its impulse.
struct ColliderView {
    const Collider* shapes = nullptr;
    const ColliderPose* prev = nullptr;
    const ColliderPose* cur = nullptr;
    uint32_t count = 0;
    uint32_t dynamic_count = 0;
    ColliderForce* impulses = nullptr;
    float impulse_scale = 0.0f;
    const MeshView* meshes = nullptr;  // the world's mesh table (rows named by Collider::mesh)
    ColliderGrid grid;                 // the broad phase over shapes' bounds
};

// ---- fluid materials -------------------------------------------------------------------------
// A world holds up to kMaxMaterials materials (limits.h); each particle carries its slot as one
// byte (slot 0 is the default material: the world's rest density and solver parameters), which
// keeps a particle at capacity within 128 B.
constexpr uint32_t kMaterialMultiphase = 1u;  // some material's rest density differs from slot 0's
constexpr uint32_t kMaterialSurface = 2u;     // some material has surface tension, cohesion or adhesion
struct MaterialConstants {
    uint32_t flags;                        // kMaterial*; 0: the single-fluid passes, unchanged
    float inv_mass[kMaxMaterials];         // w_k = ρ0_slot0 / ρ0_k: the inverse mass relative to slot 0
    float surface_tension[kMaxMaterials];  // 1/s² (material_ops.h)
    float cohesion[kMaxMaterials];         // 1/s²
    float adhesion[kMaxMaterials];         // 1/s²
};

struct WorldConstants {
    // geometry and mass
    float radius;  // particle radius (collision distance to walls and colliders)
    float h, h2;   // kernel radius
    float mass;
    float rest_density, inv_rest_density;
    float poly6_coef, spiky_coef;
    // constraint
    float rest_gradient_norm2;  // Σ_k |∇_k C|² of a particle at rest density (λ's units)
    float relaxation;           // ε of λ relative to rest_gradient_norm2
    float scorr_k, scorr_n, scorr_inv_w_dq;
    float scorr_a, scorr_b;  // s_corr's shape (ScorrShape, sph.h); its scale is in scorr_k
    // Other k, Δq or n than the defaults push pairs at or beyond the rest spacing no harder than the
    // defaults do (scorr_push, passes.h); 0 where k ≤ the default's at the reference shape.
    uint32_t scorr_bounded;
    float scorr_rest_weight;   // scorr_weight at the rest spacing
    float scorr_ref_inv_w_dq;  // 1 / W(0.2 h), the reference shape's
    float scorr_ref_k;         // the default k, in the units of scorr_k
    // velocity post-processing
    float vorticity_epsilon, max_speed;
    uint32_t ldc_enabled;
    // > 0: iterate until the mean compressive density error is below it (iterations = cap)
    float adaptive_target;
    Vec3 gravity;
    // walls: particle centres stay within [wall_min, wall_max]; the solid begins at the domain
    // box [boundary_min, boundary_max] one radius further out. An open level (desc.walls 0) has
    // no solid: boundary_* lie at ±FLT_MAX, so no particle is ever within h of them (no wall
    // density, push or adhesion), and wall_* is the open limit box (solver/step_plan.cpp) that only keeps
    // coordinates where float still resolves the kernel.
    Vec3 wall_min, wall_max;
    Vec3 boundary_min, boundary_max;
    float boundary_scale;  // γ: the half-space density integral scaled to the rest lattice
    float box_edge_scale;  // κ: the non-separable part of a box's share at its edges (box_boundary)
    GridDims grid;
    uint32_t capacity;
    MaterialConstants materials;
};

// One substep: Δt and what depends on it. Built by the step plan for each substep of a frame step.
struct StepContext {
    float dt, inv_dt;      // the substep's Δt (sub_dt), not the frame step's (StepInput::frame_dt)
    float lambda_epsilon;  // ε of λ (relaxation × the rest gradient norm)
    float error_damping;   // γ = τ / Δt: an error present at the substep's start relaxes by 1/(1 + γ)
    // The share of such an error that moves positions without giving velocity: (1 - 2/γ)² at
    // γ > 2, 0 below (passes.h, old_error_weight); 1 in the substep that settles overlaps no
    // motion made (step_plan.cpp), whose leftover compression is no motion either.
    float positional_weight;
    float ldc_k;           // LDC's K (1/s²)
    float scorr_k;         // s_corr's k of this substep: WorldConstants::scorr_k · min(1/(1 + γ), 1/(2γ²))
    float scorr_ref_k;     // the default k's, relaxed the same way (WorldConstants::scorr_bounded)
    float scorr_gap_push;  // bounded s_corr: the relaxation / (2 m/ρ0), turning a gap into a push
    float xsph_c;          // XSPH factor of this substep (the user's c is per 1/60 s)
    float speed_limit;     // min(max_speed, the travel cap · h / Δt)
    ColliderView colliders;
    uint32_t* clamped;  // counts the particles whose speed a limit cut (backend memory)
    // Materials: each particle's slot (backend memory, set by the solver), and the per-slot
    // XSPH factor and LDC K of this substep (slot 0 uses xsph_c and ldc_k above).
    const uint8_t* materials;
    float material_xsph_c[kMaxMaterials];
    float material_ldc_k[kMaxMaterials];
};

}  // namespace pbf
