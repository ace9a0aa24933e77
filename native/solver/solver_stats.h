// What the host reads of a solver's steps: the feedback each step publishes into host-visible
// memory (read without waiting), the statistics (read back on request), the step's time and its
// per-stage profile.
#pragma once
#include <cstdint>

#include "backend.h"
#include "solver_buffers.h"
#include "solver_render.h"
#include "../core/passes.h"
#include "../core/step_ops.h"

namespace pbf {

template <class Exec>
class SolverStats {
public:
    explicit SolverStats(Exec& exec) : exec_(exec) {}

    void allocate(Allocations<Exec>& alloc) {
        feedback_ = exec_.template alloc_host_visible<StepFeedback>(1);
        alloc.ok = alloc.ok && feedback_ != nullptr;
    }
    void zero() { *feedback_ = StepFeedback{}; }
    void release() { exec_.release_host_visible(feedback_); }

    // The step's last launches: the feedback of the first n particles, summed on the backend and
    // published to the host.
    void publish(const WorldConstants& s, const ParticleBuffers& p, uint32_t n) {
        const HeightFrame frame = height_frame(s);
        exec_.reduce_feedback(frame, p.pos_, p.vel_, &p.counters_->count, n, &p.counters_->feedback);
        exec_.for_each(1, PublishFeedbackOp{p.counters_, frame, feedback_});
    }
    // The latest finished step's feedback, without waiting.
    StepFeedback feedback() {
        exec_.activate();
        if (exec_.feedback_ready()) last_feedback_ = *feedback_;
        return last_feedback_;
    }

    // The counters, the diffuse particles' and the sums over the particles' densities (the
    // caller's ρ, current) and velocities (waits for the backend).
    Status read(const WorldConstants& s, const ParticleBuffers& p, SolverDiffuse<Exec>& diffuse, StatsReadback* out) {
        DeviceCounters c{};
        exec_.download(&c, p.counters_, sizeof c);
        Status st = exec_.check("pbf_world_get_stats");
        if (!st.ok()) return st;
        out->count = c.count;
        out->iterations_used = c.control.iterations_used;
        out->speed_clamps = c.speed_clamps;
        out->emitted_total = c.emitted_total;
        out->drained_total = c.drained_total;
        diffuse.read_stats(out);
        exec_.reduce_stats(s, p.density_, p.vel_, c.count, out);
        return exec_.check("pbf_world_get_stats");
    }

    Status last_step_ms(float* ms) {
        exec_.activate();
        *ms = exec_.timer_ms();
        return exec_.check("step timer");
    }
    void set_profiling(bool on) { exec_.profile_enable(on); }
    Status stage_times(StageTimes* out) {
        exec_.activate();
        exec_.profile_read(out->ms, kStageCount);
        return exec_.check("stage timing");
    }

private:
    Exec& exec_;
    StepFeedback* feedback_ = nullptr;  // host-visible; written by the step's last op
    StepFeedback last_feedback_{};
};

}  // namespace pbf
