using System;
using System.Linq;
using System.Numerics;
using NUnit.Framework;

namespace Pbf.Tests
{
    [TestFixture]
    public class EmitterColliderTests
    {
        [Test]
        public void NozzleAddsParticlesAtItsRateWhereItPoints()
        {
            using (var world = Scene.CpuWorld())
            {
                // 300 particles/s through a disc of radius 0.1 m at 2 m/s: under the flux of
                // fluid at rest density (speed · area / spacing³ ≈ 500/s), so the jet stays a jet.
                var nozzlePos = new Vector3(0, 1.5f, 0);
                Emitter nozzle = world.CreateNozzle(nozzlePos, new Vector3(0, -2, 0), 2.0f, 0.1f, 300f);
                Assert.AreEqual(EmitterType.Nozzle, nozzle.Type);
                Scene.Steps(world, 15);  // 1/4 s, before the jet reaches the floor
                int count = world.ParticleCount;
                Assert.That(count, Is.InRange(74, 75), "300 particles/s for 15 steps of 1/60 s");
                Assert.AreEqual(count, world.Stats.EmittedTotal);
                Vector4[] p = Scene.Positions(world);
                Vector4[] v = Scene.Velocities(world);
                Vector3 mean = Scene.Mean(p);
                Assert.AreEqual(0f, mean.X, 0.02f, "centred on the nozzle axis");
                Assert.AreEqual(0f, mean.Z, 0.02f);
                Assert.Less(mean.Y, nozzlePos.Y, "moving down from the nozzle");
                Assert.Greater(mean.Y, 0.5f);
                Assert.IsTrue(p.All(q => new Vector2(q.X, q.Z).Length() < 0.1f + 0.05f), "a jet as wide as the nozzle");
                Assert.IsTrue(p.All(q => q.Y < nozzlePos.Y + 0.01f && q.Y > 0.5f), "between the nozzle and the floor");
                Assert.IsTrue(v.All(q => q.Y < -1.9f), "all moving down at least at the nozzle speed");

                nozzle.SetEnabled(false);
                Scene.Steps(world, 5);
                Assert.AreEqual(count, world.ParticleCount, "a disabled nozzle emits nothing");

                // Move it and re-enable: new particles come from the new place.
                nozzle.SetNozzle(new Vector3(0.5f, 1.5f, 0.5f), new Vector3(0, -1, 0));
                nozzle.SetEnabled(true);
                Scene.Steps(world, 8);
                Assert.That(world.ParticleCount - count, Is.InRange(39, 41), "300/s for 8 steps");
                Vector4[] p2 = Scene.Positions(world);
                uint[] ids = Scene.Ids(world);
                var fresh = Enumerable.Range(0, ids.Length).Where(k => ids[k] >= count).Select(k => p2[k]).ToArray();
                Assert.AreEqual(world.ParticleCount - count, fresh.Length, "new ids continue from the old count");
                Vector3 freshMean = Scene.Mean(fresh);
                Assert.AreEqual(0.5f, freshMean.X, 0.02f);
                Assert.AreEqual(0.5f, freshMean.Z, 0.02f);

                nozzle.Destroy();
                Scene.Steps(world, 3);
                Assert.AreEqual(count + fresh.Length, world.ParticleCount, "a destroyed nozzle emits nothing");
            }
        }

        [Test]
        public void DynamicBoxUnderWaterFeelsItsWeightAndTheTableAgrees()
        {
            using (var world = Scene.CpuWorld())
            {
                // A 0.3 m cube of water dropped onto a dynamic box: resting on it, the water pushes
                // it down by about its weight (the walls take what spills over the sides).
                var d = ColliderDesc.Box(new Vector3(0, 0.1f, 0), Quaternion.Identity, new Vector3(0.2f, 0.1f, 0.2f));
                d.Dynamic = true;
                d.CenterOfMass = new Vector3(0, -0.1f, 0);
                Assert.IsTrue(d.Dynamic);
                Collider box = world.CreateCollider(d);
                Assert.AreEqual(Vector3.Zero, box.GetForce().Force, "nothing felt before the first step");
                world.EmitBlock(new Vector3(-0.15f, 0.25f, -0.15f), new Vector3(0.15f, 0.55f, 0.15f));
                Scene.Steps(world, 60);
                ColliderForce f = box.GetForce();
                Assert.Less(f.Force.Y, 0f, "the water pushes it down");
                ColliderForceTable table = world.MapColliderForces();
                Assert.AreEqual(MemoryKind.Host, table.Memory);
                Assert.AreEqual(256, table.Count, "one row per collider the world can hold");
                Assert.AreEqual(24, table.StrideBytes);
                Assert.AreEqual(f.Force, table.Read((int)box.Id.index).Force);
                Assert.AreEqual(f.Torque, table.Read((int)box.Id.index).Torque);
            }
        }

        [Test]
        public void DrainRemovesTheParticlesInsideIt()
        {
            using (var world = Scene.CpuWorld())
            {
                int emitted = world.EmitBlock(new Vector3(-0.21f, 0.0f, -0.21f), new Vector3(0.21f, 0.21f, 0.21f));
                Assert.AreEqual(256, emitted);
                // Lattice x = -0.185 .. 0.165: four columns on each side of x = 0.
                Emitter drain = world.CreateDrain(new Vector3(-1, 0, -1), new Vector3(0, 2, 1));
                Assert.AreEqual(EmitterType.Drain, drain.Type);
                world.Step(Scene.Dt);
                Assert.AreEqual(128, world.ParticleCount);
                Assert.AreEqual(128, world.Stats.DrainedTotal);
                Assert.IsTrue(Scene.Positions(world).All(q => q.X > 0f), "the x < 0 half is gone");
                Assert.IsTrue(Scene.Ids(world).All(id => id < 256));

                drain.SetEnabled(false);
                drain.SetDrainBox(new Vector3(-1, 0, -1), new Vector3(1, 2, 1));
                world.Step(Scene.Dt);
                Assert.AreEqual(128, world.ParticleCount, "a disabled drain removes nothing");
                drain.SetEnabled(true);
                world.Step(Scene.Dt);
                Assert.AreEqual(0, world.ParticleCount, "the moved drain covers everything");
                Assert.AreEqual(256, world.Stats.DrainedTotal);
                Assert.AreEqual(256, world.Stats.EmittedTotal);
            }
        }

