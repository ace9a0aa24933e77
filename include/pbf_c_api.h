/*
 * libpbf: real-time Position Based Fluids (with Local Density Calibration) for game engines.
 * Public C ABI, pure C99; its version is PBF_VERSION_MAJOR.MINOR.PATCH below.
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
#define PBF_VERSION_MAJOR 2
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
typedef struct pbf_material_id { uint32_t index; uint32_t generation; } pbf_material_id;

/* ---- Solver parameters -------------------------------------------------------------------- */
/* The most substeps a pbf_world_step runs (solver.substeps, solver.max_substeps). */
#define PBF_MAX_SUBSTEPS 64
typedef struct pbf_solver_params {
    uint32_t struct_size;
    uint32_t iterations;        /* density-constraint iterations per substep, 1..64 (default 4).
                                   With fixed substeps, exactly this many. With automatic substeps
                                   (substeps = 0) the cap: a substep runs two, more only where
                                   max_substeps cannot hold the depth rule below; with a collider
                                   that moves or a mesh collider, or with adaptive_error_target
                                   > 0 (up to this until the target is met), this many
                                   (docs/physics.md, Iterations). */
    uint32_t substeps;          /* substeps per pbf_world_step. 0 (default): automatic, chosen per
                                   step (from the last finished step's fastest particle, read
                                   without waiting, the nozzles and the kinematic colliders) so that
                                   the fastest particle moves at most substep_travel·h per substep,
                                   gravity alone moves a resting one at most substep_travel·h/64,
                                   and a resting column as deep as the fluid's extent along gravity
                                   compresses at most ~10 % at its bottom (docs/physics.md), up to
                                   max_substeps. 1..PBF_MAX_SUBSTEPS: exactly that many. */
    float relaxation;           /* ε of λ (constraint force mixing), relative to the constraint
                                   gradient norm of a particle at rest density; > 0 (default 1).
                                   Smaller converges faster per iteration but a Jacobi sweep
                                   overshoots and a resting fluid boils. */
    float scorr_k;              /* tensile instability s_corr = -k (W(r)/W(Δq))^n, 0..1 (default 0.1).
                                   Pairs at or beyond the rest spacing are pushed no harder than
                                   the defaults push them, whatever k, n and Δq are: there it
                                   only pushes a free surface out (docs/physics.md) */
    float scorr_n;              /* exponent n, 1..8 (default 4) */
    float scorr_dq;             /* Δq as a fraction of h, 0..1 (default 0.2) */
    float xsph_c;               /* XSPH viscosity c per 1/60 s of simulated time, 0..1 (default 0.01):
                                   a substep of Δt applies 1 - (1 - c)^(60 Δt), so the smoothing
                                   does not depend on the substep count. */
    float vorticity_epsilon;    /* vorticity confinement ε, in m/s; 0..1 (default 0.0005). It adds
                                   energy by design: above 1 m/s it outgrew the dissipation */
    uint32_t ldc_enabled;       /* 1: Local Density Calibration before the iterations (default 1) */
    float ldc_gain;             /* LDC strength as K·Δt² (dimensionless; Δt the substep), so the
                                   paper's K = ldc_gain / (Δt² + τ²), τ = h / sound_speed. 0..1
                                   (default 0.3). LDC acts on compression only: densities below
                                   rest count as rest. */
    float max_speed;            /* particle speed limit in m/s, > 0 (default 100). A substep also
                                   limits speed to h/Δt (no particle crosses more than h per
                                   substep); stats count the particle-substeps either limit cut. */
    float adaptive_error_target;/* 0 (default): run exactly `iterations` per substep. > 0: stop a
                                   substep's iterations once the mean compressive density error
                                   max(ρ/ρ0 - 1, 0), measured by the λ pass, is below this (e.g.
                                   0.01 = 1 %), with `iterations` as the cap; 0..1. A substep runs at
                                   least one iteration. Decided on the device: the step still never
                                   waits. Stats report iterations run. */
    uint32_t max_substeps;      /* cap of the automatic substep count, 1..PBF_MAX_SUBSTEPS (default
                                   16). A step that would need more runs this many. A step longer
                                   than 1/30 s (a hitch) runs substeps no longer than the physics
                                   holds (the fastest particle within 3/4 h, and with automatic
                                   substeps the depth rule at up to `iterations`), simulates what
                                   they hold and drops the rest, as a game engine's physics does
                                   (pbf_step_stats.simulated_dt; docs/physics.md), at least
                                   1/30 s. Steps up to 1/30 s always run whole. */
    float substep_travel;       /* automatic substeps: the fastest particle's travel per substep, as a
                                   fraction of h, 0.05..1 (default 0.5) */
    float sound_speed;          /* m/s, >= 10 (default 40): the response speed of the density
                                   constraint to an error older than the substep. Such an error
                                   relaxes over τ = h / sound_speed rather than in one substep, so
                                   the velocity its removal creates stays near error · sound_speed
                                   whatever dt is (a tiny dt cannot turn an old error into a large
                                   velocity); new compression is removed in full every substep. */
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

/* ---- Render data -------------------------------------------------------------------------- */
/* What a renderer draws besides the positions, computed at the end of every step from the
 * step's own neighbour lists (one extra pass; with flags 0 a world allocates nothing for it and
 * runs nothing), after Yu & Turk 2013, "Reconstructing surfaces of particle-based fluids using
 * anisotropic kernels". Read it like the positions: pbf_world_copy_buffer, the device pointers
 * (pbf_device_buffers) and copies into GL / Vulkan buffers (source PBF_BUFFER_SMOOTHED_POSITIONS
 * or PBF_BUFFER_ANISOTROPY). Storage order is the positions' (index k is one particle). */
#define PBF_RENDER_SMOOTHED_POSITIONS 0x1u /* 16 bytes per particle: float x̄, ȳ, z̄, density ratio:
                                              x̄ = (1 - smoothing)·x + smoothing·(the weighted mean
                                              of its neighbours within h) */
#define PBF_RENDER_ANISOTROPY 0x2u         /* 48 bytes per particle: 3 float4 rows, the principal
                                              axes of its neighbourhood, longest first; each row is
                                              (unit axis x, y, z, radius in m). The particle's
                                              ellipsoid is Σ_k radius_k² axis_k axis_kᵀ. */

typedef struct pbf_render_params {
    uint32_t struct_size;
    uint32_t flags;             /* PBF_RENDER_* the world computes; default 0 (none). Fixed at
                                   world creation (its buffers are allocated then). */
    float smoothing;            /* λ of the Laplacian smoothing, 0..1 (default 0.9; 0: the
                                   positions themselves). Surface particles move inward by up to
                                   λ times their neighbourhood's offset (0.4 rest spacings at a
                                   flat surface); interior particles of an even fluid stay put. */
    float max_stretch;          /* k_r: the longest radius of an ellipsoid is at most this many
                                   times its shortest, 1..100 (default 4) */
    float scale;                /* k_s: radius, in particle radii, of a particle whose neighbours
                                   lie as in a rest lattice; radii scale linearly with the
                                   covariance's eigenvalues. (0, 100] (default 1) */
    float isolated_scale;       /* k_n: radius, in particle radii, of a particle with fewer than
                                   min_neighbors neighbours (a sphere), (0, 100] (default 0.5) */
    uint32_t min_neighbors;     /* N_ε: neighbours within h (itself included) below which a
                                   particle stays round, 0..1000 (default 6; a full neighbourhood
                                   holds about 33, a flat surface 18, a single-file stream 3) */
    uint32_t reserved0;         /* 0 */
} pbf_render_params;
PBF_API pbf_result PBF_CALL pbf_render_params_init(pbf_render_params* params, uint32_t struct_size);
static inline pbf_render_params pbf_render_params_default(void) {
    pbf_render_params p;
    memset(&p, 0, sizeof p);
    p.struct_size = (uint32_t)sizeof(pbf_render_params);
    (void)pbf_render_params_init(&p, p.struct_size);
    return p;
}

/* ---- Diffuse particles -------------------------------------------------------------------- */
/* Spray, foam and air bubbles after Ihmsen, Akinci, Gissler & Teschner 2012, "Unified spray,
 * foam and air bubbles for particle-based fluids": at the end of every step, fluid particles
 * that trap air (meet at speed), break at wave crests and move fast generate diffuse particles,
 * which then move by their kind: spray (few fluid neighbours) flies ballistically under gravity
 * and drag, foam (a surface's neighbourhood) rides with the fluid's velocity, bubbles (inside
 * the fluid) rise by buoyancy with drag toward the fluid's velocity. Foam and spray live for
 * (0.5..1) x lifetime; bubbles age once they surface. Read them like the particles
 * (pbf_world_copy_buffer, pbf_device_buffers, GL / Vulkan copies) through
 * PBF_BUFFER_DIFFUSE_POSITIONS (float x, y, z, kind: PBF_DIFFUSE_*) and
 * PBF_BUFFER_DIFFUSE_VELOCITIES (float vx, vy, vz, remaining lifetime in s); their count is
 * pbf_step_stats.diffuse_count. With max_diffuse 0 (the default) a world allocates and runs
 * nothing for them. The potentials' thresholds τ are (min, max) pairs of Ihmsen's clamping
 * Φ(I) = (min(I, max) - min(I, min)) / (max - min). */
#define PBF_DIFFUSE_SPRAY 0.0f
#define PBF_DIFFUSE_FOAM 1.0f
#define PBF_DIFFUSE_BUBBLE 2.0f

typedef struct pbf_diffuse_params {
    uint32_t struct_size;
    uint32_t max_diffuse;       /* capacity, 0..2^26, fixed at world creation (default 0: off).
                                   Costs 64 bytes of backend memory per diffuse particle, plus 8
                                   per slot of max_diffuse + max_particles (the packing scan) */
    float trapped_air_min;      /* τ_ta: trapped-air potential Σ_j |v_ij| (1 - v̂_ij·x̂_ij) W_ij */
    float trapped_air_max;      /*   (m/s; W = 1 - r/h) that starts and saturates generation
                                   (defaults 2 and 8) */
    float wave_crest_min;       /* τ_wc: wave-crest potential Σ_j (1 - n̂_i·n̂_j) W_ij of surface */
    float wave_crest_max;       /*   particles moving along their normal (defaults 1 and 4) */
    float energy_min;           /* τ_k: kinetic energy per unit mass ½|v|² (J/kg) that starts */
    float energy_max;           /*   and saturates generation (defaults 0.5 and 4) */
    float trapped_air_rate;     /* k_ta: diffuse particles per second per fluid particle at full
                                   trapped-air and energy potentials, 0..1e4 (default 200) */
    float wave_crest_rate;      /* k_wc: the same for wave crests, 0..1e4 (default 200) */
    float lifetime;             /* s, (0, 1e4]: foam and spray live (0.5..1) x this (default 2) */
    uint32_t spray_max_neighbors;  /* fewer fluid neighbours within h: spray (default 6) */
    uint32_t bubble_min_neighbors; /* more: a bubble; between: foam (default 20; a full
                                      neighbourhood holds about 33, a flat surface 18) */
    float buoyancy;             /* k_b: a bubble accelerates by -k_b·gravity, 0..100 (default 0.5) */
    float bubble_drag;          /* k_d (1/s): a bubble's velocity relaxes toward the fluid's at
                                   this rate, 0..1e4 (default 20) */
    float spray_drag;           /* linear air drag on spray (1/s), 0..1e4 (default 0.5) */
} pbf_diffuse_params;
PBF_API pbf_result PBF_CALL pbf_diffuse_params_init(pbf_diffuse_params* params, uint32_t struct_size);
static inline pbf_diffuse_params pbf_diffuse_params_default(void) {
    pbf_diffuse_params p;
    memset(&p, 0, sizeof p);
    p.struct_size = (uint32_t)sizeof(pbf_diffuse_params);
    (void)pbf_diffuse_params_init(&p, p.struct_size);
    return p;
}

/* ---- World -------------------------------------------------------------------------------- */
/* The largest pbf_world_desc.max_colliders. */
#define PBF_MAX_COLLIDERS 2048
typedef enum pbf_backend {
    PBF_BACKEND_AUTO = 0,  /* CUDA when the library can run it here (pbf_get_backend_info),
                              else CPU. The PBF_BACKEND variable of the samples and tools is
                              theirs, turned into this field: the library reads no environment
                              variable but PBF_CUDA_DRIVER (pbf_get_backend_info) */
    PBF_BACKEND_CPU = 1,
    PBF_BACKEND_CUDA = 2,
    PBF_BACKEND_FORCE32 = 0x7FFFFFFF
} pbf_backend;

/* Whether a backend can run on this machine, and if not, why (pbf_get_backend_info). The CUDA
 * backend needs no CUDA toolkit or runtime: the library opens the NVIDIA driver itself at run
 * time (libcuda.so.1 / nvcuda.dll) and runs kernels embedded in it. */
typedef enum pbf_backend_status {
    PBF_BACKEND_STATUS_AVAILABLE = 0,
    PBF_BACKEND_STATUS_NOT_BUILT = 1,          /* this library was built without the backend */
    PBF_BACKEND_STATUS_NO_DRIVER = 2,          /* no NVIDIA driver: its library was not found */
    PBF_BACKEND_STATUS_DRIVER_TOO_OLD = 3,     /* older than required_driver_version */
    PBF_BACKEND_STATUS_NO_DEVICE = 4,          /* a driver, but no CUDA device of that ordinal */
    PBF_BACKEND_STATUS_DEVICE_UNSUPPORTED = 5, /* a GPU the kernels do not run on (before
                                                  compute capability 7.5) */
    PBF_BACKEND_STATUS_DRIVER_ERROR = 6,       /* the driver failed to start, or to load the
                                                  kernels: the message gives its error */
    PBF_BACKEND_STATUS_FORCE32 = 0x7FFFFFFF
} pbf_backend_status;

typedef struct pbf_backend_info {
    uint32_t struct_size;
    pbf_backend backend;              /* the backend described; for AUTO, the one a world
                                         created with AUTO on that device gets */
    pbf_backend_status status;
    int32_t cuda_device;              /* the device described (CUDA); -1 for the CPU */
    int32_t device_count;             /* CUDA devices the driver reports (0 without a driver) */
    int32_t driver_version;           /* the driver's CUDA version, 1000·major + 10·minor (0
                                         without a driver), e.g. 13000 for 13.0 */
    int32_t required_driver_version;  /* the least driver version the kernels need (0 in a
                                         build without CUDA) */
    uint32_t reserved0;
    char device_name[128];            /* e.g. "NVIDIA GeForce RTX 4070" or "CPU (8 threads)";
                                         empty where there is no such device */
    char message[512];                /* why the backend is unavailable (for AUTO: why CUDA was
                                         not taken), or what was found */
} pbf_backend_info;

/* Describes backend (AUTO, CPU or CUDA) on CUDA device cuda_device (ignored for the CPU) into
 * *out_info (struct_size set by the caller). Returns PBF_OK whether or not the backend is
 * available: out_info->status says which. The first call looking at a CUDA device opens the driver
 * and loads the kernels into that device's context (tens to hundreds of milliseconds); later calls
 * and world creations reuse them. Setting the environment variable PBF_CUDA_DRIVER to a library's
 * path makes the library open that one instead of the system's driver (diagnostics). */
PBF_API pbf_result PBF_CALL pbf_get_backend_info(pbf_backend backend, int32_t cuda_device,
                                                 pbf_backend_info* out_info);

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
    float domain_max[3];        /* (default -1,0,-1 .. 1,2,1); within 2^17·h of the origin */
    pbf_solver_params solver;
    pbf_render_params render;   /* render data (default: none) */
    uint32_t max_colliders;     /* collider capacity, 1..PBF_MAX_COLLIDERS, allocated up front
                                   (default 256). Each collider costs about 0.3 KB of backend memory (shape,
                                   start/end keys, two pose rows, force rows) and up to 32 entries
                                   of the broad phase's lists: with more than 8 colliders each
                                   particle tests only those listed in its coarse cell. */
    pbf_diffuse_params diffuse; /* diffuse particles (default: none) */
    uint32_t walls;             /* 1 (default): the six walls of domain_min..domain_max hold the
                                   fluid and add boundary density. 0: an open level: no walls and
                                   no box (domain_min/max are ignored); the fluid stops only at
                                   colliders. Particle centres are still held within |x| <=
                                   2^17·h on each axis (h = 4·radius: 5.2 km at radius 0.01 m),
                                   where float spacing reaches h/64 (docs/physics.md). The
                                   neighbour grid is then hashed: its memory follows max_particles,
                                   not the level's extent (pbf_world_info.grid_bytes). */
    uint32_t hashed_grid;       /* 0 (default): a dense grid over the walls' box while it has at
                                   most 4 cells per key of the hashed grid, else hashed. 1: always
                                   hashed (a sparse fluid in a big box; benchmarks). */
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

/* The shortest time a step or substep simulates, seconds. */
#define PBF_MIN_STEP_DT 1e-4f
/* Advances by dt seconds (0 < dt <= 1; successive calls may use any dt), split into substeps
 * (solver.substeps, or chosen automatically; pbf_step_stats.substeps says how many ran), none
 * shorter than PBF_MIN_STEP_DT (1e-4 s; a short step runs fewer). A step shorter than that
 * advances nothing: its dt waits, and the next step simulates it too, with the colliders'
 * targets, teleports and emissions since (pbf_step_stats.simulated_dt is 0, then the sum; every
 * dynamic collider's force reads 0, in pbf_collider_get_force and the mapped table); float32
 * positions do not resolve the velocity of a shorter motion. On CUDA the work is queued on the
 * world's stream: the call returns without waiting for the GPU. */
PBF_API pbf_result PBF_CALL pbf_world_step(pbf_world_id world, float dt);

PBF_API pbf_result PBF_CALL pbf_world_get_solver_params(pbf_world_id world, pbf_solver_params* out_params);
PBF_API pbf_result PBF_CALL pbf_world_set_solver_params(pbf_world_id world, const pbf_solver_params* params);
PBF_API pbf_result PBF_CALL pbf_world_set_gravity(pbf_world_id world, const float gravity[3]);
/* The world's render parameters (desc.render), and new ones from the next step or emission on;
 * the buffers keep their data until then. flags are fixed at creation: params.flags must equal
 * the world's (PBF_ERROR_INVALID_STATE otherwise). */
PBF_API pbf_result PBF_CALL pbf_world_get_render_params(pbf_world_id world, pbf_render_params* out_params);
PBF_API pbf_result PBF_CALL pbf_world_set_render_params(pbf_world_id world, const pbf_render_params* params);
/* The world's diffuse parameters (desc.diffuse), and new ones from the next step on.
 * max_diffuse is fixed at creation: params.max_diffuse must equal the world's
 * (PBF_ERROR_INVALID_STATE otherwise). */
PBF_API pbf_result PBF_CALL pbf_world_get_diffuse_params(pbf_world_id world, pbf_diffuse_params* out_params);
PBF_API pbf_result PBF_CALL pbf_world_set_diffuse_params(pbf_world_id world, const pbf_diffuse_params* params);
/* Adds count diffuse particles (a splash from the game, say) after the live ones, while they fit
 * in max_diffuse: positions are float4 x, y, z, kind (PBF_DIFFUSE_*), velocities float4 vx, vy,
 * vz, remaining lifetime in s (> 0). All finite, else nothing is added. *out_added (may be NULL)
 * says how many fitted; none fitting is PBF_ERROR_CAPACITY. Waits for the world's stream. A
 * world without a diffuse capacity refuses with PBF_ERROR_INVALID_STATE. */
PBF_API pbf_result PBF_CALL pbf_world_add_diffuse(pbf_world_id world, const float* positions,
                                                  const float* velocities, uint32_t count,
                                                  uint32_t* out_added);

typedef struct pbf_world_info {
    uint32_t struct_size;
    pbf_backend backend;        /* the backend in use (never AUTO) */
    uint32_t max_particles;
    float particle_radius;
    float rest_spacing;         /* 2·radius */
    float kernel_radius;        /* h */
    float particle_mass;        /* calibrated so a rest lattice has rest_density */
    uint32_t grid_cells;        /* keys of the neighbour grid (cell size h): the cells of the
                                   domain box (dense), or of the hashed grid (see grid_hashed) */
    uint64_t device_bytes;      /* memory the world allocated on its backend */
    char device_name[128];      /* e.g. "NVIDIA H100 80GB HBM3" or "CPU (8 threads)" */
    uint32_t render_flags;      /* PBF_RENDER_* the world computes (desc.render.flags) */
    uint32_t reserved0;
    uint64_t render_bytes;      /* part of device_bytes the render data takes (0 with flags 0) */
    uint64_t render_updates;    /* render passes run so far: one per step (and per
                                   pbf_world_emit_block) with render data on, 0 with it off */
    uint32_t diffuse_capacity;  /* desc.diffuse.max_diffuse */
    uint32_t reserved1;
    uint64_t diffuse_bytes;     /* part of device_bytes the diffuse particles take (0 when off) */
    uint64_t diffuse_updates;   /* diffuse passes run so far: one per step when on, 0 when off */
    uint32_t grid_hashed;       /* 0: a dense grid over the domain box; 1: a hashed grid of
                                   grid_cells = the power of two >= max_particles (at least 4096)
                                   keys, used without walls and for boxes of more than 4 cells
                                   per hashed key (docs/perf.md, Open levels) */
    uint32_t reserved2;
    uint64_t grid_bytes;        /* part of device_bytes the grid's cell table takes (4 B a key) */
} pbf_world_info;
PBF_API pbf_result PBF_CALL pbf_world_get_info(pbf_world_id world, pbf_world_info* out_info);

/* Statistics of the last step (all zero before the first). Waits for the step to finish. Reading
 * them changes nothing: a world whose stats are read steps as it would unread. */
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
    uint32_t substeps;              /* substeps the last step ran */
    uint32_t speed_clamps;          /* particle-substeps of the last step whose speed a limit cut
                                       (max_speed, or the h-per-substep cap); 0 in a healthy run */
    float simulated_dt;             /* seconds the last step advanced the world: its dt, unless
                                       the step was a hitch (over 1/30 s) longer than its
                                       substeps hold: then less, the rest dropped
                                       (solver.max_substeps); 0 for a step shorter than
                                       PBF_MIN_STEP_DT, whose dt the next step simulates (and
                                       adds here) */
    uint32_t diffuse_count;         /* live diffuse particles (desc.diffuse) */
    uint32_t diffuse_dropped;       /* generated in the last step but dropped: max_diffuse full */
    uint64_t diffuse_generated_total; /* diffuse particles ever generated (added ones excluded) */
    uint64_t diffuse_dropped_total; /* generated but dropped for capacity, ever */
} pbf_step_stats;
PBF_API pbf_result PBF_CALL pbf_world_get_stats(pbf_world_id world, pbf_step_stats* out_stats);

