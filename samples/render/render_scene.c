#include "render_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef PBF_RENDER_HAVE_DIFFUSE
#include "render_diffuse_api.h"
#endif

const char* const kSceneNames[SCENE_KIND_COUNT] = {"dam",           "pool",      "two_fluids",    "droplet",
                                                   "hanging_drops", "container", "floating_boxes"};

/* Dam break as in samples/dam_break.c: a column a x 2a x a/2 in a 4a x 2.5a x a/2 tank. */
static float dam_break_spacing(pbf_world_desc* d, scene* s, long particles) {
    const float a = 0.4f, box[3] = {4.0f * a, 2.5f * a, 0.5f * a}, eye[3] = {0.80f, 0.85f, 2.05f},
                at[3] = {0.80f, 0.32f, 0.10f};
    memset(d->domain_min, 0, sizeof d->domain_min);
    memcpy(d->domain_max, box, sizeof box);
    memcpy(s->eye, eye, sizeof eye);
    memcpy(s->at, at, sizeof at);
    return cbrtf(a * 2.0f * a * 0.5f * a / (float)particles);
}

/* The pool: a 1.2 x 0.9 x 0.6 m tank, a third of the particles resting 0.12 m deep, and a nozzle
 * high on the left that pours the rest in over the first 80 % of the frames. Spacing: all the
 * particles fill the tank 0.36 m deep. */
static float pool_spacing(pbf_world_desc* d, scene* s, long particles) {
    const float box[3] = {1.2f, 0.9f, 0.6f}, eye[3] = {0.60f, 1.15f, 2.30f}, at[3] = {0.60f, 0.22f, 0.28f};
    memset(d->domain_min, 0, sizeof d->domain_min);
    memcpy(d->domain_max, box, sizeof box);
    memcpy(s->eye, eye, sizeof eye);
    memcpy(s->at, at, sizeof at);
    return cbrtf(box[0] * box[2] * 0.36f / (float)particles);
}

static void pool_fill(scene* s, float spacing, long particles, long frames) {
    pbf_block_desc block = pbf_block_desc_default();
    pbf_emitter_desc n = pbf_emitter_desc_default();
    const float speed = 3.5f, pour_s = 0.8f * (float)frames / 60.0f, dir[3] = {0.8f, -0.45f, 0.0f};
    block.box_max[0] = s->box_max[0];
    block.box_max[1] = 0.12f;
    block.box_max[2] = s->box_max[2];
    CHECK(pbf_world_emit_block(s->world, &block, &s->emitted));
    n.type = PBF_EMITTER_NOZZLE;
    n.position[0] = 0.12f;
    n.position[1] = 0.70f;
    n.position[2] = 0.30f;
    memcpy(n.direction, dir, sizeof dir);
    n.speed = speed;
    n.particles_per_second = ((float)particles - (float)s->emitted) / pour_s;
    /* The disc must carry the rate at rest spacing (docs/physics.md, Walls): π r² v / s³ ≥ rate,
     * with 30 % to spare. */
    n.radius = sqrtf(1.3f * n.particles_per_second * spacing * spacing * spacing / (3.14159265f * speed));
    CHECK(pbf_world_create_emitter(s->world, &n, &s->nozzle));
    s->nozzle_on = 1;
    s->nozzle_frames = (long)(pour_s * 60.0f);
}

static void stream_create(pbf_egl* e, scene* s, int k, pbf_buffer source, uint32_t element_bytes, uint32_t capacity) {
    scene_stream* st = &s->streams[k];
    const GLuint zero_args[4] = {0, 0, 0, 0};
    st->source = source;
    st->element_bytes = element_bytes;
    st->capacity = capacity;
    e->gl.GenBuffers(1, &st->buffer);
    e->gl.BindBuffer(GL_ARRAY_BUFFER, st->buffer);
    e->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)capacity * element_bytes, NULL, GL_DYNAMIC_DRAW);
    e->gl.GenBuffers(1, &st->draw_args);
    e->gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, st->draw_args);
    e->gl.BufferData(GL_DRAW_INDIRECT_BUFFER, sizeof zero_args, zero_args, GL_DYNAMIC_DRAW);
    s->stream_on[k] = 1;
    check_gl(e, "creating a vertex buffer");
}

