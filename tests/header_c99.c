/* Compiled as strict C99 (-std=c99 -Wall -Wextra -pedantic -Werror): the public header is pure
 * C99, and the layout of every public struct is pinned. The C# bindings mirror these numbers;
 * changing one is an ABI break (bump PBF_VERSION_MAJOR). 64-bit targets only. */
#include <stddef.h>

#include "pbf_c_api.h"

#define PBF_STATIC_ASSERT(name, cond) typedef char pbf_static_assert_##name[(cond) ? 1 : -1]
#define SIZE_IS(T, n) PBF_STATIC_ASSERT(size_##T, sizeof(T) == (n))
#define OFFSET_IS(T, f, n) PBF_STATIC_ASSERT(offset_##T##_##f, offsetof(T, f) == (n))

PBF_STATIC_ASSERT(pointer_is_64_bit, sizeof(void*) == 8);
PBF_STATIC_ASSERT(enum_result_is_32_bit, sizeof(pbf_result) == 4);
PBF_STATIC_ASSERT(enum_backend_is_32_bit, sizeof(pbf_backend) == 4);
PBF_STATIC_ASSERT(enum_log_level_is_32_bit, sizeof(pbf_log_level) == 4);
PBF_STATIC_ASSERT(enum_emitter_type_is_32_bit, sizeof(pbf_emitter_type) == 4);
PBF_STATIC_ASSERT(enum_shape_is_32_bit, sizeof(pbf_collider_shape) == 4);
PBF_STATIC_ASSERT(enum_motion_is_32_bit, sizeof(pbf_collider_motion) == 4);
PBF_STATIC_ASSERT(enum_memory_is_32_bit, sizeof(pbf_memory_kind) == 4);

