// The solver layer's door for the world: what a world asks of its compute backend, and what one
// substep needs. One implementation, Solver<Exec> (solver.h), runs the same passes on either
// executor (native/exec): CpuExec (OpenMP) or CudaExec (one stream per world); the factories
// are in solver_cpu.cpp and solver_cuda.cpp.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "../exec/exec_common.h"
#include "../common/live_buffers.h"
#include "../common/status.h"
#include "../core/limits.h"
#include "../core/params.h"
#include "../core/diffuse_ops.h"
#include "../core/render_ops.h"
#include "../core/step_ops.h"
#include "mesh_input.h"
#include "pbf_c_api.h"

namespace pbf {

struct NozzleEmission {
    uint32_t count;     // particles this substep
    uint32_t sequence;  // running spiral index
    uint32_t disc_points;
    Vec3 center, direction, tangent, bitangent;
    float radius, speed;
    uint8_t material = 0;  // the particles' material slot
};

struct DrainBox {
    Vec3 box_min, box_max;
};

// Everything one substep needs; built by the world on the host. The solver points
// ctx.colliders at the substep's poses in backend memory.
struct SubstepInput {
    StepContext ctx{};
    std::vector<NozzleEmission> nozzles;
    std::vector<DrainBox> drains;
    uint32_t iterations = 1;
    bool settle_overlaps = false;  // first move particles out of colliders, positions only (SettleOverlapOp)
};

// One pbf_world_step: its substeps and the colliders they see. Each collider moves from its
// key's start to its end over the step; the solver interpolates the substeps' poses on the
// backend. dynamic_count: colliders flagged kColliderDynamic; frame_dt: the frame step's length
// (a dynamic collider's force is its impulse over it); simulated_dt: the time the substeps
// advance, frame_dt unless the frame was longer than they hold (step_plan.cpp, held_substep).
struct StepInput {
    std::vector<SubstepInput> substeps;
    std::vector<Collider> collider_shapes;
    std::vector<ColliderKey> collider_keys;
    uint32_t dynamic_count = 0;
    float frame_dt = 0.0f;
    float simulated_dt = 0.0f;
    bool colliders_cut = false;  // a moving collider's path was cut to simulated_dt: the rest, a teleport
    float carried_dt = 0.0f;     // a frame too short to simulate (kMinStepDt): its time, for the next step
};

// Colliders standing still (between steps): keys whose start is their end.
struct ColliderSetAtRest {
    std::vector<Collider> shapes;
    std::vector<ColliderKey> keys;
};

struct BlockEmission {
    Vec3 origin;  // first particle centre
    float spacing;
    uint32_t nx, ny, nz;
    Vec3 velocity;
    uint8_t material = 0;  // the particles' material slot
};

// Stages of a step, for pbf_bench's per-stage table (profiling on: the step is timed stage by
// stage, which costs a wait per read-out; off by default).
enum Stage : int {
    kStageEmitDrain,
    kStageGridX,
    kStageDensityX,
    kStageForcesPredict,
    kStageGridPredicted,
    kStageLambda,
    kStageDeltaCollide,
    kStageVorticity,
    kStageVorticityXsph,
    kStageDensityEnd,
    kStageRender,          // render data (only in worlds that ask for it)
    kStageDiffuse,         // diffuse sources: normals and counts (only in worlds with a diffuse capacity)
    kStageMaterialForces,  // surface tension, cohesion, adhesion (only in worlds that use them)
    kStageDiffuseAdvect,   // diffuse particles moved, generated and packed (diffuse capacity only)
    kStageCount
};
static_assert(kStageCount <= PBF_PROFILE_MAX_STAGES, "pbf_step_profile holds every stage");
const char* stage_name(int stage);
struct StageTimes {
    float ms[kStageCount] = {};
};

struct BackendConfig {
    uint32_t capacity;
    uint32_t max_colliders;
    GridDims grid;
    int32_t cuda_device;
    RenderConstants render;    // flags 0: no render buffers are allocated and no pass runs
    DiffuseConstants diffuse;  // capacity 0: no diffuse buffers and no pass
    float kernel_radius;       // h: the reach of the colliders' broad-phase queries
};

class Backend {
public:
    virtual ~Backend() = default;
    virtual pbf_backend kind() const = 0;
    virtual std::string device_name() const = 0;
    virtual uint64_t device_bytes() const = 0;

