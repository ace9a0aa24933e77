using System;
using System.Collections.Generic;
using System.Numerics;
using System.Runtime.InteropServices;
using System.Threading;
using Pbf.Interop;

namespace Pbf
{
    /// <summary>
    /// A fluid world: particles, emitters, colliders and the backend (CPU or CUDA) that steps them.
    /// Every failing call throws <see cref="PbfException"/> with the native result and message, and
    /// changes nothing. After <see cref="Dispose"/> every member throws
    /// <see cref="ObjectDisposedException"/>. Calls on one world may come from any thread (the
    /// library serialises them); calls on different worlds run in parallel.
    /// </summary>
    public sealed partial class World : IDisposable
    {
        readonly pbf_world_id _id;
        readonly Backend _backend;
        readonly string _cudaNotTakenReason;
        int _disposed;

        World(pbf_world_id id, Backend requested, int cudaDevice)
        {
            _id = id;
            RequestedBackend = requested;
            CudaDevice = cudaDevice;
            var info = new pbf_world_info { struct_size = Native.SizeOf<pbf_world_info>() };
            // The world was just created by this thread: reading its info can fail only on a bug.
            PbfException.Check(Native.pbf_world_get_info(id, ref info));
            _backend = (Backend)info.backend;
            _cudaNotTakenReason = _backend == Backend.Cuda ? string.Empty : CudaNotTaken(requested, cudaDevice);
        }

        // Asked right after creation, so that it is what creation found: the library tries the
        // driver again at each call after a failure.
        static string CudaNotTaken(Backend requested, int cudaDevice)
        {
            if (requested == Backend.Cpu) return "CUDA not taken: the world asked for the CPU backend";
            BackendInfo auto = Library.GetBackendInfo(Backend.Auto, cudaDevice);
            if (auto.Backend == Backend.Cpu) return auto.Message;
            // CUDA failed for the creation and came up for the next call (a transient driver error).
            return "CUDA not taken: CUDA device " + cudaDevice + " was unavailable when the world was created; now: " + auto.Message;
        }

        /// <summary>A world of the library's defaults (see <see cref="WorldDesc"/>).</summary>
        public static World Create() { return Create(new WorldDesc()); }

        /// <summary>Creates a world; every buffer is allocated here, up front (capacity
        /// desc.MaxParticles), so a world that fits never fails later for lack of memory.</summary>
        public static World Create(WorldDesc desc)
        {
            if (desc == null) throw new ArgumentNullException("desc");
            pbf_world_desc raw = desc.ToNative();
            pbf_world_id id;
            PbfException.Check(Native.pbf_world_create(ref raw, out id));
            try
            {
                return new World(id, desc.Backend, desc.CudaDevice);
            }
            catch
            {
                Native.pbf_world_destroy(id);
                throw;
            }
        }

        ~World() { Destroy(); }

        /// <summary>Destroys the native world. Idempotent; never throws.</summary>
        public void Dispose()
        {
            Destroy();
            GC.SuppressFinalize(this);
        }

        void Destroy()
        {
            if (Interlocked.Exchange(ref _disposed, 1) != 0) return;
            // Fails only if the raw layer already destroyed this id: nothing left to release.
            Native.pbf_world_destroy(_id);
        }

        public bool IsDisposed { get { return Volatile.Read(ref _disposed) != 0; } }

        /// <summary>The raw handle, for the Pbf.Interop layer. Throws once disposed.</summary>
        public pbf_world_id Id { get { return Handle; } }

        internal pbf_world_id Handle
        {
            get
            {
                ThrowIfDisposed();
                return _id;
            }
        }

        // ---- simulation ----------------------------------------------------------------------
        /// <summary>Advances by dt seconds (0 &lt; dt &lt;= 1; successive calls may use any dt), split
        /// into Solver.Substeps substeps (or chosen automatically; <see cref="StepStats.Substeps"/>
        /// says how many ran), none shorter than Native.PBF_MIN_STEP_DT (1e-4 s). A step shorter
        /// than that advances nothing: the next step simulates its dt too
        /// (<see cref="StepStats.SimulatedDt"/>), and every dynamic collider's force reads 0.
        /// On CUDA it returns without waiting for the GPU.</summary>
        public void Step(float dt) { PbfException.Check(Native.pbf_world_step(Handle, dt)); }

        /// <summary>A copy of the world's solver parameters.</summary>
        public SolverParams GetSolverParams()
        {
            var p = new pbf_solver_params { struct_size = Native.SizeOf<pbf_solver_params>() };
            PbfException.Check(Native.pbf_world_get_solver_params(Handle, ref p));
            return new SolverParams(p);
        }

