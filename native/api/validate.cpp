// The named checks of validate.h: one validator per desc, checks in the order the messages of
// earlier releases were given, so a desc with several faults is refused for the same one.
#include "validate.h"

#include "../world/world.h"

#include <cmath>

namespace pbf::api {
namespace {

struct CheckInfo {
    const char* name;
    pbf_result code;
    const char* message;
};

const CheckInfo kChecks[] = {{"OK", PBF_OK, ""},
#define PBF_CHECK_INFO(id, code, message) {#id, code, message},
                             PBF_VALIDATE_CHECKS(PBF_CHECK_INFO)
#undef PBF_CHECK_INFO
};
static_assert(sizeof kChecks / sizeof kChecks[0] == size_t(Check::count), "one entry per check");

bool finite3(const float v[3]) { return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]); }
bool finite_nonzero_quat(const float q[4]) {
    if (!(std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]) && std::isfinite(q[3]))) return false;
    return q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3] > 1e-6f;
}
bool in(float v, float lo, float hi) { return std::isfinite(v) && v >= lo && v <= hi; }
bool valid_source(const pbf_buffer& source) {
    const int32_t s = raw(source);
    return s >= PBF_BUFFER_POSITIONS && s <= PBF_BUFFER_MATERIALS;
}
bool valid_mode(pbf_copy_mode mode) {
    const int32_t m = raw(mode);
    return m == PBF_COPY_ON_STEP || m == PBF_COPY_ON_RENDER_EVENT || m == PBF_COPY_MANUAL;
}

// Returns the verdict of the first failed check: V(cond, CHECK) inside a validator.
#define V(cond, id)                             \
    do {                                        \
        if (!(cond)) return Verdict{Check::id}; \
    } while (0)

}  // namespace

const char* check_name(Check c) { return size_t(c) < size_t(Check::count) ? kChecks[size_t(c)].name : "?"; }
pbf_result check_code(Check c) {
    return size_t(c) < size_t(Check::count) ? kChecks[size_t(c)].code : PBF_ERROR_INTERNAL;
}

std::string check_message(const Verdict& v) {
    std::string m = size_t(v.check) < size_t(Check::count) ? kChecks[size_t(v.check)].message : "?";
    for (const auto& [key, value] : {std::pair{"{a}", v.a}, std::pair{"{b}", v.b}})
        if (const size_t at = m.find(key); at != std::string::npos) m.replace(at, 3, std::to_string(value));
    return m;
}

Verdict validate_solver_params(const pbf_solver_params& p) {
    V(p.iterations >= 1 && p.iterations <= 64, SOLVER_ITERATIONS);
    V(p.substeps <= 64, SOLVER_SUBSTEPS);
    V(p.max_substeps >= 1 && p.max_substeps <= 64, SOLVER_MAX_SUBSTEPS);
    V(std::isfinite(p.substep_travel) && p.substep_travel >= 0.05f && p.substep_travel <= 1.0f, SOLVER_SUBSTEP_TRAVEL);
    // Below ~10 m/s old errors relax too slowly: a 0.4 m dam break at 3 m/s left particles 0.46
    // radii apart, at 1 m/s 0.04 (overlapping).
    V(std::isfinite(p.sound_speed) && p.sound_speed >= 10.0f, SOLVER_SOUND_SPEED);
    V(std::isfinite(p.relaxation) && p.relaxation > 0.0f, SOLVER_RELAXATION);
    V(in(p.scorr_k, 0.0f, 1.0f), SOLVER_SCORR_K);
    V(in(p.scorr_n, 1.0f, 8.0f), SOLVER_SCORR_N);
    V(std::isfinite(p.scorr_dq) && p.scorr_dq > 0.0f && p.scorr_dq < 1.0f, SOLVER_SCORR_DQ);
    V(in(p.xsph_c, 0.0f, 1.0f), SOLVER_XSPH_C);
    // Above 1 m/s vorticity confinement makes energy: the same dam break gained 43 % of its
    // energy at 3 m/s and exploded at 10.
    V(in(p.vorticity_epsilon, 0.0f, 1.0f), SOLVER_VORTICITY);
    V(p.ldc_enabled <= 1, SOLVER_LDC_ENABLED);
    V(in(p.ldc_gain, 0.0f, 1.0f), SOLVER_LDC_GAIN);
    V(std::isfinite(p.max_speed) && p.max_speed > 0.0f, SOLVER_MAX_SPEED);
    V(std::isfinite(p.adaptive_error_target) && p.adaptive_error_target >= 0.0f && p.adaptive_error_target < 1.0f,
      SOLVER_ADAPTIVE_TARGET);
    return {};
}

