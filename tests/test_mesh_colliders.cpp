// Mesh colliders on the CPU backend, through the C ABI: the calls and their refusals,
// which meshes hold water emitted inside them (the container recipe of docs/api.md), water at
// rest in a box-mesh container against the same water in the domain's walls, an open plane
// holding a pool, and the leak test of a fast container. The scenes are in mesh_scenes.h
// ([gpu] twins in test_gpu_mesh_colliders.cpp); the field's accuracy is checked white-box in
// test_sdf.cpp.
#include "mesh_scenes.h"

using namespace mesh;

TEST_CASE("mesh: create, share, destroy; a mesh in use is not destroyed", "[mesh][api]") {
    TestWorld w;
    const Mesh m = box(0.1f, 0.1f, 0.1f);
    const pbf_mesh_desc d = m.desc();
    pbf_mesh_id a{}, b{};
    REQUIRE_OK(pbf_world_create_mesh(w, &d, &a));
    REQUIRE_OK(pbf_world_create_mesh(w, &d, &b));
    CHECK(a.generation != 0);
    CHECK(!(a.index == b.index && a.generation == b.generation));
    pbf_collider_desc c = collider_desc(PBF_SHAPE_MESH);
    c.mesh = a;
    pbf_collider_id c1{}, c2{};
    REQUIRE_OK(pbf_world_create_collider(w, &c, &c1));
    c.position[0] = 0.3f;
    c.motion = PBF_MOTION_KINEMATIC;
    REQUIRE_OK(pbf_world_create_collider(w, &c, &c2));  // shared by two colliders
    CHECK_FAILS(pbf_world_destroy_mesh(w, a), PBF_ERROR_INVALID_STATE, "collider");
    REQUIRE_OK(pbf_world_destroy_collider(w, c1));
    CHECK_FAILS(pbf_world_destroy_mesh(w, a), PBF_ERROR_INVALID_STATE, "collider");
    REQUIRE_OK(pbf_world_destroy_collider(w, c2));
    REQUIRE_OK(pbf_world_destroy_mesh(w, a));
    CHECK_FAILS(pbf_world_destroy_mesh(w, a), PBF_ERROR_INVALID_HANDLE, "mesh");
    // A stale or forged mesh in a collider desc is refused; the other mesh still works.
    CHECK_FAILS(pbf_world_create_collider(w, &c, &c1), PBF_ERROR_INVALID_HANDLE, "mesh");
    c.mesh = pbf_mesh_id{b.index, b.generation + 1000};
    CHECK_FAILS(pbf_world_create_collider(w, &c, &c1), PBF_ERROR_INVALID_HANDLE, "mesh");
    c.mesh = b;
    REQUIRE_OK(pbf_world_create_collider(w, &c, &c1));
    w.emit_default_block();
    w.require_usable(w.count());
    // Another world's mesh handle is not this world's.
    TestWorld other;
    c.mesh = b;
    CHECK_FAILS(pbf_world_create_collider(other, &c, &c2), PBF_ERROR_INVALID_HANDLE, "mesh");
}

TEST_CASE("mesh: the arrays are copied at creation", "[mesh][api]") {
    TestWorld w;
    Mesh m = box(0.1f, 0.1f, 0.1f);
    pbf_mesh_desc d = m.desc();
    pbf_mesh_id id{};
    REQUIRE_OK(pbf_world_create_mesh(w, &d, &id));
    std::fill(m.v.begin(), m.v.end(), kNaN);  // the caller reuses its buffers
    std::fill(m.i.begin(), m.i.end(), 0xFFFFFFFFu);
    pbf_collider_desc c = collider_desc(PBF_SHAPE_MESH);
    c.mesh = id;
    pbf_collider_id cid{};
    REQUIRE_OK(pbf_world_create_collider(w, &c, &cid));
    w.emit(block(-0.1f, 0.7f, -0.1f, 0.1f, 0.8f, 0.1f));  // lands on the box (top at y = 0.6)
    for (int k = 0; k < 60; ++k) REQUIRE_OK(pbf_world_step(w, kDt));
    const std::vector<float> p = w.positions();
    for (size_t k = 0; k < p.size(); k += 4) {
        REQUIRE(std::isfinite(p[k + 1]));
        if (std::fabs(p[k]) < 0.08f && std::fabs(p[k + 2]) < 0.08f) CHECK(p[k + 1] > 0.6f);
    }
}

