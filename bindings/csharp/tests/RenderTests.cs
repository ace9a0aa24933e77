using System;
using System.Numerics;
using System.Runtime.InteropServices;
using NUnit.Framework;
using Pbf.Interop;

namespace Pbf.Tests
{
    /// <summary>Render data (RenderParams, CopySmoothedPositions, CopyAnisotropy, the render
    /// pointers of DeviceBuffers) on the CPU backend.</summary>
    [TestFixture]
    public class RenderTests
    {
        static World RenderWorld(RenderFlags flags)
        {
            WorldDesc d = Scene.CpuDesc();
            d.Render.Flags = flags;
            return World.Create(d);
        }

        const RenderFlags Both = RenderFlags.SmoothedPositions | RenderFlags.Anisotropy;

        [Test]
        public void DefaultsAreTheLibrarys()
        {
            RenderParams p = RenderParams.Default;
            Assert.AreEqual(RenderFlags.None, p.Flags);
            Assert.AreEqual(0.9f, p.Smoothing);
            Assert.AreEqual(4.0f, p.MaxStretch);
            Assert.AreEqual(1.0f, p.Scale);
            Assert.AreEqual(0.5f, p.IsolatedScale);
            Assert.AreEqual(6, p.MinNeighbors);
            Assert.AreEqual(RenderFlags.None, new WorldDesc().Render.Flags);
        }

        [Test]
        public void LatticeBlockIsRoundInsideAndFlatOnTop()
        {
            using (var world = RenderWorld(Both))
            {
                Assert.AreEqual(1000, world.EmitBlock(new Vector3(-0.25f, 0.25f, -0.25f), new Vector3(0.25f, 0.75f, 0.25f), Vector3.Zero));
                Vector4[] pos = Scene.Positions(world);
                var smoothed = new Vector4[pos.Length];
                var aniso = new Vector4[pos.Length * 3];
                Assert.AreEqual(pos.Length, world.CopySmoothedPositions(smoothed));
                Assert.AreEqual(pos.Length, world.CopyAnisotropy(aniso));
                float top = float.MinValue;
                foreach (var p in pos) top = Math.Max(top, p.Y);
                int interior = 0, surface = 0;
                for (int i = 0; i < pos.Length; ++i)
                {
                    Vector3 x = Scene.Xyz(pos[i]);
                    bool sidesIn = Math.Abs(x.X) < 0.25f - 0.1f && Math.Abs(x.Z) < 0.25f - 0.1f;
                    if (sidesIn && x.Y > 0.35f && x.Y < 0.65f)
                    {
                        ++interior;
                        for (int k = 0; k < 3; ++k) Assert.AreEqual(0.025f, aniso[3 * i + k].W, 0.025f * 1e-3f, "interior radius");
                        Assert.AreEqual(0f, (Scene.Xyz(smoothed[i]) - x).Length(), 1e-6f, "interior stays put");
                    }
                    else if (sidesIn && x.Y > top - 1e-4f)
                    {
                        ++surface;
                        Assert.Greater(Math.Abs(aniso[3 * i + 2].Y), 0.999f, "the thin axis is the normal");
                        Assert.Less(aniso[3 * i + 2].W, 0.8f * aniso[3 * i].W, "flat");
                        Assert.Less(smoothed[i].Y, x.Y, "smoothing moves the surface inward");
                    }
                }
                Assert.AreEqual(6 * 6 * 6, interior);
                Assert.AreEqual(6 * 6, surface);
            }
        }

        [Test]
        public void IsolatedParticleIsRound()
        {
            using (var world = RenderWorld(RenderFlags.Anisotropy))
            {
                Assert.AreEqual(1, world.EmitBlock(new Vector3(0, 0.5f, 0), new Vector3(0.05f, 0.55f, 0.05f), Vector3.Zero));
                world.Step(Scene.Dt);
                var a = new float[12];
                Assert.AreEqual(1, world.CopyAnisotropy(a));
                for (int k = 0; k < 3; ++k)
                {
                    Assert.AreEqual(0.0125f, a[4 * k + 3], 1e-7f, "k_n · radius");
                    Assert.AreEqual(1.0f, a[4 * k + k], "world axes");
                }
            }
        }

