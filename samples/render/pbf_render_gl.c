/* Headless zero-copy renderer: a dam break drawn straight from libpbf's GPU buffers.
 *
 *   pbf_render_gl OUT_DIR [--particles N=65536] [--frames N=180] [--every K=15]
 *                         [--size WxH=640x360] [--color speed|density] [--bench N=1000000]
 *                         [--bench-frames N=60]
 *
 * EGL on the device platform (no window, no X) with an OpenGL 4.3 core context. The vertex
 * buffers (positions and velocities) and the indirect draw buffer are registered with libpbf
 * (pbf_world_register_gl_buffer, PBF_COPY_ON_STEP): each pbf_world_step copies the particles
 * GPU to GPU into them and writes the draw count, so the frame loop never reads anything back.
 * Particles are drawn as shaded sphere impostors (point sprites) into a framebuffer object,
 * coloured by speed or by density ratio; every K-th frame is read back and written as a PNG.
 *
 * Then it checks that the GL buffer equals pbf_world_copy_positions, prints the library's
 * host<->device transfer count over the frame loop (0 expected), and times the render path's
 * copy at --bench particles (0: skip). The last line is a one-line summary; the exit code is 0
 * only if everything held. */
#include <math.h>
#include <png.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "egl_gl.h"
#include "pbf_c_api.h"

