// The per-particle operations run directly on small host arrays (white-box): LDC's direction
// and effect, and the density constraint's λ and Δp. A one-cell grid makes every particle a
// neighbour candidate, so these tests do not depend on the grid build.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "core/lattice.h"
#include "core/passes.h"

using namespace pbf;

namespace {

struct Scene {
    WorldConstants s{};
    StepContext ctx{};
    uint32_t clamped = 0;
    std::vector<Vec4> pos, vel, pred, corrected;
    std::vector<float> density;
    std::vector<uint32_t> cell_begin, keys, mask_rows;

    explicit Scene(float spacing, float dt = 1.0f / 60.0f) {
        const float h = 2.0f * spacing;
        const LatticeCalibration c = calibrate_lattice(spacing, h);
        s.radius = 0.5f * spacing;
        s.h = h;
        s.h2 = h * h;
        s.rest_density = 1000.0f;
        s.inv_rest_density = 1.0f / s.rest_density;
        s.mass = float(s.rest_density / c.kernel_sum);
        s.poly6_coef = poly6_coefficient(h);
        s.spiky_coef = spiky_grad_coefficient(h);
        s.rest_gradient_norm2 = float(c.gradient_norm2 / (c.kernel_sum * c.kernel_sum));
        s.relaxation = 0.01f;
        s.scorr_k = 0.0f;
        s.scorr_n = 4.0f;
        s.scorr_inv_w_dq = 1.0f;
        s.max_speed = 100.0f;
        s.gravity = Vec3{0, 0, 0};
        s.wall_min = s.boundary_min = Vec3{-100, -100, -100};
        s.wall_max = s.boundary_max = Vec3{100, 100, 100};
        s.boundary_scale = 0.0f;  // no walls within reach
        ctx.dt = dt;
        ctx.inv_dt = 1.0f / dt;
        ctx.lambda_epsilon = s.relaxation * s.rest_gradient_norm2;
        ctx.speed_limit = s.max_speed;
        ctx.clamped = &clamped;
        s.grid = dense_grid(Vec3{-100, -100, -100}, 1.0f / 200.0f, 1, 1, 1);
    }
    void add(Vec3 p) { pos.push_back(make_vec4(p, 1.0f)); }
    uint32_t n() const { return uint32_t(pos.size()); }
    void finish() {
        vel.assign(n(), Vec4{0, 0, 0, 0});
        pred.assign(n(), Vec4{0, 0, 0, 0});
        corrected.assign(n(), Vec4{0, 0, 0, 0});
        density.assign(n(), 0.0f);
        cell_begin = {0u, n()};
        keys.assign(n(), 0u);  // one cell holds everything: its rows are walked, not listed
        mask_rows.assign(size_t(n()) * kMaskRows, 0u);
    }
    NeighborMasks masks() { return NeighborMasks{mask_rows.data(), keys.data(), n()}; }
    template <class Op>
    void run(const Op& op) {
        for (uint32_t i = 0; i < n(); ++i) op(i);
    }
    void densities(std::vector<Vec4>& at) {
        run(DensityOp{s, ctx.colliders, cell_begin.data(), at.data(), density.data()});
    }
};

// Spread (std) of ρ/ρ0 over particles at least `margin` inside the lattice's bounding box.
double interior_spread(const std::vector<Vec4>& lattice, const std::vector<float>& density, float rho0, float lo,
                       float hi) {
    double sum = 0, sum2 = 0;
    int n = 0;
    for (size_t i = 0; i < density.size(); ++i) {
        const Vec4 p = lattice[i];
        if (p.x < lo || p.y < lo || p.z < lo || p.x > hi || p.y > hi || p.z > hi) continue;
        const double r = density[i] / rho0;
        sum += r;
        sum2 += r * r;
        ++n;
    }
    const double mean = sum / n;
    return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

}  // namespace

TEST_CASE("LDC force points from denser toward less dense neighbours", "[ldc]") {
    Scene sc(0.05f);
    sc.add(Vec3{0, 0, 0});
    sc.add(Vec3{0.05f, 0, 0});   // +x neighbour
    sc.add(Vec3{-0.05f, 0, 0});  // -x neighbour
    sc.finish();
    sc.s.ldc_enabled = 1;
    const float k = 100.0f;
    const float rho0 = sc.s.rest_density;

    SECTION("denser neighbour on +x, less dense on -x: pushed toward -x") {
        sc.density = {rho0, 1.2f * rho0, 0.8f * rho0};
        const Vec3 f = ldc_force(sc.s, k, sc.cell_begin.data(), sc.pos.data(), sc.density.data(), 0);
        CHECK(f.x < 0.0f);
        CHECK(std::fabs(f.y) < 1e-6f);
        CHECK(std::fabs(f.z) < 1e-6f);
    }
    SECTION("mirror image: pushed toward +x") {
        sc.density = {rho0, 0.8f * rho0, 1.2f * rho0};
        CHECK(ldc_force(sc.s, k, sc.cell_begin.data(), sc.pos.data(), sc.density.data(), 0).x > 0.0f);
    }
    SECTION("equal densities: no force") {
        sc.density = {rho0, rho0, rho0};
        CHECK(length(ldc_force(sc.s, k, sc.cell_begin.data(), sc.pos.data(), sc.density.data(), 0)) == 0.0f);
    }
    SECTION("a particle denser than both neighbours is pushed by neither side (symmetric)") {
        sc.density = {1.3f * rho0, rho0, rho0};
        CHECK(std::fabs(ldc_force(sc.s, k, sc.cell_begin.data(), sc.pos.data(), sc.density.data(), 0).x) < 1e-6f);
        // Each neighbour is pushed away from the dense centre, toward lower density.
        CHECK(ldc_force(sc.s, k, sc.cell_begin.data(), sc.pos.data(), sc.density.data(), 1).x > 0.0f);
        CHECK(ldc_force(sc.s, k, sc.cell_begin.data(), sc.pos.data(), sc.density.data(), 2).x < 0.0f);
    }
    SECTION("the weight is the linear hat h(1 - r/h): a closer neighbour pushes harder") {
        sc.density = {rho0, 1.2f * rho0, rho0};
        const float far = -ldc_force(sc.s, k, sc.cell_begin.data(), sc.pos.data(), sc.density.data(), 0).x;
        sc.pos[1].x = 0.025f;
        const float near = -ldc_force(sc.s, k, sc.cell_begin.data(), sc.pos.data(), sc.density.data(), 0).x;
        // f = K ρ_ij h (1 - r/h): r = h/2 gives 0.5h, r = h/4 gives 0.75h.
        CHECK(near / far == Approx(1.5f).epsilon(1e-4));
        CHECK(far == Approx(100.0f * 0.2f * 0.1f * 0.5f).epsilon(1e-4));
    }
}

namespace {
// One application of LDC from rest on a jittered lattice (gravity off); returns the interior
// density spread before and after.
std::pair<double, double> ldc_once(float gain, uint32_t seed) {
    const float d = 0.05f;
    Scene sc(d);
    std::mt19937 rng(seed);
    std::normal_distribution<float> jitter(0.0f, 0.12f * d);
    const int n = 12;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) sc.add(Vec3{x * d + jitter(rng), y * d + jitter(rng), z * d + jitter(rng)});
    sc.finish();
    sc.s.ldc_enabled = 1;
    sc.ctx.ldc_k = gain / (sc.ctx.dt * sc.ctx.dt);
    const float lo = 2.0f * sc.s.h, hi = (n - 1) * d - 2.0f * sc.s.h;
    sc.densities(sc.pos);
    std::vector<Vec4> start = sc.pos;
    const double before = interior_spread(start, sc.density, sc.s.rest_density, lo, hi);
    sc.run(
        PredictOp{sc.s, sc.ctx, sc.cell_begin.data(), sc.density.data(), sc.pos.data(), sc.vel.data(), sc.pred.data()});
    sc.densities(sc.pred);
    const double after = interior_spread(start, sc.density, sc.s.rest_density, lo, hi);
    return {before, after};
}
}  // namespace

