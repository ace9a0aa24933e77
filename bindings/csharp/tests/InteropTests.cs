using System;
using System.Collections.Generic;
using System.Numerics;
using System.Runtime.InteropServices;
using NUnit.Framework;
using Pbf.Interop;

namespace Pbf.Tests
{
    /// <summary>
    /// The interop section (zero-copy rendering) on the CPU backend. The tests run against the
    /// CPU-only library: there every CUDA, OpenGL and external-memory call is refused with
    /// PBF_ERROR_BACKEND_UNAVAILABLE after its arguments are checked. Against a CUDA build the
    /// same calls on a CPU world are PBF_ERROR_INVALID_STATE (the header's rule for CUDA-only
    /// calls on CPU worlds); the expected code follows pbf_get_interop_support.
    /// </summary>
    [TestFixture]
    public class InteropTests
    {
        World _world;
        InteropSupport _support;

        [SetUp]
        public void SetUp()
        {
            _support = Library.GetInteropSupport();
            _world = Scene.CpuWorld(2048);
            _world.EmitBlock(new Vector3(-0.2f, 0.1f, -0.2f), new Vector3(0.2f, 0.4f, 0.2f));
            _world.Step(Scene.Dt);
        }

        [TearDown]
        public void TearDown()
        {
            _world.Dispose();
            Library.SetLogHandler(null);
        }

        bool HasCuda { get { return (_support & InteropSupport.Cuda) != 0; } }

        /// <summary>The code a CPU world gets for a call that needs the given support.</summary>
        Result OnCpuWorld(InteropSupport needed)
        {
            return (_support & needed) == 0 ? Result.BackendUnavailable : Result.InvalidState;
        }

        /// <summary>The code a handle no registration made gets: no such API in the build, or no such handle.</summary>
        pbf_result ForgedHandle(InteropSupport needed)
        {
            return (_support & needed) == 0 ? pbf_result.PBF_ERROR_BACKEND_UNAVAILABLE : pbf_result.PBF_ERROR_INVALID_HANDLE;
        }

        string OnCpuWorldText(InteropSupport needed)
        {
            if ((_support & needed) != 0) return "the world runs on the CPU backend";
            return HasCuda ? "" : "this libpbf was built without CUDA";
        }

        static void ExpectRaw(pbf_result expected, pbf_result actual, params string[] fragments)
        {
            string message = Native.LastErrorMessage();
            Assert.AreEqual(expected, actual, message);
            StringAssert.StartsWith(Native.ResultString(expected) + ": ", message);
            foreach (var f in fragments) StringAssert.Contains(f, message);
        }

