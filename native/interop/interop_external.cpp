// External memory and semaphores: opaque file descriptors on Linux; win32 handles, D3D11 and
// D3D12 only in Windows builds.
#include <cstring>

#if !defined(_WIN32)
#include <unistd.h>
#endif

#include "interop_cuda.h"

namespace pbf::cuda_interop {
namespace {

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

}  // namespace

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

}  // namespace pbf::cuda_interop
