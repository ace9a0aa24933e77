// OpenVDB output of pbf_bake (built only where libopenvdb-dev was found at configure time).
// The surface is the union of spheres of radius sphere_radius around the particles, rasterised
// into a narrow-band level set by openvdb::tools::ParticlesToLevelSet.
#include <openvdb/openvdb.h>
#include <openvdb/tools/ParticlesToLevelSet.h>

#include <mutex>

#include "bake_scene.h"
#include "bake_writers.h"

namespace bake {

namespace {

// The particle list interface ParticlesToLevelSet reads (positions only: fixed radius).
struct ParticleList {
    using PosType = openvdb::Vec3R;
    const Frame* frame;
    size_t size() const { return frame->count; }
    void getPos(size_t n, openvdb::Vec3R& xyz) const {
        xyz = openvdb::Vec3R(frame->xyzw[4 * n], frame->xyzw[4 * n + 1], frame->xyzw[4 * n + 2]);
    }
};

}  // namespace

uint64_t write_vdb(const std::string& path, const Frame& f, const VdbSettings& s) {
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
    openvdb::FloatGrid::Ptr grid = openvdb::createLevelSet<openvdb::FloatGrid>(s.voxel_size, float(s.half_width));
    grid->setName("surface");
    ParticleList list{&f};
    openvdb::tools::ParticlesToLevelSet<openvdb::FloatGrid> raster(*grid);
    if (f.count > 0) raster.rasterizeSpheres(list, s.sphere_radius);
    raster.finalize(/*prune=*/true);
    if (raster.getMinCount() > 0)
        throw Error(path + ": " + std::to_string(raster.getMinCount()) +
                    " particles were too small for the voxel size (sphere radius under 1.5 voxels): lower "
                    "output.vdb.voxel_size or raise output.vdb.sphere_radius");
    grid->insertMeta("pbf_frame", openvdb::Int64Metadata(f.index));
    grid->insertMeta("pbf_time", openvdb::DoubleMetadata(f.time));
    try {
        openvdb::io::File file(path);
        openvdb::GridPtrVec grids{grid};
        file.write(grids);
        file.close();
    } catch (const openvdb::Exception& e) {
        throw Error(path + ": cannot write the OpenVDB file: " + e.what());
    }
    return grid->activeVoxelCount();
}

}  // namespace bake
