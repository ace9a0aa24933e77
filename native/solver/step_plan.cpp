#include "step_plan.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <string>

#include "../core/collide.h"
#include "../core/grid.h"
#include "../core/lattice.h"
#include "../core/limits.h"
#include "../core/material_ops.h"
#include "../core/passes.h"
#include "../core/sph.h"

namespace pbf {

// The core's shape codes are the public ones, so the world passes a shape through a cast.
constexpr bool same_code(ColliderShape core, pbf_collider_shape api) { return uint32_t(core) == uint32_t(api); }
static_assert(same_code(kShapePlane, PBF_SHAPE_PLANE) && same_code(kShapeSphere, PBF_SHAPE_SPHERE) &&
                  same_code(kShapeCapsule, PBF_SHAPE_CAPSULE) && same_code(kShapeBox, PBF_SHAPE_BOX) &&
                  same_code(kShapeMesh, PBF_SHAPE_MESH),
              "core/params.h ColliderShape mirrors pbf_collider_shape");

namespace {

Vec3 to_vec3(const float v[3]) { return Vec3{v[0], v[1], v[2]}; }

Eigen::Quaternionf to_quat(const Quat& q) { return Eigen::Quaternionf(q.w, q.x, q.y, q.z).normalized(); }

// Open levels hold particle centres within |x| <= 2^17·h per axis: there float spacing is h/64,
// still fine against the kernel (a particle reaching it stops as at a wall without density).
float open_limit(float h) { return std::ldexp(h, 17); }

MaterialConstants material_constants(float rest_density, const MaterialTable& table) {
    MaterialConstants m{};
    for (uint32_t k = 0; k < kMaxMaterials; ++k) {
        m.inv_mass[k] = 1.0f;
        if (!table.alive[k]) continue;
        const pbf_material_desc& d = table.desc[k];
        if (d.rest_density != rest_density) {
            m.inv_mass[k] = rest_density / d.rest_density;
            m.flags |= kMaterialMultiphase;
        }
        m.surface_tension[k] = d.surface_tension;
        m.cohesion[k] = d.cohesion;
        m.adhesion[k] = d.adhesion;
        if (d.surface_tension > 0.0f || d.cohesion > 0.0f || d.adhesion > 0.0f) m.flags |= kMaterialSurface;
    }
    return m;
}

// The depth rule's substeps per second. A fixed number of Jacobi iterations per substep is a
// spring of finite stiffness: a column of depth H at rest settles with its bottom compressed by
// about C = κ(k) · g · H · Δt² / h² (k iterations; measured on a resting column 16 x 100 x 4
// particles, h = 8 mm, and 50 layers deep: C ∝ H and ∝ Δt², κ = 2.38, 1.38, 1.04, 0.83 for
// k = 1..4 with LDC, 1.98 and 1.07 for k = 2, 4 without; fitted as κ = 4 / (k + ½), at the
// default relaxation). The substeps keep C at or under kBottomCompression. Above it a 100-layer
// tank sank ~10 % of its depth at 7 substeps and rebounded; the speed of that rebound raised the
// substeps, which stiffened the compressed column and turned its compression into energy (KE +
// ΔPE up to 0.2-0.4 M g a, the frame benchmark's "energy gain" at 1M particles). The depth is the
// particles' extent along gravity (the last finished step's, or a block emitted since): fluid in
// the air counts as deep, which costs substeps, never stability.
constexpr double kBottomCompression = 0.1;
double frame_depth(const FrameState& frame) { return std::fmax(frame.feedback.fluid_depth, frame.emitted_depth); }
double depth_kappa(uint32_t iterations) { return 4.0 / (double(iterations) + 0.5); }
double depth_substep_rate(uint32_t iterations, float h, double g, double depth) {
    return std::sqrt(depth_kappa(iterations) * g * depth / kBottomCompression) / h;
}

// The iterations automatic substeps are planned for (docs/physics.md, Iterations): two, the
// cheapest that hold (one leaves a Jacobi sweep's overshoot uncorrected; a third or fourth lowers
// the depth rule's substep rate by sqrt(κ(2) / κ(k)) for a substep that costs more than that,
// its fixed passes costing about two iterations). `iterations` itself with fixed substeps; with
// adaptive iterations, whose target asks for however many it takes; and with a collider that
// moves or a mesh collider, whose contacts two iterations left half resolved (spray thrown
// faster than a rigid wall can throw it, water sunk into a mesh box's approximate field). Walls
// and resting analytic shapes hold at two, and alike: a puddle held by planes settles as in a
// walled box.
constexpr uint32_t kAutoIterations = 2;
bool contacts_need_iterations(const StepInput& input) {
    for (size_t k = 0; k < input.collider_keys.size(); ++k) {
        const ColliderKey& key = input.collider_keys[k];
        const Quat &a = key.from_rotation, &b = key.to_rotation;
        if (input.collider_shapes[k].shape == kShapeMesh || length_sq(key.to_position - key.from_position) > 0.0f ||
            a.x != b.x || a.y != b.y || a.z != b.z || a.w != b.w)
            return true;
    }
    return false;
}
uint32_t preferred_iterations(const pbf_solver_params& p, const StepInput& input) {
    if (p.substeps > 0 || p.adaptive_error_target > 0.0f || contacts_need_iterations(input)) return p.iterations;
    return std::min(p.iterations, kAutoIterations);
}

// The fastest motion expected over a frame step, before gravity adds to it: the latest finished
// step's fastest particle (read without waiting), particles emitted since, the nozzles, and the
// kinematic colliders' surface speed.
float expected_speed(const FrameState& frame, const std::vector<EmitterState>& emitters, const StepInput& input) {
    const float dt = frame.frame_dt;
    float v = std::fmax(frame.feedback.max_speed, frame.emitted_speed);
    for (const EmitterState& e : emitters)
        if (e.desc.enabled && e.desc.type == PBF_EMITTER_NOZZLE) v = std::fmax(v, e.desc.speed);
    for (size_t k = 0; k < input.collider_keys.size(); ++k) {
        const ColliderKey& key = input.collider_keys[k];
        const float reach = collider_reach(input.collider_shapes[k]);  // a plane: 0, its translation only
        const float angle = to_quat(key.from_rotation).angularDistance(to_quat(key.to_rotation));
        v = std::fmax(v, (length(key.to_position - key.from_position) + angle * reach) / dt);
    }
    return v;
}

// Substeps for a frame step: fixed, or from the fastest motion expected over it plus what
// gravity adds over the frame, and at least enough that gravity alone moves a resting particle
// little per substep.
uint32_t substep_count(const pbf_solver_params& p, const WorldConstants& c, const FrameState& frame,
                       const std::vector<EmitterState>& emitters, const StepInput& input) {
    if (p.substeps > 0) return p.substeps;
    const float dt = frame.frame_dt;
    const double g = length(c.gravity);
    const float v = expected_speed(frame, emitters, input) + float(g) * dt;
    const double travel = double(p.substep_travel) * c.h;
    double n = std::ceil(double(v) * dt / travel);
    // Fluid at rest: gravity moves every particle g·Δt² per substep and the iterations must
    // carry that to the floor. Shallow fluid compressed unless g·Δt² stays under travel / 64
    // (measured on the frame benchmark's tank); deep fluid by the depth rule below.
    if (g > 0.0) n = std::max(n, std::ceil(dt * std::sqrt(64.0 * g / travel) - 1e-6));
    const double depth = frame_depth(frame);
    if (g > 0.0 && depth > 0.0)
        n = std::max(n, std::ceil(dt * depth_substep_rate(preferred_iterations(p, input), c.h, g, depth) - 1e-6));
    // Surface tension, cohesion and adhesion are explicit forces: Δt within their stability caps.
    n = std::max(n, std::ceil(double(dt) * surface_substep_rate(c.materials) - 1e-6));
    return static_cast<uint32_t>(std::clamp(n, 1.0, double(p.max_substeps)));
}

// Iterations per substep: preferred_iterations, unless the substep cap left the depth rule unmet
// (a column deeper than max_substeps can hold at two iterations, or a frame step long enough to
// be capped): then the fewest iterations, up to `iterations`, whose κ meets it at the substeps
// the cap allows, since iterations are what still stiffen a column when substeps cannot.
uint32_t iteration_count(const pbf_solver_params& p, const WorldConstants& c, const FrameState& frame,
                         const StepInput& input, uint32_t substeps) {
    const uint32_t k = preferred_iterations(p, input);
    if (p.substeps > 0 || k == p.iterations) return k;
    const double g = length(c.gravity);
    const double depth = frame_depth(frame);
    const double sub_dt = double(frame.frame_dt) / substeps;
    if (!(g > 0.0 && depth > 0.0 && sub_dt > 0.0)) return k;
    // C = κ(k) g H Δt² / h² <= kBottomCompression  <=>  κ(k) <= κ_max  <=>  k >= 4 / κ_max - 1/2.
    const double kappa_max = kBottomCompression * double(c.h) * c.h / (g * depth * sub_dt * sub_dt);
    if (depth_kappa(k) <= kappa_max) return k;
    const double needed = std::ceil(4.0 / kappa_max - 0.5 - 1e-9);
    return static_cast<uint32_t>(std::clamp(needed, double(k), double(p.iterations)));
}

// No particle may move more than h in a substep: beyond that a few iterations cannot resolve
// the compression it creates (the substep's speed limit, h/Δt, holds every particle to it).
constexpr float kTravelCap = 1.0f;

// The longest substep the physics holds (docs/physics.md, Capped frames). Automatic substeps
// meet their rules by their count, up to max_substeps; a frame step longer than the cap's
// substeps hold would run substeps that break rules the solver cannot trade for cost, and its
// harm outlasts the frame: a pool crushed by gravity over long substeps (the depth rule's C
// grows as Δt²) was in equilibrium only at that Δt, and the next frame's short substeps released
// the compression as a fling; free flight faster than h/Δt was cut by the speed limit (momentum
// lost). So the substep is held to:
// - travel: the fastest expected particle, gaining g·t, crosses at most kHeldTravel h per
//   substep over the S substeps, (v + g S Δt) Δt <= kHeldTravel h: within the speed limit's reach
//   (h/Δt) with a third of its speed to spare for what the step adds (a drop's own pressure
//   pushes its surface outward). Not substep_travel, which asks for accuracy, not for the
//   physics to hold: a fast dam break that wants more substeps than the cap loses no momentum;
// - with automatic substeps, the depth rule at the step's iterations (raised first, up to the
//   cap, by iteration_count). Fixed substeps keep the compression the user's count gives, which
//   the depth rule documents.
// The surface forces' cap is no such rule: past it their coefficients are capped per substep
// (material_ops.h), weaker, not unstable.
constexpr double kHeldTravel = 0.75 * kTravelCap;
// The longest frame step never held back: two frames of 60 Hz (a game at 30 Hz runs whole).
constexpr float kHitchDt = 1.0f / 30.0f;  // float, as dt comes: a dt of 1.0f / 30 runs whole
double held_substep(const pbf_solver_params& p, const WorldConstants& c, const FrameState& frame, float speed,
                    uint32_t substeps, uint32_t iterations) {
    const double g = length(c.gravity), v = speed, s = substeps;
    const double reach = std::fmax(kHeldTravel, double(p.substep_travel)) * c.h;  // never below what the count asks
    double held = HUGE_VAL;
    if (g > 0.0)
        held = 2.0 * reach / (v + std::sqrt(v * v + 4.0 * g * s * reach));  // the root of g S Δt² + v Δt = reach
    else if (v > 0.0)
        held = reach / v;
    const double depth = frame_depth(frame);
    if (p.substeps == 0 && g > 0.0 && depth > 0.0)
        held = std::fmin(held, 1.0 / depth_substep_rate(iterations, c.h, g, depth));
    return held;
}

// A collider's path over the simulated part of a frame step: the last `fraction` of the way to
// its end pose (rotation by slerp), at the speed the whole step gives it.
ColliderKey path_end(const ColliderKey& key, float fraction) {
    ColliderKey cut = key;
    cut.from_position = key.to_position + (key.from_position - key.to_position) * fraction;
    const Eigen::Quaternionf q = to_quat(key.to_rotation).slerp(fraction, to_quat(key.from_rotation));
    cut.from_rotation = Quat{q.x(), q.y(), q.z(), q.w()};
    return cut;
}

bool moves(const ColliderKey& key) {
    const Quat &a = key.from_rotation, &b = key.to_rotation;
    return length_sq(key.to_position - key.from_position) > 0.0f || a.x != b.x || a.y != b.y || a.z != b.z ||
           a.w != b.w;
}

// A nozzle's emission in one substep of sub_dt: whole particles from its accumulator, on its
// disc's spiral.
NozzleEmission nozzle_emission(EmitterState& e, const WorldConstants& c, float sub_dt) {
    const float spacing = 2.0f * c.radius;
    e.accumulator += e.desc.particles_per_second * sub_dt;
    const float whole = std::floor(e.accumulator);
    e.accumulator -= whole;
    const uint32_t n = static_cast<uint32_t>(std::min(whole, float(c.capacity)));
    const Vec3 dir = to_vec3(e.desc.direction);
    // Any unit vector not parallel to dir, then an orthonormal frame around dir.
    const Vec3 helper = std::fabs(dir.y) < 0.9f ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
    const Vec3 t = cross(dir, helper) * (1.0f / length(cross(dir, helper)));
    const Vec3 b = cross(dir, t);
    // Clamped before the conversion: a huge (finite) radius makes this Inf.
    const float area_points = std::fmin(kPi * e.desc.radius * e.desc.radius / (spacing * spacing), 4.0e9f);
    NozzleEmission ne{n,
                      e.sequence,
                      std::max(1u, static_cast<uint32_t>(area_points)),
                      to_vec3(e.desc.position),
                      dir,
                      t,
                      b,
                      e.desc.radius,
                      e.desc.speed,
                      e.material};
    e.sequence += n;
    return ne;
}

// What a world's particle radius and rest density fix for its life: the kernel radius and the
// rest lattice's calibration.
struct FluidScales {
    float h = 0.0f;                    // kernel radius: 4 particle radii
    float mass = 0.0f;                 // a particle's mass: a rest lattice has rest density
    float rest_gradient_norm2 = 0.0f;  // Σ_k |∇_k C|² of a particle at rest density
    float boundary_scale = 0.0f;       // γ of the walls' density
    float box_edge_scale = 0.0f;       // κ of a box collider's edges
};

FluidScales fluid_scales(float radius, float rest_density) {
    FluidScales s;
    s.h = 4.0f * radius;
    const float spacing = 2.0f * radius;
    const LatticeCalibration cal = calibrate_lattice(spacing, s.h);
    s.mass = static_cast<float>(rest_density / cal.kernel_sum);
    // |∇_k C|² of a rest particle, with ∇C = (m/ρ0) ∇W.
    const double m_over_rho = 1.0 / cal.kernel_sum;
    s.rest_gradient_norm2 = static_cast<float>(cal.gradient_norm2 * m_over_rho * m_over_rho);
    s.boundary_scale = boundary_lattice_scale(spacing, s.h);
    s.box_edge_scale = box_edge_scale(spacing, s.h, s.boundary_scale);
    return s;
}

// Dense over the domain box while its cells are at most 4 per key of the hashed grid the
// capacity would get (at most 16 B of cell table per particle) and at most 2^30; hashed
// otherwise (a level-sized box), and always without walls or when the desc asks (grid.h).
GridDims choose_grid(const pbf_world_desc& desc, float h) {
    const uint32_t bits = hashed_grid_bits(desc.max_particles);
    const float inv_cell = 1.0f / h;
    if (!desc.walls) return hashed_grid(Vec3{0.0f, 0.0f, 0.0f}, inv_cell, bits);
    const double cells[3] = {std::max(1.0, double(std::ceil((desc.domain_max[0] - desc.domain_min[0]) / h))),
                             std::max(1.0, double(std::ceil((desc.domain_max[1] - desc.domain_min[1]) / h))),
                             std::max(1.0, double(std::ceil((desc.domain_max[2] - desc.domain_min[2]) / h)))};
    const Vec3 origin = to_vec3(desc.domain_min);
    const double dense_limit = std::min(4.0 * double(uint64_t(1) << bits), double(1u << 30));
    if (desc.hashed_grid || cells[0] * cells[1] * cells[2] > dense_limit) return hashed_grid(origin, inv_cell, bits);
    return dense_grid(origin, inv_cell, int32_t(cells[0]), int32_t(cells[1]), int32_t(cells[2]));
}

}  // namespace

Status check_fluid(float radius, float rest_density) {
    const FluidScales s = fluid_scales(radius, rest_density);
    // Every constant the kernels use must be a normal float: a radius or rest density so extreme
    // that one over- or underflows (a denormal rest density, a radius of 1e20 m) would make every
    // density and velocity NaN.
    const float coef6 = poly6_coefficient(s.h), coef_grad = spiky_grad_coefficient(s.h);
    const double quantities[] = {s.mass,
                                 s.rest_gradient_norm2,
                                 coef6,
                                 coef_grad,
                                 s.h * s.h,
                                 poly6(0.0f, s.h * s.h, coef6),
                                 s.mass * poly6(0.0f, s.h * s.h, coef6),
                                 1.0f / rest_density};
    for (double q : quantities) {
        if (!(std::isfinite(q) && q >= double(FLT_MIN) && q <= double(FLT_MAX))) {
            char text[96];
            std::snprintf(text, sizeof text, "particle_radius %g and rest_density %g", radius, rest_density);
            return Status::error(PBF_ERROR_INVALID_ARGUMENT,
                                 std::string(text) + " give SPH constants outside the range of float");
        }
    }
    return Status{};
}

WorldConstants derive_constants(const pbf_world_desc& desc, const MaterialTable& materials) {
    const FluidScales scales = fluid_scales(desc.particle_radius, desc.rest_density);
    const pbf_solver_params& p = desc.solver;
    const float h = scales.h;
    WorldConstants s{};
    s.radius = desc.particle_radius;
    s.h = h;
    s.h2 = h * h;
    s.mass = scales.mass;
    s.rest_density = desc.rest_density;
    s.inv_rest_density = 1.0f / desc.rest_density;
    s.poly6_coef = poly6_coefficient(h);
    s.spiky_coef = spiky_grad_coefficient(h);
    s.rest_gradient_norm2 = scales.rest_gradient_norm2;
    s.relaxation = p.relaxation;
    const float dq = p.scorr_dq * h;
    // s_corr enters beside λ_i + λ_j. Macklin & Müller's k = 0.1 presumes their units; here
    // k·(W/W(Δq))^n is read as a density-ratio error and converted to λ's units by the rest
    // gradient norm, so the same k behaves the same at any particle size.
    s.scorr_k = p.scorr_k / (scales.rest_gradient_norm2 * (1.0f + p.relaxation));
    s.scorr_n = p.scorr_n;
    s.scorr_inv_w_dq = 1.0f / poly6(dq * dq, s.h2, s.poly6_coef);
    // s_corr's shape (core/sph.h, scorr_weight): its weight at the rest spacing, against the
    // reference shape's there (Macklin & Müller's Δq = 0.2 h, n = 4: 0.052), each computed as
    // the pass computes it, so that the defaults have no excess at all.
    const float w_rest = poly6(4.0f * s.radius * s.radius, s.h2, s.poly6_coef);
    const float dq_ref = kScorrReferenceDq * h;
    const float inv_w_dq_ref = 1.0f / poly6(dq_ref * dq_ref, s.h2, s.poly6_coef);
    const ScorrShape shape =
        scorr_shape(std::fmin(scorr_power(w_rest * s.scorr_inv_w_dq, s.scorr_n), kScorrPowerCap),
                    std::fmin(scorr_power(w_rest * inv_w_dq_ref, kScorrReferenceN), kScorrPowerCap));
    s.scorr_a = shape.a;
    s.scorr_b = shape.b;
    s.scorr_k *= shape.scale;
    s.scorr_rest_weight = scorr_weight(w_rest * s.scorr_inv_w_dq, s.scorr_n, s.scorr_a, s.scorr_b);
    s.scorr_ref_inv_w_dq = inv_w_dq_ref;
    s.scorr_bounded = p.scorr_k > 0.0f && !(p.scorr_k <= kScorrReferenceK && p.scorr_n == kScorrReferenceN &&
                                            p.scorr_dq == kScorrReferenceDq);
    s.scorr_ref_k = kScorrReferenceK / (scales.rest_gradient_norm2 * (1.0f + p.relaxation));
    s.vorticity_epsilon = p.vorticity_epsilon;
    s.max_speed = p.max_speed;
    s.ldc_enabled = p.ldc_enabled;
    s.adaptive_target = p.adaptive_error_target;
    s.gravity = to_vec3(desc.gravity);
    const Vec3 r{s.radius, s.radius, s.radius};
    if (desc.walls) {
        s.boundary_min = to_vec3(desc.domain_min);
        s.boundary_max = to_vec3(desc.domain_max);
        s.wall_min = s.boundary_min + r;
        s.wall_max = s.boundary_max - r;
    } else {
        // An open level: no solid anywhere near a particle, only the open limit box.
        const float limit = open_limit(h);
        s.boundary_min = Vec3{-FLT_MAX, -FLT_MAX, -FLT_MAX};
        s.boundary_max = Vec3{FLT_MAX, FLT_MAX, FLT_MAX};
        s.wall_min = Vec3{-limit, -limit, -limit};
        s.wall_max = Vec3{limit, limit, limit};
    }
    s.boundary_scale = scales.boundary_scale;
    s.box_edge_scale = scales.box_edge_scale;
    s.grid = choose_grid(desc, h);
    s.capacity = desc.max_particles;
    s.materials = material_constants(desc.rest_density, materials);
    return s;
}

RenderConstants render_constants(const pbf_render_params& p, float radius, float h) {
    RenderConstants r;
    r.flags = p.flags & (kRenderSmoothed | kRenderAnisotropy);
    r.min_neighbors = p.min_neighbors;
    r.smoothing = p.smoothing;
    r.max_stretch = p.max_stretch;
    // Yu & Turk scale the covariance by a constant k_s; here k_s is the radius (in particle radii)
    // of a particle whose neighbourhood is a rest lattice, so the same value suits any radius.
    r.radius_per_variance = static_cast<float>(p.scale * radius / rest_render_variance(2.0f * radius, h));
    r.isolated_radius = p.isolated_scale * radius;
    return r;
}

DiffuseConstants diffuse_constants(const pbf_diffuse_params& p) {
    DiffuseConstants d;
    d.capacity = p.max_diffuse;
    d.trapped_air_min = p.trapped_air_min;
    d.trapped_air_max = p.trapped_air_max;
    d.wave_crest_min = p.wave_crest_min;
    d.wave_crest_max = p.wave_crest_max;
    d.energy_min = p.energy_min;
    d.energy_max = p.energy_max;
    d.trapped_air_rate = p.trapped_air_rate;
    d.wave_crest_rate = p.wave_crest_rate;
    d.lifetime = p.lifetime;
    d.spray_max_neighbors = p.spray_max_neighbors;
    d.bubble_min_neighbors = p.bubble_min_neighbors;
    d.buoyancy = p.buoyancy;
    d.bubble_drag = p.bubble_drag;
    d.spray_drag = p.spray_drag;
    return d;
}

float xsph_factor(float c, float sub_dt) { return c >= 1.0f ? 1.0f : 1.0f - std::pow(1.0f - c, 60.0f * sub_dt); }

// The compression a resting fluid carries its weight with grows with the substep length (C ∝ H
// Δt², see above), so a game that steps a settled pool in short steps meets it as an old error.
// Released over τ, the part of it still converted into velocity (about 4Δt/τ, an acceleration of
// about 4 C h / τ² per layer) lifted the whole pool (a 0.3 m pool stepped 0.1 s at 1e-4 s: its
// centre of mass 6.7 cm higher); released over √(h/g), gravity's time at the kernel's scale, no
// faster than gravity made it. Blended in by the weight old errors move positions by, so γ ≤ 2
// is unchanged and the rise has no step.
float error_damping(float tau, float h, float gravity, float sub_dt) {
    const float gamma = tau / sub_dt;
    if (!(gamma > 2.0f) || !(gravity > 0.0f)) return gamma;
    const float slow = std::sqrt(h / gravity) / sub_dt;
    return slow > gamma ? gamma + old_error_weight(gamma) * (slow - gamma) : gamma;
}

StepContext substep_context(const pbf_solver_params& p, const WorldConstants& s, const MaterialTable& materials,
                            float sub_dt) {
    StepContext c{};
    c.dt = sub_dt;
    c.inv_dt = 1.0f / sub_dt;
    c.lambda_epsilon = s.rest_gradient_norm2 * p.relaxation;
    // The response time τ = h / sound_speed: errors older than the substep relax over τ (the λ
    // pass's error damping, γ = τ/Δt; longer where old errors move positions, error_damping),
    // and LDC's K = gain / Δt² takes τ as a floor of Δt, so neither turns an error into a
    // velocity larger than about error · sound_speed.
    const float tau = s.h / p.sound_speed;
    c.error_damping = std::fmin(error_damping(tau, s.h, length(s.gravity), sub_dt), 1e6f);
    c.positional_weight = old_error_weight(c.error_damping);
    c.ldc_k = p.ldc_gain / (sub_dt * sub_dt + tau * tau);
    // s_corr answers an arrangement (clumping) that persists, so it pushes again every substep:
    // k/(1 + γ) while Δt ≥ τ (γ ≤ 1), then k/(2γ²), an acceleration of about k/(2τ²) as Δt → 0,
    // bounded whatever the substep count (k/(1 + γ) alone grew as 1/Δt: 12.7 m/s from an
    // emitted block at 1e-5 s, and a pool at 16 fixed substeps expanded 6 %). The two meet at
    // γ = 1; k/(1 + γ)² everywhere weakened s_corr at the default substeps (γ ≈ 0.3-0.6) and
    // raised the light fluid's largest density error in the two-fluid test on the H100.
    // Its time scale is τ, but no shorter than h / kScorrResponseSpeed: a stiffer density
    // response does not make s_corr a displacement repeated at full strength every substep, whose
    // push per second grew as 1/Δt² (at sound_speed 300 and 43 substeps per 1/60 s, a slab at
    // rest in zero gravity left at 2.4 m/s within the frame).
    const float g = std::fmin(std::fmax(tau, s.h / kScorrResponseSpeed) / sub_dt, 1e6f);
    const float scorr_relax = std::fmin(1.0f / (1.0f + g), 0.5f / (g * g));
    c.scorr_k = s.scorr_k * scorr_relax;
    c.scorr_ref_k = s.scorr_ref_k * scorr_relax;
    c.scorr_gap_push = 0.5f * scorr_relax / (s.mass * s.inv_rest_density);
    // XSPH's c is per 1/60 s: a substep of Δt applies 1 - (1 - c)^(60 Δt), so the smoothing per
    // second does not depend on the substep count.
    c.xsph_c = xsph_factor(p.xsph_c, sub_dt);
    // No particle may move more than h in a substep (kTravelCap).
    c.speed_limit = std::fmin(p.max_speed, kTravelCap * s.h / sub_dt);
    // Each material's XSPH factor and LDC K (slot 0's are the solver parameters').
    for (uint32_t k = 0; k < kMaxMaterials; ++k) {
        const bool alive = materials.alive[k];
        const pbf_material_desc& d = materials.desc[k];
        c.material_xsph_c[k] = alive ? xsph_factor(d.viscosity, sub_dt) : 0.0f;
        c.material_ldc_k[k] = alive ? d.ldc_gain / (sub_dt * sub_dt + tau * tau) : 0.0f;
    }
    return c;
}

void plan_step(const pbf_solver_params& p, const WorldConstants& c, const MaterialTable& materials,
               const FrameState& carried_to, std::vector<EmitterState>* emitters, StepInput* input) {
    // A frame step shorter than kMinStepDt (limits.h: float32 positions do not resolve the
    // velocity of so short a motion) waits: the next step simulates its time too, and the
    // colliders' targets, teleports and emissions since, as one step would have.
    FrameState frame = carried_to;
    frame.frame_dt += carried_to.carried_dt;
    input->frame_dt = carried_to.frame_dt;  // a dynamic collider's force: the carried time's impulse too
    input->carried_dt = 0.0f;
    if (frame.frame_dt < kMinStepDt) {
        input->carried_dt = frame.frame_dt;
        input->simulated_dt = 0.0f;
        input->colliders_cut = false;
        input->substeps.clear();
        return;
    }
    // No substep shorter than kMinStepDt either: a short step runs fewer substeps.
    const uint32_t most = static_cast<uint32_t>(std::fmax(1.0f, std::floor(frame.frame_dt / kMinStepDt)));
    const uint32_t substeps = std::min(substep_count(p, c, frame, *emitters, *input), most);
    const uint32_t iterations = iteration_count(p, c, frame, *input, substeps);
    float sub_dt = frame.frame_dt / static_cast<float>(substeps);
    // A frame step longer than its substeps hold simulates what they hold and drops the rest
    // (held_substep): the world advances less than the frame, as a game engine's physics does
    // past its substep cap, and says so (pbf_step_stats.simulated_dt).
    // Only a hitch is held back: a frame step of a game's rate (up to kHitchDt) runs whole, as it
    // did, its substeps' unmet rules bounded there by the speed limit's cuts and the depth rule's
    // compression, which stay small at such steps. Held back instead, a fine-scale scene whose
    // spray or depth outruns max_substeps at 60 Hz would play in slow motion every frame.
    const double held = frame.frame_dt > kHitchDt
                            ? held_substep(p, c, frame, expected_speed(frame, *emitters, *input), substeps, iterations)
                            : HUGE_VAL;
    // (The rules the count met hold at its substep up to rounding: no clamp for that.)
    const bool held_back = double(sub_dt) > held * (1.0 + 1e-5);
    // A hitch simulates at least what a frame of kHitchDt does (that one runs whole): held back
    // further, a world whose expected speed is extreme (a collider sent a kilometre in a step)
    // would advance by next to nothing, or nothing at all once Δt rounds to 0.
    if (held_back) sub_dt = std::fmax(static_cast<float>(held), kHitchDt / static_cast<float>(substeps));
    const float simulated = held_back ? sub_dt * static_cast<float>(substeps) : frame.frame_dt;
    input->simulated_dt = simulated;
    input->colliders_cut = false;
    if (held_back) {
        // The colliders move at their own speed over the simulated time, and end where the
        // engine put them: the part of their way the dropped time would have carried is a
        // teleport at the step's start, whose overlap the first substep settles (as after
        // pbf_collider_teleport). At the end instead, the fluid would lie inside them until the
        // next step.
        const float fraction = simulated / frame.frame_dt;
        for (ColliderKey& key : input->collider_keys) {
            if (!moves(key)) continue;
            key = path_end(key, fraction);
            input->colliders_cut = true;
        }
    }
    input->substeps.resize(substeps);
    const StepContext ctx = substep_context(p, c, materials, sub_dt);
    for (uint32_t k = 0; k < substeps; ++k) {
        SubstepInput& in = input->substeps[k];
        in.ctx = ctx;
        in.iterations = iterations;
        in.settle_overlaps = k == 0 && (frame.overlaps_pending || input->colliders_cut);
        if (in.settle_overlaps) {
            // What the settling iterations leave is the same overlap, no motion either: removed in
            // the positions too, as an old error is at small Δt (weight 1), and without LDC's
            // push, which would turn its density gradient into velocity (docs/physics.md,
            // Overlaps).
            in.ctx.positional_weight = 1.0f;
            in.ctx.ldc_k = 0.0f;
            for (float& k : in.ctx.material_ldc_k) k = 0.0f;
        }
        for (EmitterState& e : *emitters) {
            if (!e.desc.enabled) continue;
            if (e.desc.type == PBF_EMITTER_DRAIN)
                in.drains.push_back(DrainBox{to_vec3(e.desc.box_min), to_vec3(e.desc.box_max)});
            else
                in.nozzles.push_back(nozzle_emission(e, c, sub_dt));
        }
    }
}

Collider place_collider(Collider c, const ColliderKey& key) {
    c.bounds = swept_bounds(c, key);
    return c;
}

Status plan_block(const pbf_block_desc& d, const WorldConstants& c, float spacing, uint32_t capacity,
                  BlockEmission* out) {
    const double s = spacing;
    // Lattice points x = min + s/2 + k·s inside the box (at least one per axis). Points outside
    // the walls (centres closer than one radius to the domain's faces) are dropped: clamped onto
    // the wall they would pile up on one plane.
    const double wall_lo[3] = {c.wall_min.x, c.wall_min.y, c.wall_min.z};
    const double wall_hi[3] = {c.wall_max.x, c.wall_max.y, c.wall_max.z};
    double origin[3];
    uint32_t count[3];
    for (int axis = 0; axis < 3; ++axis) {
        const double lo = d.box_min[axis], hi = d.box_max[axis];
        const double n = std::max(1.0, std::floor((hi - lo) / s + 1e-4));  // 0.15 / 0.05 is 3, not 2
        double x0 = lo + 0.5 * s;
        double k0 = std::max(0.0, std::ceil((wall_lo[axis] - x0) / s - 1e-4));
        double k1 = std::min(n - 1.0, std::floor((wall_hi[axis] - x0) / s + 1e-4));
        if (std::fabs(lo) > 1e6 * s && k0 <= k1) {
            // A box so far out that its anchor cannot place a lattice point to float precision:
            // the lattice starts at the wall instead.
            x0 = std::max(lo + 0.5 * s, wall_lo[axis]);
            k0 = 0.0;
            k1 = std::floor((std::min(hi - 0.5 * s, wall_hi[axis]) - x0) / s + 1e-4);
        }
        if (!(k0 <= k1)) {
            return Status::error(PBF_ERROR_INVALID_ARGUMENT,
                                 "the block lies outside the walls (particle centres stay one particle_radius "
                                 "inside domain_min..domain_max; without walls, within 2^17 h of the origin on each "
                                 "axis); nothing was emitted");
        }
        origin[axis] = x0 + k0 * s;
        count[axis] = static_cast<uint32_t>(std::min(k1 - k0 + 1.0, double(capacity)));
    }
    BlockEmission b{};
    b.nx = count[0];
    b.ny = count[1];
    b.nz = count[2];
    b.spacing = static_cast<float>(s);
    b.origin = Vec3{float(origin[0]), float(origin[1]), float(origin[2])};
    b.velocity = to_vec3(d.velocity);
    if (uint64_t(b.nx) * b.ny * b.nz > capacity) {
        // Emit what fits: the lattice is filled x-first, so whole layers in z are kept.
        b.nz = std::max<uint32_t>(1, capacity / (b.nx * uint64_t(b.ny)) + 1);
    }
    *out = b;
    return Status{};
}

float block_depth(const BlockEmission& b, Vec3 gravity) {
    const float g = length(gravity);
    const float along = std::fabs(gravity.x) * float(b.nx - 1) + std::fabs(gravity.y) * float(b.ny - 1) +
                        std::fabs(gravity.z) * float(b.nz - 1);
    return g > 0.0f ? along * b.spacing / g : 0.0f;
}

bool block_meets(const BlockEmission& b, float r, const std::vector<Collider>& colliders) {
    const Vec3 reach{r, r, r};
    const Vec3 lo = b.origin - reach;
    const Vec3 hi = b.origin + Vec3{float(b.nx - 1), float(b.ny - 1), float(b.nz - 1)} * b.spacing + reach;
    bool meets = false;
    for (const Collider& c : colliders) meets = meets || overlaps(c.bounds, lo, hi);
    return meets;
}

double nozzle_capacity(const pbf_emitter_desc& d, float spacing) {
    const double s = spacing;
    const double disc_points = std::max(1.0, kPi * double(d.radius) * d.radius / (s * s));
    return disc_points * d.speed / s;
}

bool inside_walls(const WorldConstants& c, Vec3 p) {
    const Vec3 lo = c.wall_min, hi = c.wall_max;
    return !(p.x < lo.x || p.y < lo.y || p.z < lo.z || p.x > hi.x || p.y > hi.y || p.z > hi.z);
}

}  // namespace pbf