        /// <summary>Replaces the solver parameters; they apply from the next step.</summary>
        public void SetSolverParams(SolverParams parameters)
        {
            pbf_solver_params p = parameters.ToNative();
            PbfException.Check(Native.pbf_world_set_solver_params(Handle, ref p));
        }

        /// <summary>A copy of the world's render parameters (its desc's).</summary>
        public RenderParams GetRenderParams()
        {
            var p = new pbf_render_params { struct_size = Native.SizeOf<pbf_render_params>() };
            PbfException.Check(Native.pbf_world_get_render_params(Handle, ref p));
            return new RenderParams(p);
        }

        /// <summary>Replaces the render parameters from the next step or emission on. Flags are
        /// fixed at creation: a different <see cref="RenderParams.Flags"/> throws
        /// <see cref="Result.InvalidState"/>.</summary>
        public void SetRenderParams(RenderParams parameters)
        {
            pbf_render_params p = parameters.ToNative();
            PbfException.Check(Native.pbf_world_set_render_params(Handle, ref p));
        }

        /// <summary>A copy of the world's diffuse parameters (its desc's).</summary>
        public DiffuseParams GetDiffuseParams()
        {
            var p = new pbf_diffuse_params { struct_size = Native.SizeOf<pbf_diffuse_params>() };
            PbfException.Check(Native.pbf_world_get_diffuse_params(Handle, ref p));
            return new DiffuseParams(p);
        }

        /// <summary>Replaces the diffuse parameters from the next step on. The capacity is fixed at
        /// creation: a different <see cref="DiffuseParams.MaxDiffuse"/> throws <see cref="Result.InvalidState"/>.</summary>
        public void SetDiffuseParams(DiffuseParams parameters)
        {
            pbf_diffuse_params p = parameters.ToNative();
            PbfException.Check(Native.pbf_world_set_diffuse_params(Handle, ref p));
        }

        /// <summary>Adds diffuse particles (4 floats each: positions x, y, z, kind; velocities vx,
        /// vy, vz, remaining lifetime in s) while they fit; returns how many were added. Throws
        /// <see cref="Result.Capacity"/> when none fit, <see cref="Result.InvalidState"/> without a
        /// diffuse capacity.</summary>
        public int AddDiffuse(float[] positions, float[] velocities)
        {
            if (positions == null) throw new ArgumentNullException("positions");
            if (velocities == null) throw new ArgumentNullException("velocities");
            if (positions.Length % 4 != 0 || positions.Length != velocities.Length)
                throw new ArgumentException("positions and velocities need 4 floats per diffuse particle, as many of each");
            uint added = 0;
            pbf_result r = positions.Length == 0
                ? Native.pbf_world_add_diffuse(Handle, IntPtr.Zero, IntPtr.Zero, 0, IntPtr.Zero)
                : Native.pbf_world_add_diffuse(Handle, ref positions[0], ref velocities[0], (uint)(positions.Length / 4), out added);
            PbfException.Check(r);
            return (int)added;
        }

        public void SetGravity(Vector3 gravity)
        {
            Float3 g = Convert3.ToNative(gravity);
            PbfException.Check(Native.pbf_world_set_gravity(Handle, ref g));
        }

        // ---- backend ---------------------------------------------------------------------------
        /// <summary>The backend in use: Cpu or Cuda, never Auto (<see cref="WorldInfo.Backend"/>).</summary>
        public Backend Backend { get { ThrowIfDisposed(); return _backend; } }

        /// <summary>The backend the world's desc asked for (Auto, Cpu or Cuda).</summary>
        public Backend RequestedBackend { get; }

        /// <summary>The CUDA device ordinal of the world's desc (used only when it runs on CUDA).</summary>
        public int CudaDevice { get; }

        /// <summary>
        /// Why the world runs on the CPU rather than on CUDA; "" when it runs on CUDA. Created with
        /// <see cref="Backend.Auto"/>: the library's reason, as <see cref="Library.GetBackendInfo"/>
        /// for Auto on <see cref="CudaDevice"/> reported it when the world was created, e.g. "CUDA
        /// not taken: this libpbf was built without CUDA (PBF_WITH_CUDA=OFF)". Created with
        /// <see cref="Backend.Cpu"/>: "CUDA not taken: the world asked for the CPU backend".
        /// Always starts "CUDA not taken: " on the CPU. No native call: it is kept from creation.
        /// </summary>
        public string CudaNotTakenReason { get { ThrowIfDisposed(); return _cudaNotTakenReason; } }

