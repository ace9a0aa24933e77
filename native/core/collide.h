// Particle-vs-collider projection: a particle centre is kept at least `radius` outside every
// collider and inside the domain walls. Position-based, so a moving collider pushes fluid by
// displacing it; the velocity update turns that displacement into velocity.
#pragma once
#include "params.h"

namespace pbf {

// Signed distance from a collider's surface at pose `pose`, and the outward normal there.
PBF_HD float collider_distance(const Collider& c, const ColliderPose& pose, Vec3 p, Vec3& normal) {
    const Vec3 q = mul_transpose(pose.rotation, p - pose.position);  // local coordinates
    Vec3 n_local;
    float dist;
    switch (c.shape) {
        case kShapePlane:
            n_local = Vec3{0.0f, 1.0f, 0.0f};
            dist = q.y;
            break;
        case kShapeSphere:
        case kShapeCapsule: {
            const float hh = c.shape == kShapeCapsule ? c.half_height : 0.0f;
            const Vec3 d = q - Vec3{0.0f, clampf(q.y, -hh, hh), 0.0f};
            const float len = length(d);
            n_local = len > 1e-12f ? d * (1.0f / len) : Vec3{0.0f, 1.0f, 0.0f};
            dist = len - c.radius;
            break;
        }
        default: {  // box
            const Vec3 e = c.half_extents;
            const Vec3 a = Vec3{fabsf(q.x) - e.x, fabsf(q.y) - e.y, fabsf(q.z) - e.z};
            const Vec3 outside = max3(a, Vec3{0.0f, 0.0f, 0.0f});
            const float out_len = length(outside);
            if (out_len > 0.0f) {
                dist = out_len;
                n_local = Vec3{copysignf(outside.x, q.x), copysignf(outside.y, q.y), copysignf(outside.z, q.z)} *
                          (1.0f / out_len);
            } else {  // inside: leave through the nearest face
                if (a.x >= a.y && a.x >= a.z) { dist = a.x; n_local = Vec3{copysignf(1.0f, q.x), 0.0f, 0.0f}; }
                else if (a.y >= a.z) { dist = a.y; n_local = Vec3{0.0f, copysignf(1.0f, q.y), 0.0f}; }
                else { dist = a.z; n_local = Vec3{0.0f, 0.0f, copysignf(1.0f, q.z)}; }
            }
            break;
        }
    }
    normal = mul(pose.rotation, n_local);
    return dist;
}

// Projects predicted position p (the particle was at x_old at the start of the substep).
PBF_HD Vec3 collide(const SimConstants& s, const ColliderSet& colliders, Vec3 p, Vec3 x_old) {
    for (uint32_t k = 0; k < colliders.count; ++k) {
        const Collider& c = colliders.items[k];
        Vec3 n;
        const float d = collider_distance(c, c.cur, p, n);
        if (d >= s.radius) continue;
        p += n * (s.radius - d);
        if (c.friction > 0.0f) {
            // Where the contact point was at the start of the substep, had it moved with the collider.
            const Vec3 local = mul_transpose(c.cur.rotation, p - c.cur.position);
            const Vec3 carried = c.prev.position + mul(c.prev.rotation, local);
            // The particle moved p - x_old, the surface point p - carried: relative motion is the difference.
            const Vec3 rel = carried - x_old;
            const Vec3 tangential = rel - n * dot(n, rel);
            p -= tangential * c.friction;
        }
    }
    return min3(max3(p, s.wall_min), s.wall_max);
}

}  // namespace pbf