SIZE_IS(pbf_world_id, 8);
SIZE_IS(pbf_emitter_id, 8);
SIZE_IS(pbf_collider_id, 8);
SIZE_IS(pbf_mesh_id, 8);
SIZE_IS(pbf_solver_params, 64);
OFFSET_IS(pbf_solver_params, iterations, 4);
OFFSET_IS(pbf_solver_params, substeps, 8);
OFFSET_IS(pbf_solver_params, relaxation, 12);
OFFSET_IS(pbf_solver_params, scorr_k, 16);
OFFSET_IS(pbf_solver_params, scorr_n, 20);
OFFSET_IS(pbf_solver_params, scorr_dq, 24);
OFFSET_IS(pbf_solver_params, xsph_c, 28);
OFFSET_IS(pbf_solver_params, vorticity_epsilon, 32);
OFFSET_IS(pbf_solver_params, ldc_enabled, 36);
OFFSET_IS(pbf_solver_params, ldc_gain, 40);
OFFSET_IS(pbf_solver_params, max_speed, 44);
OFFSET_IS(pbf_solver_params, adaptive_error_target, 48);
OFFSET_IS(pbf_solver_params, max_substeps, 52);
OFFSET_IS(pbf_solver_params, substep_travel, 56);
OFFSET_IS(pbf_solver_params, sound_speed, 60);
SIZE_IS(pbf_render_params, 32);
OFFSET_IS(pbf_render_params, flags, 4);
OFFSET_IS(pbf_render_params, smoothing, 8);
OFFSET_IS(pbf_render_params, max_stretch, 12);
OFFSET_IS(pbf_render_params, scale, 16);
OFFSET_IS(pbf_render_params, isolated_scale, 20);
OFFSET_IS(pbf_render_params, min_neighbors, 24);
OFFSET_IS(pbf_render_params, reserved0, 28);
SIZE_IS(pbf_world_desc, 164);
OFFSET_IS(pbf_world_desc, header_version, 4);
OFFSET_IS(pbf_world_desc, backend, 8);
OFFSET_IS(pbf_world_desc, cuda_device, 12);
OFFSET_IS(pbf_world_desc, max_particles, 16);
OFFSET_IS(pbf_world_desc, particle_radius, 20);
OFFSET_IS(pbf_world_desc, rest_density, 24);
OFFSET_IS(pbf_world_desc, gravity, 28);
OFFSET_IS(pbf_world_desc, domain_min, 40);
OFFSET_IS(pbf_world_desc, domain_max, 52);
OFFSET_IS(pbf_world_desc, solver, 64);
OFFSET_IS(pbf_world_desc, render, 128);
SIZE_IS(pbf_world_info, 192);
OFFSET_IS(pbf_world_desc, max_colliders, 160);
OFFSET_IS(pbf_world_info, backend, 4);
OFFSET_IS(pbf_world_info, max_particles, 8);
OFFSET_IS(pbf_world_info, particle_radius, 12);
OFFSET_IS(pbf_world_info, rest_spacing, 16);
OFFSET_IS(pbf_world_info, kernel_radius, 20);
OFFSET_IS(pbf_world_info, particle_mass, 24);
OFFSET_IS(pbf_world_info, grid_cells, 28);
OFFSET_IS(pbf_world_info, device_bytes, 32);
OFFSET_IS(pbf_world_info, device_name, 40);
OFFSET_IS(pbf_world_info, render_flags, 168);
OFFSET_IS(pbf_world_info, reserved0, 172);
OFFSET_IS(pbf_world_info, render_bytes, 176);
OFFSET_IS(pbf_world_info, render_updates, 184);
SIZE_IS(pbf_step_stats, 64);
OFFSET_IS(pbf_step_stats, particle_count, 4);
OFFSET_IS(pbf_step_stats, step_index, 8);
OFFSET_IS(pbf_step_stats, emitted_total, 16);
OFFSET_IS(pbf_step_stats, drained_total, 24);
OFFSET_IS(pbf_step_stats, density_error_mean, 32);
OFFSET_IS(pbf_step_stats, density_error_max, 36);
OFFSET_IS(pbf_step_stats, kinetic_energy, 40);
OFFSET_IS(pbf_step_stats, step_time_ms, 44);
OFFSET_IS(pbf_step_stats, iterations, 48);
OFFSET_IS(pbf_step_stats, substeps, 52);
OFFSET_IS(pbf_step_stats, speed_clamps, 56);
OFFSET_IS(pbf_step_stats, reserved0, 60);
PBF_STATIC_ASSERT(profile_max_stages_is_16, PBF_PROFILE_MAX_STAGES == 16);
SIZE_IS(pbf_step_profile, 72);
OFFSET_IS(pbf_step_profile, stage_count, 4);
OFFSET_IS(pbf_step_profile, stage_ms, 8);
SIZE_IS(pbf_block_desc, 40);
OFFSET_IS(pbf_block_desc, box_min, 4);
OFFSET_IS(pbf_block_desc, box_max, 16);
OFFSET_IS(pbf_block_desc, velocity, 28);
SIZE_IS(pbf_emitter_desc, 72);
OFFSET_IS(pbf_emitter_desc, type, 4);
OFFSET_IS(pbf_emitter_desc, enabled, 8);
OFFSET_IS(pbf_emitter_desc, position, 12);
OFFSET_IS(pbf_emitter_desc, direction, 24);
OFFSET_IS(pbf_emitter_desc, speed, 36);
OFFSET_IS(pbf_emitter_desc, radius, 40);
OFFSET_IS(pbf_emitter_desc, particles_per_second, 44);
OFFSET_IS(pbf_emitter_desc, box_min, 48);
OFFSET_IS(pbf_emitter_desc, box_max, 60);
SIZE_IS(pbf_collider_desc, 88);
OFFSET_IS(pbf_collider_desc, mesh, 80);
OFFSET_IS(pbf_collider_desc, shape, 4);
OFFSET_IS(pbf_collider_desc, motion, 8);
OFFSET_IS(pbf_collider_desc, position, 12);
OFFSET_IS(pbf_collider_desc, rotation, 24);
OFFSET_IS(pbf_collider_desc, radius, 40);
OFFSET_IS(pbf_collider_desc, half_height, 44);
OFFSET_IS(pbf_collider_desc, half_extents, 48);
OFFSET_IS(pbf_collider_desc, friction, 60);
OFFSET_IS(pbf_collider_desc, dynamic, 64);
OFFSET_IS(pbf_collider_desc, center_of_mass, 68);
SIZE_IS(pbf_collider_force, 24);
SIZE_IS(pbf_mesh_desc, 48);
OFFSET_IS(pbf_mesh_desc, vertices, 8);
OFFSET_IS(pbf_mesh_desc, vertex_count, 16);
OFFSET_IS(pbf_mesh_desc, indices, 24);
OFFSET_IS(pbf_mesh_desc, triangle_count, 32);
OFFSET_IS(pbf_mesh_desc, closed, 36);
OFFSET_IS(pbf_mesh_desc, thickness, 40);
OFFSET_IS(pbf_mesh_desc, cell_size, 44);
OFFSET_IS(pbf_collider_force, torque, 12);
SIZE_IS(pbf_mapped_buffer, 32);
OFFSET_IS(pbf_mapped_buffer, memory, 4);
OFFSET_IS(pbf_mapped_buffer, data, 8);
OFFSET_IS(pbf_mapped_buffer, count, 16);
OFFSET_IS(pbf_mapped_buffer, stride_bytes, 20);
OFFSET_IS(pbf_mapped_buffer, reserved0, 24);
OFFSET_IS(pbf_mapped_buffer, reserved1, 28);