    // Queues the substeps of one pbf_world_step; on CUDA, returns without waiting.
    virtual Status step(const WorldConstants& constants, const StepInput& input) = 0;
    // The latest finished step's feedback, without waiting (a step still running on the
    // device is not waited for: the one before it answers).
    virtual StepFeedback feedback() = 0;
    // The colliders between steps (for densities outside a step): after the world creates or
    // destroys one. A step leaves them at its end poses itself.
    virtual Status set_colliders_at_rest(const ColliderSetAtRest& colliders) = 0;
    // The fluid's force on the dynamic colliders over the last step, max_colliders rows indexed
    // by Collider::row. collider_forces waits for the step and copies the table to the host
    // once per step (*rows points into the backend's copy, valid until the next step or clear);
    // collider_force_table is the table in backend memory, written at the end of each step.
    virtual Status collider_forces(const ColliderForce** rows) = 0;
    virtual const ColliderForce* collider_force_table() const = 0;
    // Zeroes one row (a collider created there has felt nothing yet).
    virtual Status clear_collider_force(uint32_t row) = 0;
    // Zeroes every row, in order after the steps queued before (a step too short to simulate
    // gave no collider an impulse).
    virtual Status clear_collider_forces() = 0;
    // Builds a mesh's distance field into row `row` of the mesh table (waits for the build), and
    // frees it (no collider may use the row any more).
    virtual Status create_mesh(const MeshBuild& mesh, uint32_t row) = 0;
    virtual void destroy_mesh(uint32_t row) = 0;
    // Emits a lattice block (waits for the device); *emitted = particles that fitted.
    virtual Status emit_block(const BlockEmission& block, const WorldConstants& constants, uint32_t* emitted) = 0;
    virtual Status particle_count(uint32_t* count) = 0;
    // Copy-out of one buffer in storage order (out holds max_count elements of
    // buffer_element_bytes(source)); the source must exist (live_buffer non-null).
    virtual Status copy_buffer(pbf_buffer source, void* out, uint32_t max_count, uint32_t* written) = 0;
    // New render constants from the next pass on (flags unchanged: the buffers are the creation's).
    virtual void set_render_constants(const RenderConstants& render) = 0;
    // Render passes run so far (steps and emissions that computed render data).
    virtual uint64_t render_updates() const = 0;
    // Bytes of the render buffers (0 when the world computes none).
    virtual uint64_t render_bytes() const = 0;
    // Diffuse particles: new constants from the next step on (capacity unchanged), passes run so
    // far, bytes of their buffers (0 without a diffuse capacity).
    virtual void set_diffuse_constants(const DiffuseConstants& diffuse) = 0;
    virtual uint64_t diffuse_updates() const = 0;
    virtual uint64_t diffuse_bytes() const = 0;
    // Appends n diffuse particles (rows: n positions, then n velocities) while they fit (waits
    // for the backend); *added says how many.
    virtual Status add_diffuse(const Vec4* rows, uint32_t n, uint32_t* added) = 0;
    virtual Status diffuse_count(uint32_t* count) = 0;  // waits for the backend
    // Densities at the current positions, then sums over particles (waits for the device).
    virtual Status read_stats(const WorldConstants& constants, StatsReadback* out) = 0;
    // Milliseconds the last step took on the backend (waits for it).
    virtual Status last_step_ms(float* ms) = 0;
    // For zero-copy interop. The world's CUDA stream (null on the CPU backend).
    virtual void* cuda_stream() const = 0;
    // The live buffers in backend memory, without waiting or reading anything back: valid until
    // the next step, emission or world destruction (a step reorders and swaps them).
    virtual LiveBuffers live_buffers() = 0;
    // Runs the world on stream (a cudaStream_t; null: the world's own stream again). Work queued
    // before the switch is ordered before work queued after it. CUDA only.
    virtual Status set_cuda_stream(void* stream) = 0;
    virtual void set_profiling(bool on) = 0;
    // Per-stage milliseconds of the last step (waits for it); zeros unless profiling is on.
    virtual Status stage_times(StageTimes* out) = 0;
};

// Factories; each returns null and sets *status on failure.
std::unique_ptr<Backend> create_cpu_backend(const BackendConfig& config, Status* status);
std::unique_ptr<Backend> create_cuda_backend(const BackendConfig& config, Status* status);

}  // namespace pbf
