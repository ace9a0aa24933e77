// The CUDA executor (cuda_exec.h): memory, launches, the radix sort, the scan, the reductions and
// the timers, all through the driver's entry points on the world's stream.
#include "cuda_exec.h"

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "../common/transfers.h"

namespace pbf {
namespace {

CUdeviceptr dptr(const void* p) { return CUdeviceptr(reinterpret_cast<uintptr_t>(p)); }

uint32_t tiles_of(uint64_t n) { return uint32_t((n + kCudaScanTile - 1) / kCudaScanTile); }

int bits_for(uint32_t max_key) {
    int bits = 1;
    while (bits < 32 && (uint64_t(1) << bits) <= max_key) ++bits;
    return bits;
}

// The sort's temporary storage: each tile's digit counts (scanned in place, digit by digit),
// then the digits' totals.
struct SortLayout {
    uint32_t tiles, counts;
    size_t bytes() const { return (size_t(counts) + kCudaRadixDigits + 4) * sizeof(uint32_t); }
};
SortLayout sort_layout(uint32_t n) {
    SortLayout l;
    l.tiles = std::max(1u, tiles_of(n));
    l.counts = l.tiles * uint32_t(kCudaRadixDigits);
    return l;
}

}  // namespace

CudaExec::~CudaExec() {
    if (!cu_) return;
    cu_->cuCtxSetCurrent(k_->context);
    if (own_stream_) cu_->cuStreamSynchronize(own_stream_);
    graph_.clear();
    for (CUevent e : mark_event_)
        if (e) cu_->cuEventDestroy(e);
    release(grid_scan_temp_);
    release(scan_temp_);
    release(reduce_out_);
    for (int k = 0; k < kStagingSlots; ++k) {
        if (staging_event_[k]) cu_->cuEventDestroy(staging_event_[k]);
        if (staging_[k]) cu_->cuMemFreeHost(staging_[k]);
    }
    for (CUevent e : {feedback_event_, start_, stop_, switch_event_})
        if (e) cu_->cuEventDestroy(e);
    if (own_stream_) cu_->cuStreamDestroy(own_stream_);
    if (context_retained_) cu_->cuDevicePrimaryCtxRelease(k_->device);
}

Status CudaExec::init(uint32_t, uint32_t num_cells) {
    CudaAvailability why;
    k_ = cuda::kernels(device_, &why);
    if (!k_) return Status::error(PBF_ERROR_BACKEND_UNAVAILABLE, why.message);
    cu_ = cuda::driver();
    name_ = k_->device_name;
    // The world holds its own reference to the context it allocates in.
    CUcontext context = nullptr;
    record(cu_->cuDevicePrimaryCtxRetain(&context, k_->device));
    context_retained_ = first_error_ == CUDA_SUCCESS;
    activate();
    record(cu_->cuStreamCreate(&own_stream_, CU_STREAM_NON_BLOCKING));
    stream_ = own_stream_;
    // A step's launches go as one graph unless PBF_CUDA_GRAPHS=0 (a diagnostic: the same step
    // launch by launch, to compare with).
    const char* graphs = std::getenv("PBF_CUDA_GRAPHS");
    graph_.init(cu_, k_->context, !(graphs && std::strcmp(graphs, "0") == 0));
    record(cu_->cuEventCreate(&start_, CU_EVENT_DEFAULT));
    record(cu_->cuEventCreate(&stop_, CU_EVENT_DEFAULT));
    record(cu_->cuEventCreate(&feedback_event_, CU_EVENT_DISABLE_TIMING));
    for (int k = 0; k < kStagingSlots; ++k) {
        record(cu_->cuEventCreate(&staging_event_[k], CU_EVENT_DISABLE_TIMING));
        staging_[k] = alloc_host_bytes(kStagingBytes);
    }
    // The scan of the grid sort's counters (the counters are the solver's: sort_cells).
    grid_scan_temp_bytes_ = scan_temp_bytes(num_cells + 2);
    grid_scan_temp_ = alloc_bytes(grid_scan_temp_bytes_);
    reduce_out_ = static_cast<double*>(alloc_bytes(3 * sizeof(double)));
    return check("CUDA initialisation");
}

void CudaExec::launch_args(CUfunction f, uint32_t blocks, uint32_t threads, const cuda::KernelArg* args,
                           uint32_t count) {
    if (graph_.open()) return graph_.add_kernel(f, blocks, threads, args, count);
    void* params[8];
    for (uint32_t k = 0; k < count && k < 8; ++k) params[k] = const_cast<void*>(args[k].value);
    record(count <= 8 ? cu_->cuLaunchKernel(f, blocks, 1, 1, threads, 1, 1, 0, stream_, params, nullptr)
                      : CUDA_ERROR_INVALID_VALUE);
}

void CudaExec::launch_op(uint32_t index, uint32_t n, const void* op, uint32_t op_bytes) {
    const cuda::KernelArg args[] = {{&n, uint32_t(sizeof n)}, {op, op_bytes}};
    launch_args(k_->op[index], (n + kBlock - 1) / kBlock, kBlock, args, 2);
}

Status CudaExec::use_stream(void* stream) {
    CUstream next = stream ? static_cast<CUstream>(stream) : own_stream_;
    if (next == stream_) return Status{};
    flush_recording();
    // Errors here are the caller's (a stream of another device, say): reported, not recorded,
    // so the world stays usable on its current stream.
    CUresult e = CUDA_SUCCESS;
    if (!switch_event_) e = cu_->cuEventCreate(&switch_event_, CU_EVENT_DISABLE_TIMING);
    if (e == CUDA_SUCCESS) e = cu_->cuEventRecord(switch_event_, stream_);
    if (e == CUDA_SUCCESS) e = cu_->cuStreamWaitEvent(next, switch_event_, 0);
    if (e != CUDA_SUCCESS)
        return Status::error(PBF_ERROR_BACKEND, "switching the world's CUDA stream: " + cuda::error_text(e));
    stream_ = next;
    return Status{};
}

// ---- memory -----------------------------------------------------------------------------------
void* CudaExec::malloc_counted(size_t bytes, CUresult* error) {
    CUdeviceptr p = 0;
    *error = cu_->cuMemAlloc(&p, bytes == 0 ? 16 : bytes);
    if (*error != CUDA_SUCCESS) return nullptr;
    bytes_ += bytes;
    return reinterpret_cast<void*>(uintptr_t(p));
}

void* CudaExec::alloc_bytes(size_t bytes) {
    CUresult e;
    void* p = malloc_counted(bytes, &e);
    // Out of memory is reported by the caller, and poisons the world (first_error_).
    if (!p) record(e);
    return p;
}

void* CudaExec::try_alloc_bytes(size_t bytes) {
    CUresult e;
    void* p = malloc_counted(bytes, &e);
    if (!p) refused_alloc_ = e;  // refused, not poisoned: the world goes on
    return p;
}

void* CudaExec::alloc_host_bytes(size_t bytes) {
    void* p = nullptr;
    const CUresult e =
        cu_->cuMemHostAlloc(&p, bytes == 0 ? 16 : bytes, CU_MEMHOSTALLOC_DEVICEMAP | CU_MEMHOSTALLOC_PORTABLE);
    if (e != CUDA_SUCCESS) {
        record(e);
        return nullptr;
    }
    return p;
}

void CudaExec::release_host_visible(void* p) {
    if (p && cu_) cu_->cuMemFreeHost(p);
}

void CudaExec::release(void* p) {
    // The driver's free waits for the work queued on the memory to finish.
    if (p && cu_) cu_->cuMemFree(dptr(p));
}

void CudaExec::zero(void* p, size_t bytes) {
    if (!bytes) return;
    if (graph_.open()) return graph_.add_memset(dptr(p), bytes);
    record(cu_->cuMemsetD8Async(dptr(p), 0, bytes, stream_));
}

void CudaExec::upload(void* dst, const void* src, size_t bytes) {
    if (bytes == 0) return;
    flush_recording();
    note_host_device_transfer(bytes);
    if (bytes > kStagingBytes || !staging_[staging_next_]) {  // larger than a slot: a copy that waits
        record(cu_->cuMemcpyHtoDAsync(dptr(dst), src, bytes, stream_));
        record(cu_->cuStreamSynchronize(stream_));
        return;
    }
    const int slot = staging_next_;
    staging_next_ = (staging_next_ + 1) % kStagingSlots;
    // Waits only if the host has queued kStagingSlots uploads the GPU has not reached yet.
    record(cu_->cuEventSynchronize(staging_event_[slot]));
    std::memcpy(staging_[slot], src, bytes);
    record(cu_->cuMemcpyHtoDAsync(dptr(dst), staging_[slot], bytes, stream_));
    record(cu_->cuEventRecord(staging_event_[slot], stream_));
}

void CudaExec::download(void* dst, const void* src, size_t bytes) {
    flush_recording();
    if (bytes) {
        record(cu_->cuMemcpyDtoHAsync(dst, dptr(src), bytes, stream_));
        note_host_device_transfer(bytes);
    }
    record(cu_->cuStreamSynchronize(stream_));
}

bool CudaExec::feedback_ready() {
    const CUresult e = cu_->cuEventQuery(feedback_event_);
    if (e == CUDA_ERROR_NOT_READY) return false;  // not an error: the step is still running
    record(e);
    return e == CUDA_SUCCESS;
}

// ---- scan and sort ----------------------------------------------------------------------------
size_t CudaExec::scan_temp_bytes(uint32_t n) const { return (size_t(tiles_of(n)) + 4) * sizeof(uint32_t); }

Status CudaExec::reserve_scan(uint32_t max_n) {
    scan_temp_bytes_ = scan_temp_bytes(max_n);
    scan_temp_ = alloc_bytes(scan_temp_bytes_);
    if (!scan_temp_) return Status::error(PBF_ERROR_OUT_OF_MEMORY, "cannot allocate the scan's temporary storage");
    return check("scan storage");
}

void CudaExec::exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n) {
    exclusive_scan(in, out, n, scan_temp_, scan_temp_bytes_);
}

