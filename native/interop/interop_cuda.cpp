// The world's interop state on CUDA (interop_cuda.h): lifecycle, the copies after a step, the
// render thread's work and the info call; what this build supports.
#include <cstring>

#include "interop_cuda.h"

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

namespace cuda_interop {

Status cuda_status(const std::string& what, cudaError_t e) {
    if (e == cudaSuccess) return Status{};
    (void)cudaGetLastError();  // clear a non-sticky error so the next call starts clean
    const pbf_result code = e == cudaErrorMemoryAllocation ? PBF_ERROR_OUT_OF_MEMORY : PBF_ERROR_BACKEND;
    return Status::error(code, what + ": CUDA error " + cudaGetErrorName(e) + " (" + cudaGetErrorString(e) + ")");
}

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

// ---- Automatic copies -------------------------------------------------------------------------
Status CudaInterop::copy_all(pbf_copy_mode mode) {
    std::vector<GlBuffer*> gl;
    gl_.for_each([&](GlBuffer& b) {
        if (b.desc.mode == mode && b.registered) gl.push_back(&b);
    });
    Status st = copy_gl(gl);
    external_.for_each([&](ExternalBuffer& b) {
        if (b.desc.mode != mode) return;
        std::optional<pbf_external_sync> sync = b.next_sync;
        b.next_sync.reset();
        Status s2 = copy_external(b, sync ? &*sync : nullptr);
        if (st.ok()) st = s2;
    });
    return st;
}

Status CudaInterop::after_step() {
    Status st = copy_all(PBF_COPY_ON_STEP);
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
        Status s2 = copy_all(PBF_COPY_ON_RENDER_EVENT);
        if (st.ok()) st = s2;
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

}  // namespace cuda_interop

std::unique_ptr<Interop> Interop::create(World& world, Status* status) {
    if (world.backend_kind() != PBF_BACKEND_CUDA) {
        *status = Status::error(PBF_ERROR_INVALID_STATE, "the world runs on the CPU backend; interop needs CUDA");
        return nullptr;
    }
    auto interop = std::make_unique<cuda_interop::CudaInterop>(world);
    *status = interop->init();
    if (!status->ok()) return nullptr;
    return interop;
}

}  // namespace pbf
