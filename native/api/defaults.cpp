// Every default of the C ABI in one place (after Box2D's src/types.c): the *_init functions
// that fill descs and parameters, which the header's *_default() inlines call.
#include <cstring>

#include "api_common.h"

using pbf::api::check_struct;

namespace {
// The start of an *_init: checks the caller's struct_size, zeroes *d and sets its struct_size.
template <class T>
pbf_result start(const char* fn, const char* type, T* d, uint32_t struct_size) {
    if (pbf_result r = check_struct(fn, type, d, struct_size, sizeof(T)); r != PBF_OK) return r;
    std::memset(d, 0, sizeof *d);
    d->struct_size = sizeof *d;
    return PBF_OK;
}
}  // namespace

extern "C" {

PBF_API pbf_result PBF_CALL pbf_solver_params_init(pbf_solver_params* p, uint32_t struct_size) {
    const char* fn = __func__;
    if (pbf_result r = check_struct(fn, "pbf_solver_params", p, struct_size, sizeof(pbf_solver_params)); r != PBF_OK)
        return r;
    std::memset(p, 0, sizeof *p);
    p->struct_size = sizeof *p;
    p->iterations = 4;
    p->substeps = 0;
    p->max_substeps = 16;
    p->substep_travel = 0.5f;
    p->sound_speed = 40.0f;
    p->relaxation = 1.0f;
    p->scorr_k = 0.1f;
    p->scorr_n = 4.0f;
    p->scorr_dq = 0.2f;
    p->xsph_c = 0.01f;
    p->vorticity_epsilon = 0.0005f;
    p->ldc_enabled = 1;
    p->ldc_gain = 0.3f;
    p->max_speed = 100.0f;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_world_desc_init(pbf_world_desc* d, uint32_t struct_size, uint32_t header_version) {
    const char* fn = __func__;
    if (pbf_result r = check_struct(fn, "pbf_world_desc", d, struct_size, sizeof(pbf_world_desc)); r != PBF_OK)
        return r;
    std::memset(d, 0, sizeof *d);
    d->struct_size = sizeof *d;
    d->header_version = header_version;
    d->backend = PBF_BACKEND_AUTO;
    d->cuda_device = 0;
    d->max_particles = 65536;
    d->particle_radius = 0.025f;
    d->rest_density = 1000.0f;
    d->gravity[1] = -9.81f;
    const float lo[3] = {-1.0f, 0.0f, -1.0f}, hi[3] = {1.0f, 2.0f, 1.0f};
    std::memcpy(d->domain_min, lo, sizeof lo);
    std::memcpy(d->domain_max, hi, sizeof hi);
    d->max_colliders = 256;
    d->walls = 1;
    d->solver.struct_size = sizeof d->solver;
    if (pbf_result r = pbf_solver_params_init(&d->solver, d->solver.struct_size); r != PBF_OK) return r;
    d->render.struct_size = sizeof d->render;
    if (pbf_result r = pbf_render_params_init(&d->render, d->render.struct_size); r != PBF_OK) return r;
    d->diffuse.struct_size = sizeof d->diffuse;
    return pbf_diffuse_params_init(&d->diffuse, d->diffuse.struct_size);
}

// Thresholds and rates chosen on the dam break of tests/test_diffuse.cpp (a 0.4 m column: front
// speeds 2-3 m/s) so that its front sprays and foams and a resting tank makes nothing; Ihmsen et
// al. tune theirs per scene. Classification at 6 and 20 neighbours is theirs.
PBF_API pbf_result PBF_CALL pbf_diffuse_params_init(pbf_diffuse_params* p, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_diffuse_params", p, struct_size); r != PBF_OK) return r;
    p->max_diffuse = 0;
    p->trapped_air_min = 2.0f;
    p->trapped_air_max = 8.0f;
    p->wave_crest_min = 1.0f;
    p->wave_crest_max = 4.0f;
    p->energy_min = 0.5f;
    p->energy_max = 4.0f;
    p->trapped_air_rate = 200.0f;
    p->wave_crest_rate = 200.0f;
    p->lifetime = 2.0f;
    p->spray_max_neighbors = 6;
    p->bubble_min_neighbors = 20;
    p->buoyancy = 0.5f;
    p->bubble_drag = 20.0f;
    p->spray_drag = 0.5f;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_render_params_init(pbf_render_params* p, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_render_params", p, struct_size); r != PBF_OK) return r;
    p->flags = 0;
    p->smoothing = 0.9f;
    p->max_stretch = 4.0f;     // Yu & Turk's k_r
    p->scale = 1.0f;           // k_s, relative to a rest lattice
    p->isolated_scale = 0.5f;  // Yu & Turk's k_n
    p->min_neighbors = 6;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_block_desc_init(pbf_block_desc* d, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_block_desc", d, struct_size); r != PBF_OK) return r;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_emitter_desc_init(pbf_emitter_desc* d, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_emitter_desc", d, struct_size); r != PBF_OK) return r;
    d->enabled = 1;
    d->direction[1] = -1.0f;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_collider_desc_init(pbf_collider_desc* d, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_collider_desc", d, struct_size); r != PBF_OK) return r;
    d->motion = PBF_MOTION_STATIC;
    d->rotation[3] = 1.0f;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_material_desc_init(pbf_material_desc* d, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_material_desc", d, struct_size); r != PBF_OK) return r;
    d->rest_density = 1000.0f;
    d->viscosity = 0.01f;  // solver.xsph_c's default
    d->ldc_gain = 0.3f;    // solver.ldc_gain's default
    d->color[0] = 0.2f;
    d->color[1] = 0.45f;
    d->color[2] = 0.9f;
    d->color[3] = 1.0f;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_mesh_desc_init(pbf_mesh_desc* d, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_mesh_desc", d, struct_size); r != PBF_OK) return r;
    d->closed = 1;
    return PBF_OK;
}

// ---- interop descs ----------------------------------------------------------------------------
PBF_API pbf_result PBF_CALL pbf_gl_buffer_desc_init(pbf_gl_buffer_desc* d, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_gl_buffer_desc", d, struct_size); r != PBF_OK) return r;
    d->source = PBF_BUFFER_POSITIONS;
    d->mode = PBF_COPY_ON_STEP;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_d3d11_buffer_desc_init(pbf_d3d11_buffer_desc* d, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_d3d11_buffer_desc", d, struct_size); r != PBF_OK) return r;
    d->source = PBF_BUFFER_POSITIONS;
    d->mode = PBF_COPY_ON_RENDER_EVENT;  // the D3D11 device context is the render thread's
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_external_buffer_desc_init(pbf_external_buffer_desc* d, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_external_buffer_desc", d, struct_size); r != PBF_OK) return r;
    d->fd = -1;
    d->source = PBF_BUFFER_POSITIONS;
    d->mode = PBF_COPY_MANUAL;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_semaphore_desc_init(pbf_semaphore_desc* d, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_semaphore_desc", d, struct_size); r != PBF_OK) return r;
    d->fd = -1;
    return PBF_OK;
}

PBF_API pbf_result PBF_CALL pbf_external_sync_init(pbf_external_sync* s, uint32_t struct_size) {
    if (pbf_result r = start(__func__, "pbf_external_sync", s, struct_size); r != PBF_OK) return r;
    return PBF_OK;
}

}  // extern "C"