/* A vertex array over streams ks[0..n): each float4 of their elements is the next attribute (an
 * id stream: one uint attribute). */
static GLuint vao_create(pbf_egl* e, const scene* s, const int* ks, int n) {
    GLuint vao, location = 0, a;
    int i;
    e->gl.GenVertexArrays(1, &vao);
    e->gl.BindVertexArray(vao);
    for (i = 0; i < n; ++i) {
        const scene_stream* st = &s->streams[ks[i]];
        e->gl.BindBuffer(GL_ARRAY_BUFFER, st->buffer);
        if (st->element_bytes == 4) { /* ids: one uint attribute */
            e->gl.EnableVertexAttribArray(location);
            e->gl.VertexAttribIPointer(location++, 1, GL_UNSIGNED_INT, 4, (const void*)0);
        }
        for (a = 0; a < st->element_bytes / 16; ++a, ++location) {
            e->gl.EnableVertexAttribArray(location);
            e->gl.VertexAttribPointer(location, 4, GL_FLOAT, GL_FALSE, (GLsizei)st->element_bytes,
                                      (const void*)(uintptr_t)(a * 16));
        }
    }
    e->gl.BindVertexArray(0);
    check_gl(e, "creating a vertex array");
    return vao;
}

/* Registers the stream with the world; 0 when zero-copy is not available here. */
static int stream_register(scene* s, int k) {
    scene_stream* st = &s->streams[k];
    pbf_gl_buffer_desc gd = pbf_gl_buffer_desc_default();
    pbf_result r;
    gd.buffer = st->buffer;
    gd.source = st->source;
    gd.mode = PBF_COPY_ON_STEP;
    gd.capacity = st->capacity;
    gd.draw_args_buffer = st->draw_args;
    r = pbf_world_register_gl_buffer(s->world, &gd, &st->id);
    if (r == PBF_ERROR_BACKEND_UNAVAILABLE || r == PBF_ERROR_INVALID_STATE) return 0;
    CHECK(r);
    return 1;
}

