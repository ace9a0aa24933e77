// External memory and semaphores through the driver (cuImportExternalMemory,
// cuImportExternalSemaphore): opaque file descriptors on Linux; win32 handles of Vulkan, D3D11 and
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
        if (fd < 0)
            return Status::error(PBF_ERROR_INVALID_ARGUMENT,
                                 "fd " + std::to_string(d.fd) + " is not an open file descriptor");
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

// The driver's handle type of each external memory type this platform imports.
struct MemoryType {
    pbf_external_memory_type type;
    CUexternalMemoryHandleType cuda;
    bool dedicated;  // imported as a dedicated allocation, whatever the desc says
};
constexpr MemoryType kMemoryTypes[] = {
#if defined(_WIN32)
    // Windows builds only; not run on a GPU. Committed D3D resources are dedicated.
    {PBF_EXTERNAL_MEMORY_OPAQUE_WIN32, CU_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_WIN32, false},
    {PBF_EXTERNAL_MEMORY_OPAQUE_WIN32_KMT, CU_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_WIN32_KMT, false},
    {PBF_EXTERNAL_MEMORY_D3D12_RESOURCE, CU_EXTERNAL_MEMORY_HANDLE_TYPE_D3D12_RESOURCE, true},
    {PBF_EXTERNAL_MEMORY_D3D11_RESOURCE, CU_EXTERNAL_MEMORY_HANDLE_TYPE_D3D11_RESOURCE, true},
    {PBF_EXTERNAL_MEMORY_D3D11_RESOURCE_KMT, CU_EXTERNAL_MEMORY_HANDLE_TYPE_D3D11_RESOURCE_KMT, true},
#else
    {PBF_EXTERNAL_MEMORY_OPAQUE_FD, CU_EXTERNAL_MEMORY_HANDLE_TYPE_OPAQUE_FD, false},
#endif
};

// The driver's handle type of each semaphore type this platform imports.
struct SemaphoreType {
    pbf_semaphore_type type;
    CUexternalSemaphoreHandleType cuda;
};
constexpr SemaphoreType kSemaphoreTypes[] = {
#if defined(_WIN32)
    // Windows builds only; not run on a GPU.
    {PBF_SEMAPHORE_VULKAN_BINARY_WIN32, CU_EXTERNAL_SEMAPHORE_HANDLE_TYPE_OPAQUE_WIN32},
    {PBF_SEMAPHORE_VULKAN_BINARY_WIN32_KMT, CU_EXTERNAL_SEMAPHORE_HANDLE_TYPE_OPAQUE_WIN32_KMT},
    {PBF_SEMAPHORE_VULKAN_TIMELINE_WIN32, CU_EXTERNAL_SEMAPHORE_HANDLE_TYPE_TIMELINE_SEMAPHORE_WIN32},
    {PBF_SEMAPHORE_D3D12_FENCE, CU_EXTERNAL_SEMAPHORE_HANDLE_TYPE_D3D12_FENCE},
#else
    {PBF_SEMAPHORE_VULKAN_BINARY_FD, CU_EXTERNAL_SEMAPHORE_HANDLE_TYPE_OPAQUE_FD},
    {PBF_SEMAPHORE_VULKAN_TIMELINE_FD, CU_EXTERNAL_SEMAPHORE_HANDLE_TYPE_TIMELINE_SEMAPHORE_FD},
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
    PBF_INTEROP_NEED(cu_, cuImportExternalMemory);
    PBF_INTEROP_NEED(cu_, cuExternalMemoryGetMappedBuffer);
    PBF_INTEROP_NEED(cu_, cuDestroyExternalMemory);
    Status st = activate();
    if (!st.ok()) return st;
    CUDA_EXTERNAL_MEMORY_HANDLE_DESC h;
    std::memset(&h, 0, sizeof h);
    h.size = d.size_bytes;
    h.flags = d.dedicated ? CUDA_EXTERNAL_MEMORY_DEDICATED : 0u;
    const MemoryType* type = find_type(kMemoryTypes, d.type);
    if (!type)
        return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE,
                             "this external memory type is not available on this platform");
    h.type = type->cuda;
    if (type->dedicated) h.flags = CUDA_EXTERNAL_MEMORY_DEDICATED;
    OsHandle os(d);
    st = os.set(h, d);
    if (!st.ok()) return st;
    ExternalBuffer b;
    b.desc = d;
    st = cuda_status("importing the external memory (cuImportExternalMemory)",
                     cu_->cuImportExternalMemory(&b.memory, &h));
    if (!st.ok()) return st;
    os.imported();
    CUDA_EXTERNAL_MEMORY_BUFFER_DESC bd;
    std::memset(&bd, 0, sizeof bd);
    bd.offset = 0;
    bd.size = d.size_bytes;
    st = cuda_status("mapping the external memory (cuExternalMemoryGetMappedBuffer)",
                     cu_->cuExternalMemoryGetMappedBuffer(&b.base, b.memory, &bd));
    if (!st.ok()) {
        cu_->cuDestroyExternalMemory(b.memory);
        return st;
    }
    os.take_from_caller(d);
    *out = to_id<pbf_external_buffer_id>(external_.insert(b));
    return Status{};
}

