using System;
using System.Linq;
using System.Numerics;
using System.Runtime.InteropServices;
using NUnit.Framework;
using Pbf.Interop;

namespace Pbf.Tests
{
    /// <summary>Fluid materials through the C# mirror: defaults, the default material,
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

        [Test]
        public void MaterialsListsTheLiveOnesByIndexWithTheirColours()
        {
            using (var world = Scene.CpuWorld())
            {
                Material[] before = world.Materials;
                Assert.AreEqual(Native.PBF_MAX_MATERIALS, before.Length);
                Assert.IsNotNull(before[0], "the default material");
                Assert.IsTrue(before.Skip(1).All(m => m == null), "nothing else yet");
                Material oil = world.CreateMaterial(new MaterialDesc { RestDensity = 500f, Color = new Vector4(1, 0.7f, 0.1f, 1) });
                Material honey = world.CreateMaterial(new MaterialDesc { Viscosity = 0.5f, Color = new Vector4(0.8f, 0.5f, 0, 1) });
                oil.Destroy();
                Material[] after = world.Materials;
                Assert.IsNull(after[1], "a destroyed material's index is free");
                Assert.AreEqual(honey.Index, 2);
                Assert.AreEqual(honey.Id.generation, after[2].Id.generation);
                Assert.AreEqual(new Vector4(0.8f, 0.5f, 0, 1), after[2].GetDesc().Color, "the colour a renderer reads");
                Assert.AreEqual(new Vector4(0.2f, 0.45f, 0.9f, 1), after[0].GetDesc().Color);
            }
        }

        [Test]
        public void SetDescAppliesAndTheDefaultMaterialIsTheSolvers()
        {
            using (var world = Scene.CpuWorld())
            {
                Material oil = world.CreateMaterial(new MaterialDesc { RestDensity = 800f });
                MaterialDesc d = oil.GetDesc();
                d.Cohesion = 20f;
                d.UserId = 42;
                d.Color = new Vector4(0, 1, 0, 1);
                oil.SetDesc(d);
                MaterialDesc back = oil.GetDesc();
                Assert.AreEqual(20f, back.Cohesion);
                Assert.AreEqual(42u, back.UserId);
                Assert.AreEqual(new Vector4(0, 1, 0, 1), back.Color);

                // The default material's viscosity and LDC gain are the solver's xsph_c and ldc_gain.
                Material water = world.DefaultMaterial;
                MaterialDesc w = water.GetDesc();
                w.Viscosity = 0.05f;
                w.Color = new Vector4(0.1f, 0.2f, 0.9f, 1);
                water.SetDesc(w);
                Assert.AreEqual(0.05f, world.GetSolverParams().XsphC);
                Assert.AreEqual(new Vector4(0.1f, 0.2f, 0.9f, 1), water.GetDesc().Color);
                w.RestDensity = 900f;
                Scene.ExpectError(Result.InvalidArgument, () => water.SetDesc(w), "rest_density");
                Assert.AreEqual(1000f, water.GetDesc().RestDensity, "a refused desc changes nothing");
                Assert.Throws<ArgumentNullException>(() => oil.SetDesc(null));
            }
        }

        [Test]
        public void TwoFluidsSideBySideStratify()
        {
            // A lock exchange (tests/materials_scenes.h's scene): a column of oil (500 kg/m^3)
            // beside one of water, on a two-layer film of water (a fluid's own layer against the
            // floor stays pinned under a heavier one). The interface is the height below which the
            // water's volume fits: the lowest N_water particles; at the start about half of the oil
            // lies under it, stratified none.
            const float r = 0.02f;
            var desc = new WorldDesc
            {
                Backend = Backend.Cpu, ParticleRadius = r, MaxParticles = 4096,
                DomainMin = Vector3.Zero, DomainMax = new Vector3(0.48f, 0.8f, 0.32f),
            };
            using (World world = World.Create(desc))
            {
                Material oil = world.CreateMaterial(new MaterialDesc { RestDensity = 500f });
                int light = world.EmitBlock(new BlockDesc(new Vector3(0, 0.08f, 0), new Vector3(0.24f, 0.72f, 0.32f)) { Material = oil });
                int heavy = world.EmitBlock(new Vector3(0.24f, 0.08f, 0), new Vector3(0.48f, 0.72f, 0.32f))
                          + world.EmitBlock(Vector3.Zero, new Vector3(0.48f, 0.08f, 0.32f));
                Assert.AreEqual(768, light);
                Assert.AreEqual(960, heavy);
                Scene.Steps(world, 240);
                var bytes = new byte[world.ParticleCount];
                Assert.AreEqual(light + heavy, world.CopyMaterials(bytes));
                Vector4[] p = Scene.Positions(world);
                int[] byHeight = Enumerable.Range(0, p.Length).OrderBy(k => p[k].Y).ToArray();
                int above = byHeight.Skip(heavy).Count(k => bytes[k] == oil.Index);
                Assert.GreaterOrEqual(above, 0.9 * light, "oil above the interface after 4 s");
            }
        }

        [Test]
        public void ANozzlePoursItsMaterialAndTheMappedBytesAgree()
        {
            using (var world = Scene.CpuWorld())
            {
                Material oil = world.CreateMaterial(new MaterialDesc { RestDensity = 700f });
                EmitterDesc d = EmitterDesc.Nozzle(new Vector3(0, 0.5f, 0), -Vector3.UnitY, 1f, 0.1f, 200f);
                d.Material = oil;
                Emitter nozzle = world.CreateEmitter(d);
                world.EmitBlock(new Vector3(-0.5f, 0, -0.5f), new Vector3(-0.3f, 0.1f, -0.3f));  // water
                int water = world.ParticleCount;
                Scene.Steps(world, 30);
                var bytes = new byte[world.ParticleCount];
                Assert.AreEqual(bytes.Length, world.CopyMaterials(bytes));
                Assert.Greater(bytes.Length, water, "the nozzle poured");
                Assert.AreEqual(bytes.Length - water, bytes.Count(b => b == oil.Index), "all it poured is oil");
                using (DeviceBuffers b = world.MapDeviceBuffers())
                {
                    Assert.AreNotEqual(IntPtr.Zero, b.Materials);
                    var mapped = new byte[b.Count];
                    Marshal.Copy(b.Materials, mapped, 0, mapped.Length);
                    CollectionAssert.AreEqual(bytes, mapped, "the mapped bytes are the copied ones");
                }
                Scene.ExpectError(Result.InvalidState, () => oil.Destroy(), "emitter");
                nozzle.Destroy();
            }
        }
    }
}
