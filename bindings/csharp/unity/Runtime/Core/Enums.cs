// Friendly enums of the Pbf namespace. Their values equal the header's (tests check each one),
// so a cast converts to and from the raw Pbf.Interop enums.
namespace Pbf
{
    /// <summary>pbf_result: why a libpbf call failed (carried by <see cref="PbfException"/>).</summary>
    public enum Result
    {
        Ok = 0,
        /// <summary>NULL pointer, NaN/Inf or out-of-range value.</summary>
        InvalidArgument = 1,
        /// <summary>Zeroed, forged or stale (destroyed) handle.</summary>
        InvalidHandle = 2,
        /// <summary>A desc's struct_size does not match the library's: bindings and library disagree.</summary>
        StructSize = 3,
        /// <summary>Header (bindings) and library major versions differ.</summary>
        VersionMismatch = 4,
        /// <summary>Nothing fits: world at max_particles, or a table is full.</summary>
        Capacity = 5,
        OutOfMemory = 6,
        /// <summary>CUDA asked for but not built in, or no device.</summary>
        BackendUnavailable = 7,
        /// <summary>A device call failed; the message carries its text.</summary>
        BackendError = 8,
        /// <summary>The call does not fit the object's current state.</summary>
        InvalidState = 9,
        /// <summary>A bug in libpbf; please report the message.</summary>
        Internal = 10,
    }

    /// <summary>pbf_backend.</summary>
    public enum Backend
    {
        /// <summary>CUDA when built in and a device exists, else CPU.</summary>
        Auto = 0,
        Cpu = 1,
        Cuda = 2,
    }

    /// <summary>pbf_backend_status: whether a backend can run on this machine, and if not, why
    /// (<see cref="Library.GetBackendInfo"/>).</summary>
    public enum BackendStatus
    {
        Available = 0,
        /// <summary>This libpbf was built without the backend.</summary>
        NotBuilt = 1,
        /// <summary>No NVIDIA driver: its library (libcuda.so.1 / nvcuda.dll) was not found.</summary>
        NoDriver = 2,
        /// <summary>The driver is older than <see cref="BackendInfo.RequiredDriverVersion"/>.</summary>
        DriverTooOld = 3,
        /// <summary>A driver, but no CUDA device of that ordinal.</summary>
        NoDevice = 4,
        /// <summary>A GPU the kernels do not run on (before compute capability 7.5).</summary>
        DeviceUnsupported = 5,
        /// <summary>The driver failed to start, or to load the kernels: the message gives its error.</summary>
        DriverError = 6,
    }

    /// <summary>pbf_log_level.</summary>
    public enum LogLevel
    {
        Debug = 0,
        Info = 1,
        Warning = 2,
        Error = 3,
    }

    /// <summary>pbf_emitter_type.</summary>
    public enum EmitterType
    {
        /// <summary>Emits particles_per_second through a disc, along a direction.</summary>
        Nozzle = 1,
        /// <summary>Removes particles inside a box at each step.</summary>
        Drain = 2,
    }

    /// <summary>pbf_collider_shape.</summary>
    public enum ColliderShape
    {
        /// <summary>The half-space below the plane through Position with normal Rotation·(0,1,0) is solid.</summary>
        Plane = 1,
        Sphere = 2,
        /// <summary>Radius around the segment from -HalfHeight to +HalfHeight on local y.</summary>
        Capsule = 3,
        /// <summary>HalfExtents, oriented by Rotation.</summary>
        Box = 4,
        /// <summary>A triangle mesh of the world (<see cref="World.CreateMesh"/>), placed by the pose.</summary>
        Mesh = 5,
    }

    /// <summary>pbf_collider_motion.</summary>
    public enum ColliderMotion
    {
        Static = 0,
        /// <summary>Pose set each frame with <see cref="Collider.SetTargetPose"/>; its motion over a step pushes fluid.</summary>
        Kinematic = 1,
    }

    /// <summary>pbf_memory_kind: where a mapped buffer lives.</summary>
    public enum MemoryKind
    {
        /// <summary>CPU backend: an ordinary host pointer.</summary>
        Host = 1,
        /// <summary>CUDA backend: a device pointer.</summary>
        CudaDevice = 2,
    }
}

