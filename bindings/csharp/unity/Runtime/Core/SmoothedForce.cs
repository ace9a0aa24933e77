using System;

namespace Pbf
{
    /// <summary>
    /// The fluid's force and torque on a body as an engine should apply them: an exponential
    /// moving average over the steps (each step keeps <see cref="Keep"/> of the previous value and
    /// adds the rest of the new one). Why: the coupling is explicit (the force of one step moves
    /// the body in the next), which is unstable where the fluid that a body drags along outweighs
    /// it: its added mass, and above all its added inertia when it turns (a 0.16 m cube of
    /// 500 kg/m³ free to turn, given the raw torque each 1/50 s step, spun up and was flung out
    /// of the pool within 2 s; averaged with Keep 0.8 it floats, tilted as a cube of that density
    /// does). The average leaves a steady force (buoyancy) exactly as it is and delays changes by
    /// about Keep / (1 - Keep) steps (4 at 0.8). PbfFloatingBody uses it in Unity.
    /// </summary>
    public sealed class SmoothedForce
    {
        bool _started;

        /// <param name="keep">0 (the raw force) to 0.95.</param>
        public SmoothedForce(float keep)
        {
            if (!(keep >= 0.0f && keep <= 0.95f)) throw new ArgumentOutOfRangeException("keep", "0..0.95");
            Keep = keep;
        }

        public float Keep { get; private set; }

        /// <summary>The average after the last <see cref="Add"/> (zero before the first).</summary>
        public ColliderForce Value { get; private set; }

        /// <summary>Adds a step's force and torque; returns the new average. The first one after
        /// construction or <see cref="Reset"/> is taken as it is.</summary>
        public ColliderForce Add(ColliderForce step)
        {
            if (!_started)
            {
                Value = step;
                _started = true;
                return step;
            }
            float k = Keep, n = 1.0f - Keep;
            Value = new ColliderForce { Force = k * Value.Force + n * step.Force, Torque = k * Value.Torque + n * step.Torque };
            return Value;
        }

        /// <summary>Forgets the history (a body teleported or re-attached).</summary>
        public void Reset()
        {
            _started = false;
            Value = default(ColliderForce);
        }
    }
}
