/* A scene: a libpbf world and the GL vertex buffers the renderer draws from.
 *
 * On CUDA each GL buffer is registered with the world (pbf_world_register_gl_buffer,
 * PBF_COPY_ON_STEP): every pbf_world_step copies its source GPU to GPU and writes the draw count
 * into an indirect-draw buffer; nothing passes through host memory. Where registration is not
 * available (the CPU backend, or a build without CUDA-GL interop) the scene falls back to
 * pbf_world_copy_buffer + glBufferSubData after each step, and says so: that path is for
 * developing without a GPU, not what the published frames show. */
#ifndef PBF_RENDER_SCENE_H
#define PBF_RENDER_SCENE_H

#include "render_common.h"

/* dam, pool: the water-surface scenes, sized by --particles. The others are the scenes of the tests, at
 * the tests' sizes (particle radius 0.02 m): two fluids stratifying, a cube of fluid relaxing to a
 * sphere in zero gravity and drops hanging under spheres (tests/materials_scenes.h); a
 * closed box mesh moved and turned by the engine and boxes floating and sinking
 * (tests/mesh_scenes.h, tests/coupling_scenes.h). */
typedef enum scene_kind {
    SCENE_DAM_BREAK,
    SCENE_POOL,
    SCENE_TWO_FLUIDS,
    SCENE_DROPLET,
    SCENE_HANGING_DROPS,
    SCENE_CONTAINER,
    SCENE_FLOATING_BOXES,
    SCENE_KIND_COUNT
} scene_kind;
extern const char* const kSceneNames[SCENE_KIND_COUNT];

/* One source buffer of the world mirrored in a GL buffer (and its draw arguments). */
typedef struct scene_stream {
    pbf_buffer source;
    uint32_t element_bytes, capacity;
    GLuint buffer, draw_args; /* draw_args: {count, 1, 0, 0} for glDrawArraysIndirect */
    pbf_gl_buffer_id id;
} scene_stream;

/* STREAM_IDS: only in worlds with several materials; the ids pick each particle's material from
 * a table built once after the scene's emissions (render_materials.c). */
enum {
    STREAM_POSITIONS,
    STREAM_VELOCITIES,
    STREAM_SMOOTHED,
    STREAM_ANISOTROPY,
    STREAM_DIFFUSE,
    STREAM_IDS,
    STREAM_COUNT
};

/* A collider the renderer draws at the pose it reached in the last step: a triangle mesh in the
 * collider's frame. color.a < 1: glass (a container whose water stays visible). */
#define SCENE_MAX_BODIES 8
typedef struct scene_body {
    pbf_collider_id id;
    float position[3], rotation[4]; /* reached at the end of the last step: what is drawn */
    float target[3], target_rotation[4];
    float color[4];
    GLuint vao, vbo, ibo;
    GLsizei index_count;
    /* the engine's rigid body (floating boxes): mass (kg), half size (m), velocity */
    float mass, half, velocity[3];
} scene_body;

/* Per material index (PBF_BUFFER_MATERIALS): Beer-Lambert absorption (1/m) and the colour deep
 * fluid tends to, from the material's colour (render_materials.c). */
typedef struct scene_materials {
    int on; /* 1: the world has several materials and STREAM_IDS feeds the material pass */
    float absorption[PBF_MAX_MATERIALS][3], deep[PBF_MAX_MATERIALS][3];
    GLuint table_buffer, table_texture; /* uint8 material index per particle id (texture buffer) */
} scene_materials;

typedef struct scene_options {
    scene_kind kind;
    long particles; /* fluid particles (the dam's column, or the pool's final fill) */
    long substeps;  /* 0: chosen from the dam front's speed at 1/60 s steps */
    long frames;    /* the pool's nozzle spreads its particles over these frames */
    int surface;    /* 1: smoothed positions + anisotropy; 0: positions + velocities */
    pbf_backend backend;
} scene_options;

typedef struct scene {
    pbf_world_id world;
    uint32_t capacity, emitted;
    float radius, dt;
    float box_min[3], box_max[3]; /* the tank's walls */
    float eye[3], at[3];          /* where the camera stands and looks */
    int zero_copy;                /* 1: GL buffers registered with the world */
    int has_diffuse;              /* 1: the world makes diffuse particles (STREAM_DIFFUSE) */
    int stream_on[STREAM_COUNT];
    scene_stream streams[STREAM_COUNT];
    /* Vertex arrays: the fluid's float4 attributes from location 0 on (spheres: position,
     * velocity; surface: smoothed position, the anisotropy's three rows), the diffuse positions. */
    GLuint fluid_vao, diffuse_vao;
    int fluid_draw_args_stream; /* the stream whose draw arguments count the fluid */
    /* the pool's nozzle */
    pbf_emitter_id nozzle;
    int nozzle_on;
    long frame, nozzle_frames;
    void* host;                /* the copy path's staging memory */
    int draw_walls;            /* 1: the domain's walls are the tank (edges drawn) */
    uint64_t engine_transfers; /* host<->device copies of the steps and hooks of a scene with colliders */
    int body_count;
    scene_body bodies[SCENE_MAX_BODIES];
    scene_materials materials;
    /* The engine's side of a frame, around pbf_world_step: set target poses, read forces. */
    void (*before_step)(struct scene* s);
    void (*after_step)(struct scene* s);
} scene;

/* The scenes of the tests (render_test_scenes.c): domain, radius, camera and solver settings into
 * d before the world exists; then materials, colliders and particles. */
void test_scene_configure(scene* s, const scene_options* o, pbf_world_desc* d);
void test_scene_populate(pbf_egl* e, scene* s, const scene_options* o);
/* What the test of the scene measures, at the end of the run, printed as a "measured:" line
 * (render_test_checks.c; nothing for dam and pool). */
void test_scene_report(scene* s, const scene_options* o);

/* Colliders (render_bodies.c): creates the collider and its drawing mesh (vertices xyz in its
 * frame, counter-clockwise triangles seen from outside); returns the body. */
scene_body* body_create(pbf_egl* e, scene* s, const pbf_collider_desc* d, const float* vertices, uint32_t vertex_count,
                        const uint32_t* indices, uint32_t triangle_count, const float color[4]);
/* A box, sphere or capsule collider with a generated mesh. */
scene_body* body_create_analytic(pbf_egl* e, scene* s, const pbf_collider_desc* d, const float color[4]);
void body_set_target(scene* s, scene_body* b, const float position[3], const float rotation[4]);
void bodies_destroy(pbf_egl* e, scene* s);

/* Materials (render_materials.c): the optics of every material, and the id -> material table
 * (one copy-out of ids and materials, before the frame loop). Leaves materials.on 0 in a world
 * with only the default material, which then looks exactly as before. */
void materials_prepare(pbf_egl* e, scene* s);
void materials_destroy(pbf_egl* e, scene* s);

void scene_create(pbf_egl* e, scene* s, const scene_options* o);
/* One frame: pbf_world_step (which copies into the GL buffers on the zero-copy path) and, on the
 * copy path, the copies. */
void scene_step(pbf_egl* e, scene* s);
void scene_destroy(pbf_egl* e, scene* s);
/* Compares GL buffer `stream` with pbf_world_copy_buffer; returns mismatching floats. */
long scene_verify(pbf_egl* e, const scene* s, int stream, uint32_t* out_count);

#endif /* PBF_RENDER_SCENE_H */
