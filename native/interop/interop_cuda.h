// The CUDA implementation of the interop layer (interop.h), shared by its files, each by what it
// talks to (after NVIDIA Warp's x.h / x.cpp / x.cu):
//   interop_cuda.cpp      the world's interop state: lifecycle, copies after a step, the render
//                         thread's work, info; interop_support() and Interop::create()
//   interop_gl.cpp        OpenGL buffer objects through CUDA-GL interop (PBF_HAVE_GL_INTEROP)
//   interop_external.cpp  external memory and semaphores (opaque fds; win32 handles on Windows)
//   interop_copy.cu       the copy kernel, events on the world's stream, copy timing
// Every file of it is compiled with the same PBF_HAVE_GL_INTEROP (GlBuffer's layout depends on it).
#pragma once
#include <cuda_runtime.h>
#if PBF_HAVE_GL_INTEROP
#include <cuda_gl_interop.h>
#endif

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "../common/slot_table.h"
#include "interop.h"

namespace pbf::cuda_interop {

// A Status for a CUDA error (clears a non-sticky one so the next call starts clean).
Status cuda_status(const std::string& what, cudaError_t e);

// One copy on stream: min(*live.count, capacity) elements of source into dst, and the draw
// arguments into draw_args (if not null). Never reads the count back.
cudaError_t launch_copy(const LiveBuffers& live, pbf_buffer source, void* dst, uint32_t capacity, uint32_t* draw_args,
                        uint32_t draw_vertices, cudaStream_t stream);

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
    // Every registered GL buffer and external buffer of this copy mode (external ones with the
    // sync set for their next copy); the first failure is returned, the other copies still run.
    Status copy_all(pbf_copy_mode mode);
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

}  // namespace pbf::cuda_interop
