// libpbf sample: a dam break in a tank, a nozzle pouring into it, and an optional sphere that
// follows a Transform and pushes the fluid. The world steps in FixedUpdate; every frame the
// positions are copied (no allocation) into a GraphicsBuffer and drawn as instanced spheres by
// the "Pbf/Particles" shader, coloured by density. With "Anisotropic" on (the default) the world
// also computes smoothed positions and anisotropy (Yu & Turk 2013), and each sphere is drawn as
// its particle's ellipsoid: flat along the surface, so the water reads as a surface, not beads.
//
// Setup: open FluidDemo.unity (beside this file) and press Play. Or add this component to any
// GameObject: it uses the assigned material, else one made from the Pbf/Particles shader
// (PbfParticles.shader beside this file). Optionally assign a Transform to "Pusher", and a
// MeshFilter to "Obstacle": its mesh becomes a static mesh collider where the GameObject stands.
using Pbf;
using Pbf.Unity;
using UnityEngine;
using PbfCollider = Pbf.Collider;  // UnityEngine has a Collider too
using Mesh = UnityEngine.Mesh;     // and Pbf has a Mesh too

public sealed class PbfFluidDemo : MonoBehaviour
{
    [Header("World")]
    public Backend backend = Backend.Auto;
    public int maxParticles = 32768;
    public float particleRadius = 0.025f;
    public Vector3 domainMin = new Vector3(-1.0f, 0.0f, -0.5f);
    public Vector3 domainMax = new Vector3(1.0f, 1.5f, 0.5f);
    [Tooltip("Substeps per step: 0 picks them automatically from the motion (the library's default), 1..64 fixes them.")]
    [Range(0, 64)] public int substeps = 0;
    [Range(1, 64)] public int iterations = 4;

    [Header("Scene")]
    public Vector3 blockMin = new Vector3(-1.0f, 0.0f, -0.5f);
    public Vector3 blockMax = new Vector3(-0.4f, 0.8f, 0.5f);
    public bool nozzle = true;
    [Tooltip("Toggle at run time to start and stop the nozzle.")]
    public bool nozzleEnabled = true;
    public Vector3 nozzlePosition = new Vector3(0.5f, 1.3f, 0.0f);
    public float nozzleSpeed = 2.0f;
    public float nozzleRadius = 0.1f;
    [Tooltip("Optional: a kinematic sphere collider follows this Transform (its scale.x is the diameter).")]
    public Transform pusher;
    [Tooltip("Optional: this MeshFilter's mesh (closed, e.g. a rock) becomes a static mesh collider at its Transform.")]
    public MeshFilter obstacle;

    [Header("Rendering")]
    public Material particleMaterial;
    [Tooltip("Defaults to Unity's built-in sphere.")]
    public Mesh particleMesh;
    [Tooltip("Draw each particle as its ellipsoid (smoothed position + anisotropy); fixed when the world is created.")]
    public bool anisotropic = true;

    World _world;
    Emitter _nozzle;
    PbfCollider _pusher;
    GraphicsBuffer _positionsBuffer;
    Vector4[] _positions;  // CPU staging copy, allocated once
    GraphicsBuffer _anisotropyBuffer;
    Vector4[] _anisotropy;  // 3 rows per particle: unit axis, radius (m)
    bool _anisotropic;
    int _count;
    bool _nozzleOn;
    MaterialPropertyBlock _props;

    static readonly int PositionsId = Shader.PropertyToID("_PbfPositions");
    static readonly int RadiusId = Shader.PropertyToID("_Radius");
    static readonly int AnisotropyId = Shader.PropertyToID("_PbfAnisotropy");
    static readonly int UseAnisotropyId = Shader.PropertyToID("_UseAnisotropy");