Verdict validate_world_desc(const pbf_world_desc& d) {
    if (PBF_VERSION_GET_MAJOR(d.header_version) != PBF_VERSION_MAJOR)
        return Verdict{Check::WORLD_HEADER_VERSION, PBF_VERSION_GET_MAJOR(d.header_version), PBF_VERSION_MAJOR};
    const int32_t backend = raw(d.backend);
    V(backend == PBF_BACKEND_AUTO || backend == PBF_BACKEND_CPU || backend == PBF_BACKEND_CUDA, WORLD_BACKEND);
    V(d.cuda_device >= 0, WORLD_CUDA_DEVICE);
    V(d.max_particles >= 1 && d.max_particles <= (1u << 30), WORLD_MAX_PARTICLES);
    V(std::isfinite(d.particle_radius) && d.particle_radius > 0.0f, WORLD_PARTICLE_RADIUS);
    V(std::isfinite(d.rest_density) && d.rest_density > 0.0f, WORLD_REST_DENSITY);
    V(finite3(d.gravity), WORLD_GRAVITY);
    V(d.walls == 0 || d.walls == 1, WORLD_WALLS);
    V(d.hashed_grid == 0 || d.hashed_grid == 1, WORLD_HASHED_GRID);
    if (d.walls) {  // an open level has no box: its domain fields are ignored
        V(finite3(d.domain_min) && finite3(d.domain_max), WORLD_DOMAIN_FINITE);
        for (int a = 0; a < 3; ++a) V(d.domain_max[a] - d.domain_min[a] >= 4.0f * d.particle_radius, WORLD_DOMAIN_SIZE);
        // The box's grid may be hashed (any extent costs the same memory), but float must still
        // resolve h within it: the open limit box (solver/step_plan.cpp) bounds the walls too.
        const double limit = std::ldexp(double(d.particle_radius), 19);
        for (int a = 0; a < 3; ++a)
            V(std::fabs(double(d.domain_min[a])) <= limit && std::fabs(double(d.domain_max[a])) <= limit,
              WORLD_DOMAIN_EXTENT);
    }
    if (d.max_colliders < 1 || d.max_colliders > PBF_MAX_COLLIDERS)
        return Verdict{Check::WORLD_MAX_COLLIDERS, PBF_MAX_COLLIDERS};
    return {};
}

Verdict validate_render_params(const pbf_render_params& p) {
    V((p.flags & ~(PBF_RENDER_SMOOTHED_POSITIONS | PBF_RENDER_ANISOTROPY)) == 0, RENDER_FLAGS);
    V(in(p.smoothing, 0.0f, 1.0f), RENDER_SMOOTHING);
    V(in(p.max_stretch, 1.0f, 100.0f), RENDER_MAX_STRETCH);
    V(in(p.scale, 0.0f, 100.0f) && p.scale > 0.0f, RENDER_SCALE);
    V(in(p.isolated_scale, 0.0f, 100.0f) && p.isolated_scale > 0.0f, RENDER_ISOLATED_SCALE);
    V(p.min_neighbors <= 1000, RENDER_MIN_NEIGHBORS);
    V(p.reserved0 == 0, RENDER_RESERVED0);
    return {};
}

Verdict validate_diffuse_params(const pbf_diffuse_params& p) {
    V(p.max_diffuse <= (1u << 26), DIFFUSE_CAPACITY);
    const float pairs[3][2] = {
        {p.trapped_air_min, p.trapped_air_max}, {p.wave_crest_min, p.wave_crest_max}, {p.energy_min, p.energy_max}};
    for (const auto& t : pairs) V(in(t[0], 0.0f, 1e6f) && in(t[1], 0.0f, 1e6f) && t[0] < t[1], DIFFUSE_THRESHOLDS);
    V(in(p.trapped_air_rate, 0.0f, 1e4f) && in(p.wave_crest_rate, 0.0f, 1e4f), DIFFUSE_RATES);
    V(in(p.lifetime, 0.0f, 1e4f) && p.lifetime > 0.0f, DIFFUSE_LIFETIME);
    V(p.spray_max_neighbors <= p.bubble_min_neighbors && p.bubble_min_neighbors <= 1000, DIFFUSE_NEIGHBORS);
    V(in(p.buoyancy, 0.0f, 100.0f) && in(p.bubble_drag, 0.0f, 1e4f) && in(p.spray_drag, 0.0f, 1e4f), DIFFUSE_MOTION);
    return {};
}

