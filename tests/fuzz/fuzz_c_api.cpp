// libFuzzer target for the public C ABI (include/pbf_c_api.h), CPU backend.
//
// The input bytes are decoded into a sequence of C API calls with arbitrary arguments: worlds
// created and destroyed (wrong struct sizes, wrong header versions, NaN/Inf/huge/negative
// fields), steps with arbitrary dt, solver parameters with arbitrary floats, blocks, nozzles,
// drains, colliders, poses, copy-outs with arbitrary max_count, map/unmap, stale, zeroed and
// forged handles, NULL pointers. A model of what the library holds (live worlds, emitters,
// colliders, mapping) lets each call's result be checked, and invariants are asserted after
// the calls (see check_world). A violated invariant aborts with a message, which libFuzzer
// reports as a crash together with the input.
//
// Resource clamps (so one input cannot take seconds or gigabytes): a world gets at most
// kMaxCapacity particles and kMaxCells grid cells; sizes beyond the library's own limits
// (which it must refuse without allocating) are passed through unchanged. Steps are charged
// against a per-input work budget; when it runs out, further steps are skipped.
#include <pbf_c_api.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

// c_shim.c: calls pbf_result_string with any int, as C code may.
extern "C" const char* pbf_fuzz_result_string(int32_t value);

namespace {

constexpr uint32_t kMaxCapacity = 65536;  // largest world the fuzzer lets the library allocate
constexpr double kMaxCells = 65536.0;     // largest grid
constexpr size_t kMaxWorlds = 6;          // live worlds at once (more creates are skipped)
constexpr double kWorkBudget = 5.0e7;     // neighbour candidates visited by steps, per input
constexpr uint32_t kDeadId = 0xFFFFFFFFu;

[[noreturn]] void fuzz_fail(const char* what, const char* file, int line) {
    std::fprintf(stderr, "\n*** fuzz invariant violated: %s\n    at %s:%d\n    last error: \"%s\"\n", what, file, line,
                 pbf_last_error_message());
    std::abort();
}
#define FUZZ_ASSERT(cond)                                  \
    do {                                                   \
        if (!(cond)) fuzz_fail(#cond, __FILE__, __LINE__); \
    } while (0)

// ---- input decoding --------------------------------------------------------------------------
const float kNaN = std::numeric_limits<float>::quiet_NaN();
const float kInf = std::numeric_limits<float>::infinity();
const float kSpecialFloats[] = {0.0f,
                                -0.0f,
                                1.0f,
                                -1.0f,
                                0.5f,
                                1.0f / 60.0f,
                                1e-3f,
                                1e-6f,
                                1e-30f,
                                std::numeric_limits<float>::min(),
                                std::numeric_limits<float>::denorm_min(),
                                -std::numeric_limits<float>::denorm_min(),
                                1e30f,
                                -1e30f,
                                std::numeric_limits<float>::max(),
                                -std::numeric_limits<float>::max(),
                                kInf,
                                -kInf,
                                kNaN,
                                -kNaN,
                                std::numeric_limits<float>::signaling_NaN(),
                                100.0f,
                                1000.0f,
                                16777216.0f,
                                3e9f,
                                -3e9f,
                                1e10f,
                                2.0f,
                                1.0000001f,
                                0.99999994f,
                                64.0f,
                                65.0f};
const uint32_t kSpecialU32[] = {0u,          1u,
                                2u,          3u,
                                4u,          16u,
                                17u,         31u,
                                32u,         33u,
                                64u,         65u,
                                255u,        1000u,
                                4096u,       65535u,
                                65536u,      65537u,
                                1u << 20,    (1u << 30) - 1,
                                1u << 30,    (1u << 30) + 1,
                                0x7FFFFFFFu, 0x80000000u,
                                0xFFFFFFFEu, 0xFFFFFFFFu};

struct Reader {
    const uint8_t* p;
    size_t n;
    bool empty() const { return n == 0; }
    uint8_t u8() {
        if (n == 0) return 0;
        --n;
        return *p++;
    }
    uint16_t u16() { return uint16_t(u8() | (uint16_t(u8()) << 8)); }
    uint32_t raw32() {
        uint32_t v = 0;
        for (int i = 0; i < 4; ++i) v |= uint32_t(u8()) << (8 * i);
        return v;
    }
    float raw_float() {
        const uint32_t b = raw32();
        float f;
        std::memcpy(&f, &b, sizeof f);
        return f;
    }
    // Mostly a value in [lo, hi]; otherwise a special value (NaN, Inf, huge, tiny, ...) or raw bits.
    float f(float lo, float hi) {
        const uint8_t mode = u8();
        if (mode < 176) return lo + (hi - lo) * (float(u16()) / 65535.0f);
        if (mode < 236) return kSpecialFloats[u8() % (sizeof kSpecialFloats / sizeof kSpecialFloats[0])];
        return raw_float();
    }
    // Mostly a value in [lo, hi]; otherwise a special or raw value.
    uint32_t u32(uint32_t lo, uint32_t hi) {
        const uint8_t mode = u8();
        if (mode < 192) return lo + uint32_t(u16()) % (hi - lo + 1);
        if (mode < 240) return kSpecialU32[u8() % (sizeof kSpecialU32 / sizeof kSpecialU32[0])];
        return raw32();
    }
    void vec3(float* v, float lo, float hi) {
        for (int k = 0; k < 3; ++k) v[k] = f(lo, hi);
    }
    // A struct_size: mostly right, sometimes off by a little or arbitrary.
    uint32_t struct_size(uint32_t right) {
        const uint8_t mode = u8();
        if (mode < 224) return right;
        if (mode < 240) return right + uint32_t(int32_t(u8() % 9) - 4);
        if (mode < 248) return 0;
        return raw32();
    }
};

// Stores any 32 bits in an enum field, as a C caller can (a C++ conversion or copy of a value
// outside the enum's range would be undefined behaviour in the fuzzer itself).
template <class E>
void set_bits(E* field, uint32_t v) {
    static_assert(sizeof(E) == sizeof(uint32_t), "ABI enums are 32 bits");
    std::memcpy(field, &v, sizeof v);
}

template <class E>
int32_t bits_of(const E& e) {
    int32_t v;
    std::memcpy(&v, &e, sizeof v);
    return v;
}

bool finite3(const float* v) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }

// Exact-size heap copies, so AddressSanitizer sees any read or write past a struct.
template <class T>
std::unique_ptr<T> heap(const T& v) {
    return std::unique_ptr<T>(new T(v));
}

// ---- results ---------------------------------------------------------------------------------
// PBF_FUZZ_TRACE=1 in the environment prints every call's result (to replay a crash by hand).
bool g_trace = false;

// Every result is a known code; a failure has a message naming that code.
pbf_result checked(pbf_result r) {
    if (g_trace) std::fprintf(stderr, "    -> %s %s\n", pbf_result_string(r), r ? pbf_last_error_message() : "");
    FUZZ_ASSERT(uint32_t(r) <= uint32_t(PBF_ERROR_INTERNAL));
    FUZZ_ASSERT(r != PBF_ERROR_INTERNAL);  // "a bug in libpbf"
    const char* msg = pbf_last_error_message();
    FUZZ_ASSERT(msg != nullptr);
    if (r != PBF_OK) {
        const char* name = pbf_result_string(r);
        FUZZ_ASSERT(std::strncmp(msg, name, std::strlen(name)) == 0);
    }
    return r;
}

// ---- model -----------------------------------------------------------------------------------
struct EmitterModel {
    pbf_emitter_id id;
    pbf_emitter_type type;
    bool enabled;
};
struct ColliderModel {
    pbf_collider_id id;
    pbf_collider_motion motion;
};
enum Mapped { kNotMapped, kMapped, kMaybeMapped };

struct WorldModel {
    pbf_world_id id{};
    uint32_t capacity = 0;
    uint32_t grid_cells = 0;
    float radius = 0.0f;
    float domain_min[3] = {}, domain_max[3] = {};
    pbf_solver_params params{};
    std::vector<EmitterModel> emitters;
    std::vector<pbf_emitter_id> dead_emitters;
    std::vector<ColliderModel> colliders;
    std::vector<pbf_collider_id> dead_colliders;
    Mapped mapped = kNotMapped;
    pbf_mapped_buffer map{};
    uint64_t steps = 0;
    // Steps shorter than 1e-4 s wait for the next (pbf_world_step): the time waiting, summed in
    // float as the library sums it, and whether the last step simulated anything.
    float carried = 0.0f;
    bool simulated = false;
    bool settled = false;  // no particle emitted since the last step: all are inside the walls
    bool any_enabled_source() const {
        for (const EmitterModel& e : emitters)
            if (e.enabled) return true;
        return false;
    }
};

struct State {
    std::vector<WorldModel> worlds;
    std::vector<pbf_world_id> dead_worlds;
    double budget = kWorkBudget;
};

bool same(pbf_world_id a, pbf_world_id b) { return a.index == b.index && a.generation == b.generation; }
bool same(pbf_emitter_id a, pbf_emitter_id b) { return a.index == b.index && a.generation == b.generation; }
bool same(pbf_collider_id a, pbf_collider_id b) { return a.index == b.index && a.generation == b.generation; }

WorldModel* find_world(State& s, pbf_world_id id) {
    for (WorldModel& w : s.worlds)
        if (same(w.id, id)) return &w;
    return nullptr;
}

// A world handle: live, stale, zeroed or forged. *model is the live world it names, or null.
pbf_world_id pick_world(Reader& in, State& s, WorldModel** model) {
    const uint8_t b = in.u8();
    pbf_world_id id{0, 0};
    const uint8_t kind = b % 16;
    if (kind < 11 && !s.worlds.empty()) {
        id = s.worlds[(b / 16) % s.worlds.size()].id;
    } else if (kind < 13 && !s.dead_worlds.empty()) {
        id = s.dead_worlds[(b / 16) % s.dead_worlds.size()];
    } else if (kind == 13 && !s.worlds.empty()) {  // right slot, wrong generation
        id = s.worlds[(b / 16) % s.worlds.size()].id;
        id.generation += 1 + in.u8();
    } else if (kind == 14) {
        id = pbf_world_id{in.u8() % 8u, in.u8() % 4u};
    } else if (kind == 15) {
        id = pbf_world_id{in.raw32(), in.raw32()};
    }
    *model = find_world(s, id);
    return id;
}

template <class Id, class Live>
Id pick_handle(Reader& in, const std::vector<Live>& live, const std::vector<Id>& dead, const State& s) {
    const uint8_t b = in.u8();
    const uint8_t kind = b % 16;
    if (kind < 10 && !live.empty()) return live[(b / 16) % live.size()].id;
    if (kind < 12 && !dead.empty()) return dead[(b / 16) % dead.size()];
    if (kind == 12) {  // a handle of another world (may or may not be live in this one)
        for (const WorldModel& w : s.worlds) {
            if constexpr (std::is_same<Id, pbf_emitter_id>::value) {
                if (!w.emitters.empty()) return w.emitters[(b / 16) % w.emitters.size()].id;
            } else {
                if (!w.colliders.empty()) return w.colliders[(b / 16) % w.colliders.size()].id;
            }
        }
    }
    if (kind == 13) return Id{in.u8() % 40u, in.u8() % 4u};
    if (kind == 14) return Id{0, 0};
    return Id{in.raw32(), in.raw32()};
}

template <class Live, class Id>
int find_live(const std::vector<Live>& live, Id id) {
    for (size_t k = 0; k < live.size(); ++k)
        if (same(live[k].id, id)) return int(k);
    return -1;
}

// A picked world (w: its model, null where none) and a handle picked among the live and dead
// handles of one of its tables (emitters or colliders; with no model, a forged or another
// world's handle), with the handle's index among the table's live ones (-1: not live there).
template <class Id>
struct Picked {
    WorldModel* w;
    pbf_world_id world;
    Id handle;
    int live;
};

template <class Live, class Id>
Picked<Id> pick_object(Reader& in, State& s, std::vector<Live> WorldModel::*live, std::vector<Id> WorldModel::*dead) {
    static const std::vector<Live> kNone;
    static const std::vector<Id> kNoIds;
    WorldModel* w = nullptr;
    const pbf_world_id world = pick_world(in, s, &w);
    const Id handle = pick_handle(in, w ? w->*live : kNone, w ? w->*dead : kNoIds, s);
    return Picked<Id>{w, world, handle, w ? find_live(w->*live, handle) : -1};
}

// destroy(world, handle) on a picked world and handle: it succeeds exactly for a live handle,
// which then joins the table's dead handles; any other is an invalid handle.
template <class Live, class Id, class Destroy>
void destroy_picked(Reader& in, State& s, std::vector<Live> WorldModel::*live, std::vector<Id> WorldModel::*dead,
                    Destroy destroy) {
    const auto [w, id, h, k] = pick_object(in, s, live, dead);
    const pbf_result r = checked(destroy(id, h));
    FUZZ_ASSERT((r == PBF_OK) == (k >= 0));
    if (r != PBF_OK) {
        FUZZ_ASSERT(r == PBF_ERROR_INVALID_HANDLE);
        return;
    }
    (w->*dead).push_back(h);
    (w->*live).erase((w->*live).begin() + k);
}

// A create call made with fuzzed pointers: its result, the id it wrote, which pointer was NULL.
template <class Id>
struct Created {
    pbf_result r;
    Id out;
    bool null_desc, null_out;
};

// create(world, desc, out) with desc (an exact-size heap copy of d) and out each NULL or not as
// the input picks: a refused call writes a null id.
template <class Id, class Desc, class Create>
Created<Id> create_fuzzed(Reader& in, pbf_world_id world, const Desc& d, Create create) {
    const uint8_t ptrs = in.u8();
    Created<Id> c{PBF_OK, Id{0x11111111u, 0x22222222u}, ptrs < 8, (ptrs & 0xF0) == 0xF0};
    const auto hd = heap(d);
    c.r = checked(create(world, c.null_desc ? nullptr : hd.get(), c.null_out ? nullptr : &c.out));
    if (c.r != PBF_OK && !c.null_out) FUZZ_ASSERT(c.out.index == 0 && c.out.generation == 0);
    return c;
}

// ---- snapshots and invariants ----------------------------------------------------------------
struct Snapshot {
    uint32_t count = 0;
    std::vector<float> pos, vel;
    std::vector<uint32_t> ids;
    pbf_solver_params params{};
};

uint32_t count_of(const WorldModel& w) {
    uint32_t n = 0xA5A5A5A5u;
    FUZZ_ASSERT(checked(pbf_world_get_particle_count(w.id, &n)) == PBF_OK);
    FUZZ_ASSERT(n <= w.capacity);
    return n;
}

Snapshot snapshot(const WorldModel& w) {
    Snapshot s;
    s.count = count_of(w);
    s.pos.assign(size_t(s.count) * 4, 0.0f);
    s.vel.assign(size_t(s.count) * 4, 0.0f);
    s.ids.assign(s.count, 0u);
    uint32_t written = 0xFFFFFFFFu;
    FUZZ_ASSERT(checked(pbf_world_copy_positions(w.id, s.pos.data(), s.count, &written)) == PBF_OK);
    FUZZ_ASSERT(written == s.count);
    FUZZ_ASSERT(checked(pbf_world_copy_velocities(w.id, s.vel.data(), s.count, &written)) == PBF_OK);
    FUZZ_ASSERT(written == s.count);
    FUZZ_ASSERT(checked(pbf_world_copy_ids(w.id, s.ids.data(), s.count, &written)) == PBF_OK);
    FUZZ_ASSERT(written == s.count);
    s.params = pbf_solver_params_default();
    FUZZ_ASSERT(checked(pbf_world_get_solver_params(w.id, &s.params)) == PBF_OK);
    return s;
}

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

bool same_snapshot(const Snapshot& a, const Snapshot& b) {
    return a.count == b.count && a.ids == b.ids && same_bits(a.pos, b.pos) && same_bits(a.vel, b.vel) &&
           std::memcmp(&a.params, &b.params, sizeof a.params) == 0;
}

pbf_step_stats stats_of(const WorldModel& w) {
    pbf_step_stats st;
    std::memset(&st, 0xCD, sizeof st);
    st.struct_size = sizeof st;
    FUZZ_ASSERT(checked(pbf_world_get_stats(w.id, &st)) == PBF_OK);
    return st;
}

// Counts, accounting, ids, finiteness and walls of a live world.
void check_world(const WorldModel& w, bool deep) {
    const uint32_t n = count_of(w);
    const pbf_step_stats st = stats_of(w);
    FUZZ_ASSERT(st.struct_size == sizeof st);
    FUZZ_ASSERT(st.particle_count == n);
    FUZZ_ASSERT(st.step_index == w.steps);
    FUZZ_ASSERT(st.emitted_total >= st.drained_total);
    FUZZ_ASSERT(st.emitted_total - st.drained_total == n);  // exact accounting
    FUZZ_ASSERT(!std::isnan(st.density_error_mean) && !std::isnan(st.density_error_max));
    FUZZ_ASSERT(std::isfinite(st.simulated_dt) && st.simulated_dt >= 0.0f && (st.simulated_dt > 0.0f) == w.simulated);
    if (!deep) return;
    const Snapshot s = snapshot(w);
    FUZZ_ASSERT(s.count == n);
    std::vector<uint32_t> ids = s.ids;
    std::sort(ids.begin(), ids.end());
    FUZZ_ASSERT(std::adjacent_find(ids.begin(), ids.end()) == ids.end());  // unique
    for (uint32_t id : ids) {
        FUZZ_ASSERT(id != kDeadId);
        FUZZ_ASSERT(id < st.emitted_total);  // ids are 0, 1, 2, ... per world
    }
    for (uint32_t i = 0; i < n; ++i) {
        const float* p = &s.pos[size_t(i) * 4];
        const float* v = &s.vel[size_t(i) * 4];
        FUZZ_ASSERT(finite3(p));
        FUZZ_ASSERT(finite3(v));
        FUZZ_ASSERT(v[3] == 0.0f);
        if (w.settled) {  // after a step every particle is inside the walls
            for (int a = 0; a < 3; ++a) {
                const float lo = w.domain_min[a], hi = w.domain_max[a];
                const float slack = 1e-5f * (std::fabs(lo) + std::fabs(hi) + 1.0f);
                FUZZ_ASSERT(p[a] >= lo - slack && p[a] <= hi + slack);
            }
        }
    }
}

// ---- descs -----------------------------------------------------------------------------------
void fuzz_params(Reader& in, pbf_solver_params* p) {
    const uint16_t mask = in.u16();
    if (mask & 0x001) p->iterations = in.u32(1, 8);
    if (mask & 0x002) p->substeps = in.u32(0, 3);  // 0: automatic
    if (mask & 0x004) p->relaxation = in.f(0.01f, 10.0f);
    if (mask & 0x008) p->scorr_k = in.f(0.0f, 1.0f);
    if (mask & 0x010) p->scorr_n = in.f(1.0f, 8.0f);
    if (mask & 0x020) p->scorr_dq = in.f(0.0f, 1.0f);
    if (mask & 0x040) p->xsph_c = in.f(0.0f, 1.0f);
    if (mask & 0x080) p->vorticity_epsilon = in.f(0.0f, 1.2f);  // > 1 m/s is refused
    if (mask & 0x100) p->ldc_enabled = in.u32(0, 1);
    if (mask & 0x200) p->ldc_gain = in.f(0.0f, 1.0f);
    if (mask & 0x400) p->max_speed = in.f(0.1f, 200.0f);
    if (mask & 0x800) p->struct_size = in.struct_size(sizeof *p);
    if (mask & 0x1000) p->adaptive_error_target = in.f(0.0f, 0.05f);
    if (mask & 0x2000) p->max_substeps = in.u32(0, 8);  // 0 is refused
    if (mask & 0x4000) p->substep_travel = in.f(0.0f, 1.2f);
    if (mask & 0x8000) p->sound_speed = in.f(-1.0f, 100.0f);  // < 10 m/s is refused
}

// What check_solver_params accepts (a refused struct is checked to change nothing).
bool params_valid(const pbf_solver_params& p) {
    return p.struct_size == sizeof p && p.iterations >= 1 && p.iterations <= 64 && p.substeps <= 64 &&
           p.max_substeps >= 1 && p.max_substeps <= 64 && std::isfinite(p.substep_travel) &&
           p.substep_travel >= 0.05f && p.substep_travel <= 1.0f && std::isfinite(p.sound_speed) &&
           p.sound_speed >= 10 && std::isfinite(p.relaxation) && p.relaxation > 0 && std::isfinite(p.scorr_k) &&
           p.scorr_k >= 0 && p.scorr_k <= 1 && std::isfinite(p.scorr_n) && p.scorr_n >= 1 && p.scorr_n <= 8 &&
           std::isfinite(p.scorr_dq) && p.scorr_dq > 0 && p.scorr_dq < 1 && std::isfinite(p.xsph_c) && p.xsph_c >= 0 &&
           p.xsph_c <= 1 && std::isfinite(p.vorticity_epsilon) && p.vorticity_epsilon >= 0 &&
           p.vorticity_epsilon <= 1 && p.ldc_enabled <= 1 && std::isfinite(p.ldc_gain) && p.ldc_gain >= 0 &&
           p.ldc_gain <= 1 && std::isfinite(p.max_speed) && p.max_speed > 0 && std::isfinite(p.adaptive_error_target) &&
           p.adaptive_error_target >= 0 && p.adaptive_error_target < 1;
}

// The grid the library would build for desc (or a negative number if it would refuse the desc
// before computing one).
double grid_cells_of(const pbf_world_desc& d) {
    if (!(std::isfinite(d.particle_radius) && d.particle_radius > 0.0f)) return -1.0;
    if (!finite3(d.domain_min) || !finite3(d.domain_max)) return -1.0;
    const float h = 4.0f * d.particle_radius;
    double total = 1.0;
    for (int a = 0; a < 3; ++a) {
        const float c = std::ceil((d.domain_max[a] - d.domain_min[a]) / h);
        total *= std::max(1.0, double(c));
    }
    return total;
}

// ---- the operations --------------------------------------------------------------------------
int g_log_calls = 0;
void PBF_CALL log_sink(pbf_log_level level, const char* message, void* user) {
    FUZZ_ASSERT(message != nullptr);
    FUZZ_ASSERT(uint32_t(level) <= uint32_t(PBF_LOG_ERROR));
    FUZZ_ASSERT(user == &g_log_calls);
    ++*static_cast<int*>(user);
}

void op_create_world(Reader& in, State& s) {
    pbf_world_desc d = pbf_world_desc_default();
    d.backend = PBF_BACKEND_CPU;
    d.max_particles = 256;
    const float lo[3] = {-0.3f, 0.0f, -0.3f}, hi[3] = {0.3f, 0.6f, 0.3f};
    std::memcpy(d.domain_min, lo, sizeof lo);
    std::memcpy(d.domain_max, hi, sizeof hi);
    const uint16_t mask = in.u16();
    if (mask & 0x0001) {
        const uint8_t b = in.u8() % 16;
        set_bits(&d.backend, b < 10   ? PBF_BACKEND_CPU
                             : b < 13 ? PBF_BACKEND_AUTO
                             : b < 15 ? PBF_BACKEND_CUDA
                                      : in.raw32());
    }
    if (mask & 0x0002) d.max_particles = in.u32(1, 2048);
    if (mask & 0x0004) d.particle_radius = in.f(0.01f, 0.1f);
    if (mask & 0x0008) d.rest_density = in.f(100.0f, 3000.0f);
    if (mask & 0x0010) in.vec3(d.gravity, -30.0f, 30.0f);
    if (mask & 0x0020) in.vec3(d.domain_min, -1.0f, 0.0f);
    if (mask & 0x0040) {
        for (int a = 0; a < 3; ++a) d.domain_max[a] = d.domain_min[a] + in.f(0.0f, 1.5f);
    }
    if (mask & 0x0080) fuzz_params(in, &d.solver);
    if (mask & 0x0100) d.struct_size = in.struct_size(sizeof d);
    if (mask & 0x0200)
        d.header_version = in.u8() < 200 ? PBF_MAKE_VERSION(PBF_VERSION_MAJOR, in.u8(), in.u8()) : in.raw32();
    if (mask & 0x0400) d.cuda_device = int32_t(in.u32(0, 2));
    if (mask & 0x0800) in.vec3(d.domain_max, -2.0f, 2.0f);
    const bool null_out = (mask & 0x1000) && in.u8() < 32;
    const bool null_desc = (mask & 0x2000) && in.u8() < 32;

    // Resource clamps: refusals above the library's limits stay; big but legal sizes shrink.
    if (d.max_particles > kMaxCapacity && d.max_particles <= (1u << 30)) d.max_particles = 1 + d.max_particles % 2048;
    const double cells = grid_cells_of(d);
    if (cells > kMaxCells && cells <= double(1u << 30)) {
        for (int a = 0; a < 3; ++a) d.domain_max[a] = d.domain_min[a] + 16.0f * 4.0f * d.particle_radius;
        if (grid_cells_of(d) > kMaxCells) return;  // rounding at extreme magnitudes: skip
    }
    if (s.worlds.size() >= kMaxWorlds) return;

    if (g_trace)
        std::fprintf(
            stderr,
            "  desc: size %u version %08x backend %d cap %u radius %g rho0 %g g (%g %g %g) domain (%g %g %g)..(%g "
            "%g %g) solver: it %u sub %u relax %g k %g n %g dq %g xsph %g vort %g ldc %u/%g vmax %g\n",
            d.struct_size, d.header_version, bits_of(d.backend), d.max_particles, d.particle_radius, d.rest_density,
            d.gravity[0], d.gravity[1], d.gravity[2], d.domain_min[0], d.domain_min[1], d.domain_min[2],
            d.domain_max[0], d.domain_max[1], d.domain_max[2], d.solver.iterations, d.solver.substeps,
            d.solver.relaxation, d.solver.scorr_k, d.solver.scorr_n, d.solver.scorr_dq, d.solver.xsph_c,
            d.solver.vorticity_epsilon, d.solver.ldc_enabled, d.solver.ldc_gain, d.solver.max_speed);
    const auto desc = heap(d);
    pbf_world_id id{0xAAAAAAAAu, 0xBBBBBBBBu};
    const pbf_result r = checked(pbf_world_create(null_desc ? nullptr : desc.get(), null_out ? nullptr : &id));
    if (r != PBF_OK) {
        if (!null_out) FUZZ_ASSERT(id.index == 0 && id.generation == 0);
        return;
    }
    // Success only for a desc the header calls valid.
    FUZZ_ASSERT(!null_out && !null_desc);
    FUZZ_ASSERT(d.struct_size == sizeof d && PBF_VERSION_GET_MAJOR(d.header_version) == PBF_VERSION_MAJOR);
    FUZZ_ASSERT(d.backend == PBF_BACKEND_CPU || d.backend == PBF_BACKEND_AUTO);
    FUZZ_ASSERT(d.max_particles >= 1 && d.max_particles <= kMaxCapacity);
    FUZZ_ASSERT(std::isfinite(d.particle_radius) && d.particle_radius > 0 && std::isfinite(d.rest_density) &&
                d.rest_density > 0 && finite3(d.gravity) && finite3(d.domain_min) && finite3(d.domain_max));
    FUZZ_ASSERT(params_valid(d.solver));
    FUZZ_ASSERT(id.generation != 0);
    FUZZ_ASSERT(find_world(s, id) == nullptr);

    WorldModel w;
    w.id = id;
    w.capacity = d.max_particles;
    w.radius = d.particle_radius;
    std::memcpy(w.domain_min, d.domain_min, sizeof w.domain_min);
    std::memcpy(w.domain_max, d.domain_max, sizeof w.domain_max);
    w.params = d.solver;

    pbf_world_info info;
    std::memset(&info, 0x5A, sizeof info);
    info.struct_size = sizeof info;
    FUZZ_ASSERT(checked(pbf_world_get_info(id, &info)) == PBF_OK);
    FUZZ_ASSERT(info.backend == PBF_BACKEND_CPU);
    FUZZ_ASSERT(info.max_particles == d.max_particles);
    FUZZ_ASSERT(std::memchr(info.device_name, 0, sizeof info.device_name) != nullptr);
    // A world that was created has usable constants.
    FUZZ_ASSERT(std::isfinite(info.particle_mass) && info.particle_mass > 0.0f);
    FUZZ_ASSERT(std::isfinite(info.kernel_radius) && info.kernel_radius > 0.0f);
    FUZZ_ASSERT(info.grid_cells >= 1 && double(info.grid_cells) <= kMaxCells);
    w.grid_cells = info.grid_cells;
    s.worlds.push_back(w);
    check_world(s.worlds.back(), true);
}

void op_destroy_world(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    const pbf_result r = checked(pbf_world_destroy(id));
    if (!w) {
        FUZZ_ASSERT(r == PBF_ERROR_INVALID_HANDLE);
        return;
    }
    FUZZ_ASSERT(r == PBF_OK);
    s.dead_worlds.push_back(id);
    s.worlds.erase(s.worlds.begin() + (w - s.worlds.data()));
    // The handle is dead now, for every call.
    uint32_t n = 77;
    FUZZ_ASSERT(checked(pbf_world_get_particle_count(id, &n)) == PBF_ERROR_INVALID_HANDLE);
    FUZZ_ASSERT(checked(pbf_world_step(id, 1.0f / 60.0f)) == PBF_ERROR_INVALID_HANDLE);
    FUZZ_ASSERT(checked(pbf_world_destroy(id)) == PBF_ERROR_INVALID_HANDLE);
}

void op_step(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    const float dt = in.f(0.0f, 0.05f);
    if (g_trace) std::fprintf(stderr, "  dt %g\n", dt);
    const bool dt_ok = std::isfinite(dt) && dt > 0.0f && dt <= 1.0f;
    uint32_t before = 0;
    if (w) {
        before = count_of(*w);
        if (dt_ok) {
            // Charge the step's work against the budget, in neighbour candidates visited: each
            // particle scans the 27 cells around it, so a world packed far beyond rest density
            // (more particles than its few cells hold) costs O(n²) a pass. Sources can fill it.
            const double particles = w->any_enabled_source() ? double(w->capacity) : double(before);
            const double candidates =
                std::min(particles, 27.0 * std::ceil(particles / double(std::max(1u, w->grid_cells))) + 27.0);
            // Automatic substeps (0) run up to max_substeps.
            const double cost =
                double(w->params.substeps ? w->params.substeps : w->params.max_substeps) *
                (particles * candidates * (double(w->params.iterations) * 2.0 + 8.0) + 4.0 * w->grid_cells + 64.0);
            if (cost > s.budget) return;
            s.budget -= cost;
        }
    }
    const pbf_result r = checked(pbf_world_step(id, dt));
    if (!dt_ok) {
        FUZZ_ASSERT(r == PBF_ERROR_INVALID_ARGUMENT);
        if (w) FUZZ_ASSERT(count_of(*w) == before);
        return;
    }
    if (!w) {
        FUZZ_ASSERT(r == PBF_ERROR_INVALID_HANDLE);
        return;
    }
    FUZZ_ASSERT(r == PBF_OK);
    ++w->steps;
    w->mapped = kNotMapped;
    const float total = dt + w->carried;
    w->simulated = total >= PBF_MIN_STEP_DT;
    w->carried = w->simulated ? 0.0f : total;
    w->settled = w->settled || w->simulated;
    if (!w->any_enabled_source()) FUZZ_ASSERT(count_of(*w) == before);
    check_world(*w, true);
}

void op_set_params(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    pbf_solver_params p = w ? w->params : pbf_solver_params_default();
    fuzz_params(in, &p);
    const bool null_p = in.u8() < 8;
    const bool valid = params_valid(p) && !null_p;
    const auto hp = heap(p);
    const pbf_result r = checked(pbf_world_set_solver_params(id, null_p ? nullptr : hp.get()));
    FUZZ_ASSERT((r == PBF_OK) == (valid && w != nullptr));
    if (!valid) FUZZ_ASSERT(r == PBF_ERROR_INVALID_ARGUMENT || r == PBF_ERROR_STRUCT_SIZE);
    if (!w) return;
    if (r == PBF_OK) w->params = p;
    pbf_solver_params now = pbf_solver_params_default();
    FUZZ_ASSERT(checked(pbf_world_get_solver_params(id, &now)) == PBF_OK);
    FUZZ_ASSERT(std::memcmp(&now, &w->params, sizeof now) == 0);  // refused: unchanged
}

// get(world, out) with a poisoned out struct T of fuzzed struct_size, or NULL: a refused call
// writes nothing, a wrong struct_size is refused. *written: the struct after the call.
template <class T, class Get>
pbf_result get_out(Reader& in, pbf_world_id id, bool null_out, Get get, std::unique_ptr<T>* written) {
    T v;
    std::memset(&v, 0x3C, sizeof v);
    v.struct_size = in.struct_size(sizeof v);
    *written = heap(v);
    const pbf_result r = checked(get(id, null_out ? nullptr : written->get()));
    if (r != PBF_OK && !null_out) FUZZ_ASSERT(std::memcmp(written->get(), &v, sizeof v) == 0);
    if (!null_out && v.struct_size != sizeof v) FUZZ_ASSERT(r == PBF_ERROR_STRUCT_SIZE);
    return r;
}

void op_get(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    const uint8_t which = in.u8() % 4;
    const bool null_out = in.u8() < 16;
    pbf_result r;
    if (which == 0) {
        std::unique_ptr<pbf_solver_params> p;
        r = get_out(in, id, null_out, pbf_world_get_solver_params, &p);
        FUZZ_ASSERT(r != PBF_OK || w != nullptr);
        if (r == PBF_OK) FUZZ_ASSERT(std::memcmp(p.get(), &w->params, sizeof *p) == 0);
    } else if (which == 1) {
        std::unique_ptr<pbf_world_info> info;
        r = get_out(in, id, null_out, pbf_world_get_info, &info);
        FUZZ_ASSERT(r != PBF_OK || w != nullptr);
        if (r == PBF_OK) FUZZ_ASSERT(info->max_particles == w->capacity && info->grid_cells == w->grid_cells);
    } else if (which == 2) {
        std::unique_ptr<pbf_step_stats> st;
        r = get_out(in, id, null_out, pbf_world_get_stats, &st);
    } else {
        uint32_t n = 0x12345678u;
        r = checked(pbf_world_get_particle_count(id, null_out ? nullptr : &n));
        FUZZ_ASSERT(r != PBF_OK || w != nullptr);
        if (r == PBF_OK)
            FUZZ_ASSERT(n <= w->capacity);
        else
            FUZZ_ASSERT(n == 0x12345678u);
    }
    if (null_out) FUZZ_ASSERT(r == PBF_ERROR_INVALID_ARGUMENT || (r == PBF_ERROR_INVALID_HANDLE && !w));
    if (!w) FUZZ_ASSERT(r != PBF_OK);
}

void op_gravity(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    float g[3];
    in.vec3(g, -30.0f, 30.0f);
    const bool null_g = in.u8() < 8;
    const auto hg = std::unique_ptr<float[]>(new float[3]{g[0], g[1], g[2]});
    const pbf_result r = checked(pbf_world_set_gravity(id, null_g ? nullptr : hg.get()));
    FUZZ_ASSERT((r == PBF_OK) == (w && !null_g && finite3(g)));
}

void op_emit_block(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    pbf_block_desc b = pbf_block_desc_default();
    const uint8_t mode = in.u8();
    if (w && mode < 160) {  // inside the domain, a handful of particles
        for (int a = 0; a < 3; ++a) {
            const float span = w->domain_max[a] - w->domain_min[a];
            b.box_min[a] = w->domain_min[a] + span * in.f(0.0f, 0.9f);
            b.box_max[a] = b.box_min[a] + span * in.f(0.0f, 0.4f);
        }
    } else {
        in.vec3(b.box_min, -2.0f, 2.0f);
        for (int a = 0; a < 3; ++a)
            b.box_max[a] = (mode & (1 << (a + 1))) ? in.f(-2.0f, 2.0f) : b.box_min[a] + in.f(0.0f, 1.0f);
    }
    if (in.u8() < 64) in.vec3(b.velocity, -10.0f, 10.0f);
    b.struct_size = in.struct_size(sizeof b);
    const uint8_t ptrs = in.u8();
    const bool null_desc = ptrs < 8, null_out = (ptrs & 0x10) != 0;
    const uint32_t before = w ? count_of(*w) : 0;
    Snapshot snap;
    const bool take = w && (ptrs & 0x20) && before <= 4096;
    if (take) snap = snapshot(*w);
    const auto hb = heap(b);
    uint32_t emitted = 0xEEEEEEEEu;
    const pbf_result r =
        checked(pbf_world_emit_block(id, null_desc ? nullptr : hb.get(), null_out ? nullptr : &emitted));
    bool valid_desc =
        !null_desc && b.struct_size == sizeof b && finite3(b.box_min) && finite3(b.box_max) && finite3(b.velocity);
    for (int a = 0; a < 3 && valid_desc; ++a) valid_desc = b.box_max[a] > b.box_min[a];
    if (!null_out && r != PBF_OK) FUZZ_ASSERT(emitted == 0);
    if (!w) {
        FUZZ_ASSERT(r != PBF_OK);
        return;
    }
    // An emit that adds particles ends a mapping; a refused one (world full) must leave it in place
    // (tests/test_api_particles.cpp, "a failed emit leaves a mapping in place"). The model accepts
    // either after a refusal, so it asserts nothing the API tests own.
    if (valid_desc && w->mapped != kNotMapped) w->mapped = r == PBF_OK ? kNotMapped : kMaybeMapped;
    const uint32_t after = count_of(*w);
    if (r == PBF_OK) {
        FUZZ_ASSERT(valid_desc);
        if (!null_out) {
            FUZZ_ASSERT(emitted > 0);
            FUZZ_ASSERT(after == before + emitted);
        }
        FUZZ_ASSERT(after > before);
        w->settled = false;
        check_world(*w, true);
    } else {
        FUZZ_ASSERT(after == before);  // a failed call leaves the count unchanged
        if (r == PBF_ERROR_CAPACITY) FUZZ_ASSERT(before == w->capacity);
        if (take) FUZZ_ASSERT(same_snapshot(snap, snapshot(*w)));
        check_world(*w, false);
    }
}

void fill_emitter(Reader& in, const WorldModel* w, pbf_emitter_desc* e) {
    const uint8_t t = in.u8() % 16;
    set_bits(&e->type, t < 7 ? PBF_EMITTER_NOZZLE : t < 14 ? PBF_EMITTER_DRAIN : in.u32(0, 4));
    float lo[3] = {-0.5f, 0.0f, -0.5f}, hi[3] = {0.5f, 1.0f, 0.5f};
    if (w) {
        std::memcpy(lo, w->domain_min, sizeof lo);
        std::memcpy(hi, w->domain_max, sizeof hi);
    }
    const uint16_t mask = in.u16();
    for (int a = 0; a < 3; ++a) {
        e->position[a] = (mask & 0x01) ? in.f(-2.0f, 2.0f) : in.f(lo[a], hi[a]);
        e->box_min[a] = (mask & 0x02) ? in.f(-2.0f, 2.0f) : in.f(lo[a], hi[a]);
        e->box_max[a] = e->box_min[a] + in.f(0.0f, 0.5f);
    }
    if (mask & 0x04) in.vec3(e->direction, -1.0f, 1.0f);
    e->speed = (mask & 0x08) ? in.f(-1.0f, 100.0f) : in.f(0.1f, 3.0f);
    e->radius = (mask & 0x10) ? in.f(-1.0f, 100.0f) : in.f(0.01f, 0.2f);
    e->particles_per_second = (mask & 0x20) ? in.f(-10.0f, 2e9f) : in.f(1.0f, 3000.0f);
    if (mask & 0x40) e->enabled = in.u32(0, 1);
    if (mask & 0x80) e->struct_size = in.struct_size(sizeof *e);
}

bool emitter_valid(const pbf_emitter_desc& e) {
    if (e.struct_size != sizeof e || e.enabled > 1) return false;
    if (!(finite3(e.position) && finite3(e.direction) && std::isfinite(e.speed) && std::isfinite(e.radius) &&
          std::isfinite(e.particles_per_second) && finite3(e.box_min) && finite3(e.box_max)))
        return false;
    if (e.type == PBF_EMITTER_NOZZLE)
        return e.speed > 0 && e.radius > 0 && e.particles_per_second > 0 && e.particles_per_second <= 1e9f &&
               (e.direction[0] != 0 || e.direction[1] != 0 || e.direction[2] != 0);
    if (e.type == PBF_EMITTER_DRAIN)
        return e.box_max[0] > e.box_min[0] && e.box_max[1] > e.box_min[1] && e.box_max[2] > e.box_min[2];
    return false;
}

void op_create_emitter(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    pbf_emitter_desc e = pbf_emitter_desc_default();
    fill_emitter(in, w, &e);
    if (g_trace)
        std::fprintf(
            stderr,
            "  emitter: type %d pos (%g %g %g) dir (%g %g %g) speed %g radius %g pps %g box (%g %g %g)..(%g %g %g)\n",
            bits_of(e.type), e.position[0], e.position[1], e.position[2], e.direction[0], e.direction[1],
            e.direction[2], e.speed, e.radius, e.particles_per_second, e.box_min[0], e.box_min[1], e.box_min[2],
            e.box_max[0], e.box_max[1], e.box_max[2]);
    const auto [r, out, null_desc, null_out] = create_fuzzed<pbf_emitter_id>(in, id, e, pbf_world_create_emitter);
    if (r != PBF_OK) return;
    FUZZ_ASSERT(w && !null_desc && !null_out);
    FUZZ_ASSERT(emitter_valid(e));
    FUZZ_ASSERT(out.generation != 0 && find_live(w->emitters, out) < 0);
    w->emitters.push_back(EmitterModel{out, e.type, e.enabled != 0});
}

void op_destroy_emitter(Reader& in, State& s) {
    destroy_picked(in, s, &WorldModel::emitters, &WorldModel::dead_emitters, pbf_world_destroy_emitter);
}

void op_emitter_update(Reader& in, State& s) {
    const auto [w, id, e, k] = pick_object(in, s, &WorldModel::emitters, &WorldModel::dead_emitters);
    if (in.u8() & 1) {
        const uint32_t enabled = in.u32(0, 1);
        const pbf_result r = checked(pbf_emitter_set_enabled(id, e, enabled));
        FUZZ_ASSERT((r == PBF_OK) == (k >= 0 && enabled <= 1));
        if (r == PBF_OK) w->emitters[k].enabled = enabled != 0;
        return;
    }
    float a[3], b[3];
    in.vec3(a, -1.0f, 1.0f);
    in.vec3(b, -1.0f, 1.0f);
    const uint8_t nulls = in.u8();
    const auto ha = std::unique_ptr<float[]>(new float[3]{a[0], a[1], a[2]});
    const auto hb = std::unique_ptr<float[]>(new float[3]{b[0], b[1], b[2]});
    const bool as_drain = (in.u8() & 1) != 0;  // the call used: set_drain_box or set_nozzle
    float* pa = (nulls & 0xF0) == 0xF0 ? nullptr : ha.get();
    float* pb = (nulls & 0x0F) == 0x0F ? nullptr : hb.get();
    const pbf_result r =
        checked(as_drain ? pbf_emitter_set_drain_box(id, e, pa, pb) : pbf_emitter_set_nozzle(id, e, pa, pb));
    if (r == PBF_OK) {
        FUZZ_ASSERT(k >= 0 && finite3(a) && finite3(b) && pa && pb);
        FUZZ_ASSERT((w->emitters[k].type == PBF_EMITTER_DRAIN) == as_drain);
        if (as_drain) FUZZ_ASSERT(b[0] > a[0] && b[1] > a[1] && b[2] > a[2]);
    }
}

void op_create_collider(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    pbf_collider_desc c = pbf_collider_desc_default();
    const uint8_t sh = in.u8() % 16;
    set_bits(&c.shape, sh < 14 ? 1u + sh % 4u : in.u32(0, 6));
    const uint8_t mo = in.u8() % 8;
    set_bits(&c.motion, mo < 4 ? PBF_MOTION_STATIC : mo < 7 ? PBF_MOTION_KINEMATIC : in.u32(0, 3));
    const uint16_t mask = in.u16();
    in.vec3(c.position, -1.0f, 1.0f);
    if (mask & 0x01)
        for (int k = 0; k < 4; ++k) c.rotation[k] = in.f(-1.0f, 1.0f);
    c.radius = (mask & 0x02) ? in.f(-1.0f, 10.0f) : in.f(0.01f, 0.3f);
    c.half_height = (mask & 0x04) ? in.f(-1.0f, 10.0f) : in.f(0.0f, 0.3f);
    for (int k = 0; k < 3; ++k) c.half_extents[k] = (mask & 0x08) ? in.f(-1.0f, 10.0f) : in.f(0.01f, 0.3f);
    if (mask & 0x10) c.friction = in.f(0.0f, 1.0f);
    if (mask & 0x20) c.struct_size = in.struct_size(sizeof c);
    const auto [r, out, null_desc, null_out] = create_fuzzed<pbf_collider_id>(in, id, c, pbf_world_create_collider);
    if (r != PBF_OK) {
        if (r == PBF_ERROR_CAPACITY) FUZZ_ASSERT(w && w->colliders.size() == 32);
        return;
    }
    FUZZ_ASSERT(w && !null_desc && !null_out && c.struct_size == sizeof c);
    FUZZ_ASSERT(w->colliders.size() < 32);
    FUZZ_ASSERT(finite3(c.position) && std::isfinite(c.radius) && std::isfinite(c.half_height) &&
                finite3(c.half_extents) && std::isfinite(c.friction) && c.friction >= 0 && c.friction <= 1);
    FUZZ_ASSERT(c.shape >= PBF_SHAPE_PLANE && c.shape <= PBF_SHAPE_BOX);
    FUZZ_ASSERT(c.motion == PBF_MOTION_STATIC || c.motion == PBF_MOTION_KINEMATIC);
    FUZZ_ASSERT(out.generation != 0 && find_live(w->colliders, out) < 0);
    w->colliders.push_back(ColliderModel{out, c.motion});
}

void op_destroy_collider(Reader& in, State& s) {
    destroy_picked(in, s, &WorldModel::colliders, &WorldModel::dead_colliders, pbf_world_destroy_collider);
}

void op_set_pose(Reader& in, State& s) {
    const auto [w, id, c, k] = pick_object(in, s, &WorldModel::colliders, &WorldModel::dead_colliders);
    float p[3], q[4] = {0.0f, 0.0f, 0.0f, 1.0f};
    in.vec3(p, -1.0f, 1.0f);
    const uint8_t mode = in.u8();
    if (mode & 1)
        for (int i = 0; i < 4; ++i) q[i] = in.f(-1.0f, 1.0f);
    const auto hp = std::unique_ptr<float[]>(new float[3]{p[0], p[1], p[2]});
    const auto hq = std::unique_ptr<float[]>(new float[4]{q[0], q[1], q[2], q[3]});
    const bool null_p = (mode & 0xF0) == 0xF0, null_q = (mode & 0x0E) == 0x0E;
    const pbf_result r =
        checked(pbf_collider_set_target_pose(id, c, null_p ? nullptr : hp.get(), null_q ? nullptr : hq.get()));
    if (r == PBF_OK) {
        FUZZ_ASSERT(k >= 0 && w->colliders[k].motion == PBF_MOTION_KINEMATIC);
        FUZZ_ASSERT(!null_p && !null_q && finite3(p) && std::isfinite(q[0]) && std::isfinite(q[1]) &&
                    std::isfinite(q[2]) && std::isfinite(q[3]));
    }
    if (r == PBF_ERROR_INVALID_STATE) FUZZ_ASSERT(k >= 0 && w->colliders[k].motion == PBF_MOTION_STATIC);
}

uint32_t pick_max_count(Reader& in, uint32_t count, uint32_t capacity) {
    switch (in.u8() % 10) {
        case 0:
            return 0;
        case 1:
            return count;
        case 2:
            return count ? count - 1 : 0;
        case 3:
            return count + 1;
        case 4:
            return in.u16() % 64;
        case 5:
            return 0xFFFFFFFFu;
        case 6:
            return in.raw32();
        case 7:
            return capacity;
        case 8:
            return count / 2;
        default:
            return count;
    }
}

void op_copy(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    const uint8_t which = in.u8() % 3;
    const uint32_t count = w ? count_of(*w) : 0;
    const uint32_t max_count = pick_max_count(in, count, w ? w->capacity : 0);
    const uint8_t ptrs = in.u8();
    const bool null_out = ptrs < 16, null_written = (ptrs & 0xC0) == 0xC0;
    // Exactly as many elements as the call may write: min(max_count, count), plus a canary
    // tail where max_count leaves room. The library may write min(count, max_count).
    const size_t comps = which == 2 ? 1 : 4;
    const size_t elems = std::min<uint64_t>(max_count, uint64_t(count) + 8);
    std::unique_ptr<uint32_t[]> buf(new uint32_t[std::max<size_t>(1, elems * comps)]);
    for (size_t k = 0; k < elems * comps; ++k) buf[k] = 0xA5A5A5A5u;
    uint32_t written = 0xEEEEEEEEu;
    void* out = null_out ? nullptr : buf.get();
    uint32_t* wp = null_written ? nullptr : &written;
    pbf_result r;
    if (which == 0)
        r = checked(pbf_world_copy_positions(id, static_cast<float*>(out), max_count, wp));
    else if (which == 1)
        r = checked(pbf_world_copy_velocities(id, static_cast<float*>(out), max_count, wp));
    else
        r = checked(pbf_world_copy_ids(id, static_cast<uint32_t*>(out), max_count, wp));
    if (null_out && max_count > 0) {
        FUZZ_ASSERT(r == PBF_ERROR_INVALID_ARGUMENT);
        if (wp) FUZZ_ASSERT(written == 0);
        return;
    }
    if (!w) {
        FUZZ_ASSERT(r == PBF_ERROR_INVALID_HANDLE);
        if (wp) FUZZ_ASSERT(written == 0);
        return;
    }
    FUZZ_ASSERT(r == PBF_OK);
    const uint32_t expect = std::min(count, max_count);
    if (wp) FUZZ_ASSERT(written == expect);  // writes <= max_count, and all there are
    if (!null_out) {
        for (size_t k = size_t(expect) * comps; k < elems * comps; ++k) FUZZ_ASSERT(buf[k] == 0xA5A5A5A5u);
        if (which != 2) {
            const float* f = reinterpret_cast<const float*>(buf.get());
            for (size_t k = 0; k < expect; ++k) FUZZ_ASSERT(finite3(f + 4 * k));
        } else {
            for (size_t k = 0; k < expect; ++k) FUZZ_ASSERT(buf[k] != kDeadId);
        }
    }
    FUZZ_ASSERT(count_of(*w) == count);
}

void op_map(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    const uint8_t what = in.u8();
    if (what & 1) {  // unmap
        const pbf_result r = checked(pbf_world_unmap(id));
        if (!w) {
            FUZZ_ASSERT(r == PBF_ERROR_INVALID_HANDLE);
            return;
        }
        if (w->mapped == kMapped) FUZZ_ASSERT(r == PBF_OK);
        if (w->mapped == kNotMapped) FUZZ_ASSERT(r == PBF_ERROR_INVALID_STATE);
        if (w->mapped == kMaybeMapped) FUZZ_ASSERT(r == PBF_OK || r == PBF_ERROR_INVALID_STATE);
        w->mapped = kNotMapped;
        return;
    }
    if (what & 2) {  // read the live mapping (valid until unmap, step, emit, destroy)
        if (w && w->mapped == kMapped && w->map.count > 0) {
            std::vector<float> copy(size_t(w->map.count) * 4);
            uint32_t written = 0;
            FUZZ_ASSERT(checked(pbf_world_copy_positions(id, copy.data(), w->map.count, &written)) == PBF_OK);
            FUZZ_ASSERT(written == w->map.count);
            FUZZ_ASSERT(std::memcmp(copy.data(), w->map.data, copy.size() * sizeof(float)) == 0);
        }
        return;
    }
    pbf_mapped_buffer m;
    std::memset(&m, 0x77, sizeof m);
    m.struct_size = in.struct_size(sizeof m);
    const bool null_out = in.u8() < 16;
    const auto hm = heap(m);
    const pbf_result r = checked(pbf_world_map_positions(id, null_out ? nullptr : hm.get()));
    if (r != PBF_OK) {
        FUZZ_ASSERT(!w || null_out || m.struct_size != sizeof m);
        if (!null_out) FUZZ_ASSERT(std::memcmp(hm.get(), &m, sizeof m) == 0);
        return;
    }
    FUZZ_ASSERT(w != nullptr);
    const uint32_t count = count_of(*w);
    FUZZ_ASSERT(hm->memory == PBF_MEMORY_HOST && hm->stride_bytes == 16 && hm->count == count);
    FUZZ_ASSERT(hm->data != nullptr || count == 0);
    // Touch every mapped byte (AddressSanitizer checks the range) and compare with a copy.
    float sum = 0.0f;
    const float* data = static_cast<const float*>(hm->data);
    for (size_t k = 0; k < size_t(count) * 4; ++k) sum += data[k] * 0.0f;
    (void)sum;
    w->mapped = kMapped;
    w->map = *hm;
}

void op_desc_init(Reader& in) {
    const uint8_t which = in.u8() % 5;
    const bool right_size = in.u8() < 96;
    const bool null_p = in.u8() < 64;
    pbf_result r = PBF_OK;
    uint32_t size = 0, right = 0;
    auto run = [&](auto& obj, auto call) {
        using T = std::remove_reference_t<decltype(obj)>;
        size = right_size ? uint32_t(sizeof obj) : in.struct_size(sizeof obj) + (in.u8() & 1 ? 0 : 1);
        std::memset(&obj, 0x42, sizeof obj);
        const T before = obj;
        const auto h = heap(obj);
        r = checked(call(null_p ? nullptr : h.get(), size));
        right = uint32_t(sizeof obj);
        if (r != PBF_OK && !null_p) FUZZ_ASSERT(std::memcmp(h.get(), &before, sizeof before) == 0);
        if (r == PBF_OK) FUZZ_ASSERT(h->struct_size == sizeof obj);
    };
    if (which == 0) {
        pbf_solver_params p;
        run(p, [](pbf_solver_params* x, uint32_t n) { return pbf_solver_params_init(x, n); });
    } else if (which == 1) {
        pbf_world_desc d;
        const uint32_t version = in.raw32();
        run(d, [version](pbf_world_desc* x, uint32_t n) { return pbf_world_desc_init(x, n, version); });
    } else if (which == 2) {
        pbf_block_desc b;
        run(b, [](pbf_block_desc* x, uint32_t n) { return pbf_block_desc_init(x, n); });
    } else if (which == 3) {
        pbf_emitter_desc e;
        run(e, [](pbf_emitter_desc* x, uint32_t n) { return pbf_emitter_desc_init(x, n); });
    } else {
        pbf_collider_desc c;
        run(c, [](pbf_collider_desc* x, uint32_t n) { return pbf_collider_desc_init(x, n); });
    }
    FUZZ_ASSERT((r == PBF_OK) == (!null_p && size == right));
}

// The interop calls a CPU world can answer (the CUDA/GL/Vulkan ones refuse: no CUDA in this
// build): device buffers (host memory on the CPU backend), event id, info, support, counters.
void op_interop(Reader& in, State& s) {
    WorldModel* w = nullptr;
    const pbf_world_id id = pick_world(in, s, &w);
    const uint8_t what = in.u8() % 8;
    const bool null_out = in.u8() < 16;
    if (what == 0) {
        pbf_device_buffers b;
        std::memset(&b, 0x66, sizeof b);
        b.struct_size = in.struct_size(sizeof b);
        const uint32_t flags = in.u8() < 200 ? 0u : in.u32(0, 3);
        const auto hb = heap(b);
        const pbf_result r = checked(pbf_world_map_device_buffers(id, flags, null_out ? nullptr : hb.get()));
        if (r != PBF_OK) {
            if (!null_out) FUZZ_ASSERT(std::memcmp(hb.get(), &b, sizeof b) == 0);
            return;
        }
        FUZZ_ASSERT(w && !null_out && b.struct_size == sizeof b && (flags & ~PBF_MAP_NO_WAIT) == 0);
        const uint32_t count = count_of(*w);
        FUZZ_ASSERT(hb->memory == PBF_MEMORY_HOST && hb->count == count && hb->capacity == w->capacity);
        FUZZ_ASSERT(hb->vec4_stride_bytes == 16 && hb->id_stride_bytes == 4 && hb->cuda_device == -1);
        FUZZ_ASSERT(hb->cuda_stream == nullptr && hb->count_device && *hb->count_device == count);
        FUZZ_ASSERT(static_cast<char*>(hb->density_ratio) == static_cast<char*>(hb->positions) + 12);
        // "capacity elements allocated behind each pointer": touch them all (AddressSanitizer
        // checks the ranges); the live ones match a copy.
        volatile float sink = 0.0f;
        const float* pos = static_cast<const float*>(hb->positions);
        const float* vel = static_cast<const float*>(hb->velocities);
        const uint32_t* ids = static_cast<const uint32_t*>(hb->ids);
        for (size_t k = 0; k < size_t(hb->capacity) * 4; ++k) sink = sink + pos[k] * 0.0f + vel[k] * 0.0f;
        for (size_t k = 0; k < hb->capacity; ++k) sink = sink + float(ids[k] & 1u) * 0.0f;
        if (count) {
            std::vector<uint32_t> copy(count);
            uint32_t written = 0;
            FUZZ_ASSERT(checked(pbf_world_copy_ids(id, copy.data(), count, &written)) == PBF_OK && written == count);
            FUZZ_ASSERT(std::memcmp(copy.data(), ids, size_t(count) * 4) == 0);
        }
        w->mapped = kMapped;  // pbf_world_unmap ends it
        w->map.count = 0;     // op_map's reader reads only a pbf_world_map_positions mapping
        return;
    }
    pbf_result r = PBF_OK;
    if (what == 1) {
        int32_t ev = 12345;
        r = checked(pbf_world_get_render_event_id(id, null_out ? nullptr : &ev));
        if (r == PBF_OK) FUZZ_ASSERT(w && ev > 0 && ev == int32_t(id.index + 1));
    } else if (what == 2) {
        pbf_interop_info info;
        std::memset(&info, 0x21, sizeof info);
        info.struct_size = in.struct_size(sizeof info);
        const auto hi = heap(info);
        r = checked(pbf_world_get_interop_info(id, null_out ? nullptr : hi.get()));
        if (r == PBF_OK)
            FUZZ_ASSERT(w && hi->cuda_device == -1 && hi->gl_buffers == 0);
        else if (!null_out)
            FUZZ_ASSERT(std::memcmp(hi.get(), &info, sizeof info) == 0);
    } else if (what == 3) {
        uint32_t flags = 0;
        r = checked(pbf_get_interop_support(null_out ? nullptr : &flags));
        if (r == PBF_OK) FUZZ_ASSERT((flags & PBF_INTEROP_SUPPORT_CUDA) == 0);  // a CPU-only build
    } else if (what == 4) {
        uint64_t transfers = 0, bytes = 0;
        r = checked(pbf_debug_get_transfer_count(null_out ? nullptr : &transfers, (in.u8() & 1) ? nullptr : &bytes));
    } else if (what == 5) {
        void* stream = reinterpret_cast<void*>(uintptr_t(0x1234));
        r = checked(pbf_world_get_cuda_stream(id, null_out ? nullptr : &stream));
        if (!null_out) FUZZ_ASSERT(stream == nullptr);
        FUZZ_ASSERT(r != PBF_OK);  // no CUDA world in this build
        r = checked(pbf_world_set_cuda_stream(id, nullptr));
        FUZZ_ASSERT(r != PBF_OK);
    } else if (what == 6) {
        void* event = reinterpret_cast<void*>(uintptr_t(0x1234));
        r = checked(pbf_world_record_cuda_event(id, null_out ? nullptr : &event));
        if (!null_out) FUZZ_ASSERT(event == nullptr);
        FUZZ_ASSERT(r != PBF_OK);
        r = checked(pbf_world_wait_cuda_event(id, nullptr));
        FUZZ_ASSERT(r != PBF_OK);
    } else {
        r = checked(pbf_world_unmap(id));  // also ends a device-buffer mapping
        if (w) {
            if (w->mapped == kMapped) FUZZ_ASSERT(r == PBF_OK);
            if (w->mapped == kNotMapped) FUZZ_ASSERT(r == PBF_ERROR_INVALID_STATE);
            w->mapped = kNotMapped;
        } else {
            FUZZ_ASSERT(r == PBF_ERROR_INVALID_HANDLE);
        }
    }
    if (!w && what != 3 && what != 4) FUZZ_ASSERT(r != PBF_OK);
}

void op_misc(Reader& in) {
    const uint8_t what = in.u8() % 4;
    if (what == 0) {
        FUZZ_ASSERT(pbf_fuzz_result_string(int32_t(in.raw32())) != nullptr);  // any int, from C
    } else if (what == 1) {
        FUZZ_ASSERT(pbf_get_version() == PBF_VERSION);
        FUZZ_ASSERT(pbf_last_error_message() != nullptr);
    } else if (what == 2) {
        pbf_set_log_callback(log_sink, &g_log_calls);
    } else {
        pbf_set_log_callback(nullptr, nullptr);
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    // One OpenMP thread: deterministic and cheaper under the sanitizers (the loops only go
    // parallel above 2048 particles anyway).
    setenv("OMP_NUM_THREADS", "1", 0);
    const char* trace = std::getenv("PBF_FUZZ_TRACE");
    g_trace = trace && *trace && *trace != '0';
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    Reader in{data, size};
    State s;
    int ops = 0;
    while (!in.empty() && ops++ < 256) {
        const uint8_t op = in.u8();
        if (g_trace) {
            static const char* const names[20] = {"create",
                                                  "create",
                                                  "destroy",
                                                  "step",
                                                  "step",
                                                  "step",
                                                  "set_params",
                                                  "get",
                                                  "gravity",
                                                  "emit_block",
                                                  "emit_block",
                                                  "create_emitter",
                                                  "destroy_emitter",
                                                  "emitter_update",
                                                  "create_collider",
                                                  "destroy_collider",
                                                  "set_pose",
                                                  "copy",
                                                  "map",
                                                  "desc_init/interop/misc"};
            std::fprintf(stderr, "op %d: %s\n", ops, names[op % 20]);
        }
        switch (op % 20) {
            case 0:
            case 1:
                op_create_world(in, s);
                break;
            case 2:
                op_destroy_world(in, s);
                break;
            case 3:
            case 4:
            case 5:
                op_step(in, s);
                break;
            case 6:
                op_set_params(in, s);
                break;
            case 7:
                op_get(in, s);
                break;
            case 8:
                op_gravity(in, s);
                break;
            case 9:
            case 10:
                op_emit_block(in, s);
                break;
            case 11:
                op_create_emitter(in, s);
                break;
            case 12:
                op_destroy_emitter(in, s);
                break;
            case 13:
                op_emitter_update(in, s);
                break;
            case 14:
                op_create_collider(in, s);
                break;
            case 15:
                op_destroy_collider(in, s);
                break;
            case 16:
                op_set_pose(in, s);
                break;
            case 17:
                op_copy(in, s);
                break;
            case 18:
                op_map(in, s);
                break;
            default:
                if (op & 0x80)
                    op_desc_init(in);
                else if (op & 0x40)
                    op_interop(in, s);
                else
                    op_misc(in);
                break;
        }
        // Every live world still satisfies the cheap invariants after any call: count <= capacity
        // after each, the stats' accounting every 8th (stats may run a density pass).
        for (const WorldModel& w : s.worlds) {
            if (ops % 8 == 0)
                check_world(w, false);
            else
                count_of(w);
        }
    }
    for (const WorldModel& w : s.worlds) {
        check_world(w, true);
        FUZZ_ASSERT(checked(pbf_world_destroy(w.id)) == PBF_OK);
    }
    pbf_set_log_callback(nullptr, nullptr);
    return 0;
}
