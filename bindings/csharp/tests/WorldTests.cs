using System;
using System.Linq;
using System.Numerics;
using System.Threading;
using NUnit.Framework;
using Pbf.Interop;

namespace Pbf.Tests
{
    [TestFixture]
    public class WorldTests
    {
        [Test]
        public void LibraryVersionIsCompatibleWithTheBindings()
        {
            Assert.AreEqual(Native.PBF_VERSION_MAJOR, Native.PBF_VERSION_GET_MAJOR(Library.Version));
            Assert.IsTrue(Library.IsCompatible);
            StringAssert.StartsWith(Native.PBF_VERSION_MAJOR + ".", Library.VersionString(Library.Version));
            Assert.AreEqual("1.2.3", Library.VersionString(Native.PBF_MAKE_VERSION(1, 2, 3)));
        }

        [Test]
        public void ProfileNamesStagesAndTimesThemWhenOn()
        {
            using (var world = Scene.CpuWorld(2048))
            {
                world.EmitBlock(new Vector3(-0.1f, 0, -0.1f), new Vector3(0.1f, 0.2f, 0.1f));
                world.Step(1f / 60f);
                var off = world.Profile;
                Assert.GreaterOrEqual(off.Length, 5);
                Assert.IsTrue(off.All(s => s.Value == 0f), "all zero while profiling is off");
                CollectionAssert.AllItemsAreUnique(off.Select(s => s.Key));
                CollectionAssert.Contains(off.Select(s => s.Key), "lambda");
                Assert.AreEqual(IntPtr.Zero, Native.pbf_profile_stage_name((uint)off.Length));

                world.SetProfiling(true);
                world.Step(1f / 60f);
                var on = world.Profile;
                Assert.IsTrue(on.All(s => s.Value >= 0f));
                Assert.Greater(on.Sum(s => s.Value), 0f);
                Assert.LessOrEqual(on.Sum(s => s.Value), world.Stats.StepTimeMs * 1.05f + 0.05f);
            }
        }

        [Test]
        public void ResultStringsNameEveryCode()
        {
            foreach (Result r in Enum.GetValues(typeof(Result)))
            {
                string s = Library.ResultString(r);
                string expected = Enum.GetName(typeof(pbf_result), (pbf_result)r);
                Assert.AreEqual(expected, s);
            }
            Assert.AreEqual("PBF_ERROR_UNKNOWN", Library.ResultString((Result)12345));
        }

        [Test]
        public void CreateReportsInfoAndDisposeIsIdempotent()
        {
            var world = Scene.CpuWorld(2048);
            WorldInfo info = world.Info;
            Assert.AreEqual(Backend.Cpu, info.Backend);
            Assert.AreEqual(2048, info.MaxParticles);
            Assert.AreEqual(0.025f, info.ParticleRadius, 1e-7f);
            Assert.AreEqual(0.05f, info.RestSpacing, 1e-7f);
            Assert.AreEqual(0.1f, info.KernelRadius, 1e-7f);
            Assert.AreEqual(20L * 20L * 20L, info.GridCells, "default domain 2 x 2 x 2 m in cells of h = 0.1 m");
            // Calibrated so a rest lattice has rest density: about 1000 kg/m³ · (0.05 m)³.
            Assert.AreEqual(0.125f, info.ParticleMass, 0.03f);
            Assert.Greater(info.DeviceBytes, 0L);
            StringAssert.StartsWith("CPU", info.DeviceName);
            Assert.AreEqual(0, world.ParticleCount);
            Assert.IsFalse(world.IsDisposed);

            pbf_world_id id = world.Id;
            world.Dispose();
            Assert.IsTrue(world.IsDisposed);
            world.Dispose();  // idempotent, no throw
            // The native world is really gone: its handle is stale.
            Assert.AreEqual(pbf_result.PBF_ERROR_INVALID_HANDLE, Native.pbf_world_step(id, Scene.Dt));
        }

