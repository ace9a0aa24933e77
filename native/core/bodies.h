// Colliders as bodies: their poses within a step (interpolated on the backend from the step's
// start and end), their broad-phase bounds, and the fluid's force and torque on dynamic ones.
#pragma once
#include "atomics.h"
#include "params.h"

namespace pbf {

// ---- poses -----------------------------------------------------------------------------------
PBF_HD Mat3 rotation_matrix(Quat q) {
    const float x2 = q.x + q.x, y2 = q.y + q.y, z2 = q.z + q.z;
    const float xx = q.x * x2, yy = q.y * y2, zz = q.z * z2;
    const float xy = q.x * y2, xz = q.x * z2, yz = q.y * z2;
    const float wx = q.w * x2, wy = q.w * y2, wz = q.w * z2;
    return Mat3{{1.0f - (yy + zz), xy - wz, xz + wy,  //
                 xy + wz, 1.0f - (xx + zz), yz - wx,  //
                 xz - wy, yz + wx, 1.0f - (xx + yy)}};
}

// Spherical interpolation of unit quaternions along the shorter arc; nearly equal ones are
// interpolated linearly and renormalised (the arc is a line to float precision there).
PBF_HD Quat slerp(Quat a, Quat b, float t) {
    float d = a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
    if (d < 0.0f) {
        b = Quat{-b.x, -b.y, -b.z, -b.w};
        d = -d;
    }
    float wa = 1.0f - t, wb = t;
    if (d < 0.9995f) {
        const float theta = acosf(d), inv_sin = 1.0f / sinf(theta);
        wa = sinf(wa * theta) * inv_sin;
        wb = sinf(wb * theta) * inv_sin;
    }
    Quat q{wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z, wa * a.w + wb * b.w};
    const float inv_len = 1.0f / sqrtf(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    return Quat{q.x * inv_len, q.y * inv_len, q.z * inv_len, q.w * inv_len};
}

// The pose a fraction t (0..1) of the way from a key's start to its end.
PBF_HD ColliderPose pose_between(const ColliderKey& k, float t) {
    return ColliderPose{k.from_position + (k.to_position - k.from_position) * t,
                        rotation_matrix(slerp(k.from_rotation, k.to_rotation, t))};
}

// Fills rows of `count` poses (row r at t = (first + r) / steps: the substeps' boundaries), one
// thread per pose. Between steps: one row at t = 0 of keys whose start is their end.
struct ColliderPoseOp {
    const ColliderKey* keys;
    ColliderPose* poses;
    uint32_t count;
    uint32_t steps;
    uint32_t first = 0;
    PBF_HD void operator()(uint32_t i) const {
        const uint32_t r = i / count;
        poses[i] = pose_between(keys[i - r * count], steps ? float(first + r) / float(steps) : 0.0f);
    }
};

// ---- broad phase -----------------------------------------------------------------------------
// Planes are unbounded: their box is everything (kUnbounded keeps the arithmetic finite).
constexpr float kUnbounded = 1e30f;

// Distance from the collider's origin to its farthest surface point (planes: 0).
PBF_HD float collider_reach(const Collider& c) {
    switch (c.shape) {
        case kShapeSphere:
        case kShapeMesh:
            return c.radius;
        case kShapeCapsule:
            return c.radius + c.half_height;
        case kShapeBox:
            return length(c.half_extents);
        default:
            return 0.0f;
    }
}

// Half size of the world-axis box around the shape at rotation r.
PBF_HD Vec3 oriented_half_size(const Collider& c, const Mat3& r) {
    const float* m = r.m;
    switch (c.shape) {
        case kShapeSphere:
        case kShapeMesh:
            return Vec3{c.radius, c.radius, c.radius};  // a mesh: the ball of its reach
        case kShapeCapsule: {  // the segment along the body's y axis (column 1), then the radius
            const Vec3 axis{fabsf(m[1]), fabsf(m[4]), fabsf(m[7])};
            return axis * c.half_height + Vec3{c.radius, c.radius, c.radius};
        }
        default: {  // box: |R| e
            const Vec3 e = c.half_extents;
            return Vec3{fabsf(m[0]) * e.x + fabsf(m[1]) * e.y + fabsf(m[2]) * e.z,
                        fabsf(m[3]) * e.x + fabsf(m[4]) * e.y + fabsf(m[5]) * e.z,
                        fabsf(m[6]) * e.x + fabsf(m[7]) * e.y + fabsf(m[8]) * e.z};
        }
    }
}

// A box holding the collider at every pose of the key (the position moves linearly, the
// rotation turns by slerp through an angle θ ≤ π about one axis). A body point at offset q
// from the origin turns along an arc that stays within |q|(1 - cos(θ/2)) (the arc's sagitta)
// of the chord between its two ends, so the shape lies within the larger of its two ends'
// oriented boxes grown by the sagitta of its reach, swept along the path; the ball of its
// reach bounds it too, and the tighter of the two is taken per axis. A shape that does not
// turn: its oriented box swept along the path.
PBF_HD Bounds swept_bounds(const Collider& c, const ColliderKey& k) {
    if (c.shape == kShapePlane)
        return Bounds{Vec3{-kUnbounded, -kUnbounded, -kUnbounded}, Vec3{kUnbounded, kUnbounded, kUnbounded}};
    const Quat a = k.from_rotation, b = k.to_rotation;
    const bool turns = a.x != b.x || a.y != b.y || a.z != b.z || a.w != b.w;
    Vec3 half = oriented_half_size(c, rotation_matrix(a));
    if (turns) {
        const float reach = collider_reach(c);
        // cos(θ/2) = |a·b| for unit quaternions; rounding can push it past 1.
        const float cos_half = fminf(fabsf(a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w), 1.0f);
        const float sagitta = reach * (1.0f - cos_half);
        half = max3(half, oriented_half_size(c, rotation_matrix(b))) + Vec3{sagitta, sagitta, sagitta};
        half = min3(half, Vec3{reach, reach, reach});
    }
    return Bounds{min3(k.from_position, k.to_position) - half, max3(k.from_position, k.to_position) + half};
}

// Whether the box [lo, hi] meets b.
PBF_HD bool overlaps(const Bounds& b, Vec3 lo, Vec3 hi) {
    return lo.x <= b.hi.x && hi.x >= b.lo.x && lo.y <= b.hi.y && hi.y >= b.lo.y && lo.z <= b.hi.z && hi.z >= b.lo.z;
}

// ---- the fluid's force on dynamic colliders --------------------------------------------------
// A particle of mass m displaced by Δ within a substep of Δt leaves it with its velocity
// changed by Δ/Δt (v = (x* - x)/Δt): the collider that displaced it gave it the impulse
// m·Δ/Δt and received the opposite. Recorded at the particle's position, about the collider's
// centre at the substep's end pose.
PBF_HD_COLD void record_push(const ColliderView& cv, const Collider& c, const ColliderPose& pose, Vec3 at, Vec3 moved) {
    const Vec3 impulse = moved * -cv.impulse_scale;
    const Vec3 centre = pose.position + mul(pose.rotation, c.center_local);
    ColliderForce* row = cv.impulses + c.row;
    atomic_add_vec3_pair_shared(&row->force, impulse, &row->torque, cross(at - centre, impulse));
}

// One thread per collider at the end of a step: the mean force and torque over the step (the
// impulses over its duration) of dynamic colliders, zero for the others.
struct ColliderForceOp {
    const Collider* shapes;
    const ColliderForce* impulses;
    ColliderForce* forces;
    float inv_step_dt;
    PBF_HD void operator()(uint32_t k) const {
        const Collider& c = shapes[k];
        const bool dynamic = (c.flags & kColliderDynamic) != 0;
        const ColliderForce& j = impulses[c.row];
        forces[c.row] = dynamic ? ColliderForce{j.force * inv_step_dt, j.torque * inv_step_dt}
                                : ColliderForce{Vec3{0.0f, 0.0f, 0.0f}, Vec3{0.0f, 0.0f, 0.0f}};
    }
};

}  // namespace pbf
