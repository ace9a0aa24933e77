using System;
using System.Numerics;
using NUnit.Framework;

namespace Pbf.Tests
{
    /// <summary>Every error path reachable from C#: each surfaces as a PbfException carrying the
    /// native code and the native message, and leaves the world unchanged.</summary>
    [TestFixture]
    public class ErrorTests
    {
        World _world;

        [SetUp]
        public void SetUp()
        {
            _world = Scene.CpuWorld(1024);
            _world.EmitBlock(new Vector3(-0.21f, 0, -0.21f), new Vector3(0.21f, 0.21f, 0.21f));
        }

        [TearDown]
        public void TearDown() { _world.Dispose(); }

        [TestCase(0.0f)]
        [TestCase(-0.01f)]
        [TestCase(float.NaN)]
        [TestCase(float.PositiveInfinity)]
        [TestCase(1.5f)]
        public void StepRefusesBadDt(float dt)
        {
            Scene.ExpectError(Result.InvalidArgument, () => _world.Step(dt), "pbf_world_step", "dt must be finite");
            Assert.AreEqual(0, _world.Stats.StepIndex, "a failed call changes nothing");
        }

        [Test]
        public void CreateRefusesNaNAndOutOfRangeDescs()
        {
            var d = Scene.CpuDesc();
            d.ParticleRadius = float.NaN;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "pbf_world_create", "particle_radius");

            d = Scene.CpuDesc();
            d.Gravity = new Vector3(0, float.NaN, 0);
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "gravity must be finite");

