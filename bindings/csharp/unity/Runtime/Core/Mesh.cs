using System;
using System.Numerics;
using System.Runtime.InteropServices;
using Pbf.Interop;

namespace Pbf
{
    /// <summary>
    /// A triangle mesh for mesh colliders (pbf_mesh_desc): vertices in the mesh's own frame and
    /// three indices per triangle, counter-clockwise seen from outside. The library copies the
    /// arrays when the mesh is created.
    /// </summary>
    public sealed class MeshDesc
    {
        public MeshDesc(Vector3[] vertices, int[] indices)
        {
            if (vertices == null) throw new ArgumentNullException("vertices");
            if (indices == null) throw new ArgumentNullException("indices");
            Vertices = vertices;
            Indices = indices;
            var raw = new pbf_mesh_desc { struct_size = Native.SizeOf<pbf_mesh_desc>() };
            PbfException.Check(Native.pbf_mesh_desc_init(ref raw, raw.struct_size));
            Closed = raw.closed != 0;
        }

        public Vector3[] Vertices { get; private set; }
        public int[] Indices { get; private set; }
        /// <summary>Default true: watertight, inside by the winding number. False: an open mesh (a
        /// terrain piece, a single-sided plane), solid within Thickness/2 of its surface.</summary>
        public bool Closed { get; set; }
        /// <summary>Open meshes: the shell's thickness (0, the default: 2 particle radii).</summary>
        public float Thickness { get; set; }
        /// <summary>The distance field's grid spacing (0, the default: the particle radius).</summary>
        public float CellSize { get; set; }
    }

    /// <summary>A mesh of a <see cref="World"/>: its signed distance field, shared by the colliders
    /// made with <see cref="ColliderDesc.FromMesh"/>. Destroy is refused (InvalidState) while a
    /// collider uses it.</summary>
    public sealed class Mesh : WorldObject<pbf_mesh_id>
    {
        internal Mesh(World world, pbf_mesh_id id) : base(world, id) { }

        internal override pbf_result DestroyNative() { return Native.pbf_world_destroy_mesh(World.Handle, Id); }
    }

    public sealed partial class World
    {
        /// <summary>Builds the mesh's distance field (on the world's backend; waits for it).</summary>
        public Mesh CreateMesh(MeshDesc desc)
        {
            if (desc == null) throw new ArgumentNullException("desc");
            var raw = new pbf_mesh_desc { struct_size = Native.SizeOf<pbf_mesh_desc>() };
            PbfException.Check(Native.pbf_mesh_desc_init(ref raw, raw.struct_size));
            raw.vertex_count = (uint)desc.Vertices.Length;
            raw.triangle_count = (uint)(desc.Indices.Length / 3);
            raw.closed = desc.Closed ? 1u : 0u;
            raw.thickness = desc.Thickness;
            raw.cell_size = desc.CellSize;
            // Vector3 is three floats (the library's layout): both arrays are passed pinned.
            GCHandle v = GCHandle.Alloc(desc.Vertices, GCHandleType.Pinned);
            GCHandle i = GCHandle.Alloc(desc.Indices, GCHandleType.Pinned);
            try
            {
                raw.vertices = v.AddrOfPinnedObject();
                raw.indices = i.AddrOfPinnedObject();
                return new Mesh(this, CreateNative<pbf_mesh_desc, pbf_mesh_id>(Native.pbf_world_create_mesh, raw));
            }
            finally
            {
                v.Free();
                i.Free();
            }
        }
    }
}
