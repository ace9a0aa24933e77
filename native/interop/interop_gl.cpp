// OpenGL buffer objects through CUDA-GL interop (built with the OpenGL headers:
// PBF_HAVE_GL_INTEROP; without them every GL call is refused).
#include <algorithm>

#include "interop_cuda.h"

namespace pbf::cuda_interop {

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
        const uint64_t need = d.offset_bytes + uint64_t(d.capacity) * buffer_element_bytes(d.source);
        if (st.ok() && need > size)
            st = Status::error(PBF_ERROR_INVALID_ARGUMENT,
                               name + " holds " + std::to_string(size) + " bytes; offset_bytes + capacity * " +
                                   std::to_string(buffer_element_bytes(d.source)) + " needs " + std::to_string(need));
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

}  // namespace pbf::cuda_interop