/* Per-stage time of the last step, for tuning (pbf_bench prints it). Off by default: with
 * profiling on, every stage boundary of a step records a timer (a CUDA event on the CUDA
 * backend), which costs a little, and pbf_world_get_profile waits for the last step. Stages are
 * the solver's own and may change between versions: read their names, not their indices. */
#define PBF_PROFILE_MAX_STAGES 16
typedef struct pbf_step_profile {
    uint32_t struct_size;
    uint32_t stage_count;                   /* stages of this solver, <= PBF_PROFILE_MAX_STAGES */
    float stage_ms[PBF_PROFILE_MAX_STAGES]; /* ms per stage in the last step, all its substeps;
                                               all zero while profiling is off */
} pbf_step_profile;
PBF_API pbf_result PBF_CALL pbf_world_set_profiling(pbf_world_id world, uint32_t enabled);
PBF_API pbf_result PBF_CALL pbf_world_get_profile(pbf_world_id world, pbf_step_profile* out_profile);
/* The name of stage `stage` (e.g. "lambda"), or NULL outside 0..stage_count-1. */
PBF_API const char* PBF_CALL pbf_profile_stage_name(uint32_t stage);

/* ---- Emitters and drains ------------------------------------------------------------------ */
/* One-shot fill of an axis-aligned box with particles on a cubic lattice at rest spacing.
 * Lattice points outside the walls (centres closer than particle_radius to the domain's faces)
 * are dropped; a box with none inside is refused (PBF_ERROR_INVALID_ARGUMENT). Emits what fits
 * under max_particles; *out_emitted (may be NULL) says how many. Emitting zero because the
 * world is full returns PBF_ERROR_CAPACITY. */
