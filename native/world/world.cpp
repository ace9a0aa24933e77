#include "world.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "../core/collide.h"
#include "../core/grid.h"
#include "../core/lattice.h"
#include "../core/material_ops.h"
#include "../core/sph.h"

namespace pbf {

// The core's shape codes are the public ones, so create_collider passes a shape through a cast.
constexpr bool same_code(ColliderShape core, pbf_collider_shape api) { return uint32_t(core) == uint32_t(api); }
static_assert(same_code(kShapePlane, PBF_SHAPE_PLANE) && same_code(kShapeSphere, PBF_SHAPE_SPHERE) &&
                  same_code(kShapeCapsule, PBF_SHAPE_CAPSULE) && same_code(kShapeBox, PBF_SHAPE_BOX) &&
                  same_code(kShapeMesh, PBF_SHAPE_MESH),
              "core/params.h ColliderShape mirrors pbf_collider_shape");
namespace {

Vec3 to_vec3(const float v[3]) { return Vec3{v[0], v[1], v[2]}; }

Eigen::Quaternionf to_quat(const float q[4]) { return Eigen::Quaternionf(q[3], q[0], q[1], q[2]).normalized(); }

Quat quat_of(const float q[4]) { return Quat{q[0], q[1], q[2], q[3]}; }

// Open levels hold particle centres within |x| <= 2^17·h per axis: there float spacing is h/64,
// still fine against the kernel (a particle reaching it stops as at a wall without density).
float open_limit(float h) { return std::ldexp(h, 17); }

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

std::unique_ptr<World> World::create(const pbf_world_desc& desc, Status* status) {
    std::unique_ptr<World> w(new World());
    w->desc_ = desc;
    w->params_ = desc.solver;
    w->gravity_ = to_vec3(desc.gravity);
    w->h_ = 4.0f * desc.particle_radius;
    const float spacing = 2.0f * desc.particle_radius;
    const LatticeCalibration cal = calibrate_lattice(spacing, w->h_);
    w->mass_ = static_cast<float>(desc.rest_density / cal.kernel_sum);
    // |∇_k C|² of a rest particle, with ∇C = (m/ρ0) ∇W.
    const double m_over_rho = 1.0 / cal.kernel_sum;
    w->gradient_norm2_ = static_cast<float>(cal.gradient_norm2 * m_over_rho * m_over_rho);
    w->boundary_scale_ = boundary_lattice_scale(spacing, w->h_);
    w->box_edge_scale_ = box_edge_scale(spacing, w->h_, w->boundary_scale_);
    // Every constant the kernels use must be a normal float: a radius or rest density so extreme
    // that one over- or underflows (a denormal rest density, a radius of 1e20 m) would make every
    // density and velocity NaN.
    {
        const float coef6 = poly6_coefficient(w->h_), coef_grad = spiky_grad_coefficient(w->h_);
        const double quantities[] = {w->mass_,
                                     w->gradient_norm2_,
                                     coef6,
                                     coef_grad,
                                     w->h_ * w->h_,
                                     poly6(0.0f, w->h_ * w->h_, coef6),
                                     w->mass_ * poly6(0.0f, w->h_ * w->h_, coef6),
                                     1.0f / desc.rest_density};
        for (double q : quantities) {
            if (!(std::isfinite(q) && q >= double(FLT_MIN) && q <= double(FLT_MAX))) {
                char text[96];
                std::snprintf(text, sizeof text, "particle_radius %g and rest_density %g", desc.particle_radius,
                              desc.rest_density);
                *status = Status::error(PBF_ERROR_INVALID_ARGUMENT,
                                        std::string(text) + " give SPH constants outside the range of float");
                return nullptr;
            }
        }
    }

    w->grid_ = choose_grid(desc, w->h_);
    const GridDims& g = w->grid_;
    BackendConfig config{desc.max_particles, desc.max_colliders, g, desc.cuda_device,
                         render_constants(desc.render, desc.particle_radius, w->h_), diffuse_constants(desc.diffuse),
                         w->h_};
    pbf_backend kind = desc.backend;
    if (kind == PBF_BACKEND_AUTO) kind = cuda_device_available(desc.cuda_device) ? PBF_BACKEND_CUDA : PBF_BACKEND_CPU;
    w->backend_ = kind == PBF_BACKEND_CUDA ? create_cuda_backend(config, status) : create_cpu_backend(config, status);
    if (!w->backend_) return nullptr;
    w->init_materials();
    w->update_constants();
    return w;
}

void World::update_constants() {
    WorldConstants& s = constants_;
    s = WorldConstants{};
    s.radius = desc_.particle_radius;
    s.h = h_;
    s.h2 = h_ * h_;
    s.mass = mass_;
    s.rest_density = desc_.rest_density;
    s.inv_rest_density = 1.0f / desc_.rest_density;
    s.poly6_coef = poly6_coefficient(h_);
    s.spiky_coef = spiky_grad_coefficient(h_);
    s.rest_gradient_norm2 = gradient_norm2_;
    s.relaxation = params_.relaxation;
    const float dq = params_.scorr_dq * h_;
    // s_corr enters beside λ_i + λ_j. Macklin & Müller's k = 0.1 presumes their units; here
    // k·(W/W(Δq))^n is read as a density-ratio error and converted to λ's units by the rest
    // gradient norm, so the same k behaves the same at any particle size.
    s.scorr_k = params_.scorr_k / (gradient_norm2_ * (1.0f + params_.relaxation));
    s.scorr_n = params_.scorr_n;
    s.scorr_inv_w_dq = 1.0f / poly6(dq * dq, s.h2, s.poly6_coef);
    s.vorticity_epsilon = params_.vorticity_epsilon;
    s.max_speed = params_.max_speed;
    s.ldc_enabled = params_.ldc_enabled;
    s.adaptive_target = params_.adaptive_error_target;
    s.gravity = gravity_;
    const Vec3 r{s.radius, s.radius, s.radius};
    if (desc_.walls) {
        s.boundary_min = to_vec3(desc_.domain_min);
        s.boundary_max = to_vec3(desc_.domain_max);
        s.wall_min = s.boundary_min + r;
        s.wall_max = s.boundary_max - r;
    } else {
        // An open level: no solid anywhere near a particle, only the open limit box.
        const float limit = open_limit(h_);
        s.boundary_min = Vec3{-FLT_MAX, -FLT_MAX, -FLT_MAX};
        s.boundary_max = Vec3{FLT_MAX, FLT_MAX, FLT_MAX};
        s.wall_min = Vec3{-limit, -limit, -limit};
        s.wall_max = Vec3{limit, limit, limit};
    }
    s.boundary_scale = boundary_scale_;
    s.box_edge_scale = box_edge_scale_;
    s.grid = grid_;
    s.capacity = desc_.max_particles;
    s.materials = material_constants();
}

// A substep of sub_dt: everything that depends on Δt.
StepContext World::step_context(float sub_dt) const {
    StepContext c{};
    c.dt = sub_dt;
    c.inv_dt = 1.0f / sub_dt;
    c.lambda_epsilon = gradient_norm2_ * params_.relaxation;
    // The response time τ = h / sound_speed: errors older than the substep relax over τ (the λ
    // pass's error damping, γ = τ/Δt), and LDC's K = gain / Δt² takes τ as a floor of Δt, so
    // neither turns an error into a velocity larger than about error · sound_speed.
    const float tau = h_ / params_.sound_speed;
    c.error_damping = std::fmin(tau / sub_dt, 1e6f);
    c.ldc_k = params_.ldc_gain / (sub_dt * sub_dt + tau * tau);
    // s_corr answers an arrangement (clumping) that persists, so it pushes again every substep:
    // k/(1 + γ) while Δt ≥ τ (γ ≤ 1), then k/(2γ²), an acceleration of about k/(2τ²) as Δt → 0,
    // bounded whatever the substep count (k/(1 + γ) alone grew as 1/Δt: 12.7 m/s from an
    // emitted block at 1e-5 s, and a pool at 16 fixed substeps expanded 6 %). The two meet at
    // γ = 1; k/(1 + γ)² everywhere weakened s_corr at the default substeps (γ ≈ 0.3-0.6) and
    // raised the light fluid's largest density error in the two-fluid test on the H100.
    const float g = c.error_damping;
    c.scorr_k = constants_.scorr_k * std::fmin(1.0f / (1.0f + g), 0.5f / (g * g));
    // XSPH's c is per 1/60 s: a substep of Δt applies 1 - (1 - c)^(60 Δt), so the smoothing per
    // second does not depend on the substep count.
    c.xsph_c = xsph_factor(params_.xsph_c, sub_dt);
    // No particle may move more than h in a substep (kTravelCap): beyond that a few iterations
    // cannot resolve the compression it creates.
    constexpr float kTravelCap = 1.0f;
    c.speed_limit = std::fmin(params_.max_speed, kTravelCap * h_ / sub_dt);
    material_step_context(sub_dt, &c);
    return c;
}

// Substeps for a step of dt: fixed, or from the fastest motion expected over the step: the
// latest finished step's fastest particle (read without waiting), particles emitted since, the
// nozzles, and the kinematic colliders' surface speed; plus what gravity adds over dt; and at
// least enough that gravity alone moves a resting particle little per substep.
uint32_t World::substeps_for(float dt) {
    if (params_.substeps > 0) return params_.substeps;
    const StepFeedback fb = backend_->feedback();
    float v = std::fmax(fb.max_speed, emitted_speed_);
    emitters_.for_each([&](EmitterEntry& e) {
        if (e.desc.enabled && e.desc.type == PBF_EMITTER_NOZZLE) v = std::fmax(v, e.desc.speed);
    });
    colliders_.for_each([&](ColliderEntry& e) {
        const float reach = collider_reach(e.collider);  // a plane: 0, its translation only
        const float angle = to_quat(e.rotation).angularDistance(to_quat(e.target_rotation));
        v = std::fmax(v, (length(e.target_position - e.position) + angle * reach) / dt);
    });
    const double g = length(gravity_);
    v += float(g) * dt;
    const double travel = double(params_.substep_travel) * h_;
    double n = std::ceil(double(v) * dt / travel);
    // Fluid at rest: gravity moves every particle g·Δt² per substep and the iterations must
    // carry that to the floor. Shallow fluid compressed unless g·Δt² stays under travel / 64
    // (measured on the frame benchmark's tank); deep fluid by the depth rule below.
    if (g > 0.0) n = std::max(n, std::ceil(dt * std::sqrt(64.0 * g / travel) - 1e-6));
    const double depth = std::fmax(fb.fluid_depth, emitted_depth_);
    if (g > 0.0 && depth > 0.0) n = std::max(n, std::ceil(dt * depth_substep_rate(g, depth) - 1e-6));
    // Surface tension, cohesion and adhesion are explicit forces: Δt within their stability caps.
    n = std::max(n, std::ceil(double(dt) * surface_substep_rate(constants_.materials) - 1e-6));
    return static_cast<uint32_t>(std::clamp(n, 1.0, double(params_.max_substeps)));
}

uint32_t World::gather_colliders(bool moving, std::vector<Collider>* shapes, std::vector<ColliderKey>* keys) {
    uint32_t dynamic = 0;
    colliders_.for_each([&](ColliderEntry& e) {
        ColliderKey k{e.position, moving ? e.target_position : e.position, quat_of(e.rotation),
                      quat_of(moving ? e.target_rotation : e.rotation)};
        Collider c = e.collider;
        c.bounds = swept_bounds(c, k);
        if (c.flags & kColliderDynamic) ++dynamic;
        shapes->push_back(c);
        keys->push_back(k);
    });
    return dynamic;
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
double World::depth_substep_rate(double g, double depth) const {
    constexpr double kBottomCompression = 0.1;
    const double kappa = 4.0 / (double(params_.iterations) + 0.5);
    return std::sqrt(kappa * g * depth / kBottomCompression) / h_;
}

Status World::colliders_changed() {
    ColliderSetAtRest rest;
    gather_colliders(false, &rest.shapes, &rest.keys);
    return backend_->set_colliders_at_rest(rest);
}

bool World::destroy_collider(pbf_collider_id id) {
    const ColliderEntry* e = find_collider(id);
    if (!e) return false;
    if (MeshEntry* m = meshes_.find(e->mesh.index, e->mesh.generation)) --m->users;
    colliders_.erase(id.index, id.generation);
    (void)colliders_changed();  // the step uploads its colliders anyway; this serves stats between steps
    return true;
}

Status World::step(float dt) {
    const uint32_t substeps = substeps_for(dt);
    const float sub_dt = dt / static_cast<float>(substeps);
    const float spacing = rest_spacing();
    StepInput input;
    input.substeps.resize(substeps);
    input.dynamic_count = gather_colliders(true, &input.collider_shapes, &input.collider_keys);
    input.step_dt = dt;
    const StepContext ctx = step_context(sub_dt);
    for (uint32_t k = 0; k < substeps; ++k) {
        SubstepInput& in = input.substeps[k];
        in.ctx = ctx;
        in.iterations = params_.iterations;
        in.settle_overlaps = k == 0 && overlaps_pending_;
        emitters_.for_each([&](EmitterEntry& e) {
            if (!e.desc.enabled) return;
            if (e.desc.type == PBF_EMITTER_DRAIN) {
                in.drains.push_back(DrainBox{to_vec3(e.desc.box_min), to_vec3(e.desc.box_max)});
                return;
            }
            e.accumulator += e.desc.particles_per_second * sub_dt;
            const float whole = std::floor(e.accumulator);
            e.accumulator -= whole;
            const uint32_t n = static_cast<uint32_t>(std::min(whole, float(desc_.max_particles)));
            const Vec3 dir = to_vec3(e.desc.direction);
            // Any unit vector not parallel to dir, then an orthonormal frame around dir.
            const Vec3 helper = std::fabs(dir.y) < 0.9f ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
            const Vec3 t = cross(dir, helper) * (1.0f / length(cross(dir, helper)));
            const Vec3 b = cross(dir, t);
            // Clamped before the conversion: a huge (finite) radius makes this Inf.
            const float area_points = std::fmin(kPi * e.desc.radius * e.desc.radius / (spacing * spacing), 4.0e9f);
            NozzleEmission ne{n, e.sequence, std::max(1u, static_cast<uint32_t>(area_points)),
                              to_vec3(e.desc.position), dir, t, b, e.desc.radius, e.desc.speed,
                              static_cast<uint8_t>(std::max(0, material_slot(e.desc.material)))};
            e.sequence += n;
            in.nozzles.push_back(ne);
        });
    }
    mapped_ = false;  // the mapping is valid until the next step
    Status st = backend_->step(constants_, input);
    // Kinematic colliders arrived at their targets.
    colliders_.for_each([](ColliderEntry& e) {
        e.position = e.target_position;
        std::memcpy(e.rotation, e.target_rotation, sizeof e.rotation);
    });
    if (st.ok()) {
        ++step_index_;
        last_substeps_ = substeps;
        last_iterations_ = params_.iterations * substeps;
        emitted_speed_ = 0.0f;
        emitted_depth_ = 0.0f;
        overlaps_pending_ = false;
        if (attachment_) st = attachment_->after_step();  // e.g. copies into graphics buffers
    }
    return st;
}

void World::get_info(pbf_world_info* info) const {
    info->backend = backend_->kind();
    info->max_particles = desc_.max_particles;
    info->particle_radius = desc_.particle_radius;
    info->rest_spacing = rest_spacing();
    info->kernel_radius = h_;
    info->particle_mass = mass_;
    info->grid_cells = grid_.num_cells;
    info->device_bytes = backend_->device_bytes();
    const std::string name = backend_->device_name();
    std::memset(info->device_name, 0, sizeof info->device_name);
    std::strncpy(info->device_name, name.c_str(), sizeof info->device_name - 1);
    info->render_flags = desc_.render.flags;
    info->reserved0 = 0;
    info->render_bytes = backend_->render_bytes();
    info->render_updates = backend_->render_updates();
    info->diffuse_capacity = desc_.diffuse.max_diffuse;
    info->reserved1 = 0;
    info->diffuse_bytes = backend_->diffuse_bytes();
    info->diffuse_updates = backend_->diffuse_updates();
    info->grid_hashed = grid_.hashed;
    info->reserved2 = 0;
    info->grid_bytes = (uint64_t(grid_.num_cells) + 1) * sizeof(uint32_t);  // the solver's cell_begin
}

Status World::get_stats(pbf_step_stats* out) {
    StatsReadback r;
    // Any substep's constants serve: the density pass and the reduction use no dt.
    Status st = backend_->read_stats(constants_, &r);
    if (!st.ok()) return st;
    float ms = 0.0f;
    st = backend_->last_step_ms(&ms);
    if (!st.ok()) return st;
    out->particle_count = r.count;
    out->step_index = step_index_;
    out->emitted_total = r.emitted_total;
    out->drained_total = r.drained_total;
    out->density_error_mean = r.count ? static_cast<float>(r.error_sum / r.count) : 0.0f;
    out->density_error_max = r.error_max;
    out->kinetic_energy = static_cast<float>(r.kinetic_energy);
    out->step_time_ms = step_index_ ? ms : 0.0f;
    out->iterations = params_.adaptive_error_target > 0.0f ? r.iterations_used : last_iterations_;
    out->substeps = step_index_ ? last_substeps_ : 0u;
    out->speed_clamps = step_index_ ? r.speed_clamps : 0u;
    out->reserved0 = 0;
    out->diffuse_count = r.diffuse_count;
    out->diffuse_dropped = step_index_ ? r.diffuse_dropped_step : 0u;
    out->diffuse_generated_total = r.diffuse_generated_total;
    out->diffuse_dropped_total = r.diffuse_dropped_total;
    return Status{};
}

void World::set_nozzle_direction(pbf_emitter_desc& d, Vec3 direction) {
    const Vec3 unit = direction * (1.0f / length(direction));
    d.direction[0] = unit.x;
    d.direction[1] = unit.y;
    d.direction[2] = unit.z;
}

Status World::emit_block(const pbf_block_desc& d, uint32_t* emitted) {
    const double s = rest_spacing();
    // Lattice points x = min + s/2 + k·s inside the box (at least one per axis). Points outside
    // the walls (centres closer than one radius to the domain's faces) are dropped: clamped onto
    // the wall they would pile up on one plane.
    const double wall_lo[3] = {constants_.wall_min.x, constants_.wall_min.y, constants_.wall_min.z};
    const double wall_hi[3] = {constants_.wall_max.x, constants_.wall_max.y, constants_.wall_max.z};
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
        count[axis] = static_cast<uint32_t>(std::min(k1 - k0 + 1.0, double(desc_.max_particles)));
    }
    BlockEmission b{};
    b.nx = count[0];
    b.ny = count[1];
    b.nz = count[2];
    b.spacing = static_cast<float>(s);
    b.origin = Vec3{float(origin[0]), float(origin[1]), float(origin[2])};
    b.velocity = to_vec3(d.velocity);
    b.material = static_cast<uint8_t>(material_slot(d.material));  // validated: live or zeroed
    if (uint64_t(b.nx) * b.ny * b.nz > desc_.max_particles) {
        // Emit what fits: the lattice is filled x-first, so whole layers in z are kept.
        b.nz = std::max<uint32_t>(1, desc_.max_particles / (b.nx * uint64_t(b.ny)) + 1);
    }
    Status st = backend_->emit_block(b, constants_, emitted);
    if (*emitted > 0) {
        mapped_ = false;  // new particles reorder storage; a failed emit keeps the map
        emitted_speed_ = std::fmax(emitted_speed_, length(b.velocity));
        // The block's extent along gravity (what the next step's depth rule needs before any
        // step has measured it).
        const float g = length(gravity_);
        const float along = std::fabs(gravity_.x) * float(b.nx - 1) + std::fabs(gravity_.y) * float(b.ny - 1) +
                            std::fabs(gravity_.z) * float(b.nz - 1);
        if (g > 0.0f) emitted_depth_ = std::fmax(emitted_depth_, along * b.spacing / g);
        // Into a collider: the next step settles the overlap (Solver::settle). Tested against
        // the colliders' bounds, so that blocks emitted clear of them cost no settling.
        const Vec3 reach{desc_.particle_radius, desc_.particle_radius, desc_.particle_radius};
        const Vec3 lo = b.origin - reach;
        const Vec3 hi = b.origin + Vec3{float(b.nx - 1), float(b.ny - 1), float(b.nz - 1)} * b.spacing + reach;
        ColliderSetAtRest rest;
        gather_colliders(false, &rest.shapes, &rest.keys);
        for (const Collider& c : rest.shapes) overlaps_pending_ = overlaps_pending_ || overlaps(c.bounds, lo, hi);
    }
    if (st.ok() && *emitted == 0)
        return Status::error(PBF_ERROR_CAPACITY, "world is full (max_particles = " +
                                                     std::to_string(desc_.max_particles) + "); nothing was emitted");
    return st;
}

// A nozzle the solver can honour: its disc centre inside the walls (particles emitted outside
// would be clamped onto a wall and pile up there), and a rate its disc can carry at rest
// spacing (faster, particles would be emitted on top of each other).
Status World::check_nozzle(const pbf_emitter_desc& d, Vec3 position) const {
    const Vec3 lo = constants_.wall_min, hi = constants_.wall_max;
    if (position.x < lo.x || position.y < lo.y || position.z < lo.z || position.x > hi.x || position.y > hi.y ||
        position.z > hi.z)
        return Status::error(PBF_ERROR_INVALID_ARGUMENT,
                             "the nozzle's position lies outside the walls (particle centres stay one "
                             "particle_radius inside domain_min..domain_max; without walls, within 2^17 h of the "
                             "origin on each axis)");
    const double s = rest_spacing();
    const double disc_points = std::max(1.0, kPi * double(d.radius) * d.radius / (s * s));
    const double carried = disc_points * d.speed / s;
    if (d.particles_per_second > carried * 1.0001) {
        char text[200];
        std::snprintf(text, sizeof text,
                      "particles_per_second %g exceeds what the nozzle carries at rest spacing (%.6g: disc area / "
                      "spacing² x speed / spacing); raise its speed or radius",
                      double(d.particles_per_second), carried);
        return Status::error(PBF_ERROR_INVALID_ARGUMENT, text);
    }
    return Status{};
}

Status World::create_emitter(const pbf_emitter_desc& desc, pbf_emitter_id* out) {
    EmitterEntry e;
    e.desc = desc;
    if (desc.type == PBF_EMITTER_NOZZLE) {
        Status st = check_nozzle(desc, to_vec3(desc.position));
        if (!st.ok()) return st;
        set_nozzle_direction(e.desc, to_vec3(desc.direction));
    }
    const auto h = emitters_.insert(e);
    *out = pbf_emitter_id{h.index, h.generation};
    return Status{};
}

Status World::create_collider(const pbf_collider_desc& d, pbf_collider_id* out) {
    if (colliders_.size() >= desc_.max_colliders)
        return Status::error(PBF_ERROR_CAPACITY, "the world holds max_colliders = " +
                                                     std::to_string(desc_.max_colliders) +
                                                     " colliders already (pbf_world_desc.max_colliders)");
    ColliderEntry e{};
    MeshEntry* mesh = nullptr;
    if (d.shape == PBF_SHAPE_MESH) {
        mesh = meshes_.find(d.mesh.index, d.mesh.generation);
        if (!mesh) return Status::error(PBF_ERROR_INVALID_HANDLE, "mesh is not a live mesh of this world");
        e.mesh = d.mesh;
        e.collider.mesh = d.mesh.index;
    }
    e.collider.shape = static_cast<uint32_t>(d.shape);
    e.collider.radius = mesh ? mesh->reach : d.radius;
    e.collider.half_height = d.half_height;
    e.collider.friction = d.friction;
    e.collider.half_extents = to_vec3(d.half_extents);
    e.collider.flags = d.dynamic ? kColliderDynamic : 0u;
    e.collider.center_local = to_vec3(d.center_of_mass);
    e.motion = static_cast<uint32_t>(d.motion);
    e.position = e.target_position = to_vec3(d.position);
    const Eigen::Quaternionf q = to_quat(d.rotation);
    const float qn[4] = {q.x(), q.y(), q.z(), q.w()};
    std::memcpy(e.rotation, qn, sizeof qn);
    std::memcpy(e.target_rotation, qn, sizeof qn);
    const auto h = colliders_.insert(e);
    // The handle's index is the collider's row of the force tables (indices stay below
    // max_colliders: the table reuses freed ones first).
    colliders_.find(h.index, h.generation)->collider.row = h.index;
    Status st = backend_->clear_collider_force(h.index);
    if (st.ok()) st = colliders_changed();
    if (!st.ok()) {
        colliders_.erase(h.index, h.generation);
        return st;
    }
    if (mesh) ++mesh->users;
    overlaps_pending_ = true;
    *out = pbf_collider_id{h.index, h.generation};
    return st;
}

Status World::collider_force(pbf_collider_id id, pbf_collider_force* out) {
    const ColliderEntry* e = find_collider(id);
    if (!e) return Status::error(PBF_ERROR_INVALID_HANDLE, "collider is not live");
    if (!(e->collider.flags & kColliderDynamic))
        return Status::error(PBF_ERROR_INVALID_STATE,
                             "the collider is not dynamic (pbf_collider_desc.dynamic = 1 records its force)");
    const ColliderForce* rows = nullptr;
    Status st = backend_->collider_forces(&rows);
    if (!st.ok()) return st;
    const ColliderForce& f = rows[e->collider.row];
    const float values[6] = {f.force.x, f.force.y, f.force.z, f.torque.x, f.torque.y, f.torque.z};
    std::memcpy(out->force, values, 3 * sizeof(float));
    std::memcpy(out->torque, values + 3, 3 * sizeof(float));
    return st;
}

}  // namespace pbf
