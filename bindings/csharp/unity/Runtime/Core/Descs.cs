using System;
using System.Numerics;
using Pbf.Interop;

namespace Pbf
{
    internal static class Convert3
    {
        public static Float3 ToNative(Vector3 v) { return new Float3(v.X, v.Y, v.Z); }
        public static Vector3 FromNative(Float3 v) { return new Vector3(v.x, v.y, v.z); }
        public static Float4 ToNative(Quaternion q) { return new Float4(q.X, q.Y, q.Z, q.W); }
        public static Quaternion FromNative(Float4 q) { return new Quaternion(q.x, q.y, q.z, q.w); }
    }

    /// <summary>
    /// Solver parameters (pbf_solver_params). Start from <see cref="Default"/> or
    /// <see cref="World.GetSolverParams"/>, change what you need, pass it back: a value type, so
    /// nothing changes in a world until <see cref="World.SetSolverParams"/>. The library checks
    /// the ranges; an out-of-range value fails with <see cref="Result.InvalidArgument"/>.
    /// </summary>
    public struct SolverParams
    {
        pbf_solver_params _raw;

        /// <summary>Wraps a raw pbf_solver_params.</summary>
        public SolverParams(pbf_solver_params raw) { _raw = raw; }

        /// <summary>The library's defaults (pbf_solver_params_init).</summary>
        public static SolverParams Default
        {
            get
            {
                var p = new pbf_solver_params { struct_size = Native.SizeOf<pbf_solver_params>() };
                PbfException.Check(Native.pbf_solver_params_init(ref p, p.struct_size));
                return new SolverParams(p);
            }
        }

        /// <summary>The raw struct. default(SolverParams) has struct_size 0, which the library refuses.</summary>
        public pbf_solver_params ToNative() { return _raw; }

        /// <summary>Density-constraint iterations per substep, 1..64 (default 4).</summary>
        public int Iterations { get { return (int)_raw.iterations; } set { _raw.iterations = (uint)value; } }
        /// <summary>Substeps per <see cref="World.Step"/>. 0 (default): automatic, chosen per step
        /// (from the last finished step's fastest particle, read without waiting, the nozzles and the
        /// kinematic colliders) so that the fastest particle moves at most <see cref="SubstepTravel"/>·h
        /// per substep, gravity alone moves a resting one at most SubstepTravel·h/64, and a resting
        /// column as deep as the fluid's extent along gravity compresses at most ~10 % at its bottom,
        /// up to <see cref="MaxSubsteps"/>. 1..64: exactly that many.</summary>
        public int Substeps { get { return (int)_raw.substeps; } set { _raw.substeps = (uint)value; } }
        /// <summary>Constraint force mixing ε, relative to a rest particle's gradient norm; &gt; 0 (default 1).</summary>
        public float Relaxation { get { return _raw.relaxation; } set { _raw.relaxation = value; } }
        /// <summary>Tensile instability k of s_corr = -k (W(r)/W(Δq))^n, 0..1 (default 0.1).</summary>
        public float ScorrK { get { return _raw.scorr_k; } set { _raw.scorr_k = value; } }
        /// <summary>Exponent n of s_corr, 1..8 (default 4).</summary>
        public float ScorrN { get { return _raw.scorr_n; } set { _raw.scorr_n = value; } }
        /// <summary>Δq as a fraction of the kernel radius, in (0, 1) (default 0.2).</summary>
        public float ScorrDq { get { return _raw.scorr_dq; } set { _raw.scorr_dq = value; } }
        /// <summary>XSPH viscosity c per 1/60 s of simulated time, 0..1 (default 0.01): a substep of
        /// Δt applies 1 - (1 - c)^(60 Δt), so the smoothing does not depend on the substep count.</summary>
        public float XsphC { get { return _raw.xsph_c; } set { _raw.xsph_c = value; } }
        /// <summary>Vorticity confinement ε in m/s, 0..1 (default 0.0005).</summary>
        public float VorticityEpsilon { get { return _raw.vorticity_epsilon; } set { _raw.vorticity_epsilon = value; } }
        /// <summary>Local Density Calibration before the iterations (default on).</summary>
        public bool LdcEnabled { get { return _raw.ldc_enabled != 0; } set { _raw.ldc_enabled = value ? 1u : 0u; } }
        /// <summary>LDC strength as K·Δt² (Δt the substep), so K = LdcGain / (Δt² + τ²),
        /// τ = h / <see cref="SoundSpeed"/>; 0..1 (default 0.3). LDC acts on compression only.</summary>
        public float LdcGain { get { return _raw.ldc_gain; } set { _raw.ldc_gain = value; } }
        /// <summary>Particle speed limit in m/s, &gt; 0 (default 100). A substep also limits speed to
        /// h/Δt (no particle crosses more than h per substep); <see cref="StepStats.SpeedClamps"/>
        /// counts the particle-substeps either limit cut.</summary>
        public float MaxSpeed { get { return _raw.max_speed; } set { _raw.max_speed = value; } }
        /// <summary>0: fixed iterations. &gt; 0: stop a substep's iterations once the mean compressive density error is below this (iterations is the cap; at least one runs).</summary>
        public float AdaptiveErrorTarget { get { return _raw.adaptive_error_target; } set { _raw.adaptive_error_target = value; } }
        /// <summary>Cap of the automatic substep count, 1..64 (default 16). A step that would need more
        /// runs this many, and the h/Δt speed limit keeps every particle within h per substep
        /// (<see cref="StepStats.SpeedClamps"/> counts the cuts).</summary>
        public int MaxSubsteps { get { return (int)_raw.max_substeps; } set { _raw.max_substeps = (uint)value; } }
        /// <summary>Automatic substeps: the fastest particle's travel per substep, as a fraction of h,
        /// 0.05..1 (default 0.5).</summary>
        public float SubstepTravel { get { return _raw.substep_travel; } set { _raw.substep_travel = value; } }
        /// <summary>m/s, &gt;= 10 (default 40): the response speed of the density constraint to an
        /// error older than the substep. Such an error relaxes over τ = h / SoundSpeed rather than in
        /// one substep, so the velocity its removal creates stays near error · SoundSpeed whatever dt
        /// is; new compression is removed in full every substep.</summary>
        public float SoundSpeed { get { return _raw.sound_speed; } set { _raw.sound_speed = value; } }
    }

