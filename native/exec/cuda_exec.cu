// The CUDA executor (cuda_exec.cuh): memory, the radix sort, the reductions and the timers.
#include <cub/block/block_reduce.cuh>
#include <cub/device/device_radix_sort.cuh>
#include <cub/device/device_scan.cuh>

#include <algorithm>
#include <cstring>

#include "../common/transfers.h"
#include "cuda_exec.cuh"

namespace pbf {

void CudaExec::profile_enable(bool on) {
    if (on && !mark_event_[0])
        for (cudaEvent_t& e : mark_event_) record(cudaEventCreate(&e));
    profiling_ = on && mark_event_[0] != nullptr;
}

void CudaExec::profile_read(float* ms, int stages) {
    for (int k = 0; k < stages; ++k) ms[k] = 0.0f;
    if (marks_ == 0) return;
    record(cudaEventSynchronize(mark_event_[marks_ - 1]));
    for (int k = 0; k + 1 < marks_; ++k) {
        float t = 0.0f;
        record(cudaEventElapsedTime(&t, mark_event_[k], mark_event_[k + 1]));
        if (mark_stage_[k] < stages) ms[mark_stage_[k]] += t;
    }
}

CudaExec::~CudaExec() {
    for (cudaEvent_t e : mark_event_)
        if (e) cudaEventDestroy(e);
    if (sort_temp_) cudaFree(sort_temp_);
    if (scan_temp_) cudaFree(scan_temp_);
    for (int k = 0; k < kStagingSlots; ++k) {
        if (staging_event_[k]) cudaEventDestroy(staging_event_[k]);
        if (staging_[k]) cudaFreeHost(staging_[k]);
    }
    if (feedback_event_) cudaEventDestroy(feedback_event_);
    if (reduce_out_) cudaFree(reduce_out_);
    if (start_) cudaEventDestroy(start_);
    if (stop_) cudaEventDestroy(stop_);
    if (switch_event_) cudaEventDestroy(switch_event_);
    if (own_stream_) cudaStreamDestroy(own_stream_);
}

Status CudaExec::use_stream(void* stream) {
    cudaStream_t next = stream ? static_cast<cudaStream_t>(stream) : own_stream_;
    if (next == stream_) return Status{};
    // Errors here are the caller's (a stream of another device, say): reported, not recorded,
    // so the world stays usable on its current stream.
    cudaError_t e = cudaSuccess;
    if (!switch_event_) e = cudaEventCreateWithFlags(&switch_event_, cudaEventDisableTiming);
    if (e == cudaSuccess) e = cudaEventRecord(switch_event_, stream_);
    if (e == cudaSuccess) e = cudaStreamWaitEvent(next, switch_event_, 0);
    if (e != cudaSuccess) {
        (void)cudaGetLastError();
        return Status::error(PBF_ERROR_BACKEND, std::string("switching the world's CUDA stream: CUDA error ") +
                                                    cudaGetErrorName(e) + " (" + cudaGetErrorString(e) + ")");
    }
    stream_ = next;
    return Status{};
}

Status CudaExec::init(uint32_t capacity, uint32_t num_cells) {
    if (!cuda_device_available(device_))
        return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, "no usable CUDA device " + std::to_string(device_));
    record(cudaSetDevice(device_));
    cudaDeviceProp prop{};
    record(cudaGetDeviceProperties(&prop, device_));
    name_ = prop.name;
    record(cudaStreamCreateWithFlags(&own_stream_, cudaStreamNonBlocking));
    stream_ = own_stream_;
    record(cudaEventCreate(&start_));
    record(cudaEventCreate(&stop_));
    record(cudaEventCreateWithFlags(&feedback_event_, cudaEventDisableTiming));
    for (int k = 0; k < kStagingSlots; ++k) {
        record(cudaEventCreateWithFlags(&staging_event_[k], cudaEventDisableTiming));
        staging_[k] = alloc_host_bytes(kStagingBytes);
    }
    // Temporary storage for the largest sort this world can run, allocated once.
    sort_temp_bytes_ = sort_temp_bytes(capacity, UINT32_MAX);
    sort_temp_ = alloc_bytes(sort_temp_bytes_);
    reduce_out_ = static_cast<double*>(alloc_bytes(3 * sizeof(double)));
    (void)num_cells;
    return check("CUDA initialisation");
}