/* Interop (zero-copy rendering). */
PBF_STATIC_ASSERT(enum_buffer_is_32_bit, sizeof(pbf_buffer) == 4);
PBF_STATIC_ASSERT(enum_copy_mode_is_32_bit, sizeof(pbf_copy_mode) == 4);
PBF_STATIC_ASSERT(enum_external_memory_type_is_32_bit, sizeof(pbf_external_memory_type) == 4);
PBF_STATIC_ASSERT(enum_semaphore_type_is_32_bit, sizeof(pbf_semaphore_type) == 4);
SIZE_IS(pbf_gl_buffer_id, 8);
SIZE_IS(pbf_external_buffer_id, 8);
SIZE_IS(pbf_semaphore_id, 8);
SIZE_IS(pbf_device_buffers, 104);
OFFSET_IS(pbf_device_buffers, memory, 4);
OFFSET_IS(pbf_device_buffers, positions, 8);
OFFSET_IS(pbf_device_buffers, velocities, 16);
OFFSET_IS(pbf_device_buffers, ids, 24);
OFFSET_IS(pbf_device_buffers, density_ratio, 32);
OFFSET_IS(pbf_device_buffers, count_device, 40);
OFFSET_IS(pbf_device_buffers, cuda_stream, 48);
OFFSET_IS(pbf_device_buffers, count, 56);
OFFSET_IS(pbf_device_buffers, capacity, 60);
OFFSET_IS(pbf_device_buffers, vec4_stride_bytes, 64);
OFFSET_IS(pbf_device_buffers, id_stride_bytes, 68);
OFFSET_IS(pbf_device_buffers, cuda_device, 72);
OFFSET_IS(pbf_device_buffers, reserved0, 76);
OFFSET_IS(pbf_device_buffers, smoothed_positions, 80);
OFFSET_IS(pbf_device_buffers, anisotropy, 88);
OFFSET_IS(pbf_device_buffers, anisotropy_stride_bytes, 96);
OFFSET_IS(pbf_device_buffers, render_flags, 100);
SIZE_IS(pbf_gl_buffer_desc, 48);
OFFSET_IS(pbf_gl_buffer_desc, buffer, 4);
OFFSET_IS(pbf_gl_buffer_desc, source, 8);
OFFSET_IS(pbf_gl_buffer_desc, mode, 12);
OFFSET_IS(pbf_gl_buffer_desc, offset_bytes, 16);
OFFSET_IS(pbf_gl_buffer_desc, capacity, 24);
OFFSET_IS(pbf_gl_buffer_desc, draw_args_buffer, 28);
OFFSET_IS(pbf_gl_buffer_desc, draw_args_offset_bytes, 32);
OFFSET_IS(pbf_gl_buffer_desc, draw_args_vertices, 40);
OFFSET_IS(pbf_gl_buffer_desc, reserved0, 44);
SIZE_IS(pbf_external_buffer_desc, 72);
OFFSET_IS(pbf_external_buffer_desc, type, 4);
OFFSET_IS(pbf_external_buffer_desc, fd, 8);
OFFSET_IS(pbf_external_buffer_desc, dedicated, 12);
OFFSET_IS(pbf_external_buffer_desc, win32_handle, 16);
OFFSET_IS(pbf_external_buffer_desc, size_bytes, 24);
OFFSET_IS(pbf_external_buffer_desc, offset_bytes, 32);
OFFSET_IS(pbf_external_buffer_desc, source, 40);
OFFSET_IS(pbf_external_buffer_desc, mode, 44);
OFFSET_IS(pbf_external_buffer_desc, capacity, 48);
OFFSET_IS(pbf_external_buffer_desc, write_draw_args, 52);
OFFSET_IS(pbf_external_buffer_desc, draw_args_offset_bytes, 56);
OFFSET_IS(pbf_external_buffer_desc, draw_args_vertices, 64);
OFFSET_IS(pbf_external_buffer_desc, reserved0, 68);
SIZE_IS(pbf_semaphore_desc, 24);
OFFSET_IS(pbf_semaphore_desc, type, 4);
OFFSET_IS(pbf_semaphore_desc, fd, 8);
OFFSET_IS(pbf_semaphore_desc, reserved0, 12);
OFFSET_IS(pbf_semaphore_desc, win32_handle, 16);
SIZE_IS(pbf_external_sync, 40);
OFFSET_IS(pbf_external_sync, reserved0, 4);
OFFSET_IS(pbf_external_sync, wait_semaphore, 8);
OFFSET_IS(pbf_external_sync, wait_value, 16);
OFFSET_IS(pbf_external_sync, signal_semaphore, 24);
OFFSET_IS(pbf_external_sync, signal_value, 32);
SIZE_IS(pbf_interop_info, 336);
OFFSET_IS(pbf_interop_info, gl_buffers, 4);
OFFSET_IS(pbf_interop_info, external_buffers, 8);
OFFSET_IS(pbf_interop_info, semaphores, 12);
OFFSET_IS(pbf_interop_info, copies, 16);
OFFSET_IS(pbf_interop_info, render_events, 24);
OFFSET_IS(pbf_interop_info, last_copy_gpu_ms, 32);
OFFSET_IS(pbf_interop_info, last_copy_host_ms, 36);
OFFSET_IS(pbf_interop_info, last_render_event_result, 40);
OFFSET_IS(pbf_interop_info, pending_render_work, 44);
OFFSET_IS(pbf_interop_info, device_uuid, 48);
OFFSET_IS(pbf_interop_info, device_luid, 64);
OFFSET_IS(pbf_interop_info, device_node_mask, 72);
OFFSET_IS(pbf_interop_info, cuda_device, 76);
OFFSET_IS(pbf_interop_info, last_render_event_message, 80);

