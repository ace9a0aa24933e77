// Scenes and checks shared by the reliability tests of the CPU backend (test_threads.cpp,
// test_reliability.cpp) and of the CUDA backend (test_gpu_reliability.cpp). Everything here
// that may run on a worker thread reports failures as strings instead of Catch2 assertions
// (Catch2 v2 assertions are not thread-safe); the test thread checks them after join().
#pragma once
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "pbf_c_api.h"
#include "support.h"

namespace rel {

using ::set3;

inline std::string failure(const char* call, pbf_result r) {
    return std::string(call) + " -> " + pbf_result_string(r) + ": " + pbf_last_error_message();
}

// Runs a call; on failure stores the message in `err` (if empty) and returns false.
#define REL_CALL(err, call)                                                 \
    ([&]() {                                                                \
        const pbf_result r_ = (call);                                       \
        if (r_ != PBF_OK && (err).empty()) (err) = rel::failure(#call, r_); \
        return r_ == PBF_OK;                                                \
    }())

// A few distinct scenes, so that concurrent worlds do different work: a block of water, a
// nozzle and a drain, a kinematic sphere, one large enough (variant 3) that the CPU backend's
// loops go parallel (> 2048 particles).
struct World {
    pbf_world_id id{};
    pbf_emitter_id nozzle{}, drain{};
    pbf_collider_id sphere{};
    int variant = 0;
    bool has_nozzle = false, has_sphere = false;
};

inline pbf_world_desc scene_desc(pbf_backend backend, int variant) {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = backend;
    d.particle_radius = variant == 3 ? 0.0125f : 0.025f;
    d.max_particles = variant == 3 ? 8192 : 1500;
    set3(d.domain_min, 0.0f, 0.0f, 0.0f);
    set3(d.domain_max, 0.6f + 0.1f * float(variant % 3), 0.6f, 0.4f);
    d.solver.iterations = 2 + uint32_t(variant % 3);
    d.solver.substeps = 1 + uint32_t(variant % 2);
    d.solver.ldc_enabled = uint32_t(variant % 2);
    d.gravity[0] = 0.5f * float(variant % 3) - 0.5f;
    return d;
}

// Creates scene `variant` (any int >= 0) on `backend`; "" or the failure.
inline std::string make_world(pbf_backend backend, int variant, World* w) {
    std::string err;
    w->variant = variant;
    const pbf_world_desc d = scene_desc(backend, variant);
    if (!REL_CALL(err, pbf_world_create(&d, &w->id))) return err;
    pbf_block_desc b = pbf_block_desc_default();
    set3(b.box_min, 0.02f + 0.01f * float(variant % 4), 0.0f, 0.02f);
    set3(b.box_max, variant == 3 ? 0.5f : 0.3f, variant == 3 ? 0.35f : 0.25f, 0.3f);  // variant 3: ~2900
    if (!REL_CALL(err, pbf_world_emit_block(w->id, &b, nullptr))) return err;
    if (variant % 4 != 1) {
        pbf_emitter_desc n = pbf_emitter_desc_default();
        n.type = PBF_EMITTER_NOZZLE;
        set3(n.position, 0.4f, 0.5f, 0.2f);
        set3(n.direction, -0.3f, -1.0f, 0.05f * float(variant));
        n.speed = 3.0f;
        n.radius = 0.15f;  // the disc carries π 0.15² / 0.05² x 3 / 0.05 = 1696 per second at r = 2.5 cm
        n.particles_per_second = 600.0f + 100.0f * float(variant % 5);
        if (!REL_CALL(err, pbf_world_create_emitter(w->id, &n, &w->nozzle))) return err;
        pbf_emitter_desc dr = pbf_emitter_desc_default();
        dr.type = PBF_EMITTER_DRAIN;
        set3(dr.box_min, 0.45f, 0.0f, 0.0f);
        set3(dr.box_max, 0.6f, 0.08f, 0.4f);
        if (!REL_CALL(err, pbf_world_create_emitter(w->id, &dr, &w->drain))) return err;
        w->has_nozzle = true;
    }
    if (variant % 3 != 2) {
        pbf_collider_desc c = pbf_collider_desc_default();
        c.shape = PBF_SHAPE_SPHERE;
        c.motion = PBF_MOTION_KINEMATIC;
        set3(c.position, 0.3f, 0.1f, 0.2f);
        c.radius = 0.06f;
        c.friction = 0.1f * float(variant % 4);
        if (!REL_CALL(err, pbf_world_create_collider(w->id, &c, &w->sphere))) return err;
        w->has_sphere = true;
    }
    return err;
}

// Advances the scene by `steps` steps, moving its nozzle and sphere before each.
inline std::string drive(const World& w, int first_step, int steps) {
    std::string err;
    const float dt = 1.0f / 60.0f;
    for (int k = first_step; k < first_step + steps; ++k) {
        const float t = float(k) * dt;
        if (w.has_nozzle) {
            const float p[3] = {0.4f + 0.1f * std::sin(t * 2.0f), 0.5f, 0.2f};
            const float d[3] = {-0.3f, -1.0f, 0.1f * std::cos(t)};
            if (!REL_CALL(err, pbf_emitter_set_nozzle(w.id, w.nozzle, p, d))) return err;
        }
        if (w.has_sphere) {
            const float p[3] = {0.3f + 0.1f * std::cos(3.0f * t), 0.1f, 0.2f + 0.05f * std::sin(3.0f * t)};
            const float q[4] = {0.0f, std::sin(t), 0.0f, std::cos(t)};
            if (!REL_CALL(err, pbf_collider_set_target_pose(w.id, w.sphere, p, q))) return err;
        }
        if (!REL_CALL(err, pbf_world_step(w.id, dt))) return err;
    }
    return err;
}

// A world's particles as bits, keyed by particle id (storage order may differ between runs
// only if the physics differs, but ids make the comparison independent of it).
struct Capture {
    uint32_t count = 0;
    uint64_t emitted = 0, drained = 0, step_index = 0;
    std::map<uint32_t, std::array<uint32_t, 7>> by_id;  // x y z w(density ratio) vx vy vz
};

inline std::string capture(pbf_world_id id, Capture* out) {
    std::string err;
    if (!REL_CALL(err, pbf_world_get_particle_count(id, &out->count))) return err;
    std::vector<float> pos(size_t(out->count) * 4), vel(size_t(out->count) * 4);
    std::vector<uint32_t> ids(out->count);
    uint32_t n = 0;
    if (!REL_CALL(err, pbf_world_copy_positions(id, pos.data(), out->count, &n))) return err;
    if (n != out->count) return "copy_positions wrote " + std::to_string(n) + " of " + std::to_string(out->count);
    if (!REL_CALL(err, pbf_world_copy_velocities(id, vel.data(), out->count, &n))) return err;
    if (!REL_CALL(err, pbf_world_copy_ids(id, ids.data(), out->count, &n))) return err;
    pbf_step_stats st;
    std::memset(&st, 0, sizeof st);
    st.struct_size = sizeof st;
    if (!REL_CALL(err, pbf_world_get_stats(id, &st))) return err;
    out->emitted = st.emitted_total;
    out->drained = st.drained_total;
    out->step_index = st.step_index;
    out->by_id.clear();
    for (uint32_t i = 0; i < out->count; ++i) {
        std::array<uint32_t, 7> bits;
        std::memcpy(bits.data(), &pos[4 * size_t(i)], 4 * sizeof(float));
        std::memcpy(bits.data() + 4, &vel[4 * size_t(i)], 3 * sizeof(float));
        if (!out->by_id.emplace(ids[i], bits).second) return "duplicate id " + std::to_string(ids[i]);
    }
    return err;
}

// "" when a and b hold the same particles with bit-identical state; else the first difference.
inline std::string compare(const Capture& a, const Capture& b) {
    if (a.count != b.count) return "count " + std::to_string(a.count) + " vs " + std::to_string(b.count);
    if (a.emitted != b.emitted || a.drained != b.drained || a.step_index != b.step_index)
        return "emitted/drained/step_index differ";
    for (const auto& [id, bits] : a.by_id) {
        const auto it = b.by_id.find(id);
        if (it == b.by_id.end()) return "particle id " + std::to_string(id) + " missing";
        if (it->second != bits) {
            float fa[7], fb[7];
            std::memcpy(fa, bits.data(), sizeof fa);
            std::memcpy(fb, it->second.data(), sizeof fb);
            return "particle id " + std::to_string(id) + " differs: x " + std::to_string(fa[0]) + " vs " +
                   std::to_string(fb[0]) + ", vx " + std::to_string(fa[4]) + " vs " + std::to_string(fb[4]);
        }
    }
    return "";
}

// Accounting and finiteness of a capture: "" when consistent.
inline std::string consistent(const Capture& c, uint32_t capacity) {
    if (c.count > capacity) return "count above capacity";
    if (c.emitted < c.drained || c.emitted - c.drained != c.count)
        return "emitted " + std::to_string(c.emitted) + " - drained " + std::to_string(c.drained) + " != count " +
               std::to_string(c.count);
    for (const auto& [id, bits] : c.by_id) {
        float f[7];
        std::memcpy(f, bits.data(), sizeof f);
        for (float v : f)
            if (!std::isfinite(v)) return "non-finite state of particle " + std::to_string(id);
    }
    return "";
}

// ---- scenario: N worlds on N threads against the same worlds one after another -------------
struct ParallelResult {
    std::vector<std::string> errors;       // per world, "" if fine
    std::vector<std::string> differences;  // per world, "" if bit-identical
};

inline ParallelResult parallel_vs_sequential(pbf_backend backend, int worlds, int steps) {
    ParallelResult res;
    res.errors.assign(size_t(worlds), "");
    res.differences.assign(size_t(worlds), "");
    // Sequential: each world created, stepped and captured in turn.
    std::vector<Capture> sequential(static_cast<size_t>(worlds));
    for (int k = 0; k < worlds; ++k) {
        World w;
        std::string& err = res.errors[size_t(k)];
        err = make_world(backend, k, &w);
        if (err.empty()) err = drive(w, 0, steps);
        if (err.empty()) err = capture(w.id, &sequential[size_t(k)]);
        if (w.id.generation) pbf_world_destroy(w.id);
        if (!err.empty()) return res;
    }
    // Parallel: the same worlds, created, stepped and captured on their own threads at once.
    std::vector<Capture> parallel(static_cast<size_t>(worlds));
    std::vector<std::thread> threads;
    std::atomic<int> ready{0};
    for (int k = 0; k < worlds; ++k) {
        threads.emplace_back([&, k] {
            World w;
            std::string& err = res.errors[size_t(k)];
            err = make_world(backend, k, &w);
            ready.fetch_add(1);
            while (ready.load() < worlds) std::this_thread::yield();  // step at the same time
            if (err.empty()) err = drive(w, 0, steps);
            if (err.empty()) err = capture(w.id, &parallel[size_t(k)]);
            if (w.id.generation) pbf_world_destroy(w.id);
        });
    }
    for (std::thread& t : threads) t.join();
    for (int k = 0; k < worlds; ++k)
        if (res.errors[size_t(k)].empty())
            res.differences[size_t(k)] = compare(sequential[size_t(k)], parallel[size_t(k)]);
    return res;
}

// ---- scenario: several threads calling into ONE world at once ----------------------------------
struct SharedWorldResult {
    std::string error;  // first unexpected result or inconsistency
    uint64_t steps = 0, reads = 0, copies = 0, edits = 0;
};

inline SharedWorldResult shared_world(pbf_backend backend, double seconds) {
    SharedWorldResult res;
    World w;
    res.error = make_world(backend, 0, &w);
    if (!res.error.empty()) return res;
    const uint32_t capacity = scene_desc(backend, 0).max_particles;
    std::atomic<bool> stop{false};
    std::vector<std::string> errors(4);
    std::atomic<uint64_t> steps{0}, reads{0}, copies{0}, edits{0};
    std::vector<std::thread> threads;
    // 0: steps (and moves the nozzle and sphere).
    threads.emplace_back([&] {
        int k = 0;
        while (!stop.load() && errors[0].empty()) {
            errors[0] = drive(w, k++, 1);
            steps.fetch_add(1);
        }
    });
    // 1: stats and counts: the accounting holds in every snapshot.
    threads.emplace_back([&] {
        uint64_t last_step = 0;
        while (!stop.load() && errors[1].empty()) {
            pbf_step_stats st;
            std::memset(&st, 0, sizeof st);
            st.struct_size = sizeof st;
            if (!REL_CALL(errors[1], pbf_world_get_stats(w.id, &st))) break;
            if (st.emitted_total - st.drained_total != st.particle_count || st.particle_count > capacity)
                errors[1] = "stats snapshot: emitted - drained != count";
            if (st.step_index < last_step) errors[1] = "step_index went backwards";
            last_step = st.step_index;
            uint32_t n = 0;
            if (!REL_CALL(errors[1], pbf_world_get_particle_count(w.id, &n))) break;
            if (n > capacity) errors[1] = "count above capacity";
            reads.fetch_add(1);
        }
    });
    // 2: copies with max_count below, at and above the count; writes <= max_count, all finite.
    threads.emplace_back([&] {
        std::vector<float> buf(size_t(capacity) * 4 + 64);
        std::vector<uint32_t> ids(capacity + 16);
        uint32_t round = 0;
        while (!stop.load() && errors[2].empty()) {
            const uint32_t max_count = (round++ % 3 == 0) ? capacity / 3 : capacity;
            const float canary = -12345.0f;
            for (size_t k = size_t(max_count) * 4; k < buf.size(); ++k) buf[k] = canary;
            uint32_t written = 0;
            if (!REL_CALL(errors[2], pbf_world_copy_positions(w.id, buf.data(), max_count, &written))) break;
            if (written > max_count) errors[2] = "copy_positions wrote more than max_count";
            for (size_t k = 0; k < size_t(written) * 4; ++k)
                if (!std::isfinite(buf[k])) errors[2] = "non-finite position";
            for (size_t k = size_t(max_count) * 4; k < buf.size(); ++k)
                if (buf[k] != canary) errors[2] = "copy_positions wrote past max_count";
            if (!REL_CALL(errors[2], pbf_world_copy_ids(w.id, ids.data(), max_count, &written))) break;
            if (written > max_count) errors[2] = "copy_ids wrote more than max_count";
            if (!REL_CALL(errors[2], pbf_world_copy_velocities(w.id, buf.data(), max_count, &written))) break;
            copies.fetch_add(1);
        }
    });
    // 3: edits: solver parameters, gravity, colliders created and destroyed, emitter toggled,
    // map/unmap (the mapped data is not read: another thread's step may end the mapping).
    threads.emplace_back([&] {
        uint32_t round = 0;
        while (!stop.load() && errors[3].empty()) {
            ++round;
            pbf_solver_params p = pbf_solver_params_default();
            if (!REL_CALL(errors[3], pbf_world_get_solver_params(w.id, &p))) break;
            p.iterations = 2 + round % 3;
            if (!REL_CALL(errors[3], pbf_world_set_solver_params(w.id, &p))) break;
            const float g[3] = {0.0f, -9.81f + 0.1f * float(round % 5), 0.0f};
            if (!REL_CALL(errors[3], pbf_world_set_gravity(w.id, g))) break;
            pbf_collider_desc c = pbf_collider_desc_default();
            c.shape = PBF_SHAPE_BOX;
            set3(c.position, 0.5f, 0.05f, 0.3f);
            set3(c.half_extents, 0.03f, 0.03f, 0.03f);
            pbf_collider_id box{};
            if (!REL_CALL(errors[3], pbf_world_create_collider(w.id, &c, &box))) break;
            if (w.has_nozzle && !REL_CALL(errors[3], pbf_emitter_set_enabled(w.id, w.nozzle, round % 4 != 0))) break;
            pbf_mapped_buffer m;
            std::memset(&m, 0, sizeof m);
            m.struct_size = sizeof m;
            if (!REL_CALL(errors[3], pbf_world_map_positions(w.id, &m))) break;
            const pbf_result u = pbf_world_unmap(w.id);  // a step in between already ended it
            if (u != PBF_OK && u != PBF_ERROR_INVALID_STATE) errors[3] = rel::failure("pbf_world_unmap", u);
            if (!REL_CALL(errors[3], pbf_world_destroy_collider(w.id, box))) break;
            edits.fetch_add(1);
        }
    });
    std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    stop.store(true);
    for (std::thread& t : threads) t.join();
    for (const std::string& e : errors)
        if (res.error.empty() && !e.empty()) res.error = e;
    Capture c;
    if (res.error.empty()) res.error = capture(w.id, &c);
    if (res.error.empty()) res.error = consistent(c, capacity);
    if (res.error.empty() && c.step_index != steps.load()) res.error = "step_index differs from the steps taken";
    const pbf_result r = pbf_world_destroy(w.id);
    if (res.error.empty() && r != PBF_OK) res.error = failure("pbf_world_destroy", r);
    res.steps = steps.load();
    res.reads = reads.load();
    res.copies = copies.load();
    res.edits = edits.load();
    return res;
}

// ---- scenario: pbf_world_destroy racing with calls from other threads ------------------------
struct DestroyRaceResult {
    std::string error;  // a result other than OK / INVALID_HANDLE (or CAPACITY for emits)
    uint64_t ok = 0, invalid = 0;
};

inline DestroyRaceResult destroy_race(pbf_backend backend, int rounds, int callers) {
    DestroyRaceResult res;
    std::atomic<uint64_t> ok{0}, invalid{0};
    for (int round = 0; round < rounds && res.error.empty(); ++round) {
        World w;
        res.error = make_world(backend, round % 3, &w);
        if (!res.error.empty()) return res;
        std::vector<std::string> errors(static_cast<size_t>(callers));
        std::atomic<int> started{0};
        std::vector<std::thread> threads;
        for (int t = 0; t < callers; ++t) {
            threads.emplace_back([&, t] {
                started.fetch_add(1);
                std::vector<float> buf(4096 * 4);
                for (int k = 0;; ++k) {
                    pbf_result r = PBF_OK;
                    uint32_t n = 0;
                    pbf_step_stats st;
                    std::memset(&st, 0, sizeof st);
                    st.struct_size = sizeof st;
                    pbf_block_desc b = pbf_block_desc_default();
                    set3(b.box_min, 0.4f, 0.3f, 0.1f);
                    set3(b.box_max, 0.45f, 0.35f, 0.15f);
                    pbf_collider_desc c = pbf_collider_desc_default();
                    c.shape = PBF_SHAPE_PLANE;
                    pbf_collider_id cid{};
                    pbf_mapped_buffer m;
                    std::memset(&m, 0, sizeof m);
                    m.struct_size = sizeof m;
                    switch ((k + t) % 8) {
                        case 0:
                            r = pbf_world_step(w.id, 1.0f / 60.0f);
                            break;
                        case 1:
                            r = pbf_world_get_stats(w.id, &st);
                            break;
                        case 2:
                            r = pbf_world_copy_positions(w.id, buf.data(), 4096, &n);
                            break;
                        case 3:
                            r = pbf_world_get_particle_count(w.id, &n);
                            break;
                        case 4:
                            r = pbf_world_emit_block(w.id, &b, &n);
                            break;
                        case 5:
                            r = pbf_world_create_collider(w.id, &c, &cid);
                            if (r == PBF_OK) {
                                const pbf_result r2 = pbf_world_destroy_collider(w.id, cid);
                                if (r2 != PBF_OK && r2 != PBF_ERROR_INVALID_HANDLE) r = r2;
                            }
                            break;
                        case 6:
                            r = pbf_world_map_positions(w.id, &m);
                            if (r == PBF_OK) {
                                const pbf_result r2 = pbf_world_unmap(w.id);
                                if (r2 != PBF_OK && r2 != PBF_ERROR_INVALID_HANDLE && r2 != PBF_ERROR_INVALID_STATE)
                                    r = r2;
                            }
                            break;
                        default: {
                            pbf_solver_params p = pbf_solver_params_default();
                            r = pbf_world_get_solver_params(w.id, &p);
                            if (r == PBF_OK) r = pbf_world_set_solver_params(w.id, &p);
                            break;
                        }
                    }
                    if (r == PBF_OK || (r == PBF_ERROR_CAPACITY && (k + t) % 8 == 4)) {
                        ok.fetch_add(1);
                    } else if (r == PBF_ERROR_INVALID_HANDLE) {
                        invalid.fetch_add(1);
                        return;  // destroyed: every later call is refused the same way
                    } else {
                        errors[size_t(t)] = failure("call on a world being destroyed", r);
                        return;
                    }
                }
            });
        }
        while (started.load() < callers) std::this_thread::yield();
        std::this_thread::sleep_for(std::chrono::milliseconds(2 * (round % 5)));
        const pbf_result r = pbf_world_destroy(w.id);
        if (r != PBF_OK) res.error = failure("pbf_world_destroy", r);
        for (std::thread& t : threads) t.join();
        for (const std::string& e : errors)
            if (res.error.empty() && !e.empty()) res.error = e;
        // The handle is dead for good.
        uint32_t n = 0;
        if (res.error.empty() && pbf_world_get_particle_count(w.id, &n) != PBF_ERROR_INVALID_HANDLE)
            res.error = "a destroyed world still answers";
    }
    res.ok = ok.load();
    res.invalid = invalid.load();
    return res;
}

// ---- checks the CPU tests and their CUDA twins share (Catch2: on the test thread only) --------
inline void check_parallel(const ParallelResult& r) {
    for (size_t k = 0; k < r.errors.size(); ++k) {
        INFO("world " << k);
        CHECK(r.errors[k] == "");
        CHECK(r.differences[k] == "");
    }
}

inline void check_shared_world(const SharedWorldResult& r) {
    INFO("steps " << r.steps << ", stats reads " << r.reads << ", copy rounds " << r.copies << ", edit rounds "
                  << r.edits);
    CHECK(r.error == "");
    CHECK(r.steps > 0);
    CHECK(r.reads > 0);
    CHECK(r.copies > 0);
    CHECK(r.edits > 0);
}

// The survivor (scene 0, driven `first` steps so far) steps on for `steps` more exactly as a twin
// that never saw what the survivor went through; the twin is destroyed again.
inline void check_like_twin(pbf_backend backend, const World& survivor, int first, int steps) {
    World twin;
    REQUIRE(make_world(backend, 0, &twin) == "");
    REQUIRE(drive(twin, 0, first) == "");
    REQUIRE(drive(survivor, first, steps) == "");
    REQUIRE(drive(twin, first, steps) == "");
    Capture after_survivor, after_twin;
    REQUIRE(capture(survivor.id, &after_survivor) == "");
    REQUIRE(capture(twin.id, &after_twin) == "");
    CHECK(compare(after_survivor, after_twin) == "");
    CHECK(consistent(after_survivor, 1500) == "");
    REQUIRE(pbf_world_destroy(twin.id) == PBF_OK);
}

}  // namespace rel
