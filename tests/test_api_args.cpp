// Black-box tests of the C ABI (include/pbf_c_api.h) on the CPU backend. Argument validation: NaN, Inf and out-of-range fields of every desc and call.
// Fixtures: support.h.
#include "support.h"

namespace {

// Every float solver parameter, with the name its refusal mentions.
const std::pair<float pbf_solver_params::*, const char*> kSolverFloats[] = {
    {&pbf_solver_params::relaxation, "relaxation"}, {&pbf_solver_params::scorr_k, "scorr_k"},
    {&pbf_solver_params::scorr_n, "scorr_n"},       {&pbf_solver_params::scorr_dq, "scorr_dq"},
    {&pbf_solver_params::xsph_c, "xsph_c"},         {&pbf_solver_params::vorticity_epsilon, "vorticity_epsilon"},
    {&pbf_solver_params::ldc_gain, "ldc_gain"},     {&pbf_solver_params::max_speed, "max_speed"},
};

// Each of NaN, +Inf and -Inf in each of the N floats of `field` (a vector or a quaternion) of a
// copy of `base` is refused: refuse(copy, needle).
template <class Desc, size_t N, class Refuse>
void refuse_bad_elements(const Desc& base, float (Desc::*field)[N], const char* needle, Refuse refuse) {
    for (float bad : kBad)
        for (size_t a = 0; a < N; ++a) {
            INFO("value " << bad_name(bad) << ", element " << a);
            Desc d = base;
            (d.*field)[a] = bad;
            refuse(d, needle);
        }
}

// Each of NaN, +Inf and -Inf in the float `field` of a copy of `base` is refused.
template <class Desc, class Refuse>
void refuse_bad_value(const Desc& base, float Desc::*field, const char* needle, Refuse refuse) {
    for (float bad : kBad) {
        INFO("value " << bad_name(bad));
        Desc d = base;
        d.*field = bad;
        refuse(d, needle);
    }
}

// create(w, &desc, &id) fails as an invalid argument naming `needle` and writes a null Id; an
// object created by mistake is destroyed again, to keep the world's table free.
template <class Id, class Desc, class Create, class Destroy>
void check_create_refused(pbf_world_id w, Create create, Destroy destroy, const Desc& desc, const char* needle) {
    Id id{9, 9};
    CHECK_FAILS(create(w, &desc, &id), PBF_ERROR_INVALID_ARGUMENT, needle);
    CHECK(id.index == 0);
    CHECK(id.generation == 0);
    if (id.generation != 0) destroy(w, id);
}

}  // namespace

