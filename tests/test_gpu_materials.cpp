// [gpu] twins of test_materials.cpp: the same scenes and bounds on the CUDA backend. Known
// failures as in test_materials.cpp.
#include "materials_scenes.h"

using namespace materials;

TEST_CASE("materials on CUDA: a cube with surface tension relaxes to a sphere and stays together", "[gpu][materials]") {
    const Shape with = cube_in_zero_gravity(PBF_BACKEND_CUDA, 100.0f, 100.0f, 3.0f);
    INFO("with: sphericity " << with.sphericity << ", farthest " << with.max_distance << " m");
    CHECK(with.sphericity >= 0.95);
    CHECK(with.max_distance <= 1.2 * with.equal_radius);
    const Shape without = cube_in_zero_gravity(PBF_BACKEND_CUDA, 0.0f, 0.0f, 3.0f);
    INFO("without: sphericity " << without.sphericity);
    CHECK(without.sphericity < 0.95);
}

TEST_CASE("materials on CUDA: two fluids of 1000 and 500 kg/m3 stratify without extra compression", "[gpu][materials]") {
    const Stratification two = two_fluids(PBF_BACKEND_CUDA, 500.0f, 4.0f);
    const Stratification one = two_fluids(PBF_BACKEND_CUDA, 1000.0f, 4.0f);
    INFO("above " << two.light_above << "; mean " << two.error_mean[0] << " / " << two.error_mean[1] << " vs "
                  << one.depth_mean[0] << " / " << one.depth_mean[1] << "; max " << two.error_max[0] << " / "
                  << two.error_max[1] << " vs " << one.depth_max[0] << " / " << one.depth_max[1]);
    CHECK(two.light_above >= 0.95);
    CHECK(two.error_mean[0] <= one.depth_mean[0]);
    CHECK(two.error_mean[1] <= one.depth_mean[1]);
    CHECK(two.error_max[0] <= one.depth_max[0]);
    CHECK(two.error_max[1] <= one.depth_max[1]);
}

TEST_CASE("materials on CUDA: a drop hangs under a sphere by adhesion and falls without it", "[gpu][materials]") {
    const Drop with = drop_under_sphere(PBF_BACKEND_CUDA, 3000.0f, 200.0f, 2.0f);
    const Drop without = drop_under_sphere(PBF_BACKEND_CUDA, 0.0f, 200.0f, 2.0f);
    INFO("centroid: with " << with.centroid_y << " m, without " << without.centroid_y << " m");
    CHECK(with.centroid_y >= 0.20);
    CHECK(without.centroid_y < 0.10);
}

TEST_CASE("materials on CUDA: viscosity dissipates the same energy at 2 and 8 substeps", "[gpu][materials]") {
    const double loss2 = shear_loss(PBF_BACKEND_CUDA, 0.2f, 2), loss8 = shear_loss(PBF_BACKEND_CUDA, 0.2f, 8);
    const double inviscid = shear_loss(PBF_BACKEND_CUDA, 0.0f, 8);
    INFO("lost: " << loss2 << " at 2, " << loss8 << " at 8, " << inviscid << " inviscid");
    CHECK(std::fabs(loss2 - loss8) <= 0.1 * std::max(loss2, loss8));
    CHECK(loss8 > inviscid + 0.1);
}

TEST_CASE("materials on CUDA: honey piles up where water spreads", "[gpu][materials][!shouldfail]") {
    const Spread water = collapse(PBF_BACKEND_CUDA, 0.01f, 0.5f), honey = collapse(PBF_BACKEND_CUDA, 0.9f, 0.5f);
    INFO("front: water " << water.front << " m, honey " << honey.front << " m");
    CHECK(honey.front - 0.2 <= 0.5 * (water.front - 0.2));
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