        [Test]
        public void EveryMemberOfADisposedWorldThrowsObjectDisposed()
        {
            var world = Scene.CpuWorld();
            world.EmitBlock(new Vector3(-0.1f, 0, -0.1f), new Vector3(0.1f, 0.1f, 0.1f));
            world.Dispose();
            var buffer = new float[64];
            TestDelegate[] calls =
            {
                () => world.Step(Scene.Dt),
                () => { var x = world.Stats; },
                () => { var x = world.Info; },
                () => { var x = world.ParticleCount; },
                () => { var x = world.Id; },
                () => world.GetSolverParams(),
                () => world.SetSolverParams(SolverParams.Default),
                () => world.SetGravity(Vector3.Zero),
                () => world.EmitBlock(new Vector3(-0.1f, 0, -0.1f), new Vector3(0.1f, 0.1f, 0.1f)),
                () => world.CreateNozzle(Vector3.UnitY, -Vector3.UnitY, 1, 0.05f, 100),
                () => world.CreateDrain(-Vector3.One, Vector3.One),
                () => world.CreateCollider(ColliderDesc.Sphere(Vector3.UnitY, 0.1f)),
                () => world.CopyPositions(buffer),
                () => world.CopyVelocities(new Span<float>(buffer)),
                () => world.CopyIds(new uint[4]),
                () => world.MapPositions(),
                () => world.Unmap(),
            };
            foreach (var call in calls) Assert.Throws<ObjectDisposedException>(call);
        }

        [Test]
        public void StatsCountStepsEmissionAndIterations()
        {
            using (var world = Scene.CpuWorld())
            {
                StepStats before = world.Stats;
                Assert.AreEqual(0, before.StepIndex);
                Assert.AreEqual(0, before.ParticleCount);
                Assert.AreEqual(0f, before.KineticEnergy);

                int emitted = world.EmitBlock(new Vector3(-0.21f, 0.5f, -0.21f), new Vector3(0.21f, 0.71f, 0.21f));
                Assert.AreEqual(8 * 4 * 8, emitted);
                var p = world.GetSolverParams();
                p.Iterations = 3;
                p.Substeps = 2;
                world.SetSolverParams(p);
                Scene.Steps(world, 3);

                StepStats s = world.Stats;
                Assert.AreEqual(3, s.StepIndex);
                Assert.AreEqual(emitted, s.ParticleCount);
                Assert.AreEqual(emitted, s.EmittedTotal);
                Assert.AreEqual(0, s.DrainedTotal);
                Assert.AreEqual(3 * 2, s.Iterations, "iterations x substeps of the last step");
                Assert.AreEqual(2, s.Substeps, "fixed substeps");
                // KE = Σ ½ m v² over the particles' velocities; at least that of the falling
                // centre of mass, ½ m N (g·t)².
                float mass = world.Info.ParticleMass;
                double ke = 0;
                foreach (var v in Scene.Velocities(world)) ke += 0.5 * mass * (v.X * v.X + v.Y * v.Y + v.Z * v.Z);
                Assert.AreEqual(ke, s.KineticEnergy, 1e-3 * ke);
                float vc = 9.81f * 3 * Scene.Dt;
                Assert.GreaterOrEqual(s.KineticEnergy, 0.99f * 0.5f * mass * emitted * vc * vc);
                Assert.AreEqual(-vc, Scene.Mean(Scene.Velocities(world)).Y, 0.02f * vc);
                Assert.GreaterOrEqual(s.DensityErrorMean, 0f);
                Assert.GreaterOrEqual(s.DensityErrorMax, s.DensityErrorMean);
                Assert.GreaterOrEqual(s.StepTimeMs, 0f);
            }
        }

