/* The frame target, the sphere-impostor mode and the tank's edges. */
#include <stdlib.h>
#include <string.h>

#include "render_passes.h"

static const char* kSphereVertexShader =
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

static const char* kSphereFragmentShader =
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

static const char* kLineVertexShader =
    "#version 430 core\n"
    "layout(location = 0) in vec3 a_position;\n"
    "uniform mat4 u_view;\n"
    "uniform mat4 u_proj;\n"
    "void main() { gl_Position = u_proj * u_view * vec4(a_position, 1.0); }\n";
static const char* kLineFragmentShader =
    "#version 430 core\n"
    "uniform vec3 u_color;\n"
    "out vec4 o_color;\n"
    "void main() { o_color = vec4(u_color, 1.0); }\n";

void target_create(pbf_egl* e, target* t, int width, int height) {
    memset(t, 0, sizeof *t);
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
    t->sphere_program = link_program(e, kSphereVertexShader, kSphereFragmentShader);
    t->line_program = link_program(e, kLineVertexShader, kLineFragmentShader);
    t->diffuse_program = diffuse_program_create(e);
    t->body_program = bodies_program_create(e);
    e->gl.GenVertexArrays(1, &t->line_vao);
    e->gl.GenBuffers(1, &t->line_vbo);
    e->gl.BindVertexArray(t->line_vao);
    e->gl.BindBuffer(GL_ARRAY_BUFFER, t->line_vbo);
    e->gl.BufferData(GL_ARRAY_BUFFER, 24 * 3 * sizeof(float), NULL, GL_DYNAMIC_DRAW);
    e->gl.EnableVertexAttribArray(0);
    e->gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, (const void*)0);
    e->gl.GenVertexArrays(1, &t->empty_vao);
    e->gl.BindVertexArray(0);
    t->pixels = (unsigned char*)malloc((size_t)width * (size_t)height * 3);
    if (!t->pixels) die("out of memory");
    surface_create(e, t);
    check_gl(e, "creating the framebuffer");
}

void target_destroy(pbf_egl* e, target* t) {
    surface_destroy(e, t);
    e->gl.DeleteProgram(t->sphere_program);
    e->gl.DeleteProgram(t->line_program);
    e->gl.DeleteProgram(t->diffuse_program);
    e->gl.DeleteProgram(t->body_program);
    e->gl.DeleteVertexArrays(1, &t->line_vao);
    e->gl.DeleteVertexArrays(1, &t->empty_vao);
    e->gl.DeleteBuffers(1, &t->line_vbo);
    e->gl.DeleteFramebuffers(1, &t->fbo);
    e->gl.DeleteRenderbuffers(1, &t->color);
    e->gl.DeleteRenderbuffers(1, &t->depth);
    free(t->pixels);
}

void draw_fullscreen(pbf_egl* e, const target* t) {
    e->gl.BindVertexArray(t->empty_vao);
    e->gl.DrawArrays(GL_TRIANGLES, 0, 3);
    e->gl.BindVertexArray(0);
}

void draw_tank(pbf_egl* e, const target* t, const camera* c, const scene* s) {
    /* The tank's 12 edges (corner k has x, y, z = bits 0, 1, 2 of k). */
    float lines[24 * 3];
    int n = 0, k, axis;
    for (k = 0; k < 8; ++k)
        for (axis = 0; axis < 3; ++axis) {
            int a, j = k | (1 << axis);
            if (j == k) continue;
            for (a = 0; a < 3; ++a) lines[n * 3 + a] = (k >> a & 1) ? s->box_max[a] : s->box_min[a];
            for (a = 0; a < 3; ++a) lines[n * 3 + 3 + a] = (j >> a & 1) ? s->box_max[a] : s->box_min[a];
            n += 2;
        }
    e->gl.UseProgram(t->line_program);
    e->gl.UniformMatrix4fv(uniform(e, t->line_program, "u_view"), 1, GL_FALSE, c->view);
    e->gl.UniformMatrix4fv(uniform(e, t->line_program, "u_proj"), 1, GL_FALSE, c->proj);
    e->gl.Uniform3f(uniform(e, t->line_program, "u_color"), 0.42f, 0.45f, 0.50f);
    e->gl.BindVertexArray(t->line_vao);
    e->gl.BindBuffer(GL_ARRAY_BUFFER, t->line_vbo);
    e->gl.BufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(n * 3 * sizeof(float)), lines);
    e->gl.DrawArrays(GL_LINES, 0, n);
    e->gl.BindVertexArray(0);
}

void draw_spheres(pbf_egl* e, const target* t, const camera* c, const scene* s, int color_by_density) {
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    e->gl.Viewport(0, 0, t->width, t->height);
    e->gl.ClearColor(0.07f, 0.08f, 0.10f, 1.0f);
    e->gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    e->gl.Enable(GL_DEPTH_TEST);
    e->gl.DepthFunc(GL_LESS);
    e->gl.Enable(GL_PROGRAM_POINT_SIZE);
    if (s->draw_walls) draw_tank(e, t, c, s);
    draw_bodies(e, t, c, s, BODIES_OPAQUE);
    e->gl.UseProgram(t->sphere_program);
    e->gl.UniformMatrix4fv(uniform(e, t->sphere_program, "u_view"), 1, GL_FALSE, c->view);
    e->gl.UniformMatrix4fv(uniform(e, t->sphere_program, "u_proj"), 1, GL_FALSE, c->proj);
    e->gl.Uniform1f(uniform(e, t->sphere_program, "u_radius"), s->radius);
    e->gl.Uniform1f(uniform(e, t->sphere_program, "u_viewport_height"), (float)t->height);
    e->gl.Uniform1i(uniform(e, t->sphere_program, "u_color_by_density"), color_by_density);
    e->gl.Uniform1f(uniform(e, t->sphere_program, "u_speed_scale"), 1.0f / 3.5f);
    e->gl.BindVertexArray(s->fluid_vao);
    /* The count comes from the draw arguments libpbf wrote on the GPU: nothing read back. */
    e->gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, s->streams[s->fluid_draw_args_stream].draw_args);
    e->gl.DrawArraysIndirect(GL_POINTS, (const void*)0);
    e->gl.BindVertexArray(0);
    draw_bodies(e, t, c, s, BODIES_GLASS_FRONT);
    check_gl(e, "drawing spheres");
}
