using System.Linq;
using System.Numerics;
using NUnit.Framework;
using Pbf.Interop;

namespace Pbf.Tests
{
    /// <summary>Open levels: WorldDesc.Walls and HashedGrid, WorldInfo.GridHashed and GridBytes.</summary>
    [TestFixture]
    public class OpenLevelTests
    {
        [Test]
        public void DefaultsKeepTheWallsAndTheAutomaticGrid()
        {
            var d = new WorldDesc();
            Assert.IsTrue(d.Walls);
            Assert.IsFalse(d.HashedGrid);
            Assert.AreEqual(1u, d.ToNative().walls);
            d.Walls = false;
            d.HashedGrid = true;
            Assert.AreEqual(0u, d.ToNative().walls);
            Assert.AreEqual(1u, d.ToNative().hashed_grid);
        }

        [Test]
        public void GridMemoryFollowsTheCapacityNotTheLevel()
        {
            // 100k particles of radius 0.01 m: a 2 m box has 50^3 cells, the open level 2^17 keys.
            var d = new WorldDesc { Backend = Backend.Cpu, MaxParticles = 100000, ParticleRadius = 0.01f,
                                    DomainMin = Vector3.Zero, DomainMax = new Vector3(2, 2, 2) };
            using (var box = World.Create(d))
            {
                d.Walls = false;
                using (var open = World.Create(d))
                {
                    WorldInfo a = box.Info, b = open.Info;
                    Assert.IsFalse(a.GridHashed);
                    Assert.AreEqual(125000, a.GridCells);
                    Assert.AreEqual(4 * 125001, a.GridBytes);
                    Assert.IsTrue(b.GridHashed);
                    Assert.AreEqual(131072, b.GridCells);
                    Assert.AreEqual(4 * 131073, b.GridBytes);
                    Assert.LessOrEqual((double)b.GridBytes, 1.1 * a.GridBytes);
                }
            }
        }

        [Test]
        public void WithoutWallsABlockFallsUntilAPlaneCatchesIt()
        {
            var d = Scene.CpuDesc(4096);
            d.Walls = false;
            using (var world = World.Create(d))
            {
                world.EmitBlock(new Vector3(500, 0.5f, -300), new Vector3(500.4f, 0.9f, -299.6f));
                for (int k = 0; k < 60; ++k) world.Step(1f / 60f);
                var p = Scene.Positions(world);
                Assert.IsTrue(p.All(v => v.Y < -3f), "no floor at the old domain's y = 0");
                world.CreateCollider(ColliderDesc.Plane(new Vector3(500, -10, -300), Vector3.UnitY));
                for (int k = 0; k < 120; ++k) world.Step(1f / 60f);
                p = Scene.Positions(world);
                Assert.IsTrue(p.All(v => !float.IsNaN(v.X + v.Y + v.Z) && !float.IsInfinity(v.X + v.Y + v.Z)));
                Assert.IsTrue(p.All(v => v.Y >= -10f + 0.99f * d.ParticleRadius), "the plane holds it");
            }
        }

        [Test]
        public void AnOutOfRangeWallsValueIsRefusedByName()
        {
            var raw = Scene.CpuDesc(1024).ToNative();
            raw.walls = 2;
            Assert.AreEqual(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_world_create(ref raw, out pbf_world_id _));
            StringAssert.Contains("walls must be 0", Native.LastErrorMessage());
        }
    }
}
