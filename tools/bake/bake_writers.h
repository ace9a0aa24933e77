// Frame writers of pbf_bake: binary little-endian PLY point clouds, VTK XML PolyData (.vtp, binary
// base64) with a ParaView collection (.pvd), and (where OpenVDB was found) a level set per frame.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace bake {

// One frame of particles, in the world's storage order (index k of every array is one particle).
struct Frame {
    int64_t index = 0;
    double time = 0.0;
    uint32_t count = 0;
    std::vector<float> xyzw;  // 4 per particle: x, y, z, density ratio ρ/ρ0
    std::vector<float> vel;   // 4 per particle: vx, vy, vz, 0
    std::vector<uint32_t> ids;
};

// Each throws bake::Error (with the path and the system's reason) when the file cannot be written.
//
// PLY: "format binary_little_endian 1.0", one element vertex with float x y z vx vy vz
// density_ratio and uint id (32 bytes per vertex).
void write_ply(const std::string& path, const Frame& f);
// VTK XML PolyData, version 1.0, UInt64 headers, inline base64 binary (so the file is plain,
// well-formed XML): Points (Float32 x3), PointData velocity (Float32 x3), density_ratio (Float32),
// id (UInt32), and one vertex cell per particle (Int64 connectivity/offsets) so that ParaView
// draws the points with any representation.
void write_vtp(const std::string& path, const Frame& f);
// A ParaView collection: one DataSet per (time, file name relative to the .pvd).
void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& entries);

struct VdbSettings {
    double voxel_size;     // metres
    double sphere_radius;  // metres: each particle is a sphere of this radius
    double half_width;     // narrow band, voxels
};
// OpenVDB level set ("surface", FloatGrid, class level set) of the union of spheres around the
// particles, by openvdb::tools::ParticlesToLevelSet. Returns the active voxel count. Throws
// bake::Error where pbf_bake was built without OpenVDB.
uint64_t write_vdb(const std::string& path, const Frame& f, const VdbSettings& s);

std::string base64(const void* data, size_t bytes);

}  // namespace bake