// cudaMalloc, counted; a failure is cleared so the context stays usable, and returned in *error.
void* CudaExec::malloc_counted(size_t bytes, cudaError_t* error) {
    void* p = nullptr;
    *error = cudaMalloc(&p, bytes == 0 ? 16 : bytes);
    if (*error != cudaSuccess) {
        (void)cudaGetLastError();
        return nullptr;
    }
    bytes_ += bytes;
    return p;
}

void* CudaExec::alloc_bytes(size_t bytes) {
    cudaError_t e;
    void* p = malloc_counted(bytes, &e);
    // Out of memory is reported by the caller, and poisons the world (first_error_).
    if (!p && first_error_ == cudaSuccess) first_error_ = e;
    return p;
}

void* CudaExec::try_alloc_bytes(size_t bytes) {
    cudaError_t e;
    void* p = malloc_counted(bytes, &e);
    if (!p) refused_alloc_ = e;  // refused, not poisoned: the world goes on
    return p;
}

void* CudaExec::alloc_host_bytes(size_t bytes) {
    void* p = nullptr;
    const cudaError_t e = cudaHostAlloc(&p, bytes == 0 ? 16 : bytes, cudaHostAllocMapped);
    if (e != cudaSuccess) {
        (void)cudaGetLastError();
        if (first_error_ == cudaSuccess) first_error_ = e;
        return nullptr;
    }
    return p;
}

void CudaExec::upload(void* dst, const void* src, size_t bytes) {
    if (bytes == 0) return;
    note_host_device_transfer(bytes);
    if (bytes > kStagingBytes || !staging_[staging_next_]) {  // larger than a slot: a copy that waits
        record(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyHostToDevice, stream_));
        record(cudaStreamSynchronize(stream_));
        return;
    }
    const int slot = staging_next_;
    staging_next_ = (staging_next_ + 1) % kStagingSlots;
    // Waits only if the host has queued kStagingSlots uploads the GPU has not reached yet.
    record(cudaEventSynchronize(staging_event_[slot]));
    std::memcpy(staging_[slot], src, bytes);
    record(cudaMemcpyAsync(dst, staging_[slot], bytes, cudaMemcpyHostToDevice, stream_));
    record(cudaEventRecord(staging_event_[slot], stream_));
}

bool CudaExec::feedback_ready() {
    const cudaError_t e = cudaEventQuery(feedback_event_);
    if (e == cudaErrorNotReady) {
        (void)cudaGetLastError();  // not an error: the step is still running
        return false;
    }
    record(e);
    return e == cudaSuccess;
}

void CudaExec::release(void* p) {
    if (p) cudaFree(p);
}

void CudaExec::download(void* dst, const void* src, size_t bytes) {
    if (bytes) {
        record(cudaMemcpyAsync(dst, src, bytes, cudaMemcpyDeviceToHost, stream_));
        note_host_device_transfer(bytes);
    }
    record(cudaStreamSynchronize(stream_));
}

Status CudaExec::reserve_scan(uint32_t max_n) {
    scan_temp_bytes_ = scan_temp_bytes(max_n);
    scan_temp_ = alloc_bytes(scan_temp_bytes_);
    if (!scan_temp_) return Status::error(PBF_ERROR_OUT_OF_MEMORY, "cannot allocate the scan's temporary storage");
    return check("scan storage");
}

void CudaExec::exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n) {
    exclusive_scan(in, out, n, scan_temp_, scan_temp_bytes_);
}

size_t CudaExec::scan_temp_bytes(uint32_t n) {
    size_t bytes = 0;
    record(cub::DeviceScan::ExclusiveSum(nullptr, bytes, static_cast<const uint32_t*>(nullptr),
                                         static_cast<uint32_t*>(nullptr), int(n), stream_));
    return bytes + 16;
}

