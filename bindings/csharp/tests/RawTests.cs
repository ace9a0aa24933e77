using System;
using System.Numerics;
using NUnit.Framework;
using Pbf.Interop;

namespace Pbf.Tests
{
    /// <summary>Error paths only the raw layer can reach (NULL pointers, wrong struct_size,
    /// forged or stale handles, version mismatch), and how the friendly layer reports stale handles.</summary>
    [TestFixture]
    public class RawTests
    {
        static void ExpectRaw(pbf_result expected, pbf_result actual, params string[] fragments)
        {
            string message = Native.LastErrorMessage();
            Assert.AreEqual(expected, actual, message);
            StringAssert.StartsWith(Native.ResultString(expected) + ": ", message);
            foreach (var f in fragments) StringAssert.Contains(f, message);
            // Check() turns the same code and message into the exception the friendly layer throws.
            var e = Assert.Throws<PbfException>(() => PbfException.Check(actual));
            Assert.AreEqual((Result)expected, e.Code);
            Assert.AreEqual(message, e.Message);
        }

        static pbf_world_desc CpuDesc()
        {
            pbf_world_desc d = Native.pbf_world_desc_default();
            d.backend = pbf_backend.PBF_BACKEND_CPU;
            d.max_particles = 1024;
            return d;
        }

        [Test]
        public void DefaultsFromTheInitFunctionsMatchTheHeaderDocs()
        {
            pbf_world_desc d = Native.pbf_world_desc_default();
            Assert.AreEqual(Native.SizeOf<pbf_world_desc>(), d.struct_size);
            Assert.AreEqual(Native.PBF_VERSION, d.header_version);
            Assert.AreEqual(pbf_backend.PBF_BACKEND_AUTO, d.backend);
            Assert.AreEqual(65536u, d.max_particles);
            Assert.AreEqual(0.025f, d.particle_radius);
            Assert.AreEqual(1000f, d.rest_density);
            Assert.AreEqual(-9.81f, d.gravity.y);
            Assert.AreEqual(-1f, d.domain_min.x);
            Assert.AreEqual(2f, d.domain_max.y);
            Assert.AreEqual(Native.SizeOf<pbf_solver_params>(), d.solver.struct_size);
            Assert.AreEqual(4u, d.solver.iterations);

            pbf_emitter_desc e = Native.pbf_emitter_desc_default();
            Assert.AreEqual(1u, e.enabled);
            Assert.AreEqual(-1f, e.direction.y);
            pbf_collider_desc c = Native.pbf_collider_desc_default();
            Assert.AreEqual(pbf_collider_motion.PBF_MOTION_STATIC, c.motion);
            Assert.AreEqual(1f, c.rotation.w);
            Assert.AreEqual(Native.SizeOf<pbf_block_desc>(), Native.pbf_block_desc_default().struct_size);
        }

        [Test]
        public void WrongStructSizeIsRefused()
        {
            var d = new pbf_world_desc();
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_desc_init(ref d, Native.SizeOf<pbf_world_desc>() - 4, Native.PBF_VERSION),
                "pbf_world_desc_init", "pbf_world_desc.struct_size is " + (Native.SizeOf<pbf_world_desc>() - 4));

            d = CpuDesc();
            d.struct_size += 8;
            pbf_world_id id;
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_create(ref d, out id), "pbf_world_create",
                "the library's pbf_world_desc is " + Native.SizeOf<pbf_world_desc>() + " bytes");
            Assert.AreEqual(0u, id.generation, "no world on failure");

