// The step plan on its own (white-box): a frame step turned into substeps, emissions and drains
// without a backend.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "solver/step_plan.h"

using namespace pbf;

namespace {

struct Plan {
    pbf_world_desc desc = pbf_world_desc_default();
    MaterialTable materials;
    std::vector<EmitterState> emitters;
    FrameState frame;

    Plan() {
        materials.alive[0] = true;
        materials.desc[0] = pbf_material_desc_default();
        materials.desc[0].rest_density = desc.rest_density;
        frame.frame_dt = 1.0f / 60.0f;
    }
    StepInput run() {
        StepInput input;
        plan_step(desc.solver, derive_constants(desc, materials), materials, frame, &emitters, &input);
        return input;
    }
    void add_nozzle(float rate) {
        EmitterState e{};
        e.desc = pbf_emitter_desc_default();
        e.desc.type = PBF_EMITTER_NOZZLE;
        e.desc.speed = 2.0f;
        e.desc.radius = 0.1f;
        e.desc.particles_per_second = rate;
        emitters.push_back(e);
    }
};

uint32_t emitted(const StepInput& in) {
    uint32_t n = 0;
    for (const SubstepInput& s : in.substeps)
        for (const NozzleEmission& e : s.nozzles) n += e.count;
    return n;
}

}  // namespace

TEST_CASE("step plan: fixed substeps split the frame step evenly, settling only in the first", "[plan]") {
    Plan p;
    p.desc.solver.substeps = 4;
    p.frame.overlaps_pending = true;
    const StepInput in = p.run();
    REQUIRE(in.substeps.size() == 4u);
    CHECK(in.frame_dt == p.frame.frame_dt);
    for (size_t k = 0; k < in.substeps.size(); ++k) {
        CHECK(in.substeps[k].ctx.dt == p.frame.frame_dt / 4.0f);
        CHECK(in.substeps[k].iterations == p.desc.solver.iterations);
        CHECK(in.substeps[k].settle_overlaps == (k == 0));
    }
    // The settling substep removes what the settling leaves in the positions (weight 1), with no
    // LDC push; the others keep the substep's own weight and K.
    const StepContext& settling = in.substeps[0].ctx;
    const StepContext& later = in.substeps[1].ctx;
    CHECK(settling.positional_weight == 1.0f);
    CHECK(settling.ldc_k == 0.0f);
    for (float k : settling.material_ldc_k) CHECK(k == 0.0f);
    CHECK(later.positional_weight == old_error_weight(later.error_damping));
    CHECK(later.ldc_k > 0.0f);
}

TEST_CASE("step plan: a nozzle emits its rate over the frame whatever the substep count", "[plan]") {
    for (uint32_t substeps : {1u, 3u, 7u}) {
        Plan p;
        p.desc.solver.substeps = substeps;
        p.add_nozzle(600.0f);  // 10 per frame of 1/60 s
        uint32_t total = 0;
        for (int frame = 0; frame < 6; ++frame) total += emitted(p.run());
        CHECK(total + p.emitters[0].accumulator == Approx(60.0).margin(1e-3));
        CHECK(p.emitters[0].sequence == total);  // the spiral index runs on
        p.emitters[0].desc.enabled = 0;
        CHECK(emitted(p.run()) == 0u);
    }
}

TEST_CASE("step plan: automatic substeps follow the fastest motion, up to max_substeps", "[plan]") {
    Plan p;
    const size_t calm = p.run().substeps.size();
    p.frame.feedback.max_speed = 20.0f;  // 6.7 substeps of travel at h = 0.1 m, vs gravity's 2
    const size_t fast = p.run().substeps.size();
    CHECK(fast > calm);
    p.frame.feedback.max_speed = 1000.0f;
    CHECK(p.run().substeps.size() == p.desc.solver.max_substeps);
    p.desc.solver.max_substeps = kMaxSubsteps;
    CHECK(p.run().substeps.size() == kMaxSubsteps);
}