// =============================================================================================
TEST_CASE("world desc: NaN, Inf and out-of-range fields are refused", "[api][nan][world]") {
    TestWorld survivor;
    const uint32_t n = survivor.emit_default_block();

    auto refuse = [&](const pbf_world_desc& d, const char* needle) {
        pbf_world_id id{9, 9};
        CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_INVALID_ARGUMENT, needle);
        CHECK(id.index == 0);
        CHECK(id.generation == 0);
    };

    const pbf_world_desc base = small_desc();
    refuse_bad_value(base, &pbf_world_desc::particle_radius, "particle_radius", refuse);
    refuse_bad_value(base, &pbf_world_desc::rest_density, "rest_density", refuse);
    refuse_bad_elements(base, &pbf_world_desc::gravity, "gravity", refuse);
    refuse_bad_elements(base, &pbf_world_desc::domain_min, "domain", refuse);
    refuse_bad_elements(base, &pbf_world_desc::domain_max, "domain", refuse);
    for (float bad : kBad)
        for (const auto& f : kSolverFloats) {
            INFO(bad_name(bad) << " in solver." << f.second);
            pbf_world_desc d = base;
            d.solver.*f.first = bad;
            refuse(d, f.second);
        }

    // Out-of-range values.
    struct Case {
        const char* what;
        void (*edit)(pbf_world_desc&);
        const char* needle;
    };
    const Case cases[] = {
        {"iterations 0", [](pbf_world_desc& d) { d.solver.iterations = 0; }, "iterations"},
        {"iterations 65", [](pbf_world_desc& d) { d.solver.iterations = 65; }, "iterations"},
        {"substeps 65", [](pbf_world_desc& d) { d.solver.substeps = 65; }, "substeps"},
        {"max_substeps 0", [](pbf_world_desc& d) { d.solver.max_substeps = 0; }, "max_substeps"},
        {"max_substeps 65", [](pbf_world_desc& d) { d.solver.max_substeps = 65; }, "max_substeps"},
        {"substep_travel 0.01", [](pbf_world_desc& d) { d.solver.substep_travel = 0.01f; }, "substep_travel"},
        {"substep_travel NaN", [](pbf_world_desc& d) { d.solver.substep_travel = NAN; }, "substep_travel"},
        {"sound_speed 0", [](pbf_world_desc& d) { d.solver.sound_speed = 0.0f; }, "sound_speed"},
        {"sound_speed 9.9", [](pbf_world_desc& d) { d.solver.sound_speed = 9.9f; }, "sound_speed"},
        {"sound_speed Inf", [](pbf_world_desc& d) { d.solver.sound_speed = INFINITY; }, "sound_speed"},
        {"vorticity_epsilon 1.01", [](pbf_world_desc& d) { d.solver.vorticity_epsilon = 1.01f; }, "vorticity_epsilon"},
        {"ldc_enabled 2", [](pbf_world_desc& d) { d.solver.ldc_enabled = 2; }, "ldc_enabled"},
        {"relaxation 0", [](pbf_world_desc& d) { d.solver.relaxation = 0; }, "relaxation"},
        {"max_speed 0", [](pbf_world_desc& d) { d.solver.max_speed = 0; }, "max_speed"},
        {"scorr_n 9", [](pbf_world_desc& d) { d.solver.scorr_n = 9; }, "scorr_n"},
        {"scorr_dq 1", [](pbf_world_desc& d) { d.solver.scorr_dq = 1; }, "scorr_dq"},
        {"xsph_c -0.1", [](pbf_world_desc& d) { d.solver.xsph_c = -0.1f; }, "xsph_c"},
        {"ldc_gain 2", [](pbf_world_desc& d) { d.solver.ldc_gain = 2; }, "ldc_gain"},
        {"max_particles 0", [](pbf_world_desc& d) { d.max_particles = 0; }, "max_particles"},
        {"max_particles 2^30+1", [](pbf_world_desc& d) { d.max_particles = (1u << 30) + 1; }, "max_particles"},
        {"backend 7", [](pbf_world_desc& d) { d.backend = static_cast<pbf_backend>(7); }, "backend"},
        {"backend -1",
         [](pbf_world_desc& d) {
             const int32_t v = -1;
             std::memcpy(&d.backend, &v, sizeof v);
         },
         "backend"},
        {"cuda_device -1", [](pbf_world_desc& d) { d.cuda_device = -1; }, "cuda_device"},
        {"particle_radius 0", [](pbf_world_desc& d) { d.particle_radius = 0; }, "particle_radius"},
        {"particle_radius -1", [](pbf_world_desc& d) { d.particle_radius = -1; }, "particle_radius"},
        {"rest_density 0", [](pbf_world_desc& d) { d.rest_density = 0; }, "rest_density"},
        {"inverted domain", [](pbf_world_desc& d) { std::swap(d.domain_min[1], d.domain_max[1]); }, "domain"},
        {"flat domain", [](pbf_world_desc& d) { d.domain_max[2] = d.domain_min[2] + 0.01f; }, "domain"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        pbf_world_desc d = small_desc();
        c.edit(d);
        refuse(d, c.needle);
    }
    survivor.require_usable(n);
}

TEST_CASE("block desc: NaN and Inf in every float field are refused", "[api][nan][emit]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    const std::vector<float> before = w.positions();
    for (float bad : kBad) {
        for (int a = 0; a < 3; ++a) {
            INFO(bad_name(bad) << " on axis " << a);
            for (int field = 0; field < 3; ++field) {
                pbf_block_desc b = block(0.2f, 0.5f, 0.2f, 0.4f, 0.7f, 0.4f);
                float* v = field == 0 ? b.box_min : field == 1 ? b.box_max : b.velocity;
                v[a] = bad;
                uint32_t emitted = 123;
                CHECK_FAILS(pbf_world_emit_block(w, &b, &emitted), PBF_ERROR_INVALID_ARGUMENT,
                            field == 2 ? "velocity" : "box_m");
                CHECK(emitted == 0u);
            }
        }
    }
    // An empty or inverted box.
    for (int a = 0; a < 3; ++a) {
        pbf_block_desc b = block(0.2f, 0.5f, 0.2f, 0.4f, 0.7f, 0.4f);
        b.box_max[a] = b.box_min[a];
        CHECK_FAILS(pbf_world_emit_block(w, &b, nullptr), PBF_ERROR_INVALID_ARGUMENT, "box_max");
    }
    CHECK(same_bits(w.positions(), before));
    w.require_usable(n);
}

