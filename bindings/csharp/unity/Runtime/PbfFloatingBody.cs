// Two-way coupling of a Unity Rigidbody with a libpbf world: the body's BoxCollider becomes a
// dynamic, kinematic box collider of the world. Unity integrates the body; the fluid only pushes
// it. The owner of the world calls, in its FixedUpdate, BeforeStep on every body, then
// World.Step(Time.fixedDeltaTime) once, then AfterStep on every body: AfterStep reads the force
// and torque the fluid exerted during that step and adds them, averaged over the last few steps
// (SmoothedForce: the explicit coupling is unstable for light or turning bodies without it), to
// the Rigidbody, which Unity's physics step (after all FixedUpdates) then integrates with gravity
// and contacts. Buoyancy, drag and splashes' push all arrive through that one force. See
// samples/csharp/FloatingBox.cs for the same loop without Unity.
using System;
using UnityEngine;

namespace Pbf.Unity
{
    [RequireComponent(typeof(Rigidbody), typeof(BoxCollider))]
    public sealed class PbfFloatingBody : MonoBehaviour
    {
        [Tooltip("> 0: on Attach the Rigidbody's mass becomes this density (kg/m³) times the box's volume " +
                 "(water is 1000: a body of 500 floats half under). 0 keeps the Rigidbody's mass.")]
        public float density = 0.0f;
        [Tooltip("Coulomb friction of the fluid on the box, 0..1 (0: the fluid slips along it).")]
        [Range(0.0f, 1.0f)] public float friction = 0.0f;
        [Tooltip("Each step keeps this share of the force and torque applied the step before (an average over " +
                 "about s/(1-s) steps): 0 applies the raw force; light bodies and turning ones need about 0.8 to stay stable.")]
        [Range(0.0f, 0.95f)] public float forceSmoothing = 0.8f;
        [Tooltip("If the body is found this far (m) from where the fluid last put it, something else moved it " +
                 "(a respawn, a script): the fluid's collider is teleported there instead of sweeping through the fluid.")]
        public float teleportDistance = 0.25f;

        Rigidbody _body;
        BoxCollider _box;
        Collider _collider;          // Pbf.Collider (this namespace sits in Pbf)
        Vector3 _placedPosition;     // where the fluid's box is now: its last target position
        SmoothedForce _applied;

        /// <summary>The world's collider for this body (null until <see cref="Attach"/>).</summary>
        public Collider FluidCollider { get { return _collider; } }
        /// <summary>The force (N) and the torque about the centre of mass (N·m) of the last step.</summary>
        public ColliderForce LastForce { get; private set; }
        /// <summary>What the last AfterStep added to the Rigidbody: the average of the steps' forces.</summary>
        public ColliderForce AppliedForce { get { return _applied != null ? _applied.Value : default(ColliderForce); } }
        public bool IsAttached { get { return _collider != null && !_collider.IsDestroyed; } }

        /// <summary>Makes the body's box a dynamic collider of <paramref name="world"/> where the
        /// body is now (replacing one made earlier). The box is the BoxCollider's size and centre
        /// scaled by the Transform's lossyScale (no shear); torques are taken about the
        /// Rigidbody's centre of mass as it is now.</summary>
        public void Attach(World world)
        {
            if (world == null) throw new ArgumentNullException("world");
            Detach();
            _body = GetComponent<Rigidbody>();
            _box = GetComponent<BoxCollider>();
            Vector3 half = HalfExtents();
            if (density > 0.0f) _body.mass = density * 8.0f * half.x * half.y * half.z;
            Vector3 centre = BoxCentre(_body.position, _body.rotation);
            var desc = ColliderDesc.Box(centre.ToNumerics(), _body.rotation.ToNumerics(), half.ToNumerics(),
                                        ColliderMotion.Kinematic);
            desc.Dynamic = true;
            desc.Friction = friction;
            desc.CenterOfMass = (Quaternion.Inverse(_body.rotation) * (_body.worldCenterOfMass - centre)).ToNumerics();
            _collider = world.CreateCollider(desc);
            _placedPosition = centre;
            LastForce = default(ColliderForce);
            _applied = new SmoothedForce(Mathf.Clamp(forceSmoothing, 0.0f, 0.95f));
        }

        /// <summary>Removes the collider from its world (a no-op once the world is disposed).</summary>
        public void Detach()
        {
            if (_collider != null) _collider.Dispose();
            _collider = null;
        }

        /// <summary>Before the world's step of <paramref name="dt"/> seconds: the box's target is
        /// where the body will be after Unity's physics step of the same length, predicted from its
        /// velocities now (the forces of this step are not known yet: an O(dt²) lead that the next
        /// step's target, taken from the body again, corrects without accumulating).</summary>
        public void BeforeStep(float dt)
        {
            if (!IsAttached) return;
            Vector3 now = BoxCentre(_body.position, _body.rotation);
            if ((now - _placedPosition).magnitude > teleportDistance)
            {
                _collider.Teleport(now.ToNumerics(), _body.rotation.ToNumerics());
                _applied.Reset();  // the forces of the old place say nothing of the new one
            }
            Vector3 omega = _body.angularVelocity;
            float angle = omega.magnitude * dt * Mathf.Rad2Deg;
            Quaternion rotation = angle > 0.0f ? Quaternion.AngleAxis(angle, omega.normalized) * _body.rotation : _body.rotation;
            Vector3 position = BoxCentre(_body.position + LinearVelocity() * dt, rotation);
            _collider.SetTargetPose(position.ToNumerics(), rotation.ToNumerics());
            _placedPosition = position;
        }

        /// <summary>After the world's step: the fluid's force and torque on the box over that step,
        /// averaged with the steps before (<see cref="forceSmoothing"/>) and added to the
        /// Rigidbody for Unity's next physics step (waits for the step to finish on CUDA). Expects
        /// one world step per FixedUpdate: the force is that step's mean.</summary>
        public void AfterStep()
        {
            if (!IsAttached) return;
            LastForce = _collider.GetForce();
            ColliderForce applied = _applied.Add(LastForce);
            if (_body.isKinematic) return;
            _body.AddForce(applied.Force.ToUnity(), ForceMode.Force);
            _body.AddTorque(applied.Torque.ToUnity(), ForceMode.Force);
        }

        void OnDisable() { Detach(); }

        Vector3 HalfExtents()
        {
            Vector3 s = Vector3.Scale(_box.size, transform.lossyScale);
            return 0.5f * new Vector3(Mathf.Abs(s.x), Mathf.Abs(s.y), Mathf.Abs(s.z));
        }

        // The box's centre for a body at this pose: the BoxCollider's centre, scaled, rotated, moved.
        Vector3 BoxCentre(Vector3 position, Quaternion rotation)
        {
            return position + rotation * Vector3.Scale(_box.center, transform.lossyScale);
        }

        Vector3 LinearVelocity()
        {
#if UNITY_6000_0_OR_NEWER
            return _body.linearVelocity;
#else
            return _body.velocity;
#endif
        }

        void OnDrawGizmosSelected()
        {
            if (!IsAttached) return;
            Gizmos.color = Color.cyan;
            Gizmos.DrawRay(_placedPosition, 0.01f * AppliedForce.Force.ToUnity());  // 1 cm per newton
        }
    }
}
