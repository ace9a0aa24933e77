// Headless dam break through the C# bindings: the scene, console output and final table of
// samples/dam_break.c, so the two can be compared line by line.
//
//   mono DamBreak.exe [particles=32768] [steps=300] [iterations=4]     (or samples/csharp/run.sh)
//   PBF_BACKEND=cpu|cuda overrides the backend (default: CUDA when available).
//   PBF_LDC=0|1 turns Local Density Calibration off or on (default on).
//   PBF_SUBSTEPS=n overrides the substep count.
// Exits non-zero on any libpbf error.
using System;
using System.Globalization;
using System.Numerics;
using Pbf;

public static class DamBreak
{
    static readonly CultureInfo C = CultureInfo.InvariantCulture;

    // printf("%.Nf") of a float or double: C promotes floats to double before formatting.
    static string F(double value, int decimals) { return value.ToString("F" + decimals, C); }

    static string BackendName(Backend b) { return b == Backend.Cuda ? "cuda" : "cpu"; }

    // atol/atoi: leading integer, 0 when there is none.
    static long ParseLong(string s)
    {
        s = s.TrimStart();
        int n = 0;
        if (n < s.Length && (s[n] == '-' || s[n] == '+')) ++n;
        while (n < s.Length && char.IsDigit(s[n])) ++n;
        long v;
        return long.TryParse(s.Substring(0, n), NumberStyles.AllowLeadingSign, C, out v) ? v : 0;
    }

    public static int Main(string[] args)
    {
        long particles = args.Length > 0 ? ParseLong(args[0]) : 32768;
        long steps = args.Length > 1 ? ParseLong(args[1]) : 300;
        long iterations = args.Length > 2 ? ParseLong(args[2]) : 4;
        if (particles < 64 || steps < 1 || iterations < 1 || iterations > 64)
        {
            Console.Error.WriteLine("usage: DamBreak [particles>=64] [steps>=1] [iterations 1..64]");
            return 2;
        }
        try
        {
            return Run(particles, steps, iterations);
        }
        catch (PbfException e)
        {
            Console.Error.WriteLine("dam_break: " + e.Message);
            return 1;
        }
    }

    static int Run(long particles, long steps, long iterations)
    {
        // Column a x 2a x a/2 at the left of a 4a x 2.5a x a/2 tank; spacing from the particle count.
        // Every float expression is rounded to float as C rounds it, so both samples build the same scene.
        const float a = 0.4f;
        float columnVolume = (float)((float)((float)((float)(a * 2.0f) * a) * 0.5f) * a);
        float spacing = (float)Math.Cbrt((float)(columnVolume / (float)particles));

        var desc = new WorldDesc();
        string backend = Environment.GetEnvironmentVariable("PBF_BACKEND");
        if (backend == "cpu") desc.Backend = Backend.Cpu;
        else if (backend == "cuda") desc.Backend = Backend.Cuda;
        else if (!string.IsNullOrEmpty(backend))
        {
            Console.Error.WriteLine("PBF_BACKEND must be cpu or cuda");
            return 2;
        }
        desc.MaxParticles = (int)(particles * 11 / 10 + 64);
        desc.ParticleRadius = (float)(0.5f * spacing);
        desc.DomainMin = new Vector3(0.0f, 0.0f, 0.0f);
        desc.DomainMax = new Vector3((float)(4.0f * a), (float)(2.5f * a), (float)(0.5f * a));
        desc.Solver.Iterations = (int)iterations;
        // Substeps keep the fastest particle (the front, about sqrt(2 g H)) under 0.4 h per substep.
        const float dt = 1.0f / 60.0f;
        float kernelRadius = (float)(2.0f * spacing);
        float frontSpeed = (float)Math.Sqrt((float)((float)((float)(2.0f * 9.81f) * 2.0f) * a));
        long substeps = (long)Math.Ceiling((float)((float)(frontSpeed * dt) / (float)(0.4f * kernelRadius)));
        string substepsEnv = Environment.GetEnvironmentVariable("PBF_SUBSTEPS");
        if (substepsEnv != null) substeps = ParseLong(substepsEnv);
        desc.Solver.Substeps = (int)(substeps < 1 ? 1 : substeps > 16 ? 16 : substeps);
        string ldc = Environment.GetEnvironmentVariable("PBF_LDC");
        if (!string.IsNullOrEmpty(ldc)) desc.Solver.LdcEnabled = ParseLong(ldc) != 0;

        using (World world = World.Create(desc))
        {
            WorldInfo info = world.Info;
            var block = new BlockDesc { BoxMax = new Vector3(a, (float)(2.0f * a), (float)(0.5f * a)) };
            int emitted = world.EmitBlock(block);
            Console.WriteLine("dam break: " + emitted + " particles, spacing " + F(spacing, 4) + " m, backend " +
                              BackendName(info.Backend) + " (" + info.DeviceName + "), " + steps + " steps of 1/60 s, " +
                              desc.Solver.Substeps + " substeps, " + iterations + " iterations, LDC " +
                              (desc.Solver.LdcEnabled ? "on" : "off"));

            double totalMs = 0.0;
            double errorSum = 0.0;
            StepStats stats = default(StepStats);
            for (long s = 1; s <= steps; ++s)
            {
                world.Step(dt);
                stats = world.Stats;
                totalMs += stats.StepTimeMs;
                errorSum += stats.DensityErrorMean;
                if (s % (steps >= 10 ? steps / 10 : 1) == 0 || s == steps)
                {
                    Console.WriteLine("  step " + s.ToString(C).PadLeft(5) + "  t=" + F((float)(s * dt), 2) + "s  particles " +
                                      stats.ParticleCount + "  density error mean " + F(stats.DensityErrorMean, 4) +
                                      " max " + F(stats.DensityErrorMax, 3) + "  KE " + F(stats.KineticEnergy, 3) +
                                      " J  " + F(stats.StepTimeMs, 2) + " ms/step");
                    Console.Out.Flush();
                    if (float.IsNaN(stats.KineticEnergy) || float.IsInfinity(stats.KineticEnergy))
                    {
                        Console.Error.WriteLine("dam_break: simulation diverged (kinetic energy not finite)");
                        return 1;
                    }
                }
            }

            Console.WriteLine();
            Console.WriteLine("| backend | device | particles | steps | iterations | LDC | ms/step | density error (mean over run) | " +
                              "density error max (last) | kinetic energy (J) |");
            Console.WriteLine("|---|---|---|---|---|---|---|---|---|---|");
            Console.WriteLine("| " + BackendName(info.Backend) + " | " + info.DeviceName + " | " + stats.ParticleCount + " | " + steps +
                              " | " + iterations + " | " + (desc.Solver.LdcEnabled ? "on" : "off") + " | " +
                              F(totalMs / steps, 3) + " | " + F(errorSum / steps, 5) + " | " + F(stats.DensityErrorMax, 4) +
                              " | " + F(stats.KineticEnergy, 4) + " |");
        }
        return 0;
    }
}
