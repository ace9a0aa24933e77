// The bake itself: builds a libpbf world from a Scene (public C API only), steps it frame by
// frame and writes the requested formats.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "bake_scene.h"
#include "bake_writers.h"

namespace bake {

struct RunOptions {
    bool progress = true;  // the progress bar on stderr
    // Called after each written frame, with the world (still at that frame) and the files written.
    std::function<void(const Frame&, pbf_world_id, const std::vector<std::string>&)> on_frame;
};

struct RunResult {
    int64_t frames_written = 0;
    uint32_t particles = 0;          // at the last frame
    uint64_t vdb_active_voxels = 0;  // at the last frame (0 without vdb)
    double seconds = 0.0;
    std::string device;
    std::string pvd;  // the .pvd written ("" without vtk)
};

// The voxel size and sphere radius a scene's VDB output uses (documented defaults applied).
VdbSettings vdb_settings(const Scene& s);

// Throws bake::Error: libpbf failures carry the scene path of the object, the call,
// pbf_result_string and pbf_last_error_message().
RunResult run_bake(const Scene& s, const RunOptions& o);

// Frame file names: NAME_0042.ply etc. (at least 4 digits).
std::string frame_file(const Scene& s, int64_t frame, const char* ext);

}  // namespace bake
