// [gpu] zero-copy rendering (the interop section of pbf_c_api.h): refusals of the interop ABI,
// device pointers ordered by the world's stream and events, GL buffers written by each step (and
// by the render event) equal to copy-out, a Vulkan buffer written through CUDA external memory
// and semaphores equal to copy-out, and the library's own host<->device transfer count left
// unchanged by the render path.
//
// Parts are compiled where the build found what they need (CUDA runtime, EGL + OpenGL, Vulkan);
// a part that was not compiled says so with a warning. Set PBF_TEST_ALLOW_NO_EGL=1 or
// PBF_TEST_ALLOW_NO_VULKAN=1 to accept a machine where EGL or Vulkan cannot start (otherwise the
// test fails: on the GPU machines both are expected to work).
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "support.h"

#if defined(__unix__)
#include <fcntl.h>
#include <unistd.h>
#endif
#if PBF_TEST_HAVE_CUDART
#include <cuda_runtime.h>
#endif
#if PBF_TEST_HAVE_EGL_GL
#include "egl_gl.h"
#endif
#if PBF_TEST_HAVE_VULKAN
#include "vk_interop.h"
#endif

using namespace scene;

namespace {

#define CHECK_CODE(call, code)                                                              \
    do {                                                                                    \
        const pbf_result r_ = (call);                                                       \
        INFO(#call << " -> " << pbf_result_string(r_) << ": " << pbf_last_error_message()); \
        CHECK(std::string(pbf_result_string(r_)) == std::string(pbf_result_string(code)));  \
    } while (0)

uint32_t support() {
    uint32_t s = 0;
    REQUIRE_PBF(pbf_get_interop_support(&s));
    return s;
}

// True when this libpbf's interop has `flag`; else WARNs `missing` (the test then returns).
[[maybe_unused]] bool has_interop(uint32_t flag, const char* missing) {
    if (support() & flag) return true;
    WARN(missing);
    return false;
}

uint64_t transfers() {
    uint64_t n = 0;
    REQUIRE_PBF(pbf_debug_get_transfer_count(&n, nullptr));
    return n;
}

bool env_set(const char* name) {
    const char* v = std::getenv(name);
    return v && *v && std::strcmp(v, "0") != 0;
}

// A small dam break: 8000-odd particles in a 0.8 x 0.5 x 0.2 m tank.
pbf_world_id small_world(pbf_backend backend, uint32_t capacity = 8192) {
    pbf_world_desc d = tank(backend, 0.0125f, 0.8f, 0.5f, 0.2f, capacity);
    d.solver.substeps = 2;
    pbf_world_id w = create(d);
    fill(w, 0, 0, 0, 0.2f, 0.4f, 0.2f);
    return w;
}

pbf_interop_info interop_info(pbf_world_id w) {
    pbf_interop_info info;
    std::memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    REQUIRE_PBF(pbf_world_get_interop_info(w, &info));
    return info;
}

pbf_semaphore_id forged_semaphore() { return pbf_semaphore_id{3, 0x7FFFFFF0u}; }

}  // namespace

TEST_CASE("interop: the ABI refuses bad arguments, stale handles, CPU worlds; info and support", "[gpu][interop]") {
    const uint32_t have = support();
    CHECK((have & PBF_INTEROP_SUPPORT_CUDA) != 0u);
    CHECK_CODE(pbf_get_interop_support(nullptr), PBF_ERROR_INVALID_ARGUMENT);

    // Desc inits: wrong struct_size and NULL.
    pbf_gl_buffer_desc gd;
    CHECK_CODE(pbf_gl_buffer_desc_init(&gd, sizeof gd - 4), PBF_ERROR_STRUCT_SIZE);
    CHECK_CODE(pbf_gl_buffer_desc_init(nullptr, sizeof gd), PBF_ERROR_INVALID_ARGUMENT);
    pbf_external_buffer_desc ed;
    CHECK_CODE(pbf_external_buffer_desc_init(&ed, 8), PBF_ERROR_STRUCT_SIZE);
    pbf_semaphore_desc sd;
    CHECK_CODE(pbf_semaphore_desc_init(&sd, 0), PBF_ERROR_STRUCT_SIZE);
    pbf_external_sync sy;
    CHECK_CODE(pbf_external_sync_init(&sy, sizeof sy + 8), PBF_ERROR_STRUCT_SIZE);
    gd = pbf_gl_buffer_desc_default();
    CHECK(gd.source == PBF_BUFFER_POSITIONS);
    CHECK(gd.mode == PBF_COPY_ON_STEP);
    ed = pbf_external_buffer_desc_default();
    CHECK(ed.fd == -1);
    CHECK(ed.mode == PBF_COPY_MANUAL);

    SECTION("a CPU world: CUDA-only calls are INVALID_STATE, mapping gives host memory") {
        pbf_world_id w = small_world(PBF_BACKEND_CPU);
        void* p = reinterpret_cast<void*>(1);
        CHECK_CODE(pbf_world_get_cuda_stream(w, &p), PBF_ERROR_INVALID_STATE);
        CHECK(p == nullptr);
        CHECK_CODE(pbf_world_set_cuda_stream(w, nullptr), PBF_ERROR_INVALID_STATE);
        CHECK_CODE(pbf_world_record_cuda_event(w, &p), PBF_ERROR_INVALID_STATE);
        pbf_gl_buffer_desc g = pbf_gl_buffer_desc_default();
        g.buffer = 1;
        g.capacity = 16;
        pbf_gl_buffer_id gid;
        CHECK_CODE(pbf_world_register_gl_buffer(w, &g, &gid),
                   (have & PBF_INTEROP_SUPPORT_OPENGL) ? PBF_ERROR_INVALID_STATE : PBF_ERROR_BACKEND_UNAVAILABLE);
        pbf_device_buffers b;
        std::memset(&b, 0, sizeof b);
        b.struct_size = sizeof b;
        REQUIRE_PBF(pbf_world_map_device_buffers(w, PBF_MAP_NO_WAIT, &b));
        CHECK(b.memory == PBF_MEMORY_HOST);
        CHECK(b.cuda_device == -1);
        CHECK(b.cuda_stream == nullptr);
        const Particles parts = read(w);
        CHECK(b.count == parts.count);
        REQUIRE(b.count > 0u);
        CHECK(std::memcmp(b.positions, parts.pos.data(), size_t(b.count) * 16) == 0);
        CHECK(std::memcmp(b.ids, parts.ids.data(), size_t(b.count) * 4) == 0);
        CHECK(static_cast<char*>(b.density_ratio) == static_cast<char*>(b.positions) + 12);
        REQUIRE_PBF(pbf_world_unmap(w));
        const pbf_interop_info info = interop_info(w);
        CHECK(info.cuda_device == -1);
        CHECK(info.gl_buffers == 0u);
        REQUIRE_PBF(pbf_world_destroy(w));
    }

    SECTION("a CUDA world: descs, flags and handles are validated") {
        pbf_world_id w = small_world(PBF_BACKEND_CUDA);
        pbf_device_buffers b;
        std::memset(&b, 0, sizeof b);
        b.struct_size = sizeof b;
        CHECK_CODE(pbf_world_map_device_buffers(w, 2u, &b), PBF_ERROR_INVALID_ARGUMENT);
        b.struct_size = 8;
        CHECK_CODE(pbf_world_map_device_buffers(w, 0, &b), PBF_ERROR_STRUCT_SIZE);
        CHECK_CODE(pbf_world_wait_cuda_event(w, nullptr), PBF_ERROR_INVALID_ARGUMENT);
        CHECK_CODE(pbf_world_record_cuda_event(w, nullptr), PBF_ERROR_INVALID_ARGUMENT);

        pbf_gl_buffer_id gid{1, 1};
        pbf_gl_buffer_desc g = pbf_gl_buffer_desc_default();
        g.capacity = 16;
        CHECK_CODE(pbf_world_register_gl_buffer(w, &g, &gid), PBF_ERROR_INVALID_ARGUMENT);  // buffer 0
        CHECK((gid.index == 0 && gid.generation == 0));
        g.buffer = 5;
        g.capacity = 0;
        CHECK_CODE(pbf_world_register_gl_buffer(w, &g, &gid), PBF_ERROR_INVALID_ARGUMENT);
        g.capacity = 16;
        int32_t bad = 9;  // past the last pbf_buffer (PBF_BUFFER_MATERIALS = 8)
        std::memcpy(&g.source, &bad, sizeof bad);
        CHECK_CODE(pbf_world_register_gl_buffer(w, &g, &gid), PBF_ERROR_INVALID_ARGUMENT);
        g.source = PBF_BUFFER_POSITIONS;
        std::memcpy(&g.mode, &bad, sizeof bad);
        CHECK_CODE(pbf_world_register_gl_buffer(w, &g, &gid), PBF_ERROR_INVALID_ARGUMENT);
        g.mode = PBF_COPY_ON_STEP;
        g.offset_bytes = 8;
        CHECK_CODE(pbf_world_register_gl_buffer(w, &g, &gid), PBF_ERROR_INVALID_ARGUMENT);
        g.offset_bytes = 0;
        g.draw_args_offset_bytes = 2;
        CHECK_CODE(pbf_world_register_gl_buffer(w, &g, &gid), PBF_ERROR_INVALID_ARGUMENT);
        g.draw_args_offset_bytes = 0;
        g.reserved0 = 1;
        CHECK_CODE(pbf_world_register_gl_buffer(w, &g, &gid), PBF_ERROR_INVALID_ARGUMENT);
        CHECK_CODE(pbf_world_register_gl_buffer(w, &g, nullptr), PBF_ERROR_INVALID_ARGUMENT);
        if (have & PBF_INTEROP_SUPPORT_OPENGL) {
            CHECK_CODE(pbf_world_unregister_gl_buffer(w, pbf_gl_buffer_id{0, 0}), PBF_ERROR_INVALID_HANDLE);
            CHECK_CODE(pbf_world_copy_to_gl_buffer(w, pbf_gl_buffer_id{0, 12345}), PBF_ERROR_INVALID_HANDLE);
        }
        // D3D11 on a CUDA world: the desc is checked first; then only Windows builds go on (the
        // buffer would be handed to the driver, so no forged pointer is registered here).
        pbf_d3d11_buffer_desc dd = pbf_d3d11_buffer_desc_default();
        dd.capacity = 16;
        pbf_d3d11_buffer_id did{1, 1};
        CHECK_CODE(pbf_world_register_d3d11_buffer(w, &dd, &did), PBF_ERROR_INVALID_ARGUMENT);  // NULL buffer
        CHECK((did.index == 0 && did.generation == 0));
        CHECK_CODE(pbf_world_unregister_d3d11_buffer(w, pbf_d3d11_buffer_id{0, 7}),
                   (have & PBF_INTEROP_SUPPORT_D3D11) ? PBF_ERROR_INVALID_HANDLE : PBF_ERROR_BACKEND_UNAVAILABLE);
#if !defined(_WIN32)
        dd.buffer = &dd;
        CHECK_CODE(pbf_world_register_d3d11_buffer(w, &dd, &did), PBF_ERROR_BACKEND_UNAVAILABLE);  // Windows only
#endif

        pbf_external_buffer_id eid;
        pbf_external_buffer_desc e = pbf_external_buffer_desc_default();
        CHECK_CODE(pbf_world_import_external_buffer(w, &e, &eid), PBF_ERROR_INVALID_ARGUMENT);  // no type
        e.type = PBF_EXTERNAL_MEMORY_OPAQUE_FD;
        e.size_bytes = 4096;
        e.capacity = 16;
        CHECK_CODE(pbf_world_import_external_buffer(w, &e, &eid), PBF_ERROR_INVALID_ARGUMENT);  // fd -1
        e.fd = 0;
        e.capacity = 4096 / 16 + 1;
        CHECK_CODE(pbf_world_import_external_buffer(w, &e, &eid), PBF_ERROR_INVALID_ARGUMENT);  // past the end
        e.capacity = 16;
        e.write_draw_args = 1;
        e.draw_args_offset_bytes = 128;
        CHECK_CODE(pbf_world_import_external_buffer(w, &e, &eid), PBF_ERROR_INVALID_ARGUMENT);  // overlaps
        e.draw_args_offset_bytes = 4096 - 8;
        CHECK_CODE(pbf_world_import_external_buffer(w, &e, &eid), PBF_ERROR_INVALID_ARGUMENT);  // past the end
        e.type = PBF_EXTERNAL_MEMORY_D3D12_RESOURCE;
        e.write_draw_args = 0;
        CHECK_CODE(pbf_world_import_external_buffer(w, &e, &eid), PBF_ERROR_INVALID_ARGUMENT);  // no win32 handle
        e.win32_handle = reinterpret_cast<void*>(0x10);
#if defined(_WIN32)
        (void)e;
#else
        CHECK_CODE(pbf_world_import_external_buffer(w, &e, &eid), PBF_ERROR_BACKEND_UNAVAILABLE);  // Windows only
#endif
        pbf_semaphore_id sid;
        pbf_semaphore_desc s = pbf_semaphore_desc_default();
        CHECK_CODE(pbf_world_import_semaphore(w, &s, &sid), PBF_ERROR_INVALID_ARGUMENT);
        s.type = PBF_SEMAPHORE_VULKAN_TIMELINE_FD;
        CHECK_CODE(pbf_world_import_semaphore(w, &s, &sid), PBF_ERROR_INVALID_ARGUMENT);  // fd -1
        CHECK_CODE(pbf_world_release_semaphore(w, forged_semaphore()), PBF_ERROR_INVALID_HANDLE);
        CHECK_CODE(pbf_world_release_external_buffer(w, pbf_external_buffer_id{0, 0}), PBF_ERROR_INVALID_HANDLE);
        CHECK_CODE(pbf_world_copy_to_external_buffer(w, pbf_external_buffer_id{2, 99}, nullptr),
                   PBF_ERROR_INVALID_HANDLE);

#if defined(__unix__)
        // A failed import leaves the fd with the caller (here: /dev/null is no GPU memory).
        const int fd = open("/dev/null", O_RDONLY);
        REQUIRE(fd >= 0);
        e = pbf_external_buffer_desc_default();
        e.type = PBF_EXTERNAL_MEMORY_OPAQUE_FD;
        e.fd = fd;
        e.size_bytes = 4096;
        e.capacity = 16;
        const pbf_result r = pbf_world_import_external_buffer(w, &e, &eid);
        INFO(pbf_last_error_message());
        CHECK(r == PBF_ERROR_BACKEND);
        CHECK(fcntl(fd, F_GETFD) != -1);  // still open: still the caller's
        close(fd);
        s.fd = open("/dev/null", O_RDONLY);
        CHECK(pbf_world_import_semaphore(w, &s, &sid) == PBF_ERROR_BACKEND);
        CHECK(fcntl(s.fd, F_GETFD) != -1);
        close(s.fd);
#endif

        int32_t event_id = 0;
        REQUIRE_PBF(pbf_world_get_render_event_id(w, &event_id));
        CHECK(event_id > 0);
        pbf_render_event_fn fn = pbf_get_render_event_func();
        REQUIRE(fn != nullptr);
        fn(event_id);  // nothing queued: harmless
        fn(PBF_RENDER_EVENT_ALL_WORLDS);

        const pbf_interop_info info = interop_info(w);
        CHECK(info.cuda_device == 0);
        bool uuid_set = false;
        for (uint8_t byte : info.device_uuid) uuid_set = uuid_set || byte != 0;
        CHECK(uuid_set);
        CHECK(info.last_render_event_result == PBF_OK);
        REQUIRE_PBF(pbf_world_destroy(w));
        void* p = nullptr;
        CHECK_CODE(pbf_world_get_cuda_stream(w, &p), PBF_ERROR_INVALID_HANDLE);
        CHECK_CODE(pbf_world_record_cuda_event(w, &p), PBF_ERROR_INVALID_HANDLE);
        CHECK_CODE(pbf_world_get_render_event_id(w, &event_id), PBF_ERROR_INVALID_HANDLE);
        pbf_interop_info stale;
        std::memset(&stale, 0, sizeof stale);
        stale.struct_size = sizeof stale;
        CHECK_CODE(pbf_world_get_interop_info(w, &stale), PBF_ERROR_INVALID_HANDLE);
    }
}

TEST_CASE("interop: device pointers, the world's stream, events and a caller's stream", "[gpu][interop]") {
#if !PBF_TEST_HAVE_CUDART
    WARN("not built: the test needs the CUDA runtime (a CUDA build)");
#else
    pbf_world_id w = small_world(PBF_BACKEND_CUDA);
    REQUIRE_PBF(pbf_world_step(w, kDt));
    REQUIRE_PBF(pbf_world_step(w, kDt));

    // Mapping without waiting, an event, reads on our own stream: no transfer by the library.
    const uint64_t before = transfers();
    pbf_device_buffers b;
    std::memset(&b, 0, sizeof b);
    b.struct_size = sizeof b;
    REQUIRE_PBF(pbf_world_map_device_buffers(w, PBF_MAP_NO_WAIT, &b));
    void* event = nullptr;
    REQUIRE_PBF(pbf_world_record_cuda_event(w, &event));
    CHECK(transfers() == before);
    CHECK(b.memory == PBF_MEMORY_CUDA_DEVICE);
    CHECK(b.count == PBF_COUNT_ON_DEVICE);
    CHECK(b.cuda_device == 0);
    CHECK(b.vec4_stride_bytes == 16u);
    CHECK(b.id_stride_bytes == 4u);
    CHECK(static_cast<char*>(b.density_ratio) == static_cast<char*>(b.positions) + 12);
    void* world_stream = nullptr;
    REQUIRE_PBF(pbf_world_get_cuda_stream(w, &world_stream));
    CHECK(b.cuda_stream == world_stream);

    cudaStream_t mine = nullptr;
    REQUIRE(cudaStreamCreateWithFlags(&mine, cudaStreamNonBlocking) == cudaSuccess);
    REQUIRE(cudaStreamWaitEvent(mine, static_cast<cudaEvent_t>(event), 0) == cudaSuccess);
    const uint32_t cap = b.capacity;
    std::vector<float> pos(size_t(cap) * 4), vel(size_t(cap) * 4);
    std::vector<uint32_t> ids(cap);
    uint32_t count = 0;
    REQUIRE(cudaMemcpyAsync(&count, b.count_device, 4, cudaMemcpyDeviceToHost, mine) == cudaSuccess);
    REQUIRE(cudaMemcpyAsync(pos.data(), b.positions, size_t(cap) * 16, cudaMemcpyDeviceToHost, mine) == cudaSuccess);
    REQUIRE(cudaMemcpyAsync(vel.data(), b.velocities, size_t(cap) * 16, cudaMemcpyDeviceToHost, mine) == cudaSuccess);
    REQUIRE(cudaMemcpyAsync(ids.data(), b.ids, size_t(cap) * 4, cudaMemcpyDeviceToHost, mine) == cudaSuccess);
    cudaEvent_t done = nullptr;
    REQUIRE(cudaEventCreateWithFlags(&done, cudaEventDisableTiming) == cudaSuccess);
    REQUIRE(cudaEventRecord(done, mine) == cudaSuccess);
    // The next step must not overwrite the buffers before our reads: the world waits for them.
    REQUIRE_PBF(pbf_world_wait_cuda_event(w, done));
    REQUIRE(cudaStreamSynchronize(mine) == cudaSuccess);
    REQUIRE_PBF(pbf_world_unmap(w));
    const Particles p = read(w);  // same state: no step since the mapping
    REQUIRE(count == p.count);
    REQUIRE(count > 1000u);
    CHECK(std::memcmp(pos.data(), p.pos.data(), size_t(count) * 16) == 0);
    CHECK(std::memcmp(vel.data(), p.vel.data(), size_t(count) * 16) == 0);
    CHECK(std::memcmp(ids.data(), p.ids.data(), size_t(count) * 4) == 0);

    // Waiting mapping: count filled (one transfer: the count).
    std::memset(&b, 0, sizeof b);
    b.struct_size = sizeof b;
    REQUIRE_PBF(pbf_world_map_device_buffers(w, 0, &b));
    CHECK(b.count == count);
    REQUIRE_PBF(pbf_world_unmap(w));

    // Hand the world our stream, step on it, take it back.
    REQUIRE_PBF(pbf_world_set_cuda_stream(w, mine));
    void* s = nullptr;
    REQUIRE_PBF(pbf_world_get_cuda_stream(w, &s));
    CHECK(s == static_cast<void*>(mine));
    REQUIRE_PBF(pbf_world_step(w, kDt));
    REQUIRE(cudaStreamSynchronize(mine) == cudaSuccess);  // the step ran there
    const Particles q = read(w);
    CHECK(q.count == p.count);
    CHECK(all_finite(q));
    REQUIRE_PBF(pbf_world_set_cuda_stream(w, nullptr));
    REQUIRE_PBF(pbf_world_get_cuda_stream(w, &s));
    CHECK(s == world_stream);
    REQUIRE_PBF(pbf_world_step(w, kDt));
    CHECK(all_finite(read(w)));
    REQUIRE_PBF(pbf_world_destroy(w));
    cudaEventDestroy(done);
    cudaStreamDestroy(mine);
#endif
}

#if PBF_TEST_HAVE_EGL_GL
namespace {
struct Gl {
    pbf_egl egl;
    bool ok = false;
    std::string error;
    Gl() {
        char err[512] = "";
        ok = pbf_egl_init(&egl, 0, err, sizeof err) != 0;
        error = err;
    }
    ~Gl() {
        if (ok) pbf_egl_shutdown(&egl);
    }
    GLuint buffer(size_t bytes) {
        GLuint b = 0;
        egl.gl.GenBuffers(1, &b);
        egl.gl.BindBuffer(GL_ARRAY_BUFFER, b);
        std::vector<unsigned char> zeros(bytes, 0);
        egl.gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(bytes), zeros.data(), GL_DYNAMIC_DRAW);
        return b;
    }
    template <class T>
    std::vector<T> read(GLuint b, size_t count, size_t offset_bytes = 0) {
        std::vector<T> out(count);
        egl.gl.Finish();
        egl.gl.BindBuffer(GL_ARRAY_BUFFER, b);
        egl.gl.GetBufferSubData(GL_ARRAY_BUFFER, GLintptr(offset_bytes), GLsizeiptr(count * sizeof(T)), out.data());
        return out;
    }
};

pbf_gl_buffer_id register_gl(pbf_world_id w, GLuint buffer, pbf_buffer source, pbf_copy_mode mode, uint32_t capacity,
                             GLuint args = 0, uint32_t vertices = 0, uint64_t offset = 0) {
    pbf_gl_buffer_desc d = pbf_gl_buffer_desc_default();
    d.buffer = buffer;
    d.source = source;
    d.mode = mode;
    d.capacity = capacity;
    d.offset_bytes = offset;
    d.draw_args_buffer = args;
    d.draw_args_vertices = vertices;
    pbf_gl_buffer_id id;
    REQUIRE_PBF(pbf_world_register_gl_buffer(w, &d, &id));
    return id;
}

// Whether gl works (REQUIRE), or false where EGL is missing and PBF_TEST_ALLOW_NO_EGL accepts that.
bool gl_usable(const Gl& gl) {
    if (!gl.ok && env_set("PBF_TEST_ALLOW_NO_EGL")) {
        WARN("EGL unavailable, accepted by PBF_TEST_ALLOW_NO_EGL: " << gl.error);
        return false;
    }
    INFO("EGL: " << gl.error);
    REQUIRE(gl.ok);
    return true;
}

// Runs body(gl) where this libpbf has CUDA-GL interop and EGL works; says why not otherwise.
template <class Body>
void with_gl(Body body) {
    if (!has_interop(PBF_INTEROP_SUPPORT_OPENGL, "this libpbf has no CUDA-GL interop (built without CUDA)")) return;
    Gl gl;
    if (gl_usable(gl)) body(gl);
}

// A CUDA world without the data of `source` (no render data, no diffuse particles) refuses a GL
// buffer of it before touching the buffer.
[[maybe_unused]] void check_gl_refused(GLuint buffer, pbf_buffer source, uint32_t capacity) {
    pbf_world_desc od = tank(PBF_BACKEND_CUDA, 0.0125f, 0.8f, 0.5f, 0.2f, 8192);
    pbf_world_id off;
    REQUIRE_PBF(pbf_world_create(&od, &off));
    pbf_gl_buffer_desc g = pbf_gl_buffer_desc_default();
    g.buffer = buffer;
    g.source = source;
    g.capacity = capacity;
    pbf_gl_buffer_id gid;
    CHECK_CODE(pbf_world_register_gl_buffer(off, &g, &gid), PBF_ERROR_INVALID_STATE);
    REQUIRE_PBF(pbf_world_destroy(off));
}
}  // namespace
#endif

