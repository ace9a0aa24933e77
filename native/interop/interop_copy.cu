// The copy kernel and the world's stream: events for the caller, and the timing of copy batches.
// The copies never read the particle count back: the kernel reads it on the device, copies
// min(count, capacity) elements and optionally writes draw arguments, all on the world's stream.
#include <algorithm>

#include "interop_cuda.h"

namespace pbf::cuda_interop {
namespace {

constexpr int kCopyBlock = 256;
constexpr uint32_t kMaxCopyBlocks = 4096;

// Copies min(*count, capacity) elements of `words` T each; block 0's thread 0 writes the draw
// arguments (in elements).
template <class T>
__global__ void copy_live_kernel(const T* __restrict__ src, T* __restrict__ dst, uint32_t words,
                                 const uint32_t* __restrict__ count, uint32_t capacity, uint32_t* __restrict__ draw_args,
                                 uint32_t draw_vertices) {
    const uint32_t n = min(*count, capacity);
    const uint64_t total = uint64_t(n) * words;
    for (uint64_t i = blockIdx.x * uint64_t(blockDim.x) + threadIdx.x; i < total; i += uint64_t(gridDim.x) * blockDim.x)
        dst[i] = src[i];
    if (draw_args && blockIdx.x == 0 && threadIdx.x == 0) {
        draw_args[0] = draw_vertices ? draw_vertices : n;
        draw_args[1] = draw_vertices ? n : 1u;
        draw_args[2] = 0u;
        draw_args[3] = 0u;
    }
}


}  // namespace

// One copy: source buffer of the world into dst (+ draw arguments), on stream.
cudaError_t launch_copy(const LiveBuffers& live, pbf_buffer source, void* dst, uint32_t capacity, uint32_t* draw_args,
                        uint32_t draw_vertices, cudaStream_t stream) {
    const uint32_t blocks = std::max<uint32_t>(1, std::min<uint32_t>((capacity + kCopyBlock - 1) / kCopyBlock, kMaxCopyBlocks));
    const void* src = live_buffer(live, source);
    if (!src) return cudaErrorInvalidValue;  // refused by the API layer before it gets here
    const uint32_t* count = live_count(live, source);  // the diffuse buffers have their own
    if (source == PBF_BUFFER_IDS) {
        copy_live_kernel<uint32_t><<<blocks, kCopyBlock, 0, stream>>>(static_cast<const uint32_t*>(src),
                                                                      static_cast<uint32_t*>(dst), 1u, count,
                                                                      capacity, draw_args, draw_vertices);
    } else {
        // Vec4 buffers, one float4 per particle or three (anisotropy).
        copy_live_kernel<float4><<<blocks, kCopyBlock, 0, stream>>>(
            static_cast<const float4*>(src), static_cast<float4*>(dst), buffer_element_bytes(source) / 16u, count,
            capacity, draw_args, draw_vertices);
    }
    return cudaGetLastError();
}

Status CudaInterop::record_event(void** out_event) {
    Status st = activate();
    if (!st.ok()) return st;
    if (!user_event_) {
        st = cuda_status("creating the world's event", cudaEventCreateWithFlags(&user_event_, cudaEventDisableTiming));
        if (!st.ok()) return st;
    }
    st = cuda_status("recording the world's event", cudaEventRecord(user_event_, stream()));
    if (st.ok()) *out_event = user_event_;
    return st;
}

Status CudaInterop::wait_event(void* event) {
    Status st = activate();
    if (!st.ok()) return st;
    return cuda_status("making the world's stream wait for the event",
                       cudaStreamWaitEvent(stream(), static_cast<cudaEvent_t>(event), 0));
}

void CudaInterop::batch_begin() {
    host_start_ = std::chrono::steady_clock::now();
    cudaEventRecord(copy_start_, stream());
}

void CudaInterop::batch_end() {
    copy_timed_ = cudaEventRecord(copy_stop_, stream()) == cudaSuccess;
    last_copy_host_ms_ =
        std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - host_start_).count();
}

}  // namespace pbf::cuda_interop