TEST_CASE("step plan: automatic substeps run two iterations, more only where the substep cap binds", "[plan]") {
    Plan p;  // defaults: automatic substeps, iterations 4 (the cap), h = 0.1 m
    auto iterations_of = [](const StepInput& in) {
        REQUIRE(!in.substeps.empty());
        for (const SubstepInput& s : in.substeps) CHECK(s.iterations == in.substeps[0].iterations);
        return in.substeps[0].iterations;
    };
    // A shallow pool: every rule met by substeps, at two iterations.
    p.frame.feedback.fluid_depth = 0.3f;
    StepInput in = p.run();
    CHECK(in.substeps.size() < p.desc.solver.max_substeps);
    CHECK(iterations_of(in) == 2u);
    // The depth rule is the two-iteration one: C = κ(2) g H Δt² / h² <= 0.1 at the substep chosen.
    const double sub_dt = p.frame.frame_dt / double(in.substeps.size());
    CHECK(4.0 / 2.5 * 9.81 * 0.3 * sub_dt * sub_dt / (0.1 * 0.1) <= 0.1 + 1e-6);
    // A column far deeper than 4 substeps hold at two iterations: the cap's substeps, and
    // iterations up to the user's cap.
    p.desc.solver.max_substeps = 4;
    p.frame.feedback.fluid_depth = 40.0f;
    in = p.run();
    CHECK(in.substeps.size() == p.desc.solver.max_substeps);
    CHECK(iterations_of(in) == p.desc.solver.iterations);
    // Somewhat deeper than the cap holds at two: three iterations meet the rule there.
    p.desc.solver.iterations = 64;
    const double cap_dt = p.frame.frame_dt / double(p.desc.solver.max_substeps);
    const double kappa3 = 4.0 / 3.5, kappa2 = 4.0 / 2.5;
    const double depth = 0.1 * 0.1 * 0.1 / (9.81 * cap_dt * cap_dt) / std::sqrt(kappa2 * kappa3);  // between
    p.frame.feedback.fluid_depth = float(depth);
    in = p.run();
    CHECK(in.substeps.size() == p.desc.solver.max_substeps);
    CHECK(iterations_of(in) == 3u);
    // A collider that moves over the step: the cap, whatever the depth.
    p.desc.solver.max_substeps = 16;
    p.frame.feedback.fluid_depth = 0.3f;
    ColliderKey moving{};
    moving.from_rotation = moving.to_rotation = Quat{0.0f, 0.0f, 0.0f, 1.0f};
    moving.to_position = Vec3{0.01f, 0.0f, 0.0f};
    p.desc.solver.iterations = 4;
    StepInput with_collider;
    with_collider.collider_keys.push_back(moving);
    with_collider.collider_shapes.push_back(Collider{});
    plan_step(p.desc.solver, derive_constants(p.desc, p.materials), p.materials, p.frame, &p.emitters, &with_collider);
    CHECK(iterations_of(with_collider) == 4u);
    // Fixed substeps run exactly `iterations`; a cap of one runs one.
    p.desc.solver.iterations = 4;
    p.desc.solver.substeps = 3;
    CHECK(iterations_of(p.run()) == 4u);
    p.desc.solver.substeps = 0;
    p.desc.solver.adaptive_error_target = 0.003f;  // adaptive: the device stops at the target
    CHECK(iterations_of(p.run()) == 4u);
    p.desc.solver.adaptive_error_target = 0.0f;
    p.desc.solver.iterations = 1;
    p.frame.feedback.fluid_depth = 0.3f;
    CHECK(iterations_of(p.run()) == 1u);
}