TEST_CASE("interop GL: buffers equal copy-out after a step; the render path adds no transfers", "[gpu][interop][gl]") {
#if !PBF_TEST_HAVE_EGL_GL
    WARN("not built: EGL or the OpenGL headers were not found when configuring");
#else
    if (!has_interop(PBF_INTEROP_SUPPORT_OPENGL, "this libpbf has no CUDA-GL interop (built without CUDA)")) return;
    Gl gl;
    if (!gl_usable(gl)) return;
    pbf_world_id w = small_world(PBF_BACKEND_CUDA);
    pbf_world_info winfo;
    std::memset(&winfo, 0, sizeof winfo);
    winfo.struct_size = sizeof winfo;
    REQUIRE_PBF(pbf_world_get_info(w, &winfo));
    const uint32_t cap = winfo.max_particles;

    // On-step buffers: positions with draw args {n, 1, 0, 0}, velocities at an offset, ids with
    // instanced draw args {4, n, 0, 0}.
    const GLuint pos = gl.buffer(size_t(cap) * 16), vel = gl.buffer(size_t(cap) * 16 + 64),
                 ids = gl.buffer(size_t(cap) * 4);
    const GLuint pos_args = gl.buffer(16), ids_args = gl.buffer(32);
    const pbf_gl_buffer_id pos_id = register_gl(w, pos, PBF_BUFFER_POSITIONS, PBF_COPY_ON_STEP, cap, pos_args);
    const pbf_gl_buffer_id vel_id = register_gl(w, vel, PBF_BUFFER_VELOCITIES, PBF_COPY_ON_STEP, cap, 0, 0, 64);
    pbf_gl_buffer_desc idd = pbf_gl_buffer_desc_default();
    idd.buffer = ids;
    idd.source = PBF_BUFFER_IDS;
    idd.capacity = cap;
    idd.draw_args_buffer = ids_args;
    idd.draw_args_offset_bytes = 16;
    idd.draw_args_vertices = 4;
    pbf_gl_buffer_id ids_id;
    REQUIRE_PBF(pbf_world_register_gl_buffer(w, &idd, &ids_id));
    // A manual one (copied only when asked).
    const GLuint manual = gl.buffer(size_t(cap) * 16);
    const pbf_gl_buffer_id manual_id = register_gl(w, manual, PBF_BUFFER_POSITIONS, PBF_COPY_MANUAL, cap);
    CHECK(interop_info(w).gl_buffers == 4u);

    const uint64_t before = transfers();
    for (int s = 0; s < 3; ++s) REQUIRE_PBF(pbf_world_step(w, kDt));
    REQUIRE_PBF(pbf_world_copy_to_gl_buffer(w, manual_id));
    const uint64_t after = transfers();
    INFO("library host<->device transfers during 3 steps with 3 on-step GL buffers and a manual copy: "
         << (after - before));
    CHECK(after == before);

    const Particles p = read(w);
    REQUIRE(p.count > 1000u);
    const auto gpos = gl.read<float>(pos, size_t(p.count) * 4);
    const auto gvel = gl.read<float>(vel, size_t(p.count) * 4, 64);
    const auto gids = gl.read<uint32_t>(ids, p.count);
    const auto gman = gl.read<float>(manual, size_t(p.count) * 4);
    const auto pargs = gl.read<uint32_t>(pos_args, 4);
    const auto iargs = gl.read<uint32_t>(ids_args, 4, 16);
    CHECK(gl.egl.gl.GetError() == GLenum(GL_NO_ERROR));
    CHECK(std::memcmp(gpos.data(), p.pos.data(), size_t(p.count) * 16) == 0);
    CHECK(std::memcmp(gvel.data(), p.vel.data(), size_t(p.count) * 16) == 0);
    CHECK(std::memcmp(gids.data(), p.ids.data(), size_t(p.count) * 4) == 0);
    CHECK(std::memcmp(gman.data(), p.pos.data(), size_t(p.count) * 16) == 0);
    CHECK(pargs == std::vector<uint32_t>{p.count, 1u, 0u, 0u});
    CHECK(iargs == std::vector<uint32_t>{4u, p.count, 0u, 0u});
    const pbf_interop_info info = interop_info(w);
    CHECK(info.copies == 3u * 3u + 1u);
    CHECK(info.last_copy_gpu_ms > 0.0f);
    INFO("last copy batch: " << info.last_copy_gpu_ms << " ms GPU, " << info.last_copy_host_ms << " ms host");

    SECTION("the render event registers, copies and unregisters on the calling (render) thread") {
        const GLuint rbuf = gl.buffer(size_t(cap) * 16), rargs = gl.buffer(16);
        const pbf_gl_buffer_id rid = register_gl(w, rbuf, PBF_BUFFER_POSITIONS, PBF_COPY_ON_RENDER_EVENT, cap, rargs);
        CHECK(interop_info(w).pending_render_work == 1u);
        CHECK_CODE(pbf_world_copy_to_gl_buffer(w, rid), PBF_ERROR_INVALID_STATE);
        int32_t event_id = 0;
        REQUIRE_PBF(pbf_world_get_render_event_id(w, &event_id));
        const uint64_t t0 = transfers();
        REQUIRE_PBF(pbf_world_step(w, kDt));
        pbf_get_render_event_func()(event_id);
        CHECK(transfers() == t0);
        pbf_interop_info ri = interop_info(w);
        INFO("render event: " << ri.last_render_event_message);
        CHECK(ri.last_render_event_result == PBF_OK);
        CHECK(ri.pending_render_work == 0u);
        CHECK(ri.render_events == 1u);
        const Particles r = read(w);
        CHECK(std::memcmp(gl.read<float>(rbuf, size_t(r.count) * 4).data(), r.pos.data(), size_t(r.count) * 16) == 0);
        CHECK(gl.read<uint32_t>(rargs, 4) == std::vector<uint32_t>{r.count, 1u, 0u, 0u});
        // Another step: the render-event buffer waits for the next event; the on-step one does not.
        REQUIRE_PBF(pbf_world_step(w, kDt));
        const Particles r2 = read(w);
        CHECK(std::memcmp(gl.read<float>(pos, size_t(r2.count) * 4).data(), r2.pos.data(), size_t(r2.count) * 16) == 0);
        CHECK(std::memcmp(gl.read<float>(rbuf, size_t(r.count) * 4).data(), r.pos.data(), size_t(r.count) * 16) == 0);
        pbf_get_render_event_func()(PBF_RENDER_EVENT_ALL_WORLDS);
        CHECK(std::memcmp(gl.read<float>(rbuf, size_t(r2.count) * 4).data(), r2.pos.data(), size_t(r2.count) * 16) ==
              0);
        // Unregistering queues it for the render thread; the handle is refused at once.
        REQUIRE_PBF(pbf_world_unregister_gl_buffer(w, rid));
        CHECK_CODE(pbf_world_unregister_gl_buffer(w, rid), PBF_ERROR_INVALID_HANDLE);
        CHECK(interop_info(w).pending_render_work == 1u);
        pbf_get_render_event_func()(event_id);
        ri = interop_info(w);
        CHECK(ri.pending_render_work == 0u);
        CHECK(ri.last_render_event_result == PBF_OK);
        gl.egl.gl.DeleteBuffers(1, &rbuf);
        gl.egl.gl.DeleteBuffers(1, &rargs);
    }

    SECTION("registration checks the GL buffer's size and name") {
        const GLuint small = gl.buffer(64);
        pbf_gl_buffer_desc d = pbf_gl_buffer_desc_default();
        d.buffer = small;
        d.capacity = 5;  // 80 bytes > 64
        pbf_gl_buffer_id id;
        CHECK_CODE(pbf_world_register_gl_buffer(w, &d, &id), PBF_ERROR_INVALID_ARGUMENT);
        d.capacity = 4;
        d.draw_args_buffer = small;  // the same buffer holds the args: they must not overlap
        CHECK_CODE(pbf_world_register_gl_buffer(w, &d, &id), PBF_ERROR_INVALID_ARGUMENT);
        d.capacity = 3;
        d.draw_args_offset_bytes = 48;
        REQUIRE_PBF(pbf_world_register_gl_buffer(w, &d, &id));
        REQUIRE_PBF(pbf_world_step(w, kDt));
        const Particles r = read(w);
        CHECK(std::memcmp(gl.read<float>(small, 12).data(), r.pos.data(), 48) == 0);
        CHECK(gl.read<uint32_t>(small, 4, 48) == std::vector<uint32_t>{3u, 1u, 0u, 0u});  // min(count, capacity)
        REQUIRE_PBF(pbf_world_unregister_gl_buffer(w, id));
        d = pbf_gl_buffer_desc_default();
        d.buffer = 987654u;  // no such GL buffer
        d.capacity = 4;
        CHECK_CODE(pbf_world_register_gl_buffer(w, &d, &id), PBF_ERROR_BACKEND);
        CHECK(interop_info(w).gl_buffers == 4u);
        gl.egl.gl.DeleteBuffers(1, &small);
    }

    REQUIRE_PBF(pbf_world_unregister_gl_buffer(w, pos_id));
    REQUIRE_PBF(pbf_world_unregister_gl_buffer(w, vel_id));
    REQUIRE_PBF(pbf_world_unregister_gl_buffer(w, manual_id));
    CHECK_CODE(pbf_world_copy_to_gl_buffer(w, pos_id), PBF_ERROR_INVALID_HANDLE);
    // ids stays registered: destroying the world unregisters it.
    REQUIRE_PBF(pbf_world_step(w, kDt));
    REQUIRE_PBF(pbf_world_destroy(w));
    (void)ids_id;
    const GLuint all[] = {pos, vel, ids, pos_args, ids_args, manual};
    gl.egl.gl.DeleteBuffers(6, all);
#endif
}