void CudaExec::exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n, void* temp, size_t temp_bytes) {
    record(cub::DeviceScan::ExclusiveSum(temp, temp_bytes, in, out, int(n), stream_));
}

static int bits_for(uint32_t max_key) {
    int bits = 1;
    while (bits < 32 && (uint64_t(1) << bits) <= max_key) ++bits;
    return bits;
}

void CudaExec::sort_pairs(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t max_key, int* key_sel,
                          int* value_sel) {
    sort_pairs(keys, values, n, max_key, key_sel, value_sel, sort_temp_, sort_temp_bytes_);
}

size_t CudaExec::sort_temp_bytes(uint32_t n, uint32_t max_key) {
    size_t bytes = 0;
    cub::DoubleBuffer<uint32_t> k(nullptr, nullptr), v(nullptr, nullptr);
    record(cub::DeviceRadixSort::SortPairs(nullptr, bytes, k, v, int(n), 0, bits_for(max_key), stream_));
    return bytes + 16;
}

void CudaExec::sort_pairs(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t max_key, int* key_sel,
                          int* value_sel, void* temp, size_t temp_bytes) {
    cub::DoubleBuffer<uint32_t> k(keys[0], keys[1]), v(values[0], values[1]);
    if (n > 0) record(cub::DeviceRadixSort::SortPairs(temp, temp_bytes, k, v, int(n), 0, bits_for(max_key), stream_));
    *key_sel = k.selector;
    *value_sel = v.selector;
}

namespace {
constexpr int kReduceBlock = 256;
__global__ void reduce_stats_kernel(WorldConstants s, const float* density, const Vec4* velocities, uint32_t n,
                                    double* out) {
    double err = 0.0, ke = 0.0;
    float max_err = 0.0f;
    for (uint32_t i = blockIdx.x * blockDim.x + threadIdx.x; i < n; i += gridDim.x * blockDim.x) {
        const ParticleStats ps = particle_stats(s, density[i], velocities[i]);
        err += ps.compressive_error;
        ke += ps.kinetic_energy;
        max_err = fmaxf(max_err, ps.compressive_error);
    }
    using Reduce = cub::BlockReduce<double, kReduceBlock>;
    using ReduceF = cub::BlockReduce<float, kReduceBlock>;
    __shared__ typename Reduce::TempStorage t0;
    __shared__ typename Reduce::TempStorage t1;
    __shared__ typename ReduceF::TempStorage t2;
    const double block_err = Reduce(t0).Sum(err);
    const double block_ke = Reduce(t1).Sum(ke);
    const float block_max = ReduceF(t2).Reduce(max_err, [](float a, float b) { return fmaxf(a, b); });
    if (threadIdx.x == 0) {
        atomicAdd(&out[0], block_err);
        atomicAdd(&out[1], block_ke);
        // Non-negative floats order like their bit patterns.
        atomicMax(reinterpret_cast<unsigned int*>(&out[2]), __float_as_uint(block_max));
    }
}
}  // namespace

void CudaExec::reduce_stats(const WorldConstants& s, const float* density, const Vec4* velocities, uint32_t n,
                            StatsReadback* out) {
    record(cudaMemsetAsync(reduce_out_, 0, 3 * sizeof(double), stream_));
    if (n > 0) {
        const uint32_t blocks = std::min<uint32_t>((n + kReduceBlock - 1) / kReduceBlock, 1024);
        reduce_stats_kernel<<<blocks, kReduceBlock, 0, stream_>>>(s, density, velocities, n, reduce_out_);
        record(cudaGetLastError());
    }
    double host[3] = {0, 0, 0};
    download(host, reduce_out_, sizeof host);
    out->error_sum = host[0];
    out->kinetic_energy = host[1];
    float max_err;
    std::memcpy(&max_err, &host[2], sizeof(float));
    out->error_max = max_err;
}

