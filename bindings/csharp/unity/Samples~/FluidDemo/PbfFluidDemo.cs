// libpbf sample: a dam break of water in a tank, a block of oil (a second fluid material, half
// as dense) that the water runs under and that rises to float on it, a nozzle pouring into the
// tank, a rock (a mesh collider made from a Unity mesh) in the water's way, a crate that floats
// (a Unity Rigidbody coupled both ways by PbfFloatingBody), and an optional sphere that follows a
// Transform and pushes the fluid. The world steps in FixedUpdate; every frame the particles go into
// GraphicsBuffers and are drawn as instanced spheres by the "Pbf/Particles" shader, each in its
// material's colour, brighter where compressed. Under Direct3D 11 with a CUDA world they go there
// without leaving the GPU (zero-copy: the render event, on the render thread, copies them from
// CUDA into the buffers and writes the draw arguments); elsewhere the positions and the material
// indices are copied through the CPU (no allocation). With "Anisotropic" on (the default) the
// world also computes smoothed positions and anisotropy (Yu & Turk 2013), and each sphere is
// drawn as its particle's ellipsoid: flat along the surface, so the water reads as a surface, not
// beads. A label in the corner says which backend the world runs on, on which device, when on
// the CPU why CUDA was not taken, and which of the two paths the particles take.
//
// Setup: open FluidDemo.unity (beside this file) and press Play. Or add this component to any
// GameObject: it uses the assigned material, else one made from the Pbf/Particles shader
// (PbfParticles.shader beside this file). Optionally assign a Transform to "Pusher", a
// MeshFilter to "Obstacle" (its mesh becomes a static mesh collider where the GameObject
// stands), and Rigidbodies with a BoxCollider and a PbfFloatingBody to "Floating Bodies".
using System;
using System.Runtime.InteropServices;
using Pbf;
using Pbf.Unity;
using UnityEngine;
using PbfCollider = Pbf.Collider;      // UnityEngine has a Collider too,
using Mesh = UnityEngine.Mesh;         // Pbf has a Mesh too,
using Material = UnityEngine.Material; // and a Material (a fluid's): written Pbf.Material here

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
    [Tooltip("Rigidbodies (each with a BoxCollider) that float: the fluid pushes them, Unity moves them.")]
    public PbfFloatingBody[] floatingBodies = new PbfFloatingBody[0];
    [Tooltip("Invisible Unity box colliders on the domain's floor and walls, so that floating bodies stay in the tank.")]
    public bool tankColliders = true;

    [Header("Fluids")]
    [Tooltip("The world's default material: the dam-break block, and the nozzle unless it pours oil.")]
    public Color waterColor = new Color(0.15f, 0.45f, 0.95f, 1.0f);
    [Tooltip("A second fluid in the oil block. Off: water only.")]
    public bool oil = true;
    [Tooltip("kg/m^3, 0.1..10 times the water's 1000: lighter than water, it floats on it.")]
    public float oilDensity = 500.0f;
    public Color oilColor = new Color(0.95f, 0.7f, 0.1f, 1.0f);
    public Vector3 oilBlockMin = new Vector3(0.4f, 0.0f, -0.5f);
    public Vector3 oilBlockMax = new Vector3(1.0f, 0.3f, 0.5f);
    public bool nozzlePoursOil = false;

    [Header("Rendering")]
    public Material particleMaterial;
    [Tooltip("Defaults to Unity's built-in sphere.")]
    public Mesh particleMesh;
    [Tooltip("Draw each particle as its ellipsoid (smoothed position + anisotropy); fixed when the world is created.")]
    public bool anisotropic = true;
    [Tooltip("Show the backend, its device and, on the CPU, why CUDA was not taken.")]
    public bool showBackend = true;
    [Tooltip("Under Direct3D 11 with a CUDA world, CUDA writes the GraphicsBuffers on the render thread (no copy through the CPU). Off, or elsewhere: the copy path.")]
    public bool zeroCopy = true;

    World _world;
    Emitter _nozzle;
    PbfCollider _pusher;
    GraphicsBuffer _positionsBuffer;
    Vector4[] _positions;  // CPU staging copy, allocated once
    GraphicsBuffer _anisotropyBuffer;
    Vector4[] _anisotropy;  // 3 rows per particle: unit axis, radius (m)
    bool _anisotropic;
    GraphicsBuffer _materialsBuffer;
    uint[] _materialWords;  // the particles' material bytes, four to a word (the shader unpacks them)
    readonly Vector4[] _materialColors = new Vector4[Pbf.Interop.Native.PBF_MAX_MATERIALS];
    GameObject _tank;
    int _count;
    bool _nozzleOn;
    MaterialPropertyBlock _props;
    string _backendText;  // made once the world exists: OnGUI runs several times a frame

    // The zero-copy path (Direct3D 11 and a CUDA world); null handles: the copy path.
    D3D11Buffer _d3dPositions, _d3dAnisotropy, _d3dIds;
    GraphicsBuffer _idsBuffer;  // stable ids: the shader finds each particle's material from its id
    ComputeBuffer _drawArgs;    // indexed instanced draw arguments; the render event writes the count
    readonly uint[] _drawArgsData = new uint[5];
    IntPtr _renderEventFunc;
    int _renderEventId;
    bool _zeroCopyConfirmed;   // the render thread registered the buffers and copied without error
    string _renderPath;
    // The fluids' id ranges: ids are given in emission order and kept for life, so the water block,
    // the oil block and the nozzle's particles are three ranges, and a particle's material follows
    // from its id on the GPU (materials have no graphics-buffer copy).
    Vector4 _idRangeStarts, _idRangeMaterials;

    static readonly int PositionsId = Shader.PropertyToID("_PbfPositions");
    static readonly int RadiusId = Shader.PropertyToID("_Radius");
    static readonly int AnisotropyId = Shader.PropertyToID("_PbfAnisotropy");
    static readonly int UseAnisotropyId = Shader.PropertyToID("_UseAnisotropy");
    static readonly int MaterialsId = Shader.PropertyToID("_PbfMaterials");
    static readonly int MaterialColorsId = Shader.PropertyToID("_PbfMaterialColors");
    static readonly int UseMaterialsId = Shader.PropertyToID("_UseMaterials");
    static readonly int IdsId = Shader.PropertyToID("_PbfIds");
    static readonly int MaterialsFromIdsId = Shader.PropertyToID("_MaterialsFromIds");
    static readonly int IdRangeStartsId = Shader.PropertyToID("_PbfIdRangeStarts");
    static readonly int IdRangeMaterialsId = Shader.PropertyToID("_PbfIdRangeMaterials");

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
            Pbf.Material water = _world.DefaultMaterial;
            MaterialDesc waterDesc = water.GetDesc();
            waterDesc.Color = waterColor.ToNumerics();
            water.SetDesc(waterDesc);
            Pbf.Material oilMaterial = oil
                ? _world.CreateMaterial(new MaterialDesc { RestDensity = oilDensity, Color = oilColor.ToNumerics() })
                : water;
            int waterCount = _world.EmitBlock(blockMin.ToNumerics(), blockMax.ToNumerics());
            int oilCount = oil ? _world.EmitBlock(new BlockDesc(oilBlockMin.ToNumerics(), oilBlockMax.ToNumerics()) { Material = oilMaterial }) : 0;
            // Ids from 0: the water block, then the oil block, then whatever the nozzle pours.
            Pbf.Material poured = nozzlePoursOil ? oilMaterial : water;
            _idRangeStarts = new Vector4(0, waterCount, waterCount + oilCount, 0);
            _idRangeMaterials = new Vector4(water.Index, oilMaterial.Index, poured.Index, 0);
            if (nozzle)
            {
                // Emit at most the rest-density flux through the disc (speed · area / spacing³):
                // a higher rate packs particles closer than rest spacing and the jet bursts apart.
                float spacing = 2.0f * particleRadius;
                float rate = 0.8f * nozzleSpeed * Mathf.PI * nozzleRadius * nozzleRadius / (spacing * spacing * spacing);
                _nozzle = _world.CreateEmitter(new EmitterDesc(EmitterType.Nozzle)
                {
                    Position = nozzlePosition.ToNumerics(), Direction = new System.Numerics.Vector3(0, -1, 0),
                    Speed = nozzleSpeed, Radius = nozzleRadius, ParticlesPerSecond = rate,
                    Material = poured,
                });
                _nozzle.SetEnabled(nozzleEnabled);
                _nozzleOn = nozzleEnabled;
            }
            if (pusher != null)
                _pusher = _world.CreateCollider(ColliderDesc.Sphere(pusher.position.ToNumerics(), 0.5f * pusher.lossyScale.x,
                                                                    ColliderMotion.Kinematic));
            if (obstacle != null) AddObstacle(obstacle);
            foreach (PbfFloatingBody body in floatingBodies)
                if (body != null) body.Attach(_world);
            ReadMaterialColors();
        }
        catch (PbfException e)
        {
            Debug.LogError("libpbf: " + e.Code + ": " + e.Message);
            enabled = false;
            return;
        }


        _positions = new Vector4[maxParticles];
        _positionsBuffer = new GraphicsBuffer(GraphicsBuffer.Target.Structured, maxParticles, 16);
        // The shader declares the buffer either way; without anisotropy it holds one unused row.
        _anisotropy = new Vector4[_anisotropic ? 3 * maxParticles : 1];
        _anisotropyBuffer = new GraphicsBuffer(GraphicsBuffer.Target.Structured, _anisotropy.Length, 16);
        _materialWords = new uint[(maxParticles + 3) / 4];
        _materialsBuffer = new GraphicsBuffer(GraphicsBuffer.Target.Structured, _materialWords.Length, 4);
        if (tankColliders) _tank = MakeTank();
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
        bool zeroCopyHere = ZeroCopyHere(out _renderPath);
        // Declared by the shader either way; on the copy path it holds one unused id.
        _idsBuffer = new GraphicsBuffer(GraphicsBuffer.Target.Structured, zeroCopyHere ? maxParticles : 1, 4);
        if (zeroCopyHere) StartZeroCopy();
        UpdateBackendText();
        Debug.Log(_backendText);
    }

    void UpdateBackendText()
    {
        WorldInfo info = _world.Info;
        _backendText = "libpbf " + Library.VersionString(Library.Version) + ": " + info.Backend + " on " + info.DeviceName;
        if (info.Backend != Backend.Cuda) _backendText += "\n" + _world.CudaNotTakenReason;
        _backendText += "\nRendering: " + _renderPath;
    }

    // Whether the zero-copy path can run here; path: how the frames reach the GPU, and why not
    // zero-copy when it cannot.
    bool ZeroCopyHere(out string path)
    {
        path = "copied through the CPU";
        UnityEngine.Rendering.GraphicsDeviceType api = SystemInfo.graphicsDeviceType;
        if (!zeroCopy) path += " (zero-copy is off)";
        else if (api != UnityEngine.Rendering.GraphicsDeviceType.Direct3D11) path += " (zero-copy needs Direct3D 11; this is " + api + ")";
        else if (_world.Backend != Backend.Cuda) path += " (zero-copy needs a CUDA world)";
        else if ((Library.GetInteropSupport() & InteropSupport.D3D11) == 0) path += " (this libpbf has no CUDA-D3D11 interop)";
        else if (particleMesh.GetIndexStart(0) != 0 || particleMesh.GetBaseVertex(0) != 0)
            path += " (zero-copy draws submesh 0 of the particle mesh from index 0 and vertex 0)";
        else return true;
        return false;
    }

    // Registers the GraphicsBuffers' ID3D11Buffers with the world: from the next render event on,
    // each render event (issued in Update) copies the particles of the last step into them on the
    // render thread, which owns the D3D11 device context, and writes the instance count into the
    // draw arguments, so nothing is read back to the CPU. Registration itself happens at the
    // first render event; Update checks that it worked and falls back to the copy path if not.
    void StartZeroCopy()
    {
        // DrawMeshInstancedIndirect's arguments: index count, instances, first index, base vertex,
        // first instance. The render event writes the first four as {v, n, 0, 0} (v = the
        // DrawArgsVertices below), the layout both indexed and non-indexed draws begin with.
        uint indices = particleMesh.GetIndexCount(0);
        _drawArgsData[0] = indices;
        _drawArgs = new ComputeBuffer(1, 5 * sizeof(uint), ComputeBufferType.IndirectArguments);
        _drawArgs.SetData(_drawArgsData);
        try
        {
            // Ellipsoids are centred on the smoothed positions, which belong with the anisotropy.
            BufferSource positions = _anisotropic ? BufferSource.SmoothedPositions : BufferSource.Positions;
            _d3dPositions = _world.RegisterD3D11Buffer(new D3D11BufferDesc(_positionsBuffer.GetNativeBufferPtr(), maxParticles, positions)
            {
                DrawArgsBuffer = _drawArgs.GetNativeBufferPtr(), DrawArgsVertices = (int)indices,
            });
            if (_anisotropic)
                _d3dAnisotropy = _world.RegisterD3D11Buffer(
                    new D3D11BufferDesc(_anisotropyBuffer.GetNativeBufferPtr(), maxParticles, BufferSource.Anisotropy));
            _d3dIds = _world.RegisterD3D11Buffer(new D3D11BufferDesc(_idsBuffer.GetNativeBufferPtr(), maxParticles, BufferSource.Ids));
            _renderEventFunc = Library.GetRenderEventFunc();
            _renderEventId = _world.GetRenderEventId();
            _zeroCopyConfirmed = false;
            _renderPath = "Direct3D 11 zero-copy (CUDA writes the GraphicsBuffers on the render thread)";
        }
        catch (PbfException e)
        {
            StopZeroCopy("registering the D3D11 buffers failed: " + e.Message);
        }
    }

    // Back to the copy path: unregisters the D3D11 buffers. They are unregistered by the next
    // render event, on the render thread, and must live until then: issue one and wait for the
    // render thread with a readback (Unity runs it after the commands queued before it).
    void StopZeroCopy(string why)
    {
        bool issue = false;
        foreach (D3D11Buffer b in new[] { _d3dPositions, _d3dAnisotropy, _d3dIds })
        {
            if (b == null) continue;
            b.Unregister();
            issue = true;
        }
        _d3dPositions = _d3dAnisotropy = _d3dIds = null;
        if (issue)
        {
            GL.IssuePluginEvent(_renderEventFunc, _renderEventId);
            _drawArgs.GetData(_drawArgsData);
        }
        if (_drawArgs != null) _drawArgs.Release();
        _drawArgs = null;
        if (why != null)
        {
            Debug.LogWarning("PbfFluidDemo: zero-copy off, " + why);
            _renderPath = "copied through the CPU (zero-copy failed: " + why + ")";
            UpdateBackendText();
        }
    }

    // Until the first render event has registered the buffers and copied: its result.
    void ConfirmZeroCopy()
    {
        InteropInfo interop = _world.GetInteropInfo();
        if (interop.LastRenderEventResult != Result.Ok)
            StopZeroCopy(interop.LastRenderEventResult + ": " + interop.LastRenderEventMessage);
        else if (interop.RenderEvents > 0 && interop.PendingRenderWork == 0)
            _zeroCopyConfirmed = true;
    }

    // The MeshFilter's mesh, scaled by its Transform, as a static mesh collider at its pose.
    void AddObstacle(MeshFilter filter)
    {
        Pbf.Mesh mesh = _world.CreateMesh(PbfUnityMesh.ToMeshDesc(filter.sharedMesh, filter.transform.lossyScale));
        _world.CreateCollider(ColliderDesc.FromMesh(mesh, filter.transform.position.ToNumerics(),
                                                    filter.transform.rotation.ToNumerics()));
    }

    // The shader's colour table: entry k is the colour of the material whose index is k, as the
    // world holds it (what MaterialDesc.Color is for). Read again if materials change.
    void ReadMaterialColors()
    {
        Pbf.Material[] materials = _world.Materials;
        for (int k = 0; k < _materialColors.Length; ++k)
        {
            System.Numerics.Vector4 c = materials[k] != null ? materials[k].GetDesc().Color : new System.Numerics.Vector4(1, 0, 1, 1);
            _materialColors[k] = new Vector4(c.X, c.Y, c.Z, c.W);
        }
    }

    // Unity colliders around the domain (floor and four walls, 0.5 m thick, outside it), for the
    // Rigidbodies: libpbf's walls hold only the fluid.
    GameObject MakeTank()
    {
        var tank = new GameObject("PbfTank (colliders)");
        Vector3 size = domainMax - domainMin, centre = 0.5f * (domainMin + domainMax);
        const float t = 0.5f;
        AddWall(tank, new Vector3(centre.x, domainMin.y - 0.5f * t, centre.z), new Vector3(size.x + 2 * t, t, size.z + 2 * t));
        AddWall(tank, new Vector3(domainMin.x - 0.5f * t, centre.y, centre.z), new Vector3(t, size.y, size.z + 2 * t));
        AddWall(tank, new Vector3(domainMax.x + 0.5f * t, centre.y, centre.z), new Vector3(t, size.y, size.z + 2 * t));
        AddWall(tank, new Vector3(centre.x, centre.y, domainMin.z - 0.5f * t), new Vector3(size.x, size.y, t));
        AddWall(tank, new Vector3(centre.x, centre.y, domainMax.z + 0.5f * t), new Vector3(size.x, size.y, t));
        return tank;
    }

    static void AddWall(GameObject tank, Vector3 centre, Vector3 size)
    {
        BoxCollider wall = tank.AddComponent<BoxCollider>();
        wall.center = centre;
        wall.size = size;
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
        float dt = Time.fixedDeltaTime;
        foreach (PbfFloatingBody body in floatingBodies)
            if (body != null) body.BeforeStep(dt);
        _world.Step(dt);
        // The fluid's push of this step, for Unity's physics step that follows the FixedUpdates.
        foreach (PbfFloatingBody body in floatingBodies)
            if (body != null) body.AfterStep();
    }

    void Update()
    {
        if (_world == null) return;
        if (_d3dPositions != null && !_zeroCopyConfirmed) ConfirmZeroCopy();
        if (_d3dPositions != null)
        {
            DrawZeroCopy();
            return;
        }
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
        // The material bytes, in the positions' order (both copied between the same two steps).
        int bytes = _world.CopyMaterials(MemoryMarshal.AsBytes(new Span<uint>(_materialWords)));
        _materialsBuffer.SetData(_materialWords, 0, 0, (bytes + 3) / 4);

        SetProperties(false);
        Graphics.DrawMeshInstancedProcedural(particleMesh, 0, particleMaterial, DomainBounds(), _count, _props);
    }

    // The render event copies the last step's particles into the registered buffers and the
    // count into the draw arguments on the render thread, before the draw below reads them.
    void DrawZeroCopy()
    {
        GL.IssuePluginEvent(_renderEventFunc, _renderEventId);
        if (particleMaterial == null) return;
        SetProperties(true);
        Graphics.DrawMeshInstancedIndirect(particleMesh, 0, particleMaterial, DomainBounds(), _drawArgs, 0, _props);
    }

    void SetProperties(bool materialsFromIds)
    {
        _props.SetBuffer(PositionsId, _positionsBuffer);
        _props.SetBuffer(AnisotropyId, _anisotropyBuffer);
        _props.SetFloat(UseAnisotropyId, _anisotropic ? 1.0f : 0.0f);
        _props.SetBuffer(MaterialsId, _materialsBuffer);
        _props.SetBuffer(IdsId, _idsBuffer);
        _props.SetFloat(MaterialsFromIdsId, materialsFromIds ? 1.0f : 0.0f);
        _props.SetVector(IdRangeStartsId, _idRangeStarts);
        _props.SetVector(IdRangeMaterialsId, _idRangeMaterials);
        _props.SetVectorArray(MaterialColorsId, _materialColors);
        _props.SetFloat(UseMaterialsId, 1.0f);
        _props.SetFloat(RadiusId, particleRadius);
    }

    Bounds DomainBounds() { return new Bounds(0.5f * (domainMin + domainMax), domainMax - domainMin); }

    void OnGUI()
    {
        if (showBackend && _backendText != null) GUI.Label(new Rect(10, 10, 1000, 60), _backendText);
    }

    void OnDisable()
    {
        foreach (PbfFloatingBody body in floatingBodies)
            if (body != null) body.Detach();
        // Before the world goes: its render thread work, then the buffers it writes.
        if (_world != null) StopZeroCopy(null);
        if (_world != null) _world.Dispose();  // destroys its emitters, colliders and materials too
        _world = null;
        _nozzle = null;
        _pusher = null;
        if (_positionsBuffer != null) _positionsBuffer.Release();
        _positionsBuffer = null;
        if (_anisotropyBuffer != null) _anisotropyBuffer.Release();
        _anisotropyBuffer = null;
        if (_materialsBuffer != null) _materialsBuffer.Release();
        _materialsBuffer = null;
        if (_idsBuffer != null) _idsBuffer.Release();
        _idsBuffer = null;
        if (_tank != null) Destroy(_tank);
        _tank = null;
        _backendText = null;
        PbfUnityLog.Uninstall();
    }

    void OnDrawGizmosSelected()
    {
        Gizmos.color = Color.cyan;
        Gizmos.DrawWireCube(0.5f * (domainMin + domainMax), domainMax - domainMin);
    }
}
