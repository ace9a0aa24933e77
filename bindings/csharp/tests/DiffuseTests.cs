using System;
using System.Numerics;
using System.Runtime.InteropServices;
using NUnit.Framework;

namespace Pbf.Tests
{
    /// <summary>Diffuse particles (DiffuseParams, AddDiffuse, CopyDiffusePositions/-Velocities, the
    /// diffuse pointers of DeviceBuffers, the diffuse stats) on the CPU backend.</summary>
    [TestFixture]
    public class DiffuseTests
    {
        // The C tests' dam: a 0.2 x 0.4 x 0.1 m column (512 particles) at one end of a 0.8 x 0.5 x 0.1 m tank.
        static World Dam(int capacity)
        {
            var d = new WorldDesc { Backend = Backend.Cpu, MaxParticles = 4096, ParticleRadius = 0.0125f,
                                    DomainMin = Vector3.Zero, DomainMax = new Vector3(0.8f, 0.5f, 0.1f) };
            d.Solver.Substeps = 2;
            d.Diffuse.MaxDiffuse = capacity;
            World w = World.Create(d);
            Assert.AreEqual(512, w.EmitBlock(Vector3.Zero, new Vector3(0.2f, 0.4f, 0.1f), Vector3.Zero));
            return w;
        }

        [Test]
        public void DefaultsAreTheLibrarys()
        {
            DiffuseParams p = DiffuseParams.Default;
            Assert.AreEqual(0, p.MaxDiffuse);
            Assert.AreEqual(2.0f, p.Lifetime);
            Assert.AreEqual(6, p.SprayMaxNeighbors);
            Assert.AreEqual(20, p.BubbleMinNeighbors);
            Assert.AreEqual(0.5f, p.Buoyancy);
            Assert.AreEqual(0, new WorldDesc().Diffuse.MaxDiffuse);
        }

        [Test]
        public void DamBreakMakesDiffuseParticlesWithinCapacityAndLifetime()
        {
            using (World w = Dam(20000))
            {
                Scene.Steps(w, 60);
                StepStats s = w.Stats;
                Assert.Greater(s.DiffuseCount, 50, "the breaking front foams");
                Assert.LessOrEqual(s.DiffuseCount, s.DiffuseGeneratedTotal);
                var pos = new float[4 * s.DiffuseCount];
                var vel = new float[4 * s.DiffuseCount];
                Assert.AreEqual(s.DiffuseCount, w.CopyDiffusePositions(pos));
                Assert.AreEqual(s.DiffuseCount, w.CopyDiffuseVelocities(vel));
                for (int i = 0; i < s.DiffuseCount; ++i)
                {
                    float kind = pos[4 * i + 3];
                    Assert.IsTrue(kind == (float)DiffuseKind.Spray || kind == (float)DiffuseKind.Foam || kind == (float)DiffuseKind.Bubble);
                    Assert.Greater(vel[4 * i + 3], 0f);
                    Assert.LessOrEqual(vel[4 * i + 3], 2.0f);
                }
            }
            using (World w = Dam(40))
            {
                Scene.Steps(w, 60);
                Assert.AreEqual(40, w.Stats.DiffuseCount);
                Assert.Greater(w.Stats.DiffuseDroppedTotal, 0);
            }
        }

        [Test]
        public void AddedKindsMoveAndThePointersHoldTheCopy()
        {
            WorldDesc d = Scene.CpuDesc();
            d.Diffuse.MaxDiffuse = 4;
            using (World w = World.Create(d))
            {
                // Spray in the air falls; nothing else is there.
                float[] pos = { 0f, 1.0f, 0f, (float)DiffuseKind.Spray };
                float[] vel = { 0f, 0f, 0f, 3f };
                Assert.AreEqual(1, w.AddDiffuse(pos, vel));
                Scene.Steps(w, 10);
                var p = new float[4];
                var v = new float[4];
                Assert.AreEqual(1, w.CopyDiffusePositions(p));
                Assert.AreEqual(1, w.CopyDiffuseVelocities(v));
                Assert.Less(p[1], 1.0f - 0.12f, "ballistic: ½ g t² after 1/6 s");
                Assert.Less(v[1], -1.4f);
                Assert.AreEqual(3f - 10 * Scene.Dt, v[3], 1e-4f, "spray ages");
                using (DeviceBuffers m = w.MapDeviceBuffers())
                {
                    Assert.AreEqual(1u, m.DiffuseCount);
                    Assert.AreEqual(4, m.DiffuseCapacity);
                    var mapped = new float[4];
                    Marshal.Copy(m.DiffusePositions, mapped, 0, 4);
                    CollectionAssert.AreEqual(p, mapped, "host pointer equals copy-out");
                }
                Assert.AreEqual(3, w.AddDiffuse(new float[16], new float[] { 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1 }));
                Scene.ExpectError(Result.Capacity, () => w.AddDiffuse(pos, vel), "max_diffuse");
            }
        }

        [Test]
        public void OffCostsNothingAndBadInputIsRefused()
        {
            WorldDesc d = Scene.CpuDesc();
            using (World off = World.Create(d))
            {
                d.Diffuse.MaxDiffuse = 1000;
                using (World on = World.Create(d))
                {
                    Scene.BlockSteps(2, off, on);
                    WorldInfo a = off.Info, b = on.Info;
                    Assert.AreEqual(0, a.DiffuseBytes);
                    Assert.AreEqual(0, a.DiffuseUpdates);
                    Assert.AreEqual(0, a.DiffuseCapacity);
                    Assert.AreEqual(1000, b.DiffuseCapacity);
                    Assert.AreEqual(a.DeviceBytes + b.DiffuseBytes, b.DeviceBytes);
                    Assert.AreEqual(2, b.DiffuseUpdates);
                    Scene.ExpectError(Result.InvalidState, () => off.CopyDiffusePositions(new float[4]), "max_diffuse");
                    Scene.ExpectError(Result.InvalidState, () => off.AddDiffuse(new float[4], new float[] { 0, 0, 0, 1 }), "max_diffuse");
                    using (DeviceBuffers m = off.MapDeviceBuffers()) Assert.AreEqual(IntPtr.Zero, m.DiffusePositions);

                    DiffuseParams p = on.GetDiffuseParams();
                    Assert.AreEqual(1000, p.MaxDiffuse);
                    p.Lifetime = float.NaN;
                    Scene.ExpectError(Result.InvalidArgument, () => on.SetDiffuseParams(p), "lifetime");
                    p.Lifetime = 3f;
                    p.MaxDiffuse = 10;
                    Scene.ExpectError(Result.InvalidState, () => on.SetDiffuseParams(p), "fixed at world creation");
                    p.MaxDiffuse = 1000;
                    on.SetDiffuseParams(p);
                    Assert.AreEqual(3f, on.GetDiffuseParams().Lifetime);
                    Scene.ExpectError(Result.InvalidArgument, () => on.AddDiffuse(new float[] { 0, 0.5f, 0, 7 }, new float[] { 0, 0, 0, 1 }), "kinds");
                    Assert.Throws<ArgumentException>(() => on.AddDiffuse(new float[4], new float[8]));
                }
            }
            var bad = new WorldDesc { Backend = Backend.Cpu };
            bad.Diffuse.MaxDiffuse = -1;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(bad).Dispose(), "max_diffuse");
        }
    }
}