    /// <summary>
    /// Render data (pbf_render_params): smoothed positions and anisotropy after Yu &amp; Turk 2013,
    /// computed at the end of every step from the step's neighbour lists. Off by default (no
    /// buffers, no pass); fixed at world creation. Read them with
    /// <see cref="World.CopySmoothedPositions(float[])"/>, <see cref="World.CopyAnisotropy(float[])"/>,
    /// <see cref="DeviceBuffers"/> or GL / external buffers of source SmoothedPositions / Anisotropy.
    /// </summary>
    public struct RenderParams
    {
        pbf_render_params _raw;

        /// <summary>Wraps a raw pbf_render_params.</summary>
        public RenderParams(pbf_render_params raw) { _raw = raw; }

        /// <summary>The library's defaults (pbf_render_params_init): render data off.</summary>
        public static RenderParams Default
        {
            get
            {
                var p = new pbf_render_params { struct_size = Native.SizeOf<pbf_render_params>() };
                PbfException.Check(Native.pbf_render_params_init(ref p, p.struct_size));
                return new RenderParams(p);
            }
        }

        public pbf_render_params ToNative() { return _raw; }

        /// <summary>What the world computes (default None).</summary>
        public RenderFlags Flags { get { return (RenderFlags)_raw.flags; } set { _raw.flags = (uint)value; } }
        /// <summary>λ of the Laplacian smoothing, 0..1 (default 0.9): x̄ = (1 - λ) x + λ · the
        /// weighted mean of the neighbours within h. Surface particles move inward.</summary>
        public float Smoothing { get { return _raw.smoothing; } set { _raw.smoothing = value; } }
        /// <summary>k_r: longest over shortest radius at most this, 1..100 (default 4).</summary>
        public float MaxStretch { get { return _raw.max_stretch; } set { _raw.max_stretch = value; } }
        /// <summary>k_s: radius, in particle radii, of a particle with a rest-lattice neighbourhood;
        /// radii scale linearly with the covariance's eigenvalues. (0, 100] (default 1).</summary>
        public float Scale { get { return _raw.scale; } set { _raw.scale = value; } }
        /// <summary>k_n: radius, in particle radii, of a particle with fewer than
        /// <see cref="MinNeighbors"/> neighbours (a sphere), (0, 100] (default 0.5).</summary>
        public float IsolatedScale { get { return _raw.isolated_scale; } set { _raw.isolated_scale = value; } }
        /// <summary>N_ε: neighbours within h (itself included) below which a particle stays round,
        /// 0..1000 (default 6).</summary>
        public int MinNeighbors { get { return (int)_raw.min_neighbors; } set { _raw.min_neighbors = (uint)value; } }
    }

    /// <summary>
    /// Diffuse particles (pbf_diffuse_params): spray, foam and air bubbles after Ihmsen et al. 2012,
    /// generated where the fluid traps air, breaks at wave crests and moves fast. Off by default
    /// (<see cref="MaxDiffuse"/> 0: no buffers, no pass); the capacity is fixed at creation, the
    /// rest can change between steps (<see cref="World.SetDiffuseParams"/>). Read them with
    /// <see cref="World.CopyDiffusePositions(float[])"/>, <see cref="DeviceBuffers"/> or GL /
    /// external buffers of source DiffusePositions / DiffuseVelocities.
    /// </summary>
    public struct DiffuseParams
    {
        pbf_diffuse_params _raw;

        /// <summary>Wraps a raw pbf_diffuse_params.</summary>
        public DiffuseParams(pbf_diffuse_params raw) { _raw = raw; }

