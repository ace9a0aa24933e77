// Friendly layer of the header's interop section (zero-copy rendering): CUDA streams and events,
// live buffers as device pointers, OpenGL and Direct3D 11 buffers, the render-thread event,
// interop state and the debug transfer counter. External memory and semaphores (Vulkan,
// Direct3D 12, shared handles) are in the raw layer only (Native.pbf_world_import_external_buffer, ...).
//
// Every function exists in every build of libpbf. What the build lacks throws PbfException with
// Result.BackendUnavailable (no CUDA, a Windows-only API or type on Linux, a driver without the
// entry point a call needs); a CUDA-only call on a world that runs on the CPU backend throws
// Result.InvalidState.
using System;
using System.Runtime.InteropServices;
using Pbf.Interop;

namespace Pbf
{
    public static partial class Library
    {
        /// <summary>PBF_RENDER_EVENT_ALL_WORLDS: the render event id that runs every world's render work.</summary>
        public const int RenderEventAllWorlds = Native.PBF_RENDER_EVENT_ALL_WORLDS;

        /// <summary>pbf_get_interop_support(): what this build of libpbf can do (None for a build without CUDA).</summary>
        public static InteropSupport GetInteropSupport()
        {
            uint flags;
            PbfException.Check(Native.pbf_get_interop_support(out flags));
            return (InteropSupport)flags;
        }

        /// <summary>
        /// pbf_get_render_event_func(): the native render-thread entry point, never IntPtr.Zero.
        /// In Unity: <c>GL.IssuePluginEvent(Library.GetRenderEventFunc(), world.GetRenderEventId())</c>
        /// (or <see cref="RenderEventAllWorlds"/>) from a command buffer or each frame; it runs the
        /// work of <see cref="CopyMode.OnRenderEvent"/> buffers on the render thread: pending GL
        /// registrations, the copies, pending unregistrations. Failures go to the log and to
        /// <see cref="InteropInfo.LastRenderEventResult"/>.
        /// </summary>
        public static IntPtr GetRenderEventFunc() { return Native.pbf_get_render_event_func(); }

        static pbf_render_event_fn s_renderEvent;

        /// <summary>Calls the render event function on this thread, for hosts that own their render
        /// thread (no plugin-event mechanism): it must be the thread whose GL context holds the
        /// buffers. Returns nothing; failures go to the log and to the world's InteropInfo.</summary>
        public static void IssueRenderEvent(int eventId)
        {
            pbf_render_event_fn fn = s_renderEvent;
            if (fn == null)
            {
                fn = (pbf_render_event_fn)Marshal.GetDelegateForFunctionPointer(GetRenderEventFunc(), typeof(pbf_render_event_fn));
                s_renderEvent = fn;
            }
            fn(eventId);
        }

        /// <summary>pbf_debug_get_transfer_count(): host&lt;-&gt;device copies libpbf has made,
        /// process-wide, since it was loaded (copy-out, stats, particle counts on CUDA). The CPU
        /// backend has no device, so it makes none; the render path adds none on any backend.</summary>
        public static TransferCount GetTransferCount()
        {
            ulong transfers, bytes;
            PbfException.Check(Native.pbf_debug_get_transfer_count(out transfers, out bytes));
            return new TransferCount((long)transfers, (long)bytes);
        }
    }

    /// <summary>The debug transfer counter (<see cref="Library.GetTransferCount"/>).</summary>
    public readonly struct TransferCount
    {
        public TransferCount(long transfers, long bytes) { Transfers = transfers; Bytes = bytes; }
        /// <summary>Host&lt;-&gt;device copies so far.</summary>
        public long Transfers { get; }
        /// <summary>Bytes they moved.</summary>
        public long Bytes { get; }
        public override string ToString() { return Transfers + " transfers, " + Bytes + " bytes"; }
    }

    public sealed partial class World
    {
        // ---- streams and events ---------------------------------------------------------------
        /// <summary>The cudaStream_t the world queues its work on (CUDA worlds only).</summary>
        public IntPtr GetCudaStream()
        {
            IntPtr stream;
            PbfException.Check(Native.pbf_world_get_cuda_stream(Handle, out stream));
            return stream;
        }

