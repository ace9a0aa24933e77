// [gpu] twins of test_mesh_colliders.cpp: the same scenes and bounds on the CUDA backend, where
// the mesh's distance field is built by the CUDA executor (the field's CPU build is checked
// white-box in test_sdf.cpp; here the physics it feeds checks the GPU build).
#include "mesh_scenes.h"

using namespace mesh;

TEST_CASE("mesh on CUDA: water on a sphere mesh keeps the distance it keeps from the analytic sphere", "[gpu][mesh]") {
    const float analytic = closest_to_sphere(PBF_BACKEND_CUDA, false);
    const float sampled = closest_to_sphere(PBF_BACKEND_CUDA, true);
    INFO("closest centre to the surface: analytic " << analytic << " m, mesh " << sampled << " m");
    CHECK(analytic == Approx(kR).margin(0.1f * kR));
    CHECK(std::fabs(sampled - analytic) < kR);
}

TEST_CASE("mesh on CUDA: water at rest in a box-mesh container is as dense as in the domain's walls", "[gpu][mesh]") {
    const Rest walls = settled_in_container(PBF_BACKEND_CUDA, false);
    const Rest mesh = settled_in_container(PBF_BACKEND_CUDA, true);
    INFO("density ratio: walls " << walls.density << ", mesh " << mesh.density << "; mean height: walls "
                                 << walls.height << ", mesh " << mesh.height);
    REQUIRE(mesh.count == walls.count);
    CHECK(mesh.density == Approx(walls.density).epsilon(0.01));
    CHECK(std::fabs(mesh.height - walls.height) < 0.1 * kSpacing);
}

TEST_CASE("mesh on CUDA: an open plane holds a pool on its shell", "[gpu][mesh]") {
    const PlaneResult r = pool_on_open_plane(PBF_BACKEND_CUDA);
    INFO("lowest centre above the plane " << r.lowest - 0.2f << " m; leaked " << r.leaked << " of " << r.count);
    CHECK(r.leaked == 0u);
    CHECK(r.lowest - 0.2f == Approx(2 * kR).margin(0.5f * kR));
}

TEST_CASE("mesh on CUDA: a closed container moved 20 radii and turned 30 degrees per frame keeps its water",
          "[gpu][mesh][leak]") {
    const LeakResult r = shaken_container(PBF_BACKEND_CUDA, 20.0f, 30.0f, 600);
    INFO("particles " << r.count << ", most outside " << r.outside_max << ", first loss at frame " << r.first_frame);
    CHECK(r.count == 192u);
    CHECK(r.outside_max == 0u);
}