TEST_CASE("LDC applied once reduces the spread of densities on a perturbed lattice", "[ldc]") {
    for (uint32_t seed : {1u, 2u, 3u}) {
        const auto [before, after] = ldc_once(0.1f, seed);
        INFO("seed " << seed << ": spread " << before << " -> " << after);
        CHECK(before > 0.02);          // the jitter made a real spread
        CHECK(after < 0.85 * before);  // LDC smooths it
    }
}

TEST_CASE("LDC with the opposite sign would increase the spread (the reading of Eq. 1 matters)", "[ldc]") {
    const auto [before, after] = ldc_once(-0.1f, 7u);
    CHECK(after > before);
}

TEST_CASE("LDC off leaves a resting lattice at rest (gravity off)", "[ldc]") {
    Scene sc(0.05f);
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) sc.add(Vec3{x * 0.05f, y * 0.05f, z * 0.05f});
    sc.finish();
    sc.s.ldc_enabled = 0;
    sc.run(
        PredictOp{sc.s, sc.ctx, sc.cell_begin.data(), sc.density.data(), sc.pos.data(), sc.vel.data(), sc.pred.data()});
    for (uint32_t i = 0; i < sc.n(); ++i) {
        CHECK(sc.pred[i].x == sc.pos[i].x);
        CHECK(sc.pred[i].y == sc.pos[i].y);
    }
}

