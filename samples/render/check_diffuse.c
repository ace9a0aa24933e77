/* Compiled by CMake (check_c_source_compiles) to see whether libpbf has diffuse particles. */
#include "render_diffuse_api.h"

int main(void) {
    pbf_world_desc desc = pbf_world_desc_default();
    pbf_step_stats stats;
    diffuse_enable(&desc, 1);
    stats.diffuse_count = 0;
    return (int)diffuse_count(&stats) + (int)diffuse_buffer();
}
