// Raw layer: a one-to-one mirror of include/pbf_c_api.h (C ABI v1).
//
// Names, field order and field types follow the header exactly so that a reader can check the
// two side by side; tests/LayoutTests.cs compares every size and offset with the header at test
// time. Every struct here is blittable (no bool, char, string or array fields) and every
// signature passes only primitives, blittable structs, IntPtr, and ref/out to those, so no
// marshalling code runs: the same declarations work on .NET, Mono and IL2CPP.
//
// Pointer parameters that C allows to be NULL, or that tests need to pass as NULL, also have an
// IntPtr overload. Most code should use the friendly layer (namespace Pbf) instead.
using System;
using System.Runtime.InteropServices;

namespace Pbf.Interop
{
    // ---- Enums (all 32-bit, as the header's *_FORCE32 members force) -------------------------
    public enum pbf_result : int
    {
        PBF_OK = 0,
        PBF_ERROR_INVALID_ARGUMENT = 1,
        PBF_ERROR_INVALID_HANDLE = 2,
        PBF_ERROR_STRUCT_SIZE = 3,
        PBF_ERROR_VERSION_MISMATCH = 4,
        PBF_ERROR_CAPACITY = 5,
        PBF_ERROR_OUT_OF_MEMORY = 6,
        PBF_ERROR_BACKEND_UNAVAILABLE = 7,
        PBF_ERROR_BACKEND = 8,
        PBF_ERROR_INVALID_STATE = 9,
        PBF_ERROR_INTERNAL = 10,
        PBF_RESULT_FORCE32 = 0x7FFFFFFF,
    }

    public enum pbf_log_level : int
    {
        PBF_LOG_DEBUG = 0,
        PBF_LOG_INFO = 1,
        PBF_LOG_WARNING = 2,
        PBF_LOG_ERROR = 3,
        PBF_LOG_LEVEL_FORCE32 = 0x7FFFFFFF,
    }

    public enum pbf_backend : int
    {
        PBF_BACKEND_AUTO = 0,
        PBF_BACKEND_CPU = 1,
        PBF_BACKEND_CUDA = 2,
        PBF_BACKEND_FORCE32 = 0x7FFFFFFF,
    }

    public enum pbf_emitter_type : int
    {
        PBF_EMITTER_NOZZLE = 1,
        PBF_EMITTER_DRAIN = 2,
        PBF_EMITTER_TYPE_FORCE32 = 0x7FFFFFFF,
    }

    public enum pbf_collider_shape : int
    {
        PBF_SHAPE_PLANE = 1,
        PBF_SHAPE_SPHERE = 2,
        PBF_SHAPE_CAPSULE = 3,
        PBF_SHAPE_BOX = 4,
        PBF_SHAPE_MESH = 5,
        PBF_SHAPE_FORCE32 = 0x7FFFFFFF,
    }

    public enum pbf_collider_motion : int
    {
        PBF_MOTION_STATIC = 0,
        PBF_MOTION_KINEMATIC = 1,
        PBF_MOTION_FORCE32 = 0x7FFFFFFF,
    }

    public enum pbf_memory_kind : int
    {
        PBF_MEMORY_HOST = 1,
        PBF_MEMORY_CUDA_DEVICE = 2,
        PBF_MEMORY_KIND_FORCE32 = 0x7FFFFFFF,
    }

    // Interop section of the header.
    public enum pbf_buffer : int
    {
        PBF_BUFFER_POSITIONS = 1,
        PBF_BUFFER_VELOCITIES = 2,
        PBF_BUFFER_IDS = 3,
        PBF_BUFFER_SMOOTHED_POSITIONS = 4,
        PBF_BUFFER_ANISOTROPY = 5,
        PBF_BUFFER_DIFFUSE_POSITIONS = 6,
        PBF_BUFFER_DIFFUSE_VELOCITIES = 7,
        PBF_BUFFER_MATERIALS = 8,
        PBF_BUFFER_FORCE32 = 0x7FFFFFFF,
    }

    public enum pbf_copy_mode : int
    {
        PBF_COPY_ON_STEP = 1,
        PBF_COPY_ON_RENDER_EVENT = 2,
        PBF_COPY_MANUAL = 3,
        PBF_COPY_MODE_FORCE32 = 0x7FFFFFFF,
    }

    public enum pbf_external_memory_type : int
    {
        PBF_EXTERNAL_MEMORY_OPAQUE_FD = 1,
        PBF_EXTERNAL_MEMORY_OPAQUE_WIN32 = 2,
        PBF_EXTERNAL_MEMORY_OPAQUE_WIN32_KMT = 3,
        PBF_EXTERNAL_MEMORY_D3D12_RESOURCE = 4,
        PBF_EXTERNAL_MEMORY_D3D11_RESOURCE = 5,
        PBF_EXTERNAL_MEMORY_D3D11_RESOURCE_KMT = 6,
        PBF_EXTERNAL_MEMORY_TYPE_FORCE32 = 0x7FFFFFFF,
    }

