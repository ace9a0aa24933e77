// White-box tests of the colliders' broad phase (core/collider_grid.h, built by
// solver/collider_broadphase.cpp): every query must meet exactly the colliders whose bounds its
// box meets, each once, whatever the grid's size, hash collisions, budget and the coordinates.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "core/collider_grid.h"
#include "solver/backend.h"
#include "solver/collider_broadphase.h"

using namespace pbf;

namespace {

constexpr float kReach = 0.04f;  // the kernel radius of the queries

// n boxes' bounds around `centre`: most small (0.02-0.3 m), some long (up to 3 m, more cells
// than a collider may be listed in), and every 17th unbounded (a plane).
std::vector<Collider> random_colliders(uint32_t n, Vec3 centre, std::mt19937& rng) {
    std::uniform_real_distribution<float> pos(-1.5f, 1.5f), small(0.01f, 0.15f), large(0.5f, 1.5f);
    std::vector<Collider> out(n);
    for (uint32_t k = 0; k < n; ++k) {
        Collider& c = out[k];
        c = Collider{};
        c.shape = kShapeBox;
        const Vec3 p = centre + Vec3{pos(rng), pos(rng), pos(rng)};
        const bool long_one = k % 5 == 0;
        const Vec3 half{long_one ? large(rng) : small(rng), small(rng), small(rng)};
        c.bounds = Bounds{p - half, p + half};
        if (k % 17 == 3)
            c.bounds = Bounds{Vec3{-kUnbounded, -kUnbounded, -kUnbounded}, Vec3{kUnbounded, kUnbounded, kUnbounded}};
    }
    return out;
}

// For each query box, how often the grid calls back each collider, against the bounds test.
void check_queries(const std::vector<Collider>& shapes, const ColliderGridCapacity& cap, Vec3 centre, std::mt19937& rng,
                   uint32_t* listed_out = nullptr) {
    ColliderGridLists lists;
    build_collider_grid(shapes, kReach, cap, &lists);
    ColliderView cv;
    cv.shapes = shapes.data();
    cv.count = uint32_t(shapes.size());
    cv.grid = lists.grid;
    if (!lists.bucket_begin.empty()) {
        cv.grid.bucket_begin = lists.bucket_begin.data();
        cv.grid.entries = lists.entries.data();
    }
    if (listed_out) *listed_out = lists.bucket_begin.empty() ? 0 : uint32_t(lists.entries.size()) - lists.grid.unbinned;
    std::uniform_real_distribution<float> pos(-1.8f, 1.8f), unit(-1.0f, 1.0f);
    const float paths[] = {0.0f, 0.01f, 0.1f, 0.5f, 4.0f};  // a point, short to level-crossing paths
    std::vector<int> calls(shapes.size());
    uint64_t met = 0;
    for (int q = 0; q < 4000; ++q) {
        const Vec3 a = centre + Vec3{pos(rng), pos(rng), pos(rng)};
        const float len = paths[q % 5];
        const Vec3 b = a + Vec3{unit(rng), unit(rng), unit(rng)} * len;
        const float margin = q % 2 ? kReach : 0.5f * kReach;  // h or the particle radius
        const Vec3 m{margin, margin, margin};
        const Vec3 lo = min3(a, b) - m, hi = max3(a, b) + m;
        std::fill(calls.begin(), calls.end(), 0);
        if (len == 0.0f) {  // a particle grown by h or r
            for_each_collider_near(cv, a, margin, [&](uint32_t k) { ++calls[k]; });
        } else {  // a path grown by r or h; the candidates' bounds tested here, as collide does
            for_each_collider_on_path(cv, a, b, margin, [&](uint32_t k) {
                if (overlaps(shapes[k].bounds, lo, hi)) ++calls[k];
            });
        }
        for (size_t k = 0; k < shapes.size(); ++k) {
            const int expected = overlaps(shapes[k].bounds, lo, hi) ? 1 : 0;
            met += uint64_t(expected);
            if (calls[k] != expected) {
                INFO("query " << q << " path " << len << " collider " << k << ": called " << calls[k]
                              << " times, expected " << expected);
                REQUIRE(calls[k] == expected);
            }
        }
    }
    CHECK(met > 4000);  // the queries do meet colliders
}

}  // namespace