TEST_CASE("emitter desc: NaN, Inf and out-of-range fields are refused", "[api][nan][emitter]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();

    auto refuse = [&](const pbf_emitter_desc& e, const char* needle) {
        check_create_refused<pbf_emitter_id>(w, pbf_world_create_emitter, pbf_world_destroy_emitter, e, needle);
    };

    for (pbf_emitter_type type : {PBF_EMITTER_NOZZLE, PBF_EMITTER_DRAIN}) {
        INFO((type == PBF_EMITTER_NOZZLE ? "nozzle" : "drain"));
        const pbf_emitter_desc base = type == PBF_EMITTER_NOZZLE ? nozzle_desc() : drain_desc();
        refuse_bad_elements(base, &pbf_emitter_desc::position, "position", refuse);
        refuse_bad_elements(base, &pbf_emitter_desc::direction, "direction", refuse);
        refuse_bad_elements(base, &pbf_emitter_desc::box_min, "box", refuse);
        refuse_bad_elements(base, &pbf_emitter_desc::box_max, "box", refuse);
        refuse_bad_value(base, &pbf_emitter_desc::speed, "speed", refuse);
        refuse_bad_value(base, &pbf_emitter_desc::radius, "radius", refuse);
        refuse_bad_value(base, &pbf_emitter_desc::particles_per_second, "particles_per_second", refuse);
    }

    // Out-of-range fields: test_validate.cpp compares the check that refuses each.
    refuse(edited(nozzle_desc(), [](pbf_emitter_desc& e) { e.speed = 0; }), "speed");

    // set_enabled and set_transform validate too.
    pbf_emitter_id nz{}, dr{};
    pbf_emitter_desc nd = nozzle_desc();
    nd.enabled = 0;
    REQUIRE_OK(pbf_world_create_emitter(w, &nd, &nz));
    const pbf_emitter_desc drain = drain_desc();
    REQUIRE_OK(pbf_world_create_emitter(w, &drain, &dr));
    REQUIRE_OK(pbf_emitter_set_enabled(w, dr, 0));
    CHECK_FAILS(pbf_emitter_set_enabled(w, nz, 2), PBF_ERROR_INVALID_ARGUMENT, "enabled");
    CHECK_FAILS(pbf_emitter_set_enabled(w, nz, 0xFFFFFFFFu), PBF_ERROR_INVALID_ARGUMENT, "enabled");
    for (float bad : kBad) {
        for (int a = 0; a < 3; ++a) {
            float p[3] = {0, 0.7f, 0}, d[3] = {0, -1, 0};
            p[a] = bad;
            CHECK_FAILS(pbf_emitter_set_nozzle(w, nz, p, d), PBF_ERROR_INVALID_ARGUMENT, "finite");
            p[a] = 0.1f;
            d[a] = bad;
            CHECK_FAILS(pbf_emitter_set_nozzle(w, nz, p, d), PBF_ERROR_INVALID_ARGUMENT, "finite");
        }
    }
    const float zero[3] = {0, 0, 0}, pos[3] = {0, 0.7f, 0};
    CHECK_FAILS(pbf_emitter_set_nozzle(w, nz, pos, zero), PBF_ERROR_INVALID_ARGUMENT, "direction");
    const float lo[3] = {0.4f, 0, 0.4f}, hi[3] = {0.5f, 0.1f, 0.39f};
    CHECK_FAILS(pbf_emitter_set_drain_box(w, dr, lo, hi), PBF_ERROR_INVALID_ARGUMENT, "box_max");
    // The nozzle is disabled and the drain too: nothing changes the count.
    w.require_usable(n);
}

