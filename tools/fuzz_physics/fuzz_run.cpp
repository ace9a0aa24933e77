// One fuzz world, frame by frame: the spec's events, one pbf_world_step, the state read back
// through the public API, and the invariants. Every bound is derived in docs/physics_fuzzer.md;
// the comments here say which quantity each line stands for.
#include "fuzz_run.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>
#include <sstream>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace fuzz {

namespace {

// ---- small vector and quaternion helpers ---------------------------------------------------
struct D3 {
    double x = 0, y = 0, z = 0;
};
D3 d3(const float* v) { return {v[0], v[1], v[2]}; }
D3 d3(const V3& v) { return {v[0], v[1], v[2]}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(D3 a) { return std::sqrt(dot(a, a)); }

Q4 qmul(const Q4& a, const Q4& b) {
    return {
        a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1], a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
        a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3], a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2]};
}
Q4 qconj(const Q4& q) { return {-q[0], -q[1], -q[2], q[3]}; }
Q4 qexp(const V3& w, double t) {  // rotation by angle |w| t about w
    const double n = std::sqrt(double(w[0]) * w[0] + double(w[1]) * w[1] + double(w[2]) * w[2]);
    if (n * t < 1e-12) return {0, 0, 0, 1};
    const double a = 0.5 * n * t, s = std::sin(a) / n;
    return {float(w[0] * s), float(w[1] * s), float(w[2] * s), float(std::cos(a))};
}
D3 rotate(const Q4& q, D3 v) {  // q v q*
    const D3 u{q[0], q[1], q[2]};
    const D3 t = cross(u, v) * 2.0;
    return v + t * q[3] + cross(u, t);
}
// The rotation vector (axis · angle, angle in [0, π]) taking a to b.
D3 rotation_between(const Q4& a, const Q4& b) {
    Q4 r = qmul(b, qconj(a));
    if (r[3] < 0) r = {-r[0], -r[1], -r[2], -r[3]};
    const double s = std::sqrt(double(r[0]) * r[0] + double(r[1]) * r[1] + double(r[2]) * r[2]);
    if (s < 1e-12) return {};
    const double angle = 2.0 * std::atan2(s, double(r[3]));
    return D3{r[0], r[1], r[2]} * (angle / s);
}

constexpr double kPi = 3.14159265358979323846;

// ---- the bounds' stated constants (docs/physics_fuzzer.md) ---------------------------------
// Ritter's dam-break front runs at 2√(gH) = √2 · √(2gH): the fastest a free surface driven by
// gravity alone moves, over a drop H.
constexpr double kFrontFactor = 1.41421356;
// A particle's speed allowance beyond the physical terms: the product's own "at any dt a settled
// pool has no particle faster than 1 m/s" (README, Physics; tests/test_realtime.cpp).
constexpr double kSpeedMargin = 1.0;
// The speed of "at rest" (the product's resting-pool goal) used for the energy margin's kinetic
// part: the whole fluid jittering at it.
constexpr double kRestSpeed = 0.5;
// Density: a third of the fluid's volume squeezed out (ρ = 1.5 ρ0) anywhere is broken, whatever
// the scene; on top the depth rule's documented compression with a factor 2.
constexpr double kDensityBase = 0.5;
constexpr double kDepthRuleFactor = 2.0;
// |ω| <= kVorticityGradient · v_max / h: the SPH curl of a velocity field bounded by v_max, with
// Σ_j V_j |∇W_spiky| = 6/h over a full neighbourhood, a factor 2 for |v_j - v_i| <= 2 v_max and
// 1.25 for neighbourhoods denser than rest.
constexpr double kVorticityGradient = 15.0;
// Zero gravity, no boundary: |ΔP| and |ΔL| within this fraction of their magnitude scales
// Σ m|v| and Σ m|x - c||v| (float32 sums over ~50 neighbours, dozens of iterations), plus a floor
// for a fluid at rest.
constexpr double kMomentumTolerance = 0.01;
constexpr double kMomentumFloorSpeed = 1e-4;

struct State {
    std::vector<float> pos, vel;
    std::vector<uint32_t> ids;
    std::vector<uint8_t> mat;
    uint32_t n = 0;
};

struct Live {
    pbf_collider_id id{0, 0};
    pbf_mesh_id mesh{0, 0};
    bool alive = false;
    V3 pos{};
    Q4 rot{0, 0, 0, 1};
    V3 centre{};  // the path's centre (moves with teleports)
    D3 body_velocity{};
    double body_mass = 0;
};

struct Failure {
    std::string invariant, detail;
};

class Runner {
public:
    explicit Runner(const WorldSpec& spec) : spec_(spec) {}
    RunResult run();

private:
    const WorldSpec& spec_;
    pbf_world_id w_{0, 0};
    RunResult res_;
    std::vector<pbf_material_id> mats_;
    std::vector<Live> colliders_;
    std::vector<pbf_emitter_id> nozzles_, drains_;
    std::vector<bool> nozzle_alive_, nozzle_enabled_, drain_alive_;
    std::vector<V3> nozzle_pos_, drain_lo_, drain_hi_;
    double mass_by_slot_[PBF_MAX_MATERIALS] = {};
    double volume_ = 0, h_ = 0, r_ = 0;
    V3 g_{};
    double g_max_ = 0;
    double time_ = 0;
    // Time of the steps too short for the world to simulate (pbf_step_stats.simulated_dt 0),
    // which the next step simulates with its own: the colliders move from where the world has
    // them to their newest target over both.
    double carried_ = 0;
    // Bookkeeping of the bounds.
    D3 box_lo_{1e30, 1e30, 1e30}, box_hi_{-1e30, -1e30, -1e30};  // everything ever placed or reached
    double coll_speed_max_ = 0, emit_speed_max_ = 0, vort_speed_ = 0, cohesion_speed_ = 0;
    double budget_ = 0;  // the energy the fluid may have: start + what came in - what drained
    bool energy_on_ = true, momentum_on_ = false;
    double prev_density_max_ = 0;
    D3 p0_{}, l0_{}, c0_{};
    double p_scale_ = 0, l_scale_ = 0, r_scale_ = 0, momentum_allow_p_ = 0, momentum_allow_l_ = 0;
    State post_;
    bool have_post_ = false;
    double e_post_ = 0;