    void OnEnable()
    {
        PbfUnityLog.Install(LogLevel.Info);
        if (!Library.IsCompatible)
        {
            Debug.LogError("libpbf " + Library.VersionString(Library.Version) + " does not match the bindings' " +
                           Library.VersionString(Library.HeaderVersion));
            enabled = false;
            return;
        }

        var desc = new WorldDesc
        {
            Backend = backend,
            MaxParticles = maxParticles,
            ParticleRadius = particleRadius,
            DomainMin = domainMin.ToNumerics(),
            DomainMax = domainMax.ToNumerics(),
            Gravity = Physics.gravity.ToNumerics(),
        };
        desc.Solver.Substeps = substeps;
        desc.Solver.Iterations = iterations;
        _anisotropic = anisotropic;
        if (_anisotropic) desc.Render.Flags = RenderFlags.SmoothedPositions | RenderFlags.Anisotropy;
        try
        {
            _world = World.Create(desc);
            _world.EmitBlock(blockMin.ToNumerics(), blockMax.ToNumerics());
            if (nozzle)
            {
                // Emit at most the rest-density flux through the disc (speed · area / spacing³):
                // a higher rate packs particles closer than rest spacing and the jet bursts apart.
                float spacing = 2.0f * particleRadius;
                float rate = 0.8f * nozzleSpeed * Mathf.PI * nozzleRadius * nozzleRadius / (spacing * spacing * spacing);
                _nozzle = _world.CreateNozzle(nozzlePosition.ToNumerics(), new System.Numerics.Vector3(0, -1, 0),
                                              nozzleSpeed, nozzleRadius, rate);
                _nozzle.SetEnabled(nozzleEnabled);
                _nozzleOn = nozzleEnabled;
            }
            if (pusher != null)
                _pusher = _world.CreateCollider(ColliderDesc.Sphere(pusher.position.ToNumerics(), 0.5f * pusher.lossyScale.x,
                                                                    ColliderMotion.Kinematic));
            if (obstacle != null) AddObstacle(obstacle);
        }
        catch (PbfException e)
        {
            Debug.LogError("libpbf: " + e.Code + ": " + e.Message);
            enabled = false;
            return;
        }

        WorldInfo info = _world.Info;
        Debug.Log("libpbf " + Library.VersionString(Library.Version) + " on " + info.DeviceName + " (" + info.Backend + ")");

        _positions = new Vector4[maxParticles];
        _positionsBuffer = new GraphicsBuffer(GraphicsBuffer.Target.Structured, maxParticles, 16);
        // The shader declares the buffer either way; without anisotropy it holds one unused row.
        _anisotropy = new Vector4[_anisotropic ? 3 * maxParticles : 1];
        _anisotropyBuffer = new GraphicsBuffer(GraphicsBuffer.Target.Structured, _anisotropy.Length, 16);
        _props = new MaterialPropertyBlock();
        if (particleMaterial == null)
        {
            Shader shader = Shader.Find("Pbf/Particles");
            if (shader != null) particleMaterial = new Material(shader);
            else Debug.LogWarning("PbfFluidDemo: no material assigned and the Pbf/Particles shader is not loaded: nothing is drawn");
        }
        if (particleMesh == null)
        {
            GameObject sphere = GameObject.CreatePrimitive(PrimitiveType.Sphere);
            particleMesh = sphere.GetComponent<MeshFilter>().sharedMesh;
            Destroy(sphere);
        }
    }

    // The MeshFilter's mesh, scaled by its Transform, as a static mesh collider at its pose. Unity
    // winds front faces clockwise; libpbf wants them counter-clockwise seen from outside, so each
    // triangle's last two indices are swapped.
    void AddObstacle(MeshFilter filter)
    {
        Mesh m = filter.sharedMesh;
        Vector3 scale = filter.transform.lossyScale;
        Vector3[] v = m.vertices;
        var vertices = new System.Numerics.Vector3[v.Length];
        for (int k = 0; k < v.Length; ++k) vertices[k] = Vector3.Scale(v[k], scale).ToNumerics();
        int[] indices = m.triangles;
        for (int k = 0; k + 2 < indices.Length; k += 3)
        {
            int t = indices[k + 1];
            indices[k + 1] = indices[k + 2];
            indices[k + 2] = t;
        }
        Pbf.Mesh mesh = _world.CreateMesh(new MeshDesc(vertices, indices));
        _world.CreateCollider(ColliderDesc.FromMesh(mesh, filter.transform.position.ToNumerics(),
                                                    filter.transform.rotation.ToNumerics()));
    }

    void FixedUpdate()
    {
        if (_world == null) return;
        if (_nozzle != null && _nozzleOn != nozzleEnabled)
        {
            _nozzle.SetEnabled(nozzleEnabled);
            _nozzleOn = nozzleEnabled;
        }
        if (_pusher != null && pusher != null)
            _pusher.SetTargetPose(pusher.position.ToNumerics(), pusher.rotation.ToNumerics());
        _world.Step(Time.fixedDeltaTime);
    }

    void Update()
    {
        if (_world == null) return;
        // Copy the positions out (x, y, z, density ratio) and upload them: no allocation per frame.
        // Ellipsoids are centred on the smoothed positions, which belong with the anisotropy.
        _count = _anisotropic ? _world.CopySmoothedPositions(_positions) : _world.CopyPositions(_positions);
        if (_count == 0 || particleMaterial == null) return;
        _positionsBuffer.SetData(_positions, 0, 0, _count);
        if (_anisotropic)
        {
            int rows = 3 * _world.CopyAnisotropy(_anisotropy);
            _anisotropyBuffer.SetData(_anisotropy, 0, 0, rows);
        }

        _props.SetBuffer(PositionsId, _positionsBuffer);
        _props.SetBuffer(AnisotropyId, _anisotropyBuffer);
        _props.SetFloat(UseAnisotropyId, _anisotropic ? 1.0f : 0.0f);
        _props.SetFloat(RadiusId, particleRadius);
        var bounds = new Bounds(0.5f * (domainMin + domainMax), domainMax - domainMin);
        Graphics.DrawMeshInstancedProcedural(particleMesh, 0, particleMaterial, bounds, _count, _props);
    }

    void OnDisable()
    {
        if (_world != null) _world.Dispose();  // destroys its emitters and colliders too
        _world = null;
        _nozzle = null;
        _pusher = null;
        if (_positionsBuffer != null) _positionsBuffer.Release();
        _positionsBuffer = null;
        if (_anisotropyBuffer != null) _anisotropyBuffer.Release();
        _anisotropyBuffer = null;
        PbfUnityLog.Uninstall();
    }

    void OnDrawGizmosSelected()
    {
        Gizmos.color = Color.cyan;
        Gizmos.DrawWireCube(0.5f * (domainMin + domainMax), domainMax - domainMin);
    }
}