        /// <summary>The library's defaults (pbf_diffuse_params_init): diffuse particles off.</summary>
        public static DiffuseParams Default
        {
            get
            {
                var p = new pbf_diffuse_params { struct_size = Native.SizeOf<pbf_diffuse_params>() };
                PbfException.Check(Native.pbf_diffuse_params_init(ref p, p.struct_size));
                return new DiffuseParams(p);
            }
        }

        public pbf_diffuse_params ToNative() { return _raw; }

        /// <summary>Capacity, 0..2^26, fixed at creation (default 0: off); 64 bytes each.</summary>
        public int MaxDiffuse { get { return (int)_raw.max_diffuse; } set { _raw.max_diffuse = (uint)value; } }
        /// <summary>τ_ta: trapped-air potential (m/s) where generation starts (default 2).</summary>
        public float TrappedAirMin { get { return _raw.trapped_air_min; } set { _raw.trapped_air_min = value; } }
        /// <summary>τ_ta: where it saturates (default 8).</summary>
        public float TrappedAirMax { get { return _raw.trapped_air_max; } set { _raw.trapped_air_max = value; } }
        /// <summary>τ_wc: wave-crest potential where generation starts (default 1).</summary>
        public float WaveCrestMin { get { return _raw.wave_crest_min; } set { _raw.wave_crest_min = value; } }
        /// <summary>τ_wc: where it saturates (default 4).</summary>
        public float WaveCrestMax { get { return _raw.wave_crest_max; } set { _raw.wave_crest_max = value; } }
        /// <summary>τ_k: kinetic energy per unit mass ½|v|² (J/kg) where generation starts (default 0.5).</summary>
        public float EnergyMin { get { return _raw.energy_min; } set { _raw.energy_min = value; } }
        /// <summary>τ_k: where it saturates (default 4).</summary>
        public float EnergyMax { get { return _raw.energy_max; } set { _raw.energy_max = value; } }
        /// <summary>k_ta: diffuse particles per second per fluid particle at full trapped-air and
        /// energy potentials, 0..1e4 (default 200).</summary>
        public float TrappedAirRate { get { return _raw.trapped_air_rate; } set { _raw.trapped_air_rate = value; } }
        /// <summary>k_wc: the same for wave crests, 0..1e4 (default 200).</summary>
        public float WaveCrestRate { get { return _raw.wave_crest_rate; } set { _raw.wave_crest_rate = value; } }
        /// <summary>s, (0, 1e4]: foam and spray live (0.5..1) times this (default 2).</summary>
        public float Lifetime { get { return _raw.lifetime; } set { _raw.lifetime = value; } }
        /// <summary>Fewer fluid neighbours within h: spray (default 6).</summary>
        public int SprayMaxNeighbors { get { return (int)_raw.spray_max_neighbors; } set { _raw.spray_max_neighbors = (uint)value; } }
        /// <summary>More: a bubble; between: foam (default 20).</summary>
        public int BubbleMinNeighbors { get { return (int)_raw.bubble_min_neighbors; } set { _raw.bubble_min_neighbors = (uint)value; } }
        /// <summary>k_b: a bubble accelerates by -k_b·gravity, 0..100 (default 0.5).</summary>
        public float Buoyancy { get { return _raw.buoyancy; } set { _raw.buoyancy = value; } }
        /// <summary>k_d (1/s): a bubble's velocity relaxes toward the fluid's at this rate (default 20).</summary>
        public float BubbleDrag { get { return _raw.bubble_drag; } set { _raw.bubble_drag = value; } }
        /// <summary>Linear air drag on spray (1/s) (default 0.5).</summary>
        public float SprayDrag { get { return _raw.spray_drag; } set { _raw.spray_drag = value; } }
    }

    /// <summary>How to create a <see cref="World"/> (pbf_world_desc). A new WorldDesc holds the
    /// library's defaults: AUTO backend, 65536 particles of radius 0.025 m, water density,
    /// gravity -9.81 on y, domain (-1,0,-1)..(1,2,1).</summary>
    public sealed class WorldDesc
    {
        pbf_world_desc _raw;
        SolverParams _solver;
        RenderParams _render;
        DiffuseParams _diffuse;

        public WorldDesc()
        {
            _raw.struct_size = Native.SizeOf<pbf_world_desc>();
            PbfException.Check(Native.pbf_world_desc_init(ref _raw, _raw.struct_size, Native.PBF_VERSION));
            _solver = new SolverParams(_raw.solver);
            _render = new RenderParams(_raw.render);
            _diffuse = new DiffuseParams(_raw.diffuse);
        }

        /// <summary>The raw desc to pass to pbf_world_create (with <see cref="Solver"/> in it).</summary>
        public pbf_world_desc ToNative()
        {
            pbf_world_desc d = _raw;
            d.solver = _solver.ToNative();
            d.render = _render.ToNative();
            d.diffuse = _diffuse.ToNative();
            return d;
        }