    public enum pbf_semaphore_type : int
    {
        PBF_SEMAPHORE_VULKAN_BINARY_FD = 1,
        PBF_SEMAPHORE_VULKAN_TIMELINE_FD = 2,
        PBF_SEMAPHORE_VULKAN_BINARY_WIN32 = 3,
        PBF_SEMAPHORE_VULKAN_BINARY_WIN32_KMT = 4,
        PBF_SEMAPHORE_VULKAN_TIMELINE_WIN32 = 5,
        PBF_SEMAPHORE_D3D12_FENCE = 6,
        PBF_SEMAPHORE_TYPE_FORCE32 = 0x7FFFFFFF,
    }

    // ---- Fixed-size C arrays -------------------------------------------------------------------
    /// <summary>float[3] of the header.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct Float3
    {
        public float x, y, z;
        public Float3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
        public override string ToString() { return "(" + x + ", " + y + ", " + z + ")"; }
    }

    /// <summary>float[4] of the header (quaternions as x, y, z, w).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct Float4
    {
        public float x, y, z, w;
        public Float4(float x, float y, float z, float w) { this.x = x; this.y = y; this.z = z; this.w = w; }
    }

    /// <summary>char[128] of the header: a NUL-terminated UTF-8 string.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct Char128
    {
        public byte c000, c001, c002, c003, c004, c005, c006, c007, c008, c009, c010, c011, c012, c013, c014, c015;
        public byte c016, c017, c018, c019, c020, c021, c022, c023, c024, c025, c026, c027, c028, c029, c030, c031;
        public byte c032, c033, c034, c035, c036, c037, c038, c039, c040, c041, c042, c043, c044, c045, c046, c047;
        public byte c048, c049, c050, c051, c052, c053, c054, c055, c056, c057, c058, c059, c060, c061, c062, c063;
        public byte c064, c065, c066, c067, c068, c069, c070, c071, c072, c073, c074, c075, c076, c077, c078, c079;
        public byte c080, c081, c082, c083, c084, c085, c086, c087, c088, c089, c090, c091, c092, c093, c094, c095;
        public byte c096, c097, c098, c099, c100, c101, c102, c103, c104, c105, c106, c107, c108, c109, c110, c111;
        public byte c112, c113, c114, c115, c116, c117, c118, c119, c120, c121, c122, c123, c124, c125, c126, c127;

        public const int Length = 128;

        /// <summary>The bytes up to the first NUL (or all 128), decoded as UTF-8.</summary>
        public override string ToString()
        {
            Span<byte> bytes = MemoryMarshal.AsBytes(MemoryMarshal.CreateSpan(ref this, 1));
            int n = bytes.IndexOf((byte)0);
            if (n < 0) n = bytes.Length;
            return System.Text.Encoding.UTF8.GetString(bytes.Slice(0, n).ToArray());
        }
    }

    /// <summary>char[256] of the header: a NUL-terminated UTF-8 string.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct Char256
    {
        public Char128 first, second;

        public const int Length = 256;

        /// <summary>The bytes up to the first NUL (or all 256), decoded as UTF-8.</summary>
        public override string ToString()
        {
            Span<byte> bytes = MemoryMarshal.AsBytes(MemoryMarshal.CreateSpan(ref this, 1));
            int n = bytes.IndexOf((byte)0);
            if (n < 0) n = bytes.Length;
            return System.Text.Encoding.UTF8.GetString(bytes.Slice(0, n).ToArray());
        }
    }

    /// <summary>uint8_t[16] of the header (a device UUID).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct Bytes16
    {
        public byte b00, b01, b02, b03, b04, b05, b06, b07, b08, b09, b10, b11, b12, b13, b14, b15;

        public const int Length = 16;

        /// <summary>A copy of the 16 bytes.</summary>
        public byte[] ToArray() { return MemoryMarshal.AsBytes(MemoryMarshal.CreateSpan(ref this, 1)).ToArray(); }
    }

    /// <summary>uint8_t[8] of the header (a LUID).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct Bytes8
    {
        public byte b0, b1, b2, b3, b4, b5, b6, b7;

        public const int Length = 8;

        /// <summary>A copy of the 8 bytes.</summary>
        public byte[] ToArray() { return MemoryMarshal.AsBytes(MemoryMarshal.CreateSpan(ref this, 1)).ToArray(); }
    }