            d = Scene.CpuDesc();
            d.DomainMax = new Vector3(float.PositiveInfinity, 2, 1);
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "domain bounds must be finite");

            d = Scene.CpuDesc();
            d.DomainMax = new Vector3(-0.99f, 2, 1);
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "domain_max must exceed domain_min");

            d = Scene.CpuDesc();
            d.RestDensity = -1000f;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "rest_density");

            d = Scene.CpuDesc(0);
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "max_particles");

            d = Scene.CpuDesc();
            d.Backend = (Backend)7;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "backend must be");

            d = Scene.CpuDesc();
            d.CudaDevice = -1;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "cuda_device");

            d = Scene.CpuDesc();
            d.Solver.Iterations = 0;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "solver.iterations must be 1..64");

            d = Scene.CpuDesc();
            d.Solver.Relaxation = float.NaN;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "solver.relaxation");

            Assert.Throws<ArgumentNullException>(() => World.Create(null));
        }

        [Test]
        public void CudaWithoutADeviceIsBackendUnavailable()
        {
            var d = Scene.CpuDesc();
            d.Backend = Backend.Cuda;
            World w = null;
            try
            {
                w = World.Create(d);
            }
            catch (PbfException e)
            {
                Assert.AreEqual(Result.BackendUnavailable, e.Code);
                StringAssert.Contains("PBF_BACKEND_CUDA requested", e.Message);
                return;
            }
            // A CUDA build on a machine with a GPU: then it must really be CUDA.
            using (w) Assert.AreEqual(Backend.Cuda, w.Info.Backend);
        }

        [Test]
        public void SolverParamsAreValidated()
        {
            var p = _world.GetSolverParams();
            p.Substeps = 65;
            Scene.ExpectError(Result.InvalidArgument, () => _world.SetSolverParams(p), "pbf_world_set_solver_params", "substeps must be 0 (automatic) or 1..64");
            p = _world.GetSolverParams();
            p.MaxSubsteps = 0;
            Scene.ExpectError(Result.InvalidArgument, () => _world.SetSolverParams(p), "max_substeps");
            p = _world.GetSolverParams();
            p.SubstepTravel = 0.01f;
            Scene.ExpectError(Result.InvalidArgument, () => _world.SetSolverParams(p), "substep_travel");
            p = _world.GetSolverParams();
            p.SoundSpeed = float.PositiveInfinity;
            Scene.ExpectError(Result.InvalidArgument, () => _world.SetSolverParams(p), "sound_speed");
            p = _world.GetSolverParams();
            p.SoundSpeed = 5f;  // below 10 m/s the fluid compresses until particles overlap
            Scene.ExpectError(Result.InvalidArgument, () => _world.SetSolverParams(p), "sound_speed must be finite and >= 10");
            p = _world.GetSolverParams();
            p.VorticityEpsilon = 2f;  // above 1 m/s confinement makes energy
            Scene.ExpectError(Result.InvalidArgument, () => _world.SetSolverParams(p), "vorticity_epsilon must be 0..1");
            p = _world.GetSolverParams();
            p.ScorrN = float.NaN;
            Scene.ExpectError(Result.InvalidArgument, () => _world.SetSolverParams(p), "scorr_n");
            p = _world.GetSolverParams();
            p.LdcGain = 2f;
            Scene.ExpectError(Result.InvalidArgument, () => _world.SetSolverParams(p), "ldc_gain");
            // default(SolverParams) never went through pbf_solver_params_init: struct_size is 0.
            Scene.ExpectError(Result.StructSize, () => _world.SetSolverParams(default(SolverParams)), "struct_size is 0");
            Assert.AreEqual(4, _world.GetSolverParams().Iterations, "unchanged");
            Assert.AreEqual(0, _world.GetSolverParams().Substeps, "unchanged");
        }

        [Test]
        public void GravityAndBlocksRefuseNaN()
        {
            Scene.ExpectError(Result.InvalidArgument, () => _world.SetGravity(new Vector3(float.NaN, 0, 0)), "pbf_world_set_gravity");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.EmitBlock(new Vector3(float.NaN, 0, 0), Vector3.One), "pbf_world_emit_block", "must be finite");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.EmitBlock(Vector3.Zero, new Vector3(0.2f, 0.2f, 0.2f), new Vector3(0, float.NegativeInfinity, 0)),
                "must be finite");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.EmitBlock(new Vector3(0.2f, 0, 0), new Vector3(0.1f, 0.2f, 0.2f)), "box_max must exceed box_min");
            Assert.AreEqual(256, _world.ParticleCount, "unchanged");
            Assert.Throws<ArgumentNullException>(() => _world.EmitBlock(null));
        }

        [Test]
        public void OverCapacityEmitsWhatFitsThenRefuses()
        {
            using (var small = Scene.CpuWorld(100))
            {
                int emitted = small.EmitBlock(new Vector3(-0.21f, 0, -0.21f), new Vector3(0.21f, 0.42f, 0.21f));
                Assert.AreEqual(100, emitted, "512 lattice points, 100 fit");
                Assert.AreEqual(100, small.ParticleCount);
                Scene.ExpectError(Result.Capacity,
                    () => small.EmitBlock(new Vector3(0.5f, 0, 0.5f), new Vector3(0.7f, 0.2f, 0.7f)), "world is full", "max_particles = 100");
                Assert.AreEqual(100, small.ParticleCount);
                Assert.AreEqual(100, small.Stats.EmittedTotal);
            }
        }

        [Test]
        public void EmitterDescsAreValidated()
        {
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateNozzle(Vector3.UnitY, -Vector3.UnitY, 0f, 0.05f, 100f), "pbf_world_create_emitter", "speed");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateNozzle(new Vector3(float.NaN, 1, 0), -Vector3.UnitY, 1f, 0.05f, 100f), "position and direction must be finite");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateNozzle(Vector3.UnitY, Vector3.Zero, 1f, 0.05f, 100f), "direction must be non-zero");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateNozzle(Vector3.UnitY, -Vector3.UnitY, 1f, 0.05f, float.NaN), "particles_per_second");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateDrain(Vector3.One, -Vector3.One), "drain box_max must exceed box_min");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateEmitter(new EmitterDesc((EmitterType)0)), "type must be PBF_EMITTER_NOZZLE or PBF_EMITTER_DRAIN");

            // A disc of radius 0.05 m at 1 m/s carries π 0.05² / 0.05² x 1 / 0.05 ≈ 62.8 particles/s at rest spacing.
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateNozzle(Vector3.UnitY, -Vector3.UnitY, 1f, 0.05f, 100f), "particles_per_second 100 exceeds what the nozzle carries");

            Emitter nozzle = _world.CreateNozzle(Vector3.UnitY, -Vector3.UnitY, 1f, 0.05f, 50f);
            Scene.ExpectError(Result.InvalidArgument, () => nozzle.SetNozzle(Vector3.UnitY, Vector3.Zero), "pbf_emitter_set_nozzle", "nozzle direction must be non-zero");
            Scene.ExpectError(Result.InvalidArgument, () => nozzle.SetNozzle(new Vector3(0, float.NaN, 0), Vector3.UnitY), "non-NULL and finite");
            Emitter drain = _world.CreateDrain(-Vector3.One, Vector3.One);
            Scene.ExpectError(Result.InvalidArgument, () => drain.SetDrainBox(Vector3.One, Vector3.Zero), "drain box_max must exceed box_min");
            // Each mover takes its own type of emitter.
            Scene.ExpectError(Result.InvalidArgument, () => nozzle.SetDrainBox(-Vector3.One, Vector3.One), "pbf_emitter_set_drain_box", "the emitter is of the other type");
            Scene.ExpectError(Result.InvalidArgument, () => drain.SetNozzle(Vector3.UnitY, -Vector3.UnitY), "pbf_emitter_set_nozzle", "the emitter is of the other type");
        }

        [Test]
        public void ColliderDescsAreValidated()
        {
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateCollider(ColliderDesc.Sphere(Vector3.UnitY, 0f)), "pbf_world_create_collider", "radius must be finite and > 0");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateCollider(ColliderDesc.Sphere(new Vector3(0, float.NaN, 0), 0.1f)), "position must be finite");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateCollider(ColliderDesc.Box(Vector3.UnitY, new Quaternion(0, 0, 0, 0), new Vector3(0.1f))), "non-zero quaternion");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateCollider(ColliderDesc.Box(Vector3.UnitY, Quaternion.Identity, new Vector3(0.1f, -0.1f, 0.1f))), "half_extents");
            Scene.ExpectError(Result.InvalidArgument,
                () => _world.CreateCollider(ColliderDesc.Capsule(Vector3.UnitY, Quaternion.Identity, 0.1f, float.NaN)), "half_height");
            var rough = ColliderDesc.Sphere(Vector3.UnitY, 0.1f);
            rough.Friction = 1.5f;
            Scene.ExpectError(Result.InvalidArgument, () => _world.CreateCollider(rough), "friction must be 0..1");
            var weird = new ColliderDesc((ColliderShape)9) { Radius = 0.1f };
            Scene.ExpectError(Result.InvalidArgument, () => _world.CreateCollider(weird), "shape must be");
            var moving = ColliderDesc.Sphere(Vector3.UnitY, 0.1f, (ColliderMotion)5);
            Scene.ExpectError(Result.InvalidArgument, () => _world.CreateCollider(moving), "motion must be");
        }

        [Test]
        public void StaticCollidersCannotBePosed()
        {
            Collider c = _world.CreateCollider(ColliderDesc.Sphere(new Vector3(0, 1, 0), 0.1f));
            Scene.ExpectError(Result.InvalidState, () => c.SetTargetPose(Vector3.One, Quaternion.Identity),
                "pbf_collider_set_target_pose", "only kinematic colliders can be moved");
            Collider k = _world.CreateCollider(ColliderDesc.Sphere(new Vector3(0, 1, 0), 0.1f, ColliderMotion.Kinematic));
            k.SetTargetPose(new Vector3(0.1f, 1, 0), Quaternion.Identity);
            Scene.ExpectError(Result.InvalidArgument, () => k.SetTargetPose(Vector3.One, new Quaternion(0, 0, 0, 0)), "non-zero quaternion");
        }

        [Test]
        public void ColliderTableIsBounded()
        {
            var desc = Scene.CpuDesc(1024);
            desc.MaxColliders = 300;
            using (var world = World.Create(desc))
            {
                var colliders = new Collider[300];
                for (int i = 0; i < colliders.Length; ++i)
                    colliders[i] = world.CreateCollider(ColliderDesc.Sphere(new Vector3(0, 1.5f, 0), 0.01f));
                Scene.ExpectError(Result.Capacity, () => world.CreateCollider(ColliderDesc.Sphere(Vector3.UnitY, 0.01f)),
                    "max_colliders = 300");
                colliders[5].Destroy();
                world.CreateCollider(ColliderDesc.Sphere(Vector3.UnitY, 0.01f));  // a freed slot is reused
            }
            var bad = Scene.CpuDesc(1024);
            bad.MaxColliders = 2049;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(bad), "max_colliders must be 1..2048");
        }

        [Test]
        public void ForceOfAColliderThatIsNotDynamicIsRefused()
        {
            Collider c = _world.CreateCollider(ColliderDesc.Sphere(new Vector3(0, 1, 0), 0.1f));
            Scene.ExpectError(Result.InvalidState, () => c.GetForce(), "pbf_collider_get_force", "not dynamic");
            var d = ColliderDesc.Sphere(new Vector3(0.3f, 1, 0), 0.1f);
            d.CenterOfMass = new Vector3(float.NaN, 0, 0);
            d.Dynamic = true;
            Scene.ExpectError(Result.InvalidArgument, () => _world.CreateCollider(d), "center_of_mass must be finite");
        }

        [Test]
        public void UnmapWithoutAMappingIsInvalidState()
        {
            Scene.ExpectError(Result.InvalidState, () => _world.Unmap(), "pbf_world_unmap", "no buffer is mapped");
        }

        [Test]
        public void CopyRefusesNullArraysManagedSide()
        {
            Assert.Throws<ArgumentNullException>(() => _world.CopyPositions((float[])null));
            Assert.Throws<ArgumentNullException>(() => _world.CopyVelocities((Vector4[])null));
            Assert.Throws<ArgumentNullException>(() => _world.CopyIds((uint[])null));
        }
    }
}
