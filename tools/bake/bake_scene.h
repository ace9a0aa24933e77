// pbf_bake's scene description: what a scene file (JSON) says, validated, in libpbf's own
// descriptor structs. Public C API only (pbf_c_api.h).
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf_c_api.h"

namespace bake {

// A scene or command-line error. The message is complete (file, JSON path, what was expected).
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct BlockSpec {
    pbf_block_desc desc;
};

struct EmitterSpec {
    pbf_emitter_desc desc;
    int64_t start_frame = 0;  // enabled for frames start_frame <= k < end_frame
    int64_t end_frame = -1;   // -1: until the end
};

struct Keyframe {
    double frame = 0.0;
    float position[3] = {0, 0, 0};
    float rotation[4] = {0, 0, 0, 1};  // x, y, z, w
};

struct ColliderSpec {
    pbf_collider_desc desc;
    std::vector<Keyframe> keys;  // kinematic colliders: sorted by frame, at least one
};

// Output formats, as bits.
enum Format : unsigned { kPly = 1u, kVtk = 2u, kVdb = 4u };

struct OutputSpec {
    std::string directory;  // relative paths are relative to the working directory
    std::string name;       // file prefix: NAME_0000.ply, NAME.pvd, ...
    unsigned formats = kPly | kVtk;
    double vdb_voxel_size = 0.0;     // 0: particle_radius / 2
    double vdb_sphere_radius = 0.0;  // 0: 2 · particle_radius (the rest spacing)
    double vdb_half_width = 3.0;     // narrow band half width, in voxels
};

struct Scene {
    std::string file;      // the scene file as given
    pbf_world_desc world;  // world and solver (from pbf_*_default, then the file)
    std::vector<BlockSpec> blocks;
    std::vector<EmitterSpec> emitters;
    std::vector<ColliderSpec> colliders;
    int64_t frame_start = 0;  // frames written: start..end inclusive; frame k is the
    int64_t frame_end = 120;  // state at time k / rate (frame 0: before the first step)
    double frame_rate = 60.0;
    uint32_t steps_per_frame = 1;  // pbf_world_step calls per frame (each dt = 1/(rate·steps))
    OutputSpec output;
};

// Reads and validates a scene file. Throws Error naming the file, the JSON path and what was
// expected. Files ending in .toml are read as TOML where pbf_bake was built with toml++.
Scene load_scene(const std::string& path);
// Same, from text already read (`file` names it in messages; `toml` selects the TOML reader).
Scene parse_scene(const std::string& text, const std::string& file, bool toml = false);

// "ply,vtk,vdb" -> bits; throws Error (naming `where`) on an unknown or empty list.
unsigned parse_formats(const std::string& list, const std::string& where);
std::string format_list(unsigned formats);
// Whether this build writes OpenVDB.
bool have_vdb();
bool have_toml();

// Pose of a kinematic collider at (fractional) frame f: linear in position, normalised linear
// interpolation of the rotation (shortest arc), clamped to the first and last keyframes.
Keyframe pose_at(const std::vector<Keyframe>& keys, double f);

// The names of pbf_solver_params fields a scene may set (for messages and docs).
std::vector<std::string> solver_field_names();

}  // namespace bake