        void ThrowIfDisposed()
        {
            if (Volatile.Read(ref _disposed) != 0) throw new ObjectDisposedException("Pbf.World");
        }

        /// <summary>Backend, device, capacity and particle constants of this world.</summary>
        public WorldInfo Info
        {
            get
            {
                var info = new pbf_world_info { struct_size = Native.SizeOf<pbf_world_info>() };
                PbfException.Check(Native.pbf_world_get_info(Handle, ref info));
                return new WorldInfo(info);
            }
        }

        /// <summary>Statistics of the last step (waits for it to finish on CUDA).</summary>
        public StepStats Stats
        {
            get
            {
                var stats = new pbf_step_stats { struct_size = Native.SizeOf<pbf_step_stats>() };
                PbfException.Check(Native.pbf_world_get_stats(Handle, ref stats));
                return new StepStats(stats);
            }
        }

        /// <summary>Per-stage timing of each step (off by default; on, every stage boundary records a
        /// timer and reading <see cref="Profile"/> waits for the last step).</summary>
        public void SetProfiling(bool enabled)
        {
            PbfException.Check(Native.pbf_world_set_profiling(Handle, enabled ? 1u : 0u));
        }

        /// <summary>Milliseconds per solver stage in the last step, by the library's stage names
        /// (all zero while profiling is off).</summary>
        public KeyValuePair<string, float>[] Profile
        {
            get
            {
                var raw = new pbf_step_profile { struct_size = Native.SizeOf<pbf_step_profile>() };
                PbfException.Check(Native.pbf_world_get_profile(Handle, ref raw));
                var stages = new KeyValuePair<string, float>[raw.stage_count];
                for (uint k = 0; k < raw.stage_count; ++k)
                    stages[k] = new KeyValuePair<string, float>(
                        Native.Utf8ToString(Native.pbf_profile_stage_name(k)), raw.stage_ms[(int)k]);
                return stages;
            }
        }

        // ---- emitting ------------------------------------------------------------------------
        /// <summary>Fills the box with particles at rest spacing; returns how many were emitted
        /// (what fits under MaxParticles). Lattice points outside the walls (centres closer than
        /// the particle radius to the domain's faces) are dropped; a box with none inside throws
        /// with <see cref="Result.InvalidArgument"/>. Throws with <see cref="Result.Capacity"/> when
        /// the world is already full.</summary>
        public int EmitBlock(BlockDesc desc)
        {
            if (desc == null) throw new ArgumentNullException("desc");
            pbf_block_desc raw = desc.ToNative();
            uint emitted;
            PbfException.Check(Native.pbf_world_emit_block(Handle, ref raw, out emitted));
            return (int)emitted;
        }

        public int EmitBlock(Vector3 boxMin, Vector3 boxMax) { return EmitBlock(new BlockDesc(boxMin, boxMax)); }

        public int EmitBlock(Vector3 boxMin, Vector3 boxMax, Vector3 velocity)
        {
            return EmitBlock(new BlockDesc(boxMin, boxMax) { Velocity = velocity });
        }

        /// <summary>A native call that makes an object of this world from a desc and returns its handle.</summary>
        internal delegate pbf_result NativeCreate<TDesc, TId>(pbf_world_id world, ref TDesc desc, out TId id);

        /// <summary>Runs create on this world with raw; returns the new handle, throws on failure.</summary>
        internal TId CreateNative<TDesc, TId>(NativeCreate<TDesc, TId> create, TDesc raw)
        {
            TId id;
            PbfException.Check(create(Handle, ref raw, out id));
            return id;
        }

        public Emitter CreateEmitter(EmitterDesc desc)
        {
            if (desc == null) throw new ArgumentNullException("desc");
            var id = CreateNative<pbf_emitter_desc, pbf_emitter_id>(Native.pbf_world_create_emitter, desc.ToNative());
            return new Emitter(this, id, desc.Type);
        }

        /// <summary>A nozzle: particlesPerSecond through a disc of the given radius at position,
        /// moving at speed along direction.</summary>
        public Emitter CreateNozzle(Vector3 position, Vector3 direction, float speed, float radius, float particlesPerSecond)
        {
            return CreateEmitter(EmitterDesc.Nozzle(position, direction, speed, radius, particlesPerSecond));
        }

        /// <summary>A drain: removes the particles inside boxMin..boxMax at each step.</summary>
        public Emitter CreateDrain(Vector3 boxMin, Vector3 boxMax) { return CreateEmitter(EmitterDesc.Drain(boxMin, boxMax)); }