typedef struct pbf_block_desc {
    uint32_t struct_size;
    float box_min[3];
    float box_max[3];
    float velocity[3];          /* initial velocity (default 0) */
    pbf_material_id material;   /* the particles' material; zeroed (default): the world's default
                                   material */
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
    PBF_EMITTER_NOZZLE = 1,     /* emits particles_per_second through a disc, along direction;
                                   points of the disc inside a collider emit nothing */
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
    pbf_material_id material;   /* nozzle: the particles' material; zeroed (default): the world's
                                   default material. A drain removes every material. */
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
/* Moves a nozzle: its disc centre and its direction (normalised by the library). A drain gives
 * PBF_ERROR_INVALID_ARGUMENT (check EMITTER_KIND). Takes effect at the next step. */
PBF_API pbf_result PBF_CALL pbf_emitter_set_nozzle(pbf_world_id world, pbf_emitter_id emitter,
                                                   const float position[3], const float direction[3]);
/* Moves a drain: the corners of its box (box_max > box_min on every axis). A nozzle gives
 * PBF_ERROR_INVALID_ARGUMENT (check EMITTER_KIND). Takes effect at the next step. */
PBF_API pbf_result PBF_CALL pbf_emitter_set_drain_box(pbf_world_id world, pbf_emitter_id emitter,
                                                      const float box_min[3], const float box_max[3]);

/* ---- Meshes (for PBF_SHAPE_MESH colliders) ------------------------------------------------ */
/* A triangle mesh becomes a signed distance field on a regular grid of cell_size, built once at
 * pbf_world_create_mesh (on the world's backend: the GPU for a CUDA world; the call waits for
 * the build) and shared by every collider that names it. The arrays are copied: the caller may
 * free them on return. Memory: a dense grid over the mesh's bounds grown by a pad, 8 bytes per
 * grid point (a distance and the solid's share of a particle's kernel, for boundary density):
 * nx·ny·nz·8 bytes, nx = ceil((extent_x + 2·pad) / cell_size) + 1, pad = h + 4·cell_size +
 * thickness/2 (h = 4 particle radii); at most PBF_MAX_MESH_FIELD_BYTES (256 MiB) per mesh (more:
 * PBF_ERROR_CAPACITY naming the voxel count), PBF_MAX_MESHES per world. Distances are exact at
 * the grid points and trilinear between them: a flat face is honoured to well under a cell, a
 * convex edge or corner is rounded by up to about one cell. */
#define PBF_MAX_MESHES 256
#define PBF_MAX_MESH_FIELD_BYTES 268435456
typedef struct pbf_mesh_id { uint32_t index; uint32_t generation; } pbf_mesh_id;
typedef struct pbf_mesh_desc {
    uint32_t struct_size;
    const float* vertices;      /* vertex_count x 3 floats: the mesh in its own frame (a collider's
                                   pose places it), engine units (metres) */
    uint32_t vertex_count;      /* 3 .. 2^24 */
    const uint32_t* indices;    /* triangle_count x 3, each < vertex_count; counter-clockwise seen
                                   from outside (the right-hand normal points out of the solid).
                                   A closed mesh wound inside out is accepted, not reported: its
                                   winding number inside is -1, so no point is inside and it acts
                                   as a surface without a solid behind it */
    uint32_t triangle_count;    /* 1 .. 2^22; degenerate (zero-area) triangles are skipped, a mesh of
                                   only degenerate ones is refused (PBF_ERROR_INVALID_ARGUMENT) */
    uint32_t closed;            /* 1 (default): watertight, inside by the generalised winding number
                                   (small holes and overlaps tolerated); 0: open (terrain pieces,
                                   single-sided planes): solid within thickness/2 of the surface on
                                   both sides, whatever its winding. A container is an open shell
                                   (closed 0, e.g. a box without its lid) or a closed hollow mesh
                                   (an outer surface and an inner one wound inward); a closed box
                                   is solid and pushes water emitted inside it out */
    float thickness;            /* open meshes: the shell's thickness (0, the default: 2 particle
                                   radii; fluid then rests thickness/2 + 1 radius from the surface) */
    float cell_size;            /* the field's grid spacing (0, the default: the particle radius) */
} pbf_mesh_desc;
PBF_API pbf_result PBF_CALL pbf_mesh_desc_init(pbf_mesh_desc* desc, uint32_t struct_size);
static inline pbf_mesh_desc pbf_mesh_desc_default(void) {
    pbf_mesh_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_mesh_desc);
    (void)pbf_mesh_desc_init(&d, d.struct_size);
    return d;
}
PBF_API pbf_result PBF_CALL pbf_world_create_mesh(pbf_world_id world, const pbf_mesh_desc* desc, pbf_mesh_id* out_mesh);
/* PBF_ERROR_INVALID_STATE while a collider uses the mesh (destroy those colliders first). */
PBF_API pbf_result PBF_CALL pbf_world_destroy_mesh(pbf_world_id world, pbf_mesh_id mesh);