TEST_CASE("mesh: refused descs name their check and change nothing", "[mesh][api]") {
    TestWorld w;
    Mesh m = box(0.1f, 0.1f, 0.1f);
    pbf_mesh_id id{7, 7};
    auto refused = [&](pbf_mesh_desc d, pbf_result code, const char* needle) {
        CHECK_FAILS(pbf_world_create_mesh(w, &d, &id), code, needle);
        CHECK(id.generation == 0);
    };
    pbf_mesh_desc d = m.desc();
    CHECK_FAILS(pbf_world_create_mesh(w, nullptr, &id), PBF_ERROR_INVALID_ARGUMENT, "pbf_mesh_desc");
    CHECK_FAILS(pbf_world_create_mesh(w, &d, nullptr), PBF_ERROR_INVALID_ARGUMENT, "out_mesh");
    d.struct_size = 12;
    refused(d, PBF_ERROR_STRUCT_SIZE, "pbf_mesh_desc");
    d = m.desc();
    d.vertices = nullptr;
    refused(d, PBF_ERROR_INVALID_ARGUMENT, "vertices");
    d = m.desc();
    d.vertex_count = 2;
    refused(d, PBF_ERROR_INVALID_ARGUMENT, "vertex_count");
    d = m.desc();
    d.triangle_count = 0;
    refused(d, PBF_ERROR_INVALID_ARGUMENT, "triangle_count");
    d = m.desc();
    d.closed = 2;
    refused(d, PBF_ERROR_INVALID_ARGUMENT, "closed");
    for (float bad : kBad) {
        INFO(bad_name(bad));
        d = m.desc();
        d.thickness = bad;
        refused(d, PBF_ERROR_INVALID_ARGUMENT, "thickness");
        d = m.desc();
        d.cell_size = bad;
        refused(d, PBF_ERROR_INVALID_ARGUMENT, "cell_size");
        Mesh broken = m;
        broken.v[3 * 5 + 1] = bad;
        refused(broken.desc(), PBF_ERROR_INVALID_ARGUMENT, "vertex 5 is not finite");
    }
    d = m.desc();
    d.cell_size = -0.1f;
    refused(d, PBF_ERROR_INVALID_ARGUMENT, "cell_size");
    Mesh out_of_range = m;
    out_of_range.i[7] = 8;
    refused(out_of_range.desc(), PBF_ERROR_INVALID_ARGUMENT, "index 7 is 8");
    Mesh flat;  // every triangle without area: a line and a repeated vertex
    flat.add_vertex(0, 0, 0);
    flat.add_vertex(1, 0, 0);
    flat.add_vertex(2, 0, 0);
    flat.add_triangle(0, 1, 2);
    flat.add_triangle(0, 0, 1);
    refused(flat.desc(), PBF_ERROR_INVALID_ARGUMENT, "degenerate");
    // A field over 256 MB: refused with its voxel count, never allocated.
    d = m.desc();
    d.cell_size = 0.0005f;
    refused(d, PBF_ERROR_CAPACITY, "voxels");
    CHECK_THAT(last_message(), Catch::Contains("cell_size"));
    // Triangles listed in the field's bricks over 2^31 times (6000 copies of a triangle spanning
    // a 29M-voxel field: 439k bricks each): refused before the build allocates anything.
    Mesh crowded;
    crowded.add_vertex(0, 0, 0);
    crowded.add_vertex(1, 1, 0);
    crowded.add_vertex(0, 1, 1);
    for (int k = 0; k < 6000; ++k) crowded.add_triangle(0, 1, 2);
    d = crowded.desc(false);
    d.cell_size = 0.0042f;
    refused(d, PBF_ERROR_OUT_OF_MEMORY, "2^31");
    CHECK_THAT(last_message(), Catch::Contains("cell_size"));
    // A collider desc naming the mesh shape wrongly: unknown shapes are still refused.
    pbf_collider_desc c = collider_desc(PBF_SHAPE_MESH);
    c.shape = pbf_collider_shape(6);
    pbf_collider_id cid{};
    CHECK_FAILS(pbf_world_create_collider(w, &c, &cid), PBF_ERROR_INVALID_ARGUMENT, "_MESH");
    CHECK_FAILS(pbf_world_destroy_mesh(w, pbf_mesh_id{0, 0}), PBF_ERROR_INVALID_HANDLE, "mesh");
    // Nothing was created: the world still takes a valid mesh.
    d = m.desc();
    REQUIRE_OK(pbf_world_create_mesh(w, &d, &id));
}

