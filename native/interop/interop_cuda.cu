// CUDA implementation of the interop layer (interop.h): GL buffer objects through CUDA-GL
// interop (built when the OpenGL headers were found: PBF_HAVE_GL_INTEROP), external memory and
// semaphores (opaque fds on Linux; win32 handles, D3D11 and D3D12 only in Windows builds).
//
// The copies never read the particle count back: a kernel reads it on the device, copies
// min(count, capacity) elements and optionally writes draw arguments, all on the world's stream.
#include <cuda_runtime.h>
#if PBF_HAVE_GL_INTEROP
#include <cuda_gl_interop.h>
#endif

#if !defined(_WIN32)
#include <unistd.h>
#endif

#include <algorithm>
#include <chrono>
#include <cstring>
#include <optional>
#include <string>
#include <vector>

#include "../world/slot_table.h"
#include "interop.h"

namespace pbf {

uint32_t interop_support() {
    uint32_t flags = PBF_INTEROP_SUPPORT_CUDA;
#if PBF_HAVE_GL_INTEROP
    flags |= PBF_INTEROP_SUPPORT_OPENGL;
#endif
#if defined(_WIN32)
    flags |= PBF_INTEROP_SUPPORT_EXTERNAL_WIN32;
#else
    flags |= PBF_INTEROP_SUPPORT_EXTERNAL_FD;
#endif
    return flags;
}

namespace {

constexpr int kCopyBlock = 256;
constexpr uint32_t kMaxCopyBlocks = 4096;

Status cuda_status(const std::string& what, cudaError_t e) {
    if (e == cudaSuccess) return Status{};
    (void)cudaGetLastError();  // clear a non-sticky error so the next call starts clean
    const pbf_result code = e == cudaErrorMemoryAllocation ? PBF_ERROR_OUT_OF_MEMORY : PBF_ERROR_BACKEND;
    return Status::error(code, what + ": CUDA error " + cudaGetErrorName(e) + " (" + cudaGetErrorString(e) + ")");
}

#if PBF_HAVE_GL_INTEROP
uint32_t element_bytes(pbf_buffer source) { return source == PBF_BUFFER_IDS ? 4u : 16u; }
#endif

// Copies min(*count, capacity) elements; block 0's thread 0 writes the draw arguments.
template <class T>
__global__ void copy_live_kernel(const T* __restrict__ src, T* __restrict__ dst, const uint32_t* __restrict__ count,
                                 uint32_t capacity, uint32_t* __restrict__ draw_args, uint32_t draw_vertices) {
    const uint32_t n = min(*count, capacity);
    for (uint32_t i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += gridDim.x * blockDim.x) dst[i] = src[i];
    if (draw_args && blockIdx.x == 0 && threadIdx.x == 0) {
        draw_args[0] = draw_vertices ? draw_vertices : n;
        draw_args[1] = draw_vertices ? n : 1u;
        draw_args[2] = 0u;
        draw_args[3] = 0u;
    }
}

// One copy: source buffer of the world into dst (+ draw arguments), on stream.
cudaError_t launch_copy(const LiveBuffers& live, pbf_buffer source, void* dst, uint32_t capacity, uint32_t* draw_args,
                        uint32_t draw_vertices, cudaStream_t stream) {
    const uint32_t blocks = std::max<uint32_t>(1, std::min<uint32_t>((capacity + kCopyBlock - 1) / kCopyBlock, kMaxCopyBlocks));
    if (source == PBF_BUFFER_IDS) {
        copy_live_kernel<uint32_t><<<blocks, kCopyBlock, 0, stream>>>(live.ids, static_cast<uint32_t*>(dst), live.count,
                                                                      capacity, draw_args, draw_vertices);
    } else {
        const void* src = source == PBF_BUFFER_VELOCITIES ? live.velocities : live.positions;
        copy_live_kernel<float4><<<blocks, kCopyBlock, 0, stream>>>(static_cast<const float4*>(src),
                                                                    static_cast<float4*>(dst), live.count, capacity,
                                                                    draw_args, draw_vertices);
    }
    return cudaGetLastError();
}

#if !defined(_WIN32)
// CUDA takes ownership of an fd only when an import succeeds, and a later step of ours may still
// fail: import a duplicate, and close the caller's fd once everything succeeded (the caller
// keeps it on any failure).
struct FdDup {
    int fd = -1;
    explicit FdDup(int original) : fd(dup(original)) {}
    ~FdDup() {
        if (fd >= 0) close(fd);
    }
    void consumed() { fd = -1; }  // CUDA owns it now
};
#endif

template <class Id, class H>
Id to_id(H h) {
    return Id{h.index, h.generation};
}

struct GlBuffer {
    pbf_gl_buffer_desc desc{};
#if PBF_HAVE_GL_INTEROP
    cudaGraphicsResource_t resource = nullptr;
    cudaGraphicsResource_t args_resource = nullptr;  // null; == resource when one GL buffer holds both
#endif
    bool registered = false;
    bool failed = false;  // a render-event registration failed: not retried
};

struct ExternalBuffer {
    pbf_external_buffer_desc desc{};
    cudaExternalMemory_t memory = nullptr;
    void* base = nullptr;  // the whole allocation, mapped
    std::optional<pbf_external_sync> next_sync;
};

struct Semaphore {
    pbf_semaphore_type type{};
    cudaExternalSemaphore_t handle = nullptr;
};

class CudaInterop final : public Interop {
public:
    explicit CudaInterop(World& world) : world_(world) {}
    ~CudaInterop() override;

