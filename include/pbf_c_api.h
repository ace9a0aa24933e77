/*
 * libpbf: real-time Position Based Fluids (with Local Density Calibration) for game engines.
 * Public C ABI, version 1. Pure C99.
 *
 * Conventions
 * - Every fallible call returns a pbf_result. On failure, pbf_last_error_message() returns a
 *   human-readable message for the calling thread (valid until that thread's next libpbf call).
 * - Descs carry struct_size and come from pbf_*_desc_default(); a desc whose struct_size differs
 *   from the library's, or whose required fields are unset (zero), is refused.
 * - Handles are {index, generation} pairs. A handle of a destroyed object is refused with
 *   PBF_ERROR_INVALID_HANDLE, never dereferenced. A zeroed handle is never valid.
 * - A failed call changes nothing in the world.
 * - Units: metres, seconds, kilograms. Vectors are float[3]; quaternions float[4] as (x, y, z, w).
 *
 * Thread safety
 * - Calls on different worlds may run concurrently on different threads.
 * - Calls on one world are serialised by the library (an internal per-world lock), so they are safe
 *   from any thread, but they do not run in parallel with each other.
 * - pbf_world_destroy may race with other calls on the same world: those calls either complete
 *   before it, or return PBF_ERROR_INVALID_HANDLE.
 * - pbf_set_log_callback: the callback may be invoked from any thread that calls libpbf.
 */
#ifndef PBF_C_API_H
#define PBF_C_API_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* ---- Export and calling convention ------------------------------------------------------ */
#if defined(_WIN32)
#  define PBF_CALL __cdecl
#  if defined(PBF_BUILDING_LIBRARY)
#    define PBF_API __declspec(dllexport)
#  elif defined(PBF_STATIC)
#    define PBF_API
#  else
#    define PBF_API __declspec(dllimport)
#  endif
#else
#  define PBF_CALL
#  if defined(PBF_BUILDING_LIBRARY)
#    define PBF_API __attribute__((visibility("default")))
#  else
#    define PBF_API
#  endif
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Version ------------------------------------------------------------------------------ */
#define PBF_VERSION_MAJOR 1
#define PBF_VERSION_MINOR 0
#define PBF_VERSION_PATCH 0
/* major in bits 22..31, minor in 12..21, patch in 0..11 */
#define PBF_MAKE_VERSION(major, minor, patch) \
    ((((uint32_t)(major)) << 22) | (((uint32_t)(minor)) << 12) | ((uint32_t)(patch)))
#define PBF_VERSION PBF_MAKE_VERSION(PBF_VERSION_MAJOR, PBF_VERSION_MINOR, PBF_VERSION_PATCH)
#define PBF_VERSION_GET_MAJOR(v) (((uint32_t)(v)) >> 22)

/* The version the library was built as (compare with PBF_VERSION from this header). */
PBF_API uint32_t PBF_CALL pbf_get_version(void);

/* ---- Results and errors ------------------------------------------------------------------- */
typedef enum pbf_result {
    PBF_OK = 0,
    PBF_ERROR_INVALID_ARGUMENT = 1,   /* NULL pointer, NaN/Inf, out-of-range value */
    PBF_ERROR_INVALID_HANDLE = 2,     /* zeroed, forged or stale (destroyed) handle */
    PBF_ERROR_STRUCT_SIZE = 3,        /* desc.struct_size does not match the library's */
    PBF_ERROR_VERSION_MISMATCH = 4,   /* header and library majors differ */
    PBF_ERROR_CAPACITY = 5,           /* nothing fits: world at max_particles, or table full */
    PBF_ERROR_OUT_OF_MEMORY = 6,      /* host or device allocation failed */
    PBF_ERROR_BACKEND_UNAVAILABLE = 7,/* CUDA asked for but not built in, or no device */
    PBF_ERROR_BACKEND = 8,            /* a device call failed; the message carries its text */
    PBF_ERROR_INVALID_STATE = 9,      /* the call does not fit the object's current state */
    PBF_ERROR_INTERNAL = 10,          /* a bug in libpbf; please report the message */
    PBF_RESULT_FORCE32 = 0x7FFFFFFF
} pbf_result;

