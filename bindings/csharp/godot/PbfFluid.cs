// libpbf in Godot 4 (.NET): a block of water in a box, stepped in _PhysicsProcess and drawn as a
// MultiMesh of spheres. Attach to a MultiMeshInstance3D. Needs the LibPbf NuGet package (see
// README.md beside this file). Not compiled or run here: there is no Godot or .NET SDK on the
// machine that builds libpbf.
using System;
using System.IO;
using System.Reflection;
using System.Runtime.InteropServices;
using Godot;
using Pbf;

public partial class PbfFluid : MultiMeshInstance3D
{
    [Export] public int MaxParticles = 8192;
    [Export] public float ParticleRadius = 0.025f;

    private Pbf.World _world;
    private System.Numerics.Vector4[] _positions;

    static PbfFluid()
    {
        // Where the .NET host did not resolve the package's runtimes/<rid>/native folder (Godot's
        // editor has been seen not to), load libpbf from there, or from beside the assembly.
        try { NativeLibrary.SetDllImportResolver(typeof(Pbf.World).Assembly, ResolveLibpbf); }
        catch (InvalidOperationException) { }  // already set (the script was reloaded)
    }

    private static IntPtr ResolveLibpbf(string name, Assembly assembly, DllImportSearchPath? searchPath)
    {
        if (name != "pbf") return IntPtr.Zero;
        bool windows = OperatingSystem.IsWindows();
        string file = windows ? "pbf.dll" : "libpbf.so";
        string rid = windows ? "win-x64" : "linux-x64";
        string dir = Path.GetDirectoryName(assembly.Location) ?? AppContext.BaseDirectory;
        foreach (string candidate in new[] { Path.Combine(dir, file), Path.Combine(dir, "runtimes", rid, "native", file) })
        {
            if (File.Exists(candidate) && NativeLibrary.TryLoad(candidate, out IntPtr handle)) return handle;
        }
        return IntPtr.Zero;  // fall back to the default search
    }

    public override void _Ready()
    {
        var desc = new WorldDesc { Backend = Backend.Auto, MaxParticles = MaxParticles, ParticleRadius = ParticleRadius };
        _world = Pbf.World.Create(desc);
        _world.EmitBlock(new System.Numerics.Vector3(-0.5f, 0f, -0.5f), new System.Numerics.Vector3(0f, 0.5f, 0.5f));
        _positions = new System.Numerics.Vector4[MaxParticles];
        GD.Print($"libpbf {Library.VersionString(Library.Version)} on {_world.Info.DeviceName}");

        Multimesh = new MultiMesh
        {
            TransformFormat = MultiMesh.TransformFormatEnum.Transform3D,
            Mesh = new SphereMesh { Radius = ParticleRadius, Height = 2 * ParticleRadius, RadialSegments = 8, Rings = 4 },
            InstanceCount = MaxParticles,
            VisibleInstanceCount = 0,
        };
    }

    public override void _PhysicsProcess(double delta)
    {
        _world.Step((float)delta);
        int n = _world.CopyPositions(_positions);  // x, y, z, density ratio; no allocation
        for (int i = 0; i < n; ++i)
            Multimesh.SetInstanceTransform(i, new Transform3D(Basis.Identity, new Vector3(_positions[i].X, _positions[i].Y, _positions[i].Z)));
        Multimesh.VisibleInstanceCount = n;
    }

    public override void _ExitTree()
    {
        _world?.Dispose();
        _world = null;
    }
}
