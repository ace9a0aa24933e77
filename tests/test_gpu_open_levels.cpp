// [gpu] twins of test_open_levels.cpp: the same scenes and bounds on the CUDA backend (the
// hashed grid's keys sorted by CUB).
#include "open_level_scenes.h"

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