/* Message of the calling thread's last failed call ("" if none). Never NULL. */
PBF_API const char* PBF_CALL pbf_last_error_message(void);
/* Static name of a result code, e.g. "PBF_ERROR_INVALID_HANDLE". Never NULL. */
PBF_API const char* PBF_CALL pbf_result_string(pbf_result result);

typedef enum pbf_log_level {
    PBF_LOG_DEBUG = 0,
    PBF_LOG_INFO = 1,
    PBF_LOG_WARNING = 2,
    PBF_LOG_ERROR = 3,
    PBF_LOG_LEVEL_FORCE32 = 0x7FFFFFFF
} pbf_log_level;

/* Receives every error message and informational events (world created, backend chosen).
 * May be called from any thread calling libpbf; message is valid only during the call.
 * Calls are serialised under a library lock: the callback must not call libpbf. Once
 * pbf_set_log_callback returns, no call with the previous callback/user_data is running. */
typedef void (PBF_CALL* pbf_log_fn)(pbf_log_level level, const char* message, void* user_data);
/* Pass NULL to remove. Process-wide. */
PBF_API void PBF_CALL pbf_set_log_callback(pbf_log_fn callback, void* user_data);

/* ---- Handles ------------------------------------------------------------------------------ */
typedef struct pbf_world_id { uint32_t index; uint32_t generation; } pbf_world_id;
typedef struct pbf_emitter_id { uint32_t index; uint32_t generation; } pbf_emitter_id;
typedef struct pbf_collider_id { uint32_t index; uint32_t generation; } pbf_collider_id;

/* ---- Solver parameters -------------------------------------------------------------------- */
typedef struct pbf_solver_params {
    uint32_t struct_size;
    uint32_t iterations;        /* density-constraint iterations per substep, 1..64 (default 4) */
    uint32_t substeps;          /* substeps per pbf_world_step, 1..16 (default 1) */
    float relaxation;           /* ε of λ (constraint force mixing), relative to the constraint
                                   gradient norm of a particle at rest density; > 0 (default 1).
                                   Smaller converges faster per iteration but a Jacobi sweep
                                   overshoots and a resting fluid boils. */
    float scorr_k;              /* tensile instability s_corr = -k (W(r)/W(Δq))^n; >= 0 (default 0.1) */
    float scorr_n;              /* exponent n, 1..8 (default 4) */
    float scorr_dq;             /* Δq as a fraction of h, 0..1 (default 0.2) */
    float xsph_c;               /* XSPH viscosity c, 0..1 (default 0.01) */
    float vorticity_epsilon;    /* vorticity confinement ε, in m/s; >= 0 (default 0.0005) */
    uint32_t ldc_enabled;       /* 1: Local Density Calibration before the iterations (default 1) */
    float ldc_gain;             /* LDC strength as K·Δt² (dimensionless; Δt the substep), so the
                                   paper's K = ldc_gain / Δt². 0..1 (default 0.1). LDC acts on
                                   compression only: densities below rest count as rest. */
    float max_speed;            /* particle speed clamp in m/s, > 0 (default 100) */
} pbf_solver_params;

/* Fills the library's defaults. Prefer pbf_solver_params_default(). */
PBF_API pbf_result PBF_CALL pbf_solver_params_init(pbf_solver_params* params, uint32_t struct_size);
static inline pbf_solver_params pbf_solver_params_default(void) {
    pbf_solver_params p;
    memset(&p, 0, sizeof p);
    p.struct_size = (uint32_t)sizeof(pbf_solver_params);
    (void)pbf_solver_params_init(&p, p.struct_size);
    return p;
}

/* ---- World -------------------------------------------------------------------------------- */
typedef enum pbf_backend {
    PBF_BACKEND_AUTO = 0,  /* CUDA when built in and a device exists, else CPU */
    PBF_BACKEND_CPU = 1,
    PBF_BACKEND_CUDA = 2,
    PBF_BACKEND_FORCE32 = 0x7FFFFFFF
} pbf_backend;

