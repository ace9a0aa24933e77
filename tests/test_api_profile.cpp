// The per-stage profile of a step (pbf_world_set_profiling, pbf_world_get_profile,
// pbf_profile_stage_name), as pbf_bench reads it. Fixtures: support.h.
#include <catch2/catch.hpp>

#include <cstring>
#include <set>
#include <string>

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
