// White-box tests of mesh distance fields: the field that core/sdf.h's ops build on
// the CPU executor, against the analytic sphere and box the mesh approximates, within one cell
// (the design's bound). The [gpu] suite checks the CUDA build through the physics it feeds
// (test_gpu_mesh_colliders.cpp).
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "exec/cpu_exec.h"
#include "mesh_scenes.h"
#include "solver/mesh_field.h"
#include "world/world.h"

using namespace pbf;

namespace {

constexpr float kRadius = 0.02f, kKernel = 0.08f;

struct Field {
    CpuExec exec;
    MeshView view{};
    float reach = 0.0f;
    explicit Field(const pbf_mesh_desc& d) {
        REQUIRE(exec.init(1, 1).ok());
        const MeshLayout l = mesh_layout(d, kRadius, kKernel);
        const MeshBuild b = prepare_mesh(d, l, &reach);
        float* values = nullptr;
        REQUIRE(build_mesh_field(exec, b, &values).ok());
        view = b.grid;
        view.values = values;
        view.boundary = values + size_t(view.nx) * size_t(view.ny) * size_t(view.nz);
    }
    ~Field() { exec.release(const_cast<float*>(view.values)); }
};

// Probes random points within `reach` of the surface: the sampled distance is within one cell
// of the analytic one (both clamped to the band), and where the surface is within h the normal
// is within ~18° of the analytic one away from edges. Returns the largest error.
template <class Analytic>
float max_error(const Field& f, float box, Analytic analytic, float* worst_normal) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-box, box);
    float worst = 0.0f;
    *worst_normal = 1.0f;
    for (int k = 0; k < 20000; ++k) {
        const Vec3 p{u(rng), u(rng), u(rng)};
        Vec3 n_true;
        const float d_true = analytic(p, n_true);
        Vec3 n;
        const float d = mesh_distance(f.view, p, n);
        const float band = f.view.band;
        // Beyond the grid the field says band + the distance to the grid: compared as the band.
        worst = std::max(worst, std::fabs(clampf(d, -band, band) - clampf(d_true, -band, band)));
        if (std::fabs(d_true) < kKernel && !std::isnan(n_true.x))
            *worst_normal = std::min(*worst_normal, dot(n, n_true));
    }
    return worst;
}

}  // namespace

TEST_CASE("sdf: a sphere mesh's field matches the analytic sphere within one cell", "[mesh][sdf]") {
    const float R = 0.3f;
    const mesh::Mesh m = mesh::icosphere(R, 3);  // 1280 triangles; chords sag R/400 from the sphere
    const Field f(m.desc());
    REQUIRE(f.view.cell == kRadius);
    CHECK(f.reach == Approx(R));
    float normal = 0.0f;
    const float err = max_error(
        f, R + 0.15f,
        [&](Vec3 p, Vec3& n) {
            const float len = length(p);
            n = p * (1.0f / len);
            return len - R;
        },
        &normal);
    INFO("max |error| " << err << " m, cell " << f.view.cell << ", worst normal cos " << normal);
    CHECK(err <= f.view.cell);
    CHECK(normal > 0.95f);
}