        /// <summary>A collider. Created where fluid is, the next step moves the particles inside it
        /// out and settles them without flinging them (README, Physics, Overlaps).</summary>
        public Collider CreateCollider(ColliderDesc desc)
        {
            if (desc == null) throw new ArgumentNullException("desc");
            var id = CreateNative<pbf_collider_desc, pbf_collider_id>(Native.pbf_world_create_collider, desc.ToNative());
            return new Collider(this, id, desc.Shape, desc.Motion);
        }

        // ---- particles -----------------------------------------------------------------------
        public int ParticleCount
        {
            get
            {
                uint count;
                PbfException.Check(Native.pbf_world_get_particle_count(Handle, out count));
                return (int)count;
            }
        }

        /// <summary>Copies min(ParticleCount, destination.Length / 4) particles as x, y, z, w
        /// (w = density ratio ρ/ρ0, for colouring); returns how many. Index k of positions,
        /// velocities and ids copied between two steps is one particle. Allocates nothing.</summary>
        public int CopyPositions(float[] destination) { return CopyBuffer(BufferSource.Positions, Floats(destination)); }
        public int CopyPositions(Span<float> destination) { return CopyBuffer(BufferSource.Positions, destination); }
        /// <summary>Into any 16-byte vector type (System.Numerics.Vector4, UnityEngine.Vector4, ...).</summary>
        public int CopyPositions<T>(T[] destination) where T : struct { return CopyBuffer(BufferSource.Positions, Floats<T>(destination)); }
        public int CopyPositions<T>(Span<T> destination) where T : struct { return CopyBuffer(BufferSource.Positions, MemoryMarshal.Cast<T, float>(destination)); }

        /// <summary>Velocities as vx, vy, vz, 0; same order as <see cref="CopyPositions(float[])"/>.</summary>
        public int CopyVelocities(float[] destination) { return CopyBuffer(BufferSource.Velocities, Floats(destination)); }
        public int CopyVelocities(Span<float> destination) { return CopyBuffer(BufferSource.Velocities, destination); }
        public int CopyVelocities<T>(T[] destination) where T : struct { return CopyBuffer(BufferSource.Velocities, Floats<T>(destination)); }
        public int CopyVelocities<T>(Span<T> destination) where T : struct { return CopyBuffer(BufferSource.Velocities, MemoryMarshal.Cast<T, float>(destination)); }

        /// <summary>Smoothed positions x̄, ȳ, z̄, density ratio (4 floats per particle); same order as
        /// the positions. Throws <see cref="Result.InvalidState"/> unless the world was created with
        /// <see cref="RenderFlags.SmoothedPositions"/>.</summary>
        public int CopySmoothedPositions(float[] destination) { return CopyBuffer(BufferSource.SmoothedPositions, Floats(destination)); }
        public int CopySmoothedPositions(Span<float> destination) { return CopyBuffer(BufferSource.SmoothedPositions, destination); }
        public int CopySmoothedPositions<T>(T[] destination) where T : struct { return CopyBuffer(BufferSource.SmoothedPositions, Floats<T>(destination)); }

        /// <summary>Anisotropy: 12 floats per particle, 3 rows of (unit axis x, y, z, radius in m),
        /// longest axis first; same order as the positions. Throws <see cref="Result.InvalidState"/>
        /// unless the world was created with <see cref="RenderFlags.Anisotropy"/>.</summary>
        public int CopyAnisotropy(float[] destination) { return CopyBuffer(BufferSource.Anisotropy, Floats(destination)); }
        public int CopyAnisotropy(Span<float> destination) { return CopyBuffer(BufferSource.Anisotropy, destination); }
        /// <summary>Into any 16-byte vector type: 3 elements per particle.</summary>
        public int CopyAnisotropy<T>(T[] destination) where T : struct { return CopyBuffer(BufferSource.Anisotropy, Floats<T>(destination)); }

        /// <summary>Diffuse particles (<see cref="StepStats.DiffuseCount"/>): x, y, z, kind
        /// (<see cref="DiffuseKind"/> as a float) per particle; returns how many. Throws
        /// <see cref="Result.InvalidState"/> without a diffuse capacity.</summary>
        public int CopyDiffusePositions(float[] destination) { return CopyBuffer(BufferSource.DiffusePositions, Floats(destination)); }
        public int CopyDiffusePositions(Span<float> destination) { return CopyBuffer(BufferSource.DiffusePositions, destination); }
        /// <summary>vx, vy, vz, remaining lifetime (s) per diffuse particle, in the order of the positions.</summary>
        public int CopyDiffuseVelocities(float[] destination) { return CopyBuffer(BufferSource.DiffuseVelocities, Floats(destination)); }
        public int CopyDiffuseVelocities(Span<float> destination) { return CopyBuffer(BufferSource.DiffuseVelocities, destination); }