TEST_CASE("interop Vulkan: external buffer equals copy-out; binary and timeline semaphores both ways",
          "[gpu][interop][vulkan]") {
#if !PBF_TEST_HAVE_VULKAN
    WARN("not built: Vulkan was not found when configuring");
#else
    if (!has_interop(PBF_INTEROP_SUPPORT_EXTERNAL_FD, "this libpbf cannot import opaque fds")) return;
    for (bool auto_copy : {false, true}) {
        INFO((auto_copy ? "PBF_COPY_ON_STEP + pbf_world_set_external_sync" : "pbf_world_copy_to_external_buffer"));
        pbf_world_id w = small_world(PBF_BACKEND_CUDA);
        const pbf_vk::RoundTrip r = pbf_vk::round_trip(w, 6, auto_copy);
        if (!r.ok && r.particles == 0 && env_set("PBF_TEST_ALLOW_NO_VULKAN")) {
            WARN("Vulkan unavailable, accepted by PBF_TEST_ALLOW_NO_VULKAN: " << r.error);
            REQUIRE_PBF(pbf_world_destroy(w));
            return;
        }
        INFO("Vulkan device: " << r.device_name << "; " << r.error);
        CHECK(r.ok);
        CHECK(r.particles > 1000u);
        CHECK(r.mismatching_floats == 0u);
        CHECK(r.draw_args_mismatches == 0u);
        CHECK(r.transfers_in_copies == 0u);
        const pbf_interop_info info = interop_info(w);
        CHECK(info.external_buffers == 0u);  // released by the round trip
        CHECK(info.semaphores == 0u);
        CHECK(info.copies == 6u);
        REQUIRE_PBF(pbf_world_destroy(w));
    }
#endif
}

