/* Diffuse particles (foam, spray, bubbles) as small round point sprites over the frame. Spray
 * and foam are depth-tested against the water's surface; bubbles are under it, so they are
 * drawn without the test and faint, as if seen through the water (no refraction). */
#include "render_passes.h"

static const char* kDiffuseVertexShader =
    "#version 430 core\n"
    "layout(location = 0) in vec4 a_particle;  // x, y, z, kind: 0 spray, 1 foam, 2 bubble\n"
    "uniform mat4 u_view;\n"
    "uniform mat4 u_proj;\n"
    "uniform float u_radius;\n"
    "uniform float u_viewport_height;\n"
    "uniform int u_bubbles;  // 1: this draw is the bubbles; 0: spray and foam\n"
    "out vec4 v_color;\n"
    "void main() {\n"
    "    int kind = int(a_particle.w + 0.5);\n"
    "    gl_Position = u_proj * u_view * vec4(a_particle.xyz, 1.0);\n"
    "    if ((kind == 2) != (u_bubbles != 0)) gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // clipped\n"
    "    gl_PointSize = max(u_viewport_height * u_proj[1][1] * u_radius / gl_Position.w, 1.5);\n"
    "    v_color = kind == 0 ? vec4(0.97, 0.98, 1.0, 0.9) : kind == 1 ? vec4(0.90, 0.92, 0.94, 0.8)\n"
    "                        : vec4(0.75, 0.82, 0.88, 0.35);\n"
    "}\n";

static const char* kDiffuseFragmentShader =
    "#version 430 core\n"
    "in vec4 v_color;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec2 c = gl_PointCoord * 2.0 - 1.0;\n"
    "    float r2 = dot(c, c);\n"
    "    if (r2 > 1.0) discard;\n"
    "    o_color = vec4(v_color.rgb, v_color.a * (1.0 - r2 * r2));\n"
    "}\n";

GLuint diffuse_program_create(pbf_egl* e) { return link_program(e, kDiffuseVertexShader, kDiffuseFragmentShader); }

void draw_diffuse(pbf_egl* e, const target* t, const camera* c, const scene* s) {
    GLuint p = t->diffuse_program;
    int bubbles;
    if (!s->has_diffuse) return;
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    e->gl.Enable(GL_PROGRAM_POINT_SIZE);
    e->gl.Enable(GL_BLEND);
    e->gl.BlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    e->gl.DepthMask(GL_FALSE);
    e->gl.UseProgram(p);
    e->gl.UniformMatrix4fv(uniform(e, p, "u_view"), 1, GL_FALSE, c->view);
    e->gl.UniformMatrix4fv(uniform(e, p, "u_proj"), 1, GL_FALSE, c->proj);
    e->gl.Uniform1f(uniform(e, p, "u_radius"), 0.6f * s->radius);
    e->gl.Uniform1f(uniform(e, p, "u_viewport_height"), (float)t->height);
    e->gl.BindVertexArray(s->diffuse_vao);
    e->gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, s->streams[STREAM_DIFFUSE].draw_args);
    for (bubbles = 1; bubbles >= 0; --bubbles) {
        if (bubbles)
            e->gl.Disable(GL_DEPTH_TEST);
        else
            e->gl.Enable(GL_DEPTH_TEST);
        e->gl.Uniform1i(uniform(e, p, "u_bubbles"), bubbles);
        e->gl.DrawArraysIndirect(GL_POINTS, (const void*)0);
    }
    e->gl.BindVertexArray(0);
    e->gl.DepthMask(GL_TRUE);
    e->gl.Disable(GL_BLEND);
    check_gl(e, "drawing diffuse particles");
}