namespace {
__global__ void sum_error_kernel(WorldConstants s, const float* density, const uint32_t* count, uint32_t n, float* out) {
    const uint32_t live = min(n, *count);
    float sum = 0.0f;
    for (uint32_t i = blockIdx.x * blockDim.x + threadIdx.x; i < live; i += gridDim.x * blockDim.x)
        sum += fmaxf(density[i] * s.inv_rest_density - 1.0f, 0.0f);
    using Reduce = cub::BlockReduce<float, kReduceBlock>;
    __shared__ typename Reduce::TempStorage temp;
    const float block_sum = Reduce(temp).Sum(sum);
    if (threadIdx.x == 0 && block_sum != 0.0f) atomicAdd(out, block_sum);
}
}  // namespace

void CudaExec::sum_compressive_error(const WorldConstants& s, const float* density, const uint32_t* count, uint32_t n,
                                     float* out) {
    if (n == 0) return;
    const uint32_t blocks = std::min<uint32_t>((n + kReduceBlock - 1) / kReduceBlock, 264);
    sum_error_kernel<<<blocks, kReduceBlock, 0, stream_>>>(s, density, count, n, out);
    record(cudaGetLastError());
}

namespace {
__global__ void feedback_kernel(HeightFrame frame, const Vec4* positions, const Vec4* velocities,
                                const uint32_t* count, uint32_t n, FeedbackBits* out) {
    const uint32_t live = min(n, *count);
    FeedbackSample m{0.0f, 0.0f, 0.0f};
    for (uint32_t i = blockIdx.x * blockDim.x + threadIdx.x; i < live; i += gridDim.x * blockDim.x) {
        const FeedbackSample f = feedback_sample(frame, positions[i], velocities[i]);
        m = FeedbackSample{fmaxf(m.speed, f.speed), fmaxf(m.top, f.top), fmaxf(m.below, f.below)};
    }
    using Reduce = cub::BlockReduce<float, kReduceBlock>;
    __shared__ typename Reduce::TempStorage temp;
    const auto fmax_op = [](float a, float b) { return fmaxf(a, b); };
    const float speed = Reduce(temp).Reduce(m.speed, fmax_op);
    __syncthreads();  // temp is reused
    const float top = Reduce(temp).Reduce(m.top, fmax_op);
    __syncthreads();
    const float below = Reduce(temp).Reduce(m.below, fmax_op);
    if (threadIdx.x != 0) return;
    // Non-negative floats order like their bits: an integer max is a float max.
    if (speed > 0.0f) atomicMax(&out->speed, __float_as_uint(speed));
    if (top > 0.0f) atomicMax(&out->top, __float_as_uint(top));
    if (below > 0.0f) atomicMax(&out->below, __float_as_uint(below));
}
}  // namespace

void CudaExec::reduce_feedback(const HeightFrame& frame, const Vec4* positions, const Vec4* velocities,
                               const uint32_t* count, uint32_t n, FeedbackBits* out) {
    if (n == 0) return;
    const uint32_t blocks = std::min<uint32_t>((n + kReduceBlock - 1) / kReduceBlock, 264);
    feedback_kernel<<<blocks, kReduceBlock, 0, stream_>>>(frame, positions, velocities, count, n, out);
    record(cudaGetLastError());
}

float CudaExec::timer_ms() {
    if (!timed_) return 0.0f;
    record(cudaEventSynchronize(stop_));
    float ms = 0.0f;
    record(cudaEventElapsedTime(&ms, start_, stop_));
    return ms;
}

Status CudaExec::check(const char* what) const {
    if (first_error_ == cudaSuccess) return Status{};
    const pbf_result code =
        first_error_ == cudaErrorMemoryAllocation ? PBF_ERROR_OUT_OF_MEMORY : PBF_ERROR_BACKEND;
    return Status::error(code, std::string(what) + ": CUDA error " + cudaGetErrorName(first_error_) + " (" +
                                   cudaGetErrorString(first_error_) + ")");
}

bool cuda_device_available(int32_t device) {
    int count = 0;
    if (cudaGetDeviceCount(&count) != cudaSuccess) {
        (void)cudaGetLastError();
        return false;
    }
    return device >= 0 && device < count;
}

}  // namespace pbf
