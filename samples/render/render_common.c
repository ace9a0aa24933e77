#include "render_common.h"

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void die(const char* what) {
    fprintf(stderr, "pbf_render_gl: %s\n", what);
    exit(1);
}

void check_gl(pbf_egl* e, const char* where) {
    GLenum err = e->gl.GetError();
    if (err != GL_NO_ERROR) {
        fprintf(stderr, "pbf_render_gl: GL error 0x%04x at %s\n", (unsigned)err, where);
        exit(1);
    }
}

double now_ms(void) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

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

GLuint link_program(pbf_egl* e, const char* vertex, const char* fragment) {
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

GLint uniform(pbf_egl* e, GLuint program, const char* name) { return e->gl.GetUniformLocation(program, name); }

static void perspective(float* m, float fovy_deg, float aspect, float znear, float zfar) {
    const float f = 1.0f / tanf(fovy_deg * 0.5f * 3.14159265f / 180.0f);
    memset(m, 0, 16 * sizeof(float));
    m[0] = f / aspect;
    m[5] = f;
    m[10] = (zfar + znear) / (znear - zfar);
    m[11] = -1.0f;
    m[14] = 2.0f * zfar * znear / (znear - zfar);
}

static void look_at(float* m, const float eye[3], const float at[3]) {
    const float up[3] = {0.0f, 1.0f, 0.0f};
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

void camera_look(camera* c, const float eye[3], const float at[3], float fovy_deg, int width, int height) {
    look_at(c->view, eye, at);
    perspective(c->proj, fovy_deg, (float)width / (float)height, 0.05f, 20.0f);
    memcpy(c->eye, eye, sizeof c->eye);
    c->width = width;
    c->height = height;
}

int write_png(pbf_egl* e, int width, int height, unsigned char* pixels, const char* path) {
    png_image image;
    e->gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
    e->gl.ReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels);
    check_gl(e, "reading pixels");
    memset(&image, 0, sizeof image);
    image.version = PNG_IMAGE_VERSION;
    image.width = (png_uint_32)width;
    image.height = (png_uint_32)height;
    image.format = PNG_FORMAT_RGB;
    /* A negative row stride: GL's rows run bottom-up. */
    if (!png_image_write_to_file(&image, path, 0, pixels, -(png_int_32)(width * 3), NULL)) {
        fprintf(stderr, "pbf_render_gl: writing %s failed: %s\n", path, image.message);
        return 0;
    }
    return 1;
}
