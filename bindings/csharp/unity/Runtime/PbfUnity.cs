// Unity glue for the libpbf bindings: conversions between UnityEngine and System.Numerics types,
// and a log handler that forwards libpbf's messages to the Unity console. Everything that needs
// UnityEngine lives here; the core bindings (Runtime/Core: the one copy of the C# bindings, which
// Pbf.csproj and the Mono test build compile too) compile without it.
using UnityEngine;

namespace Pbf.Unity
{
    public static class PbfUnityExtensions
    {
        public static System.Numerics.Vector3 ToNumerics(this Vector3 v) { return new System.Numerics.Vector3(v.x, v.y, v.z); }
        public static Vector3 ToUnity(this System.Numerics.Vector3 v) { return new Vector3(v.X, v.Y, v.Z); }
        public static System.Numerics.Quaternion ToNumerics(this Quaternion q) { return new System.Numerics.Quaternion(q.x, q.y, q.z, q.w); }
        public static Quaternion ToUnity(this System.Numerics.Quaternion q) { return new Quaternion(q.X, q.Y, q.Z, q.W); }
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
