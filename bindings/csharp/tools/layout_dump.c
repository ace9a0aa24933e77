/* Prints the layout of every struct, the value of every enum constant and the version and
 * interop macros of include/pbf_c_api.h, one fact a line, for the C# layout parity test
 * (tests/LayoutTests.cs):
 *
 *   const  NAME VALUE
 *   enum   TYPE NAME VALUE
 *   struct TYPE SIZE
 *   field  TYPE NAME OFFSET SIZE
 *
 * Built and run by run_tests.sh against the header as it is at test time:
 *   cc -std=c99 -I include bindings/csharp/tools/layout_dump.c -o layout_dump && ./layout_dump
 * When the header gains a struct, field or enum constant, add it here: a new field changes its
 * struct's size, which the test already catches, and the listing below names what moved. */
#include <stddef.h>
#include <stdio.h>

#include "pbf_c_api.h"

#define CONST(name) printf("const %s %lu\n", #name, (unsigned long)(name))
#define ENUM(type, name) printf("enum %s %s %ld\n", #type, #name, (long)(name))
#define STRUCT(type) printf("struct %s %lu\n", #type, (unsigned long)sizeof(type))
#define FIELD(type, name) \
    printf("field %s %s %lu %lu\n", #type, #name, (unsigned long)offsetof(type, name), \
           (unsigned long)sizeof(((type*)0)->name))

