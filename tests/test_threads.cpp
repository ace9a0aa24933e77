// Thread safety of the C ABI on the CPU backend (the header's "Thread safety" contract):
//   - worlds stepped on their own threads at once give bit-identical results to the same worlds
//     stepped one after another;
//   - calls on ONE world from several threads at once are serialised: no crash, every snapshot's
//     accounting is consistent;
//   - pbf_world_destroy racing with calls on the same world: they return OK or
//     PBF_ERROR_INVALID_HANDLE, never crash;
//   - the log callback: once pbf_set_log_callback returns, the previous callback is not called.
// The [gpu] twins of the first three are in test_gpu_reliability.cpp.
#include <catch2/catch.hpp>

#include <atomic>
#include <thread>
#include <vector>

#include "reliability_support.h"

TEST_CASE("threads: N worlds stepped on N threads give bit-identical results to one after another",
          "[threads][reliability]") {
    // 6 worlds (one of 8192 particles, whose OpenMP loops go parallel inside the thread).
    const rel::ParallelResult r = rel::parallel_vs_sequential(PBF_BACKEND_CPU, 6, 60);
    rel::check_parallel(r);
}

TEST_CASE("threads: concurrent step, stats, copies and edits on ONE world stay consistent", "[threads][reliability]") {
    const rel::SharedWorldResult r = rel::shared_world(PBF_BACKEND_CPU, 1.5);
    rel::check_shared_world(r);
}

TEST_CASE("threads: destroy racing with calls on the world returns OK or INVALID_HANDLE, never crashes",
          "[threads][reliability][handle]") {
    const rel::DestroyRaceResult r = rel::destroy_race(PBF_BACKEND_CPU, 20, 4);
    INFO("calls that completed " << r.ok << ", refused after destroy " << r.invalid);
    CHECK(r.error == "");
    CHECK(r.invalid == 20u * 4u);  // every caller saw the destroy
}

TEST_CASE("threads: worlds created and destroyed on many threads at once get distinct handles",
          "[threads][reliability][handle]") {
    const int kThreads = 6, kRounds = 40;
    std::vector<std::string> errors(kThreads);
    std::vector<std::vector<pbf_world_id>> seen(kThreads);
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t) {
        threads.emplace_back([&, t] {
            for (int k = 0; k < kRounds && errors[size_t(t)].empty(); ++k) {
                pbf_world_desc d = pbf_world_desc_default();
                d.backend = PBF_BACKEND_CPU;
                d.max_particles = 64;
                pbf_world_id id{};
                if (!REL_CALL(errors[size_t(t)], pbf_world_create(&d, &id))) return;
                seen[size_t(t)].push_back(id);
                uint32_t n = 1;
                if (!REL_CALL(errors[size_t(t)], pbf_world_get_particle_count(id, &n))) return;
                if (n != 0) errors[size_t(t)] = "a fresh world has particles";
                if (!REL_CALL(errors[size_t(t)], pbf_world_destroy(id))) return;
                if (pbf_world_destroy(id) != PBF_ERROR_INVALID_HANDLE) errors[size_t(t)] = "destroyed twice";
            }
        });
    }
    for (std::thread& t : threads) t.join();
    for (const std::string& e : errors) CHECK(e == "");
    // No two creations anywhere returned the same handle (a stale handle never names a new world).
    std::vector<std::pair<uint32_t, uint32_t>> all;
    for (const auto& v : seen)
        for (pbf_world_id id : v) all.emplace_back(id.index, id.generation);
    std::sort(all.begin(), all.end());
    CHECK(std::adjacent_find(all.begin(), all.end()) == all.end());
    CHECK(all.size() == size_t(kThreads) * kRounds);
}

namespace {
struct LogCounter {
    std::atomic<uint64_t> calls{0};
};
void PBF_CALL count_log(pbf_log_level, const char*, void* user) { static_cast<LogCounter*>(user)->calls.fetch_add(1); }
// Lets the other threads run for a while. Not sleep_for: below a millisecond it may return at
// once (MinGW's winpthreads round it down to Sleep(0)).
void pause_for(std::chrono::microseconds span) {
    const auto end = std::chrono::steady_clock::now() + span;
    while (std::chrono::steady_clock::now() < end) std::this_thread::yield();
}
}  // namespace

TEST_CASE("threads: after pbf_set_log_callback returns, the previous callback is never called",
          "[threads][reliability][log]") {
    LogCounter a, b;
    std::atomic<bool> stop{false};
    std::atomic<int> started{0};
    std::vector<std::thread> noisy;
    for (int t = 0; t < 3; ++t) {
        noisy.emplace_back([&] {  // errors from every thread, all the time
            started.fetch_add(1);
            while (!stop.load()) (void)pbf_world_step(pbf_world_id{0, 0}, 1.0f / 60.0f);
        });
    }
    // The rounds below last milliseconds: start them once the threads run (thread start-up can
    // take longer than that, e.g. under Wine), or neither callback may ever be called.
    while (started.load() < 3) std::this_thread::yield();
    bool stale_call = false;
    for (int round = 0; round < 200 && !stale_call; ++round) {
        pbf_set_log_callback(count_log, &a);
        pause_for(std::chrono::microseconds(200));
        pbf_set_log_callback(count_log, &b);
        const uint64_t frozen = a.calls.load();
        pause_for(std::chrono::microseconds(200));
        stale_call = a.calls.load() != frozen;
    }
    pbf_set_log_callback(nullptr, nullptr);
    const uint64_t b_frozen = b.calls.load();
    pause_for(std::chrono::milliseconds(5));
    stop.store(true);
    for (std::thread& t : noisy) t.join();
    CHECK_FALSE(stale_call);
    CHECK(b.calls.load() == b_frozen);
    CHECK(a.calls.load() > 0);
    CHECK(b.calls.load() > 0);
}
