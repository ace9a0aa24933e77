// Unity glue for the libpbf bindings: conversions between UnityEngine and System.Numerics types,
// a Unity mesh as a libpbf mesh, and a log handler that forwards libpbf's messages to the Unity
// console. Everything that needs UnityEngine lives beside this file; the core bindings
// (Runtime/Core: the one copy of the C# bindings, which Pbf.csproj and the Mono test build
// compile too) compile without it.
using UnityEngine;

namespace Pbf.Unity
{
    public static class PbfUnityExtensions
    {
        public static System.Numerics.Vector3 ToNumerics(this Vector3 v) { return new System.Numerics.Vector3(v.x, v.y, v.z); }
        public static Vector3 ToUnity(this System.Numerics.Vector3 v) { return new Vector3(v.X, v.Y, v.Z); }
        public static System.Numerics.Quaternion ToNumerics(this Quaternion q) { return new System.Numerics.Quaternion(q.x, q.y, q.z, q.w); }
        public static Quaternion ToUnity(this System.Numerics.Quaternion q) { return new Quaternion(q.X, q.Y, q.Z, q.W); }
        /// <summary>RGBA as a material colour (<see cref="MaterialDesc.Color"/>).</summary>
        public static System.Numerics.Vector4 ToNumerics(this Color c) { return new System.Numerics.Vector4(c.r, c.g, c.b, c.a); }
        public static Color ToUnityColor(this System.Numerics.Vector4 c) { return new Color(c.X, c.Y, c.Z, c.W); }
    }

    /// <summary>Unity meshes as libpbf meshes (<see cref="World.CreateMesh"/>).</summary>
    public static class PbfUnityMesh
    {
        /// <summary>The mesh's triangles, its vertices scaled by <paramref name="scale"/> (a
        /// Transform's lossyScale; the collider's pose carries the rotation and position). Unity's
        /// winding (clockwise seen from outside, in its left-handed frame) has the same numbers as
        /// libpbf's (counter-clockwise from outside, right-handed): (b - a) x (c - a) points out in
        /// both, so the indices pass unchanged, unless the scale mirrors the mesh (an odd number of
        /// negative factors), which turns every triangle inside out and so reverses each.</summary>
        public static MeshDesc ToMeshDesc(UnityEngine.Mesh mesh, Vector3 scale)
        {
            if (mesh == null) throw new System.ArgumentNullException("mesh");
            Vector3[] v = mesh.vertices;
            var vertices = new System.Numerics.Vector3[v.Length];
            for (int k = 0; k < v.Length; ++k) vertices[k] = Vector3.Scale(v[k], scale).ToNumerics();
            int[] indices = mesh.triangles;
            if (scale.x * scale.y * scale.z < 0.0f)
            {
                for (int k = 0; k + 2 < indices.Length; k += 3)
                {
                    int t = indices[k + 1];
                    indices[k + 1] = indices[k + 2];
                    indices[k + 2] = t;
                }
            }
            return new MeshDesc(vertices, indices);
        }
    }

    /// <summary>Routes libpbf's log to the Unity console (Debug.Log is safe from any thread).</summary>
    public static class PbfUnityLog
    {
        public static void Install(LogLevel minimum = LogLevel.Info)
        {
            Library.SetLogHandler((level, message) =>
            {
                if (level < minimum) return;
                if (level == LogLevel.Error) Debug.LogError("[libpbf] " + message);
                else if (level == LogLevel.Warning) Debug.LogWarning("[libpbf] " + message);
                else Debug.Log("[libpbf] " + message);
            });
        }

        public static void Uninstall() { Library.SetLogHandler(null); }
    }
}
