// External memory and semaphores: opaque file descriptors on Linux; win32 handles, D3D11 and
// D3D12 only in Windows builds.
#include <cstring>

#if !defined(_WIN32)
#include <unistd.h>
#endif

#include "interop_cuda.h"

namespace pbf::cuda_interop {
namespace {

// The caller's OS handle (of a pbf_external_buffer_desc or pbf_semaphore_desc d) as a CUDA
// import desc h takes it.
#if defined(_WIN32)
// Windows: the win32 handle itself; the caller keeps it.
struct OsHandle {
    template <class Desc>
    explicit OsHandle(const Desc&) {}
    template <class HandleDesc, class Desc>
    Status set(HandleDesc& h, const Desc& d) const {
        h.handle.win32.handle = d.win32_handle;
        return Status{};
    }
    void imported() {}
    template <class Desc>
    void take_from_caller(const Desc&) {}
};
#else
// Linux: CUDA takes ownership of an fd only when an import succeeds, and a later step of ours
// may still fail: import a duplicate, and close the caller's fd once everything succeeded (the
// caller keeps it on any failure).
struct OsHandle {
    int fd = -1;
    template <class Desc>
    explicit OsHandle(const Desc& d) : fd(dup(d.fd)) {}
    ~OsHandle() {
        if (fd >= 0) close(fd);
    }
    OsHandle(const OsHandle&) = delete;
    OsHandle& operator=(const OsHandle&) = delete;
    template <class HandleDesc, class Desc>
    Status set(HandleDesc& h, const Desc& d) const {
        if (fd < 0) return Status::error(PBF_ERROR_INVALID_ARGUMENT, "fd " + std::to_string(d.fd) + " is not an open file descriptor");
        h.handle.fd = fd;
        return Status{};
    }
    void imported() { fd = -1; }  // CUDA owns the duplicate now
    template <class Desc>
    void take_from_caller(const Desc& d) {
        close(d.fd);  // the caller's: the library owns it from here
    }
};
#endif

// The CUDA handle type of each external memory type this platform imports.
struct MemoryType {
    pbf_external_memory_type type;
    cudaExternalMemoryHandleType cuda;
    bool dedicated;  // imported as a dedicated allocation, whatever the desc says
};
constexpr MemoryType kMemoryTypes[] = {
#if defined(_WIN32)
    // Windows builds only; not compiled or tested on Linux. Committed D3D resources are dedicated.
    {PBF_EXTERNAL_MEMORY_OPAQUE_WIN32, cudaExternalMemoryHandleTypeOpaqueWin32, false},
    {PBF_EXTERNAL_MEMORY_OPAQUE_WIN32_KMT, cudaExternalMemoryHandleTypeOpaqueWin32Kmt, false},
    {PBF_EXTERNAL_MEMORY_D3D12_RESOURCE, cudaExternalMemoryHandleTypeD3D12Resource, true},
    {PBF_EXTERNAL_MEMORY_D3D11_RESOURCE, cudaExternalMemoryHandleTypeD3D11Resource, true},
    {PBF_EXTERNAL_MEMORY_D3D11_RESOURCE_KMT, cudaExternalMemoryHandleTypeD3D11ResourceKmt, true},
#else
    {PBF_EXTERNAL_MEMORY_OPAQUE_FD, cudaExternalMemoryHandleTypeOpaqueFd, false},
#endif
};

// The CUDA handle type of each semaphore type this platform imports.
struct SemaphoreType {
    pbf_semaphore_type type;
    cudaExternalSemaphoreHandleType cuda;
};
constexpr SemaphoreType kSemaphoreTypes[] = {
#if defined(_WIN32)
    // Windows builds only; not compiled or tested on Linux.
    {PBF_SEMAPHORE_VULKAN_BINARY_WIN32, cudaExternalSemaphoreHandleTypeOpaqueWin32},
    {PBF_SEMAPHORE_VULKAN_BINARY_WIN32_KMT, cudaExternalSemaphoreHandleTypeOpaqueWin32Kmt},
    {PBF_SEMAPHORE_VULKAN_TIMELINE_WIN32, cudaExternalSemaphoreHandleTypeTimelineSemaphoreWin32},
    {PBF_SEMAPHORE_D3D12_FENCE, cudaExternalSemaphoreHandleTypeD3D12Fence},
#else
    {PBF_SEMAPHORE_VULKAN_BINARY_FD, cudaExternalSemaphoreHandleTypeOpaqueFd},
    {PBF_SEMAPHORE_VULKAN_TIMELINE_FD, cudaExternalSemaphoreHandleTypeTimelineSemaphoreFd},
#endif
};

// The row of `table` for `type`; nullptr where this platform has none.
template <class Row, size_t N, class Type>
const Row* find_type(const Row (&table)[N], Type type) {
    for (const Row& r : table)
        if (r.type == type) return &r;
    return nullptr;
}

}  // namespace

Status CudaInterop::import_external_buffer(const pbf_external_buffer_desc& d, pbf_external_buffer_id* out) {
    Status st = activate();
    if (!st.ok()) return st;
    cudaExternalMemoryHandleDesc h;
    std::memset(&h, 0, sizeof h);
    h.size = d.size_bytes;
    h.flags = d.dedicated ? cudaExternalMemoryDedicated : 0u;
    const MemoryType* type = find_type(kMemoryTypes, d.type);
    if (!type) return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this external memory type is not available on this platform");
    h.type = type->cuda;
    if (type->dedicated) h.flags = cudaExternalMemoryDedicated;
    OsHandle os(d);
    st = os.set(h, d);
    if (!st.ok()) return st;
    ExternalBuffer b;
    b.desc = d;
    st = cuda_status("importing the external memory (cudaImportExternalMemory)", cudaImportExternalMemory(&b.memory, &h));
    if (!st.ok()) return st;
    os.imported();
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
    os.take_from_caller(d);
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
    const SemaphoreType* type = find_type(kSemaphoreTypes, d.type);
    if (!type) return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this semaphore type is not available on this platform");
    h.type = type->cuda;
    OsHandle os(d);
    st = os.set(h, d);
    if (!st.ok()) return st;
    Semaphore s;
    s.type = d.type;
    st = cuda_status("importing the semaphore (cudaImportExternalSemaphore)", cudaImportExternalSemaphore(&s.handle, &h));
    if (!st.ok()) return st;
    os.imported();
    os.take_from_caller(d);
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
