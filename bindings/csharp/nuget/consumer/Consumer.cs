// The NuGet package's consumer test (scripts/check_nuget.sh): compiled against the packaged
// lib/netstandard2.1/Pbf.dll, run under Mono with the native library from the package's
// runtimes/linux-x64/native. Creates a world, fills a block, steps it, and checks that the
// libpbf it loaded is the package's.
//
//   mono Consumer.exe EXPECTED_NATIVE_DIR
using System;
using System.IO;
using System.Numerics;
using Pbf;

static class Consumer
{
    static int Main(string[] args)
    {
        string expectedDir = args.Length > 0 ? Path.GetFullPath(args[0]) : null;
        var desc = new WorldDesc { Backend = Backend.Cpu, MaxParticles = 4096 };
        using (World world = World.Create(desc))
        {
            int emitted = world.EmitBlock(new Vector3(-0.2f, 0f, -0.2f), new Vector3(0.2f, 0.3f, 0.2f));
            for (int i = 0; i < 30; ++i) world.Step(1f / 60f);
            var positions = new Vector4[desc.MaxParticles];
            int n = world.CopyPositions(positions);
            float lowest = float.MaxValue;
            for (int i = 0; i < n; ++i) lowest = Math.Min(lowest, positions[i].Y);

            string loaded = LoadedLibpbf();
            Console.WriteLine("libpbf " + Library.VersionString(Library.Version) + " from " + loaded);
            Console.WriteLine(n + " of " + emitted + " particles after 30 steps on " + world.Info.DeviceName +
                              ", lowest y " + lowest.ToString("F3"));
            if (n != emitted || n == 0 || lowest < desc.DomainMin.Y - 1e-3f)
            {
                Console.WriteLine("FAIL: the world did not step as expected");
                return 1;
            }
            if (expectedDir != null && (loaded == null || Path.GetDirectoryName(loaded) != expectedDir))
            {
                Console.WriteLine("FAIL: libpbf was not loaded from " + expectedDir);
                return 1;
            }
        }
        Console.WriteLine("OK");
        return 0;
    }

    // The file the process mapped for libpbf (Linux: /proc/self/maps).
    static string LoadedLibpbf()
    {
        if (!File.Exists("/proc/self/maps")) return null;
        foreach (string line in File.ReadAllLines("/proc/self/maps"))
        {
            int slash = line.IndexOf('/');
            if (slash >= 0 && Path.GetFileName(line.Substring(slash)).StartsWith("libpbf.so"))
                return line.Substring(slash);
        }
        return null;
    }
}