/* ---- Colliders ---------------------------------------------------------------------------- */
typedef enum pbf_collider_shape {
    PBF_SHAPE_PLANE = 1,        /* the half-space below the plane through position with normal
                                   rotation·(0,1,0) is solid */
    PBF_SHAPE_SPHERE = 2,       /* radius */
    PBF_SHAPE_CAPSULE = 3,      /* radius; segment from -half_height to +half_height on local y */
    PBF_SHAPE_BOX = 4,          /* half_extents, oriented by rotation */
    PBF_SHAPE_MESH = 5,         /* the triangle mesh `mesh` (pbf_world_create_mesh), placed by the
                                   pose; radius, half_height, half_extents unused */
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
    float friction;             /* Coulomb friction coefficient μ, 0..1 (default 0, slip): on contact
                                   the tangential motion relative to the collider is removed up
                                   to μ times the depth the contact pushed the particle out */
    uint32_t dynamic;           /* 0 or 1 (default 0). 1: the library records the force and torque
                                   the fluid exerts on the collider each step
                                   (pbf_collider_get_force); the engine integrates its body and
                                   moves it (motion KINEMATIC, pbf_collider_set_target_pose). A STATIC
                                   dynamic collider only measures (a load on a fixed wall).
                                   Accuracy (docs/physics.md, Two-way coupling): buoyancy within
                                   3 % with the body >= 12 particle diameters across and the
                                   density held near rest (adaptive_error_target 0.003). */
    float center_of_mass[3];    /* dynamic: the point torques are taken about, in the collider's
                                   own frame (default 0: its position) */
    pbf_mesh_id mesh;           /* PBF_SHAPE_MESH: a live mesh of this world (any number of
                                   colliders may share it); ignored by the other shapes */
} pbf_collider_desc;
PBF_API pbf_result PBF_CALL pbf_collider_desc_init(pbf_collider_desc* desc, uint32_t struct_size);
static inline pbf_collider_desc pbf_collider_desc_default(void) {
    pbf_collider_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_collider_desc);
    (void)pbf_collider_desc_init(&d, d.struct_size);
    return d;
}
/* A collider created where fluid is (or teleported there, or a block emitted into one) did not
 * move into it: the next step's first substep moves the particles inside it out and settles
 * what that piles at its surface, in their positions only, so the water is not flung
 * (docs/physics.md, Overlaps; that substep runs at least 32 extra constraint iterations, in
 * rounds of 8 between neighbour-grid builds). */
PBF_API pbf_result PBF_CALL pbf_world_create_collider(pbf_world_id world, const pbf_collider_desc* desc,
                                                      pbf_collider_id* out_collider);
PBF_API pbf_result PBF_CALL pbf_world_destroy_collider(pbf_world_id world, pbf_collider_id collider);
/* Kinematic colliders only: the target pose, reached at the end of the next step. The solver
 * moves the collider from its current pose to this one over that step (linearly in position,
 * by slerp in rotation, one pose per substep). A static collider gives PBF_ERROR_INVALID_STATE. */
PBF_API pbf_result PBF_CALL pbf_collider_set_target_pose(pbf_world_id world, pbf_collider_id collider,
                                                         const float position[3], const float rotation[4]);
/* Any collider: puts it at this pose now, without moving it there (no sweep: the next step
 * starts and ends at this pose, and so does a pending target). For engines that respawn or
 * stream a body: a target pose far away would sweep through the fluid in one step and fling it.
 * Fluid it lands in is moved out and settled as for a new collider (pbf_world_create_collider). */
PBF_API pbf_result PBF_CALL pbf_collider_teleport(pbf_world_id world, pbf_collider_id collider, const float position[3],
                                                  const float rotation[4]);

/* ---- Two-way coupling --------------------------------------------------------------------- *
 * The fluid's push on a dynamic collider over one step, as its mean force (N) and its torque
 * about the collider's center_of_mass at its pose at the end of the step (N·m): the impulse the
 * contacts and the boundary density gave the particles, reversed, over the step's length. */
typedef struct pbf_collider_force {
    float force[3];
    float torque[3];
} pbf_collider_force;
/* The force of the last step (zero before the collider's first step, and after a step too short
 * to simulate: pbf_world_step; the next step's force carries its impulse). Waits for that step to
 * finish on the backend (on CUDA: one copy of the whole table per step, later calls read the
 * host copy). Refused with PBF_ERROR_INVALID_STATE when the collider is not dynamic. */
PBF_API pbf_result PBF_CALL pbf_collider_get_force(pbf_world_id world, pbf_collider_id collider,
                                                   pbf_collider_force* out_force);
/* The same forces in backend memory for engines that read them on the GPU:
 * pbf_world_map_collider_forces, below pbf_mapped_buffer. */