        /// <summary>Default Auto: CUDA when built in and a device exists, else CPU.</summary>
        public Backend Backend { get { return (Backend)_raw.backend; } set { _raw.backend = (pbf_backend)value; } }
        /// <summary>CUDA device ordinal (default 0).</summary>
        public int CudaDevice { get { return _raw.cuda_device; } set { _raw.cuda_device = value; } }
        /// <summary>Capacity, fixed for the world's life (default 65536).</summary>
        public int MaxParticles { get { return (int)_raw.max_particles; } set { _raw.max_particles = (uint)value; } }
        /// <summary>Collider capacity, 1..2048, allocated up front (default 256).</summary>
        public int MaxColliders { get { return (int)_raw.max_colliders; } set { _raw.max_colliders = (uint)value; } }
        /// <summary>Rest spacing is 2·radius, kernel radius 4·radius (default 0.025 m).</summary>
        public float ParticleRadius { get { return _raw.particle_radius; } set { _raw.particle_radius = value; } }
        /// <summary>kg/m³ (default 1000).</summary>
        public float RestDensity { get { return _raw.rest_density; } set { _raw.rest_density = value; } }
        /// <summary>m/s² (default 0, -9.81, 0).</summary>
        public Vector3 Gravity { get { return Convert3.FromNative(_raw.gravity); } set { _raw.gravity = Convert3.ToNative(value); } }
        /// <summary>The walls: an axis-aligned box that contains all particles (default -1,0,-1).</summary>
        public Vector3 DomainMin { get { return Convert3.FromNative(_raw.domain_min); } set { _raw.domain_min = Convert3.ToNative(value); } }
        /// <summary>(default 1,2,1)</summary>
        public Vector3 DomainMax { get { return Convert3.FromNative(_raw.domain_max); } set { _raw.domain_max = Convert3.ToNative(value); } }
        /// <summary>The solver parameters, editable in place: desc.Solver.Iterations = 8.</summary>
        public ref SolverParams Solver { get { return ref _solver; } }
        /// <summary>Render data, editable in place: desc.Render.Flags = RenderFlags.Anisotropy.</summary>
        public ref RenderParams Render { get { return ref _render; } }
        /// <summary>Diffuse particles, editable in place: desc.Diffuse.MaxDiffuse = 100000.</summary>
        public ref DiffuseParams Diffuse { get { return ref _diffuse; } }
        /// <summary>true (default): the six walls of DomainMin..DomainMax hold the fluid. false: an
        /// open level without walls or box (DomainMin/Max ignored, a hashed grid whose memory follows
        /// MaxParticles); particle centres stay within 2^17·h of the origin on each axis.</summary>
        public bool Walls { get { return _raw.walls != 0; } set { _raw.walls = value ? 1u : 0u; } }
        /// <summary>false (default): a dense grid over the walls' box while it has at most 4 cells per
        /// key of the hashed grid, else hashed. true: always hashed.</summary>
        public bool HashedGrid { get { return _raw.hashed_grid != 0; } set { _raw.hashed_grid = value ? 1u : 0u; } }
    }

    /// <summary>A one-shot fill of an axis-aligned box on a cubic lattice at rest spacing (pbf_block_desc).</summary>
    public sealed class BlockDesc
    {
        pbf_block_desc _raw;

        public BlockDesc()
        {
            _raw.struct_size = Native.SizeOf<pbf_block_desc>();
            PbfException.Check(Native.pbf_block_desc_init(ref _raw, _raw.struct_size));
        }

        public BlockDesc(Vector3 boxMin, Vector3 boxMax) : this()
        {
            BoxMin = boxMin;
            BoxMax = boxMax;
        }

        public pbf_block_desc ToNative() { return _raw; }

        public Vector3 BoxMin { get { return Convert3.FromNative(_raw.box_min); } set { _raw.box_min = Convert3.ToNative(value); } }
        public Vector3 BoxMax { get { return Convert3.FromNative(_raw.box_max); } set { _raw.box_max = Convert3.ToNative(value); } }
        /// <summary>Initial velocity (default 0).</summary>
        public Vector3 Velocity { get { return Convert3.FromNative(_raw.velocity); } set { _raw.velocity = Convert3.ToNative(value); } }
        /// <summary>The particles' material (default null: the world's default material).</summary>
        public Material Material { get { return _material; } set { _material = value; _raw.material = Material.NativeId(value); } }
        Material _material;
    }

    /// <summary>A nozzle or a drain (pbf_emitter_desc). Use <see cref="Nozzle"/> or <see cref="Drain"/>.</summary>
    public sealed class EmitterDesc
    {
        pbf_emitter_desc _raw;

        public EmitterDesc(EmitterType type)
        {
            _raw.struct_size = Native.SizeOf<pbf_emitter_desc>();
            PbfException.Check(Native.pbf_emitter_desc_init(ref _raw, _raw.struct_size));
            _raw.type = (pbf_emitter_type)type;
        }