Verdict validate_diffuse_rows(const float* positions, const float* velocities, uint32_t count) {
    for (uint32_t i = 0; i < count; ++i) {
        const float* x = positions + 4 * size_t(i);
        const float* v = velocities + 4 * size_t(i);
        const float kind = x[3];
        V(finite3(x) && finite3(v) && (kind == 0.0f || kind == 1.0f || kind == 2.0f) && std::isfinite(v[3]) &&
              v[3] > 0.0f,
          DIFFUSE_ROWS);
    }
    return {};
}

Verdict validate_copy_out(const pbf_buffer& source, uint64_t out_bytes) {
    V(valid_source(source), COPY_SOURCE);
    const uint32_t elem = World::element_bytes(source);  // source is valid
    if (out_bytes % elem != 0) return Verdict{Check::COPY_OUT_SIZE, elem};
    return {};
}

Verdict validate_gravity(const float g[3]) {
    V(g != nullptr && finite3(g), GRAVITY);
    return {};
}

Verdict validate_block_desc(const pbf_block_desc& d) {
    V(finite3(d.box_min) && finite3(d.box_max) && finite3(d.velocity), BLOCK_FINITE);
    for (int a = 0; a < 3; ++a) V(d.box_max[a] > d.box_min[a], BLOCK_BOX);
    return {};
}

Verdict validate_emitter_desc(const pbf_emitter_desc& d) {
    V(d.enabled <= 1, EMITTER_ENABLED);
    if (raw(d.type) == PBF_EMITTER_NOZZLE) {
        V(finite3(d.position) && finite3(d.direction), NOZZLE_FINITE);
        const float len2 =
            d.direction[0] * d.direction[0] + d.direction[1] * d.direction[1] + d.direction[2] * d.direction[2];
        V(len2 > 1e-12f, NOZZLE_DIRECTION);
        V(std::isfinite(d.speed) && d.speed > 0.0f, NOZZLE_SPEED);
        V(std::isfinite(d.radius) && d.radius > 0.0f, NOZZLE_RADIUS);
        V(std::isfinite(d.particles_per_second) && d.particles_per_second > 0.0f && d.particles_per_second <= 1e9f,
          NOZZLE_RATE);
    } else if (raw(d.type) == PBF_EMITTER_DRAIN) {
        V(finite3(d.box_min) && finite3(d.box_max), DRAIN_FINITE);
        for (int a = 0; a < 3; ++a) V(d.box_max[a] > d.box_min[a], DRAIN_BOX);
    } else {
        return Verdict{Check::EMITTER_TYPE};
    }
    V(finite3(d.position) && finite3(d.direction) && std::isfinite(d.speed) && std::isfinite(d.radius) &&
          std::isfinite(d.particles_per_second) && finite3(d.box_min) && finite3(d.box_max),
      EMITTER_UNUSED_FINITE);
    return {};
}

Verdict validate_emitter_transform(const pbf_emitter_type* type, const float a[3], const float b[3]) {
    V(a && b && finite3(a) && finite3(b), TRANSFORM_FINITE);
    if (!type) return {};
    if (*type == PBF_EMITTER_NOZZLE) {
        V(std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]) > 1e-6f, NOZZLE_DIRECTION);
    } else {
        for (int k = 0; k < 3; ++k) V(b[k] > a[k], DRAIN_BOX);
    }
    return {};
}

Verdict validate_emitter_kind(pbf_emitter_type kind, pbf_emitter_type type) {
    V(kind == type, EMITTER_KIND);
    return {};
}

Verdict validate_collider_desc(const pbf_collider_desc& d) {
    V(raw(d.shape) >= PBF_SHAPE_PLANE && raw(d.shape) <= PBF_SHAPE_MESH, COLLIDER_SHAPE);
    V(raw(d.motion) == PBF_MOTION_STATIC || raw(d.motion) == PBF_MOTION_KINEMATIC, COLLIDER_MOTION);
    V(finite3(d.position) && finite_nonzero_quat(d.rotation), COLLIDER_POSE);
    V(in(d.friction, 0.0f, 1.0f), COLLIDER_FRICTION);
    if (d.shape == PBF_SHAPE_SPHERE || d.shape == PBF_SHAPE_CAPSULE)
        V(std::isfinite(d.radius) && d.radius > 0.0f, COLLIDER_RADIUS);
    if (d.shape == PBF_SHAPE_CAPSULE) V(std::isfinite(d.half_height) && d.half_height >= 0.0f, COLLIDER_HALF_HEIGHT);
    if (d.shape == PBF_SHAPE_BOX)
        V(finite3(d.half_extents) && d.half_extents[0] > 0.0f && d.half_extents[1] > 0.0f && d.half_extents[2] > 0.0f,
          COLLIDER_HALF_EXTENTS);
    V(std::isfinite(d.radius) && std::isfinite(d.half_height) && finite3(d.half_extents), COLLIDER_UNUSED_FINITE);
    V(d.dynamic <= 1, COLLIDER_DYNAMIC);
    V(finite3(d.center_of_mass), COLLIDER_CENTER);
    return {};
}