TEST_CASE("step plan: a frame step longer than the substep cap holds simulates what the substeps hold", "[plan]") {
    Plan p;  // defaults: automatic substeps, at most 16, iterations 4 (the cap), h = 0.1 m
    p.frame.feedback.fluid_depth = 0.3f;
    // A frame the count holds is simulated whole.
    StepInput in = p.run();
    CHECK(in.simulated_dt == p.frame.frame_dt);
    CHECK_FALSE(in.colliders_cut);
    // A game's frame (up to 1/30 s) runs whole even where its substeps hold less: a column far
    // deeper than 16 substeps hold and a particle faster than h per substep.
    {
        Plan deep;
        deep.frame.feedback.fluid_depth = 500.0f;
        deep.frame.feedback.max_speed = 100.0f;
        for (float dt : {1.0f / 60.0f, 1.0f / 30.0f}) {
            deep.frame.frame_dt = dt;
            const StepInput whole = deep.run();
            CHECK(whole.substeps.size() == deep.desc.solver.max_substeps);
            CHECK(whole.simulated_dt == dt);
        }
        deep.frame.frame_dt = 1.0f / 29.0f;  // a hitch: held back
        CHECK(deep.run().simulated_dt < deep.frame.frame_dt);
        // However extreme the expected speed, a hitch simulates at least what a frame of 1/30 s
        // does (that one runs whole).
        deep.frame.feedback.max_speed = 1e30f;
        deep.frame.frame_dt = 1.0f;
        const StepInput extreme = deep.run();
        CHECK(extreme.simulated_dt == Approx(1.0f / 30.0f).epsilon(1e-5));
        CHECK(extreme.substeps[0].ctx.dt > 0.0f);
    }
    // One of 1 s: sixteen substeps of 1/16 s would compress the column past the depth rule at
    // any iteration count up to the cap; each is held to the rule at the cap instead.
    p.frame.frame_dt = 1.0f;
    in = p.run();
    REQUIRE(in.substeps.size() == p.desc.solver.max_substeps);
    const uint32_t k = in.substeps[0].iterations;
    CHECK(k == p.desc.solver.iterations);
    const double sub_dt = in.substeps[0].ctx.dt;
    CHECK(4.0 / (k + 0.5) * 9.81 * 0.3 * sub_dt * sub_dt / (0.1 * 0.1) <= 0.1 * (1.0 + 1e-4));
    CHECK(in.simulated_dt == Approx(sub_dt * in.substeps.size()).epsilon(1e-6));
    CHECK(in.simulated_dt < 0.5f);
    CHECK(in.frame_dt == 1.0f);  // a dynamic collider's force stays its impulse over the frame
    // Zero gravity, a drop at 5 m/s: fixed substeps too are held to 0.75 h of travel each.
    p.desc.gravity[1] = 0.0f;
    p.desc.solver.substeps = 4;
    p.frame.feedback.max_speed = 5.0f;
    in = p.run();
    REQUIRE(in.substeps.size() == 4u);
    CHECK(in.substeps[0].ctx.dt * 5.0f == Approx(0.75f * 0.1f).epsilon(1e-5));
    CHECK(in.substeps[0].ctx.speed_limit > 5.0f);
    // A collider moving over a held-back frame moves at its own speed over the simulated time,
    // to where the engine put it, and the rest of its way is a teleport settled at the start.
    ColliderKey moving{};
    moving.from_rotation = moving.to_rotation = Quat{0.0f, 0.0f, 0.0f, 1.0f};
    moving.to_position = Vec3{1.0f, 0.0f, 0.0f};
    StepInput with_collider;
    with_collider.collider_keys.push_back(moving);
    with_collider.collider_shapes.push_back(Collider{});
    plan_step(p.desc.solver, derive_constants(p.desc, p.materials), p.materials, p.frame, &p.emitters, &with_collider);
    REQUIRE(with_collider.simulated_dt < 1.0f);
    CHECK(with_collider.colliders_cut);
    const ColliderKey& cut = with_collider.collider_keys[0];
    CHECK(cut.to_position.x == 1.0f);
    CHECK(1.0f - cut.from_position.x == Approx(with_collider.simulated_dt).epsilon(1e-5));  // 1 m/s over it
    CHECK(with_collider.substeps[0].settle_overlaps);
    CHECK_FALSE(with_collider.substeps[1].settle_overlaps);
}

