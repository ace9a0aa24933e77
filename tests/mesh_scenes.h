// Mesh collider scenes, shared by the CPU suite (test_mesh_colliders.cpp) and its
// [gpu] twin (test_gpu_mesh_colliders.cpp): triangle meshes built by the tests (boxes, a hollow
// box container, an icosphere, an open plane), water resting in a box-mesh container against
// the same water in the domain's own walls, an open plane holding a pool, and the leak test of
// a closed container moved and turned by the engine. Black-box: only the public header.
#pragma once
#include "support.h"

namespace mesh {

using scene::set3;

constexpr float kR = 0.02f, kSpacing = 2.0f * kR, kH = 4.0f * kR;

struct Mesh {
    std::vector<float> v;     // xyz
    std::vector<uint32_t> i;  // 3 per triangle, counter-clockwise seen from outside
    uint32_t add_vertex(float x, float y, float z) {
        v.insert(v.end(), {x, y, z});
        return uint32_t(v.size() / 3 - 1);
    }
    void add_triangle(uint32_t a, uint32_t b, uint32_t c) { i.insert(i.end(), {a, b, c}); }
    pbf_mesh_desc desc(bool closed = true) const {
        pbf_mesh_desc d = pbf_mesh_desc_default();
        d.vertices = v.data();
        d.vertex_count = uint32_t(v.size() / 3);
        d.indices = i.data();
        d.triangle_count = uint32_t(i.size() / 3);
        d.closed = closed ? 1u : 0u;
        return d;
    }
};

// The box [-e, e] (centred at the origin); inward: its faces wound to face inside (a cavity).
inline void add_box(Mesh& m, const float e[3], bool inward = false) {
    uint32_t c[8];
    for (int k = 0; k < 8; ++k) c[k] = m.add_vertex(k & 1 ? e[0] : -e[0], k & 2 ? e[1] : -e[1], k & 4 ? e[2] : -e[2]);
    // Each face as a quad, counter-clockwise seen from outside.
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        if (inward) {
            m.add_triangle(c[q[0]], c[q[2]], c[q[1]]);
            m.add_triangle(c[q[0]], c[q[3]], c[q[2]]);
        } else {
            m.add_triangle(c[q[0]], c[q[1]], c[q[2]]);
            m.add_triangle(c[q[0]], c[q[2]], c[q[3]]);
        }
    }
}

inline Mesh box(float ex, float ey, float ez) {
    Mesh m;
    const float e[3] = {ex, ey, ez};
    add_box(m, e);
    return m;
}

// A closed container: the cavity [-inner, inner] inside walls `wall` thick (two nested boxes,
// the inner one wound inward: watertight, the cavity outside the solid).
inline Mesh hollow_box(float ix, float iy, float iz, float wall) {
    Mesh m;
    const float outer[3] = {ix + wall, iy + wall, iz + wall}, inner[3] = {ix, iy, iz};
    add_box(m, outer);
    add_box(m, inner, true);
    return m;
}

// An icosphere of radius R: an icosahedron subdivided `levels` times, vertices on the sphere.
inline Mesh icosphere(float R, int levels) {
    Mesh m;
    const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
    const float base[12][3] = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                               {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
    auto on_sphere = [&](float x, float y, float z) {
        const float s = R / std::sqrt(x * x + y * y + z * z);
        return m.add_vertex(x * s, y * s, z * s);
    };
    for (const auto& p : base) on_sphere(p[0], p[1], p[2]);
    std::vector<uint32_t> tris = {0, 11, 5,  0, 5,  1, 0, 1, 7, 0, 7,  10, 0, 10, 11, 1, 5, 9, 5, 11,
                                  4, 11, 10, 2, 10, 7, 6, 7, 1, 8, 3,  9,  4, 3,  4,  2, 3, 2, 6, 3,
                                  6, 8,  3,  8, 9,  4, 9, 5, 2, 4, 11, 6,  2, 10, 8,  6, 7, 9, 8, 1};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            const auto key = std::make_pair(std::min(a, b), std::max(a, b));
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            const uint32_t k =
                on_sphere(m.v[3 * a] + m.v[3 * b], m.v[3 * a + 1] + m.v[3 * b + 1], m.v[3 * a + 2] + m.v[3 * b + 2]);
            mid[key] = k;
            return k;
        };
        std::vector<uint32_t> next;
        for (size_t k = 0; k < tris.size(); k += 3) {
            const uint32_t a = tris[k], b = tris[k + 1], c = tris[k + 2];
            const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
            next.insert(next.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
        }
        tris.swap(next);
    }
    m.i = tris;
    return m;
}

