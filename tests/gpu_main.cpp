// Main of the [gpu] suite: where no CUDA device can be used, every test reports SKIPPED
// (exit code 77, which ctest shows as "Skipped") instead of passing silently.
#define CATCH_CONFIG_RUNNER
#include <catch2/catch.hpp>
#include <cstdio>
#include <cstring>

#include "pbf_c_api.h"

int main(int argc, char** argv) {
    bool listing = false;
    for (int i = 1; i < argc; ++i)
        if (std::strncmp(argv[i], "--list", 6) == 0) listing = true;
    if (!listing) {
        pbf_world_desc d = pbf_world_desc_default();
        d.backend = PBF_BACKEND_CUDA;
        d.max_particles = 16;
        pbf_world_id w;
        if (pbf_world_create(&d, &w) != PBF_OK) {
            std::printf("SKIPPED [gpu]: no usable CUDA device (%s)\n", pbf_last_error_message());
            return 77;
        }
        pbf_world_destroy(w);
    }
    return Catch::Session().run(argc, argv);
}
