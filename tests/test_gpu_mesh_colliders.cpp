// [gpu] twins of test_mesh_colliders.cpp: the same scenes and bounds on the CUDA backend, where
// the mesh's distance field is built by the CUDA executor (the field's CPU build is checked
// white-box in test_sdf.cpp; here the physics it feeds checks the GPU build).
#include "mesh_scenes.h"

using namespace mesh;

TEST_CASE("mesh on CUDA: water on a sphere mesh keeps the distance it keeps from the analytic sphere", "[gpu][mesh]") {
    check_sphere_contact(PBF_BACKEND_CUDA);
}

TEST_CASE("mesh on CUDA: water at rest in a box-mesh container is as dense as in the domain's walls", "[gpu][mesh]") {
    check_container_rest(PBF_BACKEND_CUDA);
}

TEST_CASE("mesh on CUDA: an open plane holds a pool on its shell", "[gpu][mesh]") {
    check_open_plane(PBF_BACKEND_CUDA);
}

TEST_CASE("mesh on CUDA: a closed container moved 20 radii and turned 30 degrees per frame keeps its water",
          "[gpu][mesh][leak]") {
    check_no_leak(PBF_BACKEND_CUDA);
}