/* ---- Fluid materials ---------------------------------------------------------------------- *
 * A world holds up to PBF_MAX_MATERIALS materials; each particle carries the index of its
 * material's handle in one byte (PBF_BUFFER_MATERIALS). Index 0 is the default material, which
 * every world starts with: the world's rest_density and its solver parameters' xsph_c and
 * ldc_gain (setting its viscosity or ldc_gain sets those; its rest density is the world's), no
 * surface tension, cohesion or adhesion. A world that never creates a material runs exactly as
 * before. docs/materials.md gives the model, units and approximations. */
#define PBF_MAX_MATERIALS 8
typedef struct pbf_material_desc {
    uint32_t struct_size;
    float rest_density;         /* kg/m³, 0.1..10 times the world's rest_density (default 1000).
                                   Every particle has the world's volume (2·radius)³, so its mass is
                                   rest_density · volume: lighter fluids float on heavier ones. */
    float viscosity;            /* XSPH c per 1/60 s, 0..1 (default 0.01), as solver.xsph_c: the
                                   same physical smoothing at any substep count */
    float ldc_gain;             /* LDC strength for this material, as solver.ldc_gain, 0..1
                                   (default 0.3; only with solver.ldc_enabled) */
    float surface_tension;      /* σ, 1/s², 0..10000 (default 0: off): Akinci 2013's curvature
                                   term between particles of this material */
    float cohesion;             /* κ, 1/s², 0..10000 (default 0: off): Akinci 2013's cohesion
                                   between particles of this material */
    float adhesion;             /* β, 1/s², 0..10000 (default 0: off): pull towards walls and
                                   colliders within h */
    float color[4];             /* RGBA for renderers, each 0..1 (default 0.2, 0.45, 0.9, 1);
                                   not used by the solver */
    uint32_t user_id;           /* any value, for the engine (default 0) */
    uint32_t reserved0;         /* 0 */
} pbf_material_desc;
PBF_API pbf_result PBF_CALL pbf_material_desc_init(pbf_material_desc* desc, uint32_t struct_size);
static inline pbf_material_desc pbf_material_desc_default(void) {
    pbf_material_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_material_desc);
    (void)pbf_material_desc_init(&d, d.struct_size);
    return d;
}
/* PBF_ERROR_CAPACITY when the world holds PBF_MAX_MATERIALS already. */
PBF_API pbf_result PBF_CALL pbf_world_create_material(pbf_world_id world, const pbf_material_desc* desc,
                                                      pbf_material_id* out_material);
/* Refused with PBF_ERROR_INVALID_STATE for the default material, while an emitter uses the
 * material, or while particles carry it (the call counts them: it waits for the last step). */
PBF_API pbf_result PBF_CALL pbf_world_destroy_material(pbf_world_id world, pbf_material_id material);
PBF_API pbf_result PBF_CALL pbf_world_get_material(pbf_world_id world, pbf_material_id material,
                                                   pbf_material_desc* out_desc);
/* New parameters from the next step on (particles keep their material). The default material's
 * rest_density must stay the world's (PBF_ERROR_INVALID_ARGUMENT otherwise). */
PBF_API pbf_result PBF_CALL pbf_world_set_material(pbf_world_id world, pbf_material_id material,
                                                   const pbf_material_desc* desc);
/* The handle of the material at each index (zeroed where none): out_materials[k] is the
 * material of the particles whose PBF_BUFFER_MATERIALS byte is k. [0] is the default material. */
PBF_API pbf_result PBF_CALL pbf_world_get_materials(pbf_world_id world,
                                                    pbf_material_id out_materials[PBF_MAX_MATERIALS]);

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
/* Stable ids: assigned at emission (0, 1, 2, ... per world), kept for the particle's life. After
 * 0xFFFFFFFE they wrap to 0 (0xFFFFFFFF is never an id), so ids are unique among the last
 * 2^32 - 1 particles emitted. */
PBF_API pbf_result PBF_CALL pbf_world_copy_ids(pbf_world_id world, uint32_t* out_ids,
                                               uint32_t max_count, uint32_t* out_written);

/* The particle buffers by name, for pbf_world_copy_buffer and the copies into graphics buffers. */
typedef enum pbf_buffer {
    PBF_BUFFER_POSITIONS = 1,   /* 16 bytes per particle: float x, y, z, density ratio */
    PBF_BUFFER_VELOCITIES = 2,  /* 16 bytes per particle: float vx, vy, vz, 0 */
    PBF_BUFFER_IDS = 3,         /* 4 bytes per particle: uint32_t */
    PBF_BUFFER_SMOOTHED_POSITIONS = 4, /* 16 bytes per particle (PBF_RENDER_SMOOTHED_POSITIONS) */
    PBF_BUFFER_ANISOTROPY = 5,  /* 48 bytes per particle (PBF_RENDER_ANISOTROPY) */
    PBF_BUFFER_DIFFUSE_POSITIONS = 6,  /* 16 bytes per diffuse particle: float x, y, z, kind */
    PBF_BUFFER_DIFFUSE_VELOCITIES = 7, /* 16 bytes per diffuse particle: float vx, vy, vz,
                                          remaining lifetime (s). Both count diffuse_count. */
    PBF_BUFFER_MATERIALS = 8,   /* 1 byte per particle: uint8_t, the index of its material's handle
                                   (pbf_material_id.index; 0 = the default material). Copy-out and
                                   pbf_device_buffers only: not into graphics buffers. */
    PBF_BUFFER_FORCE32 = 0x7FFFFFFF
} pbf_buffer;
/* Copies min(count, out_bytes / element size) particles of one buffer into out (element sizes
 * above; out_bytes must be a multiple of the element size, else PBF_ERROR_INVALID_ARGUMENT).
 * Works on both backends. A render
 * buffer the world does not compute (desc.render.flags), or a diffuse buffer in a world without
 * a diffuse capacity, is refused with PBF_ERROR_INVALID_STATE. The diffuse buffers copy
 * min(diffuse_count, ...) diffuse particles. */
PBF_API pbf_result PBF_CALL pbf_world_copy_buffer(pbf_world_id world, pbf_buffer source, void* out,
                                                  uint64_t out_bytes, uint32_t* out_written);

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
/* The table of every collider's force in backend memory, for engines that read it on the GPU:
 * count = max_colliders rows of pbf_collider_force (stride 24 bytes), row k for the collider whose
 * handle has index k (rows of colliders that are not dynamic hold zero or stale values). The
 * pointer is valid until the world is destroyed; no unmap. On CUDA the rows are written at the end
 * of each pbf_world_step on the world's stream (zeroed by a step too short to simulate): read
 * them on that stream or after an event recorded after the step (pbf_world_record_cuda_event);
 * the next step overwrites them. */
PBF_API pbf_result PBF_CALL pbf_world_map_collider_forces(pbf_world_id world, pbf_mapped_buffer* out_buffer);

/* ==== Interop: zero-copy rendering ======================================================== *
 * The particles go from the solver to the engine's renderer without passing through host
 * memory: as device pointers (CUDA), into OpenGL buffer objects and Direct3D 11 buffers (CUDA
 * graphics interop), or into Vulkan / Direct3D 12 allocations (CUDA external memory, ordered by
 * external semaphores). libpbf talks to the NVIDIA driver it opens at run time and includes no
 * graphics API header: a GL buffer is its name, a D3D11 buffer its ID3D11Buffer pointer.
 *
 * Every function here exists in every build. What the build or the platform lacks is refused
 * with PBF_ERROR_BACKEND_UNAVAILABLE (no CUDA in this build; a Windows-only API or handle type on
 * Linux; a driver without the entry point a call needs, named in the message);
 * pbf_get_interop_support() says what the build has.
 * A CUDA-only call on a world that runs on the CPU backend is refused with
 * PBF_ERROR_INVALID_STATE.
 *
 * Ordering. On CUDA all of a world's work (steps, copies into graphics buffers, semaphore
 * waits and signals) is queued in order on one stream, the world's stream, and the calls
 * return without waiting for the GPU. The caller orders its own GPU work against the world's
 * either on that stream (pbf_world_get_cuda_stream), with a CUDA event
 * (pbf_world_record_cuda_event / pbf_world_wait_cuda_event), with external semaphores, or by
 * handing the world its own stream (pbf_world_set_cuda_stream). Graphics API buffers are
 * ordered by CUDA's map/unmap (OpenGL, Direct3D 11) or by the semaphores in pbf_external_sync
 * (Vulkan, Direct3D 12).
 *
 * Copies. A copy into a graphics buffer writes the live particles of one source buffer in
 * storage order (the order of pbf_world_copy_*): min(count, capacity) elements; elements past
 * them keep what they held. Every copy of one world between two steps has the same order, so
 * element k of a positions buffer and of a velocities buffer is one particle. The count is
 * never read back to the host: a copy can also write draw arguments (see
 * pbf_gl_buffer_desc.draw_args_buffer) for indirect drawing.
 * A copy made automatically after pbf_world_step (PBF_COPY_ON_STEP) that fails makes
 * pbf_world_step return the error although the step itself was taken (an exception to "a
 * failed call changes nothing").
 * ------------------------------------------------------------------------------------------- */

