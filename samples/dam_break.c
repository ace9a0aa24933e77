/* Headless dam break: a column of water collapses in a tank. C99, public header only.
 *
 *   dam_break [particles=8000] [steps=150] [iterations=4]
 *   PBF_BACKEND=cpu|cuda overrides the backend (default: CUDA when available).
 *   PBF_LDC=0|1 turns Local Density Calibration off or on (default on).
 * Exits non-zero on any libpbf error. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pbf_c_api.h"

#define CHECK(call)                                                                         \
    do {                                                                                    \
        pbf_result r_ = (call);                                                             \
        if (r_ != PBF_OK) {                                                                 \
            fprintf(stderr, "dam_break: %s failed: %s\n", #call, pbf_last_error_message()); \
            return 1;                                                                       \
        }                                                                                   \
    } while (0)

static const char* backend_name(pbf_backend b) { return b == PBF_BACKEND_CUDA ? "cuda" : "cpu"; }

int main(int argc, char** argv) {
    const long particles = argc > 1 ? atol(argv[1]) : 8000;
    const long steps = argc > 2 ? atol(argv[2]) : 150;
    const long iterations = argc > 3 ? atol(argv[3]) : 4;
    if (particles < 64 || steps < 1 || iterations < 1 || iterations > 64) {
        fprintf(stderr, "usage: dam_break [particles>=64] [steps>=1] [iterations 1..64]\n");
        return 2;
    }

    /* Column a x 2a x a/2 at the left of a 4a x 2.5a x a/2 tank; spacing from the particle count. */
    const float a = 0.4f;
    const float column_volume = a * 2.0f * a * 0.5f * a;
    const float spacing = cbrtf(column_volume / (float)particles);

    pbf_world_desc desc = pbf_world_desc_default();
    const char* backend = getenv("PBF_BACKEND");
    if (backend && strcmp(backend, "cpu") == 0)
        desc.backend = PBF_BACKEND_CPU;
    else if (backend && strcmp(backend, "cuda") == 0)
        desc.backend = PBF_BACKEND_CUDA;
    else if (backend && *backend) {
        fprintf(stderr, "PBF_BACKEND must be cpu or cuda\n");
        return 2;
    }
    desc.max_particles = (uint32_t)(particles * 11 / 10 + 64);
    desc.particle_radius = 0.5f * spacing;
    const float domain_min[3] = {0.0f, 0.0f, 0.0f}, domain_max[3] = {4.0f * a, 2.5f * a, 0.5f * a};
    memcpy(desc.domain_min, domain_min, sizeof domain_min);
    memcpy(desc.domain_max, domain_max, sizeof domain_max);
    desc.solver.iterations = (uint32_t)iterations;
    /* Substeps keep the fastest particle (the front, about sqrt(2 g H)) under 0.4 h per substep. */
    const float dt = 1.0f / 60.0f;
    const float kernel_radius = 2.0f * spacing;
    const float front_speed = sqrtf(2.0f * 9.81f * 2.0f * a);
    long substeps = (long)ceilf(front_speed * dt / (0.4f * kernel_radius));
    if (getenv("PBF_SUBSTEPS")) substeps = atol(getenv("PBF_SUBSTEPS"));
    desc.solver.substeps = (uint32_t)(substeps < 1 ? 1 : substeps > 16 ? 16 : substeps);
    const char* ldc = getenv("PBF_LDC");
    if (ldc && *ldc) desc.solver.ldc_enabled = atoi(ldc) ? 1u : 0u;

    pbf_world_id world;
    CHECK(pbf_world_create(&desc, &world));
    pbf_world_info info = {0};
    info.struct_size = sizeof info;
    CHECK(pbf_world_get_info(world, &info));

    pbf_block_desc block = pbf_block_desc_default();
    const float bmax[3] = {a, 2.0f * a, 0.5f * a};
    memcpy(block.box_max, bmax, sizeof bmax);
    uint32_t emitted = 0;
    CHECK(pbf_world_emit_block(world, &block, &emitted));
    printf(
        "dam break: %u particles, spacing %.4f m, backend %s (%s), %ld steps of 1/60 s, %u substeps, %ld iterations, "
        "LDC %s\n",
        emitted, spacing, backend_name(info.backend), info.device_name, steps, desc.solver.substeps, iterations,
        desc.solver.ldc_enabled ? "on" : "off");

    double total_ms = 0.0;
    pbf_step_stats stats = {0};
    stats.struct_size = sizeof stats;
    double error_sum = 0.0;
    for (long s = 1; s <= steps; ++s) {
        CHECK(pbf_world_step(world, dt));
        CHECK(pbf_world_get_stats(world, &stats));
        total_ms += stats.step_time_ms;
        error_sum += stats.density_error_mean;
        if (s % (steps >= 10 ? steps / 10 : 1) == 0 || s == steps) {
            printf("  step %5ld  t=%.2fs  particles %u  density error mean %.4f max %.3f  KE %.3f J  %.2f ms/step\n", s,
                   s * dt, stats.particle_count, stats.density_error_mean, stats.density_error_max,
                   stats.kinetic_energy, stats.step_time_ms);
            fflush(stdout);
            if (!isfinite(stats.kinetic_energy)) {
                fprintf(stderr, "dam_break: simulation diverged (kinetic energy not finite)\n");
                return 1;
            }
        }
    }

    printf(
        "\n| backend | device | particles | steps | iterations | LDC | ms/step | density error (mean over run) | "
        "density error max (last) | kinetic energy (J) |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|\n");
    printf("| %s | %s | %u | %ld | %ld | %s | %.3f | %.5f | %.4f | %.4f |\n", backend_name(info.backend),
           info.device_name, stats.particle_count, steps, iterations, desc.solver.ldc_enabled ? "on" : "off",
           total_ms / (double)steps, error_sum / (double)steps, stats.density_error_max, stats.kinetic_energy);
    CHECK(pbf_world_destroy(world));
    return 0;
}