/* The header's inline defaults compile as C99 and are usable from C. */
int pbf_header_c99_defaults_ok(void);
int pbf_header_c99_defaults_ok(void) {
    pbf_world_desc w = pbf_world_desc_default();
    pbf_block_desc b = pbf_block_desc_default();
    pbf_emitter_desc e = pbf_emitter_desc_default();
    pbf_collider_desc c = pbf_collider_desc_default();
    pbf_solver_params p = pbf_solver_params_default();
    pbf_render_params r = pbf_render_params_default();
    return r.struct_size == sizeof r && r.flags == 0 && w.render.struct_size == sizeof r && w.struct_size == sizeof w && w.header_version == PBF_VERSION && b.struct_size == sizeof b &&
           e.struct_size == sizeof e && c.struct_size == sizeof c && p.struct_size == sizeof p &&
           p.iterations == 4;
}

/* The interop section's inline defaults compile as C99 too. */
int pbf_header_c99_interop_defaults_ok(void);
int pbf_header_c99_interop_defaults_ok(void) {
    pbf_gl_buffer_desc g = pbf_gl_buffer_desc_default();
    pbf_external_buffer_desc x = pbf_external_buffer_desc_default();
    pbf_semaphore_desc s = pbf_semaphore_desc_default();
    pbf_external_sync y = pbf_external_sync_default();
    pbf_render_event_fn f = pbf_get_render_event_func();
    return g.struct_size == sizeof g && g.mode == PBF_COPY_ON_STEP && x.struct_size == sizeof x && x.fd == -1 &&
           s.struct_size == sizeof s && y.struct_size == sizeof y && f != NULL;
}