    Status init();

    bool has_gl_buffer(pbf_gl_buffer_id id) override { return gl_.find(id.index, id.generation) != nullptr; }
    bool has_external_buffer(pbf_external_buffer_id id) override {
        return external_.find(id.index, id.generation) != nullptr;
    }
    bool has_semaphore(pbf_semaphore_id id) override { return semaphores_.find(id.index, id.generation) != nullptr; }
    pbf_copy_mode gl_buffer_mode(pbf_gl_buffer_id id) override { return gl_.find(id.index, id.generation)->desc.mode; }
    pbf_copy_mode external_buffer_mode(pbf_external_buffer_id id) override {
        return external_.find(id.index, id.generation)->desc.mode;
    }

    Status record_event(void** out_event) override;
    Status wait_event(void* event) override;

    Status register_gl_buffer(const pbf_gl_buffer_desc& desc, pbf_gl_buffer_id* out) override;
    Status unregister_gl_buffer(pbf_gl_buffer_id id) override;
    Status copy_to_gl_buffer(pbf_gl_buffer_id id) override;

    Status import_external_buffer(const pbf_external_buffer_desc& desc, pbf_external_buffer_id* out) override;
    Status release_external_buffer(pbf_external_buffer_id id) override;
    Status import_semaphore(const pbf_semaphore_desc& desc, pbf_semaphore_id* out) override;
    Status release_semaphore(pbf_semaphore_id id) override;
    Status copy_to_external_buffer(pbf_external_buffer_id id, const pbf_external_sync* sync) override;
    void set_external_sync(pbf_external_buffer_id id, const pbf_external_sync* sync) override;

    bool wants_render_events() override;
    Status render_event() override;
    void get_info(pbf_interop_info* out) override;
    Status after_step() override;

private:
    cudaStream_t stream() const { return static_cast<cudaStream_t>(world_.cuda_stream()); }
    Status activate() { return cuda_status("selecting the world's CUDA device", cudaSetDevice(device_)); }
    Status copy_gl(const std::vector<GlBuffer*>& buffers);
    Status copy_external(ExternalBuffer& b, const pbf_external_sync* sync);
    Status register_now(GlBuffer& b);
    Status unregister_now(GlBuffer& b);
    void release_external(ExternalBuffer& b);
    // Timing of a copy batch: events around it on the stream, host time around the call.
    void batch_begin();
    void batch_end();