TEST_CASE("sdf: a box mesh's field matches the analytic box within one cell, inside and out", "[mesh][sdf]") {
    const float e[3] = {0.2f, 0.1f, 0.15f};
    const mesh::Mesh m = mesh::box(e[0], e[1], e[2]);
    const Field f(m.desc());
    float normal = 0.0f;
    const float err = max_error(
        f, 0.35f,
        [&](Vec3 p, Vec3& n) {
            const Vec3 a{std::fabs(p.x) - e[0], std::fabs(p.y) - e[1], std::fabs(p.z) - e[2]};
            const Vec3 out = max3(a, Vec3{0, 0, 0});
            const float inside = std::fmin(std::fmax(a.x, std::fmax(a.y, a.z)), 0.0f);
            // Normals only off the edges (where the analytic one is a face's): NaN marks the rest.
            const int faces = (a.x > -kKernel) + (a.y > -kKernel) + (a.z > -kKernel);
            n = faces == 1 ? Vec3{a.x > -kKernel ? std::copysign(1.0f, p.x) : 0.0f,
                                  a.y > -kKernel ? std::copysign(1.0f, p.y) : 0.0f,
                                  a.z > -kKernel ? std::copysign(1.0f, p.z) : 0.0f}
                           : Vec3{NAN, NAN, NAN};
            if (length(out) > 0.0f) n = Vec3{NAN, NAN, NAN};
            return length(out) + inside;
        },
        &normal);
    INFO("max |error| " << err << " m, cell " << f.view.cell << ", worst normal cos " << normal);
    CHECK(err <= f.view.cell);
    CHECK(normal > 0.95f);
}

TEST_CASE("sdf: a mesh's boundary share is the half-space's at a face and the union's at an edge", "[mesh][sdf]") {
    const mesh::Mesh m = mesh::box(0.3f, 0.3f, 0.3f);
    const Field f(m.desc());
    float worst = 0.0f;
    for (float y = -kKernel; y <= kKernel; y += 0.005f) {
        Vec3 g;
        const float share = mesh_boundary(f.view, Vec3{0.01f, 0.3f + y, -0.02f}, g);
        // The half-space y' < 0 at distance y: Φ(y/h) outside, 1 - Φ(-y/h) inside.
        const float expected = y >= 0.0f ? boundary_phi(y / kKernel) : 1.0f - boundary_phi(-y / kKernel);
        worst = std::max(worst, std::fabs(share - expected));
        if (std::fabs(y) < 0.9f * kKernel) CHECK(g.y < 0.0f);  // rises into the solid
    }
    INFO("largest difference from the half-space's share at a face: " << worst);
    CHECK(worst < 0.03f);
    // Outside a convex edge the solid is the intersection of two half-spaces; inside a concave
    // one (a container's) the union: the share beside the edge's corner point is neither face's alone.
    Vec3 g;
    const float at_edge = mesh_boundary(f.view, Vec3{0.3f + 0.02f, 0.3f + 0.02f, 0.0f}, g);
    CHECK(at_edge < boundary_phi(0.02f / kKernel) * 0.75f);
}

TEST_CASE("sdf: an open mesh is a shell of its thickness on both sides", "[mesh][sdf]") {
    const mesh::Mesh m = mesh::plane(0.3f, 6);
    pbf_mesh_desc d = m.desc(false);
    d.thickness = 0.06f;
    const Field f(d);
    for (float y : {-0.1f, -0.05f, -0.03f, -0.01f, 0.0f, 0.01f, 0.03f, 0.05f, 0.1f}) {
        Vec3 n;
        const float got = mesh_distance(f.view, Vec3{0.05f, y, -0.07f}, n);
        INFO("y = " << y);
        // Exact at the grid's points and linear between them: the kink at the surface itself
        // (within a cell) is cut by up to half a cell.
        CHECK(got == Approx(std::fabs(y) - 0.03f).margin(std::fabs(y) < f.view.cell ? 0.5f * f.view.cell : 1e-4f));
        if (std::fabs(y) > 0.011f) CHECK(n.y == Approx(y > 0 ? 1.0f : -1.0f).margin(1e-3));
    }
}

TEST_CASE("sdf: beyond the grid the distance grows and never overestimates", "[mesh][sdf]") {
    const mesh::Mesh m = mesh::box(0.1f, 0.1f, 0.1f);
    const Field f(m.desc());
    Vec3 n;
    const float d = mesh_distance(f.view, Vec3{2.0f, 0.0f, 0.0f}, n);
    CHECK(d <= 1.9f);
    CHECK(d > f.view.band);
    CHECK(n.x == Approx(1.0f));
}
