/* The draw passes of pbf_render_gl, into one offscreen target.
 *   spheres (render_spheres.c): sphere impostors of the positions, coloured by speed or density
 *     ratio, and the tank's edges;
 *   surface (render_surface.c): a screen-space fluid surface from the smoothed positions and the
 *     anisotropy: ellipsoid depth, bilateral depth smoothing, thickness, then shading with
 *     refraction of the background, Fresnel and a specular highlight;
 *   diffuse (render_diffuse.c): foam, spray and bubbles as small point sprites. */
#ifndef PBF_RENDER_PASSES_H
#define PBF_RENDER_PASSES_H

#include "render_scene.h"

/* Texture + framebuffer pairs of the surface passes. */
typedef struct surface_buffers {
    GLuint background, depth, smooth[2], thickness; /* textures */
    GLuint background_fbo, depth_fbo, smooth_fbo[2], thickness_fbo, depth_rb;
    GLuint background_program, depth_program, thickness_program, blur_program, composite_program;
    /* Several materials: per pixel, the optical depth (sum of absorption x chord) and the deep
     * colour x chord, summed over the splats (RGBA32F, one framebuffer with both). solid_rb: the
     * depth of the opaque bodies, so water behind them adds no thickness. */
    GLuint optics, tint, material_fbo, material_program, solid_rb;
} surface_buffers;

/* Which bodies draw_bodies draws, and how (render_bodies.c). */
typedef enum body_pass {
    BODIES_OPAQUE,     /* shaded, depth written */
    BODIES_DEPTH_ONLY, /* opaque bodies' depth only (what hides water) */
    BODIES_GLASS_BACK, /* glass, the faces turned away from the camera, blended, no depth */
    BODIES_GLASS_FRONT /* glass, the faces towards it, blended over what is there, no depth */
} body_pass;

typedef struct surface_style {
    float splat_scale; /* ellipsoid radii times this (overlap closes the surface) */
    int smooth_iterations;
    float smooth_sigma; /* the filter's spatial sigma, in particle radii */
} surface_style;

typedef struct target {
    int width, height;
    GLuint fbo, color, depth; /* the frame: RGBA8 + 24-bit depth renderbuffers */
    GLuint sphere_program, line_program, diffuse_program, body_program, line_vao, line_vbo, empty_vao;
    surface_buffers surface;
    unsigned char* pixels;
} target;

void target_create(pbf_egl* e, target* t, int width, int height);
void target_destroy(pbf_egl* e, target* t);
/* The frame into t->fbo. */
void draw_spheres(pbf_egl* e, const target* t, const camera* c, const scene* s, int color_by_density);
void draw_surface(pbf_egl* e, const target* t, const camera* c, const scene* s, const surface_style* style);
void draw_tank(pbf_egl* e, const target* t, const camera* c, const scene* s);
void draw_diffuse(pbf_egl* e, const target* t, const camera* c, const scene* s);
void draw_bodies(pbf_egl* e, const target* t, const camera* c, const scene* s, body_pass pass);
/* One fullscreen triangle (gl_VertexID), for the surface passes. */
void draw_fullscreen(pbf_egl* e, const target* t);

GLuint diffuse_program_create(pbf_egl* e);
GLuint bodies_program_create(pbf_egl* e);
void surface_create(pbf_egl* e, target* t);
void surface_destroy(pbf_egl* e, target* t);

#endif /* PBF_RENDER_PASSES_H */
