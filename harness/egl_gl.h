/* Headless OpenGL for the render sample and the [gpu] interop tests: an EGL display on the device
 * platform (EGL_EXT_device_enumeration + EGL_EXT_platform_device: no window system, no X), an
 * OpenGL 4.3 core context made current without a surface, and the GL entry points they use,
 * loaded through eglGetProcAddress. Header-only C99 (also compiles as C++).
 *
 *   pbf_egl egl;
 *   char err[256];
 *   if (!pbf_egl_init(&egl, cuda_device, err, sizeof err)) { puts(err); ... }
 *   egl.gl.GenBuffers(1, &buffer); ...
 *   pbf_egl_shutdown(&egl);
 */
#ifndef PBF_SAMPLES_EGL_GL_H
#define PBF_SAMPLES_EGL_GL_H

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>
#include <stdio.h>
#include <string.h>

#ifndef EGL_PLATFORM_DEVICE_EXT
#define EGL_PLATFORM_DEVICE_EXT 0x313F
#endif
#ifndef EGL_CUDA_DEVICE_NV
#define EGL_CUDA_DEVICE_NV 0x323A
#endif

/* X(type, name): the GL functions used, loaded as pbf_gl_functions.name (glName). */
#define PBF_GL_FUNCTIONS(X)                                      \
    X(PFNGLGETSTRINGPROC, GetString)                             \
    X(PFNGLGETERRORPROC, GetError)                               \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                           \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                     \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                           \
    X(PFNGLBUFFERDATAPROC, BufferData)                           \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                     \
    X(PFNGLGETBUFFERSUBDATAPROC, GetBufferSubData)               \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                 \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)           \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                 \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray) \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)         \
    X(PFNGLCREATESHADERPROC, CreateShader)                       \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                       \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                     \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                         \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)               \
    X(PFNGLDELETESHADERPROC, DeleteShader)                       \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                     \
    X(PFNGLATTACHSHADERPROC, AttachShader)                       \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                         \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                       \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)             \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                           \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                     \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)           \
    X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)               \
    X(PFNGLUNIFORM1FPROC, Uniform1f)                             \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                             \
    X(PFNGLUNIFORM3FPROC, Uniform3f)                             \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                 \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)           \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                 \
    X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer) \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)   \
    X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)               \
    X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)         \
    X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)               \
    X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)         \
    X(PFNGLVIEWPORTPROC, Viewport)                               \
    X(PFNGLCLEARCOLORPROC, ClearColor)                           \
    X(PFNGLCLEARPROC, Clear)                                     \
    X(PFNGLENABLEPROC, Enable)                                   \
    X(PFNGLDISABLEPROC, Disable)                                 \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                             \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                           \
    X(PFNGLDRAWARRAYSINDIRECTPROC, DrawArraysIndirect)           \
    X(PFNGLREADPIXELSPROC, ReadPixels)                           \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                         \
    X(PFNGLFINISHPROC, Finish)                                   \
    X(PFNGLGENQUERIESPROC, GenQueries)                           \
    X(PFNGLDELETEQUERIESPROC, DeleteQueries)                     \
    X(PFNGLQUERYCOUNTERPROC, QueryCounter)                       \
    X(PFNGLGETQUERYOBJECTUI64VPROC, GetQueryObjectui64v)         \
    X(PFNGLUNIFORM2FPROC, Uniform2f)                             \
    X(PFNGLUNIFORM2IPROC, Uniform2i)                             \
    X(PFNGLGENTEXTURESPROC, GenTextures)                         \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                   \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                         \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                     \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                           \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                     \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)       \
    X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                     \
    X(PFNGLBLENDFUNCPROC, BlendFunc)                             \
    X(PFNGLDEPTHMASKPROC, DepthMask)                             \
    X(PFNGLVERTEXATTRIBIPOINTERPROC, VertexAttribIPointer)       \
    X(PFNGLTEXBUFFERPROC, TexBuffer)                             \
    X(PFNGLDRAWELEMENTSPROC, DrawElements)                       \
    X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                         \
    X(PFNGLCOLORMASKPROC, ColorMask)                             \
    X(PFNGLCULLFACEPROC, CullFace)                               \
    X(PFNGLUNIFORM3FVPROC, Uniform3fv)                           \
    X(PFNGLUNIFORM4FPROC, Uniform4f)

typedef struct pbf_gl_functions {
#define PBF_GL_DECLARE(type, name) type name;
    PBF_GL_FUNCTIONS(PBF_GL_DECLARE)
#undef PBF_GL_DECLARE
} pbf_gl_functions;

typedef struct pbf_egl {
    EGLDisplay display;
    EGLContext context;
    EGLSurface surface; /* EGL_NO_SURFACE when surfaceless */
    int egl_device_index;
    int matched_cuda_device; /* 1: the EGL device reported the wanted CUDA ordinal */
    pbf_gl_functions gl;
} pbf_egl;

static inline int pbf_egl_fail(char* err, size_t len, const char* what) {
    if (err && len) snprintf(err, len, "%s (EGL error 0x%04x)", what, (unsigned)eglGetError());
    return 0;
}

static inline int pbf_egl_has_extension(const char* list, const char* name) {
    const size_t n = strlen(name);
    const char* p = list;
    while (p && (p = strstr(p, name)) != NULL) {
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return 1;
        p += n;
    }
    return 0;
}