typedef struct pbf_gl_buffer_id { uint32_t index; uint32_t generation; } pbf_gl_buffer_id;
typedef struct pbf_external_buffer_id { uint32_t index; uint32_t generation; } pbf_external_buffer_id;
typedef struct pbf_semaphore_id { uint32_t index; uint32_t generation; } pbf_semaphore_id;
typedef struct pbf_d3d11_buffer_id { uint32_t index; uint32_t generation; } pbf_d3d11_buffer_id;

/* What this build of libpbf can do (a bit set). */
#define PBF_INTEROP_SUPPORT_CUDA 0x1u           /* streams, events, device pointers */
#define PBF_INTEROP_SUPPORT_OPENGL 0x2u         /* pbf_world_register_gl_buffer */
#define PBF_INTEROP_SUPPORT_EXTERNAL_FD 0x4u    /* opaque fd memory and semaphores (Linux) */
#define PBF_INTEROP_SUPPORT_EXTERNAL_WIN32 0x8u /* win32 handles, D3D11 / D3D12 (Windows) */
#define PBF_INTEROP_SUPPORT_D3D11 0x10u         /* pbf_world_register_d3d11_buffer (Windows) */
PBF_API pbf_result PBF_CALL pbf_get_interop_support(uint32_t* out_flags);

/* ---- Streams and events ------------------------------------------------------------------ */
/* The cudaStream_t the world queues its work on (its own, or the one handed to it). */
PBF_API pbf_result PBF_CALL pbf_world_get_cuda_stream(pbf_world_id world, void** out_stream);
/* Makes the world queue its work on stream (a cudaStream_t of the world's device) from now on;
 * NULL returns it to its own stream. Work queued before the call is ordered before work queued
 * after it. The caller keeps the stream alive until it hands the world another one (or NULL)
 * or destroys the world; the world never destroys it. */
PBF_API pbf_result PBF_CALL pbf_world_set_cuda_stream(pbf_world_id world, void* stream);
/* Records an event (a cudaEvent_t owned by the world, created without timing) at the current
 * end of the world's stream: after the last step and copies queued. Wait on it with
 * cudaStreamWaitEvent or cudaEventSynchronize. Each call re-records the same event; it lives
 * until the world is destroyed. */
PBF_API pbf_result PBF_CALL pbf_world_record_cuda_event(pbf_world_id world, void** out_event);
/* Makes the world's stream wait for event (a cudaEvent_t recorded by the caller) before the
 * world's next work: e.g. before the next step overwrites buffers the caller still reads. */
PBF_API pbf_result PBF_CALL pbf_world_wait_cuda_event(pbf_world_id world, void* event);

/* ---- Live buffers as device pointers ----------------------------------------------------- */
#define PBF_MAP_NO_WAIT 0x1u          /* do not wait for the world's stream (see below) */
#define PBF_COUNT_ON_DEVICE 0xFFFFFFFFu /* pbf_device_buffers.count when not waited for */

typedef struct pbf_device_buffers {
    uint32_t struct_size;
    pbf_memory_kind memory;     /* CUDA_DEVICE on CUDA; HOST on the CPU backend */
    void* positions;            /* float x, y, z, w = density ratio ρ/ρ0 (as pbf_world_copy_positions) */
    void* velocities;           /* float vx, vy, vz, 0 */
    void* ids;                  /* uint32_t stable ids */
    void* density_ratio;        /* = positions + 12 bytes: the w of each position, stride 16 */
    const uint32_t* count_device; /* the live count, in memory of kind `memory` */
    void* cuda_stream;          /* the world's stream (NULL on the CPU backend) */
    uint32_t count;             /* live particles; PBF_COUNT_ON_DEVICE when mapped with
                                   PBF_MAP_NO_WAIT on CUDA (read *count_device on the GPU) */
    uint32_t capacity;          /* max_particles: elements allocated behind each pointer */
    uint32_t vec4_stride_bytes; /* 16: positions, velocities and density_ratio */
    uint32_t id_stride_bytes;   /* 4 */
    int32_t cuda_device;        /* the device the pointers belong to; -1 on the CPU backend */
    uint32_t reserved0;
    void* smoothed_positions;   /* float x̄, ȳ, z̄, density ratio (PBF_RENDER_SMOOTHED_POSITIONS);
                                   NULL when the world does not compute it */
    void* anisotropy;           /* 3 float4 per particle (PBF_RENDER_ANISOTROPY); NULL when not
                                   computed */
    uint32_t anisotropy_stride_bytes; /* 48: particle k's rows start at anisotropy + 48·k */
    uint32_t render_flags;      /* PBF_RENDER_* the world computes */
    void* diffuse_positions;    /* float x, y, z, kind per diffuse particle (desc.diffuse); NULL
                                   without a diffuse capacity */
    void* diffuse_velocities;   /* float vx, vy, vz, remaining lifetime (s) */
    const uint32_t* diffuse_count_device; /* the live diffuse count, in memory of kind `memory` */
    uint32_t diffuse_count;     /* live diffuse particles; PBF_COUNT_ON_DEVICE as count */
    uint32_t diffuse_capacity;  /* max_diffuse: elements behind each diffuse pointer */
    void* materials;            /* uint8_t per particle (stride 1): PBF_BUFFER_MATERIALS */
} pbf_device_buffers;

/* Maps the live particle buffers without copying them. Read-only for the caller. Valid until
 * pbf_world_unmap, the next pbf_world_step, any call that adds or removes particles, or
 * pbf_world_destroy, whichever comes first: a step reorders the particles and swaps buffers, so
 * the pointers change from step to step.
 * flags 0: waits for the world's stream; the data is complete when the call returns and count
 *   is the live count.
 * PBF_MAP_NO_WAIT (CUDA): returns at once with count = PBF_COUNT_ON_DEVICE; the data is
 *   complete once the world's stream reaches this point. Read it on the world's stream, or on
 *   another stream after cudaStreamWaitEvent on pbf_world_record_cuda_event's event; and before
 *   the next step, let the world wait for those reads (pbf_world_wait_cuda_event).
 * End the mapping with pbf_world_unmap. */
PBF_API pbf_result PBF_CALL pbf_world_map_device_buffers(pbf_world_id world, uint32_t flags,
                                                         pbf_device_buffers* out_buffers);

/* ---- Copies into graphics buffers: common settings --------------------------------------- */

typedef enum pbf_copy_mode {
    PBF_COPY_ON_STEP = 1,         /* pbf_world_step queues the copy after each step */
    PBF_COPY_ON_RENDER_EVENT = 2, /* the render event (pbf_get_render_event_func) copies the
                                     current particles, on the engine's render thread */
    PBF_COPY_MANUAL = 3,          /* only pbf_world_copy_to_*_buffer copies */
    PBF_COPY_MODE_FORCE32 = 0x7FFFFFFF
} pbf_copy_mode;

/* ---- OpenGL ------------------------------------------------------------------------------ */
typedef struct pbf_gl_buffer_desc {
    uint32_t struct_size;
    uint32_t buffer;            /* GL buffer object name (a GLuint), non-zero; no default */
    pbf_buffer source;          /* default PBF_BUFFER_POSITIONS */
    pbf_copy_mode mode;         /* default PBF_COPY_ON_STEP */
    uint64_t offset_bytes;      /* where element 0 goes; a multiple of 16 (4 for ids) (default 0) */
    uint32_t capacity;          /* elements the buffer holds after offset_bytes (> 0; no default) */
    uint32_t draw_args_buffer;  /* GL buffer (0: none, the default) into which each copy writes
                                   4 uint32_t draw arguments: see draw_args_vertices */
    uint64_t draw_args_offset_bytes; /* a multiple of 4 (default 0) */
    uint32_t draw_args_vertices;/* 0: {n, 1, 0, 0} (glDrawArraysIndirect of n points);
                                   v > 0: {v, n, 0, 0} (v vertices per particle, n instances);
                                   n = min(count, capacity). Default 0. */
    uint32_t reserved0;
} pbf_gl_buffer_desc;
PBF_API pbf_result PBF_CALL pbf_gl_buffer_desc_init(pbf_gl_buffer_desc* desc, uint32_t struct_size);
static inline pbf_gl_buffer_desc pbf_gl_buffer_desc_default(void) {
    pbf_gl_buffer_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_gl_buffer_desc);
    (void)pbf_gl_buffer_desc_init(&d, d.struct_size);
    return d;
}