    bool ok(pbf_result r, const char* what, Failure& f) {
        if (r == PBF_OK) return true;
        f = {"api", std::string(what) + " -> " + pbf_result_string(r) + ": " + pbf_last_error_message()};
        return false;
    }
    void grow_around(D3 c, double reach) {  // a ball of radius `reach` around c
        grow(c + D3{reach, reach, reach});
        grow(c - D3{reach, reach, reach});
    }
    void grow(D3 p) {
        box_lo_ = {std::min(box_lo_.x, p.x), std::min(box_lo_.y, p.y), std::min(box_lo_.z, p.z)};
        box_hi_ = {std::max(box_hi_.x, p.x), std::max(box_hi_.y, p.y), std::max(box_hi_.z, p.z)};
    }
    D3 up() const {  // -ĝ (zero in zero g)
        const double g = std::sqrt(double(g_[0]) * g_[0] + double(g_[1]) * g_[1] + double(g_[2]) * g_[2]);
        return g > 0 ? D3{-g_[0] / g, -g_[1] / g, -g_[2] / g} : D3{};
    }
    double gmag() const { return std::sqrt(double(g_[0]) * g_[0] + double(g_[1]) * g_[1] + double(g_[2]) * g_[2]); }
    double mass(const State& s, uint32_t i) const { return mass_by_slot_[s.mat[i] < PBF_MAX_MATERIALS ? s.mat[i] : 0]; }
    double energy(const State& s) const {
        double e = 0;
        for (uint32_t i = 0; i < s.n; ++i) {
            const D3 x = d3(&s.pos[4 * i]), v = d3(&s.vel[4 * i]);
            e += mass(s, i) * (0.5 * dot(v, v) - (x.x * g_[0] + x.y * g_[1] + x.z * g_[2]));
        }
        return e;
    }
    double total_mass(const State& s) const {
        double m = 0;
        for (uint32_t i = 0; i < s.n; ++i) m += mass(s, i);
        return m;
    }
    bool read(State& s, Failure& f);
    V3 path_pos(const ColliderSpec& c, const Live& l, double t) const {
        V3 p;
        for (int a = 0; a < 3; ++a) p[a] = float(l.centre[a] + c.amplitude[a] * std::sin(c.omega * t + c.phase[a]));
        return p;
    }
    Q4 path_rot(const ColliderSpec& c, double t) const { return qmul(qexp(c.spin, t), c.rotation); }
    double sdf(const ColliderSpec& c, const Live& l, D3 x) const;
    double overlap_allowance(const State& s, const std::vector<char>& candidate, const std::vector<size_t>& shapes,
                             bool with_fluid);
    bool create_collider(size_t k, Failure& f);
    bool events(int frame, float dt, std::vector<size_t>& appeared, bool& particles_changed, Failure& f);
    // dt: the time the step simulated, its own and any carried to it; 0 for a step too short to
    // simulate.
    bool check_step(int frame, float dt, const State& pre, const pbf_step_stats& st0, const pbf_step_stats& st1,
                    double work_in, double overlap_in, double v_pre_max, Failure& f);
};

bool Runner::read(State& s, Failure& f) {
    if (!ok(pbf_world_get_particle_count(w_, &s.n), "pbf_world_get_particle_count", f)) return false;
    s.pos.assign(size_t(s.n) * 4, 0.0f);
    s.vel.assign(size_t(s.n) * 4, 0.0f);
    s.ids.assign(s.n, 0u);
    s.mat.assign(s.n, 0u);
    uint32_t k = 0;
    if (s.n == 0) return true;
    return ok(pbf_world_copy_positions(w_, s.pos.data(), s.n, &k), "pbf_world_copy_positions", f) &&
           ok(pbf_world_copy_velocities(w_, s.vel.data(), s.n, &k), "pbf_world_copy_velocities", f) &&
           ok(pbf_world_copy_ids(w_, s.ids.data(), s.n, &k), "pbf_world_copy_ids", f) &&
           ok(pbf_world_copy_buffer(w_, PBF_BUFFER_MATERIALS, s.mat.data(), s.n, &k),
              "pbf_world_copy_buffer(materials)", f);
}