int main(void) {
    CONST(PBF_VERSION_MAJOR);
    CONST(PBF_VERSION_MINOR);
    CONST(PBF_VERSION_PATCH);
    CONST(PBF_VERSION);
    CONST(PBF_PROFILE_MAX_STAGES);
    CONST(PBF_INTEROP_SUPPORT_CUDA);
    CONST(PBF_INTEROP_SUPPORT_OPENGL);
    CONST(PBF_INTEROP_SUPPORT_EXTERNAL_FD);
    CONST(PBF_INTEROP_SUPPORT_EXTERNAL_WIN32);
    CONST(PBF_MAP_NO_WAIT);
    CONST(PBF_RENDER_SMOOTHED_POSITIONS);
    CONST(PBF_RENDER_ANISOTROPY);
    CONST(PBF_DIFFUSE_SPRAY);
    CONST(PBF_DIFFUSE_FOAM);
    CONST(PBF_DIFFUSE_BUBBLE);
    CONST(PBF_COUNT_ON_DEVICE);
    CONST(PBF_RENDER_EVENT_ALL_WORLDS);
    CONST(PBF_MAX_MATERIALS);
    CONST(PBF_MAX_SUBSTEPS);
    CONST(PBF_MAX_COLLIDERS);
    CONST(PBF_MAX_MESHES);
    CONST(PBF_MAX_MESH_FIELD_BYTES);

    ENUM(pbf_result, PBF_OK);
    ENUM(pbf_result, PBF_ERROR_INVALID_ARGUMENT);
    ENUM(pbf_result, PBF_ERROR_INVALID_HANDLE);
    ENUM(pbf_result, PBF_ERROR_STRUCT_SIZE);
    ENUM(pbf_result, PBF_ERROR_VERSION_MISMATCH);
    ENUM(pbf_result, PBF_ERROR_CAPACITY);
    ENUM(pbf_result, PBF_ERROR_OUT_OF_MEMORY);
    ENUM(pbf_result, PBF_ERROR_BACKEND_UNAVAILABLE);
    ENUM(pbf_result, PBF_ERROR_BACKEND);
    ENUM(pbf_result, PBF_ERROR_INVALID_STATE);
    ENUM(pbf_result, PBF_ERROR_INTERNAL);
    ENUM(pbf_result, PBF_RESULT_FORCE32);

    ENUM(pbf_log_level, PBF_LOG_DEBUG);
    ENUM(pbf_log_level, PBF_LOG_INFO);
    ENUM(pbf_log_level, PBF_LOG_WARNING);
    ENUM(pbf_log_level, PBF_LOG_ERROR);
    ENUM(pbf_log_level, PBF_LOG_LEVEL_FORCE32);

    ENUM(pbf_backend, PBF_BACKEND_AUTO);
    ENUM(pbf_backend, PBF_BACKEND_CPU);
    ENUM(pbf_backend, PBF_BACKEND_CUDA);
    ENUM(pbf_backend, PBF_BACKEND_FORCE32);

    ENUM(pbf_emitter_type, PBF_EMITTER_NOZZLE);
    ENUM(pbf_emitter_type, PBF_EMITTER_DRAIN);
    ENUM(pbf_emitter_type, PBF_EMITTER_TYPE_FORCE32);

    ENUM(pbf_collider_shape, PBF_SHAPE_PLANE);
    ENUM(pbf_collider_shape, PBF_SHAPE_SPHERE);
    ENUM(pbf_collider_shape, PBF_SHAPE_CAPSULE);
    ENUM(pbf_collider_shape, PBF_SHAPE_BOX);
    ENUM(pbf_collider_shape, PBF_SHAPE_MESH);
    ENUM(pbf_collider_shape, PBF_SHAPE_FORCE32);

    ENUM(pbf_collider_motion, PBF_MOTION_STATIC);
    ENUM(pbf_collider_motion, PBF_MOTION_KINEMATIC);
    ENUM(pbf_collider_motion, PBF_MOTION_FORCE32);

    ENUM(pbf_memory_kind, PBF_MEMORY_HOST);
    ENUM(pbf_memory_kind, PBF_MEMORY_CUDA_DEVICE);
    ENUM(pbf_memory_kind, PBF_MEMORY_KIND_FORCE32);

    ENUM(pbf_buffer, PBF_BUFFER_POSITIONS);
    ENUM(pbf_buffer, PBF_BUFFER_VELOCITIES);
    ENUM(pbf_buffer, PBF_BUFFER_IDS);
    ENUM(pbf_buffer, PBF_BUFFER_SMOOTHED_POSITIONS);
    ENUM(pbf_buffer, PBF_BUFFER_ANISOTROPY);
    ENUM(pbf_buffer, PBF_BUFFER_DIFFUSE_POSITIONS);
    ENUM(pbf_buffer, PBF_BUFFER_DIFFUSE_VELOCITIES);
    ENUM(pbf_buffer, PBF_BUFFER_MATERIALS);
    ENUM(pbf_buffer, PBF_BUFFER_FORCE32);

    ENUM(pbf_copy_mode, PBF_COPY_ON_STEP);
    ENUM(pbf_copy_mode, PBF_COPY_ON_RENDER_EVENT);
    ENUM(pbf_copy_mode, PBF_COPY_MANUAL);
    ENUM(pbf_copy_mode, PBF_COPY_MODE_FORCE32);

    ENUM(pbf_external_memory_type, PBF_EXTERNAL_MEMORY_OPAQUE_FD);
    ENUM(pbf_external_memory_type, PBF_EXTERNAL_MEMORY_OPAQUE_WIN32);
    ENUM(pbf_external_memory_type, PBF_EXTERNAL_MEMORY_OPAQUE_WIN32_KMT);
    ENUM(pbf_external_memory_type, PBF_EXTERNAL_MEMORY_D3D12_RESOURCE);
    ENUM(pbf_external_memory_type, PBF_EXTERNAL_MEMORY_D3D11_RESOURCE);
    ENUM(pbf_external_memory_type, PBF_EXTERNAL_MEMORY_D3D11_RESOURCE_KMT);
    ENUM(pbf_external_memory_type, PBF_EXTERNAL_MEMORY_TYPE_FORCE32);

    ENUM(pbf_semaphore_type, PBF_SEMAPHORE_VULKAN_BINARY_FD);
    ENUM(pbf_semaphore_type, PBF_SEMAPHORE_VULKAN_TIMELINE_FD);
    ENUM(pbf_semaphore_type, PBF_SEMAPHORE_VULKAN_BINARY_WIN32);
    ENUM(pbf_semaphore_type, PBF_SEMAPHORE_VULKAN_BINARY_WIN32_KMT);
    ENUM(pbf_semaphore_type, PBF_SEMAPHORE_VULKAN_TIMELINE_WIN32);
    ENUM(pbf_semaphore_type, PBF_SEMAPHORE_D3D12_FENCE);
    ENUM(pbf_semaphore_type, PBF_SEMAPHORE_TYPE_FORCE32);

    /* The enums themselves are struct fields; their size must be 4 in C as in C#. */
    printf("enumsize pbf_result %lu\n", (unsigned long)sizeof(pbf_result));
    printf("enumsize pbf_log_level %lu\n", (unsigned long)sizeof(pbf_log_level));
    printf("enumsize pbf_backend %lu\n", (unsigned long)sizeof(pbf_backend));
    printf("enumsize pbf_emitter_type %lu\n", (unsigned long)sizeof(pbf_emitter_type));
    printf("enumsize pbf_collider_shape %lu\n", (unsigned long)sizeof(pbf_collider_shape));
    printf("enumsize pbf_collider_motion %lu\n", (unsigned long)sizeof(pbf_collider_motion));
    printf("enumsize pbf_memory_kind %lu\n", (unsigned long)sizeof(pbf_memory_kind));
    printf("enumsize pbf_buffer %lu\n", (unsigned long)sizeof(pbf_buffer));
    printf("enumsize pbf_copy_mode %lu\n", (unsigned long)sizeof(pbf_copy_mode));
    printf("enumsize pbf_external_memory_type %lu\n", (unsigned long)sizeof(pbf_external_memory_type));
    printf("enumsize pbf_semaphore_type %lu\n", (unsigned long)sizeof(pbf_semaphore_type));

    STRUCT(pbf_world_id);
    FIELD(pbf_world_id, index);
    FIELD(pbf_world_id, generation);

    STRUCT(pbf_emitter_id);
    FIELD(pbf_emitter_id, index);
    FIELD(pbf_emitter_id, generation);

    STRUCT(pbf_collider_id);
    FIELD(pbf_collider_id, index);
    FIELD(pbf_collider_id, generation);

    STRUCT(pbf_solver_params);
    FIELD(pbf_solver_params, struct_size);
    FIELD(pbf_solver_params, iterations);
    FIELD(pbf_solver_params, substeps);
    FIELD(pbf_solver_params, relaxation);
    FIELD(pbf_solver_params, scorr_k);
    FIELD(pbf_solver_params, scorr_n);
    FIELD(pbf_solver_params, scorr_dq);
    FIELD(pbf_solver_params, xsph_c);
    FIELD(pbf_solver_params, vorticity_epsilon);
    FIELD(pbf_solver_params, ldc_enabled);
    FIELD(pbf_solver_params, ldc_gain);
    FIELD(pbf_solver_params, max_speed);
    FIELD(pbf_solver_params, adaptive_error_target);
    FIELD(pbf_solver_params, max_substeps);
    FIELD(pbf_solver_params, substep_travel);
    FIELD(pbf_solver_params, sound_speed);

    STRUCT(pbf_render_params);
    FIELD(pbf_render_params, struct_size);
    FIELD(pbf_render_params, flags);
    FIELD(pbf_render_params, smoothing);
    FIELD(pbf_render_params, max_stretch);
    FIELD(pbf_render_params, scale);
    FIELD(pbf_render_params, isolated_scale);
    FIELD(pbf_render_params, min_neighbors);
    FIELD(pbf_render_params, reserved0);
    STRUCT(pbf_world_desc);
    FIELD(pbf_world_desc, struct_size);
    FIELD(pbf_world_desc, header_version);
    FIELD(pbf_world_desc, backend);
    FIELD(pbf_world_desc, cuda_device);
    FIELD(pbf_world_desc, max_particles);
    FIELD(pbf_world_desc, particle_radius);
    FIELD(pbf_world_desc, rest_density);
    FIELD(pbf_world_desc, gravity);
    FIELD(pbf_world_desc, domain_min);
    FIELD(pbf_world_desc, domain_max);
    FIELD(pbf_world_desc, solver);
    FIELD(pbf_world_desc, render);
    FIELD(pbf_world_desc, max_colliders);
    FIELD(pbf_world_desc, diffuse);
    FIELD(pbf_world_desc, walls);
    FIELD(pbf_world_desc, hashed_grid);
    STRUCT(pbf_diffuse_params);
    FIELD(pbf_diffuse_params, struct_size);
    FIELD(pbf_diffuse_params, max_diffuse);
    FIELD(pbf_diffuse_params, trapped_air_min);
    FIELD(pbf_diffuse_params, trapped_air_max);
    FIELD(pbf_diffuse_params, wave_crest_min);
    FIELD(pbf_diffuse_params, wave_crest_max);
    FIELD(pbf_diffuse_params, energy_min);
    FIELD(pbf_diffuse_params, energy_max);
    FIELD(pbf_diffuse_params, trapped_air_rate);
    FIELD(pbf_diffuse_params, wave_crest_rate);
    FIELD(pbf_diffuse_params, lifetime);
    FIELD(pbf_diffuse_params, spray_max_neighbors);
    FIELD(pbf_diffuse_params, bubble_min_neighbors);
    FIELD(pbf_diffuse_params, buoyancy);
    FIELD(pbf_diffuse_params, bubble_drag);
    FIELD(pbf_diffuse_params, spray_drag);

    STRUCT(pbf_world_info);
    FIELD(pbf_world_info, struct_size);
    FIELD(pbf_world_info, backend);
    FIELD(pbf_world_info, max_particles);
    FIELD(pbf_world_info, particle_radius);
    FIELD(pbf_world_info, rest_spacing);
    FIELD(pbf_world_info, kernel_radius);
    FIELD(pbf_world_info, particle_mass);
    FIELD(pbf_world_info, grid_cells);
    FIELD(pbf_world_info, device_bytes);
    FIELD(pbf_world_info, device_name);
    FIELD(pbf_world_info, render_flags);
    FIELD(pbf_world_info, reserved0);
    FIELD(pbf_world_info, render_bytes);
    FIELD(pbf_world_info, render_updates);
    FIELD(pbf_world_info, diffuse_capacity);
    FIELD(pbf_world_info, reserved1);
    FIELD(pbf_world_info, diffuse_bytes);
    FIELD(pbf_world_info, diffuse_updates);
    FIELD(pbf_world_info, grid_hashed);
    FIELD(pbf_world_info, reserved2);
    FIELD(pbf_world_info, grid_bytes);

    STRUCT(pbf_step_stats);
    FIELD(pbf_step_stats, struct_size);
    FIELD(pbf_step_stats, particle_count);
    FIELD(pbf_step_stats, step_index);
    FIELD(pbf_step_stats, emitted_total);
    FIELD(pbf_step_stats, drained_total);
    FIELD(pbf_step_stats, density_error_mean);
    FIELD(pbf_step_stats, density_error_max);
    FIELD(pbf_step_stats, kinetic_energy);
    FIELD(pbf_step_stats, step_time_ms);
    FIELD(pbf_step_stats, iterations);
    FIELD(pbf_step_stats, substeps);
    FIELD(pbf_step_stats, speed_clamps);
    FIELD(pbf_step_stats, reserved0);
    FIELD(pbf_step_stats, diffuse_count);
    FIELD(pbf_step_stats, diffuse_dropped);
    FIELD(pbf_step_stats, diffuse_generated_total);
    FIELD(pbf_step_stats, diffuse_dropped_total);

    STRUCT(pbf_step_profile);
    FIELD(pbf_step_profile, struct_size);
    FIELD(pbf_step_profile, stage_count);
    FIELD(pbf_step_profile, stage_ms);

    STRUCT(pbf_block_desc);
    FIELD(pbf_block_desc, struct_size);
    FIELD(pbf_block_desc, box_min);
    FIELD(pbf_block_desc, box_max);
    FIELD(pbf_block_desc, velocity);
    FIELD(pbf_block_desc, material);

    STRUCT(pbf_emitter_desc);
    FIELD(pbf_emitter_desc, struct_size);
    FIELD(pbf_emitter_desc, type);
    FIELD(pbf_emitter_desc, enabled);
    FIELD(pbf_emitter_desc, position);
    FIELD(pbf_emitter_desc, direction);
    FIELD(pbf_emitter_desc, speed);
    FIELD(pbf_emitter_desc, radius);
    FIELD(pbf_emitter_desc, particles_per_second);
    FIELD(pbf_emitter_desc, box_min);
    FIELD(pbf_emitter_desc, box_max);
    FIELD(pbf_emitter_desc, material);

    STRUCT(pbf_material_id);
    FIELD(pbf_material_id, index);
    FIELD(pbf_material_id, generation);

    STRUCT(pbf_material_desc);
    FIELD(pbf_material_desc, struct_size);
    FIELD(pbf_material_desc, rest_density);
    FIELD(pbf_material_desc, viscosity);
    FIELD(pbf_material_desc, ldc_gain);
    FIELD(pbf_material_desc, surface_tension);
    FIELD(pbf_material_desc, cohesion);
    FIELD(pbf_material_desc, adhesion);
    FIELD(pbf_material_desc, color);
    FIELD(pbf_material_desc, user_id);
    FIELD(pbf_material_desc, reserved0);

    STRUCT(pbf_collider_desc);
    FIELD(pbf_collider_desc, struct_size);
    FIELD(pbf_collider_desc, shape);
    FIELD(pbf_collider_desc, motion);
    FIELD(pbf_collider_desc, position);
    FIELD(pbf_collider_desc, rotation);
    FIELD(pbf_collider_desc, radius);
    FIELD(pbf_collider_desc, half_height);
    FIELD(pbf_collider_desc, half_extents);
    FIELD(pbf_collider_desc, friction);
    FIELD(pbf_collider_desc, dynamic);
    FIELD(pbf_collider_desc, center_of_mass);
    FIELD(pbf_collider_desc, mesh);

    STRUCT(pbf_mesh_id);
    FIELD(pbf_mesh_id, index);
    FIELD(pbf_mesh_id, generation);
    STRUCT(pbf_mesh_desc);
    FIELD(pbf_mesh_desc, struct_size);
    FIELD(pbf_mesh_desc, vertices);
    FIELD(pbf_mesh_desc, vertex_count);
    FIELD(pbf_mesh_desc, indices);
    FIELD(pbf_mesh_desc, triangle_count);
    FIELD(pbf_mesh_desc, closed);
    FIELD(pbf_mesh_desc, thickness);
    FIELD(pbf_mesh_desc, cell_size);

    STRUCT(pbf_collider_force);
    FIELD(pbf_collider_force, force);
    FIELD(pbf_collider_force, torque);

    STRUCT(pbf_mapped_buffer);
    FIELD(pbf_mapped_buffer, struct_size);
    FIELD(pbf_mapped_buffer, memory);
    FIELD(pbf_mapped_buffer, data);
    FIELD(pbf_mapped_buffer, count);
    FIELD(pbf_mapped_buffer, stride_bytes);
    FIELD(pbf_mapped_buffer, reserved0);
    FIELD(pbf_mapped_buffer, reserved1);

    /* The interop section. */
    STRUCT(pbf_gl_buffer_id);
    FIELD(pbf_gl_buffer_id, index);
    FIELD(pbf_gl_buffer_id, generation);

    STRUCT(pbf_external_buffer_id);
    FIELD(pbf_external_buffer_id, index);
    FIELD(pbf_external_buffer_id, generation);

    STRUCT(pbf_semaphore_id);
    FIELD(pbf_semaphore_id, index);
    FIELD(pbf_semaphore_id, generation);

    STRUCT(pbf_device_buffers);
    FIELD(pbf_device_buffers, struct_size);
    FIELD(pbf_device_buffers, memory);
    FIELD(pbf_device_buffers, positions);
    FIELD(pbf_device_buffers, velocities);
    FIELD(pbf_device_buffers, ids);
    FIELD(pbf_device_buffers, density_ratio);
    FIELD(pbf_device_buffers, count_device);
    FIELD(pbf_device_buffers, cuda_stream);
    FIELD(pbf_device_buffers, count);
    FIELD(pbf_device_buffers, capacity);
    FIELD(pbf_device_buffers, vec4_stride_bytes);
    FIELD(pbf_device_buffers, id_stride_bytes);
    FIELD(pbf_device_buffers, cuda_device);
    FIELD(pbf_device_buffers, reserved0);
    FIELD(pbf_device_buffers, smoothed_positions);
    FIELD(pbf_device_buffers, anisotropy);
    FIELD(pbf_device_buffers, anisotropy_stride_bytes);
    FIELD(pbf_device_buffers, render_flags);
    FIELD(pbf_device_buffers, diffuse_positions);
    FIELD(pbf_device_buffers, diffuse_velocities);
    FIELD(pbf_device_buffers, diffuse_count_device);
    FIELD(pbf_device_buffers, diffuse_count);
    FIELD(pbf_device_buffers, diffuse_capacity);
    FIELD(pbf_device_buffers, materials);

    STRUCT(pbf_gl_buffer_desc);
    FIELD(pbf_gl_buffer_desc, struct_size);
    FIELD(pbf_gl_buffer_desc, buffer);
    FIELD(pbf_gl_buffer_desc, source);
    FIELD(pbf_gl_buffer_desc, mode);
    FIELD(pbf_gl_buffer_desc, offset_bytes);
    FIELD(pbf_gl_buffer_desc, capacity);
    FIELD(pbf_gl_buffer_desc, draw_args_buffer);
    FIELD(pbf_gl_buffer_desc, draw_args_offset_bytes);
    FIELD(pbf_gl_buffer_desc, draw_args_vertices);
    FIELD(pbf_gl_buffer_desc, reserved0);

    STRUCT(pbf_external_buffer_desc);
    FIELD(pbf_external_buffer_desc, struct_size);
    FIELD(pbf_external_buffer_desc, type);
    FIELD(pbf_external_buffer_desc, fd);
    FIELD(pbf_external_buffer_desc, dedicated);
    FIELD(pbf_external_buffer_desc, win32_handle);
    FIELD(pbf_external_buffer_desc, size_bytes);
    FIELD(pbf_external_buffer_desc, offset_bytes);
    FIELD(pbf_external_buffer_desc, source);
    FIELD(pbf_external_buffer_desc, mode);
    FIELD(pbf_external_buffer_desc, capacity);
    FIELD(pbf_external_buffer_desc, write_draw_args);
    FIELD(pbf_external_buffer_desc, draw_args_offset_bytes);
    FIELD(pbf_external_buffer_desc, draw_args_vertices);
    FIELD(pbf_external_buffer_desc, reserved0);

    STRUCT(pbf_semaphore_desc);
    FIELD(pbf_semaphore_desc, struct_size);
    FIELD(pbf_semaphore_desc, type);
    FIELD(pbf_semaphore_desc, fd);
    FIELD(pbf_semaphore_desc, reserved0);
    FIELD(pbf_semaphore_desc, win32_handle);

    STRUCT(pbf_external_sync);
    FIELD(pbf_external_sync, struct_size);
    FIELD(pbf_external_sync, reserved0);
    FIELD(pbf_external_sync, wait_semaphore);
    FIELD(pbf_external_sync, wait_value);
    FIELD(pbf_external_sync, signal_semaphore);
    FIELD(pbf_external_sync, signal_value);

    STRUCT(pbf_interop_info);
    FIELD(pbf_interop_info, struct_size);
    FIELD(pbf_interop_info, gl_buffers);
    FIELD(pbf_interop_info, external_buffers);
    FIELD(pbf_interop_info, semaphores);
    FIELD(pbf_interop_info, copies);
    FIELD(pbf_interop_info, render_events);
    FIELD(pbf_interop_info, last_copy_gpu_ms);
    FIELD(pbf_interop_info, last_copy_host_ms);
    FIELD(pbf_interop_info, last_render_event_result);
    FIELD(pbf_interop_info, pending_render_work);
    FIELD(pbf_interop_info, device_uuid);
    FIELD(pbf_interop_info, device_luid);
    FIELD(pbf_interop_info, device_node_mask);
    FIELD(pbf_interop_info, cuda_device);
    FIELD(pbf_interop_info, last_render_event_message);

    return 0;
}
