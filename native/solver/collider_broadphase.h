// The host side of the colliders' broad phase (core/collider_grid.h): before each step (and
// whenever the colliders at rest change) the solver lists the colliders by coarse cells from
// their step bounds and uploads the lists with the shapes, so the step needs no host wait.
#pragma once
#include <cstdint>
#include <vector>

#include "../core/params.h"

namespace pbf {

// Up to this many colliders every query walks them all (no grid): the lists would cost more
// than the bounds tests they save.
constexpr uint32_t kLinearColliders = 8;
// A collider spanning more cells than this is walked by every query (a level's floor mesh).
constexpr uint32_t kMaxCellsPerCollider = 64;

// Sizes of a world's broad-phase buffers, fixed at creation from max_colliders; each list
// travels in one staging slot (cuda_exec.h: 256 KB): 32 entries per collider, 64K at most.
struct ColliderGridCapacity {
    uint32_t buckets = 0;  // a power of two; 0: the world never builds a grid
    uint32_t entries = 0;
};
ColliderGridCapacity collider_grid_capacity(uint32_t max_colliders);

// One build: grid's scalars (its pointers are the solver's to set), bucket_begin (buckets + 1
// offsets; empty when there is no grid) and entries.
struct ColliderGridLists {
    ColliderGrid grid;
    std::vector<uint32_t> bucket_begin;
    std::vector<uint32_t> entries;
};

// Lists shapes (their bounds already the step's) for queries reaching at most query_reach
// beyond a particle or its path (the kernel radius).
void build_collider_grid(const std::vector<Collider>& shapes, float query_reach, const ColliderGridCapacity& cap,
                         ColliderGridLists* out);

}  // namespace pbf