TEST_CASE("density constraint: λ < 0 only where compressed, and Δp reduces compression", "[pbf]") {
    const float d = 0.05f;
    Scene sc(d);
    const int n = 11;
    const float squeeze = 0.92f;  // lattice at 92 % of rest spacing: ~28 % too dense inside
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) sc.add(Vec3{x * d * squeeze, y * d * squeeze, z * d * squeeze});
    sc.finish();
    sc.pred = sc.pos;
    const float lo = sc.s.h, hi = (n - 1) * d * squeeze - sc.s.h;
    auto interior_error = [&]() {
        double e = 0;
        int k = 0;
        for (uint32_t i = 0; i < sc.n(); ++i) {
            const Vec4 p = sc.pos[i];
            if (p.x < lo || p.y < lo || p.z < lo || p.x > hi || p.y > hi || p.z > hi) continue;
            e += std::max(0.0, sc.density[i] / double(sc.s.rest_density) - 1.0);
            ++k;
        }
        REQUIRE(k > 0);
        return e / k;
    };
    sc.run(LambdaOp{sc.s, sc.ctx, sc.cell_begin.data(), sc.masks(), 1u, sc.pos.data(), sc.pred.data(),
                    sc.density.data(), nullptr});
    const double error_before = interior_error();
    CHECK(error_before > 0.2);
    const uint32_t centre = (n / 2) * n * n + (n / 2) * n + n / 2;
    CHECK(sc.pred[centre].w < 0.0f);
    CHECK(sc.pred[0].w == 0.0f);  // a corner particle is under-dense: unilateral, no pull
    for (int it = 0; it < 4; ++it) {
        sc.run(LambdaOp{sc.s, sc.ctx, sc.cell_begin.data(), sc.masks(), 0u, sc.pos.data(), sc.pred.data(),
                        sc.density.data(), nullptr});
        sc.run(DeltaOp{sc.s, sc.ctx, sc.cell_begin.data(), sc.masks(), sc.pos.data(), sc.pred.data(),
                       sc.corrected.data(), nullptr});
        std::swap(sc.pred, sc.corrected);
    }
    sc.run(LambdaOp{sc.s, sc.ctx, sc.cell_begin.data(), sc.masks(), 0u, sc.pos.data(), sc.pred.data(),
                    sc.density.data(), nullptr});
    const double error_after = interior_error();
    INFO("interior compressive error " << error_before << " -> " << error_after);
    CHECK(error_after < 0.5 * error_before);
    // Symmetry: the centre particle of a symmetric lattice does not move.
    CHECK(std::fabs(sc.pred[centre].x - sc.pos[centre].x) < 1e-5f);
}

// A collider standing unrotated at p, with the broad-phase bounds the world would give it.
static Collider standing(Collider c, Vec3 p) {
    const Quat identity{0, 0, 0, 1};
    c.bounds = swept_bounds(c, ColliderKey{p, p, identity, identity});
    return c;
}