/* Registers a GL buffer object (and its draw_args_buffer) with CUDA as a copy destination.
 * PBF_COPY_ON_STEP and PBF_COPY_MANUAL: registers now; call it with a GL context current whose
 * share group owns the buffers, on the GPU of the world's CUDA device. The buffer must already
 * have its storage (glBufferData / glBufferStorage) and keep it until unregistered.
 * PBF_COPY_ON_RENDER_EVENT: returns at once; the next render event registers the buffers on
 * the render thread (failures are reported by pbf_world_get_interop_info and the log).
 * Copies are ordered against GL by CUDA's map and unmap: GL commands issued before a copy see
 * the buffer before it, GL commands issued after it (e.g. after pbf_world_step) see the copy. */
PBF_API pbf_result PBF_CALL pbf_world_register_gl_buffer(pbf_world_id world, const pbf_gl_buffer_desc* desc,
                                                         pbf_gl_buffer_id* out_buffer);
/* Unregisters: now (GL context current, as for registration), or for a PBF_COPY_ON_RENDER_EVENT
 * buffer at the next render event, until which the GL buffers must stay alive. The handle is
 * refused from the moment of this call. */
PBF_API pbf_result PBF_CALL pbf_world_unregister_gl_buffer(pbf_world_id world, pbf_gl_buffer_id buffer);
/* Queues a copy of the current particles into the buffer now (any mode but
 * PBF_COPY_ON_RENDER_EVENT, whose buffers the render thread owns). */
PBF_API pbf_result PBF_CALL pbf_world_copy_to_gl_buffer(pbf_world_id world, pbf_gl_buffer_id buffer);

/* ---- Direct3D 11 (Windows) --------------------------------------------------------------- */
/* A D3D11 buffer written by each copy, e.g. the ID3D11Buffer of a Unity ComputeBuffer
 * (ComputeBuffer.GetNativeBufferPtr() under Unity's default Windows renderer), registered with
 * cuGraphicsD3D11RegisterResource: the D3D11 counterpart of pbf_gl_buffer_desc. The buffer must
 * be created on the adapter of the world's CUDA device (match pbf_interop_info.device_luid with
 * the adapter's LUID) and keep its storage until unregistered. Windows builds only, and not yet
 * run on a GPU: on Linux the calls check their arguments, then return
 * PBF_ERROR_BACKEND_UNAVAILABLE. */
typedef struct pbf_d3d11_buffer_desc {
    uint32_t struct_size;
    pbf_buffer source;          /* default PBF_BUFFER_POSITIONS */
    void* buffer;               /* the ID3D11Buffer*, non-NULL; no default. libpbf holds no
                                   reference: the caller keeps it alive until unregistered */
    pbf_copy_mode mode;         /* PBF_COPY_ON_RENDER_EVENT (the default) or PBF_COPY_ON_STEP */
    uint32_t capacity;          /* elements the buffer holds after offset_bytes (> 0; no default) */
    uint64_t offset_bytes;      /* where element 0 goes; a multiple of 16 (4 for ids) (default 0) */
    void* draw_args_buffer;     /* ID3D11Buffer* (NULL: none, the default; may be `buffer`) into
                                   which each copy writes 4 uint32_t draw arguments, the layout of
                                   D3D11_DRAW_INSTANCED_INDIRECT_ARGS (DrawInstancedIndirect, Unity's
                                   Graphics.DrawProceduralIndirect): see draw_args_vertices */
    uint64_t draw_args_offset_bytes; /* a multiple of 4 (default 0) */
    uint32_t draw_args_vertices;/* as in pbf_gl_buffer_desc: 0 gives {n, 1, 0, 0}, v > 0 gives
                                   {v, n, 0, 0} (v vertices per particle, n instances).
                                   Default 0. */
    uint32_t reserved0;
} pbf_d3d11_buffer_desc;
PBF_API pbf_result PBF_CALL pbf_d3d11_buffer_desc_init(pbf_d3d11_buffer_desc* desc, uint32_t struct_size);
static inline pbf_d3d11_buffer_desc pbf_d3d11_buffer_desc_default(void) {
    pbf_d3d11_buffer_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_d3d11_buffer_desc);
    (void)pbf_d3d11_buffer_desc_init(&d, d.struct_size);
    return d;
}
/* Registers a D3D11 buffer (and its draw_args_buffer) with CUDA as a copy destination.
 * Registration, the copies' map and unmap, and unregistration use the D3D11 device's immediate
 * context, which belongs to the engine's render thread:
 * PBF_COPY_ON_RENDER_EVENT (the default): returns at once; the next render event
 *   (pbf_get_render_event_func, e.g. Unity's GL.IssuePluginEvent) registers the buffers, and
 *   every render event copies the current particles into them, on the render thread. Failures
 *   are reported by pbf_world_get_interop_info and the log.
 * PBF_COPY_ON_STEP: registers now and copies after every pbf_world_step, from the calling
 *   thread: only for a caller that runs on the render thread or whose D3D11 device is protected
 *   for use from several threads (ID3D11Multithread::SetMultithreadProtected).
 * Copies are ordered against D3D11 by CUDA's map and unmap, as for OpenGL. */
PBF_API pbf_result PBF_CALL pbf_world_register_d3d11_buffer(pbf_world_id world, const pbf_d3d11_buffer_desc* desc,
                                                            pbf_d3d11_buffer_id* out_buffer);
/* Unregisters: for a PBF_COPY_ON_RENDER_EVENT buffer at the next render event, until which the
 * D3D11 buffers must stay alive; for PBF_COPY_ON_STEP now (from the same thread as its copies).
 * The handle is refused from the moment of this call. pbf_world_destroy unregisters what is
 * still registered from its own thread: unregister first, and let a render event run, where that
 * thread is not the render thread. */
PBF_API pbf_result PBF_CALL pbf_world_unregister_d3d11_buffer(pbf_world_id world, pbf_d3d11_buffer_id buffer);

/* ---- External memory and semaphores (Vulkan, Direct3D) ----------------------------------- */
/* Linux builds import opaque fds (Vulkan). The win32, D3D11 and D3D12 types are compiled only
 * in Windows builds and have not been tested; on Linux they return
 * PBF_ERROR_BACKEND_UNAVAILABLE. */
typedef enum pbf_external_memory_type {
    PBF_EXTERNAL_MEMORY_OPAQUE_FD = 1,          /* Linux: VK_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD_BIT
                                                   (vkGetMemoryFdKHR) */
    PBF_EXTERNAL_MEMORY_OPAQUE_WIN32 = 2,       /* Windows: ..._OPAQUE_WIN32_BIT, an NT handle */
    PBF_EXTERNAL_MEMORY_OPAQUE_WIN32_KMT = 3,   /* Windows: ..._OPAQUE_WIN32_KMT_BIT */
    PBF_EXTERNAL_MEMORY_D3D12_RESOURCE = 4,     /* Windows: NT handle of a committed ID3D12Resource
                                                   (ID3D12Device::CreateSharedHandle) */
    PBF_EXTERNAL_MEMORY_D3D11_RESOURCE = 5,     /* Windows: NT handle (IDXGIResource1::CreateSharedHandle) */
    PBF_EXTERNAL_MEMORY_D3D11_RESOURCE_KMT = 6, /* Windows: KMT handle (IDXGIResource::GetSharedHandle) */
    PBF_EXTERNAL_MEMORY_TYPE_FORCE32 = 0x7FFFFFFF
} pbf_external_memory_type;

