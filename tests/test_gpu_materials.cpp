// [gpu] twins of test_materials.cpp: the same scenes and bounds on the CUDA backend.
#include "materials_scenes.h"

using namespace materials;

TEST_CASE("materials on CUDA: a cube with surface tension relaxes to a sphere and stays together", "[gpu][materials]") {
    check_sphere(PBF_BACKEND_CUDA);
}

TEST_CASE("materials on CUDA: two fluids of 1000 and 500 kg/m3 stratify without extra compression",
          "[gpu][materials]") {
    check_stratification(PBF_BACKEND_CUDA);
}

TEST_CASE("materials on CUDA: a drop hangs under a sphere by adhesion and falls without it", "[gpu][materials]") {
    check_adhesion(PBF_BACKEND_CUDA);
}

TEST_CASE("materials on CUDA: viscosity dissipates the same energy at 2 and 8 substeps", "[gpu][materials]") {
    check_viscosity_substeps(PBF_BACKEND_CUDA);
}

TEST_CASE("materials on CUDA: honey piles up where water spreads", "[gpu][materials]") {
    check_honey(PBF_BACKEND_CUDA);
}

TEST_CASE("materials on CUDA: a sliding plate carries honey along and leaves water behind", "[gpu][materials]") {
    check_plate_drag(PBF_BACKEND_CUDA);
}

TEST_CASE("materials on CUDA: the material bytes are device memory and follow their particles", "[gpu][materials]") {
    pbf_world_desc d = box_world(PBF_BACKEND_CUDA, 0.8f, 0.8f, 0.8f, 9.81f);
    pbf_world_id w = scene::create(d);
    pbf_material_desc m = pbf_material_desc_default();
    m.rest_density = 600.0f;
    const pbf_material_id light = add_material(w, m);
    const float lo[3] = {0, 0, 0}, mid[3] = {0.4f, 0.4f, 0.4f}, hi[3] = {0.8f, 0.4f, 0.4f};
    const uint32_t heavy = fill(w, pbf_material_id{0, 0}, lo, mid);
    const float lo2[3] = {0.4f, 0, 0};
    fill(w, light, lo2, hi);
    run(w, 0.5f);
    const scene::Particles p = scene::read(w);
    const std::vector<uint8_t> mat = read_materials(w, p.count);
    for (uint32_t i = 0; i < p.count; ++i) CHECK(uint32_t(mat[i]) == (p.ids[i] < heavy ? 0u : light.index));
    pbf_device_buffers b;
    std::memset(&b, 0, sizeof b);
    b.struct_size = sizeof b;
    REQUIRE_PBF(pbf_world_map_device_buffers(w, 0, &b));
    CHECK(b.memory == PBF_MEMORY_CUDA_DEVICE);
    CHECK(b.materials != nullptr);
    REQUIRE_PBF(pbf_world_unmap(w));
    pbf_world_destroy(w);
}
