/* The screen-space fluid surface (after van der Laan, Green & Sainz 2009, "Screen space fluid
 * rendering with curvature flow", with a bilateral filter in place of curvature flow as in
 * Green 2010, "Screen Space Fluid Rendering for Games", GDC):
 *   1. background: sky and checker floor into a texture (what the water refracts);
 *   2. depth: the particles' ellipsoids (smoothed position + anisotropy) hit per pixel, nearest
 *      eye-space z kept (depth test on gl_FragDepth);
 *   3. thickness: the ellipsoids' chords summed along each pixel's ray;
 *   4. smoothing: a separable bilateral filter of the depth, horizontal then vertical, repeated;
 *   5. composite: normals from the smoothed depth, shading, depth for what is drawn after. */
#include <string.h>

#include "render_passes.h"
#include "render_surface_shaders.h"

static GLuint float_texture(pbf_egl* e, int width, int height) {
    GLuint tex;
    e->gl.GenTextures(1, &tex);
    e->gl.BindTexture(GL_TEXTURE_2D, tex);
    e->gl.TexImage2D(GL_TEXTURE_2D, 0, GL_R32F, width, height, 0, GL_RED, GL_FLOAT, NULL);
    e->gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    e->gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return tex;
}

static GLuint texture_fbo(pbf_egl* e, GLuint tex, GLuint depth_rb) {
    GLuint fbo;
    e->gl.GenFramebuffers(1, &fbo);
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    e->gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex, 0);
    if (depth_rb) e->gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb);
    if (e->gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("surface framebuffer incomplete");
    return fbo;
}

/* The material pass's two RGBA32F targets in one framebuffer, depth-tested against the bodies. */
static void material_targets_create(pbf_egl* e, target* t) {
    surface_buffers* b = &t->surface;
    const GLenum both[2] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
    GLuint* textures[2] = {&b->optics, &b->tint};
    int k;
    for (k = 0; k < 2; ++k) {
        e->gl.GenTextures(1, textures[k]);
        e->gl.BindTexture(GL_TEXTURE_2D, *textures[k]);
        e->gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, t->width, t->height, 0, GL_RGBA, GL_FLOAT, NULL);
        e->gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        e->gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    }
    b->material_fbo = texture_fbo(e, b->optics, b->solid_rb);
    e->gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, b->tint, 0);
    e->gl.DrawBuffers(2, both);
    if (e->gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) die("material framebuffer incomplete");
    b->material_program = link_program(e, kSplatMaterialVertexShader, kSplatMaterialFragmentShader);
}

void surface_create(pbf_egl* e, target* t) {
    surface_buffers* b = &t->surface;
    int k;
    e->gl.GenTextures(1, &b->background);
    e->gl.BindTexture(GL_TEXTURE_2D, b->background);
    e->gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, t->width, t->height, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    e->gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    e->gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    e->gl.GenRenderbuffers(1, &b->solid_rb);
    e->gl.BindRenderbuffer(GL_RENDERBUFFER, b->solid_rb);
    e->gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, t->width, t->height);
    b->background_fbo = texture_fbo(e, b->background, b->solid_rb);
    e->gl.GenRenderbuffers(1, &b->depth_rb);
    e->gl.BindRenderbuffer(GL_RENDERBUFFER, b->depth_rb);
    e->gl.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, t->width, t->height);
    b->depth = float_texture(e, t->width, t->height);
    b->depth_fbo = texture_fbo(e, b->depth, b->depth_rb);
    b->thickness = float_texture(e, t->width, t->height);
    b->thickness_fbo = texture_fbo(e, b->thickness, b->solid_rb);
    material_targets_create(e, t);
    for (k = 0; k < 2; ++k) {
        b->smooth[k] = float_texture(e, t->width, t->height);
        b->smooth_fbo[k] = texture_fbo(e, b->smooth[k], 0);
    }
    b->background_program = link_program(e, kFullscreenVertexShader, kBackgroundFragmentShader);
    b->depth_program = link_program(e, kSplatVertexShader, kSplatDepthFragmentShader);
    b->thickness_program = link_program(e, kSplatVertexShader, kSplatThicknessFragmentShader);
    b->blur_program = link_program(e, kFullscreenVertexShader, kBlurFragmentShader);
    b->composite_program = link_program(e, kFullscreenVertexShader, kCompositeFragmentShader);
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
    check_gl(e, "creating the surface buffers");
}