#define CHECK(call)                                                                            \
    do {                                                                                       \
        pbf_result r_ = (call);                                                                \
        if (r_ != PBF_OK) {                                                                    \
            fprintf(stderr, "pbf_render_gl: %s failed: %s\n", #call, pbf_last_error_message()); \
            exit(1);                                                                           \
        }                                                                                      \
    } while (0)

static void die(const char* what) {
    fprintf(stderr, "pbf_render_gl: %s\n", what);
    exit(1);
}

static void check_gl(pbf_egl* e, const char* where) {
    GLenum err = e->gl.GetError();
    if (err != GL_NO_ERROR) {
        fprintf(stderr, "pbf_render_gl: GL error 0x%04x at %s\n", (unsigned)err, where);
        exit(1);
    }
}

static double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

/* ---- matrices (column-major, as GL expects) ------------------------------------------------ */
static void perspective(float* m, float fovy_deg, float aspect, float znear, float zfar) {
    const float f = 1.0f / tanf(fovy_deg * 0.5f * 3.14159265f / 180.0f);
    memset(m, 0, 16 * sizeof(float));
    m[0] = f / aspect;
    m[5] = f;
    m[10] = (zfar + znear) / (znear - zfar);
    m[11] = -1.0f;
    m[14] = 2.0f * zfar * znear / (znear - zfar);
}

static void look_at(float* m, const float eye[3], const float at[3], const float up[3]) {
    float f[3] = {at[0] - eye[0], at[1] - eye[1], at[2] - eye[2]}, s[3], u[3], n;
    int k;
    n = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    for (k = 0; k < 3; ++k) f[k] /= n;
    s[0] = f[1] * up[2] - f[2] * up[1];
    s[1] = f[2] * up[0] - f[0] * up[2];
    s[2] = f[0] * up[1] - f[1] * up[0];
    n = sqrtf(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (k = 0; k < 3; ++k) s[k] /= n;
    u[0] = s[1] * f[2] - s[2] * f[1];
    u[1] = s[2] * f[0] - s[0] * f[2];
    u[2] = s[0] * f[1] - s[1] * f[0];
    memset(m, 0, 16 * sizeof(float));
    for (k = 0; k < 3; ++k) {
        m[4 * k + 0] = s[k];
        m[4 * k + 1] = u[k];
        m[4 * k + 2] = -f[k];
    }
    m[12] = -(s[0] * eye[0] + s[1] * eye[1] + s[2] * eye[2]);
    m[13] = -(u[0] * eye[0] + u[1] * eye[1] + u[2] * eye[2]);
    m[14] = f[0] * eye[0] + f[1] * eye[1] + f[2] * eye[2];
    m[15] = 1.0f;
}

/* ---- shaders: sphere impostors ------------------------------------------------------------- */
static const char* kVertexShader =
    "#version 430 core\n"
    "layout(location = 0) in vec4 a_position;  // x, y, z, density ratio\n"
    "layout(location = 1) in vec4 a_velocity;\n"
    "uniform mat4 u_view;\n"
    "uniform mat4 u_proj;\n"
    "uniform float u_radius;\n"
    "uniform float u_viewport_height;\n"
    "uniform int u_color_by_density;\n"
    "uniform float u_speed_scale;\n"
    "out vec3 v_color;\n"
    "out vec3 v_center_eye;\n"
    "vec3 ramp(float t) {\n"
    "    vec3 a = vec3(0.05, 0.20, 0.60), b = vec3(0.10, 0.65, 0.95), c = vec3(0.95, 0.97, 1.00);\n"
    "    return t < 0.5 ? mix(a, b, t * 2.0) : mix(b, c, t * 2.0 - 1.0);\n"
    "}\n"
    "vec3 density_ramp(float ratio) {\n"
    "    // below rest: blue; at rest: white; compressed: red\n"
    "    float t = clamp((ratio - 1.0) / 0.08, -1.0, 1.0);\n"
    "    return t < 0.0 ? mix(vec3(0.95), vec3(0.10, 0.35, 0.90), -t) : mix(vec3(0.95), vec3(0.90, 0.15, 0.10), t);\n"
    "}\n"
    "void main() {\n"
    "    vec4 eye = u_view * vec4(a_position.xyz, 1.0);\n"
    "    v_center_eye = eye.xyz;\n"
    "    gl_Position = u_proj * eye;\n"
    "    gl_PointSize = u_viewport_height * u_proj[1][1] * u_radius / gl_Position.w;\n"
    "    v_color = u_color_by_density != 0 ? density_ramp(a_position.w)\n"
    "                                      : ramp(clamp(length(a_velocity.xyz) * u_speed_scale, 0.0, 1.0));\n"
    "}\n";

static const char* kFragmentShader =
    "#version 430 core\n"
    "in vec3 v_color;\n"
    "in vec3 v_center_eye;\n"
    "uniform mat4 u_proj;\n"
    "uniform float u_radius;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec2 c = gl_PointCoord * 2.0 - 1.0;\n"
    "    c.y = -c.y;\n"
    "    float r2 = dot(c, c);\n"
    "    if (r2 > 1.0) discard;\n"
    "    vec3 n = vec3(c, sqrt(1.0 - r2));\n"
    "    vec4 clip = u_proj * vec4(v_center_eye + n * u_radius, 1.0);\n"
    "    gl_FragDepth = clip.z / clip.w * 0.5 + 0.5;\n"
    "    vec3 l = normalize(vec3(0.35, 0.8, 0.5));\n"
    "    float diffuse = max(dot(n, l), 0.0);\n"
    "    float specular = pow(max(dot(n, normalize(l + vec3(0.0, 0.0, 1.0))), 0.0), 40.0);\n"
    "    o_color = vec4(v_color * (0.28 + 0.72 * diffuse) + vec3(0.35) * specular, 1.0);\n"
    "}\n";

/* The tank's edges, as lines. */
static const char* kLineVertexShader =
    "#version 430 core\n"
    "layout(location = 0) in vec3 a_position;\n"
    "uniform mat4 u_view;\n"
    "uniform mat4 u_proj;\n"
    "void main() { gl_Position = u_proj * u_view * vec4(a_position, 1.0); }\n";
static const char* kLineFragmentShader =
    "#version 430 core\n"
    "out vec4 o_color;\n"
    "void main() { o_color = vec4(0.42, 0.45, 0.50, 1.0); }\n";

/* Exits with the info log (get_log: glGetShaderInfoLog or glGetProgramInfoLog) of a shader or
 * program whose compile or link failed (ok == 0). */
static void require_built(GLint ok, PFNGLGETSHADERINFOLOGPROC get_log, GLuint object, const char* what) {
    char log[2048];
    if (ok) return;
    get_log(object, sizeof log, NULL, log);
    fprintf(stderr, "pbf_render_gl: %s error:\n%s\n", what, log);
    exit(1);
}

static GLuint compile(pbf_egl* e, GLenum type, const char* source) {
    GLint ok = 0;
    GLuint s = e->gl.CreateShader(type);
    e->gl.ShaderSource(s, 1, &source, NULL);
    e->gl.CompileShader(s);
    e->gl.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    require_built(ok, e->gl.GetShaderInfoLog, s, "shader compile");
    return s;
}

static GLuint link_program(pbf_egl* e, const char* vertex, const char* fragment) {
    GLint ok = 0;
    GLuint vs = compile(e, GL_VERTEX_SHADER, vertex), fs = compile(e, GL_FRAGMENT_SHADER, fragment);
    GLuint p = e->gl.CreateProgram();
    e->gl.AttachShader(p, vs);
    e->gl.AttachShader(p, fs);
    e->gl.LinkProgram(p);
    e->gl.GetProgramiv(p, GL_LINK_STATUS, &ok);
    require_built(ok, e->gl.GetProgramInfoLog, p, "program link");
    e->gl.DeleteShader(vs);
    e->gl.DeleteShader(fs);
    return p;
}

/* ---- a scene: world + GL buffers registered with it --------------------------------------- */
typedef struct scene {
    pbf_world_id world;
    uint32_t capacity, emitted;
    float radius, dt;
    float box[3]; /* the tank: (0, 0, 0) .. box */
    GLuint positions, velocities, draw_args, vao;
    pbf_gl_buffer_id positions_id, velocities_id;
} scene;

/* Dam break as in samples/dam_break.c: a column a x 2a x a/2 in a 4a x 2.5a x a/2 tank.
 * substeps 0: 1/60 s steps with enough substeps for the front to move < 0.4 h per substep (as
 * dam_break.c); otherwise that many substeps and a dt short enough for it (as pbf_bench). */
static void scene_create(pbf_egl* e, scene* s, long particles, long substeps) {
    const float a = 0.4f;
    const float spacing = cbrtf(a * 2.0f * a * 0.5f * a / (float)particles);
    const float domain_max[3] = {4.0f * a, 2.5f * a, 0.5f * a};
    const float front_speed = sqrtf(2.0f * 9.81f * 2.0f * a);
    pbf_world_desc desc = pbf_world_desc_default();
    pbf_block_desc block = pbf_block_desc_default();
    pbf_gl_buffer_desc gd;
    const float bmax[3] = {a, 2.0f * a, 0.5f * a};
    GLuint zero_args[4] = {0, 0, 0, 0};

    memset(s, 0, sizeof *s);
    s->dt = 1.0f / 60.0f;
    desc.backend = PBF_BACKEND_CUDA;
    desc.max_particles = (uint32_t)(particles * 11 / 10 + 64);
    desc.particle_radius = 0.5f * spacing;
    memset(desc.domain_min, 0, sizeof desc.domain_min);
    memcpy(desc.domain_max, domain_max, sizeof domain_max);
    if (substeps <= 0) substeps = (long)ceilf(front_speed * s->dt / (0.4f * 2.0f * spacing));
    else s->dt = fminf(s->dt, 0.4f * 2.0f * spacing / front_speed); /* pbf_bench's dt: < 0.4 h per step */
    desc.solver.substeps = (uint32_t)(substeps < 1 ? 1 : substeps > 16 ? 16 : substeps);
    CHECK(pbf_world_create(&desc, &s->world));
    memcpy(block.box_max, bmax, sizeof bmax);
    CHECK(pbf_world_emit_block(s->world, &block, &s->emitted));
    s->capacity = desc.max_particles;
    s->radius = desc.particle_radius;
    memcpy(s->box, domain_max, sizeof domain_max);

    /* Vertex buffers sized for the world's capacity, and the indirect draw buffer. */
    e->gl.GenBuffers(1, &s->positions);
    e->gl.BindBuffer(GL_ARRAY_BUFFER, s->positions);
    e->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)s->capacity * 16, NULL, GL_DYNAMIC_DRAW);
    e->gl.GenBuffers(1, &s->velocities);
    e->gl.BindBuffer(GL_ARRAY_BUFFER, s->velocities);
    e->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)s->capacity * 16, NULL, GL_DYNAMIC_DRAW);
    e->gl.GenBuffers(1, &s->draw_args);
    e->gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, s->draw_args);
    e->gl.BufferData(GL_DRAW_INDIRECT_BUFFER, sizeof zero_args, zero_args, GL_DYNAMIC_DRAW);
    e->gl.GenVertexArrays(1, &s->vao);
    e->gl.BindVertexArray(s->vao);
    e->gl.BindBuffer(GL_ARRAY_BUFFER, s->positions);
    e->gl.EnableVertexAttribArray(0);
    e->gl.VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, 16, (const void*)0);
    e->gl.BindBuffer(GL_ARRAY_BUFFER, s->velocities);
    e->gl.EnableVertexAttribArray(1);
    e->gl.VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 16, (const void*)0);
    e->gl.BindVertexArray(0);
    check_gl(e, "creating the vertex buffers");

    /* Register them: each step copies positions (and the draw count) and velocities. */
    gd = pbf_gl_buffer_desc_default();
    gd.buffer = s->positions;
    gd.source = PBF_BUFFER_POSITIONS;
    gd.mode = PBF_COPY_ON_STEP;
    gd.capacity = s->capacity;
    gd.draw_args_buffer = s->draw_args;
    CHECK(pbf_world_register_gl_buffer(s->world, &gd, &s->positions_id));
    gd = pbf_gl_buffer_desc_default();
    gd.buffer = s->velocities;
    gd.source = PBF_BUFFER_VELOCITIES;
    gd.capacity = s->capacity;
    CHECK(pbf_world_register_gl_buffer(s->world, &gd, &s->velocities_id));
}