TEST_CASE("interop: render data through device pointers and GL buffers equals copy-out", "[gpu][interop][render]") {
#if !PBF_TEST_HAVE_CUDART
    WARN("not built: the test needs the CUDA runtime (a CUDA build)");
#else
    pbf_world_desc d = tank(PBF_BACKEND_CUDA, 0.0125f, 0.8f, 0.5f, 0.2f, 8192);
    d.solver.substeps = 2;
    d.render.flags = PBF_RENDER_SMOOTHED_POSITIONS | PBF_RENDER_ANISOTROPY;
    pbf_world_id w;
    REQUIRE_PBF(pbf_world_create(&d, &w));
    fill(w, 0, 0, 0, 0.2f, 0.4f, 0.2f);
    for (int s = 0; s < 2; ++s) REQUIRE_PBF(pbf_world_step(w, kDt));

    // Device pointers, read on the world's stream after a no-wait mapping.
    const uint64_t before = transfers();
    pbf_device_buffers b;
    std::memset(&b, 0, sizeof b);
    b.struct_size = sizeof b;
    REQUIRE_PBF(pbf_world_map_device_buffers(w, PBF_MAP_NO_WAIT, &b));
    CHECK(transfers() == before);
    REQUIRE(b.smoothed_positions != nullptr);
    REQUIRE(b.anisotropy != nullptr);
    CHECK(b.anisotropy_stride_bytes == 48u);
    CHECK(b.render_flags == d.render.flags);
    const uint32_t cap = b.capacity;
    std::vector<float> smoothed(size_t(cap) * 4), aniso(size_t(cap) * 12);
    cudaStream_t stream = static_cast<cudaStream_t>(b.cuda_stream);
    REQUIRE(cudaMemcpyAsync(smoothed.data(), b.smoothed_positions, smoothed.size() * 4, cudaMemcpyDeviceToHost,
                            stream) == cudaSuccess);
    REQUIRE(cudaMemcpyAsync(aniso.data(), b.anisotropy, aniso.size() * 4, cudaMemcpyDeviceToHost, stream) ==
            cudaSuccess);
    REQUIRE(cudaStreamSynchronize(stream) == cudaSuccess);
    REQUIRE_PBF(pbf_world_unmap(w));
    const RenderData r = read_render(w);
    REQUIRE(r.count > 1000u);
    CHECK(std::memcmp(smoothed.data(), r.smoothed.data(), size_t(r.count) * 16) == 0);
    CHECK(std::memcmp(aniso.data(), r.aniso.data(), size_t(r.count) * 48) == 0);

#if PBF_TEST_HAVE_EGL_GL
    with_gl([&](Gl& gl) {
        // On-step copies of both render buffers, the anisotropy at a 16-byte offset.
        const GLuint gs = gl.buffer(size_t(cap) * 16), ga = gl.buffer(size_t(cap) * 48 + 16), args = gl.buffer(16);
        register_gl(w, gs, PBF_BUFFER_SMOOTHED_POSITIONS, PBF_COPY_ON_STEP, cap);
        register_gl(w, ga, PBF_BUFFER_ANISOTROPY, PBF_COPY_ON_STEP, cap, args, 0, 16);
        const uint64_t t0 = transfers();
        for (int s = 0; s < 2; ++s) REQUIRE_PBF(pbf_world_step(w, kDt));
        CHECK(transfers() == t0);
        const RenderData q = read_render(w);
        const auto gsm = gl.read<float>(gs, size_t(q.count) * 4);
        const auto gan = gl.read<float>(ga, size_t(q.count) * 12, 16);
        CHECK(std::memcmp(gsm.data(), q.smoothed.data(), size_t(q.count) * 16) == 0);
        CHECK(std::memcmp(gan.data(), q.aniso.data(), size_t(q.count) * 48) == 0);
        CHECK(gl.read<uint32_t>(args, 4) == std::vector<uint32_t>{q.count, 1u, 0u, 0u});
        check_gl_refused(ga, PBF_BUFFER_ANISOTROPY, cap);
    });
#else
    WARN("GL part not built: EGL or the OpenGL headers were not found when configuring");
#endif
    REQUIRE_PBF(pbf_world_destroy(w));
#endif
}

