using System.Numerics;
using NUnit.Framework;

namespace Pbf.Tests
{
    /// <summary>Small CPU scenes shared by the tests.</summary>
    static class Scene
    {
        public const float Dt = 1.0f / 60.0f;
        public const float Spacing = 0.05f;  // rest spacing of the default radius 0.025

        public static WorldDesc CpuDesc(int maxParticles = 4096)
        {
            return new WorldDesc { Backend = Backend.Cpu, MaxParticles = maxParticles };
        }

        public static World CpuWorld(int maxParticles = 4096) { return World.Create(CpuDesc(maxParticles)); }

        public static Vector4[] Positions(World world)
        {
            var p = new Vector4[world.ParticleCount];
            Assert.AreEqual(p.Length, world.CopyPositions(p));
            return p;
        }

        public static Vector4[] Velocities(World world)
        {
            var v = new Vector4[world.ParticleCount];
            Assert.AreEqual(v.Length, world.CopyVelocities(v));
            return v;
        }

        public static uint[] Ids(World world)
        {
            var ids = new uint[world.ParticleCount];
            Assert.AreEqual(ids.Length, world.CopyIds(ids));
            return ids;
        }

        public static Vector3 Mean(Vector4[] v)
        {
            var sum = Vector3.Zero;
            foreach (var p in v) sum += new Vector3(p.X, p.Y, p.Z);
            return v.Length > 0 ? sum / v.Length : sum;
        }

        public static Vector3 Xyz(Vector4 v) { return new Vector3(v.X, v.Y, v.Z); }

        public static void Steps(World world, int n)
        {
            for (int i = 0; i < n; ++i) world.Step(Dt);
        }

        /// <summary>The same 0.3 m block of water on the floor of each world, then n steps.</summary>
        public static void BlockSteps(int n, params World[] worlds)
        {
            foreach (var w in worlds)
            {
                w.EmitBlock(new Vector3(-0.15f, 0, -0.15f), new Vector3(0.15f, 0.3f, 0.15f), Vector3.Zero);
                Steps(w, n);
            }
        }

        /// <summary>Runs action, expects a PbfException with code, and a native message that
        /// names the code and contains every fragment.</summary>
        public static PbfException ExpectError(Result code, TestDelegate action, params string[] fragments)
        {
            var e = Assert.Throws<PbfException>(action);
            Assert.AreEqual(code, e.Code, "result code; message: " + e.Message);
            Assert.AreEqual(e.NativeMessage, e.Message);
            StringAssert.StartsWith(Library.ResultString(code) + ": ", e.NativeMessage);
            foreach (var f in fragments) StringAssert.Contains(f, e.NativeMessage);
            return e;
        }
    }
}