typedef struct pbf_world_desc {
    uint32_t struct_size;
    uint32_t header_version;    /* PBF_VERSION of the caller's header: majors must match */
    pbf_backend backend;        /* default AUTO */
    int32_t cuda_device;        /* CUDA device ordinal (default 0) */
    uint32_t max_particles;     /* capacity, fixed for the world's life (default 65536) */
    float particle_radius;      /* rest spacing is 2·radius, kernel radius h = 4·radius (default 0.025) */
    float rest_density;         /* kg/m³ (default 1000) */
    float gravity[3];           /* m/s² (default 0, -9.81, 0) */
    float domain_min[3];        /* the walls: an axis-aligned box that contains all particles */
    float domain_max[3];        /* (default -1,0,-1 .. 1,2,1) */
    pbf_solver_params solver;
} pbf_world_desc;

PBF_API pbf_result PBF_CALL pbf_world_desc_init(pbf_world_desc* desc, uint32_t struct_size,
                                                uint32_t header_version);
static inline pbf_world_desc pbf_world_desc_default(void) {
    pbf_world_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_world_desc);
    (void)pbf_world_desc_init(&d, d.struct_size, PBF_VERSION);
    return d;
}

/* Allocates every buffer up front (max_particles). Fails with PBF_ERROR_OUT_OF_MEMORY, never
 * later, if the device cannot hold the world. */
PBF_API pbf_result PBF_CALL pbf_world_create(const pbf_world_desc* desc, pbf_world_id* out_world);
PBF_API pbf_result PBF_CALL pbf_world_destroy(pbf_world_id world);

/* Advances by dt seconds (0 < dt <= 1), split into solver.substeps substeps. On CUDA the work
 * is queued on the world's stream: the call returns without waiting for the GPU. */
PBF_API pbf_result PBF_CALL pbf_world_step(pbf_world_id world, float dt);

PBF_API pbf_result PBF_CALL pbf_world_get_solver_params(pbf_world_id world, pbf_solver_params* out_params);
PBF_API pbf_result PBF_CALL pbf_world_set_solver_params(pbf_world_id world, const pbf_solver_params* params);
PBF_API pbf_result PBF_CALL pbf_world_set_gravity(pbf_world_id world, const float gravity[3]);

typedef struct pbf_world_info {
    uint32_t struct_size;
    pbf_backend backend;        /* the backend in use (never AUTO) */
    uint32_t max_particles;
    float particle_radius;
    float rest_spacing;         /* 2·radius */
    float kernel_radius;        /* h */
    float particle_mass;        /* calibrated so a rest lattice has rest_density */
    uint32_t grid_cells;        /* uniform grid cells over the domain (cell size h) */
    uint64_t device_bytes;      /* memory the world allocated on its backend */
    char device_name[128];      /* e.g. "NVIDIA H100 80GB HBM3" or "CPU (8 threads)" */
} pbf_world_info;
PBF_API pbf_result PBF_CALL pbf_world_get_info(pbf_world_id world, pbf_world_info* out_info);

/* Statistics of the last step (all zero before the first). Waits for the step to finish. */
typedef struct pbf_step_stats {
    uint32_t struct_size;
    uint32_t particle_count;
    uint64_t step_index;            /* steps taken so far */
    uint64_t emitted_total;         /* particles ever emitted (blocks and nozzles) */
    uint64_t drained_total;         /* particles ever removed by drains */
    float density_error_mean;       /* mean over particles of max(ρ/ρ0 - 1, 0) after the step */
    float density_error_max;        /* max over particles of the same */
    float kinetic_energy;           /* Σ ½ m v², joules */
    float step_time_ms;             /* the last pbf_world_step's duration on its backend */
    uint32_t iterations;            /* constraint iterations run in the last step, all substeps */
    uint32_t reserved0;
} pbf_step_stats;
PBF_API pbf_result PBF_CALL pbf_world_get_stats(pbf_world_id world, pbf_step_stats* out_stats);

