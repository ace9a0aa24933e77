using System;
using System.Numerics;
using Pbf.Interop;

namespace Pbf
{
    /// <summary>A generation-checked handle of a <see cref="World"/>'s object, with its world.</summary>
    public abstract class WorldHandle<TId> where TId : struct
    {
        readonly World _world;
        readonly TId _id;

        internal WorldHandle(World world, TId id)
        {
            _world = world;
            _id = id;
        }

        public World World { get { return _world; } }
        public TId Id { get { return _id; } }
    }

    /// <summary>
    /// An object a <see cref="World"/> owns and that can be destroyed (an <see cref="Emitter"/>
    /// or a <see cref="Collider"/>). After <see cref="Destroy"/> the native handle is stale: other
    /// calls throw <see cref="PbfException"/> with <see cref="Result.InvalidHandle"/>. After the
    /// world is disposed they throw <see cref="ObjectDisposedException"/>.
    /// </summary>
    public abstract class WorldObject<TId> : WorldHandle<TId>, IDisposable where TId : struct
    {
        bool _destroyed;

        internal WorldObject(World world, TId id) : base(world, id) { }

        /// <summary>True after Destroy, or once its world is disposed.</summary>
        public bool IsDestroyed { get { return _destroyed || World.IsDisposed; } }

        /// <summary>The library's destroy call for this handle.</summary>
        internal abstract pbf_result DestroyNative();

        /// <summary>Removes the object from its world. Idempotent; a no-op once the world is disposed.</summary>
        public void Destroy()
        {
            if (_destroyed || World.IsDisposed) { _destroyed = true; return; }
            PbfException.Check(DestroyNative());
            _destroyed = true;
        }

        /// <summary>Destroy, without throwing.</summary>
        public void Dispose()
        {
            try { Destroy(); }
            catch (PbfException) { }
            catch (ObjectDisposedException) { }
        }
    }

    /// <summary>A nozzle or a drain of a <see cref="World"/> (see <see cref="WorldObject{TId}"/>
    /// for its handle's lifetime).</summary>
    public sealed class Emitter : WorldObject<pbf_emitter_id>
    {
        internal Emitter(World world, pbf_emitter_id id, EmitterType type) : base(world, id) { Type = type; }

        public EmitterType Type { get; private set; }

        public void SetEnabled(bool enabled)
        {
            PbfException.Check(Native.pbf_emitter_set_enabled(World.Handle, Id, enabled ? 1u : 0u));
        }

        /// <summary>Moves a nozzle: disc centre and direction (normalised by the library). A drain
        /// throws (<see cref="Result.InvalidArgument"/>).</summary>
        public void SetNozzle(Vector3 position, Vector3 direction)
        {
            Float3 p = Convert3.ToNative(position), d = Convert3.ToNative(direction);
            PbfException.Check(Native.pbf_emitter_set_nozzle(World.Handle, Id, ref p, ref d));
        }

        /// <summary>Moves a drain: the corners of its box. A nozzle throws
        /// (<see cref="Result.InvalidArgument"/>).</summary>
        public void SetDrainBox(Vector3 boxMin, Vector3 boxMax)
        {
            Float3 lo = Convert3.ToNative(boxMin), hi = Convert3.ToNative(boxMax);
            PbfException.Check(Native.pbf_emitter_set_drain_box(World.Handle, Id, ref lo, ref hi));
        }

        internal override pbf_result DestroyNative() { return Native.pbf_world_destroy_emitter(World.Handle, Id); }
    }

    /// <summary>A collider of a <see cref="World"/> (see <see cref="WorldObject{TId}"/> for its
    /// handle's lifetime).</summary>
    public sealed class Collider : WorldObject<pbf_collider_id>
    {
        internal Collider(World world, pbf_collider_id id, ColliderShape shape, ColliderMotion motion) : base(world, id)
        {
            Shape = shape;
            Motion = motion;
        }

        public ColliderShape Shape { get; private set; }
        public ColliderMotion Motion { get; private set; }

        /// <summary>Kinematic colliders only (else <see cref="Result.InvalidState"/>): the target
        /// pose, reached at the end of the next step; the solver moves the collider there over that
        /// step.</summary>
        public void SetTargetPose(Vector3 position, Quaternion rotation)
        {
            Float3 p = Convert3.ToNative(position);
            Float4 q = Convert3.ToNative(rotation);
            PbfException.Check(Native.pbf_collider_set_target_pose(World.Handle, Id, ref p, ref q));
        }

        /// <summary>Any collider: puts it at this pose now, without moving it there (no sweep: the
        /// next step starts and ends here). For respawned or streamed bodies. Fluid it lands in is
        /// moved out and settled in the next step without being flung (README, Physics, Overlaps).</summary>
        public void Teleport(Vector3 position, Quaternion rotation)
        {
            Float3 p = Convert3.ToNative(position);
            Float4 q = Convert3.ToNative(rotation);
            PbfException.Check(Native.pbf_collider_teleport(World.Handle, Id, ref p, ref q));
        }

        /// <summary>Dynamic colliders only (else <see cref="Result.InvalidState"/>): the fluid's mean
        /// force and torque over the last step (zero before the first, and after a step too short to
        /// simulate, whose impulse the next step's force carries). Waits for that step to finish
        /// on the backend; on CUDA the first call after a step copies every collider's row at once.</summary>
        public ColliderForce GetForce()
        {
            pbf_collider_force f;
            PbfException.Check(Native.pbf_collider_get_force(World.Handle, Id, out f));
            return new ColliderForce(f);
        }

        internal override pbf_result DestroyNative() { return Native.pbf_world_destroy_collider(World.Handle, Id); }
    }
}