        /// <summary>Stable particle ids (assigned 0, 1, 2, ... at emission), same order as the positions.</summary>
        public int CopyIds(uint[] destination)
        {
            if (destination == null) throw new ArgumentNullException("destination");
            return CopyIds(new Span<uint>(destination));
        }

        public int CopyIds(Span<uint> destination)
        {
            pbf_world_id id = Handle;
            uint written;
            pbf_result r = destination.Length == 0
                ? Native.pbf_world_copy_ids(id, IntPtr.Zero, 0, out written)
                : Native.pbf_world_copy_ids(id, ref MemoryMarshal.GetReference(destination), (uint)destination.Length, out written);
            PbfException.Check(r);
            return (int)written;
        }

        static Span<float> Floats(float[] destination)
        {
            if (destination == null) throw new ArgumentNullException("destination");
            return new Span<float>(destination);
        }

        static Span<float> Floats<T>(T[] destination) where T : struct
        {
            if (destination == null) throw new ArgumentNullException("destination");
            return MemoryMarshal.Cast<T, float>(new Span<T>(destination));
        }

        /// <summary>Copies min(ParticleCount, whole particles that fit) of a float buffer (4 floats
        /// per particle, 12 for the anisotropy) into destination; returns how many particles.</summary>
        public int CopyBuffer(BufferSource source, Span<float> destination)
        {
            if (source == BufferSource.Ids) throw new ArgumentException("ids are uint: use CopyIds", "source");
            if (source == BufferSource.Materials) throw new ArgumentException("materials are bytes: use CopyMaterials", "source");
            int floats = source == BufferSource.Anisotropy ? 12 : 4;
            ulong bytes = (ulong)(destination.Length / floats) * (ulong)(floats * 4);
            pbf_world_id id = Handle;
            uint written;
            pbf_result r = bytes == 0
                ? Native.pbf_world_copy_buffer(id, (pbf_buffer)source, IntPtr.Zero, 0, out written)
                : Native.pbf_world_copy_buffer(id, (pbf_buffer)source, ref MemoryMarshal.GetReference(destination), bytes, out written);
            PbfException.Check(r);
            return (int)written;
        }

        /// <summary>
        /// Maps the live position buffer without a copy (x, y, z, w floats, StrideBytes apart).
        /// Host memory on the CPU backend, a CUDA device pointer on CUDA. Valid until
        /// <see cref="Unmap"/>, the next <see cref="Step"/>, any call that adds or removes
        /// particles, or Dispose. Read-only. Dispose the result (or call Unmap) when done.
        /// </summary>
        /// <summary>Every collider's force row in backend memory (pbf_world_map_collider_forces):
        /// MaxColliders rows of pbf_collider_force, 24 bytes apart, row k for the collider whose
        /// handle index is k. Valid until the world is disposed; on CUDA a device pointer written at
        /// the end of each step on the world's stream (read it there, or after an event).</summary>
        public ColliderForceTable MapColliderForces()
        {
            var b = new pbf_mapped_buffer { struct_size = Native.SizeOf<pbf_mapped_buffer>() };
            PbfException.Check(Native.pbf_world_map_collider_forces(Handle, ref b));
            return new ColliderForceTable((MemoryKind)b.memory, b.data, (int)b.count, (int)b.stride_bytes);
        }

        public MappedPositions MapPositions()
        {
            var buffer = new pbf_mapped_buffer { struct_size = Native.SizeOf<pbf_mapped_buffer>() };
            PbfException.Check(Native.pbf_world_map_positions(Handle, ref buffer));
            return new MappedPositions(this, buffer);
        }

        /// <summary>Ends a mapping; throws <see cref="Result.InvalidState"/> if none is active.</summary>
        public void Unmap() { PbfException.Check(Native.pbf_world_unmap(Handle)); }

        internal void UnmapIfMapped()
        {
            if (IsDisposed) return;
            pbf_result r = Native.pbf_world_unmap(_id);
            if (r != pbf_result.PBF_OK && r != pbf_result.PBF_ERROR_INVALID_STATE && r != pbf_result.PBF_ERROR_INVALID_HANDLE)
                PbfException.Check(r);
        }
    }
}