        /// <summary>Makes the world queue its work on stream (a cudaStream_t of its device) from
        /// now on; IntPtr.Zero returns it to its own stream. The caller keeps the stream alive
        /// until it hands the world another one or disposes the world.</summary>
        public void SetCudaStream(IntPtr stream) { PbfException.Check(Native.pbf_world_set_cuda_stream(Handle, stream)); }

        /// <summary>Records the world's cudaEvent_t at the current end of its stream and returns
        /// it (the same event each call, owned by the world).</summary>
        public IntPtr RecordCudaEvent()
        {
            IntPtr ev;
            PbfException.Check(Native.pbf_world_record_cuda_event(Handle, out ev));
            return ev;
        }

        /// <summary>Makes the world's stream wait for a cudaEvent_t recorded by the caller before its next work.</summary>
        public void WaitCudaEvent(IntPtr cudaEvent) { PbfException.Check(Native.pbf_world_wait_cuda_event(Handle, cudaEvent)); }

        // ---- live buffers ---------------------------------------------------------------------
        /// <summary>
        /// Maps the live positions, velocities and ids without copying (pbf_world_map_device_buffers):
        /// CUDA device pointers on CUDA, host pointers on the CPU backend. Read-only; valid until
        /// Dispose/<see cref="Unmap"/>, the next step, any call that adds or removes particles,
        /// or the world's Dispose. noWait (CUDA): return at once, with the count on the device only.
        /// </summary>
        public DeviceBuffers MapDeviceBuffers(bool noWait = false)
        {
            var b = new pbf_device_buffers { struct_size = Native.SizeOf<pbf_device_buffers>() };
            PbfException.Check(Native.pbf_world_map_device_buffers(Handle, noWait ? Native.PBF_MAP_NO_WAIT : 0u, ref b));
            return new DeviceBuffers(this, b);
        }

        // ---- OpenGL ---------------------------------------------------------------------------
        /// <summary>Registers a GL buffer object as a copy destination (see <see cref="GlBufferDesc"/>).
        /// OnStep and Manual register now: call with a GL context current that owns the buffer.
        /// OnRenderEvent registers at the next render event, on the render thread.</summary>
        public GlBuffer RegisterGlBuffer(GlBufferDesc desc)
        {
            if (desc == null) throw new ArgumentNullException("desc");
            var id = CreateNative<pbf_gl_buffer_desc, pbf_gl_buffer_id>(Native.pbf_world_register_gl_buffer, desc.ToNative());
            return new GlBuffer(this, id, desc.Mode);
        }

        /// <summary>Unregisters (now, or at the next render event for OnRenderEvent buffers). The
        /// handle is refused from this call on.</summary>
        public void UnregisterGlBuffer(GlBuffer buffer)
        {
            if (buffer == null) throw new ArgumentNullException("buffer");
            buffer.Unregister();
        }

        /// <summary>Queues a copy of the current particles into the buffer now (not for OnRenderEvent buffers).</summary>
        public void CopyToGlBuffer(GlBuffer buffer)
        {
            if (buffer == null) throw new ArgumentNullException("buffer");
            buffer.Copy();
        }

        // ---- Direct3D 11 ------------------------------------------------------------------------
        /// <summary>Registers a D3D11 buffer as a copy destination (see <see cref="D3D11BufferDesc"/>):
        /// in Unity under Direct3D 11, a GraphicsBuffer's or ComputeBuffer's GetNativeBufferPtr().
        /// OnRenderEvent (the default) registers at the next render event and copies at every one,
        /// on the render thread, which owns the D3D11 immediate context. Windows builds only; not
        /// yet run on a GPU.</summary>
        public D3D11Buffer RegisterD3D11Buffer(D3D11BufferDesc desc)
        {
            if (desc == null) throw new ArgumentNullException("desc");
            var id = CreateNative<pbf_d3d11_buffer_desc, pbf_d3d11_buffer_id>(Native.pbf_world_register_d3d11_buffer, desc.ToNative());
            return new D3D11Buffer(this, id, desc.Mode);
        }

