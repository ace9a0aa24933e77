/* The diffuse-particle (foam, spray, bubbles) calls this sample uses, in one place: CMake
 * compiles this header (check_diffuse.c) against include/pbf_c_api.h and defines
 * PBF_RENDER_HAVE_DIFFUSE only where it compiles, so the sample builds against a libpbf without
 * diffuse particles and draws them once the library has them. */
#ifndef PBF_RENDER_DIFFUSE_API_H
#define PBF_RENDER_DIFFUSE_API_H

#include "pbf_c_api.h"

/* Asks the world for up to `capacity` diffuse particles. */
static inline void diffuse_enable(pbf_world_desc* desc, uint32_t capacity) { desc->diffuse.max_diffuse = capacity; }
/* Live diffuse particles after the last step. */
static inline uint32_t diffuse_count(const pbf_step_stats* stats) { return stats->diffuse_count; }
/* float4 per particle: x, y, z, kind (0 spray, 1 foam, 2 bubble). */
static inline pbf_buffer diffuse_buffer(void) { return PBF_BUFFER_DIFFUSE_POSITIONS; }

#endif /* PBF_RENDER_DIFFUSE_API_H */