        static pbf_world_id StaleId()
        {
            var d = Native.pbf_world_desc_default();
            d.backend = pbf_backend.PBF_BACKEND_CPU;
            d.max_particles = 64;
            pbf_world_id id;
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_create(ref d, out id));
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_destroy(id));
            return id;
        }

        // ---- support -----------------------------------------------------------------------------
        [Test]
        public void InteropSupportReportsNoCudaAndNoGl()
        {
            Assert.AreEqual(0u, (uint)_support & ~0x1Fu, "only the header's bits");
            if (HasCuda) Assert.Ignore("this libpbf was built with CUDA (support " + _support + "); the test is for the CPU-only build");
            Assert.AreEqual(InteropSupport.None, _support);
            Assert.IsFalse(_support.HasFlag(InteropSupport.OpenGL));
            Assert.IsFalse(_support.HasFlag(InteropSupport.ExternalFd));
            Assert.IsFalse(_support.HasFlag(InteropSupport.ExternalWin32));
            Assert.IsFalse(_support.HasFlag(InteropSupport.D3D11));

            uint raw;
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_get_interop_support(out raw));
            Assert.AreEqual(0u, raw);
        }

        [Test]
        public void InteropSupportRefusesANullPointer()
        {
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_get_interop_support(IntPtr.Zero),
                "pbf_get_interop_support", "out_flags is NULL");
        }

        // ---- streams and events --------------------------------------------------------------
        [Test]
        public void CudaStreamAndEventCallsAreRefusedOnACpuWorld()
        {
            Result code = OnCpuWorld(InteropSupport.Cuda);
            string why = OnCpuWorldText(InteropSupport.Cuda);
            Scene.ExpectError(code, () => _world.GetCudaStream(), "pbf_world_get_cuda_stream", why);
            Scene.ExpectError(code, () => _world.SetCudaStream(IntPtr.Zero), "pbf_world_set_cuda_stream", why);
            Scene.ExpectError(code, () => _world.SetCudaStream(new IntPtr(0x1000)), "pbf_world_set_cuda_stream", why);
            Scene.ExpectError(code, () => _world.RecordCudaEvent(), "pbf_world_record_cuda_event", why);
            Scene.ExpectError(code, () => _world.WaitCudaEvent(new IntPtr(0x1000)), "pbf_world_wait_cuda_event", why);

            // The out parameter is cleared on failure; NULL arguments are refused first.
            IntPtr stream = new IntPtr(1);
            ExpectRaw((pbf_result)code, Native.pbf_world_get_cuda_stream(_world.Id, out stream));
            Assert.AreEqual(IntPtr.Zero, stream);
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_get_cuda_stream(_world.Id, IntPtr.Zero), "out_stream is NULL");
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_record_cuda_event(_world.Id, IntPtr.Zero), "out_event is NULL");
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_wait_cuda_event(_world.Id, IntPtr.Zero), "event is NULL");

            // Nothing changed: the world still steps.
            _world.Step(Scene.Dt);
        }

        // ---- device buffers ----------------------------------------------------------------------
        [Test]
        public void MapDeviceBuffersOnACpuWorldGivesHostMemory()
        {
            // The header: memory is HOST on the CPU backend, cuda_stream NULL, cuda_device -1.
            Vector4[] positions = Scene.Positions(_world);
            Vector4[] velocities = Scene.Velocities(_world);
            uint[] ids = Scene.Ids(_world);
            int n = positions.Length;
            Assert.Greater(n, 100);

            foreach (bool noWait in new[] { false, true })
            {
                using (DeviceBuffers b = _world.MapDeviceBuffers(noWait))
                {
                    Assert.AreEqual(MemoryKind.Host, b.Memory);
                    Assert.AreEqual(-1, b.CudaDevice);
                    Assert.AreEqual(IntPtr.Zero, b.CudaStream);
                    Assert.IsFalse(b.IsCountOnDevice, "the CPU backend always knows its count");
                    Assert.AreEqual(n, b.Count);
                    Assert.AreEqual(2048, b.Capacity);
                    Assert.AreEqual(16, b.Vec4StrideBytes);
                    Assert.AreEqual(4, b.IdStrideBytes);
                    Assert.AreEqual(b.Positions + 12, b.DensityRatio);
                    Assert.AreEqual(n, Marshal.ReadInt32(b.CountDevice), "*count_device in host memory");

                    var p = new float[n * 4];
                    var v = new float[n * 4];
                    var i = new int[n];
                    Marshal.Copy(b.Positions, p, 0, p.Length);
                    Marshal.Copy(b.Velocities, v, 0, v.Length);
                    Marshal.Copy(b.Ids, i, 0, i.Length);
                    for (int k = 0; k < n; ++k)
                    {
                        Assert.AreEqual(positions[k], new Vector4(p[4 * k], p[4 * k + 1], p[4 * k + 2], p[4 * k + 3]));
                        Assert.AreEqual(velocities[k], new Vector4(v[4 * k], v[4 * k + 1], v[4 * k + 2], v[4 * k + 3]));
                        Assert.AreEqual(ids[k], (uint)i[k]);
                        Assert.AreEqual(positions[k].W, BitConverter.Int32BitsToSingle(Marshal.ReadInt32(b.DensityRatio, 16 * k)));
                    }
                }
                // Dispose ended the mapping.
                Scene.ExpectError(Result.InvalidState, () => _world.Unmap(), "no buffer is mapped");
            }

            // A step ends the mapping too; Dispose afterwards stays quiet.
            DeviceBuffers m = _world.MapDeviceBuffers();
            _world.Step(Scene.Dt);
            m.Dispose();
            Scene.ExpectError(Result.InvalidState, () => _world.Unmap());
            _world.MapDeviceBuffers();
            _world.Unmap();
        }

        [Test]
        public void MapDeviceBuffersRefusesBadArgumentsAndHandles()
        {
            var b = new pbf_device_buffers { struct_size = Native.SizeOf<pbf_device_buffers>() };
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_map_device_buffers(_world.Id, 2u, ref b),
                "pbf_world_map_device_buffers", "flags must be 0 or PBF_MAP_NO_WAIT");
            b.struct_size = 8;
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_map_device_buffers(_world.Id, 0, ref b), "pbf_device_buffers");
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_map_device_buffers(_world.Id, 0, IntPtr.Zero));
            b.struct_size = Native.SizeOf<pbf_device_buffers>();
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_map_device_buffers(StaleId(), 0, ref b), "pbf_world_map_device_buffers");
            // None of those mapped anything.
            Scene.ExpectError(Result.InvalidState, () => _world.Unmap(), "no buffer is mapped");

            World other = Scene.CpuWorld(64);
            other.Dispose();
            Assert.Throws<ObjectDisposedException>(() => other.MapDeviceBuffers());
        }

        // ---- OpenGL ------------------------------------------------------------------------------
        [Test]
        public void GlBufferDescHasTheLibraryDefaults()
        {
            var d = new GlBufferDesc();
            Assert.AreEqual(BufferSource.Positions, d.Source);
            Assert.AreEqual(CopyMode.OnStep, d.Mode);
            Assert.AreEqual(0u, d.Buffer);
            Assert.AreEqual(0, d.Capacity);
            Assert.AreEqual(0u, d.DrawArgsBuffer);
            Assert.AreEqual(0, d.DrawArgsVertices);
            Assert.AreEqual(Native.SizeOf<pbf_gl_buffer_desc>(), d.ToNative().struct_size);
            pbf_gl_buffer_desc raw = Native.pbf_gl_buffer_desc_default();
            Assert.AreEqual(pbf_copy_mode.PBF_COPY_ON_STEP, raw.mode);

            var wrong = new pbf_gl_buffer_desc();
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_gl_buffer_desc_init(ref wrong, Native.SizeOf<pbf_gl_buffer_desc>() - 4), "pbf_gl_buffer_desc_init");
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_gl_buffer_desc_init(IntPtr.Zero, Native.SizeOf<pbf_gl_buffer_desc>()));
        }

        [Test]
        public void GlRegistrationOnACpuWorldIsRefused()
        {
            Result code = OnCpuWorld(InteropSupport.OpenGL);
            foreach (CopyMode mode in new[] { CopyMode.OnStep, CopyMode.OnRenderEvent, CopyMode.Manual })
                foreach (BufferSource source in new[] { BufferSource.Positions, BufferSource.Velocities, BufferSource.Ids })
                {
                    var desc = new GlBufferDesc(buffer: 7, capacity: 2048, source: source, mode: mode);
                    Scene.ExpectError(code, () => _world.RegisterGlBuffer(desc), "pbf_world_register_gl_buffer", OnCpuWorldText(InteropSupport.OpenGL));
                }

            // The handle stays zeroed on failure.
            pbf_gl_buffer_desc raw = new GlBufferDesc(7, 16).ToNative();
            var id = new pbf_gl_buffer_id { index = 5, generation = 5 };
            ExpectRaw((pbf_result)code, Native.pbf_world_register_gl_buffer(_world.Id, ref raw, out id));
            Assert.AreEqual(0u, id.index);
            Assert.AreEqual(0u, id.generation);

            // Unregistering or copying a handle no registration made: no GL in the build, or no such buffer.
            var forged = new pbf_gl_buffer_id { index = 1, generation = 1 };
            pbf_result noHandle = ForgedHandle(InteropSupport.OpenGL);
            ExpectRaw(noHandle, Native.pbf_world_unregister_gl_buffer(_world.Id, forged), "pbf_world_unregister_gl_buffer");
            ExpectRaw(noHandle, Native.pbf_world_copy_to_gl_buffer(_world.Id, forged), "pbf_world_copy_to_gl_buffer");

            Assert.AreEqual(0, _world.GetInteropInfo().GlBuffers);
            _world.Step(Scene.Dt);
        }

        [Test]
        public void GlRegistrationChecksItsArgumentsFirst()
        {
            Scene.ExpectError(Result.InvalidArgument, () => _world.RegisterGlBuffer(new GlBufferDesc { Capacity = 16 }),
                "buffer must be a GL buffer object name");
            Scene.ExpectError(Result.InvalidArgument, () => _world.RegisterGlBuffer(new GlBufferDesc(3, 0)), "capacity must be > 0");
            Scene.ExpectError(Result.InvalidArgument, () => _world.RegisterGlBuffer(new GlBufferDesc(3, 16) { OffsetBytes = 8 }),
                "offset_bytes must be a multiple of 16");
            Scene.ExpectError(Result.InvalidArgument, () => _world.RegisterGlBuffer(new GlBufferDesc(3, 16) { DrawArgsOffsetBytes = 2 }),
                "draw_args_offset_bytes must be a multiple of 4");
            Scene.ExpectError(Result.InvalidArgument, () => _world.RegisterGlBuffer(new GlBufferDesc(3, 16) { Source = (BufferSource)9 }),
                "source must be");
            Scene.ExpectError(Result.InvalidArgument, () => _world.RegisterGlBuffer(new GlBufferDesc(3, 16) { Mode = (CopyMode)0 }),
                "mode must be");
            // Ids are 4 bytes: an offset of 4 passes the argument checks.
            Scene.ExpectError(OnCpuWorld(InteropSupport.OpenGL),
                () => _world.RegisterGlBuffer(new GlBufferDesc(3, 16, BufferSource.Ids) { OffsetBytes = 4 }));
            Assert.Throws<ArgumentNullException>(() => _world.RegisterGlBuffer(null));
            Assert.Throws<ArgumentNullException>(() => _world.UnregisterGlBuffer(null));
            Assert.Throws<ArgumentNullException>(() => _world.CopyToGlBuffer(null));

            pbf_gl_buffer_desc raw = new GlBufferDesc(3, 16).ToNative();
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_register_gl_buffer(_world.Id, ref raw, IntPtr.Zero), "out_buffer is NULL");
            raw.reserved0 = 1;
            pbf_gl_buffer_id id;
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_register_gl_buffer(_world.Id, ref raw, out id), "reserved0 must be 0");
            raw = new GlBufferDesc(3, 16).ToNative();
            raw.struct_size -= 8;
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_register_gl_buffer(_world.Id, ref raw, out id));
        }

        // ---- Direct3D 11 --------------------------------------------------------------------------
        // A made-up ID3D11Buffer*: the calls below never reach a D3D11 device (no Windows, no CUDA
        // world), and the library never dereferences it before the render thread registers it.
        static readonly IntPtr FakeD3D11Buffer = new IntPtr(0x1000);

        [Test]
        public void D3D11BufferDescHasTheLibraryDefaults()
        {
            var d = new D3D11BufferDesc();
            Assert.AreEqual(BufferSource.Positions, d.Source);
            Assert.AreEqual(CopyMode.OnRenderEvent, d.Mode, "the render thread owns the D3D11 immediate context");
            Assert.AreEqual(IntPtr.Zero, d.Buffer);
            Assert.AreEqual(0, d.Capacity);
            Assert.AreEqual(0L, d.OffsetBytes);
            Assert.AreEqual(IntPtr.Zero, d.DrawArgsBuffer);
            Assert.AreEqual(0L, d.DrawArgsOffsetBytes);
            Assert.AreEqual(0, d.DrawArgsVertices);
            Assert.AreEqual(Native.SizeOf<pbf_d3d11_buffer_desc>(), d.ToNative().struct_size);
            Assert.AreEqual(pbf_copy_mode.PBF_COPY_ON_RENDER_EVENT, Native.pbf_d3d11_buffer_desc_default().mode);

            // Every property reaches its field.
            var e = new D3D11BufferDesc(FakeD3D11Buffer, 512, BufferSource.Anisotropy, CopyMode.OnStep)
            {
                OffsetBytes = 48, DrawArgsBuffer = new IntPtr(0x2000), DrawArgsOffsetBytes = 20, DrawArgsVertices = 6,
            };
            pbf_d3d11_buffer_desc raw = e.ToNative();
            Assert.AreEqual(FakeD3D11Buffer, raw.buffer);
            Assert.AreEqual(512u, raw.capacity);
            Assert.AreEqual(pbf_buffer.PBF_BUFFER_ANISOTROPY, raw.source);
            Assert.AreEqual(pbf_copy_mode.PBF_COPY_ON_STEP, raw.mode);
            Assert.AreEqual(48ul, raw.offset_bytes);
            Assert.AreEqual(new IntPtr(0x2000), raw.draw_args_buffer);
            Assert.AreEqual(20ul, raw.draw_args_offset_bytes);
            Assert.AreEqual(6u, raw.draw_args_vertices);

            var wrong = new pbf_d3d11_buffer_desc();
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_d3d11_buffer_desc_init(ref wrong, Native.SizeOf<pbf_d3d11_buffer_desc>() - 4), "pbf_d3d11_buffer_desc_init");
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_d3d11_buffer_desc_init(IntPtr.Zero, Native.SizeOf<pbf_d3d11_buffer_desc>()));
        }

        [Test]
        public void D3D11RegistrationOnACpuWorldIsRefused()
        {
            Result code = OnCpuWorld(InteropSupport.D3D11);
            foreach (CopyMode mode in new[] { CopyMode.OnStep, CopyMode.OnRenderEvent })
                foreach (BufferSource source in new[] { BufferSource.Positions, BufferSource.Velocities, BufferSource.Ids })
                {
                    var desc = new D3D11BufferDesc(FakeD3D11Buffer, capacity: 2048, source: source, mode: mode);
                    Scene.ExpectError(code, () => _world.RegisterD3D11Buffer(desc), "pbf_world_register_d3d11_buffer",
                                      OnCpuWorldText(InteropSupport.D3D11));
                }

            // The handle stays zeroed on failure.
            pbf_d3d11_buffer_desc raw = new D3D11BufferDesc(FakeD3D11Buffer, 16).ToNative();
            var id = new pbf_d3d11_buffer_id { index = 5, generation = 5 };
            ExpectRaw((pbf_result)code, Native.pbf_world_register_d3d11_buffer(_world.Id, ref raw, out id));
            Assert.AreEqual(0u, id.index);
            Assert.AreEqual(0u, id.generation);

            // Unregistering a handle no registration made: no D3D11 in the build, or no such buffer.
            var forged = new pbf_d3d11_buffer_id { index = 1, generation = 1 };
            ExpectRaw(ForgedHandle(InteropSupport.D3D11), Native.pbf_world_unregister_d3d11_buffer(_world.Id, forged), "pbf_world_unregister_d3d11_buffer");
            // Nothing was registered, so nothing waits for the render thread.
            Assert.AreEqual(0, _world.GetInteropInfo().PendingRenderWork);
            _world.Step(Scene.Dt);
        }

        [Test]
        public void D3D11RegistrationChecksItsArgumentsFirst()
        {
            Scene.ExpectError(Result.InvalidArgument, () => _world.RegisterD3D11Buffer(new D3D11BufferDesc { Capacity = 16 }),
                "pbf_world_register_d3d11_buffer", "buffer must be an ID3D11Buffer* (non-NULL)");
            Scene.ExpectError(Result.InvalidArgument, () => _world.RegisterD3D11Buffer(new D3D11BufferDesc(FakeD3D11Buffer, 0)),
                "capacity must be > 0");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.RegisterD3D11Buffer(new D3D11BufferDesc(FakeD3D11Buffer, 16) { OffsetBytes = 8 }), "offset_bytes must be a multiple of 16");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.RegisterD3D11Buffer(new D3D11BufferDesc(FakeD3D11Buffer, 16) { DrawArgsOffsetBytes = 2 }), "draw_args_offset_bytes must be a multiple of 4");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.RegisterD3D11Buffer(new D3D11BufferDesc(FakeD3D11Buffer, 16) { Source = (BufferSource)9 }), "source must be");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.RegisterD3D11Buffer(new D3D11BufferDesc(FakeD3D11Buffer, 16) { Source = BufferSource.Materials }),
                "PBF_BUFFER_MATERIALS (1 byte per particle) is not copied into graphics buffers");
            // D3D11 has no manual copy: the immediate context belongs to the render thread.
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.RegisterD3D11Buffer(new D3D11BufferDesc(FakeD3D11Buffer, 16, mode: CopyMode.Manual)),
                "mode must be PBF_COPY_ON_RENDER_EVENT or PBF_COPY_ON_STEP");
            // Ids are 4 bytes: an offset of 4 passes the argument checks.
            Scene.ExpectError(OnCpuWorld(InteropSupport.D3D11),
                () => _world.RegisterD3D11Buffer(new D3D11BufferDesc(FakeD3D11Buffer, 16, BufferSource.Ids) { OffsetBytes = 4 }));
            Assert.Throws<ArgumentNullException>(() => _world.RegisterD3D11Buffer(null));
            Assert.Throws<ArgumentNullException>(() => _world.UnregisterD3D11Buffer(null));

            pbf_d3d11_buffer_desc raw = new D3D11BufferDesc(FakeD3D11Buffer, 16).ToNative();
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_register_d3d11_buffer(_world.Id, ref raw, IntPtr.Zero), "out_buffer is NULL");
            raw.reserved0 = 1;
            pbf_d3d11_buffer_id id;
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_register_d3d11_buffer(_world.Id, ref raw, out id), "reserved0 must be 0");
            raw = new D3D11BufferDesc(FakeD3D11Buffer, 16).ToNative();
            raw.struct_size -= 8;
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_register_d3d11_buffer(_world.Id, ref raw, out id));
        }

        // ---- external memory and semaphores (raw layer) ----------------------------------------
        [Test]
        public void ExternalDescsHaveTheLibraryDefaults()
        {
            pbf_external_buffer_desc e = Native.pbf_external_buffer_desc_default();
            Assert.AreEqual(Native.SizeOf<pbf_external_buffer_desc>(), e.struct_size);
            Assert.AreEqual(-1, e.fd);
            Assert.AreEqual(pbf_copy_mode.PBF_COPY_MANUAL, e.mode);
            Assert.AreEqual(pbf_buffer.PBF_BUFFER_POSITIONS, e.source);
            Assert.AreEqual(IntPtr.Zero, e.win32_handle);
            pbf_semaphore_desc s = Native.pbf_semaphore_desc_default();
            Assert.AreEqual(-1, s.fd);
            Assert.AreEqual(Native.SizeOf<pbf_semaphore_desc>(), s.struct_size);
            pbf_external_sync y = Native.pbf_external_sync_default();
            Assert.AreEqual(Native.SizeOf<pbf_external_sync>(), y.struct_size);
            Assert.AreEqual(0u, y.wait_semaphore.generation);
            Assert.AreEqual(0u, y.signal_semaphore.generation);

            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_external_buffer_desc_init(ref e, 8), "pbf_external_buffer_desc_init");
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_semaphore_desc_init(ref s, 0), "pbf_semaphore_desc_init");
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_external_sync_init(ref y, Native.SizeOf<pbf_external_sync>() + 8), "pbf_external_sync_init");
        }

        [Test]
        public void ExternalMemoryAndSemaphoresAreRefusedOnACpuWorld()
        {
            pbf_external_buffer_desc e = Native.pbf_external_buffer_desc_default();
            e.size_bytes = 4096;
            e.capacity = 16;
            pbf_external_buffer_id eid;
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_import_external_buffer(_world.Id, ref e, out eid), "type must be");
            e.type = pbf_external_memory_type.PBF_EXTERNAL_MEMORY_OPAQUE_FD;
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_import_external_buffer(_world.Id, ref e, out eid), "fd must be");
            // fd 0 passes the argument checks; refused, it stays the caller's (nothing is closed).
            e.fd = 0;
            ExpectRaw((pbf_result)OnCpuWorld(InteropSupport.ExternalFd), Native.pbf_world_import_external_buffer(_world.Id, ref e, out eid),
                "pbf_world_import_external_buffer");
            Assert.AreEqual(0u, eid.generation);
            // Windows handle types do not exist in a Linux build.
            e.type = pbf_external_memory_type.PBF_EXTERNAL_MEMORY_D3D12_RESOURCE;
            e.win32_handle = new IntPtr(0x10);
            if (Environment.OSVersion.Platform == PlatformID.Unix)
                ExpectRaw(pbf_result.PBF_ERROR_BACKEND_UNAVAILABLE, Native.pbf_world_import_external_buffer(_world.Id, ref e, out eid));

            pbf_semaphore_desc s = Native.pbf_semaphore_desc_default();
            s.type = pbf_semaphore_type.PBF_SEMAPHORE_VULKAN_TIMELINE_FD;
            pbf_semaphore_id sid;
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_import_semaphore(_world.Id, ref s, out sid), "fd must be");
            s.fd = 0;
            ExpectRaw((pbf_result)OnCpuWorld(InteropSupport.ExternalFd), Native.pbf_world_import_semaphore(_world.Id, ref s, out sid),
                "pbf_world_import_semaphore");

            var forged = new pbf_external_buffer_id { index = 1, generation = 1 };
            pbf_result noHandle = HasCuda ? pbf_result.PBF_ERROR_INVALID_HANDLE : pbf_result.PBF_ERROR_BACKEND_UNAVAILABLE;
            ExpectRaw(noHandle, Native.pbf_world_release_external_buffer(_world.Id, forged));
            ExpectRaw(noHandle, Native.pbf_world_copy_to_external_buffer(_world.Id, forged, IntPtr.Zero));
            pbf_external_sync sync = Native.pbf_external_sync_default();
            ExpectRaw(noHandle, Native.pbf_world_set_external_sync(_world.Id, forged, ref sync));
            ExpectRaw(noHandle, Native.pbf_world_release_semaphore(_world.Id, new pbf_semaphore_id { index = 1, generation = 1 }));
        }

        // ---- render event ------------------------------------------------------------------------
        [Test]
        public void RenderEventFunctionIsNonNullAndStable()
        {
            IntPtr f = Library.GetRenderEventFunc();
            Assert.AreNotEqual(IntPtr.Zero, f);
            Assert.AreEqual(f, Library.GetRenderEventFunc());
            Assert.AreEqual(f, Native.pbf_get_render_event_func());
            Assert.AreEqual(0, Library.RenderEventAllWorlds);
        }

        [Test]
        public void RenderEventIdsSelectOneWorld()
        {
            int id = _world.GetRenderEventId();
            Assert.Greater(id, 0);
            Assert.AreEqual((int)_world.Id.index + 1, id);
            Assert.AreEqual(id, _world.GetRenderEventId());
            using (World other = Scene.CpuWorld(64))
                Assert.AreNotEqual(id, other.GetRenderEventId());

            int raw;
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_get_render_event_id(StaleId(), out raw), "pbf_world_get_render_event_id");
            Assert.AreEqual(0, raw);
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_get_render_event_id(_world.Id, IntPtr.Zero), "out_event_id is NULL");
        }

        [Test]
        public void IssuingTheRenderEventIsHarmless()
        {
            var errors = new List<string>();
            Library.SetLogHandler((level, message) => { if (level >= LogLevel.Warning) lock (errors) errors.Add(message); });
            Vector4[] before = Scene.Positions(_world);
            long steps = _world.Stats.StepIndex;

            Library.IssueRenderEvent(_world.GetRenderEventId());
            Library.IssueRenderEvent(Library.RenderEventAllWorlds);
            Library.IssueRenderEvent(int.MaxValue);  // no such world
            Library.IssueRenderEvent(-5);
            // Through the raw function pointer, as an engine calls it.
            var fn = (pbf_render_event_fn)Marshal.GetDelegateForFunctionPointer(Native.pbf_get_render_event_func(), typeof(pbf_render_event_fn));
            fn(_world.GetRenderEventId());

            CollectionAssert.AreEqual(before, Scene.Positions(_world), "the render event touched no particle");
            Assert.AreEqual(steps, _world.Stats.StepIndex);
            InteropInfo info = _world.GetInteropInfo();
            Assert.AreEqual(0, info.RenderEvents, "a CPU world has no render work");
            Assert.AreEqual(Result.Ok, info.LastRenderEventResult);
            Assert.AreEqual("", info.LastRenderEventMessage);
            Library.SetLogHandler(null);
            CollectionAssert.IsEmpty(errors);

            // The world works on.
            _world.Step(Scene.Dt);
            Assert.AreEqual(before.Length, _world.ParticleCount);
        }

        // ---- interop info --------------------------------------------------------------------------
        [Test]
        public void InteropInfoOfACpuWorld()
        {
            InteropInfo info = _world.GetInteropInfo();
            Assert.AreEqual(-1, info.CudaDevice);
            Assert.AreEqual(0, info.GlBuffers);
            Assert.AreEqual(0, info.ExternalBuffers);
            Assert.AreEqual(0, info.Semaphores);
            Assert.AreEqual(0, info.Copies);
            Assert.AreEqual(0, info.RenderEvents);
            Assert.AreEqual(0, info.PendingRenderWork);
            Assert.AreEqual(Result.Ok, info.LastRenderEventResult);
            Assert.AreEqual("", info.LastRenderEventMessage);
            CollectionAssert.AreEqual(new byte[16], info.DeviceUuid);
            CollectionAssert.AreEqual(new byte[8], info.DeviceLuid);
            Assert.AreEqual(0u, info.DeviceNodeMask);
            Assert.AreEqual(Native.SizeOf<pbf_interop_info>(), info.ToNative().struct_size);

            var raw = new pbf_interop_info { struct_size = Native.SizeOf<pbf_interop_info>() - 4 };
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_get_interop_info(_world.Id, ref raw), "pbf_world_get_interop_info");
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_get_interop_info(_world.Id, IntPtr.Zero));
            raw.struct_size = Native.SizeOf<pbf_interop_info>();
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_get_interop_info(StaleId(), ref raw));

            World other = Scene.CpuWorld(64);
            other.Dispose();
            Assert.Throws<ObjectDisposedException>(() => other.GetInteropInfo());
            Assert.Throws<ObjectDisposedException>(() => other.GetRenderEventId());
            Assert.Throws<ObjectDisposedException>(() => other.GetCudaStream());
        }

        // ---- transfer counter ------------------------------------------------------------------------
        [Test]
        public void TransferCounterCountsNoCopiesOnTheCpuBackend()
        {
            // The header: the counter counts host<->device copies (copy-out, stats, particle
            // counts). A CPU world has no device: its copy-out, stats and steps add none.
            TransferCount before = Library.GetTransferCount();
            Assert.GreaterOrEqual(before.Transfers, 0);
            Assert.GreaterOrEqual(before.Bytes, 0);
            if (!HasCuda)
            {
                Assert.AreEqual(0, before.Transfers, "a library without CUDA never copies between host and device");
                Assert.AreEqual(0, before.Bytes);
            }

            Scene.Positions(_world);
            Scene.Velocities(_world);
            Scene.Ids(_world);
            Assert.Greater(_world.Stats.ParticleCount, 0);
            TransferCount afterCopy = Library.GetTransferCount();
            Assert.AreEqual(before.Transfers, afterCopy.Transfers, "copy-out on the CPU backend");
            Assert.AreEqual(before.Bytes, afterCopy.Bytes);

            Scene.Steps(_world, 3);
            using (_world.MapDeviceBuffers()) { }
            using (_world.MapPositions()) { }
            Library.IssueRenderEvent(Library.RenderEventAllWorlds);
            TransferCount afterStep = Library.GetTransferCount();
            Assert.AreEqual(before.Transfers, afterStep.Transfers, "steps, mapping and render events on the CPU backend");
            Assert.AreEqual(before.Bytes, afterStep.Bytes);

            // Either pointer may be NULL.
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_debug_get_transfer_count(IntPtr.Zero, IntPtr.Zero));
            ulong t, b;
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_debug_get_transfer_count(out t, out b));
            Assert.AreEqual((ulong)before.Transfers, t);
        }
    }
}