TEST_CASE("collider desc and set_pose: NaN, Inf and out-of-range fields are refused", "[api][nan][collider]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();

    auto refuse = [&](const pbf_collider_desc& c, const char* needle) {
        check_create_refused<pbf_collider_id>(w, pbf_world_create_collider, pbf_world_destroy_collider, c, needle);
    };

    for (pbf_collider_shape shape : {PBF_SHAPE_PLANE, PBF_SHAPE_SPHERE, PBF_SHAPE_CAPSULE, PBF_SHAPE_BOX}) {
        INFO("shape " << int(shape));
        const pbf_collider_desc base = collider_desc(shape, PBF_MOTION_KINEMATIC);
        refuse_bad_elements(base, &pbf_collider_desc::position, "position", refuse);
        refuse_bad_elements(base, &pbf_collider_desc::half_extents, "half_extents", refuse);
        refuse_bad_elements(base, &pbf_collider_desc::rotation, "rotation", refuse);
        refuse_bad_value(base, &pbf_collider_desc::radius, "radius", refuse);
        refuse_bad_value(base, &pbf_collider_desc::half_height, "half_height", refuse);
        refuse_bad_value(base, &pbf_collider_desc::friction, "friction", refuse);
    }

    const pbf_collider_desc box = collider_desc(PBF_SHAPE_BOX);
    struct Case {
        const char* what;
        pbf_collider_desc desc;
        const char* needle;
    };
    const Case cases[] = {
        {"shape 0", collider_desc(static_cast<pbf_collider_shape>(0)), "shape"},
        {"shape 99", collider_desc(static_cast<pbf_collider_shape>(99)), "shape"},
        {"unset shape", pbf_collider_desc_default(), "shape"},
        {"motion 5", collider_desc(PBF_SHAPE_SPHERE, static_cast<pbf_collider_motion>(5)), "motion"},
        {"zero quaternion", edited(box, [](pbf_collider_desc& c) { c.rotation[3] = 0; }), "rotation"},
        {"friction 1.5", edited(box, [](pbf_collider_desc& c) { c.friction = 1.5f; }), "friction"},
        {"friction -0.5", edited(box, [](pbf_collider_desc& c) { c.friction = -0.5f; }), "friction"},
        {"sphere radius 0", edited(collider_desc(PBF_SHAPE_SPHERE), [](pbf_collider_desc& c) { c.radius = 0; }),
         "radius"},
        {"capsule half_height -1",
         edited(collider_desc(PBF_SHAPE_CAPSULE), [](pbf_collider_desc& c) { c.half_height = -1; }), "half_height"},
        {"box half_extents 0", edited(box, [](pbf_collider_desc& c) { c.half_extents[1] = 0; }), "half_extents"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        refuse(c.desc, c.needle);
    }

    // set_pose: NaN and Inf in the position, the quaternion, and a zero quaternion.
    pbf_collider_id kin{};
    const pbf_collider_desc kin_desc = collider_desc(PBF_SHAPE_SPHERE, PBF_MOTION_KINEMATIC);
    REQUIRE_OK(pbf_world_create_collider(w, &kin_desc, &kin));
    for (float bad : kBad) {
        INFO("value " << bad_name(bad));
        for (int a = 0; a < 3; ++a) {
            float p[3] = {0, 0.6f, 0};
            const float q[4] = {0, 0, 0, 1};
            p[a] = bad;
            CHECK_FAILS(pbf_collider_set_target_pose(w, kin, p, q), PBF_ERROR_INVALID_ARGUMENT, "position");
        }
        for (int a = 0; a < 4; ++a) {
            const float p[3] = {0, 0.6f, 0};
            float q[4] = {0, 0, 0, 1};
            q[a] = bad;
            CHECK_FAILS(pbf_collider_set_target_pose(w, kin, p, q), PBF_ERROR_INVALID_ARGUMENT, "rotation");
        }
    }
    const float p[3] = {0, 0.6f, 0}, q0[4] = {0, 0, 0, 0};
    CHECK_FAILS(pbf_collider_set_target_pose(w, kin, p, q0), PBF_ERROR_INVALID_ARGUMENT, "rotation");
    // A valid pose (unnormalised quaternion is normalised) still works.
    const float q2[4] = {0, 0, 0, 2};
    REQUIRE_OK(pbf_collider_set_target_pose(w, kin, p, q2));
    w.require_usable(n);
}

TEST_CASE("set_gravity, set_solver_params and step: NaN, Inf and bad dt are refused", "[api][nan][step]") {
    TestWorld w;
    const uint32_t n = w.emit_default_block();
    const std::vector<float> before = w.positions();
    const pbf_solver_params params_before = w.params();

    for (float bad : kBad) {
        for (int a = 0; a < 3; ++a) {
            INFO(bad_name(bad) << " on axis " << a);
            float g[3] = {0, -9.81f, 0};
            g[a] = bad;
            CHECK_FAILS(pbf_world_set_gravity(w, g), PBF_ERROR_INVALID_ARGUMENT, "gravity");
        }
        for (const auto& f : kSolverFloats) {
            INFO(bad_name(bad) << " in solver." << f.second);
            pbf_solver_params p = params_before;
            p.*f.first = bad;
            CHECK_FAILS(pbf_world_set_solver_params(w, &p), PBF_ERROR_INVALID_ARGUMENT, f.second);
        }
    }
    for (uint32_t it : {0u, 65u}) {
        pbf_solver_params p = params_before;
        p.iterations = it;
        CHECK_FAILS(pbf_world_set_solver_params(w, &p), PBF_ERROR_INVALID_ARGUMENT, "iterations");
    }
    for (uint32_t sub : {65u, 1000u}) {
        pbf_solver_params p = params_before;
        p.substeps = sub;
        CHECK_FAILS(pbf_world_set_solver_params(w, &p), PBF_ERROR_INVALID_ARGUMENT, "substeps");
    }
    {
        pbf_solver_params p = params_before;
        p.ldc_enabled = 2;
        CHECK_FAILS(pbf_world_set_solver_params(w, &p), PBF_ERROR_INVALID_ARGUMENT, "ldc_enabled");
    }

    const float bad_dts[] = {kNaN, kInf, -kInf, 0.0f, -0.0f, -kDt, -1.0f, 1.0001f, 2.0f, 1e30f};
    for (float dt : bad_dts) {
        INFO("dt " << dt);
        CHECK_FAILS(pbf_world_step(w, dt), PBF_ERROR_INVALID_ARGUMENT, "dt");
    }
    // Nothing moved, nothing was applied.
    CHECK(same_bits(w.positions(), before));
    CHECK(same_params(w.params(), params_before));
    pbf_step_stats s{};
    s.struct_size = sizeof s;
    REQUIRE_OK(pbf_world_get_stats(w, &s));
    CHECK(s.step_index == 0u);
    // The boundary dt = 1 is accepted.
    REQUIRE_OK(pbf_world_step(w, 1.0f));
    w.require_usable(n);
}

TEST_CASE("pbf_get_backend_info: arguments, and the CPU backend always there", "[api]") {
    pbf_backend_info info;
    std::memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    CHECK_FAILS(pbf_get_backend_info(PBF_BACKEND_CPU, 0, nullptr), PBF_ERROR_INVALID_ARGUMENT, "NULL");
    pbf_backend_info small = info;
    small.struct_size = sizeof small - 4;
    CHECK_FAILS(pbf_get_backend_info(PBF_BACKEND_CPU, 0, &small), PBF_ERROR_STRUCT_SIZE, "struct_size");
    CHECK_FAILS(pbf_get_backend_info(static_cast<pbf_backend>(3), 0, &info), PBF_ERROR_INVALID_ARGUMENT, "backend");
    CHECK_FAILS(pbf_get_backend_info(PBF_BACKEND_CUDA, -1, &info), PBF_ERROR_INVALID_ARGUMENT, "cuda_device");

    REQUIRE_PBF(pbf_get_backend_info(PBF_BACKEND_CPU, 0, &info));
    CHECK(info.backend == PBF_BACKEND_CPU);
    CHECK(info.status == PBF_BACKEND_STATUS_AVAILABLE);
    CHECK(info.cuda_device == -1);
    CHECK(std::string(info.device_name).rfind("CPU (", 0) == 0);

    // CUDA is described either way: available, or a status that names why not, with a message;
    // AUTO is then CUDA exactly when CUDA is available.
    pbf_backend_info cuda = info, automatic = info;
    REQUIRE_PBF(pbf_get_backend_info(PBF_BACKEND_CUDA, 0, &cuda));
    REQUIRE_PBF(pbf_get_backend_info(PBF_BACKEND_AUTO, 0, &automatic));
    CHECK(cuda.backend == PBF_BACKEND_CUDA);
    CHECK(std::strlen(cuda.message) > 0);
    if (cuda.status == PBF_BACKEND_STATUS_AVAILABLE) {
        CHECK(automatic.backend == PBF_BACKEND_CUDA);
    } else {
        CHECK(automatic.backend == PBF_BACKEND_CPU);
        CHECK(std::string(automatic.message) == std::string("CUDA not taken: ") + cuda.message);
        pbf_world_desc d = pbf_world_desc_default();
        d.backend = PBF_BACKEND_CUDA;
        pbf_world_id w{7, 7};
        CHECK_FAILS(pbf_world_create(&d, &w), PBF_ERROR_BACKEND_UNAVAILABLE, cuda.message);
        CHECK(w.index == 0);
    }
}
