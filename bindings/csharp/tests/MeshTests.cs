using System;
using System.Linq;
using System.Numerics;
using NUnit.Framework;

namespace Pbf.Tests
{
    /// <summary>Mesh colliders through the C# mirror: a box mesh holds water from below, a mesh in
    /// use is not destroyed, bad meshes are refused with the library's result.</summary>
    [TestFixture]
    public class MeshTests
    {
        // The box [-e, e]: 8 corners, 12 triangles counter-clockwise seen from outside.
        static MeshDesc Box(Vector3 e)
        {
            var v = new Vector3[8];
            for (int k = 0; k < 8; ++k)
                v[k] = new Vector3((k & 1) != 0 ? e.X : -e.X, (k & 2) != 0 ? e.Y : -e.Y, (k & 4) != 0 ? e.Z : -e.Z);
            int[][] quads = { new[] { 0, 2, 3, 1 }, new[] { 4, 5, 7, 6 }, new[] { 0, 1, 5, 4 },
                              new[] { 2, 6, 7, 3 }, new[] { 0, 4, 6, 2 }, new[] { 1, 3, 7, 5 } };
            var i = quads.SelectMany(q => new[] { q[0], q[1], q[2], q[0], q[2], q[3] }).ToArray();
            return new MeshDesc(v, i);
        }

        [Test]
        public void BoxMeshHoldsWaterAndIsSharedByColliders()
        {
            using (var world = Scene.CpuWorld())
            {
                Mesh mesh = world.CreateMesh(Box(new Vector3(0.3f, 0.1f, 0.3f)));
                Collider a = world.CreateCollider(ColliderDesc.FromMesh(mesh, new Vector3(0, 0.3f, 0), Quaternion.Identity));
                Collider b = world.CreateCollider(ColliderDesc.FromMesh(mesh, new Vector3(0, 0.3f, 0.8f), Quaternion.Identity,
                                                                        ColliderMotion.Kinematic));
                Assert.AreEqual(ColliderShape.Mesh, a.Shape);
                world.EmitBlock(new Vector3(-0.1f, 0.6f, -0.1f), new Vector3(0.1f, 0.7f, 0.1f));
                Scene.Steps(world, 60);
                Vector4[] p = Scene.Positions(world);
                Assert.IsTrue(p.All(q => q.Y > 0.4f - 0.01f), "the water rests on the box's top (y = 0.4)");

                // Teleported away: the water that rested on it falls.
                float restY = Scene.Mean(p).Y;
                a.Teleport(new Vector3(0, 0.3f, -0.8f), Quaternion.Identity);
                Scene.Steps(world, 30);
                Assert.Less(Scene.Mean(Scene.Positions(world)).Y, restY - 0.2f);

                var e = Assert.Throws<PbfException>(() => mesh.Destroy());
                Assert.AreEqual(Result.InvalidState, e.Code);
                a.Destroy();
                b.Destroy();
                mesh.Destroy();
                Assert.IsTrue(mesh.IsDestroyed);
            }
        }

        [Test]
        public void BadMeshesAreRefused()
        {
            using (var world = Scene.CpuWorld())
            {
                MeshDesc d = Box(new Vector3(0.1f, 0.1f, 0.1f));
                d.Indices[4] = 8;  // out of range
                var e = Assert.Throws<PbfException>(() => world.CreateMesh(d));
                Assert.AreEqual(Result.InvalidArgument, e.Code);
                StringAssert.Contains("index 4 is 8", e.Message);
                MeshDesc fine = Box(new Vector3(0.1f, 0.1f, 0.1f));
                fine.CellSize = 0.0005f;  // a field over 256 MB
                e = Assert.Throws<PbfException>(() => world.CreateMesh(fine));
                Assert.AreEqual(Result.Capacity, e.Code);
                Assert.Throws<ArgumentNullException>(() => ColliderDesc.FromMesh(null, Vector3.Zero, Quaternion.Identity));
            }
        }

        [Test]
        public void AnOpenQuadWithThicknessHoldsWater()
        {
            using (var world = Scene.CpuWorld())
            {
                // A single-sided square, 1 m wide, at y = 0.3: an open mesh is solid within
                // Thickness/2 of its surface, from either side.
                var v = new[] { new Vector3(-0.5f, 0, -0.5f), new Vector3(0.5f, 0, -0.5f), new Vector3(0.5f, 0, 0.5f), new Vector3(-0.5f, 0, 0.5f) };
                var d = new MeshDesc(v, new[] { 0, 2, 1, 0, 3, 2 }) { Closed = false, Thickness = 0.06f };
                Assert.IsTrue(new MeshDesc(v, new[] { 0, 2, 1 }).Closed, "closed by default");
                Mesh sheet = world.CreateMesh(d);
                world.CreateCollider(ColliderDesc.FromMesh(sheet, new Vector3(0, 0.3f, 0), Quaternion.Identity));
                int n = world.EmitBlock(new Vector3(-0.1f, 0.4f, -0.1f), new Vector3(0.1f, 0.5f, 0.1f));
                Assert.Greater(n, 0);
                Scene.Steps(world, 45);
                Vector4[] p = Scene.Positions(world);
                Assert.AreEqual(n, p.Length);
                Assert.IsTrue(p.All(q => q.Y > 0.3f + 0.03f - 0.01f), "the water rests on the sheet's upper face (y = 0.33)");
            }
        }
    }
}