void scene_create(pbf_egl* e, scene* s, const scene_options* o) {
    pbf_world_desc desc = pbf_world_desc_default();
    float spacing = 0.0f, front_speed;
    long substeps = o->substeps;
    int k;
    memset(s, 0, sizeof *s);
    s->dt = 1.0f / 60.0f;
    s->draw_walls = 1;
    desc.backend = o->backend;
    if (o->kind == SCENE_DAM_BREAK || o->kind == SCENE_POOL) {
        spacing =
            o->kind == SCENE_POOL ? pool_spacing(&desc, s, o->particles) : dam_break_spacing(&desc, s, o->particles);
        desc.max_particles = (uint32_t)(o->particles * 11 / 10 + 64);
        desc.particle_radius = 0.5f * spacing;
        /* substeps 0: enough for the fastest water (the dam front, or the nozzle's jet after its
         * fall) to move < 0.4 h per substep at 1/60 s steps (as dam_break.c); otherwise that many
         * substeps and a dt short enough for it (as pbf_bench). */
        front_speed = o->kind == SCENE_POOL ? sqrtf(3.5f * 3.5f + 2.0f * 9.81f * 0.7f) : sqrtf(2.0f * 9.81f * 0.8f);
        if (substeps <= 0)
            substeps = (long)ceilf(front_speed * s->dt / (0.4f * 2.0f * spacing));
        else
            s->dt = fminf(s->dt, 0.4f * 2.0f * spacing / front_speed);
        desc.solver.substeps = (uint32_t)(substeps < 1 ? 1 : substeps > 16 ? 16 : substeps);
    } else {
        test_scene_configure(s, o, &desc);
    }
    if (o->surface) desc.render.flags = PBF_RENDER_SMOOTHED_POSITIONS | PBF_RENDER_ANISOTROPY;
#ifdef PBF_RENDER_HAVE_DIFFUSE
    /* Diffuse particles in the dam and pool scenes; the tests' scenes run without them, as the tests. */
    if (o->kind == SCENE_DAM_BREAK || o->kind == SCENE_POOL) {
        diffuse_enable(&desc, desc.max_particles / 2);
        s->has_diffuse = 1;
    }
#endif
    CHECK(pbf_world_create(&desc, &s->world));
    s->capacity = desc.max_particles;
    s->radius = desc.particle_radius;
    memcpy(s->box_min, desc.domain_min, sizeof s->box_min);
    memcpy(s->box_max, desc.domain_max, sizeof s->box_max);
    if (o->kind == SCENE_POOL) {
        pool_fill(s, spacing, o->particles, o->frames);
    } else if (o->kind == SCENE_DAM_BREAK) {
        pbf_block_desc block = pbf_block_desc_default();
        block.box_max[0] = 0.4f;
        block.box_max[1] = 0.8f;
        block.box_max[2] = 0.2f;
        CHECK(pbf_world_emit_block(s->world, &block, &s->emitted));
    } else {
        test_scene_populate(e, s, o);
    }
    if (o->surface) materials_prepare(e, s);

    if (o->surface) {
        static const int fluid[3] = {STREAM_SMOOTHED, STREAM_ANISOTROPY, STREAM_IDS};
        stream_create(e, s, STREAM_SMOOTHED, PBF_BUFFER_SMOOTHED_POSITIONS, 16, s->capacity);
        stream_create(e, s, STREAM_ANISOTROPY, PBF_BUFFER_ANISOTROPY, 48, s->capacity);
        if (s->materials.on) stream_create(e, s, STREAM_IDS, PBF_BUFFER_IDS, 4, s->capacity);
        s->fluid_vao = vao_create(e, s, fluid, s->materials.on ? 3 : 2);
        s->fluid_draw_args_stream = STREAM_SMOOTHED;
    } else {
        static const int fluid[2] = {STREAM_POSITIONS, STREAM_VELOCITIES};
        stream_create(e, s, STREAM_POSITIONS, PBF_BUFFER_POSITIONS, 16, s->capacity);
        stream_create(e, s, STREAM_VELOCITIES, PBF_BUFFER_VELOCITIES, 16, s->capacity);
        s->fluid_vao = vao_create(e, s, fluid, 2);
        s->fluid_draw_args_stream = STREAM_POSITIONS;
    }
#ifdef PBF_RENDER_HAVE_DIFFUSE
    if (s->has_diffuse) {
        static const int diffuse[1] = {STREAM_DIFFUSE};
        stream_create(e, s, STREAM_DIFFUSE, diffuse_buffer(), 16, desc.max_particles / 2);
        s->diffuse_vao = vao_create(e, s, diffuse, 1);
    }
#endif
    s->zero_copy = 1;
    for (k = 0; k < STREAM_COUNT && s->zero_copy; ++k)
        if (s->stream_on[k] && !stream_register(s, k)) s->zero_copy = 0;
    if (!s->zero_copy) {
        for (k = 0; k < STREAM_COUNT; ++k)
            if (s->stream_on[k] && s->streams[k].id.generation != 0)
                CHECK(pbf_world_unregister_gl_buffer(s->world, s->streams[k].id));
        s->host = malloc((size_t)s->capacity * 48);
        if (!s->host) die("out of memory");
        printf(
            "GL buffers: COPY PATH (pbf_world_copy_buffer + glBufferSubData; zero-copy registration is not "
            "available: %s). Published frames come from the zero-copy path on the GPU.\n",
            pbf_last_error_message());
    } else {
        printf(
            "GL buffers: zero-copy (registered with pbf_world_register_gl_buffer, copied GPU to GPU on each step)\n");
    }
}