    World& world_;
    int device_ = 0;
    cudaDeviceProp prop_{};
    cudaEvent_t user_event_ = nullptr;
    cudaEvent_t copy_start_ = nullptr, copy_stop_ = nullptr;
    bool copy_timed_ = false;
    std::chrono::steady_clock::time_point host_start_{};
    float last_copy_host_ms_ = 0.0f;
    uint64_t copies_ = 0, render_events_ = 0;
    Status last_render_event_;
    SlotTable<GlBuffer> gl_;
    std::vector<GlBuffer> gl_to_unregister_;  // render-event buffers released by the caller
    SlotTable<ExternalBuffer> external_;
    SlotTable<Semaphore> semaphores_;
};

CudaInterop::~CudaInterop() {
    // Best effort: the world is going away. Let queued copies finish before the resources go.
    cudaSetDevice(device_);
    if (cudaStream_t s = stream()) cudaStreamSynchronize(s);
#if PBF_HAVE_GL_INTEROP
    gl_.for_each([&](GlBuffer& b) { unregister_now(b); });
    for (GlBuffer& b : gl_to_unregister_) unregister_now(b);
#endif
    external_.for_each([&](ExternalBuffer& b) { release_external(b); });
    semaphores_.for_each([](Semaphore& s) {
        if (s.handle) cudaDestroyExternalSemaphore(s.handle);
    });
    if (user_event_) cudaEventDestroy(user_event_);
    if (copy_start_) cudaEventDestroy(copy_start_);
    if (copy_stop_) cudaEventDestroy(copy_stop_);
    (void)cudaGetLastError();
}

Status CudaInterop::init() {
    device_ = world_.live_buffers().cuda_device;
    Status st = activate();
    if (!st.ok()) return st;
    st = cuda_status("reading the device's properties", cudaGetDeviceProperties(&prop_, device_));
    if (!st.ok()) return st;
    st = cuda_status("creating the copy timer", cudaEventCreate(&copy_start_));
    if (st.ok()) st = cuda_status("creating the copy timer", cudaEventCreate(&copy_stop_));
    return st;
}

Status CudaInterop::record_event(void** out_event) {
    Status st = activate();
    if (!st.ok()) return st;
    if (!user_event_) {
        st = cuda_status("creating the world's event", cudaEventCreateWithFlags(&user_event_, cudaEventDisableTiming));
        if (!st.ok()) return st;
    }
    st = cuda_status("recording the world's event", cudaEventRecord(user_event_, stream()));
    if (st.ok()) *out_event = user_event_;
    return st;
}

Status CudaInterop::wait_event(void* event) {
    Status st = activate();
    if (!st.ok()) return st;
    return cuda_status("making the world's stream wait for the event",
                       cudaStreamWaitEvent(stream(), static_cast<cudaEvent_t>(event), 0));
}

void CudaInterop::batch_begin() {
    host_start_ = std::chrono::steady_clock::now();
    cudaEventRecord(copy_start_, stream());
}

void CudaInterop::batch_end() {
    copy_timed_ = cudaEventRecord(copy_stop_, stream()) == cudaSuccess;
    last_copy_host_ms_ =
        std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - host_start_).count();
}

// ---- OpenGL ------------------------------------------------------------------------------------
#if PBF_HAVE_GL_INTEROP
Status CudaInterop::register_now(GlBuffer& b) {
    const pbf_gl_buffer_desc& d = b.desc;
    Status st = activate();
    if (!st.ok()) return st;
    const std::string name = "GL buffer " + std::to_string(d.buffer);
    st = cuda_status("registering " + name + " with CUDA (is a GL context of the world's GPU current?)",
                     cudaGraphicsGLRegisterBuffer(&b.resource, d.buffer, cudaGraphicsRegisterFlagsNone));
    if (!st.ok()) {
        b.resource = nullptr;
        return st;
    }
    if (d.draw_args_buffer == d.buffer) {
        b.args_resource = b.resource;
    } else if (d.draw_args_buffer != 0) {
        st = cuda_status("registering draw-arguments GL buffer " + std::to_string(d.draw_args_buffer) + " with CUDA",
                         cudaGraphicsGLRegisterBuffer(&b.args_resource, d.draw_args_buffer, cudaGraphicsRegisterFlagsNone));
        if (!st.ok()) {
            b.args_resource = nullptr;
            cudaGraphicsUnregisterResource(b.resource);
            b.resource = nullptr;
            return st;
        }
    }
    // Check the sizes once, while registering (a copy never writes past a buffer's storage).
    cudaGraphicsResource_t resources[2] = {b.resource, b.args_resource};
    const int n = (b.args_resource && b.args_resource != b.resource) ? 2 : 1;
    st = cuda_status("mapping " + name + " to check its size", cudaGraphicsMapResources(n, resources, stream()));
    if (st.ok()) {
        void* p = nullptr;
        size_t size = 0, args_size = 0;
        st = cuda_status("reading the size of " + name, cudaGraphicsResourceGetMappedPointer(&p, &size, b.resource));
        if (st.ok() && b.args_resource)
            st = cuda_status("reading the size of the draw-arguments buffer",
                             cudaGraphicsResourceGetMappedPointer(&p, &args_size, b.args_resource));
        Status unmapped = cuda_status("unmapping " + name, cudaGraphicsUnmapResources(n, resources, stream()));
        if (st.ok()) st = unmapped;
        const uint64_t need = d.offset_bytes + uint64_t(d.capacity) * element_bytes(d.source);
        if (st.ok() && need > size)
            st = Status::error(PBF_ERROR_INVALID_ARGUMENT,
                               name + " holds " + std::to_string(size) + " bytes; offset_bytes + capacity * " +
                                   std::to_string(element_bytes(d.source)) + " needs " + std::to_string(need));
        if (st.ok() && b.args_resource && d.draw_args_offset_bytes + 16 > args_size)
            st = Status::error(PBF_ERROR_INVALID_ARGUMENT,
                               "draw-arguments GL buffer " + std::to_string(d.draw_args_buffer) + " holds " +
                                   std::to_string(args_size) + " bytes; draw_args_offset_bytes + 16 needs " +
                                   std::to_string(d.draw_args_offset_bytes + 16));
        if (st.ok() && d.draw_args_buffer == d.buffer) {
            const uint64_t a0 = d.draw_args_offset_bytes, a1 = a0 + 16;
            if (a0 < need && d.offset_bytes < a1)
                st = Status::error(PBF_ERROR_INVALID_ARGUMENT,
                                   "the draw arguments overlap the particles in GL buffer " + std::to_string(d.buffer));
        }
    }
    if (!st.ok()) {
        unregister_now(b);
        return st;
    }
    b.registered = true;
    return Status{};
}

Status CudaInterop::unregister_now(GlBuffer& b) {
    Status st;
    if (b.args_resource && b.args_resource != b.resource)
        st = cuda_status("unregistering the draw-arguments GL buffer", cudaGraphicsUnregisterResource(b.args_resource));
    if (b.resource) {
        Status s2 = cuda_status("unregistering GL buffer " + std::to_string(b.desc.buffer),
                                cudaGraphicsUnregisterResource(b.resource));
        if (st.ok()) st = s2;
    }
    b.resource = b.args_resource = nullptr;
    b.registered = false;
    return st;
}

Status CudaInterop::copy_gl(const std::vector<GlBuffer*>& buffers) {
    if (buffers.empty()) return Status{};
    Status st = activate();
    if (!st.ok()) return st;
    std::vector<cudaGraphicsResource_t> resources;
    for (GlBuffer* b : buffers)
        for (cudaGraphicsResource_t r : {b->resource, b->args_resource})
            if (r && std::find(resources.begin(), resources.end(), r) == resources.end()) resources.push_back(r);
    const cudaStream_t s = stream();
    const LiveBuffers live = world_.live_buffers();
    batch_begin();
    st = cuda_status("mapping the GL buffers", cudaGraphicsMapResources(int(resources.size()), resources.data(), s));
    if (!st.ok()) return st;
    for (GlBuffer* b : buffers) {
        void* dst = nullptr;
        void* args = nullptr;
        size_t size = 0;
        st = cuda_status("reading GL buffer " + std::to_string(b->desc.buffer) + "'s device address",
                         cudaGraphicsResourceGetMappedPointer(&dst, &size, b->resource));
        if (st.ok() && b->args_resource)
            st = cuda_status("reading the draw-arguments buffer's device address",
                             cudaGraphicsResourceGetMappedPointer(&args, &size, b->args_resource));
        if (!st.ok()) break;
        uint32_t* draw_args =
            args ? reinterpret_cast<uint32_t*>(static_cast<char*>(args) + b->desc.draw_args_offset_bytes) : nullptr;
        st = cuda_status("copying into GL buffer " + std::to_string(b->desc.buffer),
                         launch_copy(live, b->desc.source, static_cast<char*>(dst) + b->desc.offset_bytes,
                                     b->desc.capacity, draw_args, b->desc.draw_args_vertices, s));
        if (!st.ok()) break;
        ++copies_;
    }
    Status unmapped =
        cuda_status("unmapping the GL buffers", cudaGraphicsUnmapResources(int(resources.size()), resources.data(), s));
    batch_end();
    return st.ok() ? unmapped : st;
}
#else
Status CudaInterop::register_now(GlBuffer&) {
    return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this libpbf was built without the OpenGL headers");
}
Status CudaInterop::unregister_now(GlBuffer& b) {
    b.registered = false;
    return Status{};
}
Status CudaInterop::copy_gl(const std::vector<GlBuffer*>& buffers) {
    if (buffers.empty()) return Status{};
    return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this libpbf was built without the OpenGL headers");
}
#endif

Status CudaInterop::register_gl_buffer(const pbf_gl_buffer_desc& desc, pbf_gl_buffer_id* out) {
    GlBuffer b;
    b.desc = desc;
    if (desc.mode != PBF_COPY_ON_RENDER_EVENT) {
        Status st = register_now(b);
        if (!st.ok()) return st;
    }
    *out = to_id<pbf_gl_buffer_id>(gl_.insert(b));
    return Status{};
}

Status CudaInterop::unregister_gl_buffer(pbf_gl_buffer_id id) {
    GlBuffer b = *gl_.find(id.index, id.generation);
    gl_.erase(id.index, id.generation);
    if (b.desc.mode == PBF_COPY_ON_RENDER_EVENT) {
        if (b.registered) gl_to_unregister_.push_back(b);  // the render thread owns it
        return Status{};
    }
    Status st = activate();
    if (st.ok()) st = unregister_now(b);
    return st;
}

Status CudaInterop::copy_to_gl_buffer(pbf_gl_buffer_id id) {
    GlBuffer* b = gl_.find(id.index, id.generation);
    return copy_gl({b});
}

// ---- External memory and semaphores -----------------------------------------------------------
Status CudaInterop::import_external_buffer(const pbf_external_buffer_desc& d, pbf_external_buffer_id* out) {
    Status st = activate();
    if (!st.ok()) return st;
    cudaExternalMemoryHandleDesc h;
    std::memset(&h, 0, sizeof h);
    h.size = d.size_bytes;
    h.flags = d.dedicated ? cudaExternalMemoryDedicated : 0u;
    switch (d.type) {
#if defined(_WIN32)
        // Windows builds only; not compiled or tested on Linux.
        case PBF_EXTERNAL_MEMORY_OPAQUE_WIN32:
            h.type = cudaExternalMemoryHandleTypeOpaqueWin32;
            h.handle.win32.handle = d.win32_handle;
            break;
        case PBF_EXTERNAL_MEMORY_OPAQUE_WIN32_KMT:
            h.type = cudaExternalMemoryHandleTypeOpaqueWin32Kmt;
            h.handle.win32.handle = d.win32_handle;
            break;
        case PBF_EXTERNAL_MEMORY_D3D12_RESOURCE:
            h.type = cudaExternalMemoryHandleTypeD3D12Resource;
            h.handle.win32.handle = d.win32_handle;
            h.flags = cudaExternalMemoryDedicated;  // committed resources are dedicated
            break;
        case PBF_EXTERNAL_MEMORY_D3D11_RESOURCE:
            h.type = cudaExternalMemoryHandleTypeD3D11Resource;
            h.handle.win32.handle = d.win32_handle;
            h.flags = cudaExternalMemoryDedicated;
            break;
        case PBF_EXTERNAL_MEMORY_D3D11_RESOURCE_KMT:
            h.type = cudaExternalMemoryHandleTypeD3D11ResourceKmt;
            h.handle.win32.handle = d.win32_handle;
            h.flags = cudaExternalMemoryDedicated;
            break;
#else
        case PBF_EXTERNAL_MEMORY_OPAQUE_FD:
            h.type = cudaExternalMemoryHandleTypeOpaqueFd;
            break;
#endif
        default:
            return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this external memory type is not available on this platform");
    }
#if !defined(_WIN32)
    FdDup fd(d.fd);
    if (fd.fd < 0) return Status::error(PBF_ERROR_INVALID_ARGUMENT, "fd " + std::to_string(d.fd) + " is not an open file descriptor");
    h.handle.fd = fd.fd;
#endif
    ExternalBuffer b;
    b.desc = d;
    st = cuda_status("importing the external memory (cudaImportExternalMemory)", cudaImportExternalMemory(&b.memory, &h));
    if (!st.ok()) return st;
#if !defined(_WIN32)
    fd.consumed();
#endif
    cudaExternalMemoryBufferDesc bd;
    std::memset(&bd, 0, sizeof bd);
    bd.offset = 0;
    bd.size = d.size_bytes;
    st = cuda_status("mapping the external memory (cudaExternalMemoryGetMappedBuffer)",
                     cudaExternalMemoryGetMappedBuffer(&b.base, b.memory, &bd));
    if (!st.ok()) {
        cudaDestroyExternalMemory(b.memory);
        return st;
    }
#if !defined(_WIN32)
    close(d.fd);  // the caller's: the library owns it from here
#endif
    *out = to_id<pbf_external_buffer_id>(external_.insert(b));
    return Status{};
}

void CudaInterop::release_external(ExternalBuffer& b) {
    if (b.base) cudaFree(b.base);
    if (b.memory) cudaDestroyExternalMemory(b.memory);
    b.base = nullptr;
    b.memory = nullptr;
}

Status CudaInterop::release_external_buffer(pbf_external_buffer_id id) {
    Status st = activate();
    if (st.ok()) st = cuda_status("waiting for the world's stream", cudaStreamSynchronize(stream()));
    if (!st.ok()) return st;
    release_external(*external_.find(id.index, id.generation));
    external_.erase(id.index, id.generation);
    return cuda_status("releasing the external memory", cudaGetLastError());
}

Status CudaInterop::import_semaphore(const pbf_semaphore_desc& d, pbf_semaphore_id* out) {
    Status st = activate();
    if (!st.ok()) return st;
    cudaExternalSemaphoreHandleDesc h;
    std::memset(&h, 0, sizeof h);
    switch (d.type) {
#if defined(_WIN32)
        // Windows builds only; not compiled or tested on Linux.
        case PBF_SEMAPHORE_VULKAN_BINARY_WIN32:
            h.type = cudaExternalSemaphoreHandleTypeOpaqueWin32;
            h.handle.win32.handle = d.win32_handle;
            break;
        case PBF_SEMAPHORE_VULKAN_BINARY_WIN32_KMT:
            h.type = cudaExternalSemaphoreHandleTypeOpaqueWin32Kmt;
            h.handle.win32.handle = d.win32_handle;
            break;
        case PBF_SEMAPHORE_VULKAN_TIMELINE_WIN32:
            h.type = cudaExternalSemaphoreHandleTypeTimelineSemaphoreWin32;
            h.handle.win32.handle = d.win32_handle;
            break;
        case PBF_SEMAPHORE_D3D12_FENCE:
            h.type = cudaExternalSemaphoreHandleTypeD3D12Fence;
            h.handle.win32.handle = d.win32_handle;
            break;
#else
        case PBF_SEMAPHORE_VULKAN_BINARY_FD:
            h.type = cudaExternalSemaphoreHandleTypeOpaqueFd;
            break;
        case PBF_SEMAPHORE_VULKAN_TIMELINE_FD:
            h.type = cudaExternalSemaphoreHandleTypeTimelineSemaphoreFd;
            break;
#endif
        default:
            return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this semaphore type is not available on this platform");
    }
#if !defined(_WIN32)
    FdDup fd(d.fd);
    if (fd.fd < 0) return Status::error(PBF_ERROR_INVALID_ARGUMENT, "fd " + std::to_string(d.fd) + " is not an open file descriptor");
    h.handle.fd = fd.fd;
#endif
    Semaphore s;
    s.type = d.type;
    st = cuda_status("importing the semaphore (cudaImportExternalSemaphore)", cudaImportExternalSemaphore(&s.handle, &h));
    if (!st.ok()) return st;
#if !defined(_WIN32)
    fd.consumed();
    close(d.fd);
#endif
    *out = to_id<pbf_semaphore_id>(semaphores_.insert(s));
    return Status{};
}

Status CudaInterop::release_semaphore(pbf_semaphore_id id) {
    Status st = activate();
    if (st.ok()) st = cuda_status("waiting for the world's stream", cudaStreamSynchronize(stream()));
    if (!st.ok()) return st;
    Semaphore* s = semaphores_.find(id.index, id.generation);
    st = cuda_status("releasing the semaphore", cudaDestroyExternalSemaphore(s->handle));
    semaphores_.erase(id.index, id.generation);
    return st;
}

Status CudaInterop::copy_external(ExternalBuffer& b, const pbf_external_sync* sync) {
    Status st = activate();
    if (!st.ok()) return st;
    const cudaStream_t s = stream();
    const bool has_sync = sync != nullptr;
    Semaphore* wait = has_sync && (sync->wait_semaphore.index | sync->wait_semaphore.generation)
                          ? semaphores_.find(sync->wait_semaphore.index, sync->wait_semaphore.generation)
                          : nullptr;
    Semaphore* signal = has_sync && (sync->signal_semaphore.index | sync->signal_semaphore.generation)
                            ? semaphores_.find(sync->signal_semaphore.index, sync->signal_semaphore.generation)
                            : nullptr;
    if (has_sync && ((sync->wait_semaphore.generation && !wait) || (sync->signal_semaphore.generation && !signal)))
        return Status::error(PBF_ERROR_INVALID_HANDLE, "a semaphore of the copy's sync was released");
    batch_begin();
    if (wait) {
        cudaExternalSemaphoreWaitParams p;
        std::memset(&p, 0, sizeof p);
        p.params.fence.value = sync->wait_value;
        st = cuda_status("waiting for the external semaphore", cudaWaitExternalSemaphoresAsync(&wait->handle, &p, 1, s));
        if (!st.ok()) return st;
    }
    const pbf_external_buffer_desc& d = b.desc;
    char* base = static_cast<char*>(b.base);
    uint32_t* draw_args = d.write_draw_args ? reinterpret_cast<uint32_t*>(base + d.draw_args_offset_bytes) : nullptr;
    st = cuda_status("copying into the external buffer", launch_copy(world_.live_buffers(), d.source, base + d.offset_bytes,
                                                                     d.capacity, draw_args, d.draw_args_vertices, s));
    if (!st.ok()) return st;
    ++copies_;
    if (signal) {
        cudaExternalSemaphoreSignalParams p;
        std::memset(&p, 0, sizeof p);
        p.params.fence.value = sync->signal_value;
        st = cuda_status("signalling the external semaphore",
                         cudaSignalExternalSemaphoresAsync(&signal->handle, &p, 1, s));
        if (!st.ok()) return st;
    }
    batch_end();
    return Status{};
}

Status CudaInterop::copy_to_external_buffer(pbf_external_buffer_id id, const pbf_external_sync* sync) {
    return copy_external(*external_.find(id.index, id.generation), sync);
}

void CudaInterop::set_external_sync(pbf_external_buffer_id id, const pbf_external_sync* sync) {
    ExternalBuffer* b = external_.find(id.index, id.generation);
    if (sync) b->next_sync = *sync;
    else b->next_sync.reset();
}

// ---- Automatic copies -------------------------------------------------------------------------
Status CudaInterop::after_step() {
    std::vector<GlBuffer*> gl;
    gl_.for_each([&](GlBuffer& b) {
        if (b.desc.mode == PBF_COPY_ON_STEP && b.registered) gl.push_back(&b);
    });
    Status st = copy_gl(gl);
    external_.for_each([&](ExternalBuffer& b) {
        if (b.desc.mode != PBF_COPY_ON_STEP) return;
        std::optional<pbf_external_sync> sync = b.next_sync;
        b.next_sync.reset();
        Status s2 = copy_external(b, sync ? &*sync : nullptr);
        if (st.ok()) st = s2;
    });
    if (!st.ok()) st.message = "the step was taken, but the copy after it failed: " + st.message;
    return st;
}

bool CudaInterop::wants_render_events() {
    bool any = !gl_to_unregister_.empty();
    gl_.for_each([&](GlBuffer& b) { any = any || b.desc.mode == PBF_COPY_ON_RENDER_EVENT; });
    external_.for_each([&](ExternalBuffer& b) { any = any || b.desc.mode == PBF_COPY_ON_RENDER_EVENT; });
    return any;
}

Status CudaInterop::render_event() {
    Status st = activate();
    if (st.ok()) {
        // 1. Registrations queued by pbf_world_register_gl_buffer (GL context current here).
        gl_.for_each([&](GlBuffer& b) {
            if (b.desc.mode != PBF_COPY_ON_RENDER_EVENT || b.registered || b.failed) return;
            Status s2 = register_now(b);
            if (!s2.ok()) {
                b.failed = true;
                if (st.ok()) st = s2;
            }
        });
        // 2. The copies.
        std::vector<GlBuffer*> gl;
        gl_.for_each([&](GlBuffer& b) {
            if (b.desc.mode == PBF_COPY_ON_RENDER_EVENT && b.registered) gl.push_back(&b);
        });
        Status s2 = copy_gl(gl);
        if (st.ok()) st = s2;
        external_.for_each([&](ExternalBuffer& b) {
            if (b.desc.mode != PBF_COPY_ON_RENDER_EVENT) return;
            std::optional<pbf_external_sync> sync = b.next_sync;
            b.next_sync.reset();
            Status s3 = copy_external(b, sync ? &*sync : nullptr);
            if (st.ok()) st = s3;
        });
        // 3. Unregistrations queued by pbf_world_unregister_gl_buffer.
        for (GlBuffer& b : gl_to_unregister_) {
            Status s4 = unregister_now(b);
            if (st.ok()) st = s4;
        }
        gl_to_unregister_.clear();
    }
    ++render_events_;
    last_render_event_ = st;
    return st;
}

void CudaInterop::get_info(pbf_interop_info* out) {
    out->gl_buffers = uint32_t(gl_.size());
    out->external_buffers = uint32_t(external_.size());
    out->semaphores = uint32_t(semaphores_.size());
    out->copies = copies_;
    out->render_events = render_events_;
    out->last_copy_gpu_ms = 0.0f;
    if (copy_timed_ && activate().ok() && cudaEventSynchronize(copy_stop_) == cudaSuccess) {
        float ms = 0.0f;
        if (cudaEventElapsedTime(&ms, copy_start_, copy_stop_) == cudaSuccess) out->last_copy_gpu_ms = ms;
    }
    (void)cudaGetLastError();
    out->last_copy_host_ms = last_copy_host_ms_;
    out->last_render_event_result = last_render_event_.code;
    uint32_t pending = uint32_t(gl_to_unregister_.size());
    gl_.for_each([&](GlBuffer& b) {
        if (b.desc.mode == PBF_COPY_ON_RENDER_EVENT && !b.registered && !b.failed) ++pending;
    });
    out->pending_render_work = pending;
    std::memcpy(out->device_uuid, prop_.uuid.bytes, sizeof out->device_uuid);
#if defined(_WIN32)
    std::memcpy(out->device_luid, prop_.luid, sizeof out->device_luid);
    out->device_node_mask = prop_.luidDeviceNodeMask;
#endif
    out->cuda_device = device_;
    std::strncpy(out->last_render_event_message, last_render_event_.message.c_str(),
                 sizeof out->last_render_event_message - 1);
}

}  // namespace

std::unique_ptr<Interop> Interop::create(World& world, Status* status) {
    if (world.backend_kind() != PBF_BACKEND_CUDA) {
        *status = Status::error(PBF_ERROR_INVALID_STATE, "the world runs on the CPU backend; interop needs CUDA");
        return nullptr;
    }
    auto interop = std::make_unique<CudaInterop>(world);
    *status = interop->init();
    if (!status->ok()) return nullptr;
    return interop;
}

}  // namespace pbf
