/* What every part of pbf_render_gl shares: error exits, shader building, the camera's matrices
 * and PNG output. */
#ifndef PBF_RENDER_COMMON_H
#define PBF_RENDER_COMMON_H

#include <stdint.h>

#include "egl_gl.h"
#include "pbf_c_api.h"

#define CHECK(call)                                                                             \
    do {                                                                                        \
        pbf_result r_ = (call);                                                                 \
        if (r_ != PBF_OK) {                                                                     \
            fprintf(stderr, "pbf_render_gl: %s failed: %s\n", #call, pbf_last_error_message()); \
            exit(1);                                                                            \
        }                                                                                       \
    } while (0)

void die(const char* what);
void check_gl(pbf_egl* e, const char* where);
double now_ms(void);

/* A program from a vertex and a fragment shader; exits with the info log on failure. */
GLuint link_program(pbf_egl* e, const char* vertex, const char* fragment);
GLint uniform(pbf_egl* e, GLuint program, const char* name);

/* The camera: column-major view and projection matrices (as GL expects). */
typedef struct camera {
    float view[16], proj[16];
    float eye[3];
    int width, height;
} camera;
void camera_look(camera* c, const float eye[3], const float at[3], float fovy_deg, int width, int height);

/* Reads the bound framebuffer's colour (RGB) into pixels (width·height·3 bytes, rows top-down)
 * and writes it to path. 1 on success. */
int write_png(pbf_egl* e, int width, int height, unsigned char* pixels, const char* path);

#endif /* PBF_RENDER_COMMON_H */
