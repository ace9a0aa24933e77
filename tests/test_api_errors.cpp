// Black-box tests of the C ABI (include/pbf_c_api.h) on the CPU backend. Errors: the log callback and the thread-local message.
// Fixtures: support.h.
#include "support.h"

// =============================================================================================
namespace {
struct LogCapture {
    std::vector<std::pair<pbf_log_level, std::string>> entries;
    std::vector<void*> user_data;
};
void PBF_CALL capture_log(pbf_log_level level, const char* message, void* user_data) {
    LogCapture* cap = static_cast<LogCapture*>(user_data);
    cap->entries.emplace_back(level, message ? message : "(null)");
    cap->user_data.push_back(user_data);
}
}  // namespace

TEST_CASE("log callback: receives errors with the message and user_data, and can be removed", "[api][log]") {
    TestWorld w;
    LogCapture cap;
    pbf_set_log_callback(capture_log, &cap);

    CHECK(pbf_world_step(w, -1.0f) == PBF_ERROR_INVALID_ARGUMENT);
    const std::string message = last_message();
    pbf_set_log_callback(nullptr, nullptr);

    REQUIRE(cap.entries.size() == 1u);
    CHECK(cap.entries[0].first == PBF_LOG_ERROR);
    CHECK(cap.entries[0].second == message);
    CHECK_THAT(message, Catch::Contains("dt"));
    CHECK(cap.user_data[0] == &cap);

    // Removed: further errors are not delivered.
    CHECK(pbf_world_step(w, kNaN) == PBF_ERROR_INVALID_ARGUMENT);
    CHECK(pbf_world_step(pbf_world_id{0, 0}, kDt) == PBF_ERROR_INVALID_HANDLE);
    CHECK(cap.entries.size() == 1u);

    // Informational events arrive at a level below ERROR.
    LogCapture info;
    pbf_set_log_callback(capture_log, &info);
    {
        TestWorld x;
        (void)x;
    }
    pbf_set_log_callback(nullptr, nullptr);
    for (const auto& e : info.entries) CHECK(e.first != PBF_LOG_ERROR);
    w.require_usable(0);
}

TEST_CASE("error message is thread-local", "[api][thread]") {
    TestWorld w;
    CHECK(pbf_world_step(w, -5.0f) == PBF_ERROR_INVALID_ARGUMENT);
    const std::string mine = last_message();
    REQUIRE_THAT(mine, Catch::Contains("dt"));

    std::string other_before, other_after;
    pbf_result other_result = PBF_OK;
    std::thread t([&] {
        other_before = pbf_last_error_message();  // a fresh thread has no error
        uint32_t count = 0;
        other_result = pbf_world_get_particle_count(pbf_world_id{12345, 7}, &count);
        other_after = pbf_last_error_message();
    });
    t.join();
    CHECK(other_before.empty());
    CHECK(other_result == PBF_ERROR_INVALID_HANDLE);
    CHECK_THAT(other_after, Catch::Contains("12345"));
    CHECK(last_message() == mine);  // thread B's failure did not overwrite A's message

    // Two threads working on two worlds at once.
    TestWorld w2;
    w.emit_default_block();
    w2.emit_default_block();
    std::thread t1([&] {
        for (int i = 0; i < 5; ++i) pbf_world_step(w, kDt);
    });
    std::thread t2([&] {
        for (int i = 0; i < 5; ++i) pbf_world_step(w2, kDt);
    });
    t1.join();
    t2.join();
    CHECK(w.count() == w2.count());
}