typedef struct pbf_external_buffer_desc {
    uint32_t struct_size;
    pbf_external_memory_type type; /* no default: must be set */
    int32_t fd;                 /* OPAQUE_FD: the fd. On success the library owns it (CUDA closes
                                   it); on failure it stays the caller's. Default -1. */
    uint32_t dedicated;         /* 1: a dedicated allocation (VkMemoryDedicatedAllocateInfo, a
                                   D3D12 committed resource, any D3D11 resource). Default 0. */
    void* win32_handle;         /* Windows types: the handle; the caller keeps it. Default NULL. */
    uint64_t size_bytes;        /* size of the whole allocation (VkMemoryAllocateInfo::
                                   allocationSize, the resource's size); > 0, no default */
    uint64_t offset_bytes;      /* where element 0 goes; a multiple of 16 (4 for ids) (default 0) */
    pbf_buffer source;          /* default PBF_BUFFER_POSITIONS */
    pbf_copy_mode mode;         /* default PBF_COPY_MANUAL */
    uint32_t capacity;          /* elements that fit after offset_bytes (> 0; no default) */
    uint32_t write_draw_args;   /* 1: each copy also writes draw arguments at
                                   draw_args_offset_bytes of the same allocation (default 0) */
    uint64_t draw_args_offset_bytes; /* a multiple of 4, 16 bytes: VkDrawIndirectCommand /
                                   D3D12_DRAW_ARGUMENTS layout (see draw_args_vertices) */
    uint32_t draw_args_vertices;/* as in pbf_gl_buffer_desc (default 0) */
    uint32_t reserved0;
} pbf_external_buffer_desc;
PBF_API pbf_result PBF_CALL pbf_external_buffer_desc_init(pbf_external_buffer_desc* desc, uint32_t struct_size);
static inline pbf_external_buffer_desc pbf_external_buffer_desc_default(void) {
    pbf_external_buffer_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_external_buffer_desc);
    (void)pbf_external_buffer_desc_init(&d, d.struct_size);
    return d;
}
/* Imports a graphics API allocation as a copy destination (cudaImportExternalMemory). The
 * allocation must live on the world's CUDA device (match pbf_interop_info.device_uuid with
 * VkPhysicalDeviceIDProperties::deviceUUID, or device_luid with the DXGI adapter's LUID). */
PBF_API pbf_result PBF_CALL pbf_world_import_external_buffer(pbf_world_id world,
                                                             const pbf_external_buffer_desc* desc,
                                                             pbf_external_buffer_id* out_buffer);
/* Waits for the world's stream, then releases the import. The engine may free its allocation
 * after this returns. */
PBF_API pbf_result PBF_CALL pbf_world_release_external_buffer(pbf_world_id world, pbf_external_buffer_id buffer);

typedef enum pbf_semaphore_type {
    PBF_SEMAPHORE_VULKAN_BINARY_FD = 1,         /* Linux: VkSemaphore, OPAQUE_FD (vkGetSemaphoreFdKHR) */
    PBF_SEMAPHORE_VULKAN_TIMELINE_FD = 2,       /* Linux: timeline VkSemaphore, OPAQUE_FD */
    PBF_SEMAPHORE_VULKAN_BINARY_WIN32 = 3,      /* Windows: OPAQUE_WIN32 (NT handle) */
    PBF_SEMAPHORE_VULKAN_BINARY_WIN32_KMT = 4,  /* Windows: OPAQUE_WIN32_KMT */
    PBF_SEMAPHORE_VULKAN_TIMELINE_WIN32 = 5,    /* Windows: timeline, OPAQUE_WIN32 */
    PBF_SEMAPHORE_D3D12_FENCE = 6,              /* Windows: NT handle of a shared ID3D12Fence */
    PBF_SEMAPHORE_TYPE_FORCE32 = 0x7FFFFFFF
} pbf_semaphore_type;

typedef struct pbf_semaphore_desc {
    uint32_t struct_size;
    pbf_semaphore_type type;    /* no default: must be set */
    int32_t fd;                 /* _FD types: owned by the library after success (default -1) */
    uint32_t reserved0;
    void* win32_handle;         /* Windows types: the caller keeps it (default NULL) */
} pbf_semaphore_desc;
PBF_API pbf_result PBF_CALL pbf_semaphore_desc_init(pbf_semaphore_desc* desc, uint32_t struct_size);
static inline pbf_semaphore_desc pbf_semaphore_desc_default(void) {
    pbf_semaphore_desc d;
    memset(&d, 0, sizeof d);
    d.struct_size = (uint32_t)sizeof(pbf_semaphore_desc);
    (void)pbf_semaphore_desc_init(&d, d.struct_size);
    return d;
}
PBF_API pbf_result PBF_CALL pbf_world_import_semaphore(pbf_world_id world, const pbf_semaphore_desc* desc,
                                                       pbf_semaphore_id* out_semaphore);
/* Waits for the world's stream, then releases the import. */
PBF_API pbf_result PBF_CALL pbf_world_release_semaphore(pbf_world_id world, pbf_semaphore_id semaphore);

/* Orders one copy against the engine: the world's stream waits for wait_semaphore (a zeroed id:
 * none) right before the copy, and signals signal_semaphore (a zeroed id: none) right after it.
 * Values are for timeline semaphores and D3D12 fences (wait until >= value; signal to value);
 * binary semaphores ignore them. A binary semaphore the world waits on must have a signal
 * submitted by the engine before the copy runs, as Vulkan requires. */
typedef struct pbf_external_sync {
    uint32_t struct_size;
    uint32_t reserved0;
    pbf_semaphore_id wait_semaphore;
    uint64_t wait_value;
    pbf_semaphore_id signal_semaphore;
    uint64_t signal_value;
} pbf_external_sync;
PBF_API pbf_result PBF_CALL pbf_external_sync_init(pbf_external_sync* sync, uint32_t struct_size);
static inline pbf_external_sync pbf_external_sync_default(void) {
    pbf_external_sync s;
    memset(&s, 0, sizeof s);
    s.struct_size = (uint32_t)sizeof(pbf_external_sync);
    (void)pbf_external_sync_init(&s, s.struct_size);
    return s;
}
/* Queues a copy of the current particles into the buffer now, ordered by sync (may be NULL).
 * Any mode but PBF_COPY_ON_RENDER_EVENT. */
PBF_API pbf_result PBF_CALL pbf_world_copy_to_external_buffer(pbf_world_id world, pbf_external_buffer_id buffer,
                                                              const pbf_external_sync* sync);
/* Sets the sync of the buffer's next automatic copy (PBF_COPY_ON_STEP or _ON_RENDER_EVENT);
 * used once, then cleared. NULL clears it. */
PBF_API pbf_result PBF_CALL pbf_world_set_external_sync(pbf_world_id world, pbf_external_buffer_id buffer,
                                                        const pbf_external_sync* sync);

/* ---- The render-thread entry point ------------------------------------------------------- */
/* Engines such as Unity call this on their render thread (GL.IssuePluginEvent(func, id)). It
 * performs the work queued for PBF_COPY_ON_RENDER_EVENT buffers: pending GL and D3D11 registrations, the
 * copies, pending unregistrations, in that order. event_id: PBF_RENDER_EVENT_ALL_WORLDS or a
 * world's id from pbf_world_get_render_event_id. It returns nothing: failures go to the log
 * callback and to pbf_interop_info.last_render_event_result. */
typedef void (PBF_CALL* pbf_render_event_fn)(int event_id);
#define PBF_RENDER_EVENT_ALL_WORLDS 0
PBF_API pbf_render_event_fn PBF_CALL pbf_get_render_event_func(void);
/* The event id (> 0) that selects this world alone. */
PBF_API pbf_result PBF_CALL pbf_world_get_render_event_id(pbf_world_id world, int32_t* out_event_id);

/* ---- State, device identity and cost ----------------------------------------------------- */
typedef struct pbf_interop_info {
    uint32_t struct_size;
    uint32_t gl_buffers;            /* registered GL buffers (pending ones included) */
    uint32_t external_buffers;
    uint32_t semaphores;
    uint64_t copies;                /* copies into graphics buffers so far */
    uint64_t render_events;         /* render events that ran for this world */
    float last_copy_gpu_ms;         /* GPU time of the last copy batch, map to unmap (waits for it) */
    float last_copy_host_ms;        /* host time the call that queued it spent on it */
    pbf_result last_render_event_result; /* PBF_OK, or why the last render event failed */
    uint32_t pending_render_work;   /* registrations and unregistrations queued for the render event */
    uint8_t device_uuid[16];        /* the CUDA device's UUID (VkPhysicalDeviceIDProperties::deviceUUID) */
    uint8_t device_luid[8];         /* its LUID on Windows (DXGI_ADAPTER_DESC::AdapterLuid); else 0 */
    uint32_t device_node_mask;      /* its LUID node mask on Windows; else 0 */
    int32_t cuda_device;            /* -1 on the CPU backend */
    char last_render_event_message[256]; /* "" or the last render event's failure */
} pbf_interop_info;
PBF_API pbf_result PBF_CALL pbf_world_get_interop_info(pbf_world_id world, pbf_interop_info* out_info);

/* Debug: host<->device copies the library has made, process-wide, since it was loaded (copy-out,
 * stats, particle counts; kernel launch arguments are not counted). The render path
 * (PBF_COPY_*, device buffers, events, semaphores) adds none. Either pointer may be NULL. */
PBF_API pbf_result PBF_CALL pbf_debug_get_transfer_count(uint64_t* out_transfers, uint64_t* out_bytes);

#ifdef __cplusplus
}
#endif
#endif /* PBF_C_API_H */
