using System;
using System.Runtime.InteropServices;
using Pbf.Interop;

namespace Pbf
{
    /// <summary>A fluid material of a <see cref="World"/> (see <see cref="WorldObject{TId}"/> for its
    /// handle's lifetime). Destroy refuses the default material, and a material an emitter or a
    /// particle still uses (<see cref="Result.InvalidState"/>).</summary>
    public sealed class Material : WorldObject<pbf_material_id>
    {
        internal Material(World world, pbf_material_id id) : base(world, id) { }

        /// <summary>The value particles of this material hold in <see cref="BufferSource.Materials"/>.</summary>
        public int Index { get { return (int)Id.index; } }

        internal static pbf_material_id NativeId(Material m) { return m == null ? new pbf_material_id() : m.Id; }

        internal override pbf_result DestroyNative() { return Native.pbf_world_destroy_material(World.Handle, Id); }

        /// <summary>The material's parameters.</summary>
        public MaterialDesc GetDesc()
        {
            var raw = new pbf_material_desc { struct_size = Native.SizeOf<pbf_material_desc>() };
            PbfException.Check(Native.pbf_world_get_material(World.Handle, Id, ref raw));
            return new MaterialDesc(raw);
        }

        /// <summary>New parameters from the next step on.</summary>
        public void SetDesc(MaterialDesc desc)
        {
            if (desc == null) throw new ArgumentNullException("desc");
            pbf_material_desc raw = desc.ToNative();
            PbfException.Check(Native.pbf_world_set_material(World.Handle, Id, ref raw));
        }
    }

    public sealed partial class World
    {
        /// <summary>A new material (at most <see cref="Native.PBF_MAX_MATERIALS"/> per world, the
        /// default one included; <see cref="Result.Capacity"/> beyond).</summary>
        public Material CreateMaterial(MaterialDesc desc)
        {
            if (desc == null) throw new ArgumentNullException("desc");
            var id = CreateNative<pbf_material_desc, pbf_material_id>(Native.pbf_world_create_material, desc.ToNative());
            return new Material(this, id);
        }

        /// <summary>The world's default material (index 0): its rest density is the world's, its
        /// viscosity and LDC gain are the solver parameters'.</summary>
        public Material DefaultMaterial { get { return new Material(this, MaterialIds()[0]); } }

        /// <summary>The material handle at each index (zeroed where none).</summary>
        public pbf_material_id[] MaterialIds()
        {
            var ids = new pbf_material_id[Native.PBF_MAX_MATERIALS];
            PbfException.Check(Native.pbf_world_get_materials(Handle, ids));
            return ids;
        }

        /// <summary>The live materials by index, null where none: element k is the material of the
        /// particles whose <see cref="BufferSource.Materials"/> byte is k (a renderer's colour
        /// table: <see cref="MaterialDesc.Color"/> of each).</summary>
        public Material[] Materials
        {
            get
            {
                pbf_material_id[] ids = MaterialIds();
                var materials = new Material[ids.Length];
                for (int k = 0; k < ids.Length; ++k)
                    if (ids[k].generation != 0) materials[k] = new Material(this, ids[k]);
                return materials;
            }
        }

        /// <summary>Each particle's material index (1 byte per particle), same order as the
        /// positions; returns how many particles were copied.</summary>
        public int CopyMaterials(byte[] destination)
        {
            if (destination == null) throw new ArgumentNullException("destination");
            return CopyMaterials(new Span<byte>(destination));
        }

        public int CopyMaterials(Span<byte> destination)
        {
            uint written;
            pbf_result r = destination.Length == 0
                ? Native.pbf_world_copy_buffer(Handle, pbf_buffer.PBF_BUFFER_MATERIALS, IntPtr.Zero, 0, out written)
                : Native.pbf_world_copy_buffer(Handle, pbf_buffer.PBF_BUFFER_MATERIALS, ref MemoryMarshal.GetReference(destination),
                                               (ulong)destination.Length, out written);
            PbfException.Check(r);
            return (int)written;
        }
    }
}
