// The CUDA implementation of the interop layer (interop.h), over the CUDA driver the library opens
// at run time (the executor's driver table and module, reached through world_cuda.h): no CUDA
// runtime and no graphics API headers. Shared by its files, each by what it talks to:
//   interop_cuda.cpp      the world's interop state: lifecycle, copies after a step, the render
//                         thread's work, info; interop_support() and Interop::create()
//   interop_graphics.cpp  graphics API buffers through CUDA graphics interop: OpenGL buffer
//                         objects and Direct3D 11 buffers (Windows)
//   interop_external.cpp  external memory and semaphores (opaque fds; win32 handles on Windows)
//   interop_copy.cpp      the copy kernel's launch, events on the world's stream, copy timing
#pragma once
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "../common/slot_table.h"
#include "../world/world_cuda.h"
#include "interop.h"

namespace pbf::cuda_interop {

// A Status for a driver result: PBF_ERROR_OUT_OF_MEMORY or PBF_ERROR_BACKEND, naming what failed.
Status cuda_status(const std::string& what, CUresult e);

// PBF_ERROR_BACKEND_UNAVAILABLE naming the driver function a call needs where this driver lacks it
// (the interop entry points are optional: cuda_driver.h).
#define PBF_INTEROP_NEED(cu, name)                                                                  \
    do {                                                                                            \
        if (!(cu)->name)                                                                            \
            return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE,                                     \
                                 "the NVIDIA driver lacks " #name " (update the graphics driver)"); \
    } while (0)

// One copy on stream: min(*live.count, capacity) elements of source into dst, and the draw
// arguments into draw_args (if not 0). Never reads the count back.
CUresult launch_copy(const cuda::Driver& cu, const cuda::Kernels& k, const LiveBuffers& live, pbf_buffer source,
                     CUdeviceptr dst, uint32_t capacity, CUdeviceptr draw_args, uint32_t draw_vertices,
                     CUstream stream);

template <class Id, class H>
Id to_id(H h) {
    return Id{h.index, h.generation};
}

// A buffer of a graphics API registered through CUDA graphics interop: an OpenGL buffer object or
// a Direct3D 11 buffer. Both APIs are registered, mapped and copied into the same way; only the
// registration call and the names in messages differ.
struct GraphicsBuffer {
    enum class Api { GL, D3D11 };
    Api api = Api::GL;
    // The objects: GL buffer names, or ID3D11Buffer pointers (args: 0 / null for none).
    uint32_t gl_buffer = 0, gl_args = 0;
    void* d3d11_buffer = nullptr;
    void* d3d11_args = nullptr;
    // What each copy writes (the desc's fields).
    pbf_buffer source{};
    pbf_copy_mode mode{};
    uint64_t offset_bytes = 0;
    uint32_t capacity = 0;
    uint64_t draw_args_offset_bytes = 0;
    uint32_t draw_args_vertices = 0;

    CUgraphicsResource resource = nullptr;
    CUgraphicsResource args_resource = nullptr;  // null; == resource when one buffer holds both
    bool registered = false;
    bool failed = false;  // a render-event registration failed: not retried

    static GraphicsBuffer gl(const pbf_gl_buffer_desc& d);
    static GraphicsBuffer d3d11(const pbf_d3d11_buffer_desc& d);
    bool has_args() const { return api == Api::GL ? gl_args != 0 : d3d11_args != nullptr; }
    bool args_in_same_buffer() const { return api == Api::GL ? gl_args == gl_buffer : d3d11_args == d3d11_buffer; }
    // "GL buffer 5", "D3D11 buffer 0x1234" (args: its draw-arguments buffer).
    std::string name(bool args = false) const;
};

struct ExternalBuffer {
    pbf_external_buffer_desc desc{};
    CUexternalMemory memory = nullptr;
    CUdeviceptr base = 0;  // the whole allocation, mapped
    std::optional<pbf_external_sync> next_sync;
};

struct Semaphore {
    pbf_semaphore_type type{};
    CUexternalSemaphore handle = nullptr;
};

class CudaInterop final : public Interop {
public:
    explicit CudaInterop(World& world) : world_(world) {}
    ~CudaInterop() override;