void CudaExec::exclusive_scan(const uint32_t* in, uint32_t* out, uint32_t n, void* temp, size_t temp_bytes) {
    if (n == 0) return;
    uint32_t tiles = tiles_of(n);
    if (temp_bytes < scan_temp_bytes(n)) return record(CUDA_ERROR_INVALID_VALUE);
    uint32_t* partials = static_cast<uint32_t*>(temp);
    launch(k_->scan_reduce, tiles, kCudaScanBlock, in, n, partials);
    launch(k_->scan_spine, 1, kCudaScanBlock, partials, tiles);
    launch(k_->scan_downsweep, tiles, kCudaScanBlock, in, out, n, static_cast<const uint32_t*>(partials));
}

size_t CudaExec::sort_temp_bytes(uint32_t n, uint32_t) const { return sort_layout(n).bytes(); }

void CudaExec::sort_cells(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t num_cells, uint32_t* counters,
                          int* key_sel, int* value_sel) {
    *key_sel = *value_sel = 1;
    if (n == 0) return;
    uint32_t words = num_cells + 2;
    zero(counters, size_t(words) * sizeof(uint32_t));
    const uint32_t blocks = (n + kBlock - 1) / kBlock;
    launch(k_->count_keys, blocks, kBlock, keys[0], n, counters);
    exclusive_scan(counters, counters, words, grid_scan_temp_, grid_scan_temp_bytes_);
    launch(k_->scatter_keys, blocks, kBlock, keys[0], values[0], keys[1], values[1], n, counters);
    if (num_cells > 0)
        launch(k_->order_keys, (num_cells + kBlock - 1) / kBlock, kBlock, counters, num_cells, values[1]);
}

