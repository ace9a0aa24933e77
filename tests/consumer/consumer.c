/* An installed libpbf, used the way a game or engine would: include the header, link the
 * library, create a world, step it, destroy it. Built by scripts/check_install.sh twice, with
 * find_package(pbf) (CMakeLists.txt here) and with pkg-config; prints "OK" on success. */
#include <stdio.h>

#include <pbf_c_api.h>

#define CHECK(call)                                                                                         \
    do {                                                                                                    \
        pbf_result r_ = (call);                                                                             \
        if (r_ != PBF_OK) {                                                                                 \
            fprintf(stderr, "%s failed: %s: %s\n", #call, pbf_result_string(r_), pbf_last_error_message()); \
            return 1;                                                                                       \
        }                                                                                                   \
    } while (0)

int main(void) {
    const uint32_t version = pbf_get_version();
    if (PBF_VERSION_GET_MAJOR(version) != PBF_VERSION_MAJOR) {
        fprintf(stderr, "library major %u, header major %u\n", (unsigned)PBF_VERSION_GET_MAJOR(version),
                (unsigned)PBF_VERSION_MAJOR);
        return 1;
    }

    pbf_world_desc desc = pbf_world_desc_default();
    desc.max_particles = 4096;
    desc.backend = PBF_BACKEND_CPU;
    pbf_world_id world;
    CHECK(pbf_world_create(&desc, &world));

    pbf_block_desc block = pbf_block_desc_default();
    block.box_min[0] = -0.2f;
    block.box_min[1] = 0.0f;
    block.box_min[2] = -0.2f;
    block.box_max[0] = 0.2f;
    block.box_max[1] = 0.3f;
    block.box_max[2] = 0.2f;
    uint32_t emitted = 0;
    CHECK(pbf_world_emit_block(world, &block, &emitted));
    for (int i = 0; i < 10; ++i) CHECK(pbf_world_step(world, 1.0f / 60.0f));

    pbf_step_stats stats = {0};
    stats.struct_size = sizeof stats;
    CHECK(pbf_world_get_stats(world, &stats));
    CHECK(pbf_world_destroy(world));
    if (emitted == 0 || stats.particle_count != emitted || stats.step_index != 10) {
        fprintf(stderr, "unexpected world state: %u emitted, %u particles, step %llu\n", emitted, stats.particle_count,
                (unsigned long long)stats.step_index);
        return 1;
    }
    printf("OK: libpbf %u.%u.%u, %u particles, %llu steps\n", (unsigned)PBF_VERSION_GET_MAJOR(version),
           (unsigned)((version >> 12) & 0x3FFu), (unsigned)(version & 0xFFFu), stats.particle_count,
           (unsigned long long)stats.step_index);
    return 0;
}
