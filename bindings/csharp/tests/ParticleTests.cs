using System;
using System.Collections.Generic;
using System.Linq;
using System.Numerics;
using NUnit.Framework;

namespace Pbf.Tests
{
    [TestFixture]
    public class ParticleTests
    {
        [Test]
        public void EmitBlockFillsALatticeAtRestSpacing()
        {
            using (var world = Scene.CpuWorld())
            {
                var min = new Vector3(-0.21f, 0.0f, -0.21f);
                var max = new Vector3(0.21f, 0.42f, 0.21f);
                int emitted = world.EmitBlock(min, max, new Vector3(0.5f, 0, 0));
                Assert.AreEqual(8 * 8 * 8, emitted);
                Assert.AreEqual(emitted, world.ParticleCount);

                Vector4[] p = Scene.Positions(world);
                foreach (var q in p)
                {
                    Vector3 x = Scene.Xyz(q);
                    Assert.IsTrue(x.X > min.X && x.Y > min.Y && x.Z > min.Z && x.X < max.X && x.Y < max.Y && x.Z < max.Z, "inside the box: " + x);
                    // On the lattice min + s/2 + k·s.
                    Vector3 k = (x - min - new Vector3(Scene.Spacing / 2)) / Scene.Spacing;
                    Assert.AreEqual(Math.Round(k.X), k.X, 1e-3);
                    Assert.AreEqual(Math.Round(k.Y), k.Y, 1e-3);
                    Assert.AreEqual(Math.Round(k.Z), k.Z, 1e-3);
                }
                CollectionAssert.AreEquivalent(Enumerable.Range(0, emitted).Select(i => (uint)i).ToArray(), Scene.Ids(world),
                    "ids 0..n-1 assigned at emission");
                foreach (var v in Scene.Velocities(world))
                {
                    Assert.AreEqual(0.5f, v.X, 1e-6f, "initial velocity");
                    Assert.AreEqual(0f, v.W, "w of a velocity is 0");
                }
            }
        }

        [Test]
        public void ABlockFallsFreelyUnderGravity()
        {
            using (var world = Scene.CpuWorld())
            {
                world.EmitBlock(new Vector3(-0.11f, 1.0f, -0.11f), new Vector3(0.11f, 1.22f, 0.11f));
                Vector3 start = Scene.Mean(Scene.Positions(world));
                const int n = 10;
                Scene.Steps(world, n);
                Vector3 end = Scene.Mean(Scene.Positions(world));
                Vector3 v = Scene.Mean(Scene.Velocities(world));
                // v = g·t; x advances by v·dt after each velocity update: g·dt²·n(n+1)/2.
                Assert.AreEqual(-9.81f * n * Scene.Dt, v.Y, 0.03f * 9.81f * n * Scene.Dt);
                float drop = 9.81f * Scene.Dt * Scene.Dt * n * (n + 1) / 2;
                Assert.AreEqual(-drop, end.Y - start.Y, 0.05f * drop);
                Assert.AreEqual(0f, v.X, 0.01f);
                Assert.AreEqual(0f, v.Z, 0.01f);
            }
        }

        [Test]
        public void GravityCanBeChanged()
        {
            using (var world = Scene.CpuWorld())
            {
                world.EmitBlock(new Vector3(-0.11f, 1.0f, -0.11f), new Vector3(0.11f, 1.22f, 0.11f));
                world.SetGravity(new Vector3(2.0f, 0, 0));
                Scene.Steps(world, 6);
                Vector3 v = Scene.Mean(Scene.Velocities(world));
                Assert.AreEqual(2.0f * 6 * Scene.Dt, v.X, 0.02f);
                Assert.AreEqual(0f, v.Y, 0.01f);
            }
        }

