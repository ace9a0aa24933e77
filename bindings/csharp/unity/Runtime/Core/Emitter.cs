using System;
using System.Numerics;
using Pbf.Interop;

namespace Pbf
{
    /// <summary>
    /// A nozzle or a drain of a <see cref="World"/>. After <see cref="Destroy"/> the native handle
    /// is stale: other calls throw <see cref="PbfException"/> with <see cref="Result.InvalidHandle"/>.
    /// After the world is disposed they throw <see cref="ObjectDisposedException"/>.
    /// </summary>
    public sealed class Emitter : IDisposable
    {
        readonly World _world;
        readonly pbf_emitter_id _id;
        bool _destroyed;

        internal Emitter(World world, pbf_emitter_id id, EmitterType type)
        {
            _world = world;
            _id = id;
            Type = type;
        }

        public World World { get { return _world; } }
        public pbf_emitter_id Id { get { return _id; } }
        public EmitterType Type { get; private set; }
        /// <summary>True after Destroy, or once its world is disposed.</summary>
        public bool IsDestroyed { get { return _destroyed || _world.IsDisposed; } }

        public void SetEnabled(bool enabled)
        {
            PbfException.Check(Native.pbf_emitter_set_enabled(_world.Handle, _id, enabled ? 1u : 0u));
        }

        /// <summary>Moves a nozzle: disc centre and direction (normalised by the library). A drain
        /// throws (<see cref="Result.InvalidArgument"/>).</summary>
        public void SetNozzle(Vector3 position, Vector3 direction)
        {
            Float3 p = Convert3.ToNative(position), d = Convert3.ToNative(direction);
            PbfException.Check(Native.pbf_emitter_set_nozzle(_world.Handle, _id, ref p, ref d));
        }

        /// <summary>Moves a drain: the corners of its box. A nozzle throws
        /// (<see cref="Result.InvalidArgument"/>).</summary>
        public void SetDrainBox(Vector3 boxMin, Vector3 boxMax)
        {
            Float3 lo = Convert3.ToNative(boxMin), hi = Convert3.ToNative(boxMax);
            PbfException.Check(Native.pbf_emitter_set_drain_box(_world.Handle, _id, ref lo, ref hi));
        }

        /// <summary>Removes the emitter from its world. Idempotent; a no-op once the world is disposed.</summary>
        public void Destroy()
        {
            if (_destroyed || _world.IsDisposed) { _destroyed = true; return; }
            PbfException.Check(Native.pbf_world_destroy_emitter(_world.Handle, _id));
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

    /// <summary>
    /// A collider of a <see cref="World"/>. After <see cref="Destroy"/> the native handle is
    /// stale: other calls throw <see cref="PbfException"/> with <see cref="Result.InvalidHandle"/>.
    /// After the world is disposed they throw <see cref="ObjectDisposedException"/>.
    /// </summary>
    public sealed class Collider : IDisposable
    {
        readonly World _world;
        readonly pbf_collider_id _id;
        bool _destroyed;

        internal Collider(World world, pbf_collider_id id, ColliderShape shape, ColliderMotion motion)
        {
            _world = world;
            _id = id;
            Shape = shape;
            Motion = motion;
        }

        public World World { get { return _world; } }
        public pbf_collider_id Id { get { return _id; } }
        public ColliderShape Shape { get; private set; }
        public ColliderMotion Motion { get; private set; }
        public bool IsDestroyed { get { return _destroyed || _world.IsDisposed; } }

        /// <summary>Kinematic colliders only (else <see cref="Result.InvalidState"/>): the target
        /// pose, reached at the end of the next step; the solver moves the collider there over that
        /// step.</summary>
        public void SetTargetPose(Vector3 position, Quaternion rotation)
        {
            Float3 p = Convert3.ToNative(position);
            Float4 q = Convert3.ToNative(rotation);
            PbfException.Check(Native.pbf_collider_set_target_pose(_world.Handle, _id, ref p, ref q));
        }

        /// <summary>Dynamic colliders only (else <see cref="Result.InvalidState"/>): the fluid's mean
        /// force and torque over the last step (zero before the first). Waits for that step to finish
        /// on the backend; on CUDA the first call after a step copies every collider's row at once.</summary>
        public ColliderForce GetForce()
        {
            pbf_collider_force f;
            PbfException.Check(Native.pbf_collider_get_force(_world.Handle, _id, out f));
            return new ColliderForce(f);
        }

        /// <summary>Removes the collider from its world. Idempotent; a no-op once the world is disposed.</summary>
        public void Destroy()
        {
            if (_destroyed || _world.IsDisposed) { _destroyed = true; return; }
            PbfException.Check(Native.pbf_world_destroy_collider(_world.Handle, _id));
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
}
