// Calls added in 2.1 beside the names they replace: the per-stage profile, and the deprecated
// aliases pbf_emitter_set_transform and pbf_collider_set_pose, which must keep working until the
// next major version. Fixtures: support.h.
#include <catch2/catch.hpp>

#include <cstring>
#include <set>
#include <string>
#include <vector>

#include "pbf_c_api.h"
#include "support.h"

namespace {

pbf_step_profile empty_profile() {
    pbf_step_profile p;
    std::memset(&p, 0xFF, sizeof p);
    p.struct_size = sizeof p;
    return p;
}

}  // namespace

TEST_CASE("profile: named stages, zero while off, timed while on", "[api][profile]") {
    std::set<std::string> names;
    uint32_t n = 0;
    for (; n < PBF_PROFILE_MAX_STAGES && pbf_profile_stage_name(n); ++n) names.insert(pbf_profile_stage_name(n));
    CHECK(n >= 5u);
    CHECK(names.size() == n);  // distinct names
    CHECK(names.count("lambda") == 1);
    CHECK(pbf_profile_stage_name(n) == nullptr);
    CHECK(pbf_profile_stage_name(0xFFFFFFFFu) == nullptr);

    TestWorld w;
    w.emit_default_block();
    REQUIRE_OK(pbf_world_step(w, kDt));
    pbf_step_profile p = empty_profile();
    REQUIRE_OK(pbf_world_get_profile(w, &p));
    CHECK(p.stage_count == n);
    for (uint32_t k = 0; k < PBF_PROFILE_MAX_STAGES; ++k) CHECK(p.stage_ms[k] == 0.0f);

    REQUIRE_OK(pbf_world_set_profiling(w, 1));
    REQUIRE_OK(pbf_world_step(w, kDt));
    p = empty_profile();
    REQUIRE_OK(pbf_world_get_profile(w, &p));
    pbf_step_stats s;
    std::memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    REQUIRE_OK(pbf_world_get_stats(w, &s));
    float sum = 0.0f;
    for (uint32_t k = 0; k < p.stage_count; ++k) {
        INFO(pbf_profile_stage_name(k));
        CHECK(p.stage_ms[k] >= 0.0f);
        sum += p.stage_ms[k];
    }
    for (uint32_t k = p.stage_count; k < PBF_PROFILE_MAX_STAGES; ++k) CHECK(p.stage_ms[k] == 0.0f);
    CHECK(sum > 0.0f);
    CHECK(sum <= s.step_time_ms * 1.05f + 0.05f);  // the stages lie inside the step

    CHECK_FAILS(pbf_world_set_profiling(w, 2), PBF_ERROR_INVALID_ARGUMENT, "enabled");
    CHECK_FAILS(pbf_world_get_profile(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "pbf_step_profile");
    p.struct_size = 8;
    CHECK_FAILS(pbf_world_get_profile(w, &p), PBF_ERROR_STRUCT_SIZE, "pbf_step_profile.struct_size");
    REQUIRE_OK(pbf_world_set_profiling(w, 0));
}

#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
TEST_CASE("deprecated names: set_transform moves either emitter, set_pose sets the target pose", "[api][deprecated]") {
    TestWorld w;
    pbf_emitter_desc nd = nozzle_desc();
    pbf_emitter_id nozzle{}, drain{};
    REQUIRE_OK(pbf_world_create_emitter(w, &nd, &nozzle));
    const pbf_emitter_desc dd = drain_desc();
    REQUIRE_OK(pbf_world_create_emitter(w, &dd, &drain));

    // Moved by the old name, the nozzle emits at its new place.
    const float moved[3] = {0.3f, 0.7f, 0.3f}, down[3] = {0, -1, 0};
    REQUIRE_OK(pbf_emitter_set_transform(w, nozzle, moved, down));
    const float lo[3] = {-0.5f, 0, -0.5f}, hi[3] = {-0.4f, 0.1f, -0.4f};
    REQUIRE_OK(pbf_emitter_set_transform(w, drain, lo, hi));
    for (int k = 0; k < 10; ++k) REQUIRE_OK(pbf_world_step(w, kDt));
    const std::vector<float> p = w.positions();
    REQUIRE(!p.empty());
    for (size_t k = 0; k < p.size(); k += 4) {
        CHECK(p[k] > 0.1f);
        CHECK(p[k + 2] > 0.1f);
    }
    // The old name refuses what the new ones refuse, under its own name.
    const float zero[3] = {0, 0, 0};
    CHECK_FAILS(pbf_emitter_set_transform(w, nozzle, moved, zero), PBF_ERROR_INVALID_ARGUMENT, "pbf_emitter_set_transform");
    CHECK_FAILS(pbf_emitter_set_transform(w, drain, hi, lo), PBF_ERROR_INVALID_ARGUMENT, "box_max");

    const pbf_collider_desc cs = collider_desc(PBF_SHAPE_SPHERE);
    const pbf_collider_desc ck = collider_desc(PBF_SHAPE_SPHERE, PBF_MOTION_KINEMATIC);
    pbf_collider_id fixed{}, moving{};
    REQUIRE_OK(pbf_world_create_collider(w, &cs, &fixed));
    REQUIRE_OK(pbf_world_create_collider(w, &ck, &moving));
    const float at[3] = {0, 0.2f, 0}, q[4] = {0, 0, 0, 1};
    REQUIRE_OK(pbf_collider_set_pose(w, moving, at, q));
    CHECK_FAILS(pbf_collider_set_pose(w, fixed, at, q), PBF_ERROR_INVALID_STATE, "pbf_collider_set_pose");
    CHECK_FAILS(pbf_collider_set_target_pose(w, fixed, at, q), PBF_ERROR_INVALID_STATE, "pbf_collider_set_target_pose");
}
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
