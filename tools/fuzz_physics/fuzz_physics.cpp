// fuzz_physics: random valid worlds and histories through the public C API, with the physics
// invariants checked after every step (docs/physics_fuzzer.md).
//
//   fuzz_physics --worlds 1000 --jobs 2                 # worlds 0..999 of seed 1
//   fuzz_physics --seed 7 --world 123                    # replay one world
//   fuzz_physics --seed 7 --world 123 --frames 9 --drop c1,n0   # a shrunk repro
//   fuzz_physics --corpus tools/fuzz_physics/corpus.txt  # the regression corpus
//
// A failure prints the world's seed and index, the invariant and its numbers, then a shrunk
// repro (frames cut after the failing one, objects switched off while it still fails) as a
// command line and a corpus line. The last line is "fuzz_physics: N worlds, F failures"; the exit
// status is 1 when any world failed.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstring>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include "fuzz_run.h"

namespace {

using namespace fuzz;

// The solver's fields by name and offset (all 4 bytes wide).
const std::vector<std::pair<std::string, size_t>>& solver_fields() {
#define PBF_FIELD(name) \
    { #name, offsetof(pbf_solver_params, name) }
    static const std::vector<std::pair<std::string, size_t>> fields = {
        PBF_FIELD(iterations),   PBF_FIELD(substeps),       PBF_FIELD(relaxation), PBF_FIELD(scorr_k),
        PBF_FIELD(scorr_n),      PBF_FIELD(scorr_dq),       PBF_FIELD(xsph_c),     PBF_FIELD(vorticity_epsilon),
        PBF_FIELD(ldc_enabled),  PBF_FIELD(ldc_gain),       PBF_FIELD(max_speed),  PBF_FIELD(adaptive_error_target),
        PBF_FIELD(max_substeps), PBF_FIELD(substep_travel), PBF_FIELD(sound_speed)};
#undef PBF_FIELD
    return fields;
}

// The switchable parts of a world, named as in the repro's --drop list: b<k>, n<k>, d<k>, c<k>,
// m<k>, g (the gravity change), s (the solver change), p.<field> (a solver setting back at its
// default).
std::vector<std::string> parts(const WorldSpec& w) {
    std::vector<std::string> p;
    for (size_t k = 0; k < w.colliders.size(); ++k) p.push_back("c" + std::to_string(k));
    for (size_t k = 0; k < w.nozzles.size(); ++k) p.push_back("n" + std::to_string(k));
    for (size_t k = 0; k < w.drains.size(); ++k) p.push_back("d" + std::to_string(k));
    for (size_t k = w.blocks.size(); k-- > 1;) p.push_back("b" + std::to_string(k));
    for (size_t k = 0; k < w.materials.size(); ++k) p.push_back("m" + std::to_string(k));
    if (w.gravity_frame >= 0) p.push_back("g");
    if (w.solver_frame >= 0) p.push_back("s");
    // Solver settings back at their defaults, one at a time: what is left names the culprit.
    const pbf_solver_params def = pbf_solver_params_default();
    for (const auto& f : solver_fields())
        if (std::memcmp(reinterpret_cast<const char*>(&w.desc.solver) + f.second,
                        reinterpret_cast<const char*>(&def) + f.second, 4) != 0)
            p.push_back("p." + f.first);
    return p;
}

// Switches one part off (a solver field: back to its default); false if the name is not a part
// of w.
bool drop(WorldSpec& w, const std::string& name) {
    if (name.rfind("p.", 0) == 0) {
        const pbf_solver_params def = pbf_solver_params_default();
        for (const auto& f : solver_fields())
            if (name == "p." + f.first) {
                std::memcpy(reinterpret_cast<char*>(&w.desc.solver) + f.second,
                            reinterpret_cast<const char*>(&def) + f.second, 4);
                return true;
            }
        return false;
    }
    if (name == "g") return w.gravity_frame >= 0 ? (w.gravity_frame = -1, true) : false;
    if (name == "s") return w.solver_frame >= 0 ? (w.solver_frame = -1, true) : false;
    if (name.size() < 2) return false;
    size_t k = 0;
    try {
        k = std::stoul(name.substr(1));
    } catch (...) {
        return false;
    }
    auto off = [k](auto& v) { return k < v.size() ? (v[k].on = false, true) : false; };
    switch (name[0]) {
        case 'b':
            return k > 0 && off(w.blocks);
        case 'n':
            return off(w.nozzles);
        case 'd':
            return off(w.drains);
        case 'c':
            return off(w.colliders);
        case 'm':
            return off(w.materials);
        default:
            return false;
    }
}

struct Case {
    uint64_t seed = 1, world = 0;
    int frames = 0;  // 0: all
    std::vector<std::string> drops;
    bool expect_fail = false;
    std::string note;
};

std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
    return s;
}

std::vector<std::string> split(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream in(s);
    std::string x;
    while (std::getline(in, x, ','))
        if (!x.empty()) out.push_back(x);
    return out;
}

WorldSpec build(const Case& c, pbf_backend backend, std::string& error) {
    WorldSpec w = draw_world(c.seed, c.world, backend);
    for (const auto& d : c.drops)
        if (!drop(w, d)) error = "no part '" + d + "' in this world";
    if (c.frames > 0 && size_t(c.frames) < w.dts.size()) w.dts.resize(size_t(c.frames));
    return w;
}

std::string command_line(const Case& c) {
    std::string s = "fuzz_physics --seed " + std::to_string(c.seed) + " --world " + std::to_string(c.world);
    if (c.frames) s += " --frames " + std::to_string(c.frames);
    if (!c.drops.empty()) s += " --drop " + join(c.drops);
    return s;
}

std::string corpus_line(const Case& c, const RunResult& r) {
    std::string s = "seed=" + std::to_string(c.seed) + " world=" + std::to_string(c.world);
    if (c.frames) s += " frames=" + std::to_string(c.frames);
    if (!c.drops.empty()) s += " drop=" + join(c.drops);
    return s + "  # " + r.invariant;
}

// Cuts the frames after the failing one, then switches parts off one at a time, keeping each
// removal under which the world still fails the same invariant.
Case shrink(Case c, const RunResult& first, pbf_backend backend, RunResult& last) {
    std::string error;
    c.frames = first.frame + 1;
    last = first;
    for (const std::string& p : parts(build(c, backend, error))) {
        if (std::find(c.drops.begin(), c.drops.end(), p) != c.drops.end()) continue;  // a repro's, off already
        Case trial = c;
        trial.drops.push_back(p);
        WorldSpec w = build(trial, backend, error);
        const RunResult r = run_world(w);
        if (r.failed && r.invariant == first.invariant) {
            c = trial;
            c.frames = r.frame + 1;
            last = r;
        }
    }
    return c;
}

Case parse_corpus_line(const std::string& line) {
    Case c;
    std::string text = line;
    const size_t hash = text.find('#');
    if (hash != std::string::npos) {
        c.note = text.substr(hash + 1);
        text = text.substr(0, hash);
    }
    std::stringstream in(text);
    std::string tok;
    while (in >> tok) {
        const size_t eq = tok.find('=');
        const std::string key = tok.substr(0, eq), value = eq == std::string::npos ? "" : tok.substr(eq + 1);
        if (key == "seed")
            c.seed = std::stoull(value);
        else if (key == "world")
            c.world = std::stoull(value);
        else if (key == "frames")
            c.frames = std::stoi(value);
        else if (key == "drop")
            c.drops = split(value);
        else if (key == "expect" && value == "fail")
            c.expect_fail = true;
        else
            throw std::runtime_error("unknown corpus field '" + tok + "'");
    }
    return c;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"fuzz_physics: random valid worlds through the public C API, physics invariants checked every step"};
    uint64_t seed = 1, worlds = 1000, first_world = 0;
    std::vector<uint64_t> only;
    double seconds = 0;
    std::string backend_name = "cpu", drops, corpus;
    int frames = 0, jobs = 1;
    bool no_shrink = false, verbose = false;
    app.add_option("--seed", seed, "the run's seed (default 1)");
    app.add_option("--worlds", worlds, "how many worlds (default 1000)");
    app.add_option("--first", first_world, "index of the first world (default 0)");
    app.add_option("--world", only, "replay only these world indices");
    app.add_option("--seconds", seconds, "stop starting worlds after this many seconds (0: no limit)");
    app.add_option("--backend", backend_name, "cpu or cuda")->check(CLI::IsMember({"cpu", "cuda"}));
    app.add_option("--frames", frames, "cut every world after this many frames (a repro)");
    app.add_option("--drop", drops, "parts switched off, e.g. c1,n0,b2,m0,d0,g,s (a repro)");
    app.add_option("--corpus", corpus, "run the regression corpus in this file instead of random worlds");
    app.add_option("--jobs", jobs, "worlds run at once, one thread each (default 1)")->check(CLI::Range(1, 64));
    app.add_flag("--no-shrink", no_shrink, "report failures without shrinking them");
    size_t known_failures = 0;
    app.add_option("--known-failures", known_failures,
                   "exit 0 while at most this many worlds fail (the count still open; CI's ratchet)");
    app.add_flag("--verbose", verbose, "print each world's description and result");
    CLI11_PARSE(app, argc, argv);
    const pbf_backend backend = backend_name == "cuda" ? PBF_BACKEND_CUDA : PBF_BACKEND_CPU;

