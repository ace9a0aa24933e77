// [gpu] twins of test_open_levels.cpp: the same scenes and bounds on the CUDA backend (the
// hashed grid's keys sorted by CUB).
#include "open_level_features.h"

using namespace open_level;

TEST_CASE("open level on CUDA: a puddle 1 km out, held by planes, settles as in a walled 2 m box", "[gpu][open]") {
    check_puddle_open_like_box(PBF_BACKEND_CUDA);
}

TEST_CASE("open level on CUDA: a walled puddle flows the same on the dense and the hashed grid", "[gpu][open]") {
    check_dense_like_hashed(PBF_BACKEND_CUDA);
}

TEST_CASE("open level on CUDA: without walls a block falls freely until a collider catches it", "[gpu][open]") {
    check_free_fall(PBF_BACKEND_CUDA);
}

TEST_CASE("open level on CUDA: every push comes from colliders (five dynamic planes carry all the weight)",
          "[gpu][open]") {
    check_planes_carry_all(PBF_BACKEND_CUDA);
}

TEST_CASE("open level on CUDA: sticky honey where the walls would be falls freely", "[gpu][open]") {
    check_honey_falls_freely(PBF_BACKEND_CUDA);
}

TEST_CASE("open level on CUDA: diffuse particles and render data 400 m out, as in the walls", "[gpu][open]") {
    check_splash_far_out(PBF_BACKEND_CUDA);
}

TEST_CASE("open level on CUDA: a mesh container 1 km out holds water as the walls do", "[gpu][open]") {
    check_mesh_container_far_out(PBF_BACKEND_CUDA);
}