        /// <summary>A nozzle emitting particlesPerSecond through a disc of the given radius at
        /// position, moving at speed along direction (normalised by the library).</summary>
        public static EmitterDesc Nozzle(Vector3 position, Vector3 direction, float speed, float radius, float particlesPerSecond)
        {
            return new EmitterDesc(EmitterType.Nozzle)
            {
                Position = position,
                Direction = direction,
                Speed = speed,
                Radius = radius,
                ParticlesPerSecond = particlesPerSecond,
            };
        }

        /// <summary>A drain removing the particles inside boxMin..boxMax at each step.</summary>
        public static EmitterDesc Drain(Vector3 boxMin, Vector3 boxMax)
        {
            return new EmitterDesc(EmitterType.Drain) { BoxMin = boxMin, BoxMax = boxMax };
        }

        public pbf_emitter_desc ToNative() { return _raw; }

        public EmitterType Type { get { return (EmitterType)_raw.type; } set { _raw.type = (pbf_emitter_type)value; } }
        /// <summary>Default true.</summary>
        public bool Enabled { get { return _raw.enabled != 0; } set { _raw.enabled = value ? 1u : 0u; } }
        /// <summary>Nozzle: disc centre.</summary>
        public Vector3 Position { get { return Convert3.FromNative(_raw.position); } set { _raw.position = Convert3.ToNative(value); } }
        /// <summary>Nozzle: direction (default 0,-1,0).</summary>
        public Vector3 Direction { get { return Convert3.FromNative(_raw.direction); } set { _raw.direction = Convert3.ToNative(value); } }
        /// <summary>Nozzle: m/s, &gt; 0.</summary>
        public float Speed { get { return _raw.speed; } set { _raw.speed = value; } }
        /// <summary>Nozzle: disc radius in m, &gt; 0.</summary>
        public float Radius { get { return _raw.radius; } set { _raw.radius = value; } }
        /// <summary>Nozzle: &gt; 0.</summary>
        public float ParticlesPerSecond { get { return _raw.particles_per_second; } set { _raw.particles_per_second = value; } }
        /// <summary>Drain volume.</summary>
        public Vector3 BoxMin { get { return Convert3.FromNative(_raw.box_min); } set { _raw.box_min = Convert3.ToNative(value); } }
        public Vector3 BoxMax { get { return Convert3.FromNative(_raw.box_max); } set { _raw.box_max = Convert3.ToNative(value); } }
        /// <summary>Nozzle: the particles' material (default null: the world's default material).</summary>
        public Material Material { get { return _material; } set { _material = value; _raw.material = Material.NativeId(value); } }
        Material _material;
    }

    /// <summary>A fluid material (pbf_material_desc): README, "Materials".</summary>
    public sealed class MaterialDesc
    {
        pbf_material_desc _raw;

        public MaterialDesc()
        {
            _raw.struct_size = Native.SizeOf<pbf_material_desc>();
            PbfException.Check(Native.pbf_material_desc_init(ref _raw, _raw.struct_size));
        }

        internal MaterialDesc(pbf_material_desc raw) { _raw = raw; }

        public pbf_material_desc ToNative() { return _raw; }

        /// <summary>kg/m³, 0.1..10 times the world's rest density (default 1000).</summary>
        public float RestDensity { get { return _raw.rest_density; } set { _raw.rest_density = value; } }
        /// <summary>XSPH c per 1/60 s, 0..1 (default 0.01).</summary>
        public float Viscosity { get { return _raw.viscosity; } set { _raw.viscosity = value; } }
        /// <summary>LDC strength, 0..1 (default 0.3).</summary>
        public float LdcGain { get { return _raw.ldc_gain; } set { _raw.ldc_gain = value; } }
        /// <summary>1/s², 0..10000 (default 0: off).</summary>
        public float SurfaceTension { get { return _raw.surface_tension; } set { _raw.surface_tension = value; } }
        /// <summary>1/s², 0..10000 (default 0: off).</summary>
        public float Cohesion { get { return _raw.cohesion; } set { _raw.cohesion = value; } }
        /// <summary>1/s², 0..10000 (default 0: off): pull towards walls and colliders.</summary>
        public float Adhesion { get { return _raw.adhesion; } set { _raw.adhesion = value; } }
        /// <summary>RGBA 0..1 for renderers (default 0.2, 0.45, 0.9, 1).</summary>
        public Vector4 Color
        {
            get { return new Vector4(_raw.color.x, _raw.color.y, _raw.color.z, _raw.color.w); }
            set { _raw.color = new Float4(value.X, value.Y, value.Z, value.W); }
        }
        /// <summary>Any value, for the engine (default 0).</summary>
        public uint UserId { get { return _raw.user_id; } set { _raw.user_id = value; } }
    }

    /// <summary>A collider (pbf_collider_desc). Use the factories, or set Shape and its fields.</summary>
    public sealed class ColliderDesc
    {
        pbf_collider_desc _raw;

