// Validation of the C ABI's descs, as named checks (after sokol_gfx's _sg_validate_*): each
// check has an id, the result code it fails with and one message. A validator returns the first
// check its desc fails, or Check::ok; the entry point refuses the call with that check's message.
// Internal: nothing here is exported. White-box tests compare last_validation_check() instead of
// message substrings.
#pragma once
#include <cstdint>
#include <cstring>
#include <string>

#include "pbf_c_api.h"

namespace pbf::api {

// An enum field as the 32 bits the caller stored: a C caller may store any int, and reading an
// out-of-range value through the C++ enum type is undefined behaviour.
template <class E>
int32_t raw(const E& e) {
    static_assert(sizeof(E) == sizeof(int32_t), "ABI enums are 32 bits");
    int32_t v;
    std::memcpy(&v, &e, sizeof v);
    return v;
}

// The alignment a copy destination's offset needs (1 for materials, 4 for ids, else 16); the
// bytes per element are the world's (World::element_bytes).
inline uint32_t element_alignment(pbf_buffer source) {
    return raw(source) == PBF_BUFFER_MATERIALS ? 1u : raw(source) == PBF_BUFFER_IDS ? 4u : 16u;
}

// X(id, result code, message). {a} and {b} in a message stand for the verdict's two numbers.
#define PBF_VALIDATE_CHECKS(X)                                                                                         \
    /* solver parameters (pbf_solver_params, also inside pbf_world_desc) */                                            \
    X(SOLVER_ITERATIONS, PBF_ERROR_INVALID_ARGUMENT, "solver.iterations must be 1..64")                                \
    X(SOLVER_SUBSTEPS, PBF_ERROR_INVALID_ARGUMENT, "solver.substeps must be 0 (automatic) or 1..64")                   \
    X(SOLVER_MAX_SUBSTEPS, PBF_ERROR_INVALID_ARGUMENT, "solver.max_substeps must be 1..64")                            \
    X(SOLVER_SUBSTEP_TRAVEL, PBF_ERROR_INVALID_ARGUMENT, "solver.substep_travel must be 0.05..1 (a fraction of h)")    \
    X(SOLVER_SOUND_SPEED, PBF_ERROR_INVALID_ARGUMENT, "solver.sound_speed must be finite and >= 10 (m/s)")             \
    X(SOLVER_RELAXATION, PBF_ERROR_INVALID_ARGUMENT, "solver.relaxation must be finite and > 0")                       \
    X(SOLVER_SCORR_K, PBF_ERROR_INVALID_ARGUMENT, "solver.scorr_k must be 0..1")                                       \
    X(SOLVER_SCORR_N, PBF_ERROR_INVALID_ARGUMENT, "solver.scorr_n must be 1..8")                                       \
    X(SOLVER_SCORR_DQ, PBF_ERROR_INVALID_ARGUMENT, "solver.scorr_dq must be in (0, 1) (a fraction of h)")              \
    X(SOLVER_XSPH_C, PBF_ERROR_INVALID_ARGUMENT, "solver.xsph_c must be 0..1")                                         \
    X(SOLVER_VORTICITY, PBF_ERROR_INVALID_ARGUMENT, "solver.vorticity_epsilon must be 0..1 (m/s)")                     \
    X(SOLVER_LDC_ENABLED, PBF_ERROR_INVALID_ARGUMENT, "solver.ldc_enabled must be 0 or 1")                             \
    X(SOLVER_LDC_GAIN, PBF_ERROR_INVALID_ARGUMENT, "solver.ldc_gain must be 0..1")                                     \
    X(SOLVER_MAX_SPEED, PBF_ERROR_INVALID_ARGUMENT, "solver.max_speed must be finite and > 0")                         \
    X(SOLVER_ADAPTIVE_TARGET, PBF_ERROR_INVALID_ARGUMENT, "solver.adaptive_error_target must be in [0, 1)")            \
    /* pbf_world_desc */                                                                                               \
    X(WORLD_HEADER_VERSION, PBF_ERROR_VERSION_MISMATCH,                                                                \
      "header major version {a} does not match the library's {b} (desc.header_version must be PBF_VERSION; use "       \
      "pbf_world_desc_default())")                                                                                     \
    X(WORLD_BACKEND, PBF_ERROR_INVALID_ARGUMENT, "backend must be PBF_BACKEND_AUTO, _CPU or _CUDA")                    \
    X(WORLD_CUDA_DEVICE, PBF_ERROR_INVALID_ARGUMENT, "cuda_device must be >= 0")                                       \
    X(WORLD_MAX_PARTICLES, PBF_ERROR_INVALID_ARGUMENT, "max_particles must be 1..2^30")                                \
    X(WORLD_PARTICLE_RADIUS, PBF_ERROR_INVALID_ARGUMENT, "particle_radius must be finite and > 0")                     \
    X(WORLD_REST_DENSITY, PBF_ERROR_INVALID_ARGUMENT, "rest_density must be finite and > 0")                           \
    X(WORLD_GRAVITY, PBF_ERROR_INVALID_ARGUMENT, "gravity must be finite")                                             \
    X(WORLD_DOMAIN_FINITE, PBF_ERROR_INVALID_ARGUMENT, "domain bounds must be finite")                                 \
    X(WORLD_DOMAIN_SIZE, PBF_ERROR_INVALID_ARGUMENT,                                                                   \
      "domain_max must exceed domain_min by at least 2 particle diameters on every axis")                              \
    X(WORLD_DOMAIN_EXTENT, PBF_ERROR_INVALID_ARGUMENT,                                                                 \
      "domain_min and domain_max must lie within 2^17 h = 2^19 particle_radius of the origin on every axis (float "    \
      "spacing there reaches h/64; the same limit holds particles in an open level)")                                  \
    X(WORLD_MAX_COLLIDERS, PBF_ERROR_INVALID_ARGUMENT, "max_colliders must be 1..{a}")                                 \
    X(WORLD_WALLS, PBF_ERROR_INVALID_ARGUMENT, "walls must be 0 (an open level) or 1 (the domain box's walls)")        \
    X(WORLD_HASHED_GRID, PBF_ERROR_INVALID_ARGUMENT, "hashed_grid must be 0 (automatic) or 1 (always hashed)")         \
    /* render data (pbf_render_params, inside pbf_world_desc) */                                                       \
    X(RENDER_FLAGS, PBF_ERROR_INVALID_ARGUMENT,                                                                        \
      "render.flags must combine PBF_RENDER_SMOOTHED_POSITIONS and PBF_RENDER_ANISOTROPY only")                        \
    X(RENDER_SMOOTHING, PBF_ERROR_INVALID_ARGUMENT, "render.smoothing must be 0..1")                                   \
    X(RENDER_MAX_STRETCH, PBF_ERROR_INVALID_ARGUMENT, "render.max_stretch must be 1..100")                             \
    X(RENDER_SCALE, PBF_ERROR_INVALID_ARGUMENT, "render.scale must be in (0, 100]")                                    \
    X(RENDER_ISOLATED_SCALE, PBF_ERROR_INVALID_ARGUMENT, "render.isolated_scale must be in (0, 100]")                  \
    X(RENDER_MIN_NEIGHBORS, PBF_ERROR_INVALID_ARGUMENT, "render.min_neighbors must be 0..1000")                        \
    X(RENDER_RESERVED0, PBF_ERROR_INVALID_ARGUMENT, "render.reserved0 must be 0")                                      \
    /* diffuse particles (pbf_diffuse_params, inside pbf_world_desc; pbf_world_add_diffuse) */                         \
    X(DIFFUSE_CAPACITY, PBF_ERROR_INVALID_ARGUMENT, "diffuse.max_diffuse must be 0..2^26")                             \
    X(DIFFUSE_THRESHOLDS, PBF_ERROR_INVALID_ARGUMENT,                                                                  \
      "diffuse thresholds (trapped_air, wave_crest, energy _min/_max) must be finite, 0..1e6, with min < max")         \
    X(DIFFUSE_RATES, PBF_ERROR_INVALID_ARGUMENT, "diffuse.trapped_air_rate and wave_crest_rate must be 0..1e4")        \
    X(DIFFUSE_LIFETIME, PBF_ERROR_INVALID_ARGUMENT, "diffuse.lifetime must be in (0, 1e4] s")                          \
    X(DIFFUSE_NEIGHBORS, PBF_ERROR_INVALID_ARGUMENT,                                                                   \
      "diffuse.spray_max_neighbors must not exceed bubble_min_neighbors, which must be <= 1000")                       \
    X(DIFFUSE_MOTION, PBF_ERROR_INVALID_ARGUMENT,                                                                      \
      "diffuse.buoyancy must be 0..100, bubble_drag and spray_drag 0..1e4 (1/s)")                                      \
    X(DIFFUSE_ROWS, PBF_ERROR_INVALID_ARGUMENT,                                                                        \
      "diffuse rows must be finite, kinds PBF_DIFFUSE_SPRAY, _FOAM or _BUBBLE (0, 1, 2), lifetimes > 0")               \
    /* pbf_world_copy_buffer */                                                                                        \
    X(COPY_OUT_SIZE, PBF_ERROR_INVALID_ARGUMENT, "out_bytes must be a multiple of the source's element size {a}")      \
    /* pbf_world_set_gravity */                                                                                        \
    X(GRAVITY, PBF_ERROR_INVALID_ARGUMENT, "gravity must be non-NULL and finite")                                      \
    /* pbf_block_desc */                                                                                               \
    X(BLOCK_FINITE, PBF_ERROR_INVALID_ARGUMENT, "box_min, box_max and velocity must be finite")                        \
    X(BLOCK_BOX, PBF_ERROR_INVALID_ARGUMENT, "box_max must exceed box_min on every axis")                              \
    /* pbf_emitter_desc, pbf_emitter_set_nozzle/_drain_box */                                                          \
    X(EMITTER_ENABLED, PBF_ERROR_INVALID_ARGUMENT, "enabled must be 0 or 1")                                           \
    X(EMITTER_TYPE, PBF_ERROR_INVALID_ARGUMENT, "type must be PBF_EMITTER_NOZZLE or PBF_EMITTER_DRAIN")                \
    X(NOZZLE_FINITE, PBF_ERROR_INVALID_ARGUMENT, "nozzle position and direction must be finite")                       \
    X(NOZZLE_DIRECTION, PBF_ERROR_INVALID_ARGUMENT, "nozzle direction must be non-zero")                               \
    X(NOZZLE_SPEED, PBF_ERROR_INVALID_ARGUMENT, "nozzle speed must be finite and > 0")                                 \
    X(NOZZLE_RADIUS, PBF_ERROR_INVALID_ARGUMENT, "nozzle radius must be finite and > 0")                               \
    X(NOZZLE_RATE, PBF_ERROR_INVALID_ARGUMENT, "nozzle particles_per_second must be in (0, 1e9]")                      \
    X(DRAIN_FINITE, PBF_ERROR_INVALID_ARGUMENT, "drain box must be finite")                                            \
    X(DRAIN_BOX, PBF_ERROR_INVALID_ARGUMENT, "drain box_max must exceed box_min")                                      \
    X(EMITTER_UNUSED_FINITE, PBF_ERROR_INVALID_ARGUMENT,                                                               \
      "position, direction, speed, radius, particles_per_second, box_min and box_max must be finite, also where "      \
      "the type does not use them")                                                                                    \
    X(TRANSFORM_FINITE, PBF_ERROR_INVALID_ARGUMENT, "both vectors must be non-NULL and finite")                        \
    X(EMITTER_KIND, PBF_ERROR_INVALID_ARGUMENT,                                                                        \
      "pbf_emitter_set_nozzle moves nozzles and pbf_emitter_set_drain_box drains: the emitter is of the other type")   \
    /* pbf_collider_desc, pbf_collider_set_target_pose */                                                              \
    X(COLLIDER_SHAPE, PBF_ERROR_INVALID_ARGUMENT, "shape must be PBF_SHAPE_PLANE, _SPHERE, _CAPSULE, _BOX or _MESH")   \
    X(COLLIDER_MOTION, PBF_ERROR_INVALID_ARGUMENT, "motion must be PBF_MOTION_STATIC or PBF_MOTION_KINEMATIC")         \
    X(COLLIDER_POSE, PBF_ERROR_INVALID_ARGUMENT, "position must be finite and rotation a finite, non-zero quaternion") \
    X(COLLIDER_FRICTION, PBF_ERROR_INVALID_ARGUMENT, "friction must be 0..1")                                          \
    X(COLLIDER_RADIUS, PBF_ERROR_INVALID_ARGUMENT, "radius must be finite and > 0")                                    \
    X(COLLIDER_HALF_HEIGHT, PBF_ERROR_INVALID_ARGUMENT, "half_height must be finite and >= 0")                         \
    X(COLLIDER_HALF_EXTENTS, PBF_ERROR_INVALID_ARGUMENT, "half_extents must be finite and > 0")                        \
    X(COLLIDER_UNUSED_FINITE, PBF_ERROR_INVALID_ARGUMENT,                                                              \
      "radius, half_height and half_extents must be finite, also where the shape does not use them")                   \
    X(COLLIDER_DYNAMIC, PBF_ERROR_INVALID_ARGUMENT, "dynamic must be 0 or 1")                                          \
    X(COLLIDER_CENTER, PBF_ERROR_INVALID_ARGUMENT, "center_of_mass must be finite")                                    \
    /* pbf_mesh_desc */                                                                                                \
    X(MESH_VERTICES, PBF_ERROR_INVALID_ARGUMENT, "vertices must be non-NULL and vertex_count 3..2^24")                 \
    X(MESH_INDICES, PBF_ERROR_INVALID_ARGUMENT, "indices must be non-NULL and triangle_count 1..2^22")                 \
    X(MESH_CLOSED, PBF_ERROR_INVALID_ARGUMENT, "closed must be 0 or 1")                                                \
    X(MESH_THICKNESS, PBF_ERROR_INVALID_ARGUMENT, "thickness must be finite and >= 0")                                 \
    X(MESH_CELL_SIZE, PBF_ERROR_INVALID_ARGUMENT, "cell_size must be finite and >= 0")                                 \
    X(MESH_VERTEX_FINITE, PBF_ERROR_INVALID_ARGUMENT, "vertex {a} is not finite")                                      \
    X(MESH_INDEX_RANGE, PBF_ERROR_INVALID_ARGUMENT, "index {a} is {b}: indices must be below vertex_count")            \
    X(MESH_DEGENERATE, PBF_ERROR_INVALID_ARGUMENT,                                                                     \
      "every triangle is degenerate (zero area): the mesh has no surface")                                             \
    X(MESH_VOXELS, PBF_ERROR_CAPACITY,                                                                                 \
      "the mesh's distance field would take {a} voxels ({b} MB; at most 256 MB per mesh): raise cell_size")            \
    /* interop: pbf_gl_buffer_desc, pbf_d3d11_buffer_desc, pbf_external_buffer_desc, pbf_semaphore_desc,            \
       pbf_external_sync */  \
    X(GL_BUFFER_NAME, PBF_ERROR_INVALID_ARGUMENT, "buffer must be a GL buffer object name (non-zero)")                 \
    X(D3D11_BUFFER, PBF_ERROR_INVALID_ARGUMENT, "buffer must be an ID3D11Buffer* (non-NULL)")                          \
    X(D3D11_COPY_MODE, PBF_ERROR_INVALID_ARGUMENT,                                                                     \
      "mode must be PBF_COPY_ON_RENDER_EVENT or PBF_COPY_ON_STEP (a D3D11 buffer has no manual copy call)")            \
    X(COPY_SOURCE, PBF_ERROR_INVALID_ARGUMENT,                                                                         \
      "source must be PBF_BUFFER_POSITIONS, _VELOCITIES, _IDS, _SMOOTHED_POSITIONS, _ANISOTROPY, "                     \
      "_DIFFUSE_POSITIONS, _DIFFUSE_VELOCITIES or _MATERIALS")                                                         \
    X(COPY_MODE, PBF_ERROR_INVALID_ARGUMENT, "mode must be PBF_COPY_ON_STEP, _ON_RENDER_EVENT or _MANUAL")             \
    X(COPY_CAPACITY, PBF_ERROR_INVALID_ARGUMENT, "capacity must be > 0")                                               \
    X(COPY_OFFSET_ALIGN, PBF_ERROR_INVALID_ARGUMENT, "offset_bytes must be a multiple of {a}")                         \
    X(DRAW_ARGS_ALIGN, PBF_ERROR_INVALID_ARGUMENT, "draw_args_offset_bytes must be a multiple of 4")                   \
    X(RESERVED0, PBF_ERROR_INVALID_ARGUMENT, "reserved0 must be 0")                                                    \
    X(EXTERNAL_TYPE, PBF_ERROR_INVALID_ARGUMENT, "type must be a pbf_external_memory_type")                            \
    X(HANDLE_FD, PBF_ERROR_INVALID_ARGUMENT, "fd must be an open file descriptor (>= 0)")                              \
    X(HANDLE_WIN32, PBF_ERROR_INVALID_ARGUMENT, "win32_handle must be set for this type")                              \
    X(EXTERNAL_DEDICATED, PBF_ERROR_INVALID_ARGUMENT, "dedicated must be 0 or 1")                                      \
    X(EXTERNAL_SIZE, PBF_ERROR_INVALID_ARGUMENT, "size_bytes must be > 0")                                             \
    X(EXTERNAL_RANGE, PBF_ERROR_INVALID_ARGUMENT, "offset_bytes + capacity * {a} exceeds size_bytes")                  \
    X(EXTERNAL_WRITE_DRAW_ARGS, PBF_ERROR_INVALID_ARGUMENT, "write_draw_args must be 0 or 1")                          \
    X(DRAW_ARGS_RANGE, PBF_ERROR_INVALID_ARGUMENT, "draw_args_offset_bytes + 16 exceeds size_bytes")                   \
    X(DRAW_ARGS_OVERLAP, PBF_ERROR_INVALID_ARGUMENT, "the draw arguments overlap the particles")                       \
    X(SEMAPHORE_TYPE, PBF_ERROR_INVALID_ARGUMENT, "type must be a pbf_semaphore_type")                                 \
    X(COPY_SOURCE_GRAPHICS, PBF_ERROR_INVALID_ARGUMENT,                                                                \
      "PBF_BUFFER_MATERIALS (1 byte per particle) is not copied into graphics buffers: read it with "                  \
      "pbf_world_copy_buffer or pbf_world_map_device_buffers")                                                         \
    /* pbf_material_desc and material handles */                                                                       \
    X(MATERIAL_REST_DENSITY, PBF_ERROR_INVALID_ARGUMENT,                                                               \
      "rest_density must be finite and 0.1..10 times the world's rest_density")                                        \
    X(MATERIAL_DEFAULT_DENSITY, PBF_ERROR_INVALID_ARGUMENT,                                                            \
      "the default material's rest_density is the world's rest_density and cannot change")                             \
    X(MATERIAL_VISCOSITY, PBF_ERROR_INVALID_ARGUMENT, "viscosity must be 0..1")                                        \
    X(MATERIAL_LDC_GAIN, PBF_ERROR_INVALID_ARGUMENT, "ldc_gain must be 0..1")                                          \
    X(MATERIAL_SURFACE_TENSION, PBF_ERROR_INVALID_ARGUMENT, "surface_tension must be 0..10000 (1/s^2)")                \
    X(MATERIAL_COHESION, PBF_ERROR_INVALID_ARGUMENT, "cohesion must be 0..10000 (1/s^2)")                              \
    X(MATERIAL_ADHESION, PBF_ERROR_INVALID_ARGUMENT, "adhesion must be 0..10000 (1/s^2)")                              \
    X(MATERIAL_COLOR, PBF_ERROR_INVALID_ARGUMENT, "color must be 0..1 in every channel")                               \
    X(MATERIAL_RESERVED0, PBF_ERROR_INVALID_ARGUMENT, "material reserved0 must be 0")                                  \
    X(MATERIAL_HANDLE, PBF_ERROR_INVALID_HANDLE, "material is not live (destroyed, forged or of another world)")       \
    X(MATERIAL_DEFAULT_DESTROY, PBF_ERROR_INVALID_STATE, "the default material cannot be destroyed")                   \
    X(MATERIAL_IN_USE, PBF_ERROR_INVALID_STATE,                                                                        \
      "the material is in use: {a} emitter(s) and {b} particle(s) carry it (destroy or retarget them first)")          \
    X(SYNC_RESERVED0, PBF_ERROR_INVALID_ARGUMENT, "sync.reserved0 must be 0")

enum class Check : uint16_t {
    ok = 0,
#define PBF_CHECK_ID(id, code, message) id,
    PBF_VALIDATE_CHECKS(PBF_CHECK_ID)
#undef PBF_CHECK_ID
        count
};

// A validator's answer: the first failed check (Check::ok when none) and the numbers its message
// names.
struct Verdict {
    Check check = Check::ok;
    uint64_t a = 0, b = 0;
    bool ok() const { return check == Check::ok; }
};

const char* check_name(Check c);              // "SOLVER_ITERATIONS"
pbf_result check_code(Check c);               // the result code a call refused by c returns
std::string check_message(const Verdict& v);  // the message, {a} and {b} filled in

Verdict validate_solver_params(const pbf_solver_params& p);    // struct_size checked by the caller
Verdict validate_world_desc(const pbf_world_desc& d);          // all but the nested solver params
Verdict validate_render_params(const pbf_render_params& p);    // struct_size checked by the caller
Verdict validate_diffuse_params(const pbf_diffuse_params& p);  // struct_size checked by the caller
// pbf_world_add_diffuse's rows: count float4 positions (w = kind) and velocities (w = lifetime).
Verdict validate_diffuse_rows(const float* positions, const float* velocities, uint32_t count);
// pbf_world_copy_buffer: a known source, out_bytes a whole number of its elements.
Verdict validate_copy_out(const pbf_buffer& source, uint64_t out_bytes);
Verdict validate_gravity(const float g[3]);
Verdict validate_block_desc(const pbf_block_desc& d);
Verdict validate_emitter_desc(const pbf_emitter_desc& d);
// pbf_emitter_set_nozzle/_drain_box: a, b are a nozzle's position and direction or a drain's box (type
// null: only what holds for both, before the emitter is looked up).
Verdict validate_emitter_transform(const pbf_emitter_type* type, const float a[3], const float b[3]);
// pbf_emitter_set_nozzle / _drain_box: the call's kind matches the emitter's type.
Verdict validate_emitter_kind(pbf_emitter_type kind, pbf_emitter_type type);
Verdict validate_collider_desc(const pbf_collider_desc& d);
Verdict validate_collider_pose(const float position[3], const float rotation[4]);
Verdict validate_mesh_desc(const pbf_mesh_desc& d);  // the arrays are read (counts checked first)
Verdict validate_mesh_voxels(uint64_t voxels);       // a field of this many voxels may be built
Verdict validate_gl_buffer_desc(const pbf_gl_buffer_desc& d);
Verdict validate_d3d11_buffer_desc(const pbf_d3d11_buffer_desc& d);
Verdict validate_external_buffer_desc(const pbf_external_buffer_desc& d);
Verdict validate_semaphore_desc(const pbf_semaphore_desc& d);
// pbf_material_desc against the world's rest density (is_default: the default material's desc).
Verdict validate_material_desc(const pbf_material_desc& d, float world_rest_density, bool is_default);
Verdict validate_external_sync(const pbf_external_sync& s);  // fields only; handles: the caller

// Refuses the call: sets the thread's last check and error ("fn: message") and returns the
// check's result code.
pbf_result refuse(const char* fn, const Verdict& v);
// The check that refused the calling thread's last failed call (Check::ok when that failure was
// not a validation check). For white-box tests.
Check last_validation_check();

}  // namespace pbf::api

// Refuses the call with the verdict of a validator unless it passed.
#define PBF_VALIDATE(expr)                                                                      \
    do {                                                                                        \
        if (const ::pbf::api::Verdict v_ = (expr); !v_.ok()) return ::pbf::api::refuse(fn, v_); \
    } while (0)
