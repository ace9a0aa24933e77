// Zero-copy into Vulkan: libpbf writes a dam break's positions into a Vulkan buffer through CUDA
// external memory, ordered by exported binary and timeline semaphores; Vulkan reads the buffer
// back and the sample compares it with pbf_world_copy_positions.
//
//   pbf_render_vk [--particles N=65536] [--frames N=30]
//
// Headless (no surface, no window system). Runs the round trip twice: with explicit copies
// (pbf_world_copy_to_external_buffer) and with copies after each step (PBF_COPY_ON_STEP and
// pbf_world_set_external_sync). See vk_interop.h for the per-frame protocol. The last line is a
// one-line summary; the exit code is 0 only if every frame matched.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include <CLI/CLI.hpp>

#include "pbf_c_api.h"
#include "vk_interop.h"

namespace {

pbf_world_id dam_break(long particles) {
    const float a = 0.4f;
    const float spacing = std::cbrt(a * 2.0f * a * 0.5f * a / float(particles));
    pbf_world_desc desc = pbf_world_desc_default();
    desc.backend = PBF_BACKEND_CUDA;
    desc.max_particles = uint32_t(particles * 11 / 10 + 64);
    desc.particle_radius = 0.5f * spacing;
    const float domain_max[3] = {4.0f * a, 2.5f * a, 0.5f * a};
    std::memset(desc.domain_min, 0, sizeof desc.domain_min);
    std::memcpy(desc.domain_max, domain_max, sizeof domain_max);
    const float front_speed = std::sqrt(2.0f * 9.81f * 2.0f * a);
    const long substeps = long(std::ceil(front_speed / 60.0f / (0.4f * 2.0f * spacing)));
    desc.solver.substeps = uint32_t(substeps < 1 ? 1 : substeps > 16 ? 16 : substeps);
    pbf_world_id world{0, 0};
    if (pbf_world_create(&desc, &world) != PBF_OK) {
        std::fprintf(stderr, "pbf_render_vk: pbf_world_create: %s\n", pbf_last_error_message());
        std::exit(1);
    }
    pbf_block_desc block = pbf_block_desc_default();
    const float bmax[3] = {a, 2.0f * a, 0.5f * a};
    std::memcpy(block.box_max, bmax, sizeof bmax);
    uint32_t emitted = 0;
    if (pbf_world_emit_block(world, &block, &emitted) != PBF_OK) {
        std::fprintf(stderr, "pbf_render_vk: pbf_world_emit_block: %s\n", pbf_last_error_message());
        std::exit(1);
    }
    return world;
}

}  // namespace

int main(int argc, char** argv) {
    long particles = 65536, frames = 30;
    CLI::App app{
        "pbf_render_vk: libpbf writes a dam break's positions into a Vulkan buffer through CUDA external "
        "memory, ordered by exported semaphores; Vulkan reads it back and it is compared with "
        "pbf_world_copy_positions (explicit copies, then copies after each step). Exit status 0 only if "
        "every frame matched.",
        "pbf_render_vk"};
    app.option_defaults()->always_capture_default()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.add_option("--particles", particles, "particles in the dam break (>= 64)")->check(CLI::Range(64L, 1L << 31));
    app.add_option("--frames", frames, "frames per round trip (>= 2)")->check(CLI::Range(2L, 1L << 31));
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;  // --help: 0; a bad argument: 2, as before
    }
    uint32_t support = 0;
    pbf_get_interop_support(&support);
    if (!(support & PBF_INTEROP_SUPPORT_EXTERNAL_FD)) {
        std::fprintf(stderr, "pbf_render_vk: this libpbf cannot import opaque fds (built without CUDA?)\n");
        return 1;
    }
    bool all_ok = true;
    for (int auto_copy = 0; auto_copy <= 1; ++auto_copy) {
        pbf_world_id world = dam_break(particles);
        const pbf_vk::RoundTrip r = pbf_vk::round_trip(world, uint32_t(frames), auto_copy != 0);
        pbf_interop_info info;
        std::memset(&info, 0, sizeof info);
        info.struct_size = sizeof info;
        pbf_world_get_interop_info(world, &info);
        std::printf(
            "vulkan %s copies on %s: %u frames, %u particles, %llu mismatching floats, %u draw-args mismatches, "
            "%llu library transfers in step+copy, last copy %.4f ms GPU: %s%s%s\n",
            auto_copy ? "automatic (PBF_COPY_ON_STEP)" : "explicit (pbf_world_copy_to_external_buffer)",
            r.device_name.empty() ? "?" : r.device_name.c_str(), r.frames, r.particles,
            (unsigned long long)r.mismatching_floats, r.draw_args_mismatches, (unsigned long long)r.transfers_in_copies,
            info.last_copy_gpu_ms, r.ok ? "OK" : "FAILED", r.ok ? "" : ": ", r.error.c_str());
        if (!r.ok || r.transfers_in_copies != 0) all_ok = false;
        pbf_world_destroy(world);
    }
    std::printf("pbf_render_vk: %s\n", all_ok ? "OK (Vulkan buffer == copy-out on every frame, both modes)" : "FAILED");
    return all_ok ? 0 : 1;
}