    // ---- Handles -------------------------------------------------------------------------------
    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_world_id
    {
        public uint index;
        public uint generation;
        public override string ToString() { return "{" + index + ", " + generation + "}"; }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_emitter_id
    {
        public uint index;
        public uint generation;
        public override string ToString() { return "{" + index + ", " + generation + "}"; }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_collider_id
    {
        public uint index;
        public uint generation;
        public override string ToString() { return "{" + index + ", " + generation + "}"; }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_material_id
    {
        public uint index;
        public uint generation;
        public override string ToString() { return "{" + index + ", " + generation + "}"; }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_gl_buffer_id
    {
        public uint index;
        public uint generation;
        public override string ToString() { return "{" + index + ", " + generation + "}"; }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_external_buffer_id
    {
        public uint index;
        public uint generation;
        public override string ToString() { return "{" + index + ", " + generation + "}"; }
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_semaphore_id
    {
        public uint index;
        public uint generation;
        public override string ToString() { return "{" + index + ", " + generation + "}"; }
    }

    // ---- Descs and results ---------------------------------------------------------------------
    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_solver_params
    {
        public uint struct_size;
        public uint iterations;
        public uint substeps;
        public float relaxation;
        public float scorr_k;
        public float scorr_n;
        public float scorr_dq;
        public float xsph_c;
        public float vorticity_epsilon;
        public uint ldc_enabled;
        public float ldc_gain;
        public float max_speed;
        public float adaptive_error_target;
        public uint max_substeps;
        public float substep_travel;
        public float sound_speed;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_render_params
    {
        public uint struct_size;
        public uint flags;
        public float smoothing;
        public float max_stretch;
        public float scale;
        public float isolated_scale;
        public uint min_neighbors;
        public uint reserved0;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_diffuse_params
    {
        public uint struct_size;
        public uint max_diffuse;
        public float trapped_air_min;
        public float trapped_air_max;
        public float wave_crest_min;
        public float wave_crest_max;
        public float energy_min;
        public float energy_max;
        public float trapped_air_rate;
        public float wave_crest_rate;
        public float lifetime;
        public uint spray_max_neighbors;
        public uint bubble_min_neighbors;
        public float buoyancy;
        public float bubble_drag;
        public float spray_drag;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_world_desc
    {
        public uint struct_size;
        public uint header_version;
        public pbf_backend backend;
        public int cuda_device;
        public uint max_particles;
        public float particle_radius;
        public float rest_density;
        public Float3 gravity;
        public Float3 domain_min;
        public Float3 domain_max;
        public pbf_solver_params solver;
        public pbf_render_params render;
        public uint max_colliders;
        public pbf_diffuse_params diffuse;
        public uint walls;
        public uint hashed_grid;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_world_info
    {
        public uint struct_size;
        public pbf_backend backend;
        public uint max_particles;
        public float particle_radius;
        public float rest_spacing;
        public float kernel_radius;
        public float particle_mass;
        public uint grid_cells;
        public ulong device_bytes;
        public Char128 device_name;
        public uint render_flags;
        public uint reserved0;
        public ulong render_bytes;
        public ulong render_updates;
        public uint diffuse_capacity;
        public uint reserved1;
        public ulong diffuse_bytes;
        public ulong diffuse_updates;
        public uint grid_hashed;
        public uint reserved2;
        public ulong grid_bytes;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_step_stats
    {
        public uint struct_size;
        public uint particle_count;
        public ulong step_index;
        public ulong emitted_total;
        public ulong drained_total;
        public float density_error_mean;
        public float density_error_max;
        public float kinetic_energy;
        public float step_time_ms;
        public uint iterations;
        public uint substeps;
        public uint speed_clamps;
        public uint reserved0;
        public uint diffuse_count;
        public uint diffuse_dropped;
        public ulong diffuse_generated_total;
        public ulong diffuse_dropped_total;
    }

    /// <summary>float[16] of the header (pbf_step_profile.stage_ms), read by index.</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct Float16
    {
        public float f00, f01, f02, f03, f04, f05, f06, f07, f08, f09, f10, f11, f12, f13, f14, f15;

        public const int Length = 16;

        public float this[int i] { get { return MemoryMarshal.CreateSpan(ref f00, Length)[i]; } }
    }

    /// <summary>pbf_step_profile: per-stage ms of the last step (see World.Profile).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_step_profile
    {
        public uint struct_size;
        public uint stage_count;
        public Float16 stage_ms;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_block_desc
    {
        public uint struct_size;
        public Float3 box_min;
        public Float3 box_max;
        public Float3 velocity;
        public pbf_material_id material;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_emitter_desc
    {
        public uint struct_size;
        public pbf_emitter_type type;
        public uint enabled;
        public Float3 position;
        public Float3 direction;
        public float speed;
        public float radius;
        public float particles_per_second;
        public Float3 box_min;
        public Float3 box_max;
        public pbf_material_id material;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_material_desc
    {
        public uint struct_size;
        public float rest_density;
        public float viscosity;
        public float ldc_gain;
        public float surface_tension;
        public float cohesion;
        public float adhesion;
        public Float4 color;
        public uint user_id;
        public uint reserved0;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_collider_desc
    {
        public uint struct_size;
        public pbf_collider_shape shape;
        public pbf_collider_motion motion;
        public Float3 position;
        public Float4 rotation;
        public float radius;
        public float half_height;
        public Float3 half_extents;
        public float friction;
        public uint dynamic;
        public Float3 center_of_mass;
        public pbf_mesh_id mesh;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_mesh_id
    {
        public uint index;
        public uint generation;
        public override string ToString() { return "{" + index + ", " + generation + "}"; }
    }

    /// <summary>vertices and indices point at arrays the caller keeps pinned for the call
    /// (the library copies them).</summary>
    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_mesh_desc
    {
        public uint struct_size;
        public IntPtr vertices;
        public uint vertex_count;
        public IntPtr indices;
        public uint triangle_count;
        public uint closed;
        public float thickness;
        public float cell_size;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_collider_force
    {
        public Float3 force;
        public Float3 torque;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_mapped_buffer
    {
        public uint struct_size;
        public pbf_memory_kind memory;
        public IntPtr data;
        public uint count;
        public uint stride_bytes;
        public uint reserved0;
        public uint reserved1;
    }

    // ---- Interop structs -------------------------------------------------------------------
    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_device_buffers
    {
        public uint struct_size;
        public pbf_memory_kind memory;
        public IntPtr positions;
        public IntPtr velocities;
        public IntPtr ids;
        public IntPtr density_ratio;
        public IntPtr count_device;
        public IntPtr cuda_stream;
        public uint count;
        public uint capacity;
        public uint vec4_stride_bytes;
        public uint id_stride_bytes;
        public int cuda_device;
        public uint reserved0;
        public IntPtr smoothed_positions;
        public IntPtr anisotropy;
        public uint anisotropy_stride_bytes;
        public uint render_flags;
        public IntPtr diffuse_positions;
        public IntPtr diffuse_velocities;
        public IntPtr diffuse_count_device;
        public uint diffuse_count;
        public uint diffuse_capacity;
        public IntPtr materials;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_gl_buffer_desc
    {
        public uint struct_size;
        public uint buffer;
        public pbf_buffer source;
        public pbf_copy_mode mode;
        public ulong offset_bytes;
        public uint capacity;
        public uint draw_args_buffer;
        public ulong draw_args_offset_bytes;
        public uint draw_args_vertices;
        public uint reserved0;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_external_buffer_desc
    {
        public uint struct_size;
        public pbf_external_memory_type type;
        public int fd;
        public uint dedicated;
        public IntPtr win32_handle;
        public ulong size_bytes;
        public ulong offset_bytes;
        public pbf_buffer source;
        public pbf_copy_mode mode;
        public uint capacity;
        public uint write_draw_args;
        public ulong draw_args_offset_bytes;
        public uint draw_args_vertices;
        public uint reserved0;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_semaphore_desc
    {
        public uint struct_size;
        public pbf_semaphore_type type;
        public int fd;
        public uint reserved0;
        public IntPtr win32_handle;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_external_sync
    {
        public uint struct_size;
        public uint reserved0;
        public pbf_semaphore_id wait_semaphore;
        public ulong wait_value;
        public pbf_semaphore_id signal_semaphore;
        public ulong signal_value;
    }

    [StructLayout(LayoutKind.Sequential)]
    public struct pbf_interop_info
    {
        public uint struct_size;
        public uint gl_buffers;
        public uint external_buffers;
        public uint semaphores;
        public ulong copies;
        public ulong render_events;
        public float last_copy_gpu_ms;
        public float last_copy_host_ms;
        public pbf_result last_render_event_result;
        public uint pending_render_work;
        public Bytes16 device_uuid;
        public Bytes8 device_luid;
        public uint device_node_mask;
        public int cuda_device;
        public Char256 last_render_event_message;
    }

    /// <summary>typedef void (*pbf_log_fn)(pbf_log_level, const char*, void*).</summary>
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    public delegate void pbf_log_fn(pbf_log_level level, IntPtr message, IntPtr user_data);

    /// <summary>typedef void (*pbf_render_event_fn)(int event_id): what pbf_get_render_event_func
    /// returns. Pass the pointer itself to the engine (Unity: GL.IssuePluginEvent(ptr, id)).</summary>
    [UnmanagedFunctionPointer(CallingConvention.Cdecl)]
    public delegate void pbf_render_event_fn(int event_id);

    // ---- Functions -----------------------------------------------------------------------------
    public static class Native
    {
        /// <summary>The native library's name: libpbf.so / libpbf.dylib / pbf.dll. Where libpbf is
        /// linked statically into the player (iOS, WebGL; or any build defining PBF_STATIC_LINK)
        /// it is "__Internal".</summary>
#if PBF_STATIC_LINK || ((UNITY_IOS || UNITY_TVOS || UNITY_WEBGL) && !UNITY_EDITOR)
        public const string Library = "__Internal";
#else
        public const string Library = "pbf";
#endif

        public const uint PBF_VERSION_MAJOR = 2;
        public const uint PBF_VERSION_MINOR = 0;
        public const uint PBF_VERSION_PATCH = 0;
        /// <summary>The header version these bindings mirror: major in bits 22..31, minor in 12..21, patch in 0..11.</summary>
        public const uint PBF_VERSION = (PBF_VERSION_MAJOR << 22) | (PBF_VERSION_MINOR << 12) | PBF_VERSION_PATCH;

        public static uint PBF_MAKE_VERSION(uint major, uint minor, uint patch) { return (major << 22) | (minor << 12) | patch; }
        public static uint PBF_VERSION_GET_MAJOR(uint v) { return v >> 22; }
        public static uint PBF_VERSION_GET_MINOR(uint v) { return (v >> 12) & 0x3FFu; }
        public static uint PBF_VERSION_GET_PATCH(uint v) { return v & 0xFFFu; }

        // Interop constants
        /// <summary>pbf_get_interop_support bits: streams, events, device pointers.</summary>
        /// <summary>Stages a pbf_step_profile can hold.</summary>
        public const uint PBF_PROFILE_MAX_STAGES = 16;
        public const uint PBF_INTEROP_SUPPORT_CUDA = 0x1u;
        /// <summary>pbf_world_register_gl_buffer (CUDA-GL interop).</summary>
        public const uint PBF_INTEROP_SUPPORT_OPENGL = 0x2u;
        /// <summary>Opaque fd memory and semaphores (Linux).</summary>
        public const uint PBF_INTEROP_SUPPORT_EXTERNAL_FD = 0x4u;
        /// <summary>Win32 handles, D3D11 / D3D12 (Windows).</summary>
        public const uint PBF_INTEROP_SUPPORT_EXTERNAL_WIN32 = 0x8u;
        /// <summary>pbf_world_map_device_buffers flag: do not wait for the world's stream.</summary>
        public const uint PBF_MAP_NO_WAIT = 0x1u;
        /// <summary>pbf_render_params.flags: smoothed positions, 16 bytes per particle.</summary>
        public const uint PBF_RENDER_SMOOTHED_POSITIONS = 0x1u;
        /// <summary>pbf_render_params.flags: anisotropy, 3 float4 (unit axis, radius) per particle.</summary>
        public const uint PBF_RENDER_ANISOTROPY = 0x2u;
        /// <summary>Diffuse kinds, the w of PBF_BUFFER_DIFFUSE_POSITIONS.</summary>
        public const float PBF_DIFFUSE_SPRAY = 0.0f;
        public const float PBF_DIFFUSE_FOAM = 1.0f;
        public const float PBF_DIFFUSE_BUBBLE = 2.0f;
        /// <summary>pbf_device_buffers.count when mapped with PBF_MAP_NO_WAIT on CUDA.</summary>
        public const uint PBF_COUNT_ON_DEVICE = 0xFFFFFFFFu;
        /// <summary>The render event id that runs the render work of every world.</summary>
        public const int PBF_RENDER_EVENT_ALL_WORLDS = 0;
        /// <summary>Materials a world holds at most (the default one included).</summary>
        public const int PBF_MAX_MATERIALS = 8;
        /// <summary>The most substeps a step runs (solver substeps and max_substeps).</summary>
        public const uint PBF_MAX_SUBSTEPS = 64;
        /// <summary>The largest pbf_world_desc.max_colliders.</summary>
        public const uint PBF_MAX_COLLIDERS = 2048;
        /// <summary>Meshes a world holds at most.</summary>
        public const uint PBF_MAX_MESHES = 256;
        /// <summary>The largest distance field of one mesh, in bytes.</summary>
        public const uint PBF_MAX_MESH_FIELD_BYTES = 268435456;

        // Version, errors, logging
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern uint pbf_get_version();

        /// <summary>const char*: UTF-8, owned by the library, valid until this thread's next libpbf call.</summary>
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern IntPtr pbf_last_error_message();

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern IntPtr pbf_result_string(pbf_result result);

        /// <summary>callback: a function pointer from Marshal.GetFunctionPointerForDelegate of a
        /// pbf_log_fn kept alive by the caller, or IntPtr.Zero to remove.</summary>
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern void pbf_set_log_callback(IntPtr callback, IntPtr user_data);

        // Solver parameters
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_solver_params_init(ref pbf_solver_params @params, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_solver_params_init(IntPtr @params, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_render_params_init(ref pbf_render_params @params, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_render_params_init(IntPtr @params, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_diffuse_params_init(ref pbf_diffuse_params @params, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_diffuse_params_init(IntPtr @params, uint struct_size);

        // World
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_desc_init(ref pbf_world_desc desc, uint struct_size, uint header_version);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_desc_init(IntPtr desc, uint struct_size, uint header_version);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create(ref pbf_world_desc desc, out pbf_world_id out_world);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create(IntPtr desc, out pbf_world_id out_world);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create(ref pbf_world_desc desc, IntPtr out_world);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_destroy(pbf_world_id world);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_step(pbf_world_id world, float dt);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_solver_params(pbf_world_id world, ref pbf_solver_params out_params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_solver_params(pbf_world_id world, IntPtr out_params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_solver_params(pbf_world_id world, ref pbf_solver_params @params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_solver_params(pbf_world_id world, IntPtr @params);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_gravity(pbf_world_id world, ref Float3 gravity);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_gravity(pbf_world_id world, IntPtr gravity);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_render_params(pbf_world_id world, ref pbf_render_params out_params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_render_params(pbf_world_id world, IntPtr out_params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_render_params(pbf_world_id world, ref pbf_render_params @params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_render_params(pbf_world_id world, IntPtr @params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_diffuse_params(pbf_world_id world, ref pbf_diffuse_params out_params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_diffuse_params(pbf_world_id world, IntPtr out_params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_diffuse_params(pbf_world_id world, ref pbf_diffuse_params @params);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_diffuse_params(pbf_world_id world, IntPtr @params);
        /// <summary>positions and velocities: count float4 rows each (the ref overload passes the
        /// first elements' addresses).</summary>
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_add_diffuse(pbf_world_id world, ref float positions, ref float velocities, uint count, out uint out_added);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_add_diffuse(pbf_world_id world, IntPtr positions, IntPtr velocities, uint count, IntPtr out_added);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_info(pbf_world_id world, ref pbf_world_info out_info);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_info(pbf_world_id world, IntPtr out_info);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_stats(pbf_world_id world, ref pbf_step_stats out_stats);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_stats(pbf_world_id world, IntPtr out_stats);

        // Profiling
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_profiling(pbf_world_id world, uint enabled);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_profile(pbf_world_id world, ref pbf_step_profile out_profile);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_profile(pbf_world_id world, IntPtr out_profile);
        /// <summary>The stage's name (UTF-8, static), or IntPtr.Zero past the last stage.</summary>
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern IntPtr pbf_profile_stage_name(uint stage);

        // Emitters and drains
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_block_desc_init(ref pbf_block_desc desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_block_desc_init(IntPtr desc, uint struct_size);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_emit_block(pbf_world_id world, ref pbf_block_desc desc, out uint out_emitted);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_emit_block(pbf_world_id world, ref pbf_block_desc desc, IntPtr out_emitted);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_emit_block(pbf_world_id world, IntPtr desc, IntPtr out_emitted);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_emitter_desc_init(ref pbf_emitter_desc desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_emitter_desc_init(IntPtr desc, uint struct_size);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create_emitter(pbf_world_id world, ref pbf_emitter_desc desc, out pbf_emitter_id out_emitter);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create_emitter(pbf_world_id world, IntPtr desc, out pbf_emitter_id out_emitter);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create_emitter(pbf_world_id world, ref pbf_emitter_desc desc, IntPtr out_emitter);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_destroy_emitter(pbf_world_id world, pbf_emitter_id emitter);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_emitter_set_enabled(pbf_world_id world, pbf_emitter_id emitter, uint enabled);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_emitter_set_nozzle(pbf_world_id world, pbf_emitter_id emitter, ref Float3 position, ref Float3 direction);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_emitter_set_nozzle(pbf_world_id world, pbf_emitter_id emitter, IntPtr position, IntPtr direction);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_emitter_set_drain_box(pbf_world_id world, pbf_emitter_id emitter, ref Float3 box_min, ref Float3 box_max);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_emitter_set_drain_box(pbf_world_id world, pbf_emitter_id emitter, IntPtr box_min, IntPtr box_max);

        // Colliders
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_collider_desc_init(ref pbf_collider_desc desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_collider_desc_init(IntPtr desc, uint struct_size);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create_collider(pbf_world_id world, ref pbf_collider_desc desc, out pbf_collider_id out_collider);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create_collider(pbf_world_id world, IntPtr desc, out pbf_collider_id out_collider);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create_collider(pbf_world_id world, ref pbf_collider_desc desc, IntPtr out_collider);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_destroy_collider(pbf_world_id world, pbf_collider_id collider);

        // ---- materials ----
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_material_desc_init(ref pbf_material_desc desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create_material(pbf_world_id world, ref pbf_material_desc desc, out pbf_material_id out_material);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_destroy_material(pbf_world_id world, pbf_material_id material);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_material(pbf_world_id world, pbf_material_id material, ref pbf_material_desc out_desc);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_material(pbf_world_id world, pbf_material_id material, ref pbf_material_desc desc);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_materials(pbf_world_id world, [Out] pbf_material_id[] out_materials);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_mesh_desc_init(ref pbf_mesh_desc desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_create_mesh(pbf_world_id world, ref pbf_mesh_desc desc, out pbf_mesh_id out_mesh);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_destroy_mesh(pbf_world_id world, pbf_mesh_id mesh);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_collider_set_target_pose(pbf_world_id world, pbf_collider_id collider, ref Float3 position, ref Float4 rotation);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_collider_set_target_pose(pbf_world_id world, pbf_collider_id collider, IntPtr position, IntPtr rotation);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_collider_teleport(pbf_world_id world, pbf_collider_id collider, ref Float3 position, ref Float4 rotation);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_collider_get_force(pbf_world_id world, pbf_collider_id collider, out pbf_collider_force out_force);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_collider_get_force(pbf_world_id world, pbf_collider_id collider, IntPtr out_force);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_map_collider_forces(pbf_world_id world, ref pbf_mapped_buffer out_buffer);

        // Particles
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_particle_count(pbf_world_id world, out uint out_count);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_particle_count(pbf_world_id world, IntPtr out_count);

        /// <summary>out_xyzw: max_count * 4 floats. The ref overload passes the address of the
        /// first element (pinned by the runtime for the call), e.g. ref array[0] or
        /// ref MemoryMarshal.GetReference(span).</summary>
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_positions(pbf_world_id world, ref float out_xyzw, uint max_count, out uint out_written);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_positions(pbf_world_id world, IntPtr out_xyzw, uint max_count, out uint out_written);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_positions(pbf_world_id world, IntPtr out_xyzw, uint max_count, IntPtr out_written);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_velocities(pbf_world_id world, ref float out_xyzw, uint max_count, out uint out_written);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_velocities(pbf_world_id world, IntPtr out_xyzw, uint max_count, out uint out_written);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_velocities(pbf_world_id world, IntPtr out_xyzw, uint max_count, IntPtr out_written);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_ids(pbf_world_id world, ref uint out_ids, uint max_count, out uint out_written);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_ids(pbf_world_id world, IntPtr out_ids, uint max_count, out uint out_written);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_ids(pbf_world_id world, IntPtr out_ids, uint max_count, IntPtr out_written);

        /// <summary>out: out_bytes bytes (a multiple of the source's element size: 4 ids, 48
        /// anisotropy, else 16). The ref overload passes the first element's address.</summary>
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_buffer(pbf_world_id world, pbf_buffer source, ref float @out, ulong out_bytes, out uint out_written);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_buffer(pbf_world_id world, pbf_buffer source, ref byte @out, ulong out_bytes, out uint out_written);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_buffer(pbf_world_id world, pbf_buffer source, IntPtr @out, ulong out_bytes, out uint out_written);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_buffer(pbf_world_id world, pbf_buffer source, IntPtr @out, ulong out_bytes, IntPtr out_written);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_map_positions(pbf_world_id world, ref pbf_mapped_buffer out_buffer);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_map_positions(pbf_world_id world, IntPtr out_buffer);

        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_unmap(pbf_world_id world);

        // ==== Interop: zero-copy rendering ====
        // Every function exists in every build; what the build lacks returns
        // PBF_ERROR_BACKEND_UNAVAILABLE, a CUDA-only call on a CPU world PBF_ERROR_INVALID_STATE.
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_get_interop_support(out uint out_flags);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_get_interop_support(IntPtr out_flags);

        // Streams and events (cudaStream_t / cudaEvent_t as IntPtr)
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_cuda_stream(pbf_world_id world, out IntPtr out_stream);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_cuda_stream(pbf_world_id world, IntPtr out_stream_ptr);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_cuda_stream(pbf_world_id world, IntPtr stream);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_record_cuda_event(pbf_world_id world, out IntPtr out_event);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_record_cuda_event(pbf_world_id world, IntPtr out_event_ptr);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_wait_cuda_event(pbf_world_id world, IntPtr @event);

        // Live buffers as device pointers
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_map_device_buffers(pbf_world_id world, uint flags, ref pbf_device_buffers out_buffers);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_map_device_buffers(pbf_world_id world, uint flags, IntPtr out_buffers);

        // OpenGL
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_gl_buffer_desc_init(ref pbf_gl_buffer_desc desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_gl_buffer_desc_init(IntPtr desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_register_gl_buffer(pbf_world_id world, ref pbf_gl_buffer_desc desc, out pbf_gl_buffer_id out_buffer);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_register_gl_buffer(pbf_world_id world, IntPtr desc, out pbf_gl_buffer_id out_buffer);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_register_gl_buffer(pbf_world_id world, ref pbf_gl_buffer_desc desc, IntPtr out_buffer);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_unregister_gl_buffer(pbf_world_id world, pbf_gl_buffer_id buffer);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_to_gl_buffer(pbf_world_id world, pbf_gl_buffer_id buffer);

        // External memory and semaphores (Vulkan, Direct3D)
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_external_buffer_desc_init(ref pbf_external_buffer_desc desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_external_buffer_desc_init(IntPtr desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_import_external_buffer(pbf_world_id world, ref pbf_external_buffer_desc desc, out pbf_external_buffer_id out_buffer);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_import_external_buffer(pbf_world_id world, IntPtr desc, out pbf_external_buffer_id out_buffer);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_import_external_buffer(pbf_world_id world, ref pbf_external_buffer_desc desc, IntPtr out_buffer);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_release_external_buffer(pbf_world_id world, pbf_external_buffer_id buffer);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_semaphore_desc_init(ref pbf_semaphore_desc desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_semaphore_desc_init(IntPtr desc, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_import_semaphore(pbf_world_id world, ref pbf_semaphore_desc desc, out pbf_semaphore_id out_semaphore);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_import_semaphore(pbf_world_id world, IntPtr desc, out pbf_semaphore_id out_semaphore);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_import_semaphore(pbf_world_id world, ref pbf_semaphore_desc desc, IntPtr out_semaphore);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_release_semaphore(pbf_world_id world, pbf_semaphore_id semaphore);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_external_sync_init(ref pbf_external_sync sync, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_external_sync_init(IntPtr sync, uint struct_size);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_to_external_buffer(pbf_world_id world, pbf_external_buffer_id buffer, ref pbf_external_sync sync);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_copy_to_external_buffer(pbf_world_id world, pbf_external_buffer_id buffer, IntPtr sync);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_external_sync(pbf_world_id world, pbf_external_buffer_id buffer, ref pbf_external_sync sync);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_set_external_sync(pbf_world_id world, pbf_external_buffer_id buffer, IntPtr sync);

        // The render-thread entry point
        /// <summary>pbf_render_event_fn as a raw function pointer (never null): hand it to the
        /// engine as is (Unity: GL.IssuePluginEvent(pbf_get_render_event_func(), eventId)).</summary>
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern IntPtr pbf_get_render_event_func();
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_render_event_id(pbf_world_id world, out int out_event_id);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_render_event_id(pbf_world_id world, IntPtr out_event_id);

        // State, device identity and cost
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_interop_info(pbf_world_id world, ref pbf_interop_info out_info);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_world_get_interop_info(pbf_world_id world, IntPtr out_info);
        /// <summary>Debug: host&lt;-&gt;device copies made by the library, process-wide.</summary>
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_debug_get_transfer_count(out ulong out_transfers, out ulong out_bytes);
        [DllImport(Library, CallingConvention = CallingConvention.Cdecl)]
        public static extern pbf_result pbf_debug_get_transfer_count(IntPtr out_transfers, IntPtr out_bytes);

        // ---- Helpers that the header provides as static inline functions ----------------------
        /// <summary>Marshal.SizeOf(T) as the struct_size a desc carries (computed once per type).</summary>
        public static uint SizeOf<T>() where T : struct { return SizeCache<T>.Value; }

        static class SizeCache<T> where T : struct
        {
            public static readonly uint Value = (uint)Marshal.SizeOf(typeof(T));
        }

        /// <summary>pbf_solver_params_default(): the library's defaults.</summary>
        public static pbf_solver_params pbf_solver_params_default()
        {
            var p = new pbf_solver_params { struct_size = SizeOf<pbf_solver_params>() };
            pbf_solver_params_init(ref p, p.struct_size);
            return p;
        }

        /// <summary>pbf_diffuse_params_default(): the library's defaults (diffuse particles off).</summary>
        public static pbf_diffuse_params pbf_diffuse_params_default()
        {
            var p = new pbf_diffuse_params { struct_size = SizeOf<pbf_diffuse_params>() };
            pbf_diffuse_params_init(ref p, p.struct_size);
            return p;
        }

        /// <summary>pbf_render_params_default(): the library's defaults (render data off).</summary>
        public static pbf_render_params pbf_render_params_default()
        {
            var p = new pbf_render_params { struct_size = SizeOf<pbf_render_params>() };
            pbf_render_params_init(ref p, p.struct_size);
            return p;
        }

        /// <summary>pbf_world_desc_default(): the library's defaults, header_version = PBF_VERSION.</summary>
        public static pbf_world_desc pbf_world_desc_default()
        {
            var d = new pbf_world_desc { struct_size = SizeOf<pbf_world_desc>() };
            pbf_world_desc_init(ref d, d.struct_size, PBF_VERSION);
            return d;
        }

        public static pbf_block_desc pbf_block_desc_default()
        {
            var d = new pbf_block_desc { struct_size = SizeOf<pbf_block_desc>() };
            pbf_block_desc_init(ref d, d.struct_size);
            return d;
        }

        public static pbf_emitter_desc pbf_emitter_desc_default()
        {
            var d = new pbf_emitter_desc { struct_size = SizeOf<pbf_emitter_desc>() };
            pbf_emitter_desc_init(ref d, d.struct_size);
            return d;
        }

        public static pbf_material_desc pbf_material_desc_default()
        {
            var d = new pbf_material_desc { struct_size = SizeOf<pbf_material_desc>() };
            pbf_material_desc_init(ref d, d.struct_size);
            return d;
        }

        public static pbf_collider_desc pbf_collider_desc_default()
        {
            var d = new pbf_collider_desc { struct_size = SizeOf<pbf_collider_desc>() };
            pbf_collider_desc_init(ref d, d.struct_size);
            return d;
        }

        public static pbf_gl_buffer_desc pbf_gl_buffer_desc_default()
        {
            var d = new pbf_gl_buffer_desc { struct_size = SizeOf<pbf_gl_buffer_desc>() };
            pbf_gl_buffer_desc_init(ref d, d.struct_size);
            return d;
        }

        public static pbf_external_buffer_desc pbf_external_buffer_desc_default()
        {
            var d = new pbf_external_buffer_desc { struct_size = SizeOf<pbf_external_buffer_desc>() };
            pbf_external_buffer_desc_init(ref d, d.struct_size);
            return d;
        }

        public static pbf_semaphore_desc pbf_semaphore_desc_default()
        {
            var d = new pbf_semaphore_desc { struct_size = SizeOf<pbf_semaphore_desc>() };
            pbf_semaphore_desc_init(ref d, d.struct_size);
            return d;
        }

        public static pbf_external_sync pbf_external_sync_default()
        {
            var s = new pbf_external_sync { struct_size = SizeOf<pbf_external_sync>() };
            pbf_external_sync_init(ref s, s.struct_size);
            return s;
        }

        /// <summary>Decodes a NUL-terminated UTF-8 string owned by the library ("" for NULL).</summary>
        public static string Utf8ToString(IntPtr text)
        {
            if (text == IntPtr.Zero) return string.Empty;
            int n = 0;
            while (Marshal.ReadByte(text, n) != 0) ++n;
            if (n == 0) return string.Empty;
            var bytes = new byte[n];
            Marshal.Copy(text, bytes, 0, n);
            return System.Text.Encoding.UTF8.GetString(bytes);
        }

        /// <summary>pbf_last_error_message() as a string.</summary>
        public static string LastErrorMessage() { return Utf8ToString(pbf_last_error_message()); }

        /// <summary>pbf_result_string() as a string.</summary>
        public static string ResultString(pbf_result result) { return Utf8ToString(pbf_result_string(result)); }
    }
}
