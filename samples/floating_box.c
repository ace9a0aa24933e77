/* Two-way coupling, the engine's loop: a crate of 500 kg/m^3 dropped into a pool. The library
 * moves the water; this program plays the engine: after each step it reads the force the water
 * exerted on the crate (pbf_collider_get_force), integrates the crate's body and sets its next
 * pose (pbf_collider_set_target_pose). C99, public header only.
 *
 *   floating_box [steps=300]      PBF_BACKEND=cpu|cuda overrides the backend.
 * Prints the crate's height and the force every 30 steps; exits non-zero on any libpbf error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pbf_c_api.h"

#define CHECK(call)                                                                            \
    do {                                                                                       \
        pbf_result r_ = (call);                                                                \
        if (r_ != PBF_OK) {                                                                    \
            fprintf(stderr, "floating_box: %s failed: %s\n", #call, pbf_last_error_message()); \
            return 1;                                                                          \
        }                                                                                      \
    } while (0)

int main(int argc, char** argv) {
    const long steps = argc > 1 ? atol(argv[1]) : 300;
    const float dt = 1.0f / 60.0f, g = 9.81f;
    if (steps < 1) {
        fprintf(stderr, "usage: floating_box [steps>=1]\n");
        return 2;
    }
    pbf_world_desc desc = pbf_world_desc_default();
    const char* backend = getenv("PBF_BACKEND");
    if (backend && strcmp(backend, "cpu") == 0) desc.backend = PBF_BACKEND_CPU;
    if (backend && strcmp(backend, "cuda") == 0) desc.backend = PBF_BACKEND_CUDA;
    desc.particle_radius = 0.02f;
    desc.max_particles = 16384;
    desc.max_colliders = 8;
    const float lo[3] = {0, 0, 0}, hi[3] = {0.72f, 0.8f, 0.72f};
    memcpy(desc.domain_min, lo, sizeof lo);
    memcpy(desc.domain_max, hi, sizeof hi);
    pbf_world_id world;
    CHECK(pbf_world_create(&desc, &world));

    /* A pool 0.36 m deep. */
    pbf_block_desc water = pbf_block_desc_default();
    const float water_hi[3] = {0.72f, 0.36f, 0.72f};
    memcpy(water.box_max, water_hi, sizeof water_hi);
    CHECK(pbf_world_emit_block(world, &water, NULL));

    /* The crate: a 0.24 m cube just above the water, moved by this program (kinematic) and
     * told the water's force (dynamic). */
    const float half = 0.12f, density = 500.0f;
    const float mass = density * 8.0f * half * half * half;
    pbf_collider_desc crate_desc = pbf_collider_desc_default();
    crate_desc.shape = PBF_SHAPE_BOX;
    crate_desc.motion = PBF_MOTION_KINEMATIC;
    crate_desc.dynamic = 1;
    crate_desc.position[0] = crate_desc.position[2] = 0.36f;
    crate_desc.position[1] = 0.37f + half;
    crate_desc.half_extents[0] = crate_desc.half_extents[1] = crate_desc.half_extents[2] = half;
    pbf_collider_id crate;
    CHECK(pbf_world_create_collider(world, &crate_desc, &crate));

    /* The engine's loop: step the water, read the force of that step (this waits for it),
     * integrate the body (semi-implicit Euler, vertical motion only here), set its next pose. */
    float y = crate_desc.position[1], vy = 0.0f;
    for (long step = 0; step < steps; ++step) {
        CHECK(pbf_world_step(world, dt));
        pbf_collider_force f;
        CHECK(pbf_collider_get_force(world, crate, &f));
        vy += (f.force[1] / mass - g) * dt;
        y += vy * dt;
        const float position[3] = {0.36f, y, 0.36f}, rotation[4] = {0, 0, 0, 1};
        CHECK(pbf_collider_set_target_pose(world, crate, position, rotation));
        if (step % 30 == 29)
            printf("t %.2f s  crate bottom %.3f m  water force %.1f N (weight %.1f N)\n", (step + 1) * dt, y - half,
                   f.force[1], mass * g);
    }
    CHECK(pbf_world_destroy(world));
    return 0;
}
