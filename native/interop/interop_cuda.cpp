// The world's interop state on CUDA (interop_cuda.h): lifecycle, the copies after a step, the
// render thread's work and the info call; what this build supports.
#include <cstring>

#include "interop_cuda.h"

#include "../common/c_text.h"

namespace pbf {

uint32_t interop_support() {
    // GL names and D3D11 pointers travel as plain integers and pointers to the driver: no graphics
    // API header is needed, so every CUDA build has graphics interop. Whether the driver has the
    // entry points is known only at run time (a call needing a missing one is refused).
    uint32_t flags = PBF_INTEROP_SUPPORT_CUDA | PBF_INTEROP_SUPPORT_OPENGL;
#if defined(_WIN32)
    flags |= PBF_INTEROP_SUPPORT_EXTERNAL_WIN32 | PBF_INTEROP_SUPPORT_D3D11;
#else
    flags |= PBF_INTEROP_SUPPORT_EXTERNAL_FD;
#endif
    return flags;
}

namespace cuda_interop {

Status cuda_status(const std::string& what, CUresult e) {
    if (e == CUDA_SUCCESS) return Status{};
    const pbf_result code = e == CUDA_ERROR_OUT_OF_MEMORY ? PBF_ERROR_OUT_OF_MEMORY : PBF_ERROR_BACKEND;
    return Status::error(code, what + ": " + cuda::error_text(e));
}

CudaInterop::~CudaInterop() {
    if (!cu_) return;  // init failed before anything was created
    // Best effort: the world is going away. Let queued copies finish before the resources go.
    if (!activate().ok()) return;
    if (CUstream s = stream()) cu_->cuStreamSynchronize(s);
    for_each_graphics([&](GraphicsBuffer& b) { unregister_now(b); });
    for (GraphicsBuffer& b : graphics_to_unregister_) unregister_now(b);
    external_.for_each([&](ExternalBuffer& b) { release_external(b); });
    semaphores_.for_each([&](Semaphore& s) {
        if (s.handle) cu_->cuDestroyExternalSemaphore(s.handle);
    });
    for (CUevent e : {user_event_, copy_start_, copy_stop_})
        if (e) cu_->cuEventDestroy(e);
}

Status CudaInterop::init() {
    device_ = world_.live_buffers().cuda_device;
    CudaAvailability why;
    k_ = cuda::kernels(device_, &why);
    if (!k_) return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, why.message);
    cu_ = cuda::driver();
    Status st = activate();
    if (st.ok()) st = cuda_status("creating the copy timer", cu_->cuEventCreate(&copy_start_, CU_EVENT_DEFAULT));
    if (st.ok()) st = cuda_status("creating the copy timer", cu_->cuEventCreate(&copy_stop_, CU_EVENT_DEFAULT));
    return st;
}

// ---- Automatic copies -------------------------------------------------------------------------
Status CudaInterop::copy_all(pbf_copy_mode mode) {
    std::vector<GraphicsBuffer*> graphics;
    for_each_graphics([&](GraphicsBuffer& b) {
        if (b.mode == mode && b.registered) graphics.push_back(&b);
    });
    Status st = copy_graphics(graphics);
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
    bool any = !graphics_to_unregister_.empty();
    for_each_graphics([&](GraphicsBuffer& b) { any = any || b.mode == PBF_COPY_ON_RENDER_EVENT; });
    external_.for_each([&](ExternalBuffer& b) { any = any || b.desc.mode == PBF_COPY_ON_RENDER_EVENT; });
    return any;
}

Status CudaInterop::render_event() {
    Status st = activate();
    if (st.ok()) {
        // 1. Registrations queued by pbf_world_register_gl_buffer / _d3d11_buffer: the render
        //    thread is where the GL context is current and the D3D11 device context may be used.
        for_each_graphics([&](GraphicsBuffer& b) {
            if (b.mode != PBF_COPY_ON_RENDER_EVENT || b.registered || b.failed) return;
            Status s2 = register_now(b);
            if (!s2.ok()) {
                b.failed = true;
                if (st.ok()) st = s2;
            }
        });
        // 2. The copies.
        Status s2 = copy_all(PBF_COPY_ON_RENDER_EVENT);
        if (st.ok()) st = s2;
        // 3. Unregistrations queued by pbf_world_unregister_gl_buffer / _d3d11_buffer.
        for (GraphicsBuffer& b : graphics_to_unregister_) {
            Status s4 = unregister_now(b);
            if (st.ok()) st = s4;
        }
        graphics_to_unregister_.clear();
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
    if (copy_timed_ && activate().ok() && cu_->cuEventSynchronize(copy_stop_) == CUDA_SUCCESS) {
        float ms = 0.0f;
        if (cu_->cuEventElapsedTime(&ms, copy_start_, copy_stop_) == CUDA_SUCCESS) out->last_copy_gpu_ms = ms;
    }
    out->last_copy_host_ms = last_copy_host_ms_;
    out->last_render_event_result = last_render_event_.code;
    uint32_t pending = uint32_t(graphics_to_unregister_.size());
    for_each_graphics([&](GraphicsBuffer& b) {
        if (b.mode == PBF_COPY_ON_RENDER_EVENT && !b.registered && !b.failed) ++pending;
    });
    out->pending_render_work = pending;
    CUuuid uuid{};
    if (cu_->cuDeviceGetUuid(&uuid, k_->device) == CUDA_SUCCESS)
        std::memcpy(out->device_uuid, uuid.bytes, sizeof out->device_uuid);
#if defined(_WIN32)
    // The LUID is what D3D11 and D3D12 name adapters by; Windows drivers only.
    if (cu_->cuDeviceGetLuid) {
        char luid[8] = {};
        unsigned int mask = 0;
        if (cu_->cuDeviceGetLuid(luid, &mask, k_->device) == CUDA_SUCCESS) {
            std::memcpy(out->device_luid, luid, sizeof out->device_luid);
            out->device_node_mask = mask;
        }
    }
#endif
    out->cuda_device = device_;
    copy_text(out->last_render_event_message, last_render_event_.message);
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