void CudaExec::sort_pairs(uint32_t* keys[2], uint32_t* values[2], uint32_t n, uint32_t max_key, int* key_sel,
                          int* value_sel, void* temp, size_t temp_bytes) {
    int sel = 0;
    const SortLayout l = sort_layout(n);
    if (n > 0 && temp_bytes >= l.bytes()) {
        uint32_t* counts = static_cast<uint32_t*>(temp);
        uint32_t* totals = counts + l.counts;
        uint32_t tiles = l.tiles;
        for (uint32_t shift = 0; shift < uint32_t(bits_for(max_key)); shift += kCudaRadixBits) {
            launch(k_->radix_upsweep, tiles, kCudaScanBlock, keys[sel], n, shift, counts);
            launch(k_->radix_scan_rows, kCudaRadixDigits, kCudaScanBlock, counts, tiles, totals);
            launch(k_->radix_downsweep, tiles, kCudaScanBlock, keys[sel], values[sel], keys[1 - sel], values[1 - sel],
                   n, shift, counts, totals);
            sel = 1 - sel;
        }
    } else if (n > 0) {
        record(CUDA_ERROR_INVALID_VALUE);
    }
    *key_sel = *value_sel = sel;
}

// ---- reductions -------------------------------------------------------------------------------
void CudaExec::reduce_stats(const WorldConstants& s, const float* density, const Vec4* velocities, uint32_t n,
                            StatsReadback* out) {
    zero(reduce_out_, 3 * sizeof(double));
    if (n > 0) {
        const uint32_t blocks = std::min<uint32_t>((n + kCudaReduceBlock - 1) / kCudaReduceBlock, 1024);
        launch(k_->reduce_stats, blocks, kCudaReduceBlock, s, density, velocities, n, reduce_out_);
    }
    double host[3] = {0, 0, 0};
    download(host, reduce_out_, sizeof host);
    out->error_sum = host[0];
    out->kinetic_energy = host[1];
    float max_err;
    std::memcpy(&max_err, &host[2], sizeof(float));
    out->error_max = max_err;
}