void surface_destroy(pbf_egl* e, target* t) {
    surface_buffers* b = &t->surface;
    GLuint textures[7] = {b->background, b->depth, b->thickness, b->smooth[0], b->smooth[1], b->optics, b->tint};
    GLuint fbos[6] = {b->background_fbo, b->depth_fbo,     b->thickness_fbo,
                      b->smooth_fbo[0],  b->smooth_fbo[1], b->material_fbo};
    GLuint programs[6] = {b->background_program, b->depth_program,     b->thickness_program,
                          b->blur_program,       b->composite_program, b->material_program};
    GLuint renderbuffers[2] = {b->depth_rb, b->solid_rb};
    int k;
    e->gl.DeleteTextures(7, textures);
    e->gl.DeleteFramebuffers(6, fbos);
    e->gl.DeleteRenderbuffers(2, renderbuffers);
    for (k = 0; k < 6; ++k) e->gl.DeleteProgram(programs[k]);
}

/* The uniforms every pass of this file shares (a program ignores those it lacks). */
static void camera_uniforms(pbf_egl* e, GLuint program, const camera* c) {
    e->gl.UseProgram(program);
    e->gl.UniformMatrix4fv(uniform(e, program, "u_view"), 1, GL_FALSE, c->view);
    e->gl.UniformMatrix4fv(uniform(e, program, "u_proj"), 1, GL_FALSE, c->proj);
    e->gl.Uniform2f(uniform(e, program, "u_viewport"), (float)c->width, (float)c->height);
    e->gl.Uniform3f(uniform(e, program, "u_eye"), c->eye[0], c->eye[1], c->eye[2]);
}

static void draw_splats(pbf_egl* e, GLuint program, const camera* c, const scene* s, const surface_style* style) {
    camera_uniforms(e, program, c);
    e->gl.Uniform1f(uniform(e, program, "u_scale"), style->splat_scale);
    e->gl.Uniform1f(uniform(e, program, "u_min_radius"), 0.5f * s->radius);
    e->gl.Uniform1f(uniform(e, program, "u_viewport_height"), (float)c->height);
    e->gl.BindVertexArray(s->fluid_vao);
    e->gl.BindBuffer(GL_DRAW_INDIRECT_BUFFER, s->streams[s->fluid_draw_args_stream].draw_args);
    e->gl.DrawArraysIndirect(GL_POINTS, (const void*)0);
    e->gl.BindVertexArray(0);
}

static void bind_texture(pbf_egl* e, GLuint program, const char* name, int unit, GLuint tex) {
    e->gl.ActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    e->gl.BindTexture(GL_TEXTURE_2D, tex);
    e->gl.Uniform1i(uniform(e, program, name), unit);
}

/* The material pass into optics and tint (render_materials.c gives the per-material values). */
static void draw_material_splats(pbf_egl* e, const target* t, const camera* c, const scene* s,
                                 const surface_style* style) {
    const surface_buffers* b = &t->surface;
    const GLuint program = b->material_program;
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, b->material_fbo);
    e->gl.ClearBufferfv(GL_COLOR, 0, zero);
    e->gl.ClearBufferfv(GL_COLOR, 1, zero);
    e->gl.UseProgram(program);
    e->gl.ActiveTexture(GL_TEXTURE0);
    e->gl.BindTexture(GL_TEXTURE_BUFFER, s->materials.table_texture);
    e->gl.Uniform1i(uniform(e, program, "u_material_of_id"), 0);
    e->gl.Uniform3fv(uniform(e, program, "u_material_absorption"), PBF_MAX_MATERIALS, &s->materials.absorption[0][0]);
    e->gl.Uniform3fv(uniform(e, program, "u_material_deep"), PBF_MAX_MATERIALS, &s->materials.deep[0][0]);
    draw_splats(e, program, c, s, style);
    e->gl.BindTexture(GL_TEXTURE_BUFFER, 0);
}

/* Smooths b->depth into b->smooth[..]; returns the texture that holds the result. */
static GLuint smooth_depth(pbf_egl* e, const target* t, const camera* c, const scene* s, const surface_style* style) {
    const surface_buffers* b = &t->surface;
    GLuint source = b->depth, program = b->blur_program;
    int pass;
    e->gl.UseProgram(program);
    e->gl.Uniform1f(uniform(e, program, "u_sigma"), style->smooth_sigma * s->radius);
    e->gl.Uniform1f(uniform(e, program, "u_depth_sigma"), 4.0f * s->radius);
    e->gl.Uniform1f(uniform(e, program, "u_pixels_per_metre_at_1m"), 0.5f * c->proj[5] * (float)c->height);
    e->gl.Uniform1i(uniform(e, program, "u_max_radius"), 24);
    for (pass = 0; pass < 2 * style->smooth_iterations; ++pass) {
        e->gl.BindFramebuffer(GL_FRAMEBUFFER, b->smooth_fbo[pass & 1]);
        e->gl.Uniform2i(uniform(e, program, "u_direction"), (pass & 1) ? 0 : 1, (pass & 1) ? 1 : 0);
        bind_texture(e, program, "u_depth", 0, source);
        draw_fullscreen(e, t);
        source = b->smooth[pass & 1];
    }
    return source;
}

