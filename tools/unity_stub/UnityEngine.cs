// Stand-ins for the UnityEngine API that the Unity package's scripts (Runtime/*.cs) and its
// sample (Samples~/FluidDemo) use, for tools/check_unity_sample.sh: signatures only (a compile
// check), no behaviour. Each member has the signature of UnityEngine's.
using System;
namespace UnityEngine
{
    public class Object { public static void Destroy(Object o) {} }
    public class Component : Object { public Transform transform; public T GetComponent<T>() { return default(T); } }
    public class Behaviour : Component { public bool enabled; }
    public class MonoBehaviour : Behaviour {}
    public class Transform : Component { public Vector3 position; public Quaternion rotation; public Vector3 lossyScale; }
    public class GameObject : Object
    {
        public GameObject(string name) {}
        public Transform transform;
        public static GameObject CreatePrimitive(PrimitiveType t) { return null; }
        public T GetComponent<T>() { return default(T); }
        public T AddComponent<T>() where T : Component { return null; }
    }
    public enum PrimitiveType { Sphere }
    public class MeshFilter : Component { public Mesh sharedMesh; }
    public class Mesh : Object { public Vector3[] vertices; public int[] triangles;
        public uint GetIndexCount(int submesh) { return 0; } public uint GetIndexStart(int submesh) { return 0; } public uint GetBaseVertex(int submesh) { return 0; } }
    public class Collider : Component { public bool enabled; }
    public class BoxCollider : Collider { public Vector3 center; public Vector3 size; }
    public enum ForceMode { Force, Acceleration, Impulse, VelocityChange }
    public class Rigidbody : Component
    {
        public float mass; public bool isKinematic; public Vector3 position; public Quaternion rotation;
        public Vector3 velocity; public Vector3 angularVelocity; public Vector3 worldCenterOfMass;
        public void AddForce(Vector3 force, ForceMode mode) {} public void AddTorque(Vector3 torque, ForceMode mode) {}
    }
    public class Shader : Object { public static Shader Find(string n) { return null; } public static int PropertyToID(string n) { return 0; } }
    public class Material : Object { public Material(Shader s) {} }
    public class MaterialPropertyBlock { public void SetBuffer(int id, GraphicsBuffer b) {} public void SetFloat(int id, float v) {}
        public void SetVector(int id, Vector4 value) {} public void SetVectorArray(int id, Vector4[] values) {} }
    public class GraphicsBuffer { public enum Target { Structured } public GraphicsBuffer(Target t, int count, int stride) {}
        public void SetData(Array data, int managedStart, int bufferStart, int count) {} public void Release() {}
        public IntPtr GetNativeBufferPtr() { return IntPtr.Zero; } }
    public enum ComputeBufferType { Default = 0, IndirectArguments = 256 }
    public class ComputeBuffer { public ComputeBuffer(int count, int stride, ComputeBufferType type) {}
        public void SetData(Array data) {} public void GetData(Array data) {} public void Release() {}
        public IntPtr GetNativeBufferPtr() { return IntPtr.Zero; } }
    public static class GL { public static void IssuePluginEvent(IntPtr callback, int eventID) {} }
    public static class SystemInfo { public static Rendering.GraphicsDeviceType graphicsDeviceType { get { return Rendering.GraphicsDeviceType.Null; } } }
    public struct Vector3
    {
        public float x, y, z; public Vector3(float x, float y, float z) { this.x = x; this.y = y; this.z = z; }
        public float magnitude { get { return 0; } } public Vector3 normalized { get { return this; } }
        public static Vector3 Scale(Vector3 a, Vector3 b) { return a; }
        public static Vector3 operator +(Vector3 a, Vector3 b) { return a; } public static Vector3 operator -(Vector3 a, Vector3 b) { return a; }
        public static Vector3 operator *(float s, Vector3 a) { return a; } public static Vector3 operator *(Vector3 a, float s) { return a; }
    }
    public struct Vector4 { public float x, y, z, w; public Vector4(float x, float y, float z, float w) { this.x = x; this.y = y; this.z = z; this.w = w; } }
    public struct Quaternion
    {
        public float x, y, z, w; public Quaternion(float x, float y, float z, float w) { this.x = x; this.y = y; this.z = z; this.w = w; }
        public static Quaternion Inverse(Quaternion q) { return q; } public static Quaternion AngleAxis(float degrees, Vector3 axis) { return default(Quaternion); }
        public static Quaternion operator *(Quaternion a, Quaternion b) { return a; } public static Vector3 operator *(Quaternion q, Vector3 v) { return v; }
    }
    public struct Bounds { public Bounds(Vector3 c, Vector3 s) {} }
    public struct Color { public float r, g, b, a; public Color(float r, float g, float b, float a) { this.r = r; this.g = g; this.b = b; this.a = a; }
        public static Color cyan; }
    public static class Gizmos { public static Color color; public static void DrawWireCube(Vector3 c, Vector3 s) {} public static void DrawRay(Vector3 from, Vector3 direction) {} }
    public static class Graphics { public static void DrawMeshInstancedProcedural(Mesh m, int sub, Material mat, Bounds b, int n, MaterialPropertyBlock p) {}
        public static void DrawMeshInstancedIndirect(Mesh m, int sub, Material mat, Bounds b, ComputeBuffer bufferWithArgs, int argsOffset = 0,
                                                     MaterialPropertyBlock properties = null) {} }
    public struct Rect { public Rect(float x, float y, float width, float height) {} }
    public static class GUI { public static void Label(Rect position, string text) {} }
    public static class Debug { public static void Log(object o) {} public static void LogError(object o) {} public static void LogWarning(object o) {} }
    public static class Mathf { public const float PI = 3.14159265f; public const float Rad2Deg = 57.29578f; public static float Abs(float f) { return f; } public static float Clamp(float v, float lo, float hi) { return v; } }
    public static class Physics { public static Vector3 gravity; }
    public static class Time { public static float fixedDeltaTime; }
    public class HeaderAttribute : Attribute { public HeaderAttribute(string s) {} }
    public class TooltipAttribute : Attribute { public TooltipAttribute(string s) {} }
    public class RangeAttribute : Attribute { public RangeAttribute(float a, float b) {} }
    [AttributeUsage(AttributeTargets.Class, AllowMultiple = true)]
    public class RequireComponentAttribute : Attribute { public RequireComponentAttribute(Type a) {} public RequireComponentAttribute(Type a, Type b) {} }
}
namespace UnityEngine.Rendering
{
    public enum GraphicsDeviceType { Direct3D11 = 2, Null = 4, OpenGLES3 = 11, Metal = 16, OpenGLCore = 17, Direct3D12 = 18, Vulkan = 21 }
}