        /// <summary>Unregisters (at the next render event for OnRenderEvent buffers, until which the
        /// D3D11 buffers must stay alive; now for OnStep). The handle is refused from this call on.
        /// Disposing the world unregisters what is left from the disposing thread: unregister and
        /// let a render event run first where that is not the render thread.</summary>
        public void UnregisterD3D11Buffer(D3D11Buffer buffer)
        {
            if (buffer == null) throw new ArgumentNullException("buffer");
            buffer.Unregister();
        }

        // ---- render event and state -----------------------------------------------------------
        /// <summary>The render event id (&gt; 0) that selects this world alone, for
        /// <see cref="Library.GetRenderEventFunc"/>.</summary>
        public int GetRenderEventId()
        {
            int eventId;
            PbfException.Check(Native.pbf_world_get_render_event_id(Handle, out eventId));
            return eventId;
        }

        /// <summary>Interop state, device identity and copy cost of this world.</summary>
        public InteropInfo GetInteropInfo()
        {
            var info = new pbf_interop_info { struct_size = Native.SizeOf<pbf_interop_info>() };
            PbfException.Check(Native.pbf_world_get_interop_info(Handle, ref info));
            return new InteropInfo(info);
        }
    }

    /// <summary>The live particle buffers of a world (pbf_device_buffers). Dispose ends the mapping.</summary>
    public readonly struct DeviceBuffers : IDisposable
    {
        readonly World _world;

        internal DeviceBuffers(World world, pbf_device_buffers raw)
        {
            _world = world;
            Raw = raw;
        }

        /// <summary>The raw struct as the library filled it.</summary>
        public pbf_device_buffers Raw { get; }

        /// <summary>CudaDevice on CUDA; Host on the CPU backend.</summary>
        public MemoryKind Memory { get { return (MemoryKind)Raw.memory; } }
        /// <summary>float x, y, z, density ratio per particle, <see cref="Vec4StrideBytes"/> apart.</summary>
        public IntPtr Positions { get { return Raw.positions; } }
        /// <summary>float vx, vy, vz, 0 per particle.</summary>
        public IntPtr Velocities { get { return Raw.velocities; } }
        /// <summary>uint stable ids, <see cref="IdStrideBytes"/> apart.</summary>
        public IntPtr Ids { get { return Raw.ids; } }
        /// <summary>Positions + 12 bytes: the w of each position, stride 16.</summary>
        public IntPtr DensityRatio { get { return Raw.density_ratio; } }
        /// <summary>const uint*: the live count, in memory of kind <see cref="Memory"/>.</summary>
        public IntPtr CountDevice { get { return Raw.count_device; } }
        /// <summary>The world's cudaStream_t (IntPtr.Zero on the CPU backend).</summary>
        public IntPtr CudaStream { get { return Raw.cuda_stream; } }
        /// <summary>True when mapped with noWait on CUDA: the count is only on the device.</summary>
        public bool IsCountOnDevice { get { return Raw.count == Native.PBF_COUNT_ON_DEVICE; } }
        /// <summary>Live particles; -1 when <see cref="IsCountOnDevice"/>.</summary>
        public int Count { get { return IsCountOnDevice ? -1 : (int)Raw.count; } }
        /// <summary>Elements allocated behind each pointer (the world's MaxParticles).</summary>
        public int Capacity { get { return (int)Raw.capacity; } }
        public int Vec4StrideBytes { get { return (int)Raw.vec4_stride_bytes; } }
        public int IdStrideBytes { get { return (int)Raw.id_stride_bytes; } }
        /// <summary>The CUDA device the pointers belong to; -1 on the CPU backend.</summary>
        public int CudaDevice { get { return Raw.cuda_device; } }
        /// <summary>float x̄, ȳ, z̄, density ratio per particle, stride 16; IntPtr.Zero unless the
        /// world computes <see cref="Pbf.RenderFlags.SmoothedPositions"/>.</summary>
        public IntPtr SmoothedPositions { get { return Raw.smoothed_positions; } }
        /// <summary>3 float4 rows (unit axis, radius) per particle, <see cref="AnisotropyStrideBytes"/>
        /// apart; IntPtr.Zero unless the world computes <see cref="Pbf.RenderFlags.Anisotropy"/>.</summary>
        public IntPtr Anisotropy { get { return Raw.anisotropy; } }
        public int AnisotropyStrideBytes { get { return (int)Raw.anisotropy_stride_bytes; } }
        /// <summary>The render data the world computes.</summary>
        public RenderFlags RenderFlags { get { return (RenderFlags)Raw.render_flags; } }
        /// <summary>float x, y, z, kind per diffuse particle, stride 16; IntPtr.Zero without a
        /// diffuse capacity (<see cref="DiffuseParams.MaxDiffuse"/>).</summary>
        public IntPtr DiffusePositions { get { return Raw.diffuse_positions; } }
        /// <summary>float vx, vy, vz, remaining lifetime (s) per diffuse particle, stride 16.</summary>
        public IntPtr DiffuseVelocities { get { return Raw.diffuse_velocities; } }
        /// <summary>The live diffuse count in memory of kind <see cref="Memory"/>.</summary>
        public IntPtr DiffuseCountDevice { get { return Raw.diffuse_count_device; } }
        /// <summary>Live diffuse particles; Native.PBF_COUNT_ON_DEVICE when mapped without waiting on CUDA.</summary>
        public uint DiffuseCount { get { return Raw.diffuse_count; } }
        /// <summary>Diffuse particles allocated behind each diffuse pointer.</summary>
        public int DiffuseCapacity { get { return (int)Raw.diffuse_capacity; } }
        /// <summary>byte per particle (stride 1): the index of its material
        /// (<see cref="BufferSource.Materials"/>, <see cref="World.Materials"/>), in the positions' order.</summary>
        public IntPtr Materials { get { return Raw.materials; } }

        /// <summary>Ends the world's mapping; does nothing when a step or another call already ended it.</summary>
        public void Dispose()
        {
            if (_world != null) _world.UnmapIfMapped();
        }
    }