static void scene_destroy(pbf_egl* e, scene* s) {
    CHECK(pbf_world_unregister_gl_buffer(s->world, s->positions_id));
    CHECK(pbf_world_unregister_gl_buffer(s->world, s->velocities_id));
    CHECK(pbf_world_destroy(s->world));
    e->gl.DeleteVertexArrays(1, &s->vao);
    e->gl.DeleteBuffers(1, &s->positions);
    e->gl.DeleteBuffers(1, &s->velocities);
    e->gl.DeleteBuffers(1, &s->draw_args);
}

/* ---- framebuffer and drawing ---------------------------------------------------------------- */
typedef struct target {
    int width, height;
    GLuint fbo, color, depth, program, line_program, line_vao, line_vbo;
    unsigned char* pixels;
} target;

static void target_create(pbf_egl* e, target* t, int width, int height) {
    t->width = width;
    t->height = height;
    e->gl.GenRenderbuffers(1, &t->color);
    e->gl.BindRenderbuffer(GL_RENDERBUFFER, t->color);
    e->gl.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    e->gl.GenRenderbuffers(1, &t->depth);
    e->gl.BindRenderbuffer(GL_RENDERBUFFER, t->depth);
    e->gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height);
    e->gl.GenFramebuffers(1, &t->fbo);
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    e->gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->color);
    e->gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t->depth);
    if (e->gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("framebuffer incomplete");
    t->program = link_program(e, kVertexShader, kFragmentShader);
    t->line_program = link_program(e, kLineVertexShader, kLineFragmentShader);
    e->gl.GenVertexArrays(1, &t->line_vao);
    e->gl.GenBuffers(1, &t->line_vbo);
    e->gl.BindVertexArray(t->line_vao);
    e->gl.BindBuffer(GL_ARRAY_BUFFER, t->line_vbo);
    e->gl.BufferData(GL_ARRAY_BUFFER, 24 * 3 * sizeof(float), NULL, GL_DYNAMIC_DRAW);
    e->gl.EnableVertexAttribArray(0);
    e->gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, (const void*)0);
    e->gl.BindVertexArray(0);
    t->pixels = (unsigned char*)malloc((size_t)width * (size_t)height * 3);
    if (!t->pixels) die("out of memory");
    check_gl(e, "creating the framebuffer");
}

