/* Colliders as the renderer draws them: a triangle mesh per collider in its own frame, placed by
 * the pose the collider reached in the last step (the target the engine set before it), flat
 * shaded. Opaque bodies go into the background the water refracts and hide the water behind
 * them; glass bodies (colour alpha < 1, a container) draw their far side into the background and
 * their near side over the water, blended, so the water inside stays visible. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_passes.h"

static const char* kBodyVertexShader =
    "#version 430 core\n"
    "layout(location = 0) in vec3 a_position;\n"
    "uniform mat4 u_model;\n"
    "uniform mat4 u_view;\n"
    "uniform mat4 u_proj;\n"
    "out vec3 v_world;\n"
    "void main() {\n"
    "    vec4 world = u_model * vec4(a_position, 1.0);\n"
    "    v_world = world.xyz;\n"
    "    gl_Position = u_proj * u_view * world;\n"
    "}\n";

/* Flat shading: the face normal from the world position's screen derivatives, turned to the
 * viewer; glass is more opaque at grazing angles (a Fresnel-like rim). */
static const char* kBodyFragmentShader =
    "#version 430 core\n"
    "in vec3 v_world;\n"
    "uniform vec4 u_color;\n"
    "uniform vec3 u_eye;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec3 n = normalize(cross(dFdx(v_world), dFdy(v_world)));\n"
    "    vec3 v = normalize(u_eye - v_world);\n"
    "    if (dot(n, v) < 0.0) n = -n;\n"
    "    vec3 l = normalize(vec3(0.4, 0.9, 0.3));\n"
    "    float diffuse = max(dot(n, l), 0.0);\n"
    "    float specular = pow(max(dot(n, normalize(l + v)), 0.0), 60.0);\n"
    "    float rim = pow(1.0 - max(dot(n, v), 0.0), 3.0);\n"
    "    float alpha = u_color.a < 1.0 ? mix(u_color.a, 0.8, rim) : 1.0;\n"
    "    o_color = vec4(u_color.rgb * (0.35 + 0.65 * diffuse) + vec3(0.4 * specular), alpha);\n"
    "}\n";

GLuint bodies_program_create(pbf_egl* e) { return link_program(e, kBodyVertexShader, kBodyFragmentShader); }

scene_body* body_create(pbf_egl* e, scene* s, const pbf_collider_desc* d, const float* vertices, uint32_t vertex_count,
                        const uint32_t* indices, uint32_t triangle_count, const float color[4]) {
    scene_body* b;
    if (s->body_count >= SCENE_MAX_BODIES) die("too many bodies");
    b = &s->bodies[s->body_count++];
    memset(b, 0, sizeof *b);
    CHECK(pbf_world_create_collider(s->world, d, &b->id));
    memcpy(b->position, d->position, sizeof b->position);
    memcpy(b->rotation, d->rotation, sizeof b->rotation);
    memcpy(b->target, d->position, sizeof b->target);
    memcpy(b->target_rotation, d->rotation, sizeof b->target_rotation);
    memcpy(b->color, color, sizeof b->color);
    e->gl.GenVertexArrays(1, &b->vao);
    e->gl.BindVertexArray(b->vao);
    e->gl.GenBuffers(1, &b->vbo);
    e->gl.BindBuffer(GL_ARRAY_BUFFER, b->vbo);
    e->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)vertex_count * 12, vertices, GL_STATIC_DRAW);
    e->gl.EnableVertexAttribArray(0);
    e->gl.VertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 12, (const void*)0);
    e->gl.GenBuffers(1, &b->ibo);
    e->gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, b->ibo);
    e->gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)triangle_count * 12, indices, GL_STATIC_DRAW);
    e->gl.BindVertexArray(0);
    b->index_count = (GLsizei)(triangle_count * 3);
    check_gl(e, "creating a body");
    return b;
}

/* A capsule along local y: rings of latitude from the top pole to the bottom one, the upper
 * hemisphere raised by half_height and the lower lowered (the equator twice: the band between is
 * the cylinder). A sphere is a capsule of half_height 0, a box its 8 corners. */