    /// <summary>How to register a GL buffer object (pbf_gl_buffer_desc). A new desc holds the
    /// library's defaults: source Positions, mode OnStep; Buffer and Capacity must be set.</summary>
    public sealed class GlBufferDesc
    {
        pbf_gl_buffer_desc _raw;

        public GlBufferDesc()
        {
            _raw.struct_size = Native.SizeOf<pbf_gl_buffer_desc>();
            PbfException.Check(Native.pbf_gl_buffer_desc_init(ref _raw, _raw.struct_size));
        }

        /// <summary>buffer: a GL buffer object name, capacity: elements it holds after OffsetBytes.</summary>
        public GlBufferDesc(uint buffer, int capacity, BufferSource source = BufferSource.Positions, CopyMode mode = CopyMode.OnStep)
            : this()
        {
            Buffer = buffer;
            Capacity = capacity;
            Source = source;
            Mode = mode;
        }

        public pbf_gl_buffer_desc ToNative() { return _raw; }

        /// <summary>GL buffer object name (GLuint), non-zero; with its storage already allocated.</summary>
        public uint Buffer { get { return _raw.buffer; } set { _raw.buffer = value; } }
        public BufferSource Source { get { return (BufferSource)_raw.source; } set { _raw.source = (pbf_buffer)value; } }
        public CopyMode Mode { get { return (CopyMode)_raw.mode; } set { _raw.mode = (pbf_copy_mode)value; } }
        /// <summary>Where element 0 goes; a multiple of 16 (4 for ids).</summary>
        public long OffsetBytes { get { return (long)_raw.offset_bytes; } set { _raw.offset_bytes = (ulong)value; } }
        /// <summary>Elements the buffer holds after OffsetBytes (&gt; 0).</summary>
        public int Capacity { get { return (int)_raw.capacity; } set { _raw.capacity = (uint)value; } }
        /// <summary>GL buffer that receives 4 uint draw arguments at each copy (0: none).</summary>
        public uint DrawArgsBuffer { get { return _raw.draw_args_buffer; } set { _raw.draw_args_buffer = value; } }
        /// <summary>A multiple of 4.</summary>
        public long DrawArgsOffsetBytes { get { return (long)_raw.draw_args_offset_bytes; } set { _raw.draw_args_offset_bytes = (ulong)value; } }
        /// <summary>0: {n, 1, 0, 0} (n points); v &gt; 0: {v, n, 0, 0} (v vertices per particle, n instances).</summary>
        public int DrawArgsVertices { get { return (int)_raw.draw_args_vertices; } set { _raw.draw_args_vertices = (uint)value; } }
    }