        [Test]
        public void FluidSettlesInsideTheDomain()
        {
            using (var world = Scene.CpuWorld())
            {
                world.EmitBlock(new Vector3(-0.21f, 0.3f, -0.21f), new Vector3(0.21f, 0.72f, 0.21f));
                Scene.Steps(world, 40);
                StepStats s = world.Stats;
                Assert.IsFalse(float.IsNaN(s.KineticEnergy) || float.IsInfinity(s.KineticEnergy));
                foreach (var q in Scene.Positions(world))
                {
                    Assert.IsFalse(float.IsNaN(q.X) || float.IsNaN(q.Y) || float.IsNaN(q.Z));
                    Assert.GreaterOrEqual(q.Y, 0.025f - 1e-4f, "above the floor by a radius");
                    Assert.LessOrEqual(Math.Abs(q.X), 1f - 0.025f + 1e-4f);
                    Assert.LessOrEqual(Math.Abs(q.Z), 1f - 0.025f + 1e-4f);
                    Assert.Greater(q.W, 0f, "w is the density ratio");
                }
                Assert.Less(Scene.Mean(Scene.Positions(world)).Y, 0.3f, "it fell to the floor");
                Assert.Less(s.DensityErrorMean, 0.1f, "incompressible to within 10% on average");
            }
        }

        [Test]
        public void IdsFollowParticlesAcrossReorderingSteps()
        {
            var desc = Scene.CpuDesc();
            desc.Solver.LdcEnabled = false;  // keeps the free block's internal motion small
            using (var world = World.Create(desc))
            {
                // Emitted high-x first, low-x second: the grid sort puts the second block first.
                world.EmitBlock(new Vector3(0.4f, 1.0f, 0.4f), new Vector3(0.62f, 1.22f, 0.62f));
                world.EmitBlock(new Vector3(-0.6f, 1.0f, -0.6f), new Vector3(-0.38f, 1.22f, -0.38f));
                var before = new Dictionary<uint, Vector3>();
                Vector4[] p0 = Scene.Positions(world);
                uint[] ids0 = Scene.Ids(world);
                for (int k = 0; k < ids0.Length; ++k) before[ids0[k]] = Scene.Xyz(p0[k]);

                for (int step = 0; step < 3; ++step)
                {
                    world.Step(Scene.Dt);
                    Vector4[] p = Scene.Positions(world);
                    uint[] ids = Scene.Ids(world);
                    Assert.AreEqual(before.Count, ids.Length);
                    CollectionAssert.AreEquivalent(before.Keys.ToArray(), ids);
                    if (step == 0)
                        Assert.IsTrue(ids.Where((id, k) => id != (uint)k).Any(), "storage order changed (the solver sorts by cell)");
                    // A free-falling block moves as one: every particle moved by the same amount.
                    Vector3 mean = Vector3.Zero;
                    for (int k = 0; k < ids.Length; ++k) mean += Scene.Xyz(p[k]) - before[ids[k]];
                    mean /= ids.Length;
                    Assert.Less(mean.Y, 0f);
                    for (int k = 0; k < ids.Length; ++k)
                    {
                        Vector3 d = Scene.Xyz(p[k]) - before[ids[k]];
                        Assert.Less((d - mean).Length(), 0.2f * Scene.Spacing, "particle " + ids[k] + " moved with the block");
                        before[ids[k]] = Scene.Xyz(p[k]);
                    }
                }
            }
        }

        [Test]
        public void CopiesFillCallerArraysAndSpans()
        {
            using (var world = Scene.CpuWorld())
            {
                world.EmitBlock(new Vector3(-0.21f, 0.0f, -0.21f), new Vector3(0.21f, 0.21f, 0.21f));
                world.Step(Scene.Dt);
                int n = world.ParticleCount;
                Assert.AreEqual(256, n);

                var flat = new float[n * 4];
                Assert.AreEqual(n, world.CopyPositions(flat));
                var vec = new Vector4[n + 10];
                Assert.AreEqual(n, world.CopyPositions(vec), "min(count, capacity)");
                for (int i = 0; i < n; ++i)
                    Assert.AreEqual(new Vector4(flat[4 * i], flat[4 * i + 1], flat[4 * i + 2], flat[4 * i + 3]), vec[i]);
                Assert.AreEqual(Vector4.Zero, vec[n], "untouched past the count");

                // A slice: only as many particles as fit, into the right place.
                var partial = new float[4 * 10 + 3];
                Assert.AreEqual(10, world.CopyPositions(new Span<float>(partial, 0, partial.Length)));
                Assert.AreEqual(0, world.CopyPositions(new float[3]), "fewer than 4 floats: nothing");
                Span<Vector4> window = new Vector4[40].AsSpan(5, 20);
                Assert.AreEqual(20, world.CopyPositions(window));
                Assert.AreEqual(vec[19], window[19]);

                var ids = new uint[n];
                Assert.AreEqual(n, world.CopyIds(ids));
                var someIds = new uint[7];
                Assert.AreEqual(7, world.CopyIds(someIds.AsSpan()));
                CollectionAssert.AreEqual(ids.Take(7).ToArray(), someIds);

                var vel = new float[n * 4];
                Assert.AreEqual(n, world.CopyVelocities(vel));
                Assert.Less(vel[1], 0f, "falling after one step");
            }
        }

