// The copy kernel's launch and the world's stream: events for the caller, and the timing of copy
// batches. The copies never read the particle count back: the kernel (pbf_copy_live_*, embedded
// with the executor's kernels) reads it on the device, copies min(count, capacity) elements and
// optionally writes draw arguments, all on the world's stream.
#include <algorithm>

#include "interop_cuda.h"

namespace pbf::cuda_interop {
namespace {

constexpr uint32_t kCopyBlock = 256;
constexpr uint32_t kMaxCopyBlocks = 4096;  // the kernel strides over the rest

}  // namespace

CUresult launch_copy(const cuda::Driver& cu, const cuda::Kernels& k, const LiveBuffers& live, pbf_buffer source,
                     CUdeviceptr dst, uint32_t capacity, CUdeviceptr draw_args, uint32_t draw_vertices,
                     CUstream stream) {
    const uint32_t blocks =
        std::max<uint32_t>(1, std::min<uint32_t>((capacity + kCopyBlock - 1) / kCopyBlock, kMaxCopyBlocks));
    const void* src = live_buffer(live, source);
    if (!src) return CUDA_ERROR_INVALID_VALUE;         // refused by the API layer before it gets here
    const uint32_t* count = live_count(live, source);  // the diffuse buffers have their own
    // Ids are copied as uint32_t; the Vec4 buffers as float4, one per particle or three (anisotropy).
    const bool ids = source == PBF_BUFFER_IDS;
    uint32_t words = ids ? 1u : buffer_element_bytes(source) / 16u;
    // The kernel's parameters (const T* src, T* dst, uint32_t words, const uint32_t* count,
    // uint32_t capacity, uint32_t* draw_args, uint32_t draw_vertices), each passed by address.
    void* params[] = {&src, &dst, &words, &count, &capacity, &draw_args, &draw_vertices};
    return cu.cuLaunchKernel(ids ? k.copy_live_u32 : k.copy_live_f4, blocks, 1, 1, kCopyBlock, 1, 1, 0, stream, params,
                             nullptr);
}

Status CudaInterop::record_event(void** out_event) {
    Status st = activate();
    if (!st.ok()) return st;
    if (!user_event_) {
        st = cuda_status("creating the world's event", cu_->cuEventCreate(&user_event_, CU_EVENT_DISABLE_TIMING));
        if (!st.ok()) return st;
    }
    st = cuda_status("recording the world's event", cu_->cuEventRecord(user_event_, stream()));
    if (st.ok()) *out_event = user_event_;
    return st;
}

Status CudaInterop::wait_event(void* event) {
    Status st = activate();
    if (!st.ok()) return st;
    return cuda_status("making the world's stream wait for the event",
                       cu_->cuStreamWaitEvent(stream(), static_cast<CUevent>(event), 0));
}

void CudaInterop::batch_begin() {
    host_start_ = std::chrono::steady_clock::now();
    cu_->cuEventRecord(copy_start_, stream());
}

void CudaInterop::batch_end() {
    copy_timed_ = cu_->cuEventRecord(copy_stop_, stream()) == CUDA_SUCCESS;
    last_copy_host_ms_ =
        std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - host_start_).count();
}

}  // namespace pbf::cuda_interop