    /// <summary>A GL buffer registered with a world (<see cref="World.RegisterGlBuffer"/>). After
    /// <see cref="Unregister"/> the handle is stale: further calls throw <see cref="Result.InvalidHandle"/>.</summary>
    public sealed class GlBuffer : WorldHandle<pbf_gl_buffer_id>
    {
        internal GlBuffer(World world, pbf_gl_buffer_id id, CopyMode mode) : base(world, id) { Mode = mode; }

        public CopyMode Mode { get; private set; }

        /// <summary>pbf_world_copy_to_gl_buffer: queues a copy of the current particles now.</summary>
        public void Copy() { PbfException.Check(Native.pbf_world_copy_to_gl_buffer(World.Handle, Id)); }

        /// <summary>pbf_world_unregister_gl_buffer (GL context current, as for registration).</summary>
        public void Unregister() { PbfException.Check(Native.pbf_world_unregister_gl_buffer(World.Handle, Id)); }
    }

    /// <summary>How to register a D3D11 buffer (pbf_d3d11_buffer_desc). A new desc holds the
    /// library's defaults: source Positions, mode OnRenderEvent; Buffer and Capacity must be set.
    /// The buffer must belong to the D3D11 device on the adapter of the world's CUDA device
    /// (<see cref="InteropInfo.DeviceLuid"/>). libpbf holds no reference to it: keep it alive until
    /// it is unregistered and a render event has run.</summary>
    public sealed class D3D11BufferDesc
    {
        pbf_d3d11_buffer_desc _raw;

        public D3D11BufferDesc()
        {
            _raw.struct_size = Native.SizeOf<pbf_d3d11_buffer_desc>();
            PbfException.Check(Native.pbf_d3d11_buffer_desc_init(ref _raw, _raw.struct_size));
        }

        /// <summary>buffer: an ID3D11Buffer*, capacity: elements it holds after OffsetBytes.</summary>
        public D3D11BufferDesc(IntPtr buffer, int capacity, BufferSource source = BufferSource.Positions,
                               CopyMode mode = CopyMode.OnRenderEvent)
            : this()
        {
            Buffer = buffer;
            Capacity = capacity;
            Source = source;
            Mode = mode;
        }

        public pbf_d3d11_buffer_desc ToNative() { return _raw; }