TEST_CASE("colliders push particle centres out to one radius from the surface", "[collide]") {
    Scene sc(0.05f);
    const float r = sc.s.radius;
    auto pose = [](Vec3 p) { return ColliderPose{p, Mat3{{1, 0, 0, 0, 1, 0, 0, 0, 1}}}; };
    const Vec3 at[4] = {Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}};
    const Collider shapes[4] = {standing({kShapeSphere, 0.2f, 0.0f, 0.0f, Vec3{0, 0, 0}}, at[0]),
                                standing({kShapeBox, 0.0f, 0.0f, 0.0f, Vec3{0.1f, 0.2f, 0.3f}}, at[1]),
                                standing({kShapeCapsule, 0.1f, 0.3f, 0.0f, Vec3{0, 0, 0}}, at[2]),
                                standing({kShapePlane, 0.0f, 0.0f, 0.0f, Vec3{0, 0, 0}}, at[3])};
    const ColliderPose poses[4] = {pose(at[0]), pose(at[1]), pose(at[2]), pose(at[3])};
    const ColliderView set{shapes, poses, poses, 4};
    Vec3 n;
    const Vec3 in_sphere = collide(sc.s, set, Vec3{0.05f, 0.0f, 0.0f}, Vec3{0, 0, 0});
    CHECK(collider_distance(shapes[0], poses[0], in_sphere, n, nullptr) == Approx(r).margin(1e-5));
    CHECK(in_sphere.x > 0.0f);
    const Vec3 in_box = collide(sc.s, set, Vec3{1.08f, 0.0f, 0.0f}, Vec3{1.08f, 0, 0});
    CHECK(in_box.x == Approx(1.1f + r).margin(1e-5));  // out through the nearest (+x) face
    const Vec3 in_capsule = collide(sc.s, set, Vec3{0.0f, 1.25f, 0.05f}, Vec3{0, 1.25f, 0.05f});
    CHECK(in_capsule.z == Approx(0.1f + r).margin(1e-5));
    const Vec3 below_plane = collide(sc.s, set, Vec3{3.0f, -1.5f, 0.0f}, Vec3{3.0f, -1.5f, 0.0f});
    CHECK(below_plane.y == Approx(-1.0f + r).margin(1e-5));
    const Vec3 free = collide(sc.s, set, Vec3{3.0f, 3.0f, 3.0f}, Vec3{3.0f, 3.0f, 3.0f});
    CHECK(free.x == 3.0f);
    CHECK(free.y == 3.0f);
}

TEST_CASE("particle ids wrap past 0xFFFFFFFE to 0 and never take the dead marker", "[emit]") {
    CHECK(particle_id(5u, 3u) == 8u);
    CHECK(particle_id(0xFFFFFFFDu, 1u) == 0xFFFFFFFEu);
    CHECK(particle_id(0xFFFFFFFEu, 1u) == 0u);
    CHECK(particle_id(0xFFFFFFFEu, 0xFFFFFFFFull) == 0xFFFFFFFEu);  // a whole cycle later: the same id
    // Through the emission ops: a counter 2 short of the marker emits ..FD, ..FE, 0, 1.
    uint32_t count = 0, next_id = 0xFFFFFFFDu, blocked = 0;
    unsigned long long emitted = 0;
    std::vector<Vec4> pos(8), vel(8);
    std::vector<uint32_t> ids(8, 7u);
    const EmitBlockOp block{&count, &next_id,      8u,         Vec3{0, 0, 0}, 0.1f,      2u,
                            2u,     Vec3{0, 0, 0}, pos.data(), vel.data(),    ids.data()};
    for (uint32_t k = 0; k < 4; ++k) block(k);
    CommitEmissionOp{&count, &next_id, &emitted, &blocked, 8u, 4u}(0);
    CHECK(ids[0] == 0xFFFFFFFDu);
    CHECK(ids[1] == 0xFFFFFFFEu);
    CHECK(ids[2] == 0u);
    CHECK(ids[3] == 1u);
    CHECK(next_id == 2u);
    CHECK(count == 4u);
    for (uint32_t k = 0; k < 4; ++k) CHECK(ids[k] != kDeadId);
}

TEST_CASE("collider friction is Coulomb: tangential motion removed up to mu times the contact depth", "[collide]") {
    Scene sc(0.05f);
    const float r = sc.s.radius;
    const Collider floor = standing({kShapePlane, 0.0f, 0.0f, 0.5f, Vec3{0, 0, 0}}, Vec3{0, 0, 0});
    const ColliderPose at_origin{Vec3{0, 0, 0}, Mat3{{1, 0, 0, 0, 1, 0, 0, 0, 1}}};
    const ColliderView set{&floor, &at_origin, &at_origin, 1};
    // Pushed out by depth 0.2 r while sliding 0.1 r: static friction holds it (0.1 r <= mu 0.2 r).
    const Vec3 slow = collide(sc.s, set, Vec3{0.1f * r, 0.8f * r, 0.0f}, Vec3{0, r, 0});
    CHECK(slow.y == Approx(r).margin(1e-6));
    CHECK(slow.x == Approx(0.0f).margin(1e-6));
    // Sliding 1.0 r with depth 0.2 r: kinetic friction removes mu x depth = 0.1 r of it.
    const Vec3 fast = collide(sc.s, set, Vec3{1.0f * r, 0.8f * r, 0.0f}, Vec3{0, r, 0});
    CHECK(fast.x == Approx(0.9f * r).epsilon(1e-4));
    // No contact, no friction.
    const Vec3 free = collide(sc.s, set, Vec3{1.0f * r, 2.0f * r, 0.0f}, Vec3{0, 2.0f * r, 0});
    CHECK(free.x == Approx(1.0f * r).epsilon(1e-6));
}

