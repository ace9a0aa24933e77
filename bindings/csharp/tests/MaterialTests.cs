using System;
using System.Linq;
using System.Numerics;
using NUnit.Framework;
using Pbf.Interop;

namespace Pbf.Tests
{
    /// <summary>Fluid materials (issue 16) through the C# mirror: defaults, the default material,
    /// per-particle read-back, refusals.</summary>
    [TestFixture]
    public class MaterialTests
    {
        [Test]
        public void DescDefaultsAreTheLibrarys()
        {
            var d = new MaterialDesc();
            Assert.AreEqual(1000f, d.RestDensity);
            Assert.AreEqual(0.01f, d.Viscosity);
            Assert.AreEqual(0.3f, d.LdcGain);
            Assert.AreEqual(0f, d.SurfaceTension);
            Assert.AreEqual(0f, d.Cohesion);
            Assert.AreEqual(0f, d.Adhesion);
            Assert.AreEqual(new Vector4(0.2f, 0.45f, 0.9f, 1f), d.Color);
            Assert.AreEqual(0u, d.UserId);
        }

        [Test]
        public void BlocksCarryTheirMaterialIndex()
        {
            using (var world = Scene.CpuWorld())
            {
                Material def = world.DefaultMaterial;
                Assert.AreEqual(0, def.Index);
                Assert.AreEqual(1000f, def.GetDesc().RestDensity, "the default material is the world's");
                Material oil = world.CreateMaterial(new MaterialDesc { RestDensity = 800f, UserId = 7, Color = new Vector4(1, 0.8f, 0, 1) });
                Assert.AreEqual(1, oil.Index);
                Assert.AreEqual(7u, oil.GetDesc().UserId);
                int water = world.EmitBlock(new Vector3(-0.4f, 0, -0.4f), new Vector3(-0.1f, 0.3f, -0.1f));
                int oily = world.EmitBlock(new BlockDesc(new Vector3(0.1f, 0, 0.1f), new Vector3(0.4f, 0.3f, 0.4f)) { Material = oil });
                Scene.Steps(world, 3);
                var bytes = new byte[world.ParticleCount];
                Assert.AreEqual(water + oily, world.CopyMaterials(bytes));
                Assert.AreEqual(water, bytes.Count(b => b == 0));
                Assert.AreEqual(oily, bytes.Count(b => b == oil.Index));
                Vector4[] p = Scene.Positions(world);
                Assert.IsTrue(Enumerable.Range(0, p.Length).All(k => (bytes[k] == oil.Index) == (p[k].X > 0)),
                              "the index follows its particle through the step's reordering");
                var ids = world.MaterialIds();
                Assert.AreEqual(oil.Id.generation, ids[1].generation);
                Assert.AreEqual(0u, ids[2].generation, "free index: zeroed");
            }
        }

        [Test]
        public void RefusalsNameTheirCheck()
        {
            using (var world = Scene.CpuWorld())
            {
                Scene.ExpectError(Result.InvalidArgument, () => world.CreateMaterial(new MaterialDesc { RestDensity = 50f }), "rest_density");
                Scene.ExpectError(Result.InvalidArgument, () => world.CreateMaterial(new MaterialDesc { SurfaceTension = -1f }), "surface_tension");
                Scene.ExpectError(Result.InvalidState, () => world.DefaultMaterial.Destroy(), "default material");
                Material honey = world.CreateMaterial(new MaterialDesc { Viscosity = 0.9f });
                world.EmitBlock(new BlockDesc(new Vector3(-0.1f, 0, -0.1f), new Vector3(0.1f, 0.2f, 0.1f)) { Material = honey });
                Scene.ExpectError(Result.InvalidState, () => honey.Destroy(), "in use");
                for (int k = 2; k < Native.PBF_MAX_MATERIALS; ++k) world.CreateMaterial(new MaterialDesc());
                Scene.ExpectError(Result.Capacity, () => world.CreateMaterial(new MaterialDesc()), "PBF_MAX_MATERIALS");
            }
        }

        [Test]
        public void AnUnusedMaterialIsDestroyedAndItsHandleGoesStale()
        {
            using (var world = Scene.CpuWorld())
            {
                Material m = world.CreateMaterial(new MaterialDesc { Adhesion = 100f });
                m.Destroy();
                Assert.IsTrue(m.IsDestroyed);
                Scene.ExpectError(Result.InvalidHandle, () => m.GetDesc(), "material is not live");
                Scene.ExpectError(Result.InvalidHandle,
                                  () => world.EmitBlock(new BlockDesc(new Vector3(-0.1f, 0, -0.1f), new Vector3(0.1f, 0.2f, 0.1f)) { Material = m }),
                                  "material");
                Assert.AreEqual(0, world.ParticleCount, "nothing emitted with a stale material");
            }
        }
    }
}
