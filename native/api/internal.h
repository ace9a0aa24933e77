// Internal hooks for pbf_bench (linked against the static core): not part of the C ABI and not
// exported from the shared library.
#pragma once
#include "../world/world.h"
#include "pbf_c_api.h"

namespace pbf {
// Turns per-stage timing on or off for a world (on: each stage boundary records an event).
pbf_result internal_set_profiling(pbf_world_id world, bool on);
// Per-stage milliseconds of the world's last step (waits for it).
pbf_result internal_stage_times(pbf_world_id world, StageTimes* out);
}  // namespace pbf