        [Test]
        public void PerFrameCallsDoNotAllocate()
        {
            using (var world = Scene.CpuWorld())
            {
                world.EmitBlock(new Vector3(-0.21f, 0.0f, -0.21f), new Vector3(0.21f, 0.21f, 0.21f));
                var positions = new Vector4[world.ParticleCount];
                var floats = new float[positions.Length * 4];
                var ids = new uint[positions.Length];
                Span<Vector4> span = positions;
                // Warm up (JIT, first P/Invoke binding).
                world.CopyPositions(span);
                world.CopyPositions(floats);
                world.CopyVelocities(positions);
                world.CopyIds(ids);
                world.Step(Scene.Dt);
                StepStats stats = world.Stats;
                int count = world.ParticleCount;
                long before = GC.GetAllocatedBytesForCurrentThread();
                for (int i = 0; i < 200; ++i)
                {
                    if (i % 50 == 0) world.Step(Scene.Dt);
                    stats = world.Stats;
                    world.CopyPositions(span);
                    world.CopyPositions(floats);
                    world.CopyVelocities(positions);
                    world.CopyIds(ids);
                    count = world.ParticleCount;
                }
                long allocated = GC.GetAllocatedBytesForCurrentThread() - before;
                Assert.AreEqual(256, count);
                Assert.AreEqual(256, stats.ParticleCount);
                Assert.AreEqual(0L, allocated, "bytes allocated by 4 steps and 1200 copy, count and stats calls");
            }
        }

        [Test]
        public void MapPositionsExposesTheLiveHostBuffer()
        {
            using (var world = Scene.CpuWorld())
            {
                world.EmitBlock(new Vector3(-0.21f, 0.0f, -0.21f), new Vector3(0.21f, 0.21f, 0.21f));
                world.Step(Scene.Dt);
                Vector4[] copied = Scene.Positions(world);
                using (MappedPositions m = world.MapPositions())
                {
                    Assert.AreEqual(MemoryKind.Host, m.Memory);
                    Assert.AreNotEqual(IntPtr.Zero, m.Data);
                    Assert.AreEqual(copied.Length, m.Count);
                    Assert.AreEqual(16, m.StrideBytes);
                    for (int i = 0; i < m.Count; ++i) Assert.AreEqual(copied[i], m[i]);
                    var flat = new float[m.Count * 4];
                    Assert.AreEqual(m.Count, m.CopyTo(flat));
                    Assert.AreEqual(copied[7].Y, flat[7 * 4 + 1]);
                    Assert.Throws<ArgumentOutOfRangeException>(() => { var x = m[m.Count]; });
                }
                // Dispose unmapped it.
                Scene.ExpectError(Result.InvalidState, () => world.Unmap(), "no buffer is mapped");

                // A step ends a mapping: Unmap then has nothing to do, Dispose stays quiet.
                MappedPositions m2 = world.MapPositions();
                world.Step(Scene.Dt);
                Scene.ExpectError(Result.InvalidState, () => world.Unmap());
                m2.Dispose();

                MappedPositions m3 = world.MapPositions();
                world.Unmap();
                m3.Dispose();
            }
        }
    }
}
