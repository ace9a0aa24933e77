// A solver's particle and grid arrays: the step's working memory, whose roles (x, v, x*, spare;
// the sort's keys and values) the step rotates, and how a solver's parts allocate, clear and
// free their memory.
#pragma once
#include <cstddef>
#include <cstdint>

#include "../core/grid.h"
#include "../core/step_ops.h"
#include "../core/vec.h"

namespace pbf {

// A solver's allocations at creation: every one is tried, and ok says whether all succeeded
// (the error then names the executor's last failure).
template <class Exec>
struct Allocations {
    Exec& exec;
    bool ok = true;
    template <class T>
    void operator()(T*& p, size_t count) {
        p = exec.template alloc<T>(count);
        ok = ok && p != nullptr;
    }
};

struct ParticleBuffers {
    // n particles over a grid of num_cells cells.
    template <class Exec>
    void allocate(Allocations<Exec>& alloc, size_t n, uint32_t num_cells) {
        // Four Vec4 arrays in rotating roles (x, v, x*, spare), one id array (its gather target
        // is the sort's free value buffer), the sort's keys and values, ρ, the neighbour masks.
        for (Vec4*& b : vec4_) alloc(b, n);
        pos_ = vec4_[0];
        vel_ = vec4_[1];
        pred_ = vec4_[2];
        spare_ = vec4_[3];
        alloc(ids_, n);
        alloc(materials_, n);  // 1 B per particle; the sort's gather borrows a free key buffer
        for (int b = 0; b < 2; ++b) {
            alloc(keys_[b], n);
            alloc(order_[b], n);
        }
        alloc(masks_, n * kMaskRows);
        alloc(density_, n);
        alloc(cell_begin_, size_t(num_cells) + 2);  // + 1: the grid sort's counters (sort_cells)
        alloc(counters_, 1);
    }

    // Unused slots hold finite data so passes that touch them (they never affect live
    // particles) compute nothing undefined; all counters start at zero.
    template <class Exec>
    void zero(Exec& exec, size_t n, uint32_t num_cells) {
        for (Vec4* b : vec4_) exec.zero(b, n * sizeof(Vec4));
        exec.zero(ids_, n * sizeof(uint32_t));
        exec.zero(materials_, n);
        for (int b = 0; b < 2; ++b) {
            exec.zero(keys_[b], n * sizeof(uint32_t));
            exec.zero(order_[b], n * sizeof(uint32_t));
        }
        exec.zero(masks_, n * kMaskRows * sizeof(uint32_t));
        exec.zero(density_, n * sizeof(float));
        exec.zero(cell_begin_, (size_t(num_cells) + 2) * sizeof(uint32_t));
        exec.zero(counters_, sizeof(DeviceCounters));
    }

    template <class Exec>
    void release(Exec& exec) {
        // The role pointers (pos_, ids_, ...) alias the arrays: release each array once.
        for (Vec4* b : vec4_) exec.release(b);
        exec.release(ids_);
        exec.release(materials_);
        for (int b = 0; b < 2; ++b) {
            exec.release(keys_[b]);
            exec.release(order_[b]);
        }
        exec.release(masks_);
        exec.release(density_);
        exec.release(cell_begin_);
        exec.release(counters_);
    }

    Vec4* vec4_[4] = {};  // the allocations; the roles below point into them and rotate
    Vec4* pos_ = nullptr;
    Vec4* vel_ = nullptr;
    Vec4* pred_ = nullptr;
    Vec4* spare_ = nullptr;
    uint32_t* ids_ = nullptr;       // rotates with the sort's value buffers
    uint8_t* materials_ = nullptr;  // each particle's material slot (fixed: the gather copies back)
    uint32_t* keys_[2] = {};
    uint32_t* order_[2] = {};
    const uint32_t* sorted_keys_ = nullptr;  // the cell of each particle at the last grid build
    uint32_t* masks_ = nullptr;              // kMaskRows x capacity neighbour masks
    float* denominator_ = nullptr;           // λ's Σ|∇C|² + ε per particle (aliases a sort buffer)
    float* density_ = nullptr;
    uint32_t* cell_begin_ = nullptr;
    DeviceCounters* counters_ = nullptr;
};

}  // namespace pbf
