// Graphics API buffers through CUDA graphics interop: OpenGL buffer objects
// (cuGraphicsGLRegisterBuffer) and Direct3D 11 buffers (cuGraphicsD3D11RegisterResource, Windows).
// Registered once, then mapped, written by the copy kernel and unmapped on the world's stream for
// every copy batch; the driver orders map and unmap against the graphics API's own work.
#include <algorithm>
#include <cstdio>

#include "interop_cuda.h"

namespace pbf::cuda_interop {

namespace {
// The fields both descs share: what each copy writes.
template <class Desc>
GraphicsBuffer copying(GraphicsBuffer::Api api, const Desc& d) {
    GraphicsBuffer b;
    b.api = api;
    b.source = d.source;
    b.mode = d.mode;
    b.offset_bytes = d.offset_bytes;
    b.capacity = d.capacity;
    b.draw_args_offset_bytes = d.draw_args_offset_bytes;
    b.draw_args_vertices = d.draw_args_vertices;
    return b;
}
}  // namespace

GraphicsBuffer GraphicsBuffer::gl(const pbf_gl_buffer_desc& d) {
    GraphicsBuffer b = copying(Api::GL, d);
    b.gl_buffer = d.buffer;
    b.gl_args = d.draw_args_buffer;
    return b;
}

GraphicsBuffer GraphicsBuffer::d3d11(const pbf_d3d11_buffer_desc& d) {
    GraphicsBuffer b = copying(Api::D3D11, d);
    b.d3d11_buffer = d.buffer;
    b.d3d11_args = d.draw_args_buffer;
    return b;
}

std::string GraphicsBuffer::name(bool args) const {
    const std::string what = args ? "draw-arguments " : "";
    if (api == Api::GL) return what + "GL buffer " + std::to_string(args ? gl_args : gl_buffer);
    char text[32];
    std::snprintf(text, sizeof text, "%p", args ? d3d11_args : d3d11_buffer);
    return what + "D3D11 buffer " + text;
}

Status CudaInterop::graphics_entry_points(GraphicsBuffer::Api api) const {
    if (api == GraphicsBuffer::Api::GL)
        PBF_INTEROP_NEED(cu_, cuGraphicsGLRegisterBuffer);
    else
        PBF_INTEROP_NEED(cu_, cuGraphicsD3D11RegisterResource);
    PBF_INTEROP_NEED(cu_, cuGraphicsMapResources);
    PBF_INTEROP_NEED(cu_, cuGraphicsUnmapResources);
    PBF_INTEROP_NEED(cu_, cuGraphicsResourceGetMappedPointer);
    PBF_INTEROP_NEED(cu_, cuGraphicsUnregisterResource);
    return Status{};
}

Status CudaInterop::register_one(const GraphicsBuffer& b, bool args, CUgraphicsResource* out) {
    *out = nullptr;
    CUresult e;
    std::string hint;
    if (b.api == GraphicsBuffer::Api::GL) {
        e = cu_->cuGraphicsGLRegisterBuffer(out, args ? b.gl_args : b.gl_buffer, CU_GRAPHICS_REGISTER_FLAGS_NONE);
        hint = " (is a GL context of the world's GPU current?)";
    } else {
        e = cu_->cuGraphicsD3D11RegisterResource(out, args ? b.d3d11_args : b.d3d11_buffer,
                                                 CU_GRAPHICS_REGISTER_FLAGS_NONE);
        hint = " (is it an ID3D11Buffer of a D3D11 device on the world's GPU?)";
    }
    if (e != CUDA_SUCCESS) *out = nullptr;
    return cuda_status("registering " + b.name(args) + " with CUDA" + (args ? "" : hint), e);
}

Status CudaInterop::register_now(GraphicsBuffer& b) {
    Status st = activate();
    if (!st.ok()) return st;
    st = register_one(b, false, &b.resource);
    if (!st.ok()) return st;
    if (b.args_in_same_buffer()) {
        b.args_resource = b.resource;
    } else if (b.has_args()) {
        st = register_one(b, true, &b.args_resource);
        if (!st.ok()) {
            cu_->cuGraphicsUnregisterResource(b.resource);
            b.resource = nullptr;
            return st;
        }
    }
    // Check the sizes once, while registering (a copy never writes past a buffer's storage).
    const std::string name = b.name();
    CUgraphicsResource resources[2] = {b.resource, b.args_resource};
    const unsigned n = (b.args_resource && b.args_resource != b.resource) ? 2 : 1;
    st = cuda_status("mapping " + name + " to check its size", cu_->cuGraphicsMapResources(n, resources, stream()));
    if (st.ok()) {
        CUdeviceptr p = 0;
        size_t size = 0, args_size = 0;
        st = cuda_status("reading the size of " + name, cu_->cuGraphicsResourceGetMappedPointer(&p, &size, b.resource));
        if (st.ok() && b.args_resource)
            st = cuda_status("reading the size of the draw-arguments buffer",
                             cu_->cuGraphicsResourceGetMappedPointer(&p, &args_size, b.args_resource));
        Status unmapped = cuda_status("unmapping " + name, cu_->cuGraphicsUnmapResources(n, resources, stream()));
        if (st.ok()) st = unmapped;
        const uint64_t need = b.offset_bytes + uint64_t(b.capacity) * buffer_element_bytes(b.source);
        if (st.ok() && need > size)
            st = Status::error(PBF_ERROR_INVALID_ARGUMENT,
                               name + " holds " + std::to_string(size) + " bytes; offset_bytes + capacity * " +
                                   std::to_string(buffer_element_bytes(b.source)) + " needs " + std::to_string(need));
        if (st.ok() && b.args_resource && b.draw_args_offset_bytes + 16 > args_size)
            st = Status::error(PBF_ERROR_INVALID_ARGUMENT, b.name(true) + " holds " + std::to_string(args_size) +
                                                               " bytes; draw_args_offset_bytes + 16 needs " +
                                                               std::to_string(b.draw_args_offset_bytes + 16));
        if (st.ok() && b.args_in_same_buffer()) {
            const uint64_t a0 = b.draw_args_offset_bytes, a1 = a0 + 16;
            if (a0 < need && b.offset_bytes < a1)
                st = Status::error(PBF_ERROR_INVALID_ARGUMENT, "the draw arguments overlap the particles in " + name);
        }
    }
    if (!st.ok()) {
        unregister_now(b);
        return st;
    }
    b.registered = true;
    return Status{};
}

Status CudaInterop::unregister_now(GraphicsBuffer& b) {
    Status st;
    if (b.args_resource && b.args_resource != b.resource)
        st = cuda_status("unregistering the " + b.name(true), cu_->cuGraphicsUnregisterResource(b.args_resource));
    if (b.resource) {
        Status s2 = cuda_status("unregistering " + b.name(), cu_->cuGraphicsUnregisterResource(b.resource));
        if (st.ok()) st = s2;
    }
    b.resource = b.args_resource = nullptr;
    b.registered = false;
    return st;
}

Status CudaInterop::copy_graphics(const std::vector<GraphicsBuffer*>& buffers) {
    if (buffers.empty()) return Status{};
    Status st = activate();
    if (!st.ok()) return st;
    std::vector<CUgraphicsResource> resources;
    for (GraphicsBuffer* b : buffers)
        for (CUgraphicsResource r : {b->resource, b->args_resource})
            if (r && std::find(resources.begin(), resources.end(), r) == resources.end()) resources.push_back(r);
    const CUstream s = stream();
    const LiveBuffers live = world_.live_buffers();
    batch_begin();
    st = cuda_status("mapping the graphics buffers",
                     cu_->cuGraphicsMapResources(unsigned(resources.size()), resources.data(), s));
    if (!st.ok()) return st;
    for (GraphicsBuffer* b : buffers) {
        CUdeviceptr dst = 0, args = 0;
        size_t size = 0;
        st = cuda_status("reading " + b->name() + "'s device address",
                         cu_->cuGraphicsResourceGetMappedPointer(&dst, &size, b->resource));
        if (st.ok() && b->args_resource)
            st = cuda_status("reading the draw-arguments buffer's device address",
                             cu_->cuGraphicsResourceGetMappedPointer(&args, &size, b->args_resource));
        if (!st.ok()) break;
        st = cuda_status("copying into " + b->name(),
                         launch_copy(*cu_, *k_, live, b->source, dst + b->offset_bytes, b->capacity,
                                     args ? args + b->draw_args_offset_bytes : 0, b->draw_args_vertices, s));
        if (!st.ok()) break;
        ++copies_;
    }
    Status unmapped = cuda_status("unmapping the graphics buffers",
                                  cu_->cuGraphicsUnmapResources(unsigned(resources.size()), resources.data(), s));
    batch_end();
    return st.ok() ? unmapped : st;
}

template <class Id>
Status CudaInterop::add_graphics(SlotTable<GraphicsBuffer>& table, GraphicsBuffer b, Id* out) {
    Status st = graphics_entry_points(b.api);
    if (!st.ok()) return st;
    if (b.mode != PBF_COPY_ON_RENDER_EVENT) {
        st = register_now(b);
        if (!st.ok()) return st;
    }
    *out = to_id<Id>(table.insert(b));
    return Status{};
}

template <class Id>
Status CudaInterop::remove_graphics(SlotTable<GraphicsBuffer>& table, Id id) {
    GraphicsBuffer b = *table.find(id.index, id.generation);
    table.erase(id.index, id.generation);
    if (b.mode == PBF_COPY_ON_RENDER_EVENT) {
        if (b.registered) graphics_to_unregister_.push_back(b);  // the render thread owns it
        return Status{};
    }
    Status st = activate();
    if (st.ok()) st = unregister_now(b);
    return st;
}

Status CudaInterop::register_gl_buffer(const pbf_gl_buffer_desc& desc, pbf_gl_buffer_id* out) {
    return add_graphics(gl_, GraphicsBuffer::gl(desc), out);
}

Status CudaInterop::unregister_gl_buffer(pbf_gl_buffer_id id) { return remove_graphics(gl_, id); }

Status CudaInterop::copy_to_gl_buffer(pbf_gl_buffer_id id) {
    return copy_graphics({gl_.find(id.index, id.generation)});
}

Status CudaInterop::register_d3d11_buffer(const pbf_d3d11_buffer_desc& desc, pbf_d3d11_buffer_id* out) {
    return add_graphics(d3d11_, GraphicsBuffer::d3d11(desc), out);
}

Status CudaInterop::unregister_d3d11_buffer(pbf_d3d11_buffer_id id) { return remove_graphics(d3d11_, id); }

}  // namespace pbf::cuda_interop