Verdict validate_collider_pose(const float position[3], const float rotation[4]) {
    V(position && rotation && finite3(position) && finite_nonzero_quat(rotation), COLLIDER_POSE);
    return {};
}

Verdict validate_mesh_desc(const pbf_mesh_desc& d) {
    V(d.vertices && d.vertex_count >= 3 && d.vertex_count <= (1u << 24), MESH_VERTICES);
    V(d.indices && d.triangle_count >= 1 && d.triangle_count <= (1u << 22), MESH_INDICES);
    V(d.closed <= 1, MESH_CLOSED);
    V(std::isfinite(d.thickness) && d.thickness >= 0.0f, MESH_THICKNESS);
    V(std::isfinite(d.cell_size) && d.cell_size >= 0.0f, MESH_CELL_SIZE);
    for (uint32_t k = 0; k < d.vertex_count; ++k)
        if (!finite3(d.vertices + 3 * k)) return Verdict{Check::MESH_VERTEX_FINITE, k};
    const uint64_t indices = uint64_t(d.triangle_count) * 3;
    for (uint64_t k = 0; k < indices; ++k)
        if (d.indices[k] >= d.vertex_count) return Verdict{Check::MESH_INDEX_RANGE, k, d.indices[k]};
    auto vertex = [&](uint32_t i) {
        return pbf::Vec3{d.vertices[3 * i], d.vertices[3 * i + 1], d.vertices[3 * i + 2]};
    };
    bool surface = false;
    for (uint64_t t = 0; t < indices && !surface; t += 3)
        surface = !pbf::triangle_degenerate(vertex(d.indices[t]), vertex(d.indices[t + 1]), vertex(d.indices[t + 2]));
    V(surface, MESH_DEGENERATE);
    return {};
}

Verdict validate_mesh_voxels(uint64_t voxels) {
    if (voxels * 8 > PBF_MAX_MESH_FIELD_BYTES || voxels > (uint64_t(1) << 40))
        return Verdict{Check::MESH_VOXELS, voxels, voxels > (uint64_t(1) << 40) ? ~uint64_t(0) : voxels * 8 >> 20};
    return {};
}

namespace {
// What pbf_gl_buffer_desc and pbf_d3d11_buffer_desc have in common, after the buffer itself;
// mode_ok / mode_check: the API's own modes.
template <class Desc>
Verdict validate_graphics_buffer_desc(const Desc& d, bool mode_ok, Check mode_check) {
    V(valid_source(d.source), COPY_SOURCE);
    V(raw(d.source) != PBF_BUFFER_MATERIALS, COPY_SOURCE_GRAPHICS);
    if (!mode_ok) return Verdict{mode_check};
    V(d.capacity > 0, COPY_CAPACITY);
    if (d.offset_bytes % element_alignment(d.source) != 0)
        return Verdict{Check::COPY_OFFSET_ALIGN, element_alignment(d.source)};
    V(d.draw_args_offset_bytes % 4 == 0, DRAW_ARGS_ALIGN);
    V(d.reserved0 == 0, RESERVED0);
    return {};
}
}  // namespace

Verdict validate_gl_buffer_desc(const pbf_gl_buffer_desc& d) {
    V(d.buffer != 0, GL_BUFFER_NAME);
    return validate_graphics_buffer_desc(d, valid_mode(d.mode), Check::COPY_MODE);
}

Verdict validate_d3d11_buffer_desc(const pbf_d3d11_buffer_desc& d) {
    V(d.buffer != nullptr, D3D11_BUFFER);
    // The D3D11 immediate context is the render thread's: no manual copy from any thread.
    const bool mode_ok = raw(d.mode) == PBF_COPY_ON_RENDER_EVENT || raw(d.mode) == PBF_COPY_ON_STEP;
    return validate_graphics_buffer_desc(d, mode_ok, Check::D3D11_COPY_MODE);
}

