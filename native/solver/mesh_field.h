// The build of a mesh's distance field on either executor, all of it on the backend: the
// triangles binned to bricks (count, scan, fill, sort by brick), the winding numbers at the
// bricks' centres, the distances and the boundary shares (core/sdf_build.h's ops, in order).
// The host waits twice: for the lists' length (to allocate them) and at the end (the creation
// call returns with the field complete); everything but the field is freed.
#pragma once
#include <cstdint>
#include <string>

#include "mesh_input.h"
#include "../common/status.h"

namespace pbf {

// The build's backend allocations, freed together (the field itself is handed over). A failed
// one refuses the mesh and leaves the world as it was (try_alloc).
template <class Exec>
class BuildMemory {
public:
    explicit BuildMemory(Exec& exec) : exec_(exec) {}
    ~BuildMemory() {
        for (int k = 0; k < used_; ++k) exec_.release(held_[k]);
    }
    BuildMemory(const BuildMemory&) = delete;
    BuildMemory& operator=(const BuildMemory&) = delete;
    template <class T>
    T* alloc(size_t count) {
        T* p = exec_.template try_alloc<T>(count > 0 ? count : 1);
        if (!p)
            failed_ = true;
        else
            held_[used_++] = p;
        return p;
    }
    bool failed() const { return failed_; }

private:
    static constexpr int kMax = 24;
    Exec& exec_;
    void* held_[kMax] = {};
    int used_ = 0;
    bool failed_ = false;
};

template <class Exec>
Status mesh_memory_error(Exec& exec, const std::string& what) {
    return Status::error(PBF_ERROR_OUT_OF_MEMORY,
                         "cannot allocate " + what + " on " + exec.device_name() + ": " + exec.last_error_text());
}

template <class Exec>
Status build_mesh_field(Exec& exec, const MeshBuild& b, float** out_values) {
    const size_t voxels = size_t(b.grid.nx) * size_t(b.grid.ny) * size_t(b.grid.nz);
    const SdfBricks bricks{b.grid, b.bricks[0], b.bricks[1], b.bricks[2], b.margin};
    const uint32_t brick_total = brick_count(bricks);
    const uint32_t triangles = uint32_t(b.indices.size() / 3);
    // Offsets are 32-bit and the sort and scan count items in an int.
    if (b.listing_bound > 0x7fffffffull)
        return Status::error(PBF_ERROR_OUT_OF_MEMORY,
                             "a mesh's triangles would be listed in its field's bricks up to " +
                                 std::to_string(b.listing_bound) +
                                 " times (over 2^31): use fewer or smaller triangles, or a coarser cell_size");
    const uint32_t chunks = sdf_winding_chunks(brick_total, triangles);
    BuildMemory<Exec> mem(exec);
    Vec3* vertices = mem.template alloc<Vec3>(b.vertices.size());
    uint32_t* indices = mem.template alloc<uint32_t>(b.indices.size());
    Vec4* corners = mem.template alloc<Vec4>(size_t(triangles) * 3);
    uint32_t* counts = mem.template alloc<uint32_t>(size_t(triangles) + 1);
    uint32_t* offsets = mem.template alloc<uint32_t>(size_t(triangles) + 1);
    const size_t scan_bytes = exec.scan_temp_bytes(triangles + 1);
    void* scan_temp = mem.template alloc<unsigned char>(scan_bytes);
    uint32_t* begin = mem.template alloc<uint32_t>(size_t(brick_total) + 1);
    float* parts = mem.template alloc<float>(size_t(brick_total) * chunks);
    float* winding = mem.template alloc<float>(2 * size_t(brick_total));
    float* values = exec.template try_alloc<float>(2 * voxels);  // distances, then the boundary shares
    if (mem.failed() || !values) {
        exec.release(values);
        return mesh_memory_error(exec, "a mesh's distance field of " + std::to_string(voxels) + " voxels");
    }
    exec.upload(vertices, b.vertices.data(), b.vertices.size() * sizeof(Vec3));
    exec.upload(indices, b.indices.data(), b.indices.size() * sizeof(uint32_t));
    exec.for_each(triangles, SdfCornersOp{vertices, indices, corners});
    // Per triangle its bricks' count; the scan's last entry (a zero count) is the lists' length.
    exec.zero(counts + triangles, sizeof(uint32_t));
    exec.for_each(triangles, SdfBinCountOp{bricks, corners, counts});
    exec.exclusive_scan(counts, offsets, triangles + 1, scan_temp, scan_bytes);
    uint32_t listed = 0;
    exec.download(&listed, offsets + triangles, sizeof listed);  // waits: the lists' size
    Status st = exec.check("binning a mesh's triangles");
    if (!st.ok()) {
        exec.release(values);
        return st;
    }
    uint32_t* keys[2] = {mem.template alloc<uint32_t>(listed), mem.template alloc<uint32_t>(listed)};
    uint32_t* listed_triangles[2] = {mem.template alloc<uint32_t>(listed), mem.template alloc<uint32_t>(listed)};
    const size_t sort_bytes = exec.sort_temp_bytes(listed, brick_total);
    void* sort_temp = mem.template alloc<unsigned char>(sort_bytes);
    if (mem.failed()) {
        exec.release(values);
        return mesh_memory_error(exec, "a mesh's " + std::to_string(listed) + " brick list entries");
    }
    exec.for_each(triangles, SdfBinFillOp{bricks, corners, offsets, keys[0], listed_triangles[0]});
    int key_sel = 0, triangle_sel = 0;
    exec.sort_pairs(keys, listed_triangles, listed, brick_total, &key_sel, &triangle_sel, sort_temp, sort_bytes);
    exec.for_each(brick_total + 1, SdfBrickBeginOp{keys[key_sel], listed, begin});
    const SdfSource src{corners, triangles, begin, listed_triangles[triangle_sel], bricks};
    exec.for_each(brick_total * chunks, SdfWindingPartOp{src, sdf_winding_chunk(chunks, triangles), parts});
    exec.for_each(brick_total, SdfBrickWindingOp{src, chunks, parts, winding});
    exec.for_each(brick_total * kSdfBrickPoints, SdfVoxelOp{src, winding, b.closed, b.half_thickness, values});
    MeshView field = b.grid;
    field.values = values;
    exec.for_each(uint32_t(voxels), SdfBoundaryOp{field, b.kernel_radius, values + voxels});
    // Waits for the build (a download is a host wait): the temporaries are then free to go, and
    // the creation call returns with the field complete.
    float probe = 0.0f;
    exec.download(&probe, values, sizeof probe);
    st = exec.check("building a mesh's distance field");
    if (!st.ok()) {
        exec.release(values);
        return st;
    }
    *out_values = values;
    return st;
}

}  // namespace pbf
