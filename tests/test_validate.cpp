// White-box tests of the C ABI's named checks (native/api/validate.h): calls through the static
// core, comparing the check that refused a call instead of substrings of its message. Fixtures:
// support.h.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <set>
#include <string>
#include <utility>

#include "api/validate.h"
#include "pbf_c_api.h"
#include "support.h"

using pbf::api::Check;
using pbf::api::last_validation_check;

namespace {

// The call fails with the check's code and the thread's last check is `check`.
#define CHECK_REFUSED_BY(call, check)                                                                     \
    do {                                                                                                  \
        const pbf_result r_ = (call);                                                                     \
        INFO(#call << " -> " << pbf_result_string(r_) << " \"" << pbf_last_error_message() << "\"");      \
        CHECK(r_ == pbf::api::check_code(check));                                                         \
        CHECK(std::string(pbf::api::check_name(last_validation_check())) == pbf::api::check_name(check)); \
    } while (0)

}  // namespace

TEST_CASE("validate: every check has a unique name, a failure code and a message", "[api][validate]") {
    std::set<std::string> names;
    for (uint16_t c = 1; c < uint16_t(Check::count); ++c) {
        const Check check = Check(c);
        INFO(pbf::api::check_name(check));
        CHECK(names.insert(pbf::api::check_name(check)).second);
        CHECK(pbf::api::check_code(check) != PBF_OK);
        const std::string m = pbf::api::check_message(pbf::api::Verdict{check, 16, 2});
        CHECK(!m.empty());
        CHECK(m.find('{') == std::string::npos);  // every placeholder filled
    }
}

TEST_CASE("validate: a successful call leaves the last check alone, a non-check failure clears it", "[api][validate]") {
    TestWorld w;
    const float nan3[3] = {NAN, 0, 0};
    CHECK_REFUSED_BY(pbf_world_set_gravity(w.id, nan3), Check::GRAVITY);
    const float g[3] = {0, -9.81f, 0};
    REQUIRE(pbf_world_set_gravity(w.id, g) == PBF_OK);
    CHECK(last_validation_check() == Check::GRAVITY);
    CHECK(pbf_world_step(w.id, -1.0f) == PBF_ERROR_INVALID_ARGUMENT);  // dt is no desc check
    CHECK(last_validation_check() == Check::ok);
}

TEST_CASE("validate: world desc and solver parameters name the failed check", "[api][validate][world]") {
    struct Case {
        const char* what;
        void (*spoil)(pbf_world_desc&);
        Check check;
    };
    const Case cases[] = {
        {"another header major",
         [](pbf_world_desc& d) { d.header_version = PBF_MAKE_VERSION(PBF_VERSION_MAJOR + 1, 0, 0); },
         Check::WORLD_HEADER_VERSION},
        {"backend 7", [](pbf_world_desc& d) { d.backend = static_cast<pbf_backend>(7); }, Check::WORLD_BACKEND},
        {"cuda_device -1", [](pbf_world_desc& d) { d.cuda_device = -1; }, Check::WORLD_CUDA_DEVICE},
        {"max_particles 0", [](pbf_world_desc& d) { d.max_particles = 0; }, Check::WORLD_MAX_PARTICLES},
        {"radius 0", [](pbf_world_desc& d) { d.particle_radius = 0; }, Check::WORLD_PARTICLE_RADIUS},
        {"rest density NaN", [](pbf_world_desc& d) { d.rest_density = NAN; }, Check::WORLD_REST_DENSITY},
        {"gravity Inf", [](pbf_world_desc& d) { d.gravity[2] = INFINITY; }, Check::WORLD_GRAVITY},
        {"domain NaN", [](pbf_world_desc& d) { d.domain_max[0] = NAN; }, Check::WORLD_DOMAIN_FINITE},
        {"flat domain", [](pbf_world_desc& d) { d.domain_max[1] = d.domain_min[1]; }, Check::WORLD_DOMAIN_SIZE},
        {"domain beyond 2^19 radii", [](pbf_world_desc& d) { d.domain_max[2] = 1e6f; }, Check::WORLD_DOMAIN_EXTENT},
        {"walls 2", [](pbf_world_desc& d) { d.walls = 2; }, Check::WORLD_WALLS},
        {"hashed_grid 2", [](pbf_world_desc& d) { d.hashed_grid = 2; }, Check::WORLD_HASHED_GRID},
        {"max_colliders 0", [](pbf_world_desc& d) { d.max_colliders = 0; }, Check::WORLD_MAX_COLLIDERS},
        {"max_colliders 2049", [](pbf_world_desc& d) { d.max_colliders = 2049; }, Check::WORLD_MAX_COLLIDERS},
        {"iterations 0", [](pbf_world_desc& d) { d.solver.iterations = 0; }, Check::SOLVER_ITERATIONS},
        {"substeps 65", [](pbf_world_desc& d) { d.solver.substeps = 65; }, Check::SOLVER_SUBSTEPS},
        {"max_substeps 0", [](pbf_world_desc& d) { d.solver.max_substeps = 0; }, Check::SOLVER_MAX_SUBSTEPS},
        {"scorr_dq 1", [](pbf_world_desc& d) { d.solver.scorr_dq = 1.0f; }, Check::SOLVER_SCORR_DQ},
        {"ldc_enabled 2", [](pbf_world_desc& d) { d.solver.ldc_enabled = 2; }, Check::SOLVER_LDC_ENABLED},
        {"adaptive 1", [](pbf_world_desc& d) { d.solver.adaptive_error_target = 1.0f; }, Check::SOLVER_ADAPTIVE_TARGET},
        {"render flags 4", [](pbf_world_desc& d) { d.render.flags = 4; }, Check::RENDER_FLAGS},
        {"render smoothing NaN", [](pbf_world_desc& d) { d.render.smoothing = NAN; }, Check::RENDER_SMOOTHING},
        {"render smoothing 1.01", [](pbf_world_desc& d) { d.render.smoothing = 1.01f; }, Check::RENDER_SMOOTHING},
        {"render smoothing -0.1", [](pbf_world_desc& d) { d.render.smoothing = -0.1f; }, Check::RENDER_SMOOTHING},
        {"render max_stretch 0.5", [](pbf_world_desc& d) { d.render.max_stretch = 0.5f; }, Check::RENDER_MAX_STRETCH},
        {"render max_stretch Inf", [](pbf_world_desc& d) { d.render.max_stretch = INFINITY; },
         Check::RENDER_MAX_STRETCH},
        {"render scale 0", [](pbf_world_desc& d) { d.render.scale = 0.0f; }, Check::RENDER_SCALE},
        {"render scale 101", [](pbf_world_desc& d) { d.render.scale = 101.0f; }, Check::RENDER_SCALE},
        {"render isolated_scale -1", [](pbf_world_desc& d) { d.render.isolated_scale = -1.0f; },
         Check::RENDER_ISOLATED_SCALE},
        {"render isolated_scale NaN", [](pbf_world_desc& d) { d.render.isolated_scale = NAN; },
         Check::RENDER_ISOLATED_SCALE},
        {"render min_neighbors 1001", [](pbf_world_desc& d) { d.render.min_neighbors = 1001; },
         Check::RENDER_MIN_NEIGHBORS},
        {"render reserved0 1", [](pbf_world_desc& d) { d.render.reserved0 = 1; }, Check::RENDER_RESERVED0},
        {"max_diffuse -1", [](pbf_world_desc& d) { d.diffuse.max_diffuse = uint32_t(-1); }, Check::DIFFUSE_CAPACITY},
        {"diffuse energy_min NaN", [](pbf_world_desc& d) { d.diffuse.energy_min = NAN; }, Check::DIFFUSE_THRESHOLDS},
        {"diffuse wave_crest min = max", [](pbf_world_desc& d) { d.diffuse.wave_crest_min = d.diffuse.wave_crest_max; },
         Check::DIFFUSE_THRESHOLDS},
        {"diffuse trapped_air_rate -1", [](pbf_world_desc& d) { d.diffuse.trapped_air_rate = -1.0f; },
         Check::DIFFUSE_RATES},
        {"diffuse lifetime 0", [](pbf_world_desc& d) { d.diffuse.lifetime = 0.0f; }, Check::DIFFUSE_LIFETIME},
        {"diffuse spray above bubble", [](pbf_world_desc& d) { d.diffuse.spray_max_neighbors = 21; },
         Check::DIFFUSE_NEIGHBORS},
        {"diffuse buoyancy Inf", [](pbf_world_desc& d) { d.diffuse.buoyancy = INFINITY; }, Check::DIFFUSE_MOTION},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        pbf_world_desc d = small_desc();
        c.spoil(d);
        pbf_world_id id{9, 9};
        CHECK_REFUSED_BY(pbf_world_create(&d, &id), c.check);
        CHECK(id.generation == 0);
    }
    // The version check names both majors.
    pbf_world_desc d = small_desc();
    d.header_version = PBF_MAKE_VERSION(PBF_VERSION_MAJOR + 1, 0, 0);
    pbf_world_id id{};
    pbf_world_create(&d, &id);
    const std::string expected = "header major version " + std::to_string(PBF_VERSION_MAJOR + 1) +
                                 " does not match the library's " + std::to_string(PBF_VERSION_MAJOR);
    CHECK(std::string(pbf_last_error_message()).find(expected) != std::string::npos);
}

// Each case names the check that refuses it, not a substring of its message, so rewording a
// message does not break the test.
TEST_CASE("validate: emitter descs and transforms name the failed check", "[api][validate][emitter]") {
    TestWorld w;
    const pbf_emitter_desc nozzle = nozzle_desc(), drain = drain_desc();
    struct Case {
        const char* what;
        pbf_emitter_desc desc;
        Check check;
    };
    const Case cases[] = {
        {"type 0", edited(nozzle, [](pbf_emitter_desc& e) { e.type = static_cast<pbf_emitter_type>(0); }),
         Check::EMITTER_TYPE},
        {"type 3", edited(nozzle, [](pbf_emitter_desc& e) { e.type = static_cast<pbf_emitter_type>(3); }),
         Check::EMITTER_TYPE},
        {"unset type", pbf_emitter_desc_default(), Check::EMITTER_TYPE},
        {"enabled 2", edited(nozzle, [](pbf_emitter_desc& e) { e.enabled = 2; }), Check::EMITTER_ENABLED},
        {"drain enabled 2", edited(drain, [](pbf_emitter_desc& e) { e.enabled = 2; }), Check::EMITTER_ENABLED},
        {"speed 0", edited(nozzle, [](pbf_emitter_desc& e) { e.speed = 0; }), Check::NOZZLE_SPEED},
        {"radius -1", edited(nozzle, [](pbf_emitter_desc& e) { e.radius = -1; }), Check::NOZZLE_RADIUS},
        {"rate 0", edited(nozzle, [](pbf_emitter_desc& e) { e.particles_per_second = 0; }), Check::NOZZLE_RATE},
        {"rate 2e9", edited(nozzle, [](pbf_emitter_desc& e) { e.particles_per_second = 2e9f; }), Check::NOZZLE_RATE},
        {"zero direction", edited(nozzle, [](pbf_emitter_desc& e) { e.direction[1] = 0; }), Check::NOZZLE_DIRECTION},
        {"nozzle position NaN", edited(nozzle, [](pbf_emitter_desc& e) { e.position[0] = NAN; }), Check::NOZZLE_FINITE},
        {"inverted drain", edited(drain, [](pbf_emitter_desc& e) { std::swap(e.box_min[0], e.box_max[0]); }),
         Check::DRAIN_BOX},
        {"drain box Inf", edited(drain, [](pbf_emitter_desc& e) { e.box_max[2] = INFINITY; }), Check::DRAIN_FINITE},
        {"drain with NaN speed", edited(drain, [](pbf_emitter_desc& e) { e.speed = NAN; }),
         Check::EMITTER_UNUSED_FINITE},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        pbf_emitter_id id{9, 9};
        CHECK_REFUSED_BY(pbf_world_create_emitter(w.id, &c.desc, &id), c.check);
        CHECK(id.generation == 0);
    }
    pbf_emitter_id nz{}, dr{};
    REQUIRE(pbf_world_create_emitter(w.id, &nozzle, &nz) == PBF_OK);
    REQUIRE(pbf_world_create_emitter(w.id, &drain, &dr) == PBF_OK);
    const float zero[3] = {0, 0, 0}, pos[3] = {0, 0.7f, 0}, nan3[3] = {NAN, 0, 0};
    CHECK_REFUSED_BY(pbf_emitter_set_nozzle(w.id, nz, pos, zero), Check::NOZZLE_DIRECTION);
    CHECK_REFUSED_BY(pbf_emitter_set_nozzle(w.id, nz, pos, nan3), Check::TRANSFORM_FINITE);
    CHECK_REFUSED_BY(pbf_emitter_set_nozzle(w.id, nz, pos, nullptr), Check::TRANSFORM_FINITE);
    const float lo[3] = {0.4f, 0, 0.4f}, hi[3] = {0.5f, 0.1f, 0.39f};
    CHECK_REFUSED_BY(pbf_emitter_set_drain_box(w.id, dr, lo, hi), Check::DRAIN_BOX);
    // Each mover takes its own type of emitter.
    const float box_lo[3] = {0.4f, 0, 0.4f}, box_hi[3] = {0.5f, 0.1f, 0.5f}, down[3] = {0, -1, 0};
    CHECK_REFUSED_BY(pbf_emitter_set_drain_box(w.id, nz, box_lo, box_hi), Check::EMITTER_KIND);
    CHECK_REFUSED_BY(pbf_emitter_set_nozzle(w.id, dr, pos, down), Check::EMITTER_KIND);
    CHECK(pbf_emitter_set_nozzle(w.id, nz, pos, down) == PBF_OK);
    CHECK(pbf_emitter_set_drain_box(w.id, dr, box_lo, box_hi) == PBF_OK);
}

TEST_CASE("validate: collider descs and poses name the failed check", "[api][validate][collider]") {
    TestWorld w;
    auto sphere = [] {
        pbf_collider_desc c = pbf_collider_desc_default();
        c.shape = PBF_SHAPE_SPHERE;
        c.position[1] = 0.5f;
        c.radius = 0.1f;
        return c;
    };
    struct Case {
        const char* what;
        void (*spoil)(pbf_collider_desc&);
        Check check;
    };
    const Case cases[] = {
        {"shape 9", [](pbf_collider_desc& c) { c.shape = static_cast<pbf_collider_shape>(9); }, Check::COLLIDER_SHAPE},
        {"motion 5", [](pbf_collider_desc& c) { c.motion = static_cast<pbf_collider_motion>(5); },
         Check::COLLIDER_MOTION},
        {"zero quaternion", [](pbf_collider_desc& c) { c.rotation[3] = 0; }, Check::COLLIDER_POSE},
        {"friction 2", [](pbf_collider_desc& c) { c.friction = 2; }, Check::COLLIDER_FRICTION},
        {"radius 0", [](pbf_collider_desc& c) { c.radius = 0; }, Check::COLLIDER_RADIUS},
        {"capsule half_height -1",
         [](pbf_collider_desc& c) {
             c.shape = PBF_SHAPE_CAPSULE;
             c.half_height = -1;
         },
         Check::COLLIDER_HALF_HEIGHT},
        {"box extents 0", [](pbf_collider_desc& c) { c.shape = PBF_SHAPE_BOX; }, Check::COLLIDER_HALF_EXTENTS},
        {"sphere with NaN extents", [](pbf_collider_desc& c) { c.half_extents[1] = NAN; },
         Check::COLLIDER_UNUSED_FINITE},
        {"dynamic 2", [](pbf_collider_desc& c) { c.dynamic = 2; }, Check::COLLIDER_DYNAMIC},
        {"centre NaN", [](pbf_collider_desc& c) { c.center_of_mass[2] = NAN; }, Check::COLLIDER_CENTER},
    };
    for (const Case& k : cases) {
        INFO(k.what);
        pbf_collider_desc c = sphere();
        k.spoil(c);
        pbf_collider_id id{9, 9};
        CHECK_REFUSED_BY(pbf_world_create_collider(w.id, &c, &id), k.check);
    }
    const float pos[3] = {0, 0.5f, 0}, zero_q[4] = {0, 0, 0, 0};
    CHECK_REFUSED_BY(pbf_collider_set_target_pose(w.id, pbf_collider_id{1, 1}, pos, zero_q), Check::COLLIDER_POSE);
}

TEST_CASE("validate: pbf_world_copy_buffer names the failed check", "[api][validate][render]") {
    TestWorld w;
    w.emit_default_block();
    float out[48];
    uint32_t written = 7;
    CHECK_REFUSED_BY(pbf_world_copy_buffer(w.id, static_cast<pbf_buffer>(0), out, sizeof out, &written),
                     Check::COPY_SOURCE);
    CHECK(written == 0u);
    CHECK_REFUSED_BY(pbf_world_copy_buffer(w.id, static_cast<pbf_buffer>(9), out, sizeof out, &written),
                     Check::COPY_SOURCE);
    CHECK_REFUSED_BY(pbf_world_copy_buffer(w.id, PBF_BUFFER_POSITIONS, out, 20, &written), Check::COPY_OUT_SIZE);
    CHECK_REFUSED_BY(pbf_world_copy_buffer(w.id, PBF_BUFFER_ANISOTROPY, out, 32, &written), Check::COPY_OUT_SIZE);
    CHECK_REFUSED_BY(pbf_world_copy_buffer(w.id, PBF_BUFFER_IDS, out, 6, &written), Check::COPY_OUT_SIZE);
    // The message names the element size.
    CHECK(std::string(pbf_last_error_message()).find("element size 4") != std::string::npos);
}

TEST_CASE("validate: pbf_world_add_diffuse names the failed check", "[api][validate][diffuse]") {
    pbf_world_desc d = small_desc();
    d.diffuse.max_diffuse = 8;
    TestWorld w(d);
    float pos[4] = {0.0f, 0.5f, 0.0f, PBF_DIFFUSE_FOAM}, vel[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    uint32_t added = 7;
    pos[3] = 1.5f;
    CHECK_REFUSED_BY(pbf_world_add_diffuse(w.id, pos, vel, 1, &added), Check::DIFFUSE_ROWS);
    CHECK(added == 0u);
    pos[3] = PBF_DIFFUSE_FOAM;
    vel[3] = -1.0f;
    CHECK_REFUSED_BY(pbf_world_add_diffuse(w.id, pos, vel, 1, &added), Check::DIFFUSE_ROWS);
}

TEST_CASE("validate: material descs and handles name the failed check", "[api][validate][materials]") {
    TestWorld w;
    pbf_material_desc m = pbf_material_desc_default();
    pbf_material_id id{};
    auto with = [&](auto change) {
        pbf_material_desc d = m;
        change(d);
        return pbf_world_create_material(w.id, &d, &id);
    };
    CHECK_REFUSED_BY(with([](pbf_material_desc& d) { d.rest_density = 20000.0f; }), Check::MATERIAL_REST_DENSITY);
    CHECK_REFUSED_BY(with([](pbf_material_desc& d) { d.viscosity = 1.5f; }), Check::MATERIAL_VISCOSITY);
    CHECK_REFUSED_BY(with([](pbf_material_desc& d) { d.ldc_gain = -1.0f; }), Check::MATERIAL_LDC_GAIN);
    CHECK_REFUSED_BY(with([](pbf_material_desc& d) { d.surface_tension = kNaN; }), Check::MATERIAL_SURFACE_TENSION);
    CHECK_REFUSED_BY(with([](pbf_material_desc& d) { d.cohesion = kInf; }), Check::MATERIAL_COHESION);
    CHECK_REFUSED_BY(with([](pbf_material_desc& d) { d.adhesion = 2e4f; }), Check::MATERIAL_ADHESION);
    CHECK_REFUSED_BY(with([](pbf_material_desc& d) { d.color[0] = -0.1f; }), Check::MATERIAL_COLOR);
    CHECK_REFUSED_BY(with([](pbf_material_desc& d) { d.reserved0 = 3; }), Check::MATERIAL_RESERVED0);
    pbf_material_id ids[PBF_MAX_MATERIALS];
    REQUIRE(pbf_world_get_materials(w.id, ids) == PBF_OK);
    CHECK_REFUSED_BY(pbf_world_destroy_material(w.id, ids[0]), Check::MATERIAL_DEFAULT_DESTROY);
    pbf_material_desc other = m;
    other.rest_density = 900.0f;
    CHECK_REFUSED_BY(pbf_world_set_material(w.id, ids[0], &other), Check::MATERIAL_DEFAULT_DENSITY);
    CHECK_REFUSED_BY(pbf_world_get_material(w.id, pbf_material_id{0, 0}, &other), Check::MATERIAL_HANDLE);
    REQUIRE(pbf_world_create_material(w.id, &m, &id) == PBF_OK);
    pbf_block_desc b = block(-0.1f, 0.0f, -0.1f, 0.1f, 0.2f, 0.1f);
    b.material = id;
    REQUIRE(pbf_world_emit_block(w.id, &b, nullptr) == PBF_OK);
    CHECK_REFUSED_BY(pbf_world_destroy_material(w.id, id), Check::MATERIAL_IN_USE);
    b.material = pbf_material_id{id.index, id.generation + 1};
    CHECK_REFUSED_BY(pbf_world_emit_block(w.id, &b, nullptr), Check::MATERIAL_HANDLE);
    // Bytes per particle are not copied into graphics buffers.
    pbf_gl_buffer_desc gl = pbf_gl_buffer_desc_default();
    gl.buffer = 1;
    gl.capacity = 16;
    gl.source = PBF_BUFFER_MATERIALS;
    pbf_gl_buffer_id gl_id{};
    CHECK_REFUSED_BY(pbf_world_register_gl_buffer(w.id, &gl, &gl_id), Check::COPY_SOURCE_GRAPHICS);
    pbf_d3d11_buffer_desc d3d = pbf_d3d11_buffer_desc_default();
    d3d.buffer = &gl;  // any non-NULL pointer: refused before it is used
    d3d.capacity = 16;
    d3d.source = PBF_BUFFER_MATERIALS;
    pbf_d3d11_buffer_id d3d_id{};
    CHECK_REFUSED_BY(pbf_world_register_d3d11_buffer(w.id, &d3d, &d3d_id), Check::COPY_SOURCE_GRAPHICS);
    d3d.source = PBF_BUFFER_POSITIONS;
    d3d.mode = PBF_COPY_MANUAL;
    CHECK_REFUSED_BY(pbf_world_register_d3d11_buffer(w.id, &d3d, &d3d_id), Check::D3D11_COPY_MODE);
    d3d.mode = PBF_COPY_ON_STEP;
    d3d.buffer = nullptr;
    CHECK_REFUSED_BY(pbf_world_register_d3d11_buffer(w.id, &d3d, &d3d_id), Check::D3D11_BUFFER);
}