/* Opens the EGL device of CUDA device cuda_device (or the first device when none reports it),
 * creates an OpenGL 4.3 core context and makes it current. 1 on success, 0 with err filled. */
static inline int pbf_egl_init(pbf_egl* e, int cuda_device, char* err, size_t err_len) {
    PFNEGLQUERYDEVICESEXTPROC query_devices;
    PFNEGLQUERYDEVICEATTRIBEXTPROC query_device_attrib;
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_platform_display;
    EGLDeviceEXT devices[32];
    EGLint device_count = 0, major = 0, minor = 0, config_count = 0, i;
    EGLConfig config;
    int chosen = -1;
    const char* display_extensions;
    static const EGLint config_attribs[] = {EGL_SURFACE_TYPE,
                                            EGL_PBUFFER_BIT,
                                            EGL_RENDERABLE_TYPE,
                                            EGL_OPENGL_BIT,
                                            EGL_RED_SIZE,
                                            8,
                                            EGL_GREEN_SIZE,
                                            8,
                                            EGL_BLUE_SIZE,
                                            8,
                                            EGL_DEPTH_SIZE,
                                            24,
                                            EGL_NONE};
    static const EGLint context_attribs[] = {
        EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    static const EGLint pbuffer_attribs[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};

    memset(e, 0, sizeof *e);
    e->display = EGL_NO_DISPLAY;
    e->context = EGL_NO_CONTEXT;
    e->surface = EGL_NO_SURFACE;
    e->egl_device_index = -1;
    query_devices = (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
    query_device_attrib = (PFNEGLQUERYDEVICEATTRIBEXTPROC)eglGetProcAddress("eglQueryDeviceAttribEXT");
    get_platform_display = (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    if (!query_devices || !get_platform_display)
        return pbf_egl_fail(err, err_len, "EGL_EXT_device_enumeration / EGL_EXT_platform_device are missing");
    if (!query_devices(32, devices, &device_count) || device_count < 1)
        return pbf_egl_fail(err, err_len, "eglQueryDevicesEXT found no EGL device");
    for (i = 0; i < device_count && query_device_attrib; ++i) {
        EGLAttrib ordinal = -1;
        if (query_device_attrib(devices[i], EGL_CUDA_DEVICE_NV, &ordinal) && ordinal == (EGLAttrib)cuda_device) {
            chosen = i;
            e->matched_cuda_device = 1;
            break;
        }
    }
    (void)eglGetError(); /* devices without EGL_NV_device_cuda leave an error behind */
    /* No device reported the ordinal: take the first one that initialises. */
    for (i = chosen >= 0 ? chosen : 0; i < device_count; ++i) {
        e->display = get_platform_display(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL);
        if (e->display != EGL_NO_DISPLAY && eglInitialize(e->display, &major, &minor)) {
            e->egl_device_index = i;
            break;
        }
        e->display = EGL_NO_DISPLAY;
        if (chosen >= 0) break;
    }
    if (e->display == EGL_NO_DISPLAY) return pbf_egl_fail(err, err_len, "no EGL device display could be initialised");
    if (!eglBindAPI(EGL_OPENGL_API)) return pbf_egl_fail(err, err_len, "eglBindAPI(EGL_OPENGL_API) failed");
    if (!eglChooseConfig(e->display, config_attribs, &config, 1, &config_count) || config_count < 1)
        return pbf_egl_fail(err, err_len, "no EGL config for OpenGL with a pbuffer");
    e->context = eglCreateContext(e->display, config, EGL_NO_CONTEXT, context_attribs);
    if (e->context == EGL_NO_CONTEXT) return pbf_egl_fail(err, err_len, "cannot create an OpenGL 4.3 core context");
    display_extensions = eglQueryString(e->display, EGL_EXTENSIONS);
    if (!pbf_egl_has_extension(display_extensions, "EGL_KHR_surfaceless_context")) {
        e->surface = eglCreatePbufferSurface(e->display, config, pbuffer_attribs);
        if (e->surface == EGL_NO_SURFACE) return pbf_egl_fail(err, err_len, "cannot create a pbuffer surface");
    }
    if (!eglMakeCurrent(e->display, e->surface, e->surface, e->context))
        return pbf_egl_fail(err, err_len, "eglMakeCurrent failed");
#define PBF_GL_LOAD(type, name)                                                               \
    e->gl.name = (type)eglGetProcAddress("gl" #name);                                         \
    if (!e->gl.name) {                                                                        \
        if (err && err_len) snprintf(err, err_len, "OpenGL function gl%s is missing", #name); \
        return 0;                                                                             \
    }
    PBF_GL_FUNCTIONS(PBF_GL_LOAD)
#undef PBF_GL_LOAD
    return 1;
}

static inline void pbf_egl_shutdown(pbf_egl* e) {
    if (e->display == EGL_NO_DISPLAY) return;
    eglMakeCurrent(e->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (e->surface != EGL_NO_SURFACE) eglDestroySurface(e->display, e->surface);
    if (e->context != EGL_NO_CONTEXT) eglDestroyContext(e->display, e->context);
    eglTerminate(e->display);
    e->display = EGL_NO_DISPLAY;
}

#endif /* PBF_SAMPLES_EGL_GL_H */