TEST_CASE("mesh: water at rest in a box-mesh container is as dense as in the domain's walls", "[mesh][physics]") {
    check_container_rest(PBF_BACKEND_CPU);
}

TEST_CASE("mesh: water on a sphere mesh keeps the distance it keeps from the analytic sphere", "[mesh][physics]") {
    check_sphere_contact(PBF_BACKEND_CPU);
}

TEST_CASE("mesh: an open plane holds a pool on its shell", "[mesh][physics]") { check_open_plane(PBF_BACKEND_CPU); }

namespace {
// The container recipe of docs/api.md: a block of water emitted inside a box mesh 0.6 m across
// (its floor 0.2 m above the tank's), stepped 0.5 s; returns how many particle centres are still
// inside the box, and the count emitted.
std::pair<uint32_t, uint32_t> kept_inside(const Mesh& m, bool closed) {
    pbf_world_id w = scene::create(scene::tank(PBF_BACKEND_CPU, kR, 2.0f, 1.6f, 2.0f, 4096));
    const float e = 0.3f, at[3] = {1.0f, 0.5f, 1.0f};
    mesh_collider(w, create_mesh(w, m.desc(closed)), at);
    const uint32_t emitted = scene::fill(w, 0.8f, 0.32f, 0.8f, 1.2f, 0.6f, 1.2f);
    for (int k = 0; k < 30; ++k) REQUIRE_PBF(pbf_world_step(w, kDt));
    const scene::Particles p = scene::read(w);
    uint32_t inside = 0;
    for (uint32_t k = 0; k < p.count; ++k) {
        const float* x = &p.pos[4 * size_t(k)];
        inside += std::fabs(x[0] - at[0]) < e && std::fabs(x[2] - at[2]) < e && x[1] > at[1] - e && x[1] < at[1] + e;
    }
    REQUIRE_PBF(pbf_world_destroy(w));
    return {inside, emitted};
}

// The box without the triangles of its top face (all three corners at y = +e).
Mesh without_lid(const Mesh& m, float e) {
    Mesh open;
    open.v = m.v;
    for (size_t t = 0; t < m.i.size(); t += 3) {
        bool top = true;
        for (size_t c = 0; c < 3; ++c) top = top && m.v[3 * size_t(m.i[t + c]) + 1] == e;
        if (!top) open.i.insert(open.i.end(), m.i.begin() + std::ptrdiff_t(t), m.i.begin() + std::ptrdiff_t(t + 3));
    }
    return open;
}
}  // namespace

// A closed mesh is solid inside: a closed box pushes water emitted inside it out, as any
// collider it overlaps. An open shell (closed = 0, with or without its lid) and a hollow box
// (an inner surface wound inward) are containers. A closed box wound inside out has no inside
// (its winding number there is -1): a surface without a solid behind it, which holds the water.
TEST_CASE("mesh: a closed box is solid; an open shell or a hollow box holds water emitted inside", "[mesh][physics]") {
    const float e = 0.3f;
    Mesh inverted;
    const float half[3] = {e, e, e};
    add_box(inverted, half, true);
    const struct {
        const char* what;
        Mesh mesh;
        bool closed, holds;
    } cases[] = {
        {"closed box", box(e, e, e), true, false},
        {"box as an open shell", box(e, e, e), false, true},
        {"box without its lid, open shell", without_lid(box(e, e, e), e), false, true},
        {"hollow box, walls 2 radii thick", hollow_box(e, e, e, 2 * kR), true, true},
        {"closed box wound inside out", inverted, true, true},
    };
    for (const auto& c : cases) {
        INFO(c.what);
        const auto [inside, emitted] = kept_inside(c.mesh, c.closed);
        REQUIRE(emitted == 700u);
        CHECK(inside == (c.holds ? emitted : 0u));
    }
}

TEST_CASE("mesh: a closed container moved 20 radii and turned 30 degrees per frame keeps its water", "[mesh][leak]") {
    check_no_leak(PBF_BACKEND_CPU);
}