        [Test]
        public void OffCostsNothingAndIsRefused()
        {
            using (var off = RenderWorld(RenderFlags.None))
            using (var on = RenderWorld(Both))
            {
                Scene.BlockSteps(2, off, on);
                WorldInfo a = off.Info, b = on.Info;
                Assert.AreEqual(0, a.RenderBytes);
                Assert.AreEqual(0, a.RenderUpdates);
                Assert.AreEqual(RenderFlags.None, a.RenderFlags);
                Assert.AreEqual(4096L * 64, b.RenderBytes);
                Assert.AreEqual(a.DeviceBytes + b.RenderBytes, b.DeviceBytes);
                Assert.AreEqual(3, b.RenderUpdates);
                Assert.AreEqual(Both, b.RenderFlags);

                var buf = new float[12 * 216];
                Scene.ExpectError(Result.InvalidState, () => off.CopyAnisotropy(buf), "PBF_RENDER_ANISOTROPY");
                Scene.ExpectError(Result.InvalidState, () => off.CopySmoothedPositions(buf), "PBF_RENDER_SMOOTHED_POSITIONS");
                Assert.Throws<ArgumentNullException>(() => on.CopyAnisotropy((float[])null));
                Assert.AreEqual(0, on.CopyAnisotropy(new float[11]), "less than one particle fits");
                Assert.AreEqual(1, on.CopyAnisotropy(new float[23]));
                // The raw entry point refuses a size that is not whole particles.
                uint written;
                Assert.AreEqual(pbf_result.PBF_ERROR_INVALID_ARGUMENT,
                    Native.pbf_world_copy_buffer(on.Id, pbf_buffer.PBF_BUFFER_ANISOTROPY, ref buf[0], 47, out written));
                Assert.AreEqual(pbf_result.PBF_ERROR_INVALID_ARGUMENT,
                    Native.pbf_world_copy_buffer(on.Id, (pbf_buffer)9, ref buf[0], 48, out written));

                using (DeviceBuffers m = off.MapDeviceBuffers())
                {
                    Assert.AreEqual(IntPtr.Zero, m.SmoothedPositions);
                    Assert.AreEqual(IntPtr.Zero, m.Anisotropy);
                }
                int n = on.ParticleCount;
                var copied = new float[n * 12];
                Assert.AreEqual(n, on.CopyAnisotropy(copied));
                using (DeviceBuffers m = on.MapDeviceBuffers())
                {
                    Assert.AreEqual(48, m.AnisotropyStrideBytes);
                    Assert.AreEqual(Both, m.RenderFlags);
                    var mapped = new float[n * 12];
                    Marshal.Copy(m.Anisotropy, mapped, 0, mapped.Length);
                    CollectionAssert.AreEqual(copied, mapped, "host pointer equals copy-out");
                }
            }
        }

        [Test]
        public void ParamsChangeBetweenStepsFlagsDoNot()
        {
            using (var world = RenderWorld(Both))
            {
                world.EmitBlock(new Vector3(-0.15f, 0.3f, -0.15f), new Vector3(0.15f, 0.6f, 0.15f), Vector3.Zero);
                RenderParams p = world.GetRenderParams();
                Assert.AreEqual(Both, p.Flags);
                p.Smoothing = 0.0f;
                world.SetRenderParams(p);
                Assert.AreEqual(0.0f, world.GetRenderParams().Smoothing);
                world.Step(Scene.Dt);
                Vector4[] pos = Scene.Positions(world);
                var smoothed = new Vector4[pos.Length];
                world.CopySmoothedPositions(smoothed);
                for (int i = 0; i < pos.Length; ++i)
                    Assert.AreEqual(Scene.Xyz(pos[i]), Scene.Xyz(smoothed[i]), "smoothing 0: the positions");
                p.Flags = RenderFlags.Anisotropy;
                Scene.ExpectError(Result.InvalidState, () => world.SetRenderParams(p), "fixed at world creation");
                p.Flags = Both;
                p.MaxStretch = 0.5f;
                Scene.ExpectError(Result.InvalidArgument, () => world.SetRenderParams(p), "render.max_stretch");
                Assert.AreEqual(4.0f, world.GetRenderParams().MaxStretch, "unchanged by the refusals");
            }
        }

        [Test]
        public void BadRenderParamsAreRefused()
        {
            WorldDesc d = Scene.CpuDesc();
            d.Render.Smoothing = 1.5f;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "render.smoothing");
            d = Scene.CpuDesc();
            d.Render.Flags = (RenderFlags)8;
            Scene.ExpectError(Result.InvalidArgument, () => World.Create(d), "render.flags");
            Assert.AreEqual(pbf_result.PBF_ERROR_INVALID_ARGUMENT, Native.pbf_render_params_init(IntPtr.Zero, Native.SizeOf<pbf_render_params>()));
        }
    }
}
