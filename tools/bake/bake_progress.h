// A plain-text progress bar with ETA on stderr: redrawn in place ("\r") when stderr is a
// terminal, otherwise one line per 10 % so that logs stay short.
#pragma once
#include <chrono>
#include <cstdint>
#include <cstdio>

#if defined(_WIN32)
#include <io.h>
#define PBF_BAKE_ISATTY(fd) _isatty(fd)
#else
#include <unistd.h>
#define PBF_BAKE_ISATTY(fd) isatty(fd)
#endif

namespace bake {

class Progress {
public:
    Progress(int64_t total, bool enabled)
        : total_(total > 0 ? total : 1),
          enabled_(enabled),
          tty_(PBF_BAKE_ISATTY(2) != 0),
          start_(std::chrono::steady_clock::now()) {}

    // `done` frames of `total` finished; `count` particles in the last one.
    void update(int64_t done, uint32_t count) {
        if (!enabled_) return;
        const double elapsed = seconds();
        const double frac = double(done) / double(total_);
        const int pct = int(frac * 100.0 + 1e-9);
        char eta[32];
        format_time(done > 0 ? elapsed / double(done) * double(total_ - done) : -1.0, eta, sizeof eta);
        if (tty_) {
            const int width = 30, filled = int(frac * width + 1e-9);
            char bar[width + 1];
            for (int i = 0; i < width; ++i) bar[i] = i < filled ? '#' : '.';
            bar[width] = '\0';
            std::fprintf(stderr, "\r[%s] %3d%%  frame %lld/%lld  %u particles  %.1f frames/s  ETA %s   ", bar, pct,
                         (long long)done, (long long)total_, count, done > 0 ? double(done) / elapsed : 0.0, eta);
            drawn_ = done < total_;
            if (!drawn_) std::fprintf(stderr, "\n");
            std::fflush(stderr);
        } else {
            // One line when a new multiple of 10 % is reached (one line even if a frame crosses several).
            if (next_decile_ <= 10 && pct >= next_decile_ * 10) {
                std::fprintf(stderr, "pbf_bake: %3d%%  frame %lld/%lld  %u particles  elapsed %.1f s  ETA %s\n", pct,
                             (long long)done, (long long)total_, count, elapsed, eta);
                next_decile_ = pct / 10 + 1;
            }
            std::fflush(stderr);
        }
    }

    // Ends the bar's line (on a terminal) so that a message can follow on a line of its own.
    void break_line() {
        if (drawn_) std::fprintf(stderr, "\n");
        drawn_ = false;
    }

    double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

private:
    static void format_time(double s, char* out, size_t n) {
        if (s < 0) {
            std::snprintf(out, n, "--:--");
            return;
        }
        const long t = long(s + 0.5);
        if (t >= 3600)
            std::snprintf(out, n, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
        else
            std::snprintf(out, n, "%02ld:%02ld", t / 60, t % 60);
    }

    int64_t total_;
    bool enabled_, tty_, drawn_ = false;
    int next_decile_ = 0;
    std::chrono::steady_clock::time_point start_;
};

}  // namespace bake