void draw_surface(pbf_egl* e, const target* t, const camera* c, const scene* s, const surface_style* style) {
    const surface_buffers* b = &t->surface;
    const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    GLuint depth;
    e->gl.Viewport(0, 0, t->width, t->height);
    e->gl.Enable(GL_PROGRAM_POINT_SIZE);
    /* 1. Background, with the tank's edges and the bodies (seen through the water, refracted);
     *    the opaque bodies' depth stays in solid_rb for the thickness and material passes. */
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, b->background_fbo);
    e->gl.Clear(GL_DEPTH_BUFFER_BIT);
    e->gl.Disable(GL_DEPTH_TEST);
    camera_uniforms(e, b->background_program, c);
    draw_fullscreen(e, t);
    if (s->draw_walls) draw_tank(e, t, c, s);
    draw_bodies(e, t, c, s, BODIES_OPAQUE);
    draw_bodies(e, t, c, s, BODIES_GLASS_BACK);
    /* 2. Nearest ellipsoid per pixel (not behind an opaque body). */
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, b->depth_fbo);
    e->gl.ClearBufferfv(GL_COLOR, 0, zero);
    e->gl.Clear(GL_DEPTH_BUFFER_BIT);
    draw_bodies(e, t, c, s, BODIES_DEPTH_ONLY);
    e->gl.Enable(GL_DEPTH_TEST);
    e->gl.DepthFunc(GL_LESS);
    draw_splats(e, b->depth_program, c, s, style);
    /* 3. Thickness: every ellipsoid's chord in front of the opaque bodies, added (and with
     *    several materials, their optics). */
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, b->thickness_fbo);
    e->gl.ClearBufferfv(GL_COLOR, 0, zero);
    e->gl.Enable(GL_DEPTH_TEST);
    e->gl.DepthMask(GL_FALSE);
    e->gl.Enable(GL_BLEND);
    e->gl.BlendFunc(GL_ONE, GL_ONE);
    draw_splats(e, b->thickness_program, c, s, style);
    if (s->materials.on) draw_material_splats(e, t, c, s, style);
    e->gl.Disable(GL_BLEND);
    e->gl.DepthMask(GL_TRUE);
    e->gl.Disable(GL_DEPTH_TEST);
    /* 4. Smoothing. */
    depth = smooth_depth(e, t, c, s, style);
    /* 5. Shading into the frame, with its depth (for the tank's front edges and diffuse particles). */
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, t->fbo);
    e->gl.Clear(GL_DEPTH_BUFFER_BIT);
    e->gl.Enable(GL_DEPTH_TEST);
    e->gl.DepthFunc(GL_ALWAYS);
    camera_uniforms(e, b->composite_program, c);
    bind_texture(e, b->composite_program, "u_background", 0, b->background);
    bind_texture(e, b->composite_program, "u_depth", 1, depth);
    bind_texture(e, b->composite_program, "u_thickness", 2, b->thickness);
    e->gl.Uniform3f(uniform(e, b->composite_program, "u_absorption"), 6.0f, 2.2f, 1.1f);
    e->gl.Uniform3f(uniform(e, b->composite_program, "u_deep_color"), 0.02f, 0.12f, 0.20f);
    e->gl.Uniform1f(uniform(e, b->composite_program, "u_refraction"), 0.25f);
    e->gl.Uniform1i(uniform(e, b->composite_program, "u_materials"), s->materials.on);
    bind_texture(e, b->composite_program, "u_optics", 3, b->optics);
    bind_texture(e, b->composite_program, "u_tint", 4, b->tint);
    draw_fullscreen(e, t);
    e->gl.ActiveTexture(GL_TEXTURE0);
    e->gl.DepthFunc(GL_LESS);
    if (s->draw_walls) draw_tank(e, t, c, s);
    /* The opaque bodies' depth (for the diffuse particles), then glass over the water. */
    draw_bodies(e, t, c, s, BODIES_DEPTH_ONLY);
    draw_bodies(e, t, c, s, BODIES_GLASS_FRONT);
    check_gl(e, "drawing the surface");
}