        public ColliderDesc(ColliderShape shape)
        {
            _raw.struct_size = Native.SizeOf<pbf_collider_desc>();
            PbfException.Check(Native.pbf_collider_desc_init(ref _raw, _raw.struct_size));
            _raw.shape = (pbf_collider_shape)shape;
        }

        public static ColliderDesc Sphere(Vector3 center, float radius, ColliderMotion motion = ColliderMotion.Static)
        {
            return new ColliderDesc(ColliderShape.Sphere) { Position = center, Radius = radius, Motion = motion };
        }

        /// <summary>A capsule of the given radius around the segment from -halfHeight to
        /// +halfHeight along the rotated y axis.</summary>
        public static ColliderDesc Capsule(Vector3 center, Quaternion rotation, float radius, float halfHeight,
                                           ColliderMotion motion = ColliderMotion.Static)
        {
            return new ColliderDesc(ColliderShape.Capsule)
            {
                Position = center, Rotation = rotation, Radius = radius, HalfHeight = halfHeight, Motion = motion,
            };
        }

        public static ColliderDesc Box(Vector3 center, Quaternion rotation, Vector3 halfExtents,
                                       ColliderMotion motion = ColliderMotion.Static)
        {
            return new ColliderDesc(ColliderShape.Box)
            {
                Position = center, Rotation = rotation, HalfExtents = halfExtents, Motion = motion,
            };
        }

        /// <summary>The triangle mesh <paramref name="mesh"/> of the same world, placed by the pose
        /// (any number of colliders may share a mesh).</summary>
        public static ColliderDesc FromMesh(Mesh mesh, Vector3 position, Quaternion rotation,
                                            ColliderMotion motion = ColliderMotion.Static)
        {
            if (mesh == null) throw new ArgumentNullException("mesh");
            var d = new ColliderDesc(ColliderShape.Mesh) { Position = position, Rotation = rotation, Motion = motion };
            d._raw.mesh = mesh.Id;
            return d;
        }

        /// <summary>The half-space below the plane through point with the given normal is solid.</summary>
        public static ColliderDesc Plane(Vector3 point, Vector3 normal, ColliderMotion motion = ColliderMotion.Static)
        {
            return new ColliderDesc(ColliderShape.Plane) { Position = point, Rotation = FromUp(normal), Motion = motion };
        }

        /// <summary>The rotation that takes (0,1,0) to direction (normalised).</summary>
        public static Quaternion FromUp(Vector3 direction)
        {
            float len = direction.Length();
            if (!(len > 0.0f)) return Quaternion.Identity;  // zero or NaN: let the library judge the rest
            Vector3 d = direction / len;
            Vector3 up = Vector3.UnitY;
            float c = Vector3.Dot(up, d);
            if (c < -0.999999f) return new Quaternion(1.0f, 0.0f, 0.0f, 0.0f);  // half turn about x
            Vector3 axis = Vector3.Cross(up, d);
            return Quaternion.Normalize(new Quaternion(axis.X, axis.Y, axis.Z, 1.0f + c));
        }

        public pbf_collider_desc ToNative() { return _raw; }

        public ColliderShape Shape { get { return (ColliderShape)_raw.shape; } set { _raw.shape = (pbf_collider_shape)value; } }
        /// <summary>Default Static.</summary>
        public ColliderMotion Motion { get { return (ColliderMotion)_raw.motion; } set { _raw.motion = (pbf_collider_motion)value; } }
        public Vector3 Position { get { return Convert3.FromNative(_raw.position); } set { _raw.position = Convert3.ToNative(value); } }
        /// <summary>Unit quaternion, normalised by the library (default identity).</summary>
        public Quaternion Rotation { get { return Convert3.FromNative(_raw.rotation); } set { _raw.rotation = Convert3.ToNative(value); } }
        /// <summary>Sphere, capsule.</summary>
        public float Radius { get { return _raw.radius; } set { _raw.radius = value; } }
        /// <summary>Capsule.</summary>
        public float HalfHeight { get { return _raw.half_height; } set { _raw.half_height = value; } }
        /// <summary>Box.</summary>
        public Vector3 HalfExtents { get { return Convert3.FromNative(_raw.half_extents); } set { _raw.half_extents = Convert3.ToNative(value); } }
        /// <summary>Coulomb friction coefficient μ, 0..1 (default 0, slip): on contact the tangential
        /// motion relative to the collider is removed up to μ times the depth the contact pushed the
        /// particle out.</summary>
        public float Friction { get { return _raw.friction; } set { _raw.friction = value; } }
        /// <summary>Default false. True: the library records the force and torque the fluid exerts
        /// on the collider each step (<see cref="Collider.GetForce"/>); the engine integrates its
        /// body and moves it (Kinematic, <see cref="Collider.SetTargetPose"/>). Buoyancy is within 3 %
        /// with the body at least 12 particle diameters across and the density held near rest
        /// (<see cref="SolverParams.AdaptiveErrorTarget"/> 0.003; README, Physics, Two-way coupling).</summary>
        public bool Dynamic { get { return _raw.dynamic != 0; } set { _raw.dynamic = value ? 1u : 0u; } }
        /// <summary>Dynamic: the point torques are taken about, in the collider's own frame (default 0).</summary>
        public Vector3 CenterOfMass { get { return Convert3.FromNative(_raw.center_of_mass); } set { _raw.center_of_mass = Convert3.ToNative(value); } }
    }