#define RINGS 16
#define SEGMENTS 24
scene_body* body_create_analytic(pbf_egl* e, scene* s, const pbf_collider_desc* d, const float color[4]) {
    float v[(RINGS + 2) * SEGMENTS * 3];
    uint32_t idx[(RINGS + 1) * SEGMENTS * 6];
    uint32_t nv = 0, nt = 0, r, k;
    if (d->shape == PBF_SHAPE_BOX) {
        static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (k = 0; k < 8; ++k, ++nv) {
            v[3 * k] = (k & 1 ? 1.0f : -1.0f) * d->half_extents[0];
            v[3 * k + 1] = (k & 2 ? 1.0f : -1.0f) * d->half_extents[1];
            v[3 * k + 2] = (k & 4 ? 1.0f : -1.0f) * d->half_extents[2];
        }
        for (k = 0; k < 6; ++k, nt += 2) {
            const uint32_t t[6] = {quads[k][0], quads[k][1], quads[k][2], quads[k][0], quads[k][2], quads[k][3]};
            memcpy(&idx[3 * nt], t, sizeof t);
        }
        return body_create(e, s, d, v, nv, idx, nt, color);
    }
    if (d->shape != PBF_SHAPE_SPHERE && d->shape != PBF_SHAPE_CAPSULE)
        die("body_create_analytic: not a box, sphere or capsule");
    for (r = 0; r < RINGS + 2; ++r) {
        const uint32_t lat = r <= RINGS / 2 ? r : r - 1;
        const float theta = 3.14159265f * (float)lat / RINGS;
        const float lift = d->shape == PBF_SHAPE_CAPSULE ? (r <= RINGS / 2 ? d->half_height : -d->half_height) : 0.0f;
        for (k = 0; k < SEGMENTS; ++k, ++nv) {
            const float phi = 2.0f * 3.14159265f * (float)k / SEGMENTS;
            v[3 * nv] = d->radius * sinf(theta) * cosf(phi);
            v[3 * nv + 1] = d->radius * cosf(theta) + lift;
            v[3 * nv + 2] = -d->radius * sinf(theta) * sinf(phi);
        }
    }
    for (r = 0; r + 1 < RINGS + 2; ++r)
        for (k = 0; k < SEGMENTS; ++k, nt += 2) {
            const uint32_t a = r * SEGMENTS + k, b = r * SEGMENTS + (k + 1) % SEGMENTS, c = a + SEGMENTS,
                           dd = b + SEGMENTS;
            const uint32_t t[6] = {a, c, dd, a, dd, b};
            memcpy(&idx[3 * nt], t, sizeof t);
        }
    return body_create(e, s, d, v, nv, idx, nt, color);
}

void body_set_target(scene* s, scene_body* b, const float position[3], const float rotation[4]) {
    CHECK(pbf_collider_set_target_pose(s->world, b->id, position, rotation));
    memcpy(b->target, position, sizeof b->target);
    memcpy(b->target_rotation, rotation, sizeof b->target_rotation);
}

void bodies_destroy(pbf_egl* e, scene* s) {
    int k;
    for (k = 0; k < s->body_count; ++k) {
        e->gl.DeleteVertexArrays(1, &s->bodies[k].vao);
        e->gl.DeleteBuffers(1, &s->bodies[k].vbo);
        e->gl.DeleteBuffers(1, &s->bodies[k].ibo);
    }
    s->body_count = 0;
}

/* Column-major model matrix of the pose (unit quaternion x, y, z, w). */
static void pose_matrix(float m[16], const float p[3], const float q[4]) {
    const float n = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    const float x = q[0] / n, y = q[1] / n, z = q[2] / n, w = q[3] / n;
    const float r[16] = {1 - 2 * (y * y + z * z),
                         2 * (x * y + z * w),
                         2 * (x * z - y * w),
                         0,
                         2 * (x * y - z * w),
                         1 - 2 * (x * x + z * z),
                         2 * (y * z + x * w),
                         0,
                         2 * (x * z + y * w),
                         2 * (y * z - x * w),
                         1 - 2 * (x * x + y * y),
                         0,
                         p[0],
                         p[1],
                         p[2],
                         1};
    memcpy(m, r, sizeof r);
}

void draw_bodies(pbf_egl* e, const target* t, const camera* c, const scene* s, body_pass pass) {
    const GLuint program = t->body_program;
    const int glass_pass = pass == BODIES_GLASS_BACK || pass == BODIES_GLASS_FRONT;
    int k;
    float model[16];
    if (s->body_count == 0) return;
    e->gl.UseProgram(program);
    e->gl.UniformMatrix4fv(uniform(e, program, "u_view"), 1, GL_FALSE, c->view);
    e->gl.UniformMatrix4fv(uniform(e, program, "u_proj"), 1, GL_FALSE, c->proj);
    e->gl.Uniform3f(uniform(e, program, "u_eye"), c->eye[0], c->eye[1], c->eye[2]);
    e->gl.Enable(GL_DEPTH_TEST);
    e->gl.DepthFunc(GL_LESS);
    if (pass == BODIES_DEPTH_ONLY) e->gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    if (glass_pass) {
        /* Glass writes no depth: the water inside must not be hidden from the passes after it. */
        e->gl.DepthMask(GL_FALSE);
        e->gl.Enable(GL_BLEND);
        e->gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
        e->gl.Enable(GL_CULL_FACE);
        e->gl.CullFace(pass == BODIES_GLASS_BACK ? GL_FRONT : GL_BACK);
    }
    for (k = 0; k < s->body_count; ++k) {
        const scene_body* b = &s->bodies[k];
        if ((b->color[3] < 1.0f) != glass_pass) continue;
        pose_matrix(model, b->position, b->rotation);
        e->gl.UniformMatrix4fv(uniform(e, program, "u_model"), 1, GL_FALSE, model);
        e->gl.Uniform4f(uniform(e, program, "u_color"), b->color[0], b->color[1], b->color[2], b->color[3]);
        e->gl.BindVertexArray(b->vao);
        e->gl.DrawElements(GL_TRIANGLES, b->index_count, GL_UNSIGNED_INT, (const void*)0);
    }
    e->gl.BindVertexArray(0);
    e->gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    e->gl.DepthMask(GL_TRUE);
    e->gl.Disable(GL_BLEND);
    e->gl.Disable(GL_CULL_FACE);
    check_gl(e, "drawing bodies");
}
