using System;
using System.Numerics;
using System.Runtime.InteropServices;
using Pbf.Interop;

namespace Pbf
{
    /// <summary>
    /// The live position buffer of a world (pbf_mapped_buffer): Count particles of x, y, z, w floats,
    /// StrideBytes apart, at Data. On <see cref="MemoryKind.Host"/> it can be read here; on
    /// <see cref="MemoryKind.CudaDevice"/> Data is a device pointer for CUDA interop only.
    /// Valid until Dispose/<see cref="World.Unmap"/>, the next step, any call that adds or
    /// removes particles, or the world's Dispose. With unsafe code enabled,
    /// <c>new ReadOnlySpan&lt;Vector4&gt;((void*)Data, Count)</c> reads it without copying.
    /// </summary>
    public readonly struct MappedPositions : IDisposable
    {
        readonly World _world;

        internal MappedPositions(World world, pbf_mapped_buffer buffer)
        {
            _world = world;
            Data = buffer.data;
            Count = (int)buffer.count;
            StrideBytes = (int)buffer.stride_bytes;
            Memory = (MemoryKind)buffer.memory;
        }

        public IntPtr Data { get; }
        public int Count { get; }
        public int StrideBytes { get; }
        public MemoryKind Memory { get; }

        /// <summary>Particle i's x, y, z, w (host memory only).</summary>
        public Vector4 this[int index]
        {
            get
            {
                RequireHost();
                if ((uint)index >= (uint)Count) throw new ArgumentOutOfRangeException("index");
                IntPtr p = Data + index * StrideBytes;
                return new Vector4(BitConverter.Int32BitsToSingle(Marshal.ReadInt32(p, 0)),
                                   BitConverter.Int32BitsToSingle(Marshal.ReadInt32(p, 4)),
                                   BitConverter.Int32BitsToSingle(Marshal.ReadInt32(p, 8)),
                                   BitConverter.Int32BitsToSingle(Marshal.ReadInt32(p, 12)));
            }
        }

        /// <summary>Copies min(Count, destination.Length / 4) particles (host memory only); returns how many.</summary>
        public int CopyTo(float[] destination)
        {
            if (destination == null) throw new ArgumentNullException("destination");
            RequireHost();
            int n = Math.Min(Count, destination.Length / 4);
            if (StrideBytes == 16)
            {
                if (n > 0) Marshal.Copy(Data, destination, 0, n * 4);
            }
            else
            {
                for (int i = 0; i < n; ++i) Marshal.Copy(Data + i * StrideBytes, destination, i * 4, 4);
            }
            return n;
        }

        void RequireHost()
        {
            if (Memory != MemoryKind.Host)
                throw new InvalidOperationException("the mapped buffer is " + Memory + " memory; only Host memory can be read from C#");
        }

        /// <summary>Ends the world's mapping (pbf_world_unmap); does nothing, and does not throw,
        /// when a step or another call already ended it or the world is disposed.</summary>
        public void Dispose()
        {
            if (_world != null) _world.UnmapIfMapped();
        }
    }
}