/* ---- Emitters and drains ------------------------------------------------------------------ */
/* One-shot fill of an axis-aligned box with particles on a cubic lattice at rest spacing.
 * Emits what fits under max_particles; *out_emitted (may be NULL) says how many. Emitting zero
 * because the world is full returns PBF_ERROR_CAPACITY. */
typedef struct pbf_block_desc {
    uint32_t struct_size;
    float box_min[3];
    float box_max[3];
    float velocity[3];          /* initial velocity (default 0) */
} pbf_block_desc;
PBF_API pbf_result PBF_CALL pbf_block_desc_init(pbf_block_desc* desc, uint32_t struct_size);
static inline pbf_block_desc pbf_block_desc_default(void) {
    pbf_block_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_block_desc);
    (void)pbf_block_desc_init(&d, d.struct_size);
    return d;
}
PBF_API pbf_result PBF_CALL pbf_world_emit_block(pbf_world_id world, const pbf_block_desc* desc,
                                                 uint32_t* out_emitted);

typedef enum pbf_emitter_type {
    PBF_EMITTER_NOZZLE = 1,     /* emits particles_per_second through a disc, along direction */
    PBF_EMITTER_DRAIN = 2,      /* removes particles inside box_min..box_max at each step */
    PBF_EMITTER_TYPE_FORCE32 = 0x7FFFFFFF
} pbf_emitter_type;

typedef struct pbf_emitter_desc {
    uint32_t struct_size;
    pbf_emitter_type type;      /* no default: must be set */
    uint32_t enabled;           /* default 1 */
    float position[3];          /* nozzle: disc centre */
    float direction[3];         /* nozzle: normalised by the library (default 0,-1,0) */
    float speed;                /* nozzle: m/s (> 0) */
    float radius;               /* nozzle: disc radius, m (> 0) */
    float particles_per_second; /* nozzle: (> 0) */
    float box_min[3];           /* drain volume */
    float box_max[3];
} pbf_emitter_desc;
PBF_API pbf_result PBF_CALL pbf_emitter_desc_init(pbf_emitter_desc* desc, uint32_t struct_size);
static inline pbf_emitter_desc pbf_emitter_desc_default(void) {
    pbf_emitter_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_emitter_desc);
    (void)pbf_emitter_desc_init(&d, d.struct_size);
    return d;
}
PBF_API pbf_result PBF_CALL pbf_world_create_emitter(pbf_world_id world, const pbf_emitter_desc* desc,
                                                     pbf_emitter_id* out_emitter);
PBF_API pbf_result PBF_CALL pbf_world_destroy_emitter(pbf_world_id world, pbf_emitter_id emitter);
PBF_API pbf_result PBF_CALL pbf_emitter_set_enabled(pbf_world_id world, pbf_emitter_id emitter, uint32_t enabled);
/* Moves a nozzle (position, direction) or a drain (box_min, box_max: pass the two corners). */
PBF_API pbf_result PBF_CALL pbf_emitter_set_transform(pbf_world_id world, pbf_emitter_id emitter,
                                                      const float a[3], const float b[3]);

/* ---- Colliders ---------------------------------------------------------------------------- */
typedef enum pbf_collider_shape {
    PBF_SHAPE_PLANE = 1,        /* the half-space below the plane through position with normal
                                   rotation·(0,1,0) is solid */
    PBF_SHAPE_SPHERE = 2,       /* radius */
    PBF_SHAPE_CAPSULE = 3,      /* radius; segment from -half_height to +half_height on local y */
    PBF_SHAPE_BOX = 4,          /* half_extents, oriented by rotation */
    PBF_SHAPE_FORCE32 = 0x7FFFFFFF
} pbf_collider_shape;

typedef enum pbf_collider_motion {
    PBF_MOTION_STATIC = 0,
    PBF_MOTION_KINEMATIC = 1,   /* pose set each frame; its motion over a step pushes fluid */
    PBF_MOTION_FORCE32 = 0x7FFFFFFF
} pbf_collider_motion;

