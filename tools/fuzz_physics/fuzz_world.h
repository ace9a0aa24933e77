// The physics fuzzer's worlds: a WorldSpec is everything one random world does (its desc, its
// materials, blocks, nozzles, drains, colliders and their paths, its events and its step
// sequence), drawn from a seed by draw_world(), so a seed and a world index replay it exactly.
// Every object can be switched off (shrinking) and the frames cut short without changing what
// the rest draws. Public C API only.
#pragma once
#include <pbf_c_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace fuzz {

using V3 = std::array<float, 3>;
using Q4 = std::array<float, 4>;

// splitmix64: a seed per world from (seed, index), so world k never depends on worlds before it.
inline uint64_t mix64(uint64_t x) {
    x += 0x9E3779B97F4A7C15ull;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
    return x ^ (x >> 31);
}

// A small deterministic generator (xoshiro256**), identical on every platform and compiler,
// unlike the standard distributions.
struct Rng {
    uint64_t s[4];
    explicit Rng(uint64_t seed) {
        for (auto& v : s) v = seed = mix64(seed);
    }
    static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    uint64_t next() {
        const uint64_t r = rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = rotl(s[3], 45);
        return r;
    }
    double unit() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }  // [0, 1)
    float uniform(double lo, double hi) { return float(lo + (hi - lo) * unit()); }
    float log_uniform(double lo, double hi) {
        return float(std::exp(std::log(lo) + (std::log(hi) - std::log(lo)) * unit()));
    }
    int integer(int lo, int hi) { return lo + int(next() % uint64_t(hi - lo + 1)); }  // [lo, hi]
    bool chance(double p) { return unit() < p; }
    V3 direction() {
        for (;;) {
            const V3 v{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
            const float n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
            if (n > 0.1f && n <= 1.0f) return {v[0] / n, v[1] / n, v[2] / n};
        }
    }
    Q4 rotation() {
        for (;;) {
            const Q4 q{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)};
            const float n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
            if (n > 0.1f && n <= 1.0f) return {q[0] / n, q[1] / n, q[2] / n, q[3] / n};
        }
    }
};

enum class MeshKind { none, closed_box, octahedron, open_terrain };

struct MaterialSpec {
    bool on = true;
    pbf_material_desc desc{};
};

struct BlockSpec {
    bool on = true;
    int frame = 0;  // emitted before this frame's step
    V3 lo{}, hi{}, velocity{};
    int material = -1;  // index into WorldSpec::materials, -1: the default material
};

struct NozzleSpec {
    bool on = true;
    int create_frame = 0, destroy_frame = -1, toggle_frame = -1, move_frame = -1;
    V3 position{}, direction{}, moved_position{}, moved_direction{};
    float speed = 1, radius = 0.1f, rate = 100;
    int material = -1;
};

struct DrainSpec {
    bool on = true;
    int create_frame = 0, move_frame = -1;
    V3 lo{}, hi{}, moved_lo{}, moved_hi{};
};

// A collider and its motion. Kinematic ones follow x(t) = centre + amplitude ⊙ sin(ω t + φ) and
// turn at a constant angular velocity; a body ("engine-integrated") is moved by the engine from
// the fluid's force, its weight and its own inertia, as a game's rigid body would be.
struct ColliderSpec {
    bool on = true;
    pbf_collider_shape shape = PBF_SHAPE_SPHERE;
    MeshKind mesh = MeshKind::none;
    bool kinematic = false, body = false, dynamic = false;
    int create_frame = 0, destroy_frame = -1, teleport_frame = -1;
    V3 centre{}, amplitude{}, phase{}, spin{}, teleport_to{};
    float omega = 0;
    Q4 rotation{0, 0, 0, 1};
    float radius = 0.1f, half_height = 0.1f, friction = 0, body_density = 1000;
    V3 half_extents{0.1f, 0.1f, 0.1f};
};

struct WorldSpec {
    uint64_t seed = 0;
    uint64_t index = 0;
    pbf_world_desc desc{};
    std::vector<MaterialSpec> materials;
    std::vector<BlockSpec> blocks;
    std::vector<NozzleSpec> nozzles;
    std::vector<DrainSpec> drains;
    std::vector<ColliderSpec> colliders;
    std::vector<float> dts;
    int gravity_frame = -1;  // set_gravity to `gravity_after` before this frame
    V3 gravity_after{};
    int solver_frame = -1;  // set_solver_params to `solver_after` before this frame
    pbf_solver_params solver_after{};
    std::string dt_pattern;  // what the step sequence is, for the report
};

// The surface's largest distance from a collider's position (its surface speed is |ω| times it);
// a plane's is infinite (planes never turn).
float collider_reach(const ColliderSpec& c);

WorldSpec draw_world(uint64_t seed, uint64_t index, pbf_backend backend);

// Mesh geometry of a MeshKind, in the collider's own frame, sized by the spec's half_extents.
struct MeshData {
    std::vector<float> vertices;
    std::vector<uint32_t> indices;
    bool closed = true;
};
MeshData mesh_of(const ColliderSpec& c);

// A one-line description of each part of a world, for the repro printout.
std::string describe(const WorldSpec& w);

}  // namespace fuzz