Status CudaInterop::release_external(ExternalBuffer& b) {
    // The mapping is freed like any allocation, before the import it maps.
    Status st;
    if (b.base) st = cuda_status("freeing the external memory's mapping", cu_->cuMemFree(b.base));
    if (b.memory) {
        Status s2 = cuda_status("releasing the external memory", cu_->cuDestroyExternalMemory(b.memory));
        if (st.ok()) st = s2;
    }
    b.base = 0;
    b.memory = nullptr;
    return st;
}

Status CudaInterop::release_external_buffer(pbf_external_buffer_id id) {
    Status st = activate();
    if (st.ok()) st = cuda_status("waiting for the world's stream", cu_->cuStreamSynchronize(stream()));
    if (!st.ok()) return st;
    st = release_external(*external_.find(id.index, id.generation));
    external_.erase(id.index, id.generation);
    return st;
}

Status CudaInterop::import_semaphore(const pbf_semaphore_desc& d, pbf_semaphore_id* out) {
    PBF_INTEROP_NEED(cu_, cuImportExternalSemaphore);
    PBF_INTEROP_NEED(cu_, cuSignalExternalSemaphoresAsync);
    PBF_INTEROP_NEED(cu_, cuWaitExternalSemaphoresAsync);
    PBF_INTEROP_NEED(cu_, cuDestroyExternalSemaphore);
    Status st = activate();
    if (!st.ok()) return st;
    CUDA_EXTERNAL_SEMAPHORE_HANDLE_DESC h;
    std::memset(&h, 0, sizeof h);
    const SemaphoreType* type = find_type(kSemaphoreTypes, d.type);
    if (!type)
        return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "this semaphore type is not available on this platform");
    h.type = type->cuda;
    OsHandle os(d);
    st = os.set(h, d);
    if (!st.ok()) return st;
    Semaphore s;
    s.type = d.type;
    st = cuda_status("importing the semaphore (cuImportExternalSemaphore)",
                     cu_->cuImportExternalSemaphore(&s.handle, &h));
    if (!st.ok()) return st;
    os.imported();
    os.take_from_caller(d);
    *out = to_id<pbf_semaphore_id>(semaphores_.insert(s));
    return Status{};
}

Status CudaInterop::release_semaphore(pbf_semaphore_id id) {
    Status st = activate();
    if (st.ok()) st = cuda_status("waiting for the world's stream", cu_->cuStreamSynchronize(stream()));
    if (!st.ok()) return st;
    Semaphore* s = semaphores_.find(id.index, id.generation);
    st = cuda_status("releasing the semaphore", cu_->cuDestroyExternalSemaphore(s->handle));
    semaphores_.erase(id.index, id.generation);
    return st;
}

Status CudaInterop::copy_external(ExternalBuffer& b, const pbf_external_sync* sync) {
    Status st = activate();
    if (!st.ok()) return st;
    const CUstream s = stream();
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
        CUDA_EXTERNAL_SEMAPHORE_WAIT_PARAMS p;
        std::memset(&p, 0, sizeof p);
        p.params.fence.value = sync->wait_value;
        st = cuda_status("waiting for the external semaphore",
                         cu_->cuWaitExternalSemaphoresAsync(&wait->handle, &p, 1, s));
        if (!st.ok()) return st;
    }
    const pbf_external_buffer_desc& d = b.desc;
    const CUdeviceptr draw_args = d.write_draw_args ? b.base + d.draw_args_offset_bytes : 0;
    st = cuda_status("copying into the external buffer",
                     launch_copy(*cu_, *k_, world_.live_buffers(), d.source, b.base + d.offset_bytes, d.capacity,
                                 draw_args, d.draw_args_vertices, s));
    if (!st.ok()) return st;
    ++copies_;
    if (signal) {
        CUDA_EXTERNAL_SEMAPHORE_SIGNAL_PARAMS p;
        std::memset(&p, 0, sizeof p);
        p.params.fence.value = sync->signal_value;
        st = cuda_status("signalling the external semaphore",
                         cu_->cuSignalExternalSemaphoresAsync(&signal->handle, &p, 1, s));
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
    if (sync)
        b->next_sync = *sync;
    else
        b->next_sync.reset();
}

}  // namespace pbf::cuda_interop