Verdict validate_external_buffer_desc(const pbf_external_buffer_desc& d) {
    V(raw(d.type) >= PBF_EXTERNAL_MEMORY_OPAQUE_FD && raw(d.type) <= PBF_EXTERNAL_MEMORY_D3D11_RESOURCE_KMT,
      EXTERNAL_TYPE);
    if (raw(d.type) == PBF_EXTERNAL_MEMORY_OPAQUE_FD)
        V(d.fd >= 0, HANDLE_FD);
    else
        V(d.win32_handle != nullptr, HANDLE_WIN32);
    V(d.dedicated <= 1, EXTERNAL_DEDICATED);
    V(valid_source(d.source), COPY_SOURCE);
    V(raw(d.source) != PBF_BUFFER_MATERIALS, COPY_SOURCE_GRAPHICS);
    V(valid_mode(d.mode), COPY_MODE);
    V(d.size_bytes > 0, EXTERNAL_SIZE);
    V(d.capacity > 0, COPY_CAPACITY);
    const uint64_t elem = World::element_bytes(d.source);
    if (d.offset_bytes % element_alignment(d.source) != 0)
        return Verdict{Check::COPY_OFFSET_ALIGN, element_alignment(d.source)};
    const uint64_t bytes = uint64_t(d.capacity) * elem;
    if (!(d.offset_bytes <= d.size_bytes && bytes <= d.size_bytes - d.offset_bytes))
        return Verdict{Check::EXTERNAL_RANGE, elem};
    V(d.write_draw_args <= 1, EXTERNAL_WRITE_DRAW_ARGS);
    if (d.write_draw_args) {
        V(d.draw_args_offset_bytes % 4 == 0, DRAW_ARGS_ALIGN);
        V(d.size_bytes >= 16 && d.draw_args_offset_bytes <= d.size_bytes - 16, DRAW_ARGS_RANGE);
        const uint64_t a0 = d.draw_args_offset_bytes, a1 = a0 + 16;
        V(a1 <= d.offset_bytes || a0 >= d.offset_bytes + bytes, DRAW_ARGS_OVERLAP);
    }
    V(d.reserved0 == 0, RESERVED0);
    return {};
}

Verdict validate_semaphore_desc(const pbf_semaphore_desc& d) {
    V(raw(d.type) >= PBF_SEMAPHORE_VULKAN_BINARY_FD && raw(d.type) <= PBF_SEMAPHORE_D3D12_FENCE, SEMAPHORE_TYPE);
    const bool fd_type =
        raw(d.type) == PBF_SEMAPHORE_VULKAN_BINARY_FD || raw(d.type) == PBF_SEMAPHORE_VULKAN_TIMELINE_FD;
    if (fd_type)
        V(d.fd >= 0, HANDLE_FD);
    else
        V(d.win32_handle != nullptr, HANDLE_WIN32);
    V(d.reserved0 == 0, RESERVED0);
    return {};
}

Verdict validate_external_sync(const pbf_external_sync& s) {
    V(s.reserved0 == 0, SYNC_RESERVED0);
    return {};
}

Verdict validate_material_desc(const pbf_material_desc& d, float world_rest_density, bool is_default) {
    if (is_default) V(d.rest_density == world_rest_density, MATERIAL_DEFAULT_DENSITY);
    V(in(d.rest_density, 0.1f * world_rest_density, 10.0f * world_rest_density), MATERIAL_REST_DENSITY);
    V(in(d.viscosity, 0.0f, 1.0f), MATERIAL_VISCOSITY);
    V(in(d.ldc_gain, 0.0f, 1.0f), MATERIAL_LDC_GAIN);
    V(in(d.surface_tension, 0.0f, 10000.0f), MATERIAL_SURFACE_TENSION);
    V(in(d.cohesion, 0.0f, 10000.0f), MATERIAL_COHESION);
    V(in(d.adhesion, 0.0f, 10000.0f), MATERIAL_ADHESION);
    V(in(d.color[0], 0.0f, 1.0f) && in(d.color[1], 0.0f, 1.0f) && in(d.color[2], 0.0f, 1.0f) &&
          in(d.color[3], 0.0f, 1.0f),
      MATERIAL_COLOR);
    V(d.reserved0 == 0, MATERIAL_RESERVED0);
    return {};
}

}  // namespace pbf::api
