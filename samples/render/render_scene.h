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

typedef enum scene_kind { SCENE_DAM_BREAK, SCENE_POOL } scene_kind;

/* One source buffer of the world mirrored in a GL buffer (and its draw arguments). */
typedef struct scene_stream {
    pbf_buffer source;
    uint32_t element_bytes, capacity;
    GLuint buffer, draw_args; /* draw_args: {count, 1, 0, 0} for glDrawArraysIndirect */
    pbf_gl_buffer_id id;
} scene_stream;

enum { STREAM_POSITIONS, STREAM_VELOCITIES, STREAM_SMOOTHED, STREAM_ANISOTROPY, STREAM_DIFFUSE, STREAM_COUNT };

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
    void* host; /* the copy path's staging memory */
} scene;

void scene_create(pbf_egl* e, scene* s, const scene_options* o);
/* One frame: pbf_world_step (which copies into the GL buffers on the zero-copy path) and, on the
 * copy path, the copies. */
void scene_step(pbf_egl* e, scene* s);
void scene_destroy(pbf_egl* e, scene* s);
/* Compares GL buffer `stream` with pbf_world_copy_buffer; returns mismatching floats. */
long scene_verify(pbf_egl* e, const scene* s, int stream, uint32_t* out_count);

#endif /* PBF_RENDER_SCENE_H */