        [Test]
        public void SolverParamsRoundTripWithDocumentedDefaults()
        {
            var d = SolverParams.Default;
            Assert.AreEqual(4, d.Iterations);
            Assert.AreEqual(0, d.Substeps, "automatic");
            Assert.AreEqual(16, d.MaxSubsteps);
            Assert.AreEqual(0.5f, d.SubstepTravel);
            Assert.AreEqual(40f, d.SoundSpeed);
            Assert.AreEqual(0f, d.AdaptiveErrorTarget);
            Assert.AreEqual(1.0f, d.Relaxation);
            Assert.AreEqual(0.1f, d.ScorrK);
            Assert.AreEqual(4f, d.ScorrN);
            Assert.AreEqual(0.2f, d.ScorrDq);
            Assert.AreEqual(0.01f, d.XsphC);
            Assert.AreEqual(0.0005f, d.VorticityEpsilon);
            Assert.IsTrue(d.LdcEnabled);
            Assert.AreEqual(0.3f, d.LdcGain);
            Assert.AreEqual(100f, d.MaxSpeed);

            var desc = Scene.CpuDesc();
            desc.Solver.Iterations = 9;  // edits the desc in place (ref property)
            desc.Solver.LdcEnabled = false;
            using (var world = World.Create(desc))
            {
                var p = world.GetSolverParams();
                Assert.AreEqual(9, p.Iterations);
                Assert.IsFalse(p.LdcEnabled);
                p.Substeps = 3;
                p.XsphC = 0.5f;
                p.MaxSpeed = 12.5f;
                p.MaxSubsteps = 24;
                p.SubstepTravel = 0.25f;
                p.SoundSpeed = 20f;
                world.SetSolverParams(p);
                var q = world.GetSolverParams();
                Assert.AreEqual(3, q.Substeps);
                Assert.AreEqual(0.5f, q.XsphC);
                Assert.AreEqual(12.5f, q.MaxSpeed);
                Assert.AreEqual(9, q.Iterations);
                Assert.AreEqual(24, q.MaxSubsteps);
                Assert.AreEqual(0.25f, q.SubstepTravel);
                Assert.AreEqual(20f, q.SoundSpeed);
            }
        }

        [Test]
        public void AutomaticSubstepsAreReportedInStats()
        {
            var desc = Scene.CpuDesc();
            Assert.AreEqual(0, desc.Solver.Substeps, "a new desc asks for automatic substeps");
            using (var world = World.Create(desc))
            {
                Assert.AreEqual(0, world.Stats.Substeps, "all zero before the first step");
                world.EmitBlock(new Vector3(-0.21f, 0.5f, -0.21f), new Vector3(0.21f, 0.71f, 0.21f));
                Scene.Steps(world, 3);
                StepStats s = world.Stats;
                Assert.GreaterOrEqual(s.Substeps, 1, "automatic substeps run at least one");
                Assert.LessOrEqual(s.Substeps, world.GetSolverParams().MaxSubsteps);
                Assert.GreaterOrEqual(s.Iterations, s.Substeps, "at least one iteration per substep");
                Assert.GreaterOrEqual(s.SpeedClamps, 0L);
            }
        }

        [Test]
        public void DisposeRacingWithStepNeverCrashes()
        {
            for (int round = 0; round < 3; ++round)
            {
                var world = Scene.CpuWorld();
                world.EmitBlock(new Vector3(-0.21f, 0, -0.21f), new Vector3(0.21f, 0.42f, 0.21f));
                Exception seen = null;
                int steps = 0;
                var stepper = new Thread(() =>
                {
                    try
                    {
                        while (true) { world.Step(Scene.Dt); ++steps; }
                    }
                    catch (Exception e) { seen = e; }
                });
                stepper.Start();
                while (Volatile.Read(ref steps) < 2) Thread.Sleep(1);
                world.Dispose();
                Assert.IsTrue(stepper.Join(10000), "stepping thread did not stop");
                Assert.IsNotNull(seen);
                bool disposed = seen is ObjectDisposedException;
                bool stale = seen is PbfException && ((PbfException)seen).Code == Result.InvalidHandle;
                Assert.IsTrue(disposed || stale, "unexpected " + seen);
            }
        }

        [Test]
        public void WorldsAreIndependent()
        {
            using (var a = Scene.CpuWorld())
            using (var b = Scene.CpuWorld())
            {
                a.EmitBlock(new Vector3(-0.21f, 0, -0.21f), new Vector3(0.21f, 0.21f, 0.21f));
                a.Step(Scene.Dt);
                Assert.AreEqual(256, a.ParticleCount);
                Assert.AreEqual(0, b.ParticleCount);
                Assert.AreEqual(0, b.Stats.StepIndex);
                Assert.AreNotEqual(a.Id.index.ToString() + "/" + a.Id.generation, b.Id.index + "/" + b.Id.generation);
            }
        }
    }
}