    /// <summary>The force table of <see cref="World.MapColliderForces"/>.</summary>
    public struct ColliderForceTable
    {
        public readonly MemoryKind Memory;
        public readonly IntPtr Data;
        public readonly int Count;
        public readonly int StrideBytes;
        public ColliderForceTable(MemoryKind memory, IntPtr data, int count, int strideBytes)
        {
            Memory = memory;
            Data = data;
            Count = count;
            StrideBytes = strideBytes;
        }

        /// <summary>Row k, read from host memory (MemoryKind.Host only).</summary>
        public ColliderForce Read(int row)
        {
            if (Memory != MemoryKind.Host) throw new InvalidOperationException("the table is in device memory");
            if (row < 0 || row >= Count) throw new ArgumentOutOfRangeException("row");
            var raw = (pbf_collider_force)System.Runtime.InteropServices.Marshal.PtrToStructure(
                new IntPtr(Data.ToInt64() + (long)row * StrideBytes), typeof(pbf_collider_force));
            return new ColliderForce(raw);
        }
    }

    /// <summary>The fluid's push on a dynamic collider over the last step (pbf_collider_force): the
    /// mean force (N) and the torque about its CenterOfMass (N·m).</summary>
    public struct ColliderForce
    {
        public Vector3 Force;
        public Vector3 Torque;
        public ColliderForce(pbf_collider_force raw)
        {
            Force = Convert3.FromNative(raw.force);
            Torque = Convert3.FromNative(raw.torque);
        }
    }

    /// <summary>Statistics of the last step (pbf_step_stats); all zero before the first.</summary>
    public struct StepStats
    {
        readonly pbf_step_stats _raw;
        public StepStats(pbf_step_stats raw) { _raw = raw; }
        public pbf_step_stats ToNative() { return _raw; }

        public int ParticleCount { get { return (int)_raw.particle_count; } }
        /// <summary>Steps taken so far.</summary>
        public long StepIndex { get { return (long)_raw.step_index; } }
        /// <summary>Particles ever emitted (blocks and nozzles).</summary>
        public long EmittedTotal { get { return (long)_raw.emitted_total; } }
        /// <summary>Particles ever removed by drains.</summary>
        public long DrainedTotal { get { return (long)_raw.drained_total; } }
        /// <summary>Mean over particles of max(ρ/ρ0 - 1, 0) after the step.</summary>
        public float DensityErrorMean { get { return _raw.density_error_mean; } }
        public float DensityErrorMax { get { return _raw.density_error_max; } }
        /// <summary>Σ ½ m v², joules.</summary>
        public float KineticEnergy { get { return _raw.kinetic_energy; } }
        /// <summary>The last step's duration on its backend.</summary>
        public float StepTimeMs { get { return _raw.step_time_ms; } }
        /// <summary>Constraint iterations run in the last step, all substeps.</summary>
        public int Iterations { get { return (int)_raw.iterations; } }
        /// <summary>Substeps the last step ran.</summary>
        public int Substeps { get { return (int)_raw.substeps; } }
        /// <summary>Particle-substeps of the last step whose speed a limit cut (max_speed, or the
        /// h-per-substep cap); 0 in a healthy run.</summary>
        public long SpeedClamps { get { return _raw.speed_clamps; } }
        /// <summary>Seconds the last step advanced the world: its dt, unless the step was longer than
        /// MaxSubsteps substeps hold (a hitch), when the rest was dropped; 0 for a step shorter than
        /// Native.PBF_MIN_STEP_DT (1e-4 s), whose dt the next step simulates (and adds here).</summary>
        public float SimulatedDt { get { return _raw.simulated_dt; } }
        /// <summary>Live diffuse particles.</summary>
        public int DiffuseCount { get { return (int)_raw.diffuse_count; } }
        /// <summary>Diffuse particles generated in the last step but dropped: the capacity was full.</summary>
        public int DiffuseDropped { get { return (int)_raw.diffuse_dropped; } }
        /// <summary>Diffuse particles ever generated (added ones excluded).</summary>
        public long DiffuseGeneratedTotal { get { return (long)_raw.diffuse_generated_total; } }
        /// <summary>Generated but dropped for capacity, ever.</summary>
        public long DiffuseDroppedTotal { get { return (long)_raw.diffuse_dropped_total; } }
    }

    /// <summary>What a world is and where it runs (pbf_world_info).</summary>
    public struct WorldInfo
    {
        readonly pbf_world_info _raw;
        readonly string _deviceName;
        public WorldInfo(pbf_world_info raw)
        {
            _raw = raw;
            _deviceName = raw.device_name.ToString();
        }
        public pbf_world_info ToNative() { return _raw; }