static void draw(pbf_egl* e, const target* t, const scene* s, int color_by_density) {
    float view[16], proj[16];
    const float eye[3] = {0.80f, 0.70f, 1.95f}, at[3] = {0.80f, 0.44f, 0.10f}, up[3] = {0.0f, 1.0f, 0.0f};
    look_at(view, eye, at, up);
    perspective(proj, 40.0f, (float)t->width / (float)t->height, 0.05f, 20.0f);
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    e->gl.Viewport(0, 0, t->width, t->height);
    e->gl.ClearColor(0.07f, 0.08f, 0.10f, 1.0f);
    e->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    e->gl.Enable(GL_DEPTH_TEST);
    e->gl.DepthFunc(GL_LESS);
    e->gl.Enable(GL_PROGRAM_POINT_SIZE);
    e->gl.UseProgram(t->program);
    e->gl.UniformMatrix4fv(e->gl.GetUniformLocation(t->program, "u_view"), 1, GL_FALSE, view);
    e->gl.UniformMatrix4fv(e->gl.GetUniformLocation(t->program, "u_proj"), 1, GL_FALSE, proj);
    e->gl.Uniform1f(e->gl.GetUniformLocation(t->program, "u_radius"), s->radius);
    e->gl.Uniform1f(e->gl.GetUniformLocation(t->program, "u_viewport_height"), (float)t->height);
    e->gl.Uniform1i(e->gl.GetUniformLocation(t->program, "u_color_by_density"), color_by_density);
    e->gl.Uniform1f(e->gl.GetUniformLocation(t->program, "u_speed_scale"), 1.0f / 3.5f);
    /* The tank's 12 edges (corner k has x, y, z = bits 0, 1, 2 of k). */
    {
        float lines[24 * 3];
        int n = 0, k, axis;
        for (k = 0; k < 8; ++k)
            for (axis = 0; axis < 3; ++axis) {
                int a, j = k | (1 << axis);
                if (j == k) continue;
                for (a = 0; a < 3; ++a) lines[n * 3 + a] = (k >> a & 1) ? s->box[a] : 0.0f;
                for (a = 0; a < 3; ++a) lines[n * 3 + 3 + a] = (j >> a & 1) ? s->box[a] : 0.0f;
                n += 2;
            }
        e->gl.UseProgram(t->line_program);
        e->gl.UniformMatrix4fv(e->gl.GetUniformLocation(t->line_program, "u_view"), 1, GL_FALSE, view);
        e->gl.UniformMatrix4fv(e->gl.GetUniformLocation(t->line_program, "u_proj"), 1, GL_FALSE, proj);
        e->gl.BindVertexArray(t->line_vao);
        e->gl.BindBuffer(GL_ARRAY_BUFFER, t->line_vbo);
        e->gl.BufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(n * 3 * sizeof(float)), lines);
        e->gl.DrawArrays(GL_LINES, 0, n);
        e->gl.UseProgram(t->program);
    }
    e->gl.BindVertexArray(s->vao);
    /* The count comes from the draw arguments libpbf wrote on the GPU: nothing read back. */
    e->gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, s->draw_args);
    e->gl.DrawArraysIndirect(GL_POINTS, (const void*)0);
    e->gl.BindVertexArray(0);
    check_gl(e, "drawing");
}

