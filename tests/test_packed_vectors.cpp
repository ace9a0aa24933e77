// White-box tests of core/packed_vectors.h: the 8-byte vectors that carry the colliders'
// boundary gradient from the λ pass to the Δ pass must come back within 1e-4 of their length,
// in every octant, on the axes and at the octahedron's folds, and zero must stay zero.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "core/packed_vectors.h"

using namespace pbf;

namespace {

// The largest |unpacked - v| / |v| over the vectors, stored and loaded through PackedVectors.
double worst_relative_error(const std::vector<Vec3>& vs) {
    std::vector<uint32_t> directions(vs.size());
    std::vector<float> lengths(vs.size());
    const PackedVectors packed{directions.data(), lengths.data()};
    double worst = 0;
    for (uint32_t i = 0; i < vs.size(); ++i) {
        packed.store(i, vs[i]);
        const Vec3 back = packed.load(i);
        const double err = std::sqrt(double(length_sq(back - vs[i]))) / double(length(vs[i]));
        worst = std::max(worst, err);
    }
    return worst;
}

}  // namespace

TEST_CASE("packed vectors come back within 1e-4 of their length", "[packed_vectors]") {
    std::mt19937 rng(7);
    std::normal_distribution<float> normal(0.0f, 1.0f);
    std::uniform_real_distribution<float> exponent(-8.0f, 8.0f);
    std::vector<Vec3> vs;
    for (int k = 0; k < 20000; ++k) {
        const float scale = std::pow(10.0f, exponent(rng));
        vs.push_back(Vec3{normal(rng), normal(rng), normal(rng)} * scale);
    }
    // The axes, the octahedron's edges and its folds (z = 0, |x| + |y| = 1 on the square).
    for (float sx : {-1.0f, 0.0f, 1.0f})
        for (float sy : {-1.0f, 0.0f, 1.0f})
            for (float sz : {-1.0f, 0.0f, 1.0f})
                if (sx != 0.0f || sy != 0.0f || sz != 0.0f) vs.push_back(Vec3{sx, sy, sz} * 3.5f);
    vs.push_back(Vec3{1e-7f, -1e-7f, -1.0f});
    vs.push_back(Vec3{0.3f, -0.7f, -1e-9f});
    const double worst = worst_relative_error(vs);
    INFO("worst relative error " << worst);
    CHECK(worst <= 1e-4);
    CHECK(worst > 0.0);  // it is quantised: a lossless copy would not exercise the packing
}

TEST_CASE("a packed zero vector stays zero", "[packed_vectors]") {
    uint32_t direction = 12345u;
    float len = 1.0f;
    const PackedVectors packed{&direction, &len};
    packed.store(0, Vec3{0.0f, 0.0f, 0.0f});
    const Vec3 back = packed.load(0);
    CHECK(back.x == 0.0f);
    CHECK(back.y == 0.0f);
    CHECK(back.z == 0.0f);
}

TEST_CASE("the octahedral fold keeps opposite directions apart", "[packed_vectors]") {
    // Below the equator the fold maps (x, y, -z) elsewhere than (x, y, z): both come back.
    const Vec3 up{0.2f, 0.3f, 0.9f}, down{0.2f, 0.3f, -0.9f};
    const Vec3 a = unpack_direction(pack_direction(up)), b = unpack_direction(pack_direction(down));
    CHECK(a.z > 0.0f);
    CHECK(b.z < 0.0f);
    CHECK(std::fabs(dot(a, up * (1.0f / length(up))) - 1.0f) < 1e-6f);
    CHECK(std::fabs(dot(b, down * (1.0f / length(down))) - 1.0f) < 1e-6f);
}