namespace Pbf
{
    /// <summary>What this build of libpbf can do for zero-copy rendering (pbf_get_interop_support
    /// bits; see <see cref="Library.GetInteropSupport"/>).</summary>
    [System.Flags]
    public enum InteropSupport : uint
    {
        None = 0,
        /// <summary>CUDA streams, events and device pointers.</summary>
        Cuda = 0x1,
        /// <summary>CUDA-GL interop: <see cref="World.RegisterGlBuffer"/>.</summary>
        OpenGL = 0x2,
        /// <summary>Opaque fd memory and semaphores (Vulkan on Linux).</summary>
        ExternalFd = 0x4,
        /// <summary>Win32 handles, D3D11 / D3D12 (Windows).</summary>
        ExternalWin32 = 0x8,
        /// <summary>CUDA-D3D11 interop: <see cref="World.RegisterD3D11Buffer"/> (Windows).</summary>
        D3D11 = 0x10,
    }

    /// <summary>pbf_buffer: which particle buffer a graphics-buffer copy writes.</summary>
    public enum BufferSource
    {
        /// <summary>16 bytes per particle: float x, y, z, density ratio.</summary>
        Positions = 1,
        /// <summary>16 bytes per particle: float vx, vy, vz, 0.</summary>
        Velocities = 2,
        /// <summary>4 bytes per particle: uint id.</summary>
        Ids = 3,
        /// <summary>16 bytes per particle: float x̄, ȳ, z̄, density ratio (<see cref="RenderFlags.SmoothedPositions"/>).</summary>
        SmoothedPositions = 4,
        /// <summary>48 bytes per particle: 3 rows of (unit axis x, y, z, radius in m), longest
        /// first (<see cref="RenderFlags.Anisotropy"/>).</summary>
        Anisotropy = 5,
        /// <summary>16 bytes per diffuse particle: float x, y, z, kind (<see cref="DiffuseKind"/>);
        /// <see cref="StepStats.DiffuseCount"/> of them.</summary>
        DiffusePositions = 6,
        /// <summary>16 bytes per diffuse particle: float vx, vy, vz, remaining lifetime in s.</summary>
        DiffuseVelocities = 7,
        /// <summary>1 byte per particle: the index of its material (<see cref="Material.Index"/>);
        /// copy-out and device pointers only.</summary>
        Materials = 8,
    }

    /// <summary>PBF_DIFFUSE_*: what a diffuse particle is, stored as a float in its position's w.</summary>
    public enum DiffuseKind
    {
        /// <summary>Few fluid neighbours: flies ballistically under gravity and air drag.</summary>
        Spray = 0,
        /// <summary>At a surface: rides with the fluid's velocity, dissolves over its lifetime.</summary>
        Foam = 1,
        /// <summary>Inside the fluid: rises by buoyancy, dragged toward the fluid's velocity.</summary>
        Bubble = 2,
    }

    /// <summary>PBF_RENDER_*: the render data a world computes after every step (fixed at creation).</summary>
    [System.Flags]
    public enum RenderFlags
    {
        /// <summary>No render buffers, no render pass.</summary>
        None = 0,
        /// <summary>Laplacian-smoothed positions (Yu &amp; Turk 2013).</summary>
        SmoothedPositions = 0x1,
        /// <summary>Per-particle ellipsoids from the neighbourhood's covariance (Yu &amp; Turk 2013).</summary>
        Anisotropy = 0x2,
    }

    /// <summary>pbf_copy_mode: when a graphics buffer receives the particles.</summary>
    public enum CopyMode
    {
        /// <summary><see cref="World.Step"/> queues the copy after each step.</summary>
        OnStep = 1,
        /// <summary>The render event (<see cref="Library.GetRenderEventFunc"/>) copies, on the
        /// engine's render thread.</summary>
        OnRenderEvent = 2,
        /// <summary>Only <see cref="World.CopyToGlBuffer"/> copies (not for D3D11 buffers).</summary>
        Manual = 3,
    }
}