void CudaExec::sum_compressive_error(const WorldConstants& s, const float* density, const uint32_t* count, uint32_t n,
                                     float* out) {
    if (n == 0) return;
    const uint32_t blocks = std::min<uint32_t>((n + kCudaReduceBlock - 1) / kCudaReduceBlock, 264);
    launch(k_->sum_error, blocks, kCudaReduceBlock, s, density, count, n, out);
}

void CudaExec::reduce_feedback(const HeightFrame& frame, const Vec4* positions, const Vec4* velocities,
                               const uint32_t* count, uint32_t n, FeedbackBits* out) {
    if (n == 0) return;
    const uint32_t blocks = std::min<uint32_t>((n + kCudaReduceBlock - 1) / kCudaReduceBlock, 264);
    launch(k_->feedback, blocks, kCudaReduceBlock, frame, positions, velocities, count, n, out);
}

// ---- timing and errors ------------------------------------------------------------------------
float CudaExec::timer_ms() {
    if (!timed_) return 0.0f;
    record(cu_->cuEventSynchronize(stop_));
    float ms = 0.0f;
    record(cu_->cuEventElapsedTime(&ms, start_, stop_));
    return ms;
}

void CudaExec::profile_enable(bool on) {
    if (on && !mark_event_[0])
        for (CUevent& e : mark_event_) record(cu_->cuEventCreate(&e, CU_EVENT_DEFAULT));
    profiling_ = on && mark_event_[0] != nullptr;
}

void CudaExec::profile_read(float* ms, int stages) {
    for (int k = 0; k < stages; ++k) ms[k] = 0.0f;
    if (marks_ == 0) return;
    record(cu_->cuEventSynchronize(mark_event_[marks_ - 1]));
    for (int k = 0; k + 1 < marks_; ++k) {
        float t = 0.0f;
        record(cu_->cuEventElapsedTime(&t, mark_event_[k], mark_event_[k + 1]));
        if (mark_stage_[k] < stages) ms[mark_stage_[k]] += t;
    }
}

Status CudaExec::check(const char* what) const {
    if (first_error_ == CUDA_SUCCESS) return Status{};
    const pbf_result code = first_error_ == CUDA_ERROR_OUT_OF_MEMORY ? PBF_ERROR_OUT_OF_MEMORY : PBF_ERROR_BACKEND;
    return Status::error(code, std::string(what) + ": " + cuda::error_text(first_error_));
}

}  // namespace pbf