            d = CpuDesc();
            d.solver.struct_size = 12;
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_create(ref d, out id), "pbf_solver_params.struct_size is 12");

            var p = new pbf_solver_params();
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_solver_params_init(ref p, 7), "pbf_solver_params_init");
            var b = new pbf_block_desc();
            ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_block_desc_init(ref b, 0), "pbf_block_desc_init");

            using (var world = Scene.CpuWorld())
            {
                var info = new pbf_world_info { struct_size = 40 };
                ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_get_info(world.Id, ref info), "pbf_world_get_info");
                var stats = new pbf_step_stats();  // struct_size 0
                ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_get_stats(world.Id, ref stats), "pbf_world_get_stats");
                var map = new pbf_mapped_buffer { struct_size = 16 };
                ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_map_positions(world.Id, ref map), "pbf_world_map_positions");
                pbf_emitter_desc e = Native.pbf_emitter_desc_default();
                e.type = pbf_emitter_type.PBF_EMITTER_DRAIN;
                e.box_min = new Float3(-1, 0, -1);
                e.box_max = new Float3(1, 1, 1);
                e.struct_size = 4;
                pbf_emitter_id eid;
                ExpectRaw(pbf_result.PBF_ERROR_STRUCT_SIZE, Native.pbf_world_create_emitter(world.Id, ref e, out eid), "pbf_world_create_emitter");
            }
        }

        [Test]
        public void NullPointersAreInvalidArguments()
        {
            pbf_world_id id;
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_create(IntPtr.Zero, out id), "pbf_world_create", "pointer is NULL");
            pbf_world_desc d = CpuDesc();
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_create(ref d, IntPtr.Zero), "out_world is NULL");
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_desc_init(IntPtr.Zero, Native.SizeOf<pbf_world_desc>(), Native.PBF_VERSION), "pointer is NULL");
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_solver_params_init(IntPtr.Zero, Native.SizeOf<pbf_solver_params>()), "pointer is NULL");

            using (var world = Scene.CpuWorld())
            {
                Assert.AreEqual(4 * 2 * 4, world.EmitBlock(new Vector3(-0.11f, 0, -0.11f), new Vector3(0.11f, 0.11f, 0.11f)));
                pbf_world_id w = world.Id;
                uint written;
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_copy_positions(w, IntPtr.Zero, 10, out written),
                    "pbf_world_copy_positions", "output array is NULL");
                Assert.AreEqual(0u, written);
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_copy_ids(w, IntPtr.Zero, 1, out written), "pbf_world_copy_ids");
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_get_particle_count(w, IntPtr.Zero), "out_count is NULL");
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_set_gravity(w, IntPtr.Zero), "pbf_world_set_gravity");
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_emit_block(w, IntPtr.Zero, IntPtr.Zero), "pbf_world_emit_block", "pointer is NULL");
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_get_info(w, IntPtr.Zero), "pointer is NULL");
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_get_stats(w, IntPtr.Zero), "pointer is NULL");
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_set_solver_params(w, IntPtr.Zero), "pointer is NULL");
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_map_positions(w, IntPtr.Zero), "pointer is NULL");
                pbf_collider_id cid;
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_create_collider(w, IntPtr.Zero, out cid), "pointer is NULL");
                Emitter nozzle = world.CreateNozzle(Vector3.UnitY, -Vector3.UnitY, 1, 0.05f, 10);
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_emitter_set_nozzle(w, nozzle.Id, IntPtr.Zero, IntPtr.Zero), "non-NULL");
                Collider k = world.CreateCollider(ColliderDesc.Sphere(Vector3.UnitY, 0.1f, ColliderMotion.Kinematic));
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_collider_set_target_pose(w, k.Id, IntPtr.Zero, IntPtr.Zero), "pbf_collider_set_target_pose");
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_emitter_set_enabled(w, nozzle.Id, 2), "enabled must be 0 or 1");

                // NULL is fine where the header allows it.
                Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_copy_positions(w, IntPtr.Zero, 0, IntPtr.Zero));
                var block = Native.pbf_block_desc_default();
                block.box_min = new Float3(0.5f, 0, 0.5f);
                block.box_max = new Float3(0.61f, 0.11f, 0.61f);
                Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_emit_block(w, ref block, IntPtr.Zero));
                Assert.AreEqual(4 * 2 * 4 + 2 * 2 * 2, world.ParticleCount);
            }
        }

        [Test]
        public void HeaderMajorMismatchIsRefused()
        {
            pbf_world_desc d = CpuDesc();
            d.header_version = Native.PBF_MAKE_VERSION(Native.PBF_VERSION_MAJOR + 1, 0, 0);
            pbf_world_id id;
            ExpectRaw(pbf_result.PBF_ERROR_VERSION_MISMATCH, Native.pbf_world_create(ref d, out id),
                      "header major version " + (Native.PBF_VERSION_MAJOR + 1));
            d.header_version = Native.PBF_MAKE_VERSION(Native.PBF_VERSION_MAJOR, 7, 3);  // minor/patch may differ
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_create(ref d, out id), Native.LastErrorMessage());
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_destroy(id));
        }

        [Test]
        public void ZeroedForgedAndStaleWorldHandlesAreRefused()
        {
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_step(default(pbf_world_id), Scene.Dt), "pbf_world_step", "is not a live world");
            var forged = new pbf_world_id { index = 4000, generation = 1 };
            var stats = new pbf_step_stats { struct_size = Native.SizeOf<pbf_step_stats>() };
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_get_stats(forged, ref stats), "world {4000, 1}");

            pbf_world_desc d = CpuDesc();
            pbf_world_id id;
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_create(ref d, out id));
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_destroy(id));
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_step(id, Scene.Dt), "is not a live world");
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_destroy(id), "pbf_world_destroy", "destroyed twice");
            uint count;
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_get_particle_count(id, out count), "pbf_world_get_particle_count");

            // A new world may reuse the slot; the old handle still names nothing.
            pbf_world_id again;
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_create(ref d, out again));
            ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_step(id, Scene.Dt));
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_step(again, Scene.Dt));
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_destroy(again));
        }

        [Test]
        public void FriendlyWorldDestroyedBehindItsBackReportsTheNativeMessage()
        {
            var world = Scene.CpuWorld();
            Assert.AreEqual(pbf_result.PBF_OK, Native.pbf_world_destroy(world.Id));
            Scene.ExpectError(Result.InvalidHandle, () => world.Step(Scene.Dt), "pbf_world_step", "is not a live world");
            Scene.ExpectError(Result.InvalidHandle, () => { var n = world.ParticleCount; }, "pbf_world_get_particle_count");
            world.Dispose();  // still fine: nothing left to release, no throw
            Assert.Throws<ObjectDisposedException>(() => world.Step(Scene.Dt));
        }

        [Test]
        public void StaleEmitterAndColliderHandlesThrowWithTheNativeMessage()
        {
            using (var world = Scene.CpuWorld())
            {
                Emitter drain = world.CreateDrain(new Vector3(-1, 0, -1), new Vector3(-0.9f, 0.1f, -0.9f));
                drain.Destroy();
                Assert.IsTrue(drain.IsDestroyed);
                drain.Destroy();  // idempotent
                Scene.ExpectError(Result.InvalidHandle, () => drain.SetEnabled(false), "pbf_emitter_set_enabled", "emitter is not live");
                Scene.ExpectError(Result.InvalidHandle, () => drain.SetDrainBox(-Vector3.One, Vector3.One), "pbf_emitter_set_drain_box", "emitter is not live");
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_destroy_emitter(world.Id, drain.Id), "pbf_world_destroy_emitter");

                // A destroyed collider's slot is reused by the next one; the old handle must not reach it.
                Collider a = world.CreateCollider(ColliderDesc.Sphere(new Vector3(0, 1, 0), 0.1f, ColliderMotion.Kinematic));
                a.Destroy();
                Collider b = world.CreateCollider(ColliderDesc.Sphere(new Vector3(0, 1, 0), 0.1f, ColliderMotion.Kinematic));
                Assert.AreEqual(a.Id.index, b.Id.index, "slot reused");
                Assert.AreNotEqual(a.Id.generation, b.Id.generation);
                Scene.ExpectError(Result.InvalidHandle, () => a.SetTargetPose(Vector3.One, Quaternion.Identity), "pbf_collider_set_target_pose", "collider is not live");
                b.SetTargetPose(new Vector3(0, 1.1f, 0), Quaternion.Identity);
                ExpectRaw(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_destroy_collider(world.Id, default(pbf_collider_id)), "collider is not live");

                // Children of a disposed world: ObjectDisposedException, and Destroy is a no-op.
                Emitter nozzle = world.CreateNozzle(Vector3.UnitY, -Vector3.UnitY, 1, 0.05f, 10);
                world.Dispose();
                Assert.IsTrue(nozzle.IsDestroyed);
                Assert.Throws<ObjectDisposedException>(() => nozzle.SetEnabled(true));
                Assert.Throws<ObjectDisposedException>(() => b.SetTargetPose(Vector3.One, Quaternion.Identity));
                nozzle.Destroy();
                b.Dispose();
            }
        }
    }
}
