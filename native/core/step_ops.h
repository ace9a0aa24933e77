// The step's bookkeeping ops, one thread each: the counters a step keeps in backend memory, and
// the feedback it publishes for the host to read without waiting.
#pragma once
#include "passes.h"

namespace pbf {

// What a step leaves for the host to read without waiting (the next step's substep choice):
// valid once the step has finished on the backend; the host reads the latest finished one.
struct StepFeedback {
    float max_speed = 0.0f;     // fastest particle at the end of the step (m/s)
    uint32_t speed_clamps = 0;  // particle-substeps whose speed a limit cut
    uint32_t steps = 0;         // steps finished (0: no feedback yet)
    float fluid_depth = 0.0f;   // the particles' extent along gravity at the end of the step (m)
};

// Counters that live in backend memory so the step never reads them back.
struct DeviceCounters {
    uint32_t count;  // live particles in slots [0, count)
    uint32_t next_id;
    uint32_t drained;  // drained this step, folded into drained_total
    uint32_t blocked;  // points of the current nozzle emission inside a collider: not emitted
    unsigned long long emitted_total;
    unsigned long long drained_total;
    IterationControl control;
    uint32_t speed_clamps;  // particle-substeps a speed limit cut, this step
    uint32_t steps;         // steps finished
    FeedbackBits feedback;  // the fastest particle and the fluid's extent at the end of the step
    uint32_t pad2;
};

// One thread at the start of a step: clears the step's counters.
struct BeginStepOp {
    DeviceCounters* c;
    PBF_HD void operator()(uint32_t) const {
        c->control.converged = 0;
        c->control.error_sum = 0.0f;
        c->control.iterations_used = 0;
        c->speed_clamps = 0;
        c->feedback = FeedbackBits{0, 0, 0};
    }
};

// One thread at the end of a step: publishes what the host reads without waiting.
struct PublishFeedbackOp {
    DeviceCounters* c;
    HeightFrame frame;
    StepFeedback* out;  // host-visible memory
    PBF_HD void operator()(uint32_t) const {
        ++c->steps;
        StepFeedback f;
        f.max_speed = float_from_bits(c->feedback.speed);
        f.speed_clamps = c->speed_clamps;
        f.steps = c->steps;
        f.fluid_depth = fluid_depth(frame, c->feedback);
        *out = f;
    }
};

}  // namespace pbf