TEST_CASE("collider grid: each query meets exactly the colliders its box meets, once", "[collider_grid]") {
    std::mt19937 rng(7);
    const std::vector<Collider> shapes = random_colliders(300, Vec3{0, 0, 0}, rng);
    uint32_t listed = 0;
    check_queries(shapes, collider_grid_capacity(2048), Vec3{0, 0, 0}, rng, &listed);
    CHECK(listed > 300);  // a real grid: most colliders listed, some in several cells
}

TEST_CASE("collider grid: hash collisions and an exhausted entry budget change nothing", "[collider_grid]") {
    std::mt19937 rng(11);
    const std::vector<Collider> shapes = random_colliders(200, Vec3{0, 0, 0}, rng);
    ColliderGridCapacity tiny;
    tiny.buckets = 16;   // every bucket shared by many cells
    tiny.entries = 300;  // room for some colliders' cells only: the rest are walked by all
    uint32_t listed = 0;
    check_queries(shapes, tiny, Vec3{0, 0, 0}, rng, &listed);
    CHECK(listed > 0);
    CHECK(listed <= 100);
}

TEST_CASE("collider grid: 1 km from the origin", "[collider_grid]") {
    std::mt19937 rng(13);
    const Vec3 far{1000.0f, -700.0f, 950.0f};
    check_queries(random_colliders(150, far, rng), collider_grid_capacity(256), far, rng);
}

TEST_CASE("collider grid: few colliders, or none bounded, build no grid", "[collider_grid]") {
    std::mt19937 rng(17);
    ColliderGridLists lists;
    build_collider_grid(random_colliders(kLinearColliders, Vec3{0, 0, 0}, rng), kReach, collider_grid_capacity(64),
                        &lists);
    CHECK(lists.bucket_begin.empty());
    std::vector<Collider> planes(40);
    for (Collider& c : planes)
        c.bounds = Bounds{Vec3{-kUnbounded, -kUnbounded, -kUnbounded}, Vec3{kUnbounded, kUnbounded, kUnbounded}};
    build_collider_grid(planes, kReach, collider_grid_capacity(64), &lists);
    CHECK(lists.bucket_begin.empty());
    CHECK(collider_grid_capacity(kLinearColliders).buckets == 0);
    // Lists of one world's build fit their capacity, each within a 256 KB staging slot.
    const ColliderGridCapacity cap = collider_grid_capacity(kMaxColliderCapacity);
    CHECK((cap.buckets + 1) * sizeof(uint32_t) <= 256 * 1024);
    CHECK(cap.entries * sizeof(uint32_t) <= 256 * 1024);
    build_collider_grid(random_colliders(kMaxColliderCapacity, Vec3{0, 0, 0}, rng), kReach, cap, &lists);
    CHECK(lists.entries.size() <= cap.entries);
    CHECK(lists.bucket_begin.size() <= cap.buckets + 1);
}

namespace {

Quat random_rotation(std::mt19937& rng) {
    std::normal_distribution<float> g(0.0f, 1.0f);
    Quat q{g(rng), g(rng), g(rng), g(rng)};
    const float inv = 1.0f / std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return Quat{q.x * inv, q.y * inv, q.z * inv, q.w * inv};
}

// Points on the shape's surface in its own frame: a box's corners, a capsule's or sphere's
// extreme points along many directions.
std::vector<Vec3> surface_samples(const Collider& c, std::mt19937& rng) {
    std::vector<Vec3> pts;
    if (c.shape == kShapeBox) {
        for (int m = 0; m < 8; ++m)
            pts.push_back(Vec3{m & 1 ? c.half_extents.x : -c.half_extents.x,
                               m & 2 ? c.half_extents.y : -c.half_extents.y,
                               m & 4 ? c.half_extents.z : -c.half_extents.z});
        return pts;
    }
    std::normal_distribution<float> g(0.0f, 1.0f);
    for (int m = 0; m < 200; ++m) {
        Vec3 d{g(rng), g(rng), g(rng)};
        d = d * (c.radius / length(d));
        const float end = c.shape == kShapeCapsule ? (m % 2 ? c.half_height : -c.half_height) : 0.0f;
        pts.push_back(Vec3{0.0f, end, 0.0f} + d);
    }
    return pts;
}

}  // namespace