        [Test]
        public void SphereColliderDisplacesFluid()
        {
            var centre = new Vector3(0, 0.21f, 0);
            const float radius = 0.12f;
            Func<World, float> closest = w => Scene.Positions(w).Min(q => (Scene.Xyz(q) - centre).Length());

            // Control: without the sphere the block's particles fill the sphere's volume.
            using (var control = Scene.CpuWorld())
            {
                control.EmitBlock(new Vector3(-0.21f, 0.0f, -0.21f), new Vector3(0.21f, 0.42f, 0.21f));
                Scene.Steps(control, 3);
                Assert.Less(closest(control), radius / 2);
            }

            using (var world = Scene.CpuWorld())
            {
                Collider sphere = world.CreateCollider(ColliderDesc.Sphere(centre, radius));
                Assert.AreEqual(ColliderShape.Sphere, sphere.Shape);
                Assert.AreEqual(ColliderMotion.Static, sphere.Motion);
                world.EmitBlock(new Vector3(-0.21f, 0.0f, -0.21f), new Vector3(0.21f, 0.42f, 0.21f));
                Assert.Less(closest(world), radius / 2, "emitted inside the sphere");
                Scene.Steps(world, 3);
                Assert.GreaterOrEqual(closest(world), radius - 1e-3f, "pushed out of the sphere");

                // Gone: fluid put back into its volume stays there. (This test used to wait 10 steps
                // for the block to flow back in; since boundary density (2.0) the shell squeezed
                // around the sphere springs outward when it goes, and the block spreads before it
                // refills: a timing of the splash, not of the collider, so the check is direct now.)
                sphere.Destroy();
                world.EmitBlock(centre - new Vector3(0.03f, 0.03f, 0.03f), centre + new Vector3(0.03f, 0.03f, 0.03f));
                Scene.Steps(world, 1);
                Assert.Less(closest(world), radius - 0.03f);
            }
        }

        [Test]
        public void KinematicSpherePushesFluidAlongItsPath()
        {
            using (var world = Scene.CpuWorld())
            {
                world.EmitBlock(new Vector3(-0.21f, 0.0f, -0.21f), new Vector3(0.21f, 0.42f, 0.21f));
                var start = new Vector3(0.6f, 0.21f, 0);
                Collider ball = world.CreateCollider(ColliderDesc.Sphere(start, 0.1f, ColliderMotion.Kinematic));
                Vector3 target = start;
                for (int i = 0; i < 6; ++i)
                {
                    target -= new Vector3(0.1f, 0, 0);
                    ball.SetTargetPose(target, Quaternion.Identity);
                    world.Step(Scene.Dt);
                }
                float closest = Scene.Positions(world).Min(q => (Scene.Xyz(q) - target).Length());
                Assert.GreaterOrEqual(closest, 0.1f - 1e-3f, "no particle inside the ball at its new place");
                Assert.Less(Scene.Mean(Scene.Velocities(world)).X, -0.01f, "the ball pushed the fluid towards -x");
            }
        }

        [Test]
        public void PlaneColliderHoldsFluidUp()
        {
            using (var world = Scene.CpuWorld())
            {
                Collider floor = world.CreateCollider(ColliderDesc.Plane(new Vector3(0, 0.5f, 0), Vector3.UnitY));
                Assert.AreEqual(ColliderShape.Plane, floor.Shape);
                world.EmitBlock(new Vector3(-0.21f, 0.6f, -0.21f), new Vector3(0.21f, 0.81f, 0.21f));
                Scene.Steps(world, 30);
                float lowest = Scene.Positions(world).Min(q => q.Y);
                Assert.GreaterOrEqual(lowest, 0.5f - 1e-3f, "resting on the plane at y = 0.5, not the floor");
                Assert.Less(lowest, 0.6f, "it fell onto the plane");

                // Boxes and capsules are accepted too.
                world.CreateCollider(ColliderDesc.Box(new Vector3(0.7f, 0.2f, 0.7f), Quaternion.CreateFromAxisAngle(Vector3.UnitY, 0.3f), new Vector3(0.1f, 0.2f, 0.1f)));
                world.CreateCollider(ColliderDesc.Capsule(new Vector3(-0.7f, 0.3f, -0.7f), Quaternion.Identity, 0.05f, 0.2f));
                world.Step(Scene.Dt);
            }
        }

        [Test]
        public void FromUpRotatesTheYAxisOntoTheDirection()
        {
            foreach (var dir in new[] { Vector3.UnitY, -Vector3.UnitY, Vector3.UnitX, new Vector3(1, 2, 3) })
            {
                Vector3 n = Vector3.Normalize(dir);
                Vector3 r = Vector3.Transform(Vector3.UnitY, ColliderDesc.FromUp(dir));
                Assert.Less((r - n).Length(), 1e-5f, dir.ToString());
            }
        }
    }
}