static int write_png(pbf_egl* e, target* t, const char* path) {
    png_image image;
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    e->gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    e->gl.ReadPixels(0, 0, t->width, t->height, GL_RGB, GL_UNSIGNED_BYTE, t->pixels);
    check_gl(e, "reading pixels");
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = (png_uint_32)t->width;
    image.height = (png_uint_32)t->height;
    image.format = PNG_FORMAT_RGB;
    /* A negative row stride: GL's rows run bottom-up. */
    if (!png_image_write_to_file(&image, path, 0, t->pixels, -(png_int_32)(t->width * 3), NULL)) {
        fprintf(stderr, "pbf_render_gl: writing %s failed: %s\n", path, image.message);
        return 0;
    }
    return 1;
}

/* Compares the GL positions buffer with pbf_world_copy_positions; returns mismatching floats. */
static long verify(pbf_egl* e, const scene* s, uint32_t* out_count) {
    GLuint args[4] = {0, 0, 0, 0};
    uint32_t count = 0, written = 0, i;
    float *gl_data, *copy;
    long mismatches = 0;
    e->gl.Finish();
    e->gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, s->draw_args);
    e->gl.GetBufferSubData(GL_DRAW_INDIRECT_BUFFER, 0, sizeof args, args);
    CHECK(pbf_world_get_particle_count(s->world, &count));
    gl_data = (float*)malloc((size_t)s->capacity * 16);
    copy = (float*)malloc((size_t)s->capacity * 16);
    if (!gl_data || !copy) die("out of memory");
    e->gl.BindBuffer(GL_ARRAY_BUFFER, s->positions);
    e->gl.GetBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)count * 16, gl_data);
    check_gl(e, "reading the GL buffer back");
    CHECK(pbf_world_copy_positions(s->world, copy, s->capacity, &written));
    if (args[0] != count || args[1] != 1 || written != count) {
        fprintf(stderr, "pbf_render_gl: draw args {%u, %u} / copy-out %u vs count %u\n", args[0], args[1], written, count);
        ++mismatches;
    }
    for (i = 0; i < 4 * count; ++i)
        if (memcmp(&gl_data[i], &copy[i], sizeof(float)) != 0) ++mismatches;
    free(gl_data);
    free(copy);
    *out_count = count;
    return mismatches;
}