double Runner::sdf(const ColliderSpec& c, const Live& l, D3 x) const {
    const D3 local = rotate(qconj(l.rot), x - d3(l.pos));
    switch (c.shape) {
        case PBF_SHAPE_SPHERE:
            return norm(local) - c.radius;
        case PBF_SHAPE_CAPSULE: {
            const double y = std::clamp(local.y, -double(c.half_height), double(c.half_height));
            return norm(local - D3{0, y, 0}) - c.radius;
        }
        case PBF_SHAPE_PLANE:
            return local.y;
        default: {
            // Boxes; meshes by their bounding box (closed ones lie within it; an open terrain's shell
            // reaches one radius beyond its bumps): an over-estimate of what a mesh displaces.
            D3 e = d3(c.half_extents);
            if (c.shape == PBF_SHAPE_MESH && c.mesh == MeshKind::open_terrain) e.y += 2 * r_;
            const D3 q{std::fabs(local.x) - e.x, std::fabs(local.y) - e.y, std::fabs(local.z) - e.z};
            const D3 outside{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
            return norm(outside) + std::min(std::max({q.x, q.y, q.z}), 0.0);
        }
    }
}

// The potential energy an incompressible fluid gains when the volume of the candidate particles
// (inside the listed colliders, or, with_fluid, overlapping fluid already there) is displaced:
// each displaced particle's mass lifted from its height to the fluid's top, plus the level's rise
// (the displaced volume over the fluid's footprint).
double Runner::overlap_allowance(const State& s, const std::vector<char>& candidate, const std::vector<size_t>& shapes,
                                 bool with_fluid) {
    const double g = gmag();
    if (g == 0 || s.n == 0) return 0;
    const D3 u = up();
    // A basis across gravity for the footprint.
    const D3 e1 = norm(cross(u, D3{1, 0, 0})) > 0.5 ? cross(u, D3{1, 0, 0}) * (1.0 / norm(cross(u, D3{1, 0, 0})))
                                                    : cross(u, D3{0, 0, 1}) * (1.0 / norm(cross(u, D3{0, 0, 1})));
    const D3 e2 = cross(u, e1);
    double top = -1e30, a_lo = 1e30, a_hi = -1e30, b_lo = 1e30, b_hi = -1e30;
    D3 old_lo{1e30, 1e30, 1e30}, old_hi{-1e30, -1e30, -1e30};
    for (uint32_t i = 0; i < s.n; ++i) {
        const D3 x = d3(&s.pos[4 * i]);
        top = std::max(top, dot(x, u));
        a_lo = std::min(a_lo, dot(x, e1));
        a_hi = std::max(a_hi, dot(x, e1));
        b_lo = std::min(b_lo, dot(x, e2));
        b_hi = std::max(b_hi, dot(x, e2));
        if (!candidate[i]) {
            old_lo = {std::min(old_lo.x, x.x), std::min(old_lo.y, x.y), std::min(old_lo.z, x.z)};
            old_hi = {std::max(old_hi.x, x.x), std::max(old_hi.y, x.y), std::max(old_hi.z, x.z)};
        }
    }
    const double s_ = 2 * r_, area = (a_hi - a_lo + s_) * (b_hi - b_lo + s_);
    double lift = 0, displaced = 0;
    for (uint32_t i = 0; i < s.n; ++i) {
        if (!candidate[i]) continue;
        const D3 x = d3(&s.pos[4 * i]);
        bool inside = false;
        for (size_t k : shapes)
            if (colliders_[k].alive && sdf(spec_.colliders[k], colliders_[k], x) < r_) inside = true;
        if (with_fluid && x.x >= old_lo.x - r_ && x.x <= old_hi.x + r_ && x.y >= old_lo.y - r_ &&
            x.y <= old_hi.y + r_ && x.z >= old_lo.z - r_ && x.z <= old_hi.z + r_)
            inside = true;
        if (!inside) continue;
        lift += mass(s, i) * (top - dot(x, u));
        displaced += mass(s, i);
    }
    const double rise = displaced > 0 ? (displaced / mass_by_slot_[0]) * volume_ / area + s_ : 0.0;
    return g * (lift + displaced * rise);
}

bool Runner::create_collider(size_t k, Failure& f) {
    const ColliderSpec& c = spec_.colliders[k];
    Live& l = colliders_[k];
    pbf_collider_desc d = pbf_collider_desc_default();
    d.shape = c.shape;
    d.motion = c.kinematic ? PBF_MOTION_KINEMATIC : PBF_MOTION_STATIC;
    d.radius = c.radius;
    d.half_height = c.half_height;
    std::copy(c.half_extents.begin(), c.half_extents.end(), d.half_extents);
    d.friction = c.friction;
    d.dynamic = c.dynamic ? 1u : 0u;
    l.centre = c.centre;
    l.pos = c.kinematic && !c.body ? path_pos(c, l, time_) : c.centre;
    l.rot = c.kinematic && !c.body ? path_rot(c, time_) : c.rotation;
    std::copy(l.pos.begin(), l.pos.end(), d.position);
    std::copy(l.rot.begin(), l.rot.end(), d.rotation);
    if (c.shape == PBF_SHAPE_MESH) {
        const MeshData m = mesh_of(c);
        pbf_mesh_desc md = pbf_mesh_desc_default();
        md.vertices = m.vertices.data();
        md.vertex_count = uint32_t(m.vertices.size() / 3);
        md.indices = m.indices.data();
        md.triangle_count = uint32_t(m.indices.size() / 3);
        md.closed = m.closed ? 1u : 0u;
        if (!ok(pbf_world_create_mesh(w_, &md, &l.mesh), "pbf_world_create_mesh", f)) return false;
        d.mesh = l.mesh;
    }
    if (!ok(pbf_world_create_collider(w_, &d, &l.id), "pbf_world_create_collider", f)) return false;
    l.alive = true;
    if (c.body) {
        const double pi = kPi;
        double vol = 0;
        if (c.shape == PBF_SHAPE_SPHERE)
            vol = 4.0 / 3.0 * pi * std::pow(c.radius, 3);
        else if (c.shape == PBF_SHAPE_CAPSULE)
            vol = pi * c.radius * c.radius * 2 * c.half_height + 4.0 / 3.0 * pi * std::pow(c.radius, 3);
        else
            vol = 8.0 * c.half_extents[0] * c.half_extents[1] * c.half_extents[2];
        l.body_mass = c.body_density * vol;
    }
    if (c.shape != PBF_SHAPE_PLANE) {
        const double reach = collider_reach(c);
        grow_around(d3(l.pos), reach);
    }
    return true;
}

// The spec's events before frame `frame`'s step, and the kinematic targets of the step.
bool Runner::events(int frame, float dt, std::vector<size_t>& appeared, bool& particles_changed, Failure& f) {
    const WorldSpec& s = spec_;
    if (frame == s.gravity_frame) {
        g_ = s.gravity_after;
        g_max_ = std::max(g_max_, gmag());
        if (!ok(pbf_world_set_gravity(w_, s.gravity_after.data()), "pbf_world_set_gravity", f)) return false;
        particles_changed = true;  // the potential energy's field changed
    }
    if (frame == s.solver_frame &&
        !ok(pbf_world_set_solver_params(w_, &s.solver_after), "pbf_world_set_solver_params", f))
        return false;
    for (size_t k = 0; k < s.blocks.size(); ++k) {
        const BlockSpec& b = s.blocks[k];
        if (!b.on || b.frame != frame) continue;
        pbf_block_desc d = pbf_block_desc_default();
        std::copy(b.lo.begin(), b.lo.end(), d.box_min);
        std::copy(b.hi.begin(), b.hi.end(), d.box_max);
        std::copy(b.velocity.begin(), b.velocity.end(), d.velocity);
        if (b.material >= 0 && s.materials[size_t(b.material)].on) d.material = mats_[size_t(b.material)];
        uint32_t emitted = 0;
        const pbf_result r = pbf_world_emit_block(w_, &d, &emitted);
        if (r != PBF_ERROR_CAPACITY && !ok(r, "pbf_world_emit_block", f)) return false;  // full: the capacity's answer
        particles_changed = true;
        emit_speed_max_ = std::max(emit_speed_max_, norm(d3(b.velocity)));
        grow(d3(b.lo));
        grow(d3(b.hi));
    }
    for (size_t k = 0; k < s.nozzles.size(); ++k) {
        const NozzleSpec& n = s.nozzles[k];
        if (!n.on) continue;
        if (frame == n.create_frame) {
            pbf_emitter_desc e = pbf_emitter_desc_default();
            e.type = PBF_EMITTER_NOZZLE;
            std::copy(n.position.begin(), n.position.end(), e.position);
            std::copy(n.direction.begin(), n.direction.end(), e.direction);
            e.speed = n.speed;
            e.radius = n.radius;
            e.particles_per_second = n.rate;
            if (n.material >= 0 && s.materials[size_t(n.material)].on) e.material = mats_[size_t(n.material)];
            if (!ok(pbf_world_create_emitter(w_, &e, &nozzles_[k]), "pbf_world_create_emitter(nozzle)", f))
                return false;
            nozzle_alive_[k] = nozzle_enabled_[k] = true;
            nozzle_pos_[k] = n.position;
            emit_speed_max_ = std::max(emit_speed_max_, double(n.speed));
            grow_around(d3(n.position), n.radius);
        }
        if (!nozzle_alive_[k]) continue;
        if (frame == n.destroy_frame) {
            if (!ok(pbf_world_destroy_emitter(w_, nozzles_[k]), "pbf_world_destroy_emitter", f)) return false;
            nozzle_alive_[k] = false;
            continue;
        }
        if (frame == n.toggle_frame) {
            nozzle_enabled_[k] = !nozzle_enabled_[k];
            if (!ok(pbf_emitter_set_enabled(w_, nozzles_[k], nozzle_enabled_[k] ? 1u : 0u), "pbf_emitter_set_enabled",
                    f))
                return false;
        }
        if (frame == n.move_frame) {
            if (!ok(pbf_emitter_set_nozzle(w_, nozzles_[k], n.moved_position.data(), n.moved_direction.data()),
                    "pbf_emitter_set_nozzle", f))
                return false;
            nozzle_pos_[k] = n.moved_position;
            grow_around(d3(n.moved_position), n.radius);
        }
    }
    for (size_t k = 0; k < s.drains.size(); ++k) {
        const DrainSpec& d = s.drains[k];
        if (!d.on) continue;
        if (frame == d.create_frame) {
            pbf_emitter_desc e = pbf_emitter_desc_default();
            e.type = PBF_EMITTER_DRAIN;
            std::copy(d.lo.begin(), d.lo.end(), e.box_min);
            std::copy(d.hi.begin(), d.hi.end(), e.box_max);
            if (!ok(pbf_world_create_emitter(w_, &e, &drains_[k]), "pbf_world_create_emitter(drain)", f)) return false;
            drain_alive_[k] = true;
            drain_lo_[k] = d.lo;
            drain_hi_[k] = d.hi;
        }
        if (drain_alive_[k] && frame == d.move_frame) {
            if (!ok(pbf_emitter_set_drain_box(w_, drains_[k], d.moved_lo.data(), d.moved_hi.data()),
                    "pbf_emitter_set_drain_box", f))
                return false;
            drain_lo_[k] = d.moved_lo;
            drain_hi_[k] = d.moved_hi;
        }
    }
    for (size_t k = 0; k < s.colliders.size(); ++k) {
        const ColliderSpec& c = s.colliders[k];
        if (!c.on) continue;
        Live& l = colliders_[k];
        if (frame == c.create_frame) {
            if (!create_collider(k, f)) return false;
            appeared.push_back(k);
        }
        if (!l.alive) continue;
        if (frame == c.destroy_frame) {
            if (!ok(pbf_world_destroy_collider(w_, l.id), "pbf_world_destroy_collider", f)) return false;
            if (l.mesh.generation && !ok(pbf_world_destroy_mesh(w_, l.mesh), "pbf_world_destroy_mesh", f)) return false;
            l.alive = false;
            continue;
        }
        if (frame == c.teleport_frame) {
            // The path continues from where the collider lands.
            const V3 at = c.kinematic && !c.body ? path_pos(c, l, time_) : l.pos;
            for (int a = 0; a < 3; ++a) l.centre[a] += c.teleport_to[a] - at[a];
            l.pos = c.teleport_to;
            if (!ok(pbf_collider_teleport(w_, l.id, l.pos.data(), l.rot.data()), "pbf_collider_teleport", f))
                return false;
            appeared.push_back(k);
            if (c.shape != PBF_SHAPE_PLANE) {
                const double reach = collider_reach(c);
                grow_around(d3(l.pos), reach);
            }
        }
    }
    (void)dt;
    return true;
}

bool Runner::check_step(int frame, float dt, const State& pre, const pbf_step_stats& st0, const pbf_step_stats& st1,
                        double work_in, double overlap_in, double v_pre_max, Failure& f) {
    const State& post = post_;
    std::ostringstream o;
    // ---- finite ----
    for (size_t k = 0; k < post.pos.size(); ++k)
        if (!std::isfinite(post.pos[k]) || !std::isfinite(post.vel[k])) {
            o << "particle " << k / 4 << " (id " << post.ids[k / 4] << ") has a non-finite "
              << (std::isfinite(post.pos[k]) ? "velocity" : "position");
            f = {"finite", o.str()};
            return false;
        }
    if (!std::isfinite(st1.kinetic_energy) || !std::isfinite(st1.density_error_max) ||
        !std::isfinite(st1.density_error_mean)) {
        f = {"finite", "stats: kinetic energy or density error not finite"};
        return false;
    }
    if (!std::isfinite(work_in)) {
        f = {"finite", "a dynamic collider's force is not finite"};
        return false;
    }
    // ---- accounting: nothing appears or vanishes but through emission and drains ----
    const int64_t emitted = int64_t(st1.emitted_total - st0.emitted_total),
                  drained = int64_t(st1.drained_total - st0.drained_total);
    std::unordered_map<uint32_t, uint32_t> before;
    before.reserve(pre.n * 2);
    for (uint32_t i = 0; i < pre.n; ++i) before[pre.ids[i]] = i;
    std::unordered_set<uint32_t> seen;
    seen.reserve(post.n * 2);
    std::vector<uint32_t> fresh;
    for (uint32_t i = 0; i < post.n; ++i) {
        if (!seen.insert(post.ids[i]).second) {
            o << "id " << post.ids[i] << " appears twice";
            f = {"accounting", o.str()};
            return false;
        }
        if (!before.count(post.ids[i])) fresh.push_back(i);
    }
    std::vector<uint32_t> vanished;
    for (uint32_t i = 0; i < pre.n; ++i)
        if (!seen.count(pre.ids[i])) vanished.push_back(i);
    if (int64_t(post.n) != int64_t(pre.n) + emitted - drained || int64_t(fresh.size()) > emitted ||
        int64_t(vanished.size()) > drained || post.n > spec_.desc.max_particles || st1.particle_count != post.n) {
        o << "count " << pre.n << " -> " << post.n << " (stats " << st1.particle_count << "), emitted " << emitted
          << ", drained " << drained << ", new ids " << fresh.size() << ", vanished ids " << vanished.size()
          << ", capacity " << spec_.desc.max_particles;
        f = {"accounting", o.str()};
        return false;
    }
    // ---- the speed bound (computed before this step's positions widen the scene) ----
    const double g = g_max_;
    const double height = std::fabs(up().x) * (box_hi_.x - box_lo_.x) + std::fabs(up().y) * (box_hi_.y - box_lo_.y) +
                          std::fabs(up().z) * (box_hi_.z - box_lo_.z);
    // After a gravity change the drop may lie along any axis: the scene's diagonal.
    const double drop =
        spec_.gravity_frame >= 0 && frame >= spec_.gravity_frame ? norm(box_hi_ - box_lo_) : std::max(height, 0.0);
    for (uint32_t i : vanished) {  // a drained particle was inside a drain box, as far as it could travel
        const D3 x = d3(&pre.pos[4 * i]);
        bool near = false;
        // A particle inside a collider is first moved out of it (to one radius from its surface).
        double depth = 0;
        for (size_t k = 0; k < colliders_.size(); ++k)
            if (colliders_[k].alive) depth = std::max(depth, r_ - sdf(spec_.colliders[k], colliders_[k], x));
        const double reach = (norm(d3(&pre.vel[4 * i])) + kFrontFactor * std::sqrt(2 * g * std::max(drop, 0.0)) +
                              2 * coll_speed_max_ + emit_speed_max_ + kSpeedMargin + vort_speed_ + cohesion_speed_) *
                                 dt +
                             h_ + depth;
        for (size_t k = 0; k < drains_.size(); ++k) {
            if (!drain_alive_[k]) continue;
            const D3 lo = d3(drain_lo_[k]), hi = d3(drain_hi_[k]);
            const D3 q{std::max({lo.x - x.x, 0.0, x.x - hi.x}), std::max({lo.y - x.y, 0.0, x.y - hi.y}),
                       std::max({lo.z - x.z, 0.0, x.z - hi.z})};
            if (norm(q) <= reach) near = true;
        }
        if (!near) {
            o << "particle id " << pre.ids[i] << " at (" << x.x << ", " << x.y << ", " << x.z
              << ") vanished, out of every drain's reach " << reach << " m";
            f = {"accounting", o.str()};
            return false;
        }
    }
    // ---- containment: walls hold centres one radius inside; no particle deep in a collider ----
    if (spec_.desc.walls) {
        const pbf_world_desc& d = spec_.desc;
        for (uint32_t i = 0; i < post.n; ++i)
            for (int a = 0; a < 3; ++a) {
                const double x = post.pos[4 * i + a], tol = 1e-3 * r_ + 1e-6 * std::fabs(x);
                if (x < d.domain_min[a] + r_ - tol || x > d.domain_max[a] - r_ + tol) {
                    o << "particle id " << post.ids[i] << " at "
                      << "xyz"[a] << " = " << x << " is outside the walls " << d.domain_min[a] << ".."
                      << d.domain_max[a] << " (less one radius)";
                    f = {"walls", o.str()};
                    return false;
                }
            }
    }
    // (After a step too short to simulate, a collider created or teleported since is where it was
    // put, the fluid not yet moved out: the step that simulates settles it.)
    for (size_t k = 0; k < colliders_.size() && st1.simulated_dt > 0.0f; ++k) {
        const ColliderSpec& c = spec_.colliders[k];
        if (!colliders_[k].alive || c.shape == PBF_SHAPE_MESH) continue;
        for (uint32_t i = 0; i < post.n; ++i) {
            const double d = sdf(c, colliders_[k], d3(&post.pos[4 * i]));
            if (d < -h_) {
                o << "particle id " << post.ids[i] << " is " << -d << " m inside collider c" << k
                  << " (more than h = " << h_ << ")";
                f = {"collider", o.str()};
                return false;
            }
        }
    }
    // ---- no two particles on one position ----
    {
        // Each position with its particle's index, sorted: equal positions end side by side.
        std::vector<std::pair<std::array<float, 3>, uint32_t>> p(post.n);
        for (uint32_t i = 0; i < post.n; ++i) p[i] = {{post.pos[4 * i], post.pos[4 * i + 1], post.pos[4 * i + 2]}, i};
        std::sort(p.begin(), p.end());
        for (size_t k = 1; k < p.size(); ++k)
            if (p[k].first == p[k - 1].first) {
                o << "two particles at (" << p[k].first[0] << ", " << p[k].first[1] << ", " << p[k].first[2] << ")";
                // Where each came from names the mechanism (a wall's clamp, a collider's pocket).
                for (const uint32_t i : {p[k - 1].second, p[k].second}) {
                    o << "; id " << post.ids[i];
                    const auto was = before.find(post.ids[i]);
                    if (was == before.end()) {
                        o << " new this step";
                        continue;
                    }
                    const uint32_t j = was->second;
                    o << " from (" << pre.pos[4 * j] << ", " << pre.pos[4 * j + 1] << ", " << pre.pos[4 * j + 2]
                      << ") at (" << pre.vel[4 * j] << ", " << pre.vel[4 * j + 1] << ", " << pre.vel[4 * j + 2]
                      << ") m/s";
                }
                f = {"coincident", o.str()};
                return false;
            }
    }
    // ---- density error within the depth rule (dt 0: a step too short to simulate, nothing moved) ----
    if (dt > 0.0f) {
        const uint32_t substeps = std::max(st1.substeps, 1u);
        const double sub_dt = double(dt) / substeps, k = std::max(1.0, double(st1.iterations) / substeps);
        double lo = 1e30, hi_ = -1e30;
        for (uint32_t i = 0; i < post.n; ++i) {
            const double y = dot(d3(&post.pos[4 * i]), up());
            lo = std::min(lo, y);
            hi_ = std::max(hi_, y);
        }
        const double depth = post.n ? hi_ - lo + 2 * r_ : 0.0;
        const double depth_rule = 4.0 / (k + 0.5) * gmag() * depth * sub_dt * sub_dt / (h_ * h_);
        pbf_solver_params sp = pbf_solver_params_default();
        (void)pbf_world_get_solver_params(w_, &sp);
        // γ as the library damps errors (docs/physics.md, Error damping): τ/Δt, and where old
        // errors move positions (γ > 2) rising toward √(h/g)/Δt by the weight (1 - 2/γ)².
        double gamma = (h_ / sp.sound_speed) / sub_dt;
        if (gamma > 2.0 && gmag() > 0.0) {
            const double slow = std::sqrt(h_ / gmag()) / sub_dt, u = 1.0 - 2.0 / gamma;
            if (slow > gamma) gamma += u * u * (slow - gamma);
        }
        const double carried = prev_density_max_ * std::pow(1.0 + gamma, -double(substeps));
        // Adaptive iterations stop once the mean error is below the target: the error the user asked
        // to tolerate, with the same factor.
        const double bound = kDensityBase + kDepthRuleFactor * (depth_rule + sp.adaptive_error_target) + carried;
        if (st1.density_error_max > bound) {
            o << "density error max " << st1.density_error_max << " (mean " << st1.density_error_mean << ") > bound "
              << bound << " (0.5 + 2 x (depth rule " << depth_rule << " + adaptive target " << sp.adaptive_error_target
              << ") + carried " << carried << "; " << substeps << " substeps of " << sub_dt << " s, " << k
              << " iterations, depth " << depth << " m)";
            f = {"density", o.str()};
            return false;
        }
        prev_density_max_ = st1.density_error_max;
    }
    // ---- speed ----
    double v_post_max = 0;
    uint32_t fastest = 0;
    for (uint32_t i = 0; i < post.n; ++i) {
        const double v = norm(d3(&post.vel[4 * i]));
        if (v > v_post_max) v_post_max = v, fastest = i;
    }
    {
        const double free_fall = kFrontFactor * std::sqrt(2 * g * drop);
        const double bound =
            free_fall + 2 * coll_speed_max_ + emit_speed_max_ + kSpeedMargin + vort_speed_ + cohesion_speed_;
        if (v_post_max > bound) {
            const D3 x = d3(&post.pos[4 * fastest]);
            o << "particle id " << post.ids[fastest] << " at (" << x.x << ", " << x.y << ", " << x.z << ") moves at "
              << v_post_max << " m/s > bound " << bound << " (free fall over " << drop << " m x sqrt2: " << free_fall
              << ", 2 x collider " << coll_speed_max_ << ", emitters " << emit_speed_max_ << ", margin " << kSpeedMargin
              << ", vorticity " << vort_speed_ << ", cohesion " << cohesion_speed_ << "); fastest before the step "
              << v_pre_max << " m/s, " << st1.substeps << " substeps, " << st1.speed_clamps << " speed clamps";
            f = {"speed", o.str()};
            return false;
        }
    }
    const double eps = spec_.desc.solver.vorticity_epsilon, v_top = std::max(v_pre_max, v_post_max);
    const double omega_bound = kVorticityGradient * v_top / h_;
    // ---- energy ----
    const double m_post = total_mass(post);
    const double e_post = energy(post);
    if (energy_on_) {
        const D3 u = up();
        const double gm = gmag();
        double nozzle_top = -1e30;
        for (size_t k = 0; k < nozzles_.size(); ++k)
            if (nozzle_alive_[k] && nozzle_enabled_[k])
                nozzle_top = std::max(nozzle_top, dot(d3(nozzle_pos_[k]), u) + spec_.nozzles[k].radius +
                                                      spec_.nozzles[k].speed * double(dt));
        double fluid_top = -1e30;
        for (uint32_t i = 0; i < pre.n; ++i) fluid_top = std::max(fluid_top, dot(d3(&pre.pos[4 * i]), u));
        double in = work_in + overlap_in;
        for (uint32_t i :
             fresh) {  // a new particle: the nozzle's speed, at the disc's top or against the fluid above it
            const double m = mass(post, i);
            in += m * (0.5 * emit_speed_max_ * emit_speed_max_ + gm * std::max(nozzle_top, fluid_top));
        }
        double drain_floor = 1e30;
        for (size_t k = 0; k < drains_.size(); ++k)
            if (drain_alive_[k])
                for (int c = 0; c < 8; ++c) {
                    const D3 x{(c & 1) ? drain_hi_[k][0] : drain_lo_[k][0], (c & 2) ? drain_hi_[k][1] : drain_lo_[k][1],
                               (c & 4) ? drain_hi_[k][2] : drain_lo_[k][2]};
                    drain_floor = std::min(drain_floor, dot(x, u));
                }
        for (uint32_t i : vanished) in -= mass(pre, i) * gm * drain_floor;  // it left with at least its height's energy
        in += eps * omega_bound * v_top * m_post * dt;                      // what confinement could add at most
        budget_ += in;
        const double margin = m_post * (g_max_ * r_ + 0.5 * kRestSpeed * kRestSpeed);
        if (e_post > budget_ + margin) {
            o << "energy " << e_post << " J > budget " << budget_ << " + margin " << margin
              << " J (this step: collider work " << work_in << ", overlaps " << overlap_in << ", " << fresh.size()
              << " emitted, " << vanished.size() << " drained; fluid mass " << m_post << " kg, fastest " << v_post_max
              << " m/s)";
            f = {"energy", o.str()};
            return false;
        }
    }
    // ---- momentum in zero gravity without boundaries ----
    if (momentum_on_) {
        D3 p{}, l{};
        double sp = 0, sl = 0;
        for (uint32_t i = 0; i < post.n; ++i) {
            const double m = mass(post, i);
            const D3 x = d3(&post.pos[4 * i]) - c0_, v = d3(&post.vel[4 * i]);
            p = p + v * m;
            l = l + cross(x, v) * m;
            sp += m * norm(v);
            sl += m * norm(x) * norm(v);
            r_scale_ = std::max(r_scale_, norm(x));
        }
        p_scale_ = std::max(p_scale_, sp);
        l_scale_ = std::max(l_scale_, sl);
        momentum_allow_p_ += eps * omega_bound * m_post * dt;
        momentum_allow_l_ += eps * omega_bound * m_post * r_scale_ * dt;
        const double tol_p = kMomentumTolerance * p_scale_ + m_post * kMomentumFloorSpeed + momentum_allow_p_;
        const double tol_l =
            kMomentumTolerance * l_scale_ + m_post * r_scale_ * kMomentumFloorSpeed + momentum_allow_l_;
        if (norm(p - p0_) > tol_p || norm(l - l0_) > tol_l) {
            o << "|dP| " << norm(p - p0_) << " (tolerance " << tol_p << ", scale sum m|v| " << p_scale_ << "), |dL| "
              << norm(l - l0_) << " (tolerance " << tol_l << ", scale " << l_scale_ << ")";
            f = {"momentum", o.str()};
            return false;
        }
    }
    // The scene widens with where particles went (a later fall starts there), and confinement's
    // speed allowance grows with what it could add this step.
    for (uint32_t i = 0; i < post.n; ++i) grow(d3(&post.pos[4 * i]));
    vort_speed_ += eps * omega_bound * dt;
    e_post_ = e_post;
    return true;
}

RunResult Runner::run() {
    const auto start = std::chrono::steady_clock::now();
    const WorldSpec& s = spec_;
    Failure f;
    auto finish = [&](int frame) {
        if (!f.invariant.empty()) {
            res_.failed = true;
            res_.frame = frame;
            res_.invariant = f.invariant;
            res_.detail = f.detail;
            res_.setup_refused = f.invariant == "api";
        }
        if (w_.generation) pbf_world_destroy(w_);
        res_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return res_;
    };
    if (!ok(pbf_world_create(&s.desc, &w_), "pbf_world_create", f)) return finish(-1);
    pbf_world_info info{};
    info.struct_size = sizeof info;
    if (!ok(pbf_world_get_info(w_, &info), "pbf_world_get_info", f)) return finish(-1);
    r_ = s.desc.particle_radius;
    h_ = info.kernel_radius;
    volume_ = double(info.particle_mass) / s.desc.rest_density;
    g_ = {s.desc.gravity[0], s.desc.gravity[1], s.desc.gravity[2]};
    g_max_ = gmag();
    mats_.assign(s.materials.size(), pbf_material_id{0, 0});
    for (auto& m : mass_by_slot_) m = info.particle_mass;
    for (size_t k = 0; k < s.materials.size(); ++k) {
        if (!s.materials[k].on) continue;
        if (!ok(pbf_world_create_material(w_, &s.materials[k].desc, &mats_[k]), "pbf_world_create_material", f))
            return finish(-1);
        mass_by_slot_[mats_[k].index % PBF_MAX_MATERIALS] = double(s.materials[k].desc.rest_density) * volume_;
        const pbf_material_desc& d = s.materials[k].desc;
        // Surface forces store energy the API does not expose: the energy check is off, and a
        // particle may move at the speed of an oscillator of the forces' stiffness over h.
        if (d.surface_tension > 0 || d.cohesion > 0 || d.adhesion > 0) {
            energy_on_ = false;
            cohesion_speed_ =
                std::max(cohesion_speed_, h_ * std::sqrt(40.0 * (d.surface_tension + d.cohesion) + 6.0 * d.adhesion));
        }
    }
    colliders_.assign(s.colliders.size(), Live{});
    nozzles_.assign(s.nozzles.size(), pbf_emitter_id{0, 0});
    drains_.assign(s.drains.size(), pbf_emitter_id{0, 0});
    nozzle_alive_.assign(s.nozzles.size(), false);
    nozzle_enabled_.assign(s.nozzles.size(), false);
    drain_alive_.assign(s.drains.size(), false);
    nozzle_pos_.assign(s.nozzles.size(), V3{});
    drain_lo_.assign(s.drains.size(), V3{});
    drain_hi_.assign(s.drains.size(), V3{});
    if (s.desc.walls) {
        grow(d3(s.desc.domain_min));
        // The walls' top is not a height fluid falls from; the floor is where it lands.
        grow(D3{s.desc.domain_max[0], s.desc.domain_min[1], s.desc.domain_max[2]});
    }
    // Momentum is checked where nothing outside the fluid acts: zero gravity, no walls, colliders,
    // nozzles or drains, and every block emitted before the first step.
    bool isolated = g_max_ == 0 && s.gravity_frame < 0 && !s.desc.walls;
    for (const auto& c : s.colliders) isolated = isolated && !c.on;
    for (const auto& n : s.nozzles) isolated = isolated && !n.on;
    for (const auto& d : s.drains) isolated = isolated && !d.on;
    for (const auto& b : s.blocks) isolated = isolated && (!b.on || b.frame == 0);
    momentum_on_ = isolated;
    res_.energy_checked = energy_on_;
    res_.momentum_checked = momentum_on_;

    State pre;
    for (int frame = 0; frame < int(s.dts.size()); ++frame) {
        const float dt = s.dts[size_t(frame)];
        std::vector<size_t> appeared;
        bool particles_changed = false;
        if (!events(frame, dt, appeared, particles_changed, f)) return finish(frame);
        // Kinematic targets (the path at the step's end) and engine-integrated bodies.
        double coll_speed = 0;
        std::vector<std::pair<D3, D3>> motion(s.colliders.size());  // displacement, rotation vector
        std::vector<std::pair<V3, Q4>> held(s.colliders.size());    // where the world has each, for a carried step
        for (size_t k = 0; k < s.colliders.size(); ++k) held[k] = {colliders_[k].pos, colliders_[k].rot};
        for (size_t k = 0; k < s.colliders.size(); ++k) {
            const ColliderSpec& c = s.colliders[k];
            Live& l = colliders_[k];
            if (!c.on || !l.alive || !c.kinematic || frame == c.teleport_frame || frame == c.create_frame) continue;
            V3 target = l.pos;
            Q4 rot = l.rot;
            if (c.body) {
                pbf_collider_force cf{};
                if (!ok(pbf_collider_get_force(w_, l.id, &cf), "pbf_collider_get_force", f)) return finish(frame);
                const D3 a = d3(cf.force) * (1.0 / l.body_mass) + d3(g_);
                l.body_velocity = l.body_velocity + a * double(dt);
                const double vmax = 20.0;  // an engine's body speed cap
                if (norm(l.body_velocity) > vmax) l.body_velocity = l.body_velocity * (vmax / norm(l.body_velocity));
                for (int ax = 0; ax < 3; ++ax) {
                    const double reach = collider_reach(c);
                    const double lo = s.desc.domain_min[ax] - reach, hi = s.desc.domain_max[ax] + reach;
                    double x = l.pos[ax] + (&l.body_velocity.x)[ax] * dt;
                    if (x < lo || x > hi) x = std::clamp(x, lo, hi), (&l.body_velocity.x)[ax] = 0;  // it hit the level
                    target[ax] = float(x);
                }
            } else {
                target = path_pos(c, l, time_ + dt);
                rot = path_rot(c, time_ + dt);
            }
            const D3 dx = d3(target) - d3(l.pos), dtheta = rotation_between(l.rot, rot);
            motion[k] = {dx, dtheta};
            const double reach = c.shape == PBF_SHAPE_PLANE ? 0.0 : collider_reach(c);
            coll_speed = std::max(coll_speed, (norm(dx) + norm(dtheta) * reach) / (dt + carried_));
            if (!ok(pbf_collider_set_target_pose(w_, l.id, target.data(), rot.data()), "pbf_collider_set_target_pose",
                    f))
                return finish(frame);
            l.pos = target;
            l.rot = rot;
            if (c.shape != PBF_SHAPE_PLANE) {
                grow_around(d3(target), reach);
            }
        }
        coll_speed_max_ = std::max(coll_speed_max_, coll_speed);

        if (!read(pre, f)) return finish(frame);
        pbf_step_stats st0{};
        st0.struct_size = sizeof st0;
        if (!ok(pbf_world_get_stats(w_, &st0), "pbf_world_get_stats", f)) return finish(frame);
        st0.particle_count = pre.n;
        const double e_pre = energy(pre);
        if (frame == 0) {
            budget_ = e_pre;
            for (uint32_t i = 0; i < pre.n; ++i) grow(d3(&pre.pos[4 * i]));
            // The momentum reference: the fluid as emitted.
            D3 p{}, l{}, c{};
            double m = 0;
            for (uint32_t i = 0; i < pre.n; ++i) {
                const double mi = mass(pre, i);
                c = c + d3(&pre.pos[4 * i]) * mi;
                m += mi;
            }
            c0_ = m > 0 ? c * (1.0 / m) : D3{};
            for (uint32_t i = 0; i < pre.n; ++i) {
                const double mi = mass(pre, i);
                p = p + d3(&pre.vel[4 * i]) * mi;
                l = l + cross(d3(&pre.pos[4 * i]) - c0_, d3(&pre.vel[4 * i])) * mi;
            }
            p0_ = p;
            l0_ = l;
        } else if (particles_changed) {
            budget_ += e_pre - e_post_;  // blocks emitted and gravity changes: exactly what the state shows
        }
        res_.peak_particles = std::max(res_.peak_particles, pre.n);
        // Overlaps no motion made: new colliders and teleports into fluid, blocks into colliders
        // or onto fluid.
        double overlap_in = 0;
        if (energy_on_ && pre.n) {
            if (!appeared.empty()) overlap_in += overlap_allowance(pre, std::vector<char>(pre.n, 1), appeared, false);
            if (particles_changed && have_post_) {
                std::unordered_set<uint32_t> old(post_.ids.begin(), post_.ids.end());
                std::vector<char> fresh(pre.n, 0);
                bool any = false;
                for (uint32_t i = 0; i < pre.n; ++i) any |= (fresh[i] = old.count(pre.ids[i]) ? 0 : 1) != 0;
                if (any) {
                    std::vector<size_t> all;
                    for (size_t k = 0; k < colliders_.size(); ++k)
                        if (colliders_[k].alive) all.push_back(k);
                    overlap_in += overlap_allowance(pre, fresh, all, true);
                }
            }
        }
        double v_pre_max = 0;
        for (uint32_t i = 0; i < pre.n; ++i) v_pre_max = std::max(v_pre_max, norm(d3(&pre.vel[4 * i])));

        if (!ok(pbf_world_step(w_, dt), "pbf_world_step", f)) return finish(frame);
        time_ += dt;
        res_.frames_run = frame + 1;
        if (!read(post_, f)) return finish(frame);
        have_post_ = true;
        pbf_step_stats st1{};
        st1.struct_size = sizeof st1;
        if (!ok(pbf_world_get_stats(w_, &st1), "pbf_world_get_stats", f)) return finish(frame);
        const bool carried = st1.simulated_dt == 0.0f;
        if (carried) {
            // Nothing advanced: the kinematic colliders are where they were (teleports and new
            // ones are where they were put, their overlaps settled by the step that simulates).
            carried_ += dt;
            for (size_t k = 0; k < s.colliders.size(); ++k) {
                const ColliderSpec& c = s.colliders[k];
                if (c.on && colliders_[k].alive && c.kinematic && frame != c.teleport_frame && frame != c.create_frame)
                    std::tie(colliders_[k].pos, colliders_[k].rot) = held[k];
            }
            if (!check_step(frame, 0.0f, pre, st0, st1, 0.0, overlap_in, v_pre_max, f)) return finish(frame);
            continue;
        }
        const float simulated = float(dt + carried_);  // the step simulated the carried time too
        carried_ = 0;
        // The work moving colliders did on the fluid: minus the fluid's mean force on them times
        // their displacement, and its torque times their rotation.
        double work_in = 0;
        for (size_t k = 0; k < s.colliders.size(); ++k) {
            const ColliderSpec& c = s.colliders[k];
            if (!c.on || !colliders_[k].alive || !c.dynamic) continue;
            pbf_collider_force cf{};
            if (!ok(pbf_collider_get_force(w_, colliders_[k].id, &cf), "pbf_collider_get_force", f))
                return finish(frame);
            work_in -= dot(d3(cf.force), motion[k].first) + dot(d3(cf.torque), motion[k].second);
        }
        work_in *= double(dt) / simulated;  // the force is the impulse over this step's dt; the motion, over both
        if (!check_step(frame, simulated, pre, st0, st1, work_in, overlap_in, v_pre_max, f)) return finish(frame);
    }
    return finish(-1);
}

}  // namespace

RunResult run_world(const WorldSpec& spec) { return Runner(spec).run(); }

}  // namespace fuzz
