// A step's physics, as pure functions: a world's parameters turned into its constants, and a
// frame turned into the plan of its substeps (StepInput). The world holds the handles and their
// state and calls these; nothing here keeps state of its own.
//
// Two step lengths meet here and are named apart: the frame step (frame_dt), what one
// pbf_world_step advances, and the substep (sub_dt, StepContext::dt), what one pass of the
// solver advances; a frame step runs one or more substeps.
#pragma once
#include <vector>

#include "backend.h"

namespace pbf {

// INVALID_ARGUMENT when a particle radius or rest density is so extreme that a constant the
// kernels use is not a normal float (every density and velocity would be NaN).
Status check_fluid(float radius, float rest_density);

// The materials as the solver sees them. Slot 0 is the default material: the world's rest
// density, and its viscosity and LDC gain are the solver parameters' xsph_c and ldc_gain.
struct MaterialTable {
    bool alive[kMaxMaterials] = {};
    pbf_material_desc desc[kMaxMaterials] = {};
};

// The world's constants from its desc (the solver parameters and gravity it holds now) and its
// materials: the rest lattice's calibration (core/lattice.h) and the neighbour grid included.
WorldConstants derive_constants(const pbf_world_desc& desc, const MaterialTable& materials);
// The render pass's constants from the desc's render params.
RenderConstants render_constants(const pbf_render_params& p, float radius, float h);
// The diffuse pass's constants from the desc's diffuse params.
DiffuseConstants diffuse_constants(const pbf_diffuse_params& p);

// XSPH's factor for a substep of sub_dt from c per 1/60 s: 1 - (1 - c)^(60 Δt).
float xsph_factor(float c, float sub_dt);
// The error damping γ of a substep of sub_dt: τ/Δt, the response time τ = h / sound_speed in
// substeps. Where old errors move positions (γ > 2, passes.h old_error_weight), the time scale
// the old error relaxes over rises from τ toward √(h/g) by the weight u² positions take
// (docs/physics.md, Error damping).
float error_damping(float tau, float h, float gravity, float sub_dt);
// A substep of sub_dt: everything that depends on its length.
StepContext substep_context(const pbf_solver_params& p, const WorldConstants& c, const MaterialTable& materials,
                            float sub_dt);

// A nozzle or drain as the step plan sees it; the plan advances accumulator and sequence.
struct EmitterState {
    pbf_emitter_desc desc;     // enabled, its direction normalised
    float accumulator = 0.0f;  // fractional particles carried between substeps
    uint32_t sequence = 0;     // the nozzle's running spiral index
    uint8_t material = 0;      // the nozzle's particles' material slot
};

// What the world knows of a frame before it steps it.
struct FrameState {
    float frame_dt = 0.0f;          // the frame step (s)
    StepFeedback feedback;          // the latest finished step's, read without waiting
    float emitted_speed = 0.0f;     // fastest particle emitted since the last step (m/s)
    float emitted_depth = 0.0f;     // tallest block emitted since the last step, along gravity (m)
    bool overlaps_pending = false;  // particles may overlap a collider without having moved into it
    float carried_dt = 0.0f;        // time earlier frame steps too short to simulate left to this one (s)
};

// Plans a frame step: its substep count and each substep's context, emissions and drains.
// input's colliders (shapes, keys, dynamic_count) are the world's, placed by place_collider;
// emitters (in the world's order) advance their accumulators and sequences. A frame step that
// with the time carried to it is shorter than kMinStepDt gets no substeps: it advances nothing,
// and input->carried_dt is its time, for the next one.
void plan_step(const pbf_solver_params& p, const WorldConstants& c, const MaterialTable& materials,
               const FrameState& frame, std::vector<EmitterState>* emitters, StepInput* input);

// A collider as a step sees it, moving over key: its bounds hold it at every pose (the broad phase).
Collider place_collider(Collider c, const ColliderKey& key);

// A block's lattice at rest spacing within the walls, at most capacity particles (material
// unset); INVALID_ARGUMENT when no lattice point lies inside the walls.
Status plan_block(const pbf_block_desc& d, const WorldConstants& c, float spacing, uint32_t capacity,
                  BlockEmission* out);
// The block's extent along gravity (m; 0 without gravity).
float block_depth(const BlockEmission& b, Vec3 gravity);
// Whether the block's particles (radius r) may reach any of the colliders' bounds.
bool block_meets(const BlockEmission& b, float r, const std::vector<Collider>& colliders);

// Particles per second a nozzle's disc carries at rest spacing.
double nozzle_capacity(const pbf_emitter_desc& d, float spacing);
// Whether p lies inside the walls (where particle centres are held).
bool inside_walls(const WorldConstants& c, Vec3 p);

}  // namespace pbf