typedef struct pbf_collider_desc {
    uint32_t struct_size;
    pbf_collider_shape shape;   /* no default: must be set */
    pbf_collider_motion motion; /* default STATIC */
    float position[3];
    float rotation[4];          /* unit quaternion (x, y, z, w), normalised by the library
                                   (default identity) */
    float radius;               /* sphere, capsule */
    float half_height;          /* capsule */
    float half_extents[3];      /* box */
    float friction;             /* 0 (slip) .. 1 (stick) tangential damping on contact (default 0) */
} pbf_collider_desc;
PBF_API pbf_result PBF_CALL pbf_collider_desc_init(pbf_collider_desc* desc, uint32_t struct_size);
static inline pbf_collider_desc pbf_collider_desc_default(void) {
    pbf_collider_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_collider_desc);
    (void)pbf_collider_desc_init(&d, d.struct_size);
    return d;
}
PBF_API pbf_result PBF_CALL pbf_world_create_collider(pbf_world_id world, const pbf_collider_desc* desc,
                                                      pbf_collider_id* out_collider);
PBF_API pbf_result PBF_CALL pbf_world_destroy_collider(pbf_world_id world, pbf_collider_id collider);
/* Kinematic colliders only: the pose reached at the end of the next step. The solver moves the
 * collider from its current pose to this one over that step. */
PBF_API pbf_result PBF_CALL pbf_collider_set_pose(pbf_world_id world, pbf_collider_id collider,
                                                  const float position[3], const float rotation[4]);

/* ---- Particles ---------------------------------------------------------------------------- */
/* Storage order: the solver reorders particles every step (by grid cell). All copy-out calls
 * between two steps use the same order, so index k of positions, velocities and ids is one
 * particle. Use the ids to follow a particle across steps. */
PBF_API pbf_result PBF_CALL pbf_world_get_particle_count(pbf_world_id world, uint32_t* out_count);

/* Copies min(count, max_count) particles into out as 4 floats each: x, y, z, and w = the
 * particle's density ratio ρ/ρ0 at its last constraint evaluation (for colouring). */
PBF_API pbf_result PBF_CALL pbf_world_copy_positions(pbf_world_id world, float* out_xyzw,
                                                     uint32_t max_count, uint32_t* out_written);
/* 4 floats per particle: vx, vy, vz, 0. */
PBF_API pbf_result PBF_CALL pbf_world_copy_velocities(pbf_world_id world, float* out_xyzw,
                                                      uint32_t max_count, uint32_t* out_written);
/* Stable ids: assigned at emission (0, 1, 2, ... per world), kept for the particle's life. */
PBF_API pbf_result PBF_CALL pbf_world_copy_ids(pbf_world_id world, uint32_t* out_ids,
                                               uint32_t max_count, uint32_t* out_written);

typedef enum pbf_memory_kind {
    PBF_MEMORY_HOST = 1,        /* CPU backend: an ordinary host pointer */
    PBF_MEMORY_CUDA_DEVICE = 2, /* CUDA backend: a device pointer on the world's desc.cuda_device */
    PBF_MEMORY_KIND_FORCE32 = 0x7FFFFFFF
} pbf_memory_kind;

typedef struct pbf_mapped_buffer {
    uint32_t struct_size;
    pbf_memory_kind memory;
    void* data;                 /* count elements, stride_bytes apart */
    uint32_t count;
    uint32_t stride_bytes;      /* 16: float x, y, z, w as in pbf_world_copy_positions */
    uint32_t reserved0;
    uint32_t reserved1;
} pbf_mapped_buffer;
/* Maps the live position buffer, without a copy. Validity: the pointer and its contents are
 * valid until pbf_world_unmap, the next pbf_world_step, any call that adds or removes particles,
 * or pbf_world_destroy, whichever comes first. It is read-only for the caller. On CUDA the data
 * is complete when this returns (the call waits for the world's stream). */
PBF_API pbf_result PBF_CALL pbf_world_map_positions(pbf_world_id world, pbf_mapped_buffer* out_buffer);
PBF_API pbf_result PBF_CALL pbf_world_unmap(pbf_world_id world);

#ifdef __cplusplus
}
#endif
#endif /* PBF_C_API_H */