    Status init();

    bool has_gl_buffer(pbf_gl_buffer_id id) override { return gl_.find(id.index, id.generation) != nullptr; }
    bool has_d3d11_buffer(pbf_d3d11_buffer_id id) override { return d3d11_.find(id.index, id.generation) != nullptr; }
    bool has_external_buffer(pbf_external_buffer_id id) override {
        return external_.find(id.index, id.generation) != nullptr;
    }
    bool has_semaphore(pbf_semaphore_id id) override { return semaphores_.find(id.index, id.generation) != nullptr; }
    pbf_copy_mode gl_buffer_mode(pbf_gl_buffer_id id) override { return gl_.find(id.index, id.generation)->mode; }
    pbf_copy_mode external_buffer_mode(pbf_external_buffer_id id) override {
        return external_.find(id.index, id.generation)->desc.mode;
    }

    Status record_event(void** out_event) override;
    Status wait_event(void* event) override;

    Status register_gl_buffer(const pbf_gl_buffer_desc& desc, pbf_gl_buffer_id* out) override;
    Status unregister_gl_buffer(pbf_gl_buffer_id id) override;
    Status copy_to_gl_buffer(pbf_gl_buffer_id id) override;
    Status register_d3d11_buffer(const pbf_d3d11_buffer_desc& desc, pbf_d3d11_buffer_id* out) override;
    Status unregister_d3d11_buffer(pbf_d3d11_buffer_id id) override;

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
    CUstream stream() const { return static_cast<CUstream>(world_.cuda_stream()); }
    Status activate() {
        return cuda_status("making the world's CUDA context current", cu_->cuCtxSetCurrent(k_->context));
    }
    // The driver functions graphics buffers of api need (PBF_ERROR_BACKEND_UNAVAILABLE if missing).
    Status graphics_entry_points(GraphicsBuffer::Api api) const;
    // Registers b now (or later, on the render thread, for PBF_COPY_ON_RENDER_EVENT) in table.
    template <class Id>
    Status add_graphics(SlotTable<GraphicsBuffer>& table, GraphicsBuffer b, Id* out);
    template <class Id>
    Status remove_graphics(SlotTable<GraphicsBuffer>& table, Id id);
    Status register_one(const GraphicsBuffer& b, bool args, CUgraphicsResource* out);
    Status copy_graphics(const std::vector<GraphicsBuffer*>& buffers);
    Status copy_external(ExternalBuffer& b, const pbf_external_sync* sync);
    // Every registered graphics buffer and external buffer of this copy mode (external ones with
    // the sync set for their next copy); the first failure is returned, the other copies still run.
    Status copy_all(pbf_copy_mode mode);
    Status register_now(GraphicsBuffer& b);
    Status unregister_now(GraphicsBuffer& b);
    Status release_external(ExternalBuffer& b);
    // Visits every graphics buffer of both APIs.
    template <class F>
    void for_each_graphics(F&& f) {
        gl_.for_each(f);
        d3d11_.for_each(f);
    }
    // Timing of a copy batch: events around it on the stream, host time around the call.
    void batch_begin();
    void batch_end();

    World& world_;
    const cuda::Driver* cu_ = nullptr;
    const cuda::Kernels* k_ = nullptr;
    int device_ = 0;
    CUevent user_event_ = nullptr;
    CUevent copy_start_ = nullptr, copy_stop_ = nullptr;
    bool copy_timed_ = false;
    std::chrono::steady_clock::time_point host_start_{};
    float last_copy_host_ms_ = 0.0f;
    uint64_t copies_ = 0, render_events_ = 0;
    Status last_render_event_;
    SlotTable<GraphicsBuffer> gl_;
    SlotTable<GraphicsBuffer> d3d11_;
    std::vector<GraphicsBuffer> graphics_to_unregister_;  // render-event buffers released by the caller
    SlotTable<ExternalBuffer> external_;
    SlotTable<Semaphore> semaphores_;
};

}  // namespace pbf::cuda_interop