TEST_CASE("boundary density: a box's share is the half-space's at a face, 1/4 at an edge, 1/8 at a corner",
          "[boundary]") {
    Scene sc(0.04f);
    sc.s.boundary_scale = 1.0f;
    const float h = sc.s.h;
    Collider c{};
    c.shape = kShapeBox;
    c.half_extents = Vec3{0.2f, 0.15f, 0.3f};
    // Turned, so the slabs are taken in the body frame.
    const ColliderPose pose{Vec3{0.5f, -0.2f, 0.1f}, rotation_matrix(Quat{0.0f, 0.38268343f, 0.0f, 0.92387953f})};
    const auto at = [&](Vec3 local) { return pose.position + mul(pose.rotation, local); };
    for (float y : {0.0f, 0.2f * h, 0.5f * h, 0.9f * h}) {  // above the top face's middle
        const BoundarySample b = box_boundary(sc.s, c, pose, at(Vec3{0.03f, 0.15f + y, -0.05f}));
        CHECK(b.density_ratio == Approx(boundary_phi(y / h)).margin(1e-5));
    }
    CHECK(box_boundary(sc.s, c, pose, at(Vec3{0.2f, 0.15f, 0.0f})).density_ratio == Approx(0.25f).margin(1e-5));
    CHECK(box_boundary(sc.s, c, pose, at(Vec3{-0.2f, 0.15f, 0.3f})).density_ratio == Approx(0.125f).margin(1e-5));
    // Beyond an edge, less than the closest point's half-space (which counts the whole plane).
    const Vec3 beyond = at(Vec3{0.2f + 0.3f * h, 0.15f + 0.3f * h, 0.0f});
    CHECK(box_boundary(sc.s, c, pose, beyond).density_ratio < 0.5f * boundary_phi(0.3f * std::sqrt(2.0f)));
    // The gradient is the share's, by central differences in world space.
    const Vec3 p = at(Vec3{0.2f + 0.2f * h, 0.1f, 0.3f + 0.1f * h});
    const BoundarySample b = box_boundary(sc.s, c, pose, p);
    const float e = 1e-4f;
    const Vec3 axes[3] = {Vec3{e, 0, 0}, Vec3{0, e, 0}, Vec3{0, 0, e}};
    const float grad[3] = {b.gradient.x, b.gradient.y, b.gradient.z};
    for (int a = 0; a < 3; ++a) {
        const float numeric = (box_boundary(sc.s, c, pose, p + axes[a]).density_ratio -
                               box_boundary(sc.s, c, pose, p - axes[a]).density_ratio) /
                              (2.0f * e);
        CHECK(grad[a] == Approx(numeric).margin(0.05f / h));
    }
}

