// White-box tests of the render data's core (native/core/render_ops.h): the hand-written Jacobi
// eigen solver that runs on host and device, checked against Eigen's, and the rest-lattice
// reference of the anisotropy's scale.
#include <catch2/catch.hpp>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "core/lattice.h"
#include "core/render_ops.h"

using pbf::Sym3;
using pbf::Vec3;

namespace {

Sym3 to_sym3(const Eigen::Matrix3f& m) {
    Sym3 s;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) s.a[r][c] = m(r, c);
    return s;
}

// symmetric_eigen's result for m: values descending, axes unit, orthogonal, A v = λ v, and the
// values equal Eigen's (relative to the largest magnitude).
void check_decomposition(const Eigen::Matrix3f& m) {
    float value[3];
    Vec3 axis[3];
    pbf::symmetric_eigen(to_sym3(m), value, axis);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> ref(m);
    const Eigen::Vector3f ev = ref.eigenvalues();  // ascending
    const float scale = std::max({std::fabs(ev[0]), std::fabs(ev[2]), 1e-30f});
    INFO("matrix\n" << m);
    CHECK(value[0] >= value[1]);
    CHECK(value[1] >= value[2]);
    for (int k = 0; k < 3; ++k) {
        INFO("k = " << k << ", value " << value[k] << ", Eigen's " << ev[2 - k]);
        CHECK(std::fabs(value[k] - ev[2 - k]) <= 2e-5f * scale);
        const Eigen::Vector3f v(axis[k].x, axis[k].y, axis[k].z);
        CHECK(std::fabs(v.norm() - 1.0f) < 1e-5f);
        CHECK((m * v - value[k] * v).norm() <= 5e-5f * scale);
        for (int j = k + 1; j < 3; ++j) CHECK(std::fabs(pbf::dot(axis[k], axis[j])) < 1e-4f);
    }
}

}  // namespace

TEST_CASE("render: the Jacobi eigen solver agrees with Eigen on random and degenerate matrices", "[render][core]") {
    std::mt19937 rng(15);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    for (int t = 0; t < 500; ++t) {
        Eigen::Matrix3f a;
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) a(r, c) = u(rng);
        // Covariance-like (positive semi-definite, at the scale of h² = 1e-2 m²) and indefinite.
        const Eigen::Matrix3f m =
            t % 2 ? Eigen::Matrix3f(1e-2f * a * a.transpose()) : Eigen::Matrix3f(a + a.transpose());
        check_decomposition(m);
    }
    SECTION("degenerate") {
        check_decomposition(Eigen::Matrix3f::Zero());
        check_decomposition(Eigen::Matrix3f::Identity() * 3e-4f);
        check_decomposition(Eigen::Vector3f(1e-4f, 3e-4f, 2e-4f).asDiagonal());
        // A rank-1 and a rank-2 covariance (a line and a plane of neighbours), rotated.
        const Eigen::Matrix3f r = Eigen::AngleAxisf(0.7f, Eigen::Vector3f(1, 2, 3).normalized()).toRotationMatrix();
        check_decomposition(r * Eigen::Vector3f(4e-3f, 0, 0).asDiagonal() * r.transpose());
        check_decomposition(r * Eigen::Vector3f(4e-3f, 4e-3f, 0).asDiagonal() * r.transpose());
        check_decomposition(r * Eigen::Vector3f(4e-3f, 1e-3f, 1e-3f).asDiagonal() * r.transpose());
    }
}

TEST_CASE("render: the weight is Yu & Turk's 1 - (r/h)^3, zero from h on", "[render][core]") {
    const float h2 = 0.01f;  // h = 0.1
    CHECK(pbf::render_weight(0.0f, h2) == 1.0f);
    CHECK(pbf::render_weight(0.0025f, h2) == Approx(1.0f - 0.125f));  // r = h/2
    CHECK(pbf::render_weight(h2, h2) == 0.0f);
    CHECK(pbf::render_weight(2.0f * h2, h2) == 0.0f);
}

TEST_CASE("render: the rest-lattice variance scales with spacing squared", "[render][core]") {
    // h = 2 spacings in every world: the variance is spacing² times one pure number.
    const double a = pbf::rest_render_variance(0.05f, 0.1f), b = pbf::rest_render_variance(0.01f, 0.02f);
    CHECK(a > 0.0);
    CHECK(a / (0.05 * 0.05) == Approx(b / (0.01 * 0.01)).epsilon(1e-4));
    // Between the nearest shell (x² = spacing² for 2 of 6) and the farthest inside h.
    CHECK(a < 0.05 * 0.05);
}