// An open square of half size `half` in the plane y = 0: n x n quads (a terrain piece).
inline Mesh plane(float half, int n) {
    Mesh m;
    for (int z = 0; z <= n; ++z)
        for (int x = 0; x <= n; ++x) m.add_vertex(-half + 2 * half * x / n, 0.0f, -half + 2 * half * z / n);
    for (int z = 0; z < n; ++z)
        for (int x = 0; x < n; ++x) {
            const uint32_t a = uint32_t(z * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
            m.add_triangle(a, c, d);
            m.add_triangle(a, d, b);
        }
    return m;
}

inline pbf_mesh_id create_mesh(pbf_world_id w, const pbf_mesh_desc& d) {
    pbf_mesh_id id{0, 0};
    REQUIRE_PBF(pbf_world_create_mesh(w, &d, &id));
    return id;
}

inline pbf_collider_id mesh_collider(pbf_world_id w, pbf_mesh_id m, const float pos[3],
                                     pbf_collider_motion motion = PBF_MOTION_STATIC) {
    pbf_collider_desc c = pbf_collider_desc_default();
    c.shape = PBF_SHAPE_MESH;
    c.motion = motion;
    c.mesh = m;
    set3(c.position, pos[0], pos[1], pos[2]);
    pbf_collider_id id{0, 0};
    REQUIRE_PBF(pbf_world_create_collider(w, &c, &id));
    return id;
}

// Mean density ratio (the positions' w) and mean height of the particles.
struct Rest {
    double density = 0, height = 0;
    uint32_t count = 0;
};
inline Rest rest_of(pbf_world_id w) {
    const scene::Particles p = scene::read(w);
    Rest r;
    r.count = p.count;
    for (uint32_t k = 0; k < p.count; ++k) {
        r.density += p.pos[4 * k + 3];
        r.height += p.pos[4 * k + 1];
    }
    r.density /= std::max(1u, p.count);
    r.height /= std::max(1u, p.count);
    return r;
}

// Water 0.32 m square and 0.24 m deep settled for two seconds in a container 0.32 m square
// inside: the domain's own walls (analytic) or a closed hollow-box mesh in a larger domain.
// Both report the mean density ratio and the mean height above the container's floor.
inline Rest settled_in_container(pbf_backend backend, bool mesh_container) {
    const float inner = 0.16f, wall = 0.08f;
    pbf_world_desc d = scene::tank(backend, kR, 2 * inner, 0.48f, 2 * inner, 8192);
    if (mesh_container) {  // the same cavity, [0, 0.32] x [0, 0.48] x [0, 0.32], in a larger domain
        set3(d.domain_min, -0.4f, -0.4f, -0.4f);
        set3(d.domain_max, 0.8f, 0.9f, 0.8f);
    }
    pbf_world_id w = scene::create(d);
    if (mesh_container) {
        const Mesh m = hollow_box(inner, 0.24f, inner, wall);
        const pbf_mesh_id id = create_mesh(w, m.desc());
        const float at[3] = {inner, 0.24f, inner};
        mesh_collider(w, id, at);
    }
    scene::fill(w, 0, 0, 0, 2 * inner, 0.24f, 2 * inner);
    for (int k = 0; k < 120; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    Rest r = rest_of(w);
    REQUIRE_PBF(pbf_world_destroy(w));
    return r;
}

// An open plane (terrain piece, default thickness 2 r) 0.2 m above the floor, wider than the
// domain (the water cannot flow around it), under a falling block of water: returns the lowest
// particle centre (the pool rests on the shell: thickness/2 + r above the plane) and the
// particles below the plane (leaked through).
struct PlaneResult {
    float lowest = 0;
    uint32_t leaked = 0, count = 0;
};
inline PlaneResult pool_on_open_plane(pbf_backend backend) {
    pbf_world_desc d = scene::tank(backend, kR, 1.0f, 0.8f, 1.0f, 8192);
    pbf_world_id w = scene::create(d);
    const Mesh m = plane(0.6f, 12);
    const pbf_mesh_id id = create_mesh(w, m.desc(false));
    const float at[3] = {0.5f, 0.2f, 0.5f};
    mesh_collider(w, id, at);
    scene::fill(w, 0.36f, 0.28f, 0.36f, 0.64f, 0.52f, 0.64f);
    for (int k = 0; k < 90; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const scene::Particles p = scene::read(w);
    PlaneResult r;
    r.lowest = 1e9f;
    r.count = p.count;
    for (uint32_t k = 0; k < p.count; ++k) {
        const float y = p.pos[4 * k + 1];
        if (y < 0.2f)
            ++r.leaked;
        else
            r.lowest = std::min(r.lowest, y);
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    return r;
}

// Water poured on a sphere (radius 0.2 m, centre 0.3 m up) from above: an icosphere mesh
// (1280 triangles) or the analytic sphere. Returns the closest any particle centre came to the
// sphere's surface over a second while the water slid over it (contact keeps it one radius out).
inline float closest_to_sphere(pbf_backend backend, bool as_mesh) {
    pbf_world_desc d = scene::tank(backend, kR, 0.8f, 1.0f, 0.8f, 8192);
    pbf_world_id w = scene::create(d);
    const float c[3] = {0.4f, 0.3f, 0.4f}, R = 0.2f;
    if (as_mesh) {
        const Mesh m = icosphere(R, 3);
        mesh_collider(w, create_mesh(w, m.desc()), c);
    } else {
        pbf_collider_desc s = pbf_collider_desc_default();
        s.shape = PBF_SHAPE_SPHERE;
        s.radius = R;
        set3(s.position, c[0], c[1], c[2]);
        pbf_collider_id id;
        REQUIRE_PBF(pbf_world_create_collider(w, &s, &id));
    }
    scene::fill(w, 0.3f, 0.56f, 0.3f, 0.5f, 0.68f, 0.5f);
    float closest = 1e9f;
    for (int f = 0; f < 60; ++f) {
        REQUIRE_PBF(pbf_world_step(w, kDt));
        const scene::Particles p = scene::read(w);
        for (uint32_t k = 0; k < p.count; ++k) {
            const float dx = p.pos[4 * k] - c[0], dy = p.pos[4 * k + 1] - c[1], dz = p.pos[4 * k + 2] - c[2];
            closest = std::min(closest, std::sqrt(dx * dx + dy * dy + dz * dz) - R);
        }
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    return closest;
}

// ---- the leak test: fast containers do not leak --------------------------------------------
// A closed hollow-box mesh, cavity 0.32 x 0.24 x 0.32 m, walls 2 r thick, half full of water,
// moved by the engine every frame (1/60 s) along a circle by `travel` particle radii (a chord)
// and turned by `degrees` about a tilted axis. Counts the particles outside the cavity (in the
// container's frame, with a tolerance of one radius) after each frame; returns the most.
struct LeakResult {
    uint32_t outside_max = 0, count = 0;
    int first_frame = -1;  // the first frame that lost a particle
};
inline void quat_axis_angle(float q[4], const float axis[3], float angle) {
    const float n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    const float s = std::sin(0.5f * angle) / n;
    q[0] = axis[0] * s;
    q[1] = axis[1] * s;
    q[2] = axis[2] * s;
    q[3] = std::cos(0.5f * angle);
}
inline void rotate_inverse(const double q[4], const double v[3], double out[3]) {  // q* v q
    // v' = v + 2w(u x v) + 2u x (u x v) with u = -q.xyz for the inverse rotation.
    const double u[3] = {-q[0], -q[1], -q[2]}, w = q[3];
    const double c1[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    const double c2[3] = {u[1] * c1[2] - u[2] * c1[1], u[2] * c1[0] - u[0] * c1[2], u[0] * c1[1] - u[1] * c1[0]};
    for (int a = 0; a < 3; ++a) out[a] = v[a] + 2 * w * c1[a] + 2 * c2[a];
}
inline LeakResult shaken_container(pbf_backend backend, float travel_radii, float degrees, int frames,
                                   uint32_t max_substeps = 64) {
    const float inner[3] = {0.16f, 0.12f, 0.16f}, wall = 2 * kR;
    const float travel = travel_radii * kR;
    // A circle whose chord per frame is `travel`, at most a quarter turn per frame.
    const float step_angle = 0.5f;  // radians of the path per frame
    const float path_r = 0.5f * travel / std::sin(0.5f * step_angle);
    const float centre[3] = {0.0f, 0.0f, 0.0f};
    pbf_world_desc d = scene::tank(backend, kR, 1, 1, 1, 8192);
    const float extent = path_r + 0.6f;
    set3(d.domain_min, -extent, -extent, -0.6f);
    set3(d.domain_max, extent, extent, 0.6f);
    d.solver.max_substeps = max_substeps;
    pbf_world_id w = scene::create(d);
    const Mesh m = hollow_box(inner[0], inner[1], inner[2], wall);
    const pbf_mesh_id id = create_mesh(w, m.desc());
    float pos[3] = {centre[0] + path_r, centre[1], centre[2]};
    const pbf_collider_id c = mesh_collider(w, id, pos, PBF_MOTION_KINEMATIC);
    // Half full: the lower half of the cavity, a lattice clear of the walls.
    scene::fill(w, pos[0] - inner[0], pos[1] - inner[1], pos[2] - inner[2], pos[0] + inner[0], pos[1],
                pos[2] + inner[2]);
    LeakResult r;
    const float axis[3] = {0.3f, 1.0f, 0.5f};
    for (int f = 1; f <= frames; ++f) {
        const float a = step_angle * float(f);
        pos[0] = centre[0] + path_r * std::cos(a);
        pos[1] = centre[1] + path_r * std::sin(a);
        float q[4];
        quat_axis_angle(q, axis, float(f) * degrees * 3.14159265f / 180.0f);
        REQUIRE_PBF(pbf_collider_set_target_pose(w, c, pos, q));
        REQUIRE_PBF(pbf_world_step(w, kDt));
        const scene::Particles p = scene::read(w);
        r.count = p.count;
        const double qd[4] = {q[0], q[1], q[2], q[3]};
        uint32_t outside = 0;
        for (uint32_t k = 0; k < p.count; ++k) {
            const double rel[3] = {p.pos[4 * k] - pos[0], p.pos[4 * k + 1] - pos[1], p.pos[4 * k + 2] - pos[2]};
            double local[3];
            rotate_inverse(qd, rel, local);
            bool in = true;
            for (int ax = 0; ax < 3; ++ax) in = in && std::fabs(local[ax]) <= inner[ax] + kR;
            if (!in) ++outside;
        }
        if (outside > 0 && r.first_frame < 0) r.first_frame = f;
        r.outside_max = std::max(r.outside_max, outside);
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    return r;
}

// ---- the checks both suites run (CPU in test_mesh_colliders.cpp, CUDA in its [gpu] twin) -------
inline void check_sphere_contact(pbf_backend backend) {
    const float analytic = closest_to_sphere(backend, false);
    const float sampled = closest_to_sphere(backend, true);
    INFO("closest centre to the surface: analytic " << analytic << " m, mesh " << sampled << " m");
    CHECK(analytic == Approx(kR).margin(0.1f * kR));
    CHECK(std::fabs(sampled - analytic) < kR);  // within one cell (cell = r)
}

inline void check_container_rest(pbf_backend backend) {
    const Rest walls = settled_in_container(backend, false);
    const Rest mesh = settled_in_container(backend, true);
    INFO("density ratio: walls " << walls.density << ", mesh " << mesh.density << "; mean height: walls "
                                 << walls.height << ", mesh " << mesh.height);
    REQUIRE(mesh.count == walls.count);
    CHECK(mesh.density == Approx(walls.density).epsilon(0.01));
    // Packing against the walls would lower the water: its mean height agrees within a tenth of
    // a particle spacing.
    CHECK(std::fabs(mesh.height - walls.height) < 0.1 * kSpacing);
}

inline void check_open_plane(pbf_backend backend) {
    const PlaneResult r = pool_on_open_plane(backend);
    INFO("lowest centre above the plane " << r.lowest - 0.2f << " m; leaked " << r.leaked << " of " << r.count);
    CHECK(r.leaked == 0u);
    // Resting on the shell: thickness/2 (one radius by default) + one radius above the plane.
    CHECK(r.lowest - 0.2f == Approx(2 * kR).margin(0.5f * kR));
}

// The leak test: 20 particle radii and 30 degrees per frame, 600 frames.
inline void check_no_leak(pbf_backend backend) {
    const LeakResult r = shaken_container(backend, 20.0f, 30.0f, 600);
    INFO("particles " << r.count << ", most outside " << r.outside_max << ", first loss at frame " << r.first_frame);
    CHECK(r.count == 192u);
    CHECK(r.outside_max == 0u);
}

}  // namespace mesh