/* The copy path: every stream through host memory, and its draw count. */
static void scene_copy(pbf_egl* e, scene* s) {
    int k;
    for (k = 0; k < STREAM_COUNT; ++k) {
        scene_stream* st = &s->streams[k];
        uint32_t written = 0;
        GLuint args[4] = {0, 1, 0, 0};
        if (!s->stream_on[k]) continue;
        CHECK(
            pbf_world_copy_buffer(s->world, st->source, s->host, (uint64_t)st->capacity * st->element_bytes, &written));
        e->gl.BindBuffer(GL_ARRAY_BUFFER, st->buffer);
        e->gl.BufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)written * st->element_bytes, s->host);
        args[0] = written;
        e->gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, st->draw_args);
        e->gl.BufferSubData(GL_DRAW_INDIRECT_BUFFER, 0, sizeof args, args);
    }
}

void scene_step(pbf_egl* e, scene* s) {
    uint64_t before = 0, after = 0;
    int k;
    ++s->frame;
    if (s->nozzle_on && s->frame > s->nozzle_frames) {
        CHECK(pbf_emitter_set_enabled(s->world, s->nozzle, 0));
        s->nozzle_on = 0;
    }
    /* With colliders, the step uploads their poses and the engine reads forces back: counted
     * apart from the render path's transfers (which must stay 0). */
    if (s->body_count) CHECK(pbf_debug_get_transfer_count(&before, NULL));
    if (s->before_step) s->before_step(s);
    CHECK(pbf_world_step(s->world, s->dt));
    for (k = 0; k < s->body_count; ++k) { /* the step took each collider to its target */
        memcpy(s->bodies[k].position, s->bodies[k].target, sizeof s->bodies[k].position);
        memcpy(s->bodies[k].rotation, s->bodies[k].target_rotation, sizeof s->bodies[k].rotation);
    }
    if (s->after_step) s->after_step(s);
    if (s->body_count) {
        CHECK(pbf_debug_get_transfer_count(&after, NULL));
        s->engine_transfers += after - before;
    }
    if (!s->zero_copy) scene_copy(e, s);
}

void scene_destroy(pbf_egl* e, scene* s) {
    int k;
    for (k = 0; k < STREAM_COUNT; ++k) {
        if (!s->stream_on[k]) continue;
        if (s->zero_copy) CHECK(pbf_world_unregister_gl_buffer(s->world, s->streams[k].id));
        e->gl.DeleteBuffers(1, &s->streams[k].buffer);
        e->gl.DeleteBuffers(1, &s->streams[k].draw_args);
    }
    e->gl.DeleteVertexArrays(1, &s->fluid_vao);
    if (s->diffuse_vao) e->gl.DeleteVertexArrays(1, &s->diffuse_vao);
    bodies_destroy(e, s);
    materials_destroy(e, s);
    CHECK(pbf_world_destroy(s->world));
    free(s->host);
}

long scene_verify(pbf_egl* e, const scene* s, int stream, uint32_t* out_count) {
    const scene_stream* st = &s->streams[stream];
    GLuint args[4] = {0, 0, 0, 0};
    uint32_t written = 0, i, floats;
    float *gl_data, *copy;
    long mismatches = 0;
    e->gl.Finish();
    e->gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, st->draw_args);
    e->gl.GetBufferSubData(GL_DRAW_INDIRECT_BUFFER, 0, sizeof args, args);
    gl_data = (float*)malloc((size_t)st->capacity * st->element_bytes);
    copy = (float*)malloc((size_t)st->capacity * st->element_bytes);
    if (!gl_data || !copy) die("out of memory");
    CHECK(pbf_world_copy_buffer(s->world, st->source, copy, (uint64_t)st->capacity * st->element_bytes, &written));
    e->gl.BindBuffer(GL_ARRAY_BUFFER, st->buffer);
    e->gl.GetBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)written * st->element_bytes, gl_data);
    check_gl(e, "reading the GL buffer back");
    if (args[0] != written || args[1] != 1) {
        fprintf(stderr, "pbf_render_gl: draw args {%u, %u} vs copy-out %u\n", args[0], args[1], written);
        ++mismatches;
    }
    floats = written * (st->element_bytes / 4);
    for (i = 0; i < floats; ++i)
        if (memcmp(&gl_data[i], &copy[i], sizeof(float)) != 0) ++mismatches;
    free(gl_data);
    free(copy);
    *out_count = written;
    return mismatches;
}