static void usage(void) {
    fprintf(stderr,
            "usage: pbf_render_gl OUT_DIR [--particles N=65536] [--frames N=180] [--every K=15]\n"
            "                     [--size WxH=640x360] [--color speed|density] [--bench N=1000000]\n"
            "                     [--bench-frames N=60]\n");
    exit(2);
}

int main(int argc, char** argv) {
    const char* out_dir;
    long particles = 65536, frames = 180, every = 15, bench = 1000000, bench_frames = 60;
    int width = 640, height = 360, color_by_density = 0, i, pngs = 0, ok = 1;
    char err[512], path[4096];
    pbf_egl e;
    scene s;
    target t;
    uint64_t transfers_before = 0, transfers_after = 0;
    uint32_t support = 0, verified_count = 0;
    long mismatches;
    double loop_ms;
    pbf_interop_info info;

    if (argc < 2 || argv[1][0] == '-') usage();
    out_dir = argv[1];
    for (i = 2; i < argc; ++i) {
        const char* v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) usage();
        if (strcmp(argv[i], "--particles") == 0) particles = atol(v);
        else if (strcmp(argv[i], "--frames") == 0) frames = atol(v);
        else if (strcmp(argv[i], "--every") == 0) every = atol(v);
        else if (strcmp(argv[i], "--bench") == 0) bench = atol(v);
        else if (strcmp(argv[i], "--bench-frames") == 0) bench_frames = atol(v);
        else if (strcmp(argv[i], "--size") == 0) {
            if (sscanf(v, "%dx%d", &width, &height) != 2) usage();
        } else if (strcmp(argv[i], "--color") == 0) {
            if (strcmp(v, "density") == 0) color_by_density = 1;
            else if (strcmp(v, "speed") == 0) color_by_density = 0;
            else usage();
        } else usage();
        ++i;
    }
    if (particles < 64 || frames < 1 || every < 1 || width < 16 || height < 16 || bench < 0 || bench_frames < 1) usage();
    mkdir(out_dir, 0755);

    CHECK(pbf_get_interop_support(&support));
    if (!(support & PBF_INTEROP_SUPPORT_OPENGL)) die("this libpbf has no CUDA-GL interop (built without CUDA or GL headers)");
    if (!pbf_egl_init(&e, 0, err, sizeof err)) {
        fprintf(stderr, "pbf_render_gl: EGL: %s\n", err);
        return 1;
    }
    printf("GL: %s | %s | EGL device %d%s\n", (const char*)e.gl.GetString(GL_RENDERER),
           (const char*)e.gl.GetString(GL_VERSION), e.egl_device_index,
           e.matched_cuda_device ? " (= CUDA device 0)" : " (CUDA ordinal not reported; first device)");

    target_create(&e, &t, width, height);
    scene_create(&e, &s, particles, 0);
    printf("dam break: %u particles, radius %.4f m, %ld frames of 1/60 s, %dx%d, colour by %s\n", s.emitted, s.radius,
           frames, width, height, color_by_density ? "density ratio" : "speed");

    /* The frame loop: step (which copies into the GL buffers on the GPU), draw, sometimes save.
     * Nothing in it asks libpbf for data on the host. */
    CHECK(pbf_debug_get_transfer_count(&transfers_before, NULL));
    loop_ms = now_ms();
    for (i = 1; i <= frames; ++i) {
        CHECK(pbf_world_step(s.world, s.dt));
        draw(&e, &t, &s, color_by_density);
        if (i % every == 0 || i == frames) {
            snprintf(path, sizeof path, "%s/frame_%04d.png", out_dir, i);
            if (!write_png(&e, &t, path)) ok = 0;
            else ++pngs;
        }
    }
    e.gl.Finish();
    loop_ms = now_ms() - loop_ms;
    CHECK(pbf_debug_get_transfer_count(&transfers_after, NULL));
    printf("frame loop: %ld frames in %.1f ms (%.2f ms/frame incl. PNG writes), %d PNGs in %s\n", frames, loop_ms,
           loop_ms / (double)frames, pngs, out_dir);
    printf("library host<->device transfers during the frame loop: %llu (render path adds none: %s)\n",
           (unsigned long long)(transfers_after - transfers_before), transfers_after == transfers_before ? "yes" : "NO");
    if (transfers_after != transfers_before) ok = 0;

    mismatches = verify(&e, &s, &verified_count);
    printf("GL positions buffer == pbf_world_copy_positions: %s (%u particles, %ld mismatching floats)\n",
           mismatches == 0 ? "yes" : "NO", verified_count, mismatches);
    if (mismatches != 0) ok = 0;
    memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    CHECK(pbf_world_get_interop_info(s.world, &info));
    printf("interop: %u GL buffers, %llu copies, last copy batch %.4f ms GPU, %.4f ms host\n", info.gl_buffers,
           (unsigned long long)info.copies, info.last_copy_gpu_ms, info.last_copy_host_ms);
    scene_destroy(&e, &s);

    /* The render path's cost at --bench particles: per step, the GPU time of map + copy of
     * positions and velocities + draw count + unmap, against the step's own GPU time. */
    if (bench > 0) {
        scene b;
        double copy_gpu = 0.0, copy_host = 0.0, step_gpu = 0.0, copyout_ms = 0.0;
        const long warmup = 5;
        float* host_copy;
        uint32_t written = 0;
        pbf_step_stats stats;
        /* One substep per step, as pbf_bench's "step" (so the share compares with its numbers). */
        scene_create(&e, &b, bench, 1);
        for (i = 0; i < warmup + bench_frames; ++i) {
            CHECK(pbf_world_step(b.world, b.dt));
            memset(&info, 0, sizeof info);
            info.struct_size = sizeof info;
            CHECK(pbf_world_get_interop_info(b.world, &info)); /* waits for the copy */
            memset(&stats, 0, sizeof stats);
            stats.struct_size = sizeof stats;
            CHECK(pbf_world_get_stats(b.world, &stats));
            if (i >= warmup) {
                copy_gpu += info.last_copy_gpu_ms;
                copy_host += info.last_copy_host_ms;
                step_gpu += stats.step_time_ms;
            }
        }
        copy_gpu /= (double)bench_frames;
        copy_host /= (double)bench_frames;
        step_gpu /= (double)bench_frames;
        /* For scale: the same positions through the host (what zero-copy avoids). */
        host_copy = (float*)malloc((size_t)b.capacity * 16);
        if (!host_copy) die("out of memory");
        for (i = 0; i < 5; ++i) {
            double t0 = now_ms();
            CHECK(pbf_world_copy_positions(b.world, host_copy, b.capacity, &written));
            copyout_ms += now_ms() - t0;
        }
        copyout_ms /= 5.0;
        free(host_copy);
        draw(&e, &t, &b, color_by_density);
        snprintf(path, sizeof path, "%s/bench_%ld.png", out_dir, bench);
        if (write_png(&e, &t, path)) ++pngs;
        printf("render path at %u particles (positions + velocities + draw count, %ld steps of 1 substep, 4 "
               "iterations): copy %.4f ms GPU "
               "(map..unmap), %.4f ms host; step %.3f ms GPU; render path = %.2f %% of a step "
               "(copy-out through the host: %.3f ms)\n",
               b.emitted, bench_frames, copy_gpu, copy_host, step_gpu, step_gpu > 0 ? 100.0 * copy_gpu / step_gpu : 0.0,
               copyout_ms);
        printf("BENCH render_path particles=%u substeps=1 iterations=4 copy_gpu_ms=%.4f copy_host_ms=%.4f step_gpu_ms=%.4f percent=%.3f "
               "copyout_host_ms=%.3f\n",
               b.emitted, copy_gpu, copy_host, step_gpu, step_gpu > 0 ? 100.0 * copy_gpu / step_gpu : 0.0, copyout_ms);
        scene_destroy(&e, &b);
    }

    pbf_egl_shutdown(&e);
    printf("pbf_render_gl: %s (%d PNGs in %s)\n", ok ? "OK" : "FAILED", pngs, out_dir);
    return ok ? 0 : 1;
}