        /// <summary>The ID3D11Buffer* (non-zero), with its storage; e.g. GraphicsBuffer.GetNativeBufferPtr().</summary>
        public IntPtr Buffer { get { return _raw.buffer; } set { _raw.buffer = value; } }
        public BufferSource Source { get { return (BufferSource)_raw.source; } set { _raw.source = (pbf_buffer)value; } }
        /// <summary>OnRenderEvent or OnStep; D3D11 has no manual copy (the immediate context is the
        /// render thread's). OnStep copies from the thread that steps: only where that is the render
        /// thread or the device is multithread-protected.</summary>
        public CopyMode Mode { get { return (CopyMode)_raw.mode; } set { _raw.mode = (pbf_copy_mode)value; } }
        /// <summary>Where element 0 goes; a multiple of 16 (4 for ids).</summary>
        public long OffsetBytes { get { return (long)_raw.offset_bytes; } set { _raw.offset_bytes = (ulong)value; } }
        /// <summary>Elements the buffer holds after OffsetBytes (&gt; 0).</summary>
        public int Capacity { get { return (int)_raw.capacity; } set { _raw.capacity = (uint)value; } }
        /// <summary>ID3D11Buffer* (IntPtr.Zero: none; may be <see cref="Buffer"/>) that receives 4
        /// uint draw arguments at each copy, as DrawInstancedIndirect reads them.</summary>
        public IntPtr DrawArgsBuffer { get { return _raw.draw_args_buffer; } set { _raw.draw_args_buffer = value; } }
        /// <summary>A multiple of 4.</summary>
        public long DrawArgsOffsetBytes { get { return (long)_raw.draw_args_offset_bytes; } set { _raw.draw_args_offset_bytes = (ulong)value; } }
        /// <summary>0: {n, 1, 0, 0} (n points); v &gt; 0: {v, n, 0, 0} (v vertices per particle, n instances).</summary>
        public int DrawArgsVertices { get { return (int)_raw.draw_args_vertices; } set { _raw.draw_args_vertices = (uint)value; } }
    }

    /// <summary>A D3D11 buffer registered with a world (<see cref="World.RegisterD3D11Buffer"/>).
    /// After <see cref="Unregister"/> the handle is stale: further calls throw <see cref="Result.InvalidHandle"/>.</summary>
    public sealed class D3D11Buffer : WorldHandle<pbf_d3d11_buffer_id>
    {
        internal D3D11Buffer(World world, pbf_d3d11_buffer_id id, CopyMode mode) : base(world, id) { Mode = mode; }

        public CopyMode Mode { get; private set; }

        /// <summary>pbf_world_unregister_d3d11_buffer.</summary>
        public void Unregister() { PbfException.Check(Native.pbf_world_unregister_d3d11_buffer(World.Handle, Id)); }
    }

    /// <summary>Interop state of a world (pbf_interop_info).</summary>
    public struct InteropInfo
    {
        readonly pbf_interop_info _raw;
        readonly string _message;

        public InteropInfo(pbf_interop_info raw)
        {
            _raw = raw;
            _message = raw.last_render_event_message.ToString();
        }

        public pbf_interop_info ToNative() { return _raw; }

        /// <summary>Registered GL buffers, pending ones included.</summary>
        public int GlBuffers { get { return (int)_raw.gl_buffers; } }
        public int ExternalBuffers { get { return (int)_raw.external_buffers; } }
        public int Semaphores { get { return (int)_raw.semaphores; } }
        /// <summary>Copies into graphics buffers so far.</summary>
        public long Copies { get { return (long)_raw.copies; } }
        /// <summary>Render events that ran for this world.</summary>
        public long RenderEvents { get { return (long)_raw.render_events; } }
        public float LastCopyGpuMs { get { return _raw.last_copy_gpu_ms; } }
        public float LastCopyHostMs { get { return _raw.last_copy_host_ms; } }
        /// <summary>Ok, or why the last render event failed (see <see cref="LastRenderEventMessage"/>).</summary>
        public Result LastRenderEventResult { get { return (Result)_raw.last_render_event_result; } }
        /// <summary>Registrations and unregistrations queued for the render event.</summary>
        public int PendingRenderWork { get { return (int)_raw.pending_render_work; } }
        /// <summary>The CUDA device's UUID (match VkPhysicalDeviceIDProperties::deviceUUID).</summary>
        public byte[] DeviceUuid { get { return _raw.device_uuid.ToArray(); } }
        /// <summary>Its LUID on Windows; else zeros.</summary>
        public byte[] DeviceLuid { get { return _raw.device_luid.ToArray(); } }
        public uint DeviceNodeMask { get { return _raw.device_node_mask; } }
        /// <summary>-1 on the CPU backend.</summary>
        public int CudaDevice { get { return _raw.cuda_device; } }
        /// <summary>"" or the last render event's failure.</summary>
        public string LastRenderEventMessage { get { return _message ?? string.Empty; } }
    }
}