TEST_CASE("step plan: a frame step shorter than the shortest step waits, and no substep is shorter", "[plan]") {
    Plan p;
    p.desc.solver.substeps = 42;
    p.emitters.clear();
    p.add_nozzle(1000.0f);
    // Too short: no substeps, nothing simulated or emitted; its time waits for the next step.
    p.frame.frame_dt = 0.4f * kMinStepDt;
    StepInput in = p.run();
    CHECK(in.substeps.empty());
    CHECK(in.simulated_dt == 0.0f);
    CHECK(in.carried_dt == p.frame.frame_dt);
    CHECK(p.emitters[0].accumulator == 0.0f);
    // The next one simulates both: with the carried time it is 2.2 shortest steps long, so it
    // runs two substeps of 1.1 (not 42 of 5e-6 s).
    p.frame.carried_dt = in.carried_dt;
    p.frame.frame_dt = 1.8f * kMinStepDt;
    in = p.run();
    REQUIRE(in.substeps.size() == 2u);
    CHECK(in.carried_dt == 0.0f);
    CHECK(in.simulated_dt == Approx(2.2f * kMinStepDt).epsilon(1e-6));
    CHECK(in.frame_dt == p.frame.frame_dt);  // a dynamic collider's force: both impulses over this dt
    CHECK(in.substeps[0].ctx.dt == Approx(1.1f * kMinStepDt).epsilon(1e-6));
    // A game's frame keeps its 42 substeps.
    p.frame.carried_dt = 0.0f;
    p.frame.frame_dt = 1.0f / 60.0f;
    CHECK(p.run().substeps.size() == 42u);
}

// s_corr's bound (scorr_push, core/passes.h) measures every other setting against the reference
// shape and k of core/sph.h, which are documented as the C ABI's defaults; kScorrResponseSpeed is
// documented as the default sound_speed. Changing a default without them would silently bound the
// new defaults, or leave them unbounded.
TEST_CASE("step plan: s_corr's reference shape and response speed are the C ABI's defaults", "[plan]") {
    Plan plan;
    const pbf_solver_params& p = plan.desc.solver;
    CHECK(p.scorr_k == kScorrReferenceK);
    CHECK(p.scorr_n == kScorrReferenceN);
    CHECK(p.scorr_dq == kScorrReferenceDq);
    CHECK(p.sound_speed == kScorrResponseSpeed);

    WorldConstants c = derive_constants(plan.desc, plan.materials);
    CHECK(c.scorr_bounded == 0u);
    // The bound's reference term, scorr_ref_k min(ratio^4, cap), is the defaults' own term,
    // scorr_k sat(ratio^4 / cap) (their shape has no excess: its scale is the cap).
    CHECK(c.scorr_k == Approx(c.scorr_ref_k * kScorrPowerCap).epsilon(1e-6));
    CHECK(c.scorr_ref_inv_w_dq == Approx(c.scorr_inv_w_dq).epsilon(1e-6));

    plan.desc.solver.scorr_k = 0.05f;  // weaker than the defaults at their shape: nothing to bound
    CHECK(derive_constants(plan.desc, plan.materials).scorr_bounded == 0u);
    plan.desc.solver.scorr_k = 0.5f;
    CHECK(derive_constants(plan.desc, plan.materials).scorr_bounded == 1u);
    plan.desc.solver.scorr_k = 0.05f;
    plan.desc.solver.scorr_dq = 0.6f;  // another shape at any k
    CHECK(derive_constants(plan.desc, plan.materials).scorr_bounded == 1u);
    plan.desc.solver.scorr_k = 0.0f;  // s_corr off
    CHECK(derive_constants(plan.desc, plan.materials).scorr_bounded == 0u);
}