TEST_CASE("collider grid: a turning collider's step bounds hold it at every pose of the step", "[collider_grid]") {
    std::mt19937 rng(23);
    std::uniform_real_distribution<float> u(0.05f, 0.5f), pos(-1.0f, 1.0f), small(0.0f, 0.2f);
    const uint32_t shapes[] = {kShapeBox, kShapeSphere, kShapeCapsule};
    double tightest = 1.0;  // how much of the ball bound the swept box uses, at small turns
    for (int trial = 0; trial < 600; ++trial) {
        Collider c{};
        c.shape = shapes[trial % 3];
        c.radius = u(rng);
        c.half_height = u(rng);
        c.half_extents = Vec3{u(rng), u(rng), u(rng)};
        ColliderKey k;
        k.from_position = Vec3{pos(rng), pos(rng), pos(rng)};
        k.to_position = k.from_position + Vec3{pos(rng), pos(rng), pos(rng)} * (trial % 4 == 0 ? 0.0f : 0.3f);
        k.from_rotation = random_rotation(rng);
        // Any turn (random) or a small one (a game's per-frame spin).
        if (trial % 2) {
            k.to_rotation = random_rotation(rng);
        } else {
            const Vec3 axis = Vec3{pos(rng), pos(rng), pos(rng)} * (1.0f / 1.8f);
            const float angle = small(rng), sn = std::sin(0.5f * angle) / std::fmax(length(axis), 1e-6f);
            const Quat r{axis.x * sn, axis.y * sn, axis.z * sn, std::cos(0.5f * angle)};
            const Quat a = k.from_rotation;  // r * a
            k.to_rotation =
                Quat{r.w * a.x + r.x * a.w + r.y * a.z - r.z * a.y, r.w * a.y - r.x * a.z + r.y * a.w + r.z * a.x,
                     r.w * a.z + r.x * a.y - r.y * a.x + r.z * a.w, r.w * a.w - r.x * a.x - r.y * a.y - r.z * a.z};
        }
        const Bounds b = swept_bounds(c, k);
        const std::vector<Vec3> pts = surface_samples(c, rng);
        float outside = 0.0f;  // the farthest a surface point gets outside the bounds
        for (int step = 0; step <= 64; ++step) {
            const ColliderPose pose = pose_between(k, float(step) / 64.0f);
            for (const Vec3& q : pts) {
                const Vec3 x = pose.position + mul(pose.rotation, q);
                const Vec3 below = b.lo - x, above = x - b.hi;
                outside = std::max({outside, below.x, below.y, below.z, above.x, above.y, above.z});
            }
        }
        INFO("trial " << trial << " shape " << c.shape);
        REQUIRE(outside <= 1e-5f);
        if (trial % 2 == 0 && c.shape == kShapeBox) {
            const float reach = collider_reach(c);
            const Vec3 path = max3(k.from_position, k.to_position) - min3(k.from_position, k.to_position);
            const double ball = double(path.x + 2 * reach) * (path.y + 2 * reach) * (path.z + 2 * reach);
            tightest = std::min(tightest, double(b.hi.x - b.lo.x) * (b.hi.y - b.lo.y) * (b.hi.z - b.lo.z) / ball);
        }
    }
    CHECK(tightest < 0.5);  // a box turning a little is bounded well inside its reach's ball
}

TEST_CASE("collider grid: a collider kilometres wide among small ones is walked by every query", "[collider_grid]") {
    std::mt19937 rng(29);
    std::vector<Collider> shapes = random_colliders(100, Vec3{0, 0, 0}, rng);
    // 20,000 km across: far more cells than a collider may be listed in.
    shapes[7].bounds = Bounds{Vec3{-1.0e7f, -1.0e7f, -1.0e7f}, Vec3{1.0e7f, 1.0e7f, 1.0e7f}};
    ColliderGridLists lists;
    build_collider_grid(shapes, kReach, collider_grid_capacity(256), &lists);
    REQUIRE_FALSE(lists.bucket_begin.empty());
    bool always = false;
    for (uint32_t e = 0; e < lists.grid.unbinned; ++e) always = always || lists.entries[e] == 7;
    CHECK(always);
    check_queries(shapes, collider_grid_capacity(256), Vec3{0, 0, 0}, rng);
}
