// Two-way coupling through the C# bindings, the engine's loop of samples/floating_box.c: a crate of
// 500 kg/m^3 dropped into a pool. After each step the program reads the force the water exerted on
// the crate (Collider.GetForce), integrates the crate's body and sets its next pose
// (Collider.SetTargetPose) -- what the Unity package's PbfFloatingBody does with a Rigidbody in
// FixedUpdate (there the body also turns, and the force and torque are averaged over the last
// steps with Pbf.SmoothedForce, without which a light body free to turn is flung about).
//
//   mono FloatingBox.exe [steps=300]          (or samples/csharp/run.sh --floating-box [steps])
//   PBF_BACKEND=cpu|cuda overrides the backend.
// Prints the crate's height and the force every 30 steps; exits non-zero on any libpbf error.
using System;
using System.Globalization;
using System.Numerics;
using Pbf;

public static class FloatingBox
{
    static readonly CultureInfo C = CultureInfo.InvariantCulture;

    public static int Main(string[] args)
    {
        long steps = 300;
        if (args.Length > 0 && (!long.TryParse(args[0], NumberStyles.Integer, C, out steps) || steps < 1))
        {
            Console.Error.WriteLine("usage: FloatingBox [steps>=1]");
            return 2;
        }
        try
        {
            return Run(steps);
        }
        catch (PbfException e)
        {
            Console.Error.WriteLine("floating_box: " + e.Message);
            return 1;
        }
    }

    static int Run(long steps)
    {
        const float dt = 1.0f / 60.0f, g = 9.81f;
        var desc = new WorldDesc
        {
            ParticleRadius = 0.02f,
            MaxParticles = 16384,
            MaxColliders = 8,
            DomainMin = new Vector3(0.0f, 0.0f, 0.0f),
            DomainMax = new Vector3(0.72f, 0.8f, 0.72f),
        };
        string backend = Environment.GetEnvironmentVariable("PBF_BACKEND");
        if (backend == "cpu") desc.Backend = Backend.Cpu;
        else if (backend == "cuda") desc.Backend = Backend.Cuda;

        using (World world = World.Create(desc))
        {
            // A pool 0.36 m deep.
            world.EmitBlock(new Vector3(0.0f, 0.0f, 0.0f), new Vector3(0.72f, 0.36f, 0.72f));

            // The crate: a 0.24 m cube just above the water, moved by this program (kinematic) and
            // told the water's force (dynamic).
            const float half = 0.12f, density = 500.0f;
            float mass = density * 8.0f * half * half * half;
            float y = 0.37f + half, vy = 0.0f;
            var crateDesc = ColliderDesc.Box(new Vector3(0.36f, y, 0.36f), Quaternion.Identity,
                                             new Vector3(half, half, half), ColliderMotion.Kinematic);
            crateDesc.Dynamic = true;
            Collider crate = world.CreateCollider(crateDesc);

            // Step the water, read the force of that step (this waits for it), integrate the body
            // (semi-implicit Euler, vertical motion only here), set its next pose.
            for (long step = 0; step < steps; ++step)
            {
                world.Step(dt);
                ColliderForce f = crate.GetForce();
                vy += (f.Force.Y / mass - g) * dt;
                y += vy * dt;
                crate.SetTargetPose(new Vector3(0.36f, y, 0.36f), Quaternion.Identity);
                if (step % 30 == 29)
                    Console.WriteLine(string.Format(C, "t {0:F2} s  crate bottom {1:F3} m  water force {2:F1} N (weight {3:F1} N)",
                                                    (step + 1) * dt, y - half, f.Force.Y, mass * g));
            }
        }
        return 0;
    }
}