    std::vector<Case> cases;
    if (!corpus.empty()) {
        std::ifstream in(corpus);
        if (!in) {
            std::fprintf(stderr, "fuzz_physics: cannot read %s\n", corpus.c_str());
            return 2;
        }
        std::string line;
        while (std::getline(in, line)) {
            const size_t start = line.find_first_not_of(" \t");
            if (start == std::string::npos || line[start] == '#') continue;
            try {
                cases.push_back(parse_corpus_line(line));
            } catch (const std::exception& e) {
                std::fprintf(stderr, "fuzz_physics: %s: %s\n", corpus.c_str(), e.what());
                return 2;
            }
        }
    } else if (!only.empty()) {
        for (uint64_t k : only) cases.push_back(Case{seed, k, frames, split(drops), false, ""});
    } else {
        for (uint64_t k = 0; k < worlds; ++k)
            cases.push_back(Case{seed, first_world + k, frames, split(drops), false, ""});
    }

    const auto start = std::chrono::steady_clock::now();
    auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
    std::vector<RunResult> results(cases.size());
    std::vector<char> ran(cases.size(), 0);
    std::atomic<size_t> next{0};
    std::mutex print;
    size_t failures = 0, expected_failures = 0, energy_checked = 0, momentum_checked = 0, worlds_run = 0;
    double particle_frames = 0;
    auto worker = [&] {
        for (;;) {
            const size_t k = next++;
            if (k >= cases.size() || (seconds > 0 && elapsed() > seconds)) return;
            std::string error;
            const WorldSpec w = build(cases[k], backend, error);
            RunResult r;
            if (!error.empty()) {
                r.failed = true;
                r.invariant = "repro";
                r.detail = error;
            } else {
                r = run_world(w);
            }
            const Case& c = cases[k];
            std::string report;
            const bool unexpected = r.failed != c.expect_fail;
            if (r.failed && !c.expect_fail) {
                std::ostringstream o;
                o << "FAIL seed=" << c.seed << " world=" << c.world << " frame=" << r.frame << " " << r.invariant
                  << ": " << r.detail << "\n  replay: " << command_line(c) << "\n";
                if (!no_shrink && r.invariant != "repro" && r.frame >= 0) {
                    RunResult last;
                    const Case small = shrink(c, r, backend, last);
                    std::string e;
                    o << "  minimal repro: " << command_line(small) << "\n    (" << last.invariant << " at frame "
                      << last.frame << ": " << last.detail << ")\n  corpus line: " << corpus_line(small, last) << "\n"
                      << describe(build(small, backend, e));
                }
                report = o.str();
            } else if (r.failed) {
                report = "expected failure (open): " + command_line(c) + ": " + r.invariant + ": " + r.detail + "\n";
            } else if (c.expect_fail) {
                report = "NOW PASSES (remove expect=fail from the corpus): " + command_line(c) + "\n";
            }
            std::lock_guard<std::mutex> lock(print);
            results[k] = r;
            ran[k] = 1;
            ++worlds_run;
            failures += unexpected ? 1 : 0;
            expected_failures += (r.failed && c.expect_fail) ? 1 : 0;
            energy_checked += r.energy_checked ? 1 : 0;
            momentum_checked += r.momentum_checked ? 1 : 0;
            particle_frames += double(r.peak_particles) * r.frames_run;
            if (verbose) {
                std::string e;
                std::printf("world %llu: %s, %d frames, peak %u particles, %.2f s%s\n%s", (unsigned long long)c.world,
                            r.failed ? "FAIL" : "ok", r.frames_run, r.peak_particles, r.seconds,
                            r.energy_checked ? ", energy checked" : "", describe(build(c, backend, e)).c_str());
            }
            if (!report.empty()) std::fputs(report.c_str(), stdout);
            std::fflush(stdout);
        }
    };
    std::vector<std::thread> threads;
    for (int j = 0; j < jobs; ++j) threads.emplace_back(worker);
    for (auto& t : threads) t.join();

    std::printf("fuzz_physics: %zu worlds, %zu failures", worlds_run, failures);
    if (expected_failures) std::printf(" (%zu expected failures)", expected_failures);
    std::printf(" [seed %llu, %s backend, %.1f s; energy checked in %zu, momentum in %zu; %.2g particle-frames]\n",
                (unsigned long long)seed, backend_name.c_str(), elapsed(), energy_checked, momentum_checked,
                particle_frames);
    if (known_failures > 0) {
        if (failures > known_failures) {
            std::printf("fuzz_physics: FAILED: %zu failures, more than the %zu known\n", failures, known_failures);
            return 1;
        }
        if (failures < known_failures)
            std::printf("fuzz_physics: %zu failures, fewer than the %zu known: lower --known-failures to %zu\n",
                        failures, known_failures, failures);
        return 0;
    }
    return failures ? 1 : 0;
}