// The limit (hidden: run it by name, "[.leak_limit]"): the leak test's container at growing
// translation and rotation per frame, 600 frames each, with the default max_substeps (16);
// prints what each loses.
TEST_CASE("mesh: leak limit of a fast container", "[.leak_limit]") {
    for (float t : {20.0f, 80.0f, 320.0f, 640.0f})
        for (float deg : {30.0f, 90.0f, 170.0f}) {
            const LeakResult r = shaken_container(PBF_BACKEND_CPU, t, deg, 600, 16);
            WARN("travel " << t << " r/frame, turn " << deg << " deg/frame: most outside " << r.outside_max << " of "
                           << r.count << ", first loss at frame " << r.first_frame);
        }
}

// The fastest particle's speed.
static float fastest(pbf_world_id w) {
    const scene::Particles p = scene::read(w);
    float v = 0.0f;
    for (uint32_t k = 0; k < p.count; ++k)
        v = std::max(v, std::sqrt(p.vel[4 * k] * p.vel[4 * k] + p.vel[4 * k + 1] * p.vel[4 * k + 1] +
                                  p.vel[4 * k + 2] * p.vel[4 * k + 2]));
    return v;
}

TEST_CASE("mesh: a teleported collider starts its next step where it was put, pushing nothing", "[mesh][teleport]") {
    // A pool on a floor plane (the domain reaches 3.5 m below it) and a box above the water,
    // out of its reach. The box is put 3 m below the floor and back, each time in a step of
    // 0.1 ms: as target poses it would sweep down through the water at 30 km/s and fling it
    // (100 m/s, the speed cap); teleported, it never crosses the water, which moves as in the
    // same world whose box is teleported where it already is (a teleport invalidates the cached
    // densities, recomputed in another order; a 0.1 ms step turns those last bits into speed,
    // so the control teleports too).
    pbf_world_desc d = scene::tank(PBF_BACKEND_CPU, kR, 0.64f, 0.8f, 0.64f, 8192);
    d.domain_min[1] = -3.5f;
    auto run = [&](bool teleport) {
        TestWorld w(d);
        pbf_collider_desc floor = collider_desc(PBF_SHAPE_PLANE);
        floor.position[1] = 0.0f;
        pbf_collider_id floor_id{}, box{};
        REQUIRE_OK(pbf_world_create_collider(w, &floor, &floor_id));
        pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX, PBF_MOTION_KINEMATIC);  // half extents 0.1 m
        set3(c.position, 0.32f, 0.5f, 0.32f);
        REQUIRE_OK(pbf_world_create_collider(w, &c, &box));
        scene::fill(w, 0, 0, 0, 0.64f, 0.24f, 0.64f);
        for (int k = 0; k < 60; ++k) REQUIRE_OK(pbf_world_step(w, kDt));
        const float away[3] = {0.32f, -3.0f, 0.32f}, q[4] = {0, 0, 0, 1};
        REQUIRE_OK(pbf_collider_teleport(w, box, teleport ? away : c.position, q));
        REQUIRE_OK(pbf_world_step(w, 1e-4f));
        REQUIRE_OK(pbf_collider_teleport(w, box, c.position, q));
        REQUIRE_OK(pbf_world_step(w, 1e-4f));
        return fastest(w);
    };
    const float still = run(false), moved = run(true);
    INFO("fastest particle: box still " << still << " m/s, teleported away and back " << moved << " m/s");
    CHECK(moved < still + 0.05f);

    TestWorld w(d);
    pbf_collider_desc c = collider_desc(PBF_SHAPE_BOX, PBF_MOTION_KINEMATIC);
    const float away[3] = {0.32f, -3.0f, 0.32f}, q[4] = {0, 0, 0, 1};
    // A static collider can be teleported too; a bad pose or handle is refused.
    c.motion = PBF_MOTION_STATIC;
    set3(c.position, 0.1f, 0.6f, 0.1f);
    pbf_collider_id fixed{};
    REQUIRE_OK(pbf_world_create_collider(w, &c, &fixed));
    REQUIRE_OK(pbf_collider_teleport(w, fixed, away, q));
    const float nan_pos[3] = {kNaN, 0, 0};
    CHECK_FAILS(pbf_collider_teleport(w, fixed, nan_pos, q), PBF_ERROR_INVALID_ARGUMENT, "position");
    CHECK_FAILS(pbf_collider_teleport(w, fixed, away, nullptr), PBF_ERROR_INVALID_ARGUMENT, "rotation");
    CHECK_FAILS(pbf_collider_teleport(w, pbf_collider_id{fixed.index, fixed.generation + 99}, away, q),
                PBF_ERROR_INVALID_HANDLE, "collider");
}