TEST_CASE("interop: diffuse particles through device pointers and GL buffers equal copy-out",
          "[gpu][interop][diffuse]") {
#if !PBF_TEST_HAVE_CUDART
    WARN("not built: the test needs the CUDA runtime (a CUDA build)");
#else
    pbf_world_id w = diffuse_dam(PBF_BACKEND_CUDA, 20000);
    for (int s = 0; s < 40; ++s) REQUIRE_PBF(pbf_world_step(w, kDt));

    // Device pointers, read on the world's stream after a no-wait mapping; the count on the device.
    const pbf_device_buffers b = map_buffers(w, PBF_MAP_NO_WAIT);
    CHECK(b.diffuse_count == PBF_COUNT_ON_DEVICE);
    CHECK(b.diffuse_capacity == 20000u);
    REQUIRE(b.diffuse_positions != nullptr);
    REQUIRE(b.diffuse_velocities != nullptr);
    const uint32_t cap = b.diffuse_capacity;
    std::vector<float> pos(size_t(cap) * 4), vel(size_t(cap) * 4);
    uint32_t count = 0;
    cudaStream_t stream = static_cast<cudaStream_t>(b.cuda_stream);
    REQUIRE(cudaMemcpyAsync(pos.data(), b.diffuse_positions, pos.size() * 4, cudaMemcpyDeviceToHost, stream) ==
            cudaSuccess);
    REQUIRE(cudaMemcpyAsync(vel.data(), b.diffuse_velocities, vel.size() * 4, cudaMemcpyDeviceToHost, stream) ==
            cudaSuccess);
    REQUIRE(cudaMemcpyAsync(&count, b.diffuse_count_device, 4, cudaMemcpyDeviceToHost, stream) == cudaSuccess);
    REQUIRE(cudaStreamSynchronize(stream) == cudaSuccess);
    REQUIRE_PBF(pbf_world_unmap(w));
    const Diffuse r = read_diffuse(w);
    INFO(r.count << " diffuse particles after 40 steps");
    REQUIRE(r.count > 0u);
    CHECK(count == r.count);
    CHECK(std::memcmp(pos.data(), r.pos.data(), size_t(r.count) * 16) == 0);
    CHECK(std::memcmp(vel.data(), r.vel.data(), size_t(r.count) * 16) == 0);

#if PBF_TEST_HAVE_EGL_GL
    with_gl([&](Gl& gl) {
        // On-step copies of both diffuse buffers; the draw arguments count diffuse particles.
        const GLuint gp = gl.buffer(size_t(cap) * 16), gv = gl.buffer(size_t(cap) * 16), args = gl.buffer(16);
        register_gl(w, gp, PBF_BUFFER_DIFFUSE_POSITIONS, PBF_COPY_ON_STEP, cap, args);
        register_gl(w, gv, PBF_BUFFER_DIFFUSE_VELOCITIES, PBF_COPY_ON_STEP, cap);
        const uint64_t t0 = transfers();
        for (int s = 0; s < 2; ++s) REQUIRE_PBF(pbf_world_step(w, kDt));
        CHECK(transfers() == t0);
        const Diffuse q = read_diffuse(w);
        CHECK(std::memcmp(gl.read<float>(gp, size_t(q.count) * 4).data(), q.pos.data(), size_t(q.count) * 16) == 0);
        CHECK(std::memcmp(gl.read<float>(gv, size_t(q.count) * 4).data(), q.vel.data(), size_t(q.count) * 16) == 0);
        CHECK(gl.read<uint32_t>(args, 4) == std::vector<uint32_t>{q.count, 1u, 0u, 0u});
        check_gl_refused(gp, PBF_BUFFER_DIFFUSE_POSITIONS, cap);
    });
#else
    WARN("GL part not built: EGL or the OpenGL headers were not found when configuring");
#endif
    REQUIRE_PBF(pbf_world_destroy(w));
#endif
}