        /// <summary>The backend in use (never Auto).</summary>
        public Backend Backend { get { return (Backend)_raw.backend; } }
        public int MaxParticles { get { return (int)_raw.max_particles; } }
        public float ParticleRadius { get { return _raw.particle_radius; } }
        /// <summary>2·radius.</summary>
        public float RestSpacing { get { return _raw.rest_spacing; } }
        /// <summary>h = 4·radius.</summary>
        public float KernelRadius { get { return _raw.kernel_radius; } }
        /// <summary>Calibrated so a rest lattice has the rest density.</summary>
        public float ParticleMass { get { return _raw.particle_mass; } }
        /// <summary>Keys of the neighbour grid (cell size h): the domain's cells, or the hashed grid's.</summary>
        public long GridCells { get { return _raw.grid_cells; } }
        /// <summary>true: the hashed grid (open levels, big boxes); false: dense over the domain.</summary>
        public bool GridHashed { get { return _raw.grid_hashed != 0; } }
        /// <summary>Part of <see cref="DeviceBytes"/> the grid's cell table takes (4 B a key).</summary>
        public long GridBytes { get { return (long)_raw.grid_bytes; } }
        /// <summary>Memory the world allocated on its backend.</summary>
        public long DeviceBytes { get { return (long)_raw.device_bytes; } }
        /// <summary>e.g. "NVIDIA H100 80GB HBM3" or "CPU (8 threads)".</summary>
        public string DeviceName { get { return _deviceName ?? string.Empty; } }
        /// <summary>The render data the world computes.</summary>
        public RenderFlags RenderFlags { get { return (RenderFlags)_raw.render_flags; } }
        /// <summary>Part of <see cref="DeviceBytes"/> the render data takes (0 when off).</summary>
        public long RenderBytes { get { return (long)_raw.render_bytes; } }
        /// <summary>Render passes run so far (one per step and per block emission when on; 0 when off).</summary>
        public long RenderUpdates { get { return (long)_raw.render_updates; } }
        /// <summary>The diffuse capacity (desc.Diffuse.MaxDiffuse).</summary>
        public int DiffuseCapacity { get { return (int)_raw.diffuse_capacity; } }
        /// <summary>Part of <see cref="DeviceBytes"/> the diffuse particles take (0 when off).</summary>
        public long DiffuseBytes { get { return (long)_raw.diffuse_bytes; } }
        /// <summary>Diffuse passes run so far (one per step when on; 0 when off).</summary>
        public long DiffuseUpdates { get { return (long)_raw.diffuse_updates; } }
    }

    /// <summary>Whether a backend can run on this machine, and if not, why (pbf_backend_info,
    /// from <see cref="Library.GetBackendInfo"/>).</summary>
    public struct BackendInfo
    {
        readonly pbf_backend_info _raw;
        readonly string _deviceName;
        readonly string _message;

        public BackendInfo(pbf_backend_info raw)
        {
            _raw = raw;
            _deviceName = raw.device_name.ToString();
            _message = raw.message.ToString();
        }

        public pbf_backend_info ToNative() { return _raw; }

        /// <summary>The backend described: Cpu or Cuda; for Auto, the one a world created with
        /// Auto on that device gets (never Auto).</summary>
        public Backend Backend { get { return (Backend)_raw.backend; } }
        /// <summary>Available, or why <see cref="Backend"/> cannot run here.</summary>
        public BackendStatus Status { get { return (BackendStatus)_raw.status; } }
        public bool IsAvailable { get { return Status == BackendStatus.Available; } }
        /// <summary>The CUDA device described; -1 for the CPU.</summary>
        public int CudaDevice { get { return _raw.cuda_device; } }
        /// <summary>CUDA devices the driver reports (0 without a driver).</summary>
        public int DeviceCount { get { return _raw.device_count; } }
        /// <summary>The driver's CUDA version, 1000·major + 10·minor (13000 for 13.0; 0 without a
        /// driver).</summary>
        public int DriverVersion { get { return _raw.driver_version; } }
        /// <summary>The least driver version the kernels need (0 in a build without CUDA).</summary>
        public int RequiredDriverVersion { get { return _raw.required_driver_version; } }
        /// <summary>e.g. "NVIDIA GeForce RTX 4070" or "CPU (8 threads)"; "" where there is no such device.</summary>
        public string DeviceName { get { return _deviceName ?? string.Empty; } }
        /// <summary>Why the backend is unavailable (for Auto on the CPU: why CUDA was not taken,
        /// starting "CUDA not taken: "), or what was found.</summary>
        public string Message { get { return _message ?? string.Empty; } }

        /// <summary>"13.0" for 13000 (a driver version as the CUDA driver API reports it).</summary>
        public static string VersionString(int driverVersion)
        {
            return (driverVersion / 1000) + "." + (driverVersion % 1000 / 10);
        }

        public override string ToString() { return Backend + " (" + Status + "): " + Message; }
    }
}