TEST_CASE("boundary density: a rest lattice around a box's edge has rest density there", "[boundary]") {
    // A box filling x < 0, y > 0 (its +x face and its bottom meet in an edge along z), and a rest
    // lattice filling the rest, one radius off both faces. Without the edge term (κ = 0) the
    // product of the slabs gives the site one radius outside both faces 37 % more share than the
    // lattice misses there, and the site beside it 7 % less; with κ each site is at rest density.
    const float spacing = 0.04f, h = 2.0f * spacing;
    Scene sc(spacing);
    sc.s.boundary_scale = boundary_lattice_scale(spacing, h);
    const float kappa = box_edge_scale(spacing, h, sc.s.boundary_scale);
    CHECK(kappa > 0.0f);
    Collider c{};
    c.shape = kShapeBox;
    c.half_extents = Vec3{1.0f, 1.0f, 1.0f};
    const ColliderPose pose{Vec3{-1.0f, 1.0f, 0.0f}, rotation_matrix(Quat{0.0f, 0.0f, 0.0f, 1.0f})};
    const auto site = [&](int i, int j, int k) {
        return Vec3{(i + 0.5f) * spacing, (j - 0.5f) * spacing, k * spacing};
    };
    const auto in_box = [](int i, int j) { return i < 0 && j > 0; };
    const auto density_ratio = [&](int i, int j) {  // the site (i, j, 0): its fluid neighbours plus the box's share
        const Vec3 p = site(i, j, 0);
        float rho = 0.0f;
        for (int a = i - 2; a <= i + 2; ++a)
            for (int b = j - 2; b <= j + 2; ++b)
                for (int k = -2; k <= 2; ++k)
                    if (!in_box(a, b)) rho += poly6(length_sq(p - site(a, b, k)), sc.s.h2, sc.s.poly6_coef);
        return rho * sc.s.mass * sc.s.inv_rest_density + box_boundary(sc.s, c, pose, p).density_ratio;
    };
    const int sites[4][2] = {
        {0, 0}, {0, 1}, {-1, 0}, {0, 2}};  // diagonal, beside the face, under the bottom, a layer up
    sc.s.box_edge_scale = 0.0f;
    CHECK(density_ratio(0, 0) > 1.009f);
    CHECK(density_ratio(0, 1) < 0.991f);
    sc.s.box_edge_scale = kappa;
    for (const auto& ij : sites) {
        INFO("site " << ij[0] << ", " << ij[1]);
        CHECK(density_ratio(ij[0], ij[1]) == Approx(1.0f).margin(1e-3));
    }
    // The gradient is the share's with the edge term too, by central differences.
    const Vec3 p = site(0, 0, 0) + Vec3{0.13f * h, 0.07f * h, 0.0f};
    const BoundarySample b = box_boundary(sc.s, c, pose, p);
    const float e = 1e-4f;
    const float numeric_x = (box_boundary(sc.s, c, pose, p + Vec3{e, 0, 0}).density_ratio -
                             box_boundary(sc.s, c, pose, p - Vec3{e, 0, 0}).density_ratio) /
                            (2.0f * e);
    const float numeric_y = (box_boundary(sc.s, c, pose, p + Vec3{0, e, 0}).density_ratio -
                             box_boundary(sc.s, c, pose, p - Vec3{0, e, 0}).density_ratio) /
                            (2.0f * e);
    CHECK(b.gradient.x == Approx(numeric_x).margin(0.05f / h));
    CHECK(b.gradient.y == Approx(numeric_y).margin(0.05f / h));
}

TEST_CASE("boundary density: a rest lattice against a wall has rest density in its first layer", "[boundary]") {
    // γ is computed from the lattice; with it, Φ at one radius plus the layers present equals rest.
    const float spacing = 0.05f, h = 2.0f * spacing;
    const float gamma = boundary_lattice_scale(spacing, h);
    CHECK(gamma > 0.8f);
    CHECK(gamma < 1.0f);
    CHECK(boundary_phi(0.0f) == Approx(0.5f));
    CHECK(boundary_phi(1.0f) == 0.0f);
    // Φ' is Φ's derivative.
    for (float t : {0.1f, 0.25f, 0.5f, 0.8f}) {
        const float numeric = (boundary_phi(t + 1e-3f) - boundary_phi(t - 1e-3f)) / 2e-3f;
        CHECK(boundary_phi_slope(t) == Approx(numeric).epsilon(2e-3));
    }
    // A half lattice (y >= radius) filling the half-space above a floor at y = 0, through the
    // density op with the walls on: the first layer's density ratio is 1 within 0.5 %.
    Scene sc(spacing);
    sc.s.boundary_scale = gamma;
    sc.s.boundary_min = Vec3{-100, 0, -100};
    sc.s.wall_min = Vec3{-100, 0.5f * spacing, -100};
    const int n = 9;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < n; ++x) sc.add(Vec3{x * spacing, (y + 0.5f) * spacing, z * spacing});
    sc.finish();
    sc.densities(sc.pos);
    const uint32_t centre_floor = (n / 2) * 4 * n + 0 * n + n / 2;
    CHECK(sc.pos[centre_floor].y == Approx(0.5f * spacing));
    CHECK(sc.density[centre_floor] / sc.s.rest_density == Approx(1.0f).epsilon(5e-3));
}
