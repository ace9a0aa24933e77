// Particles against colliders and the domain walls: projection (a particle centre stays at least
// `radius` outside every collider and inside the walls), Coulomb friction, a swept test against
// fast colliders, and the boundary density that walls and colliders contribute.
#pragma once
#include "bodies.h"
#include "collider_grid.h"
#include "params.h"
#include "sdf.h"

namespace pbf {

// Signed distance from a collider's surface at pose `pose`, and the outward normal there.
// meshes: the mesh table (read by mesh colliders only).
PBF_HD float collider_distance(const Collider& c, const ColliderPose& pose, Vec3 p, Vec3& normal,
                               const MeshView* meshes) {
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
        case kShapeMesh:
            dist = mesh_distance(meshes[c.mesh], q, n_local);
            break;
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
                if (a.x >= a.y && a.x >= a.z) {
                    dist = a.x;
                    n_local = Vec3{copysignf(1.0f, q.x), 0.0f, 0.0f};
                } else if (a.y >= a.z) {
                    dist = a.y;
                    n_local = Vec3{0.0f, copysignf(1.0f, q.y), 0.0f};
                } else {
                    dist = a.z;
                    n_local = Vec3{0.0f, 0.0f, copysignf(1.0f, q.z)};
                }
            }
            break;
        }
    }
    normal = mul(pose.rotation, n_local);
    return dist;
}

// A particle that the walls hold inside a box: one whose push out along the normal of the
// closest point (collider_distance) would end beyond a domain wall, as between a plate and the
// floor or a wall closer to it than a particle diameter. Pushed that way and clamped back, it
// stays inside at every projection until the box or the pressure moves it far enough that the
// normal turns, and then crosses the rest in one substep (100 m/s at 1e-4 s from a plate swept
// at 2 m/s). Finds the face, of the box's six, whose normal frees it in the shortest move
// ending within the walls: along axis a, the move that brings its distance from the box to
// `radius` given how far it lies outside the other two slabs. The move is at most
// 2√(radius · depth) and h: a particle `depth` into the shell under an edge leaves it by
// √(2 radius depth) sideways; a longer move (across a large box, for a particle barely in
// contact) would carry it into fluid it does not touch. Returns false where the push is not
// blocked (a push at a slant to a wall is left to clamp_into_walls, whose rounds slide the
// particle along the wall) or no face frees it within that.
PBF_HD bool wall_detour(const WorldConstants& s, const Collider& c, const ColliderPose& pose, Vec3 p, Vec3& normal,
                        float& move) {
    if (c.shape != kShapeBox) return false;
    Vec3 n;
    const float d = collider_distance(c, pose, p, n, nullptr);
    if (d >= s.radius) return false;
    // Blocked: the wall clamp would undo nearly all of the push, as it carries p out through a
    // wall by more than 0.9 of its length.
    const auto beyond = [&](Vec3 x) {
        const Vec3 lo = max3(s.wall_min - x, Vec3{0.0f, 0.0f, 0.0f});
        const Vec3 hi = max3(x - s.wall_max, Vec3{0.0f, 0.0f, 0.0f});
        return lo.x + lo.y + lo.z + hi.x + hi.y + hi.z;
    };
    const float beyond_p = beyond(p);
    const auto blocked = [&](Vec3 dir, float length) { return beyond(p + dir * length) - beyond_p > 0.9f * length; };
    if (!blocked(n, s.radius - d)) return false;
    const Vec3 q = mul_transpose(pose.rotation, p - pose.position);
    const float local[3] = {q.x, q.y, q.z};
    const float half[3] = {c.half_extents.x, c.half_extents.y, c.half_extents.z};
    float outside[3];
    for (int a = 0; a < 3; ++a) outside[a] = fmaxf(fabsf(local[a]) - half[a], 0.0f);
    bool found = false;
    move = fminf(s.h, 2.0f * sqrtf(s.radius * (s.radius - d)));
    for (int a = 0; a < 3; ++a) {
        const float o1 = outside[(a + 1) % 3], o2 = outside[(a + 2) % 3];
        const float reach = sqrtf(fmaxf(s.radius * s.radius - o1 * o1 - o2 * o2, 0.0f));
        for (int side = -1; side <= 1; side += 2) {
            const float length = half[a] + reach - float(side) * local[a];
            if (!(length > 0.0f) || length > move) continue;
            const Vec3 dir = mul(pose.rotation, Vec3{a == 0 ? float(side) : 0.0f, a == 1 ? float(side) : 0.0f,
                                                     a == 2 ? float(side) : 0.0f});
            if (blocked(dir, length)) continue;
            move = length;
            normal = dir;
            found = true;
        }
    }
    return found;
}

// Where a particle that moved from x_old to p met collider c, seen from the collider (which
// moved from prev to cur over the substep): the segment is marched in the collider's frame by
// its distance field (sphere tracing, at most 16 probes, then the last point reached) up to the first point within `radius`
// of the surface, or, for a particle that started closer than that (in contact), up to the
// surface itself. Returns false when it did not get there. Without it a particle could pass
// through a collider that moves (or that it crosses) more than about its thickness in one
// substep, or be pushed through a thin one from contact and leave by the far face.
PBF_HD bool swept_contact(const Collider& c, const ColliderPose& prev, const ColliderPose& cur, Vec3 x_old, Vec3 p,
                          float radius, const MeshView* meshes, Vec3& hit) {
    // Both ends in the end pose's world frame: the collider stands still there and the particle
    // moves from a to b.
    const Vec3 a = cur.position + mul(cur.rotation, mul_transpose(prev.rotation, x_old - prev.position));
    const Vec3 ab = p - a;
    const float len = length(ab);
    if (len <= 1e-3f * radius) return false;
    Vec3 n;
    const float d_start = collider_distance(c, cur, a, n, meshes);
    if (d_start <= 0.0f) return false;  // started inside: the end-pose projection handles it
    // In contact at the start (within the radius, resting or sliding): only a crossing of the
    // surface itself counts, so a sliding particle keeps sliding.
    const float reach = d_start < 1.001f * radius ? 0.5f * d_start : radius;
    // A short move that ends clear of that reach: the end-pose projection handles it.
    if (len <= radius && collider_distance(c, cur, p, n, meshes) > reach) return false;
    const Vec3 dir = ab * (1.0f / len);
    // A sampled field can overestimate the distance slightly near convex ridges (trilinear
    // interpolation of a true distance): mesh colliders march 0.9 of it.
    const float step_scale = c.shape == kShapeMesh ? 0.9f : 1.0f;
    float t = 0.0f;
    for (int k = 0; k < 16; ++k) {
        const Vec3 x = a + dir * t;
        const float d = collider_distance(c, cur, x, n, meshes) - reach;
        if (d <= 1e-4f * radius) {
            hit = x;
            return true;
        }
        t += d * step_scale;
        if (t >= len) return false;
    }
    // Out of probes (a path grazing the surface converges slowly): stop at the last point
    // reached, which is still clear of the surface, rather than let the projection pick a side.
    hit = a + dir * t;
    return true;
}

// One collider's contact with a particle that moved from x_old to p over the substep: the
// swept test, then the projection to `radius` outside the surface at the end pose, then
// friction. Friction is Coulomb's, in position form: the tangential motion relative to the
// collider over the substep is removed up to μ times the depth this projection pushed out.
PBF_HD Vec3 contact(const WorldConstants& s, const Collider& c, const ColliderPose& prev, const ColliderPose& cur,
                    Vec3 p, Vec3 x_old, const MeshView* meshes) {
    Vec3 hit;
    if (swept_contact(c, prev, cur, x_old, p, s.radius, meshes, hit)) p = hit;
    Vec3 n;
    const float d = collider_distance(c, cur, p, n, meshes);
    if (d >= s.radius) return p;
    const float depth = s.radius - d;
    p += n * depth;
    if (c.friction > 0.0f) {
        // Where the contact point was at the start of the substep, had it moved with the collider.
        const Vec3 local = mul_transpose(cur.rotation, p - cur.position);
        const Vec3 carried = prev.position + mul(prev.rotation, local);
        // The particle moved p - x_old, the surface point p - carried: relative motion is the difference.
        const Vec3 rel = carried - x_old;
        const Vec3 tangential = rel - n * dot(n, rel);
        const float t_len = length(tangential);
        const float removable = c.friction * depth;
        p -= t_len <= removable ? tangential : tangential * (removable / t_len);
    }
    return p;
}

// Rounds of collider projection and wall clamp after a collide or project_out_at_start. A
// collider's projection can push a particle through a wall and the wall's clamp back into the
// collider (a sphere sunk into the floor, a box against a wall), which left it inside to be
// pushed out again by the next projection, each time further along the wall: in a substep of
// 1e-7 s that crawl was a velocity of 100 m/s. Alternating the two moves it along the wall to
// where it clears both, where there is such a place near.
constexpr uint32_t kProjectRounds = 8;

// The walls' clamp, with a restitution of kWallRestitution: a particle driven a depth beyond a
// wall ends that fraction of the depth inside it, up to kWallRestitutionReach radii. A plain
// clamp maps every point beyond a corner onto the corner, and every point beyond an edge onto
// one point of it per position along the edge, so particles driven into a corner or an edge
// together (a block thrown there, whose lattice columns share coordinates exactly) ended on one
// position, with no direction between them. With the restitution distinct depths end at distinct
// positions; the energy it returns is kWallRestitution² of the normal kinetic energy.
constexpr float kWallRestitution = 1e-3f;
constexpr float kWallRestitutionReach = 1e-2f;
PBF_HD Vec3 clamp_to_walls(const WorldConstants& s, Vec3 p) {
    const Vec3 c = min3(max3(p, s.wall_min), s.wall_max);
    const float reach = kWallRestitutionReach * s.radius;
    const Vec3 back = (c - p) * kWallRestitution;
    const Vec3 q =
        c + Vec3{clampf(back.x, -reach, reach), clampf(back.y, -reach, reach), clampf(back.z, -reach, reach)};
    return min3(max3(q, s.wall_min), s.wall_max);
}

// Moves p out of every collider it overlaps at `poses`, to `radius` outside the surface, plus
// its depth inside where `mirror` (no sweep, no friction, no reaction recorded); returns whether
// it was inside one.
// A particle within `slack` of that distance counts as outside.
PBF_HD bool push_out_of_colliders(const WorldConstants& s, const ColliderView& cv, const ColliderPose* poses, Vec3& p,
                                  bool mirror = false, float slack = 0.0f) {
    const Vec3 r{s.radius, s.radius, s.radius};
    bool inside = false;
    for_each_collider_on_path(cv, p, p, s.radius, [&](uint32_t k) {
        const Collider& c = cv.shapes[k];
        if (!overlaps(c.bounds, p - r, p + r)) return;
        Vec3 n;
        const float d = collider_distance(c, poses[k], p, n, cv.meshes);
        if (d < s.radius - slack) {
            p += n * (s.radius - d + (mirror ? fmaxf(-d, 0.0f) : 0.0f));
            inside = true;
        }
    });
    return inside;
}

// Where a push out of one collider landed p inside another (a sphere sunk into a floor plane,
// a box resting on a capsule: shells that overlap), pushes out of them again, alternately, up to
// kProjectRounds - 1 times or until p overlaps none: alternating moves it along both surfaces to
// where it clears them, where there is such a place near. Pushed once, a particle in such a
// wedge stayed inside the collider pushed first, and the substep's projection out of it became
// velocity, depth / Δt.
PBF_HD void push_out_in_rounds(const WorldConstants& s, const ColliderView& cv, const ColliderPose* poses, Vec3& p) {
    if (cv.count < 2) return;
    for (uint32_t round = 1; round < kProjectRounds; ++round)
        if (!push_out_of_colliders(s, cv, poses, p)) return;
}

// Frees a particle that ends a substep held inside a box by a wall (wall_detour), in x alone:
// the substep's velocity is already taken, and the next starts clear of the box. Only a
// particle on a wall (within the clamp's restitution of it) can be held so; the others pay six
// comparisons.
PBF_HD Vec3 free_from_walls(const WorldConstants& s, const ColliderView& cv, Vec3 p) {
    const float slack = kWallRestitutionReach * s.radius;
    const bool on_wall = p.x <= s.wall_min.x + slack || p.y <= s.wall_min.y + slack || p.z <= s.wall_min.z + slack ||
                         p.x >= s.wall_max.x - slack || p.y >= s.wall_max.y - slack || p.z >= s.wall_max.z - slack;
    if (!on_wall) return p;
    const Vec3 r{s.radius, s.radius, s.radius};
    for_each_collider_on_path(cv, p, p, s.radius, [&](uint32_t k) {
        const Collider& c = cv.shapes[k];
        if (!overlaps(c.bounds, p - r, p + r)) return;
        Vec3 n;
        float move;
        if (wall_detour(s, c, cv.cur[k], p, n, move)) p += n * move;
    });
    return clamp_to_walls(s, p);
}

// p clamped into the walls; then, while that clamp moved p back into a collider, moved out of
// the colliders at `poses` (push_out_of_colliders: the geometry's resolution of a wedge, not a
// contact's response) and clamped again, up to kProjectRounds times. A particle that meets no
// wall pays one comparison.
// The rounds end once the clamp leaves p within kWedgeSlack of a radius of the collider's
// reach. Alternated to convergence, every particle a collider pressed into a pocket of the walls
// (a body in a corner) ended on the pocket's one clear point, all on one position, with no
// direction between them; stopped that close to it, each ends where its own path brings it.
constexpr float kWedgeSlack = 1e-2f;
PBF_HD Vec3 clamp_into_walls(const WorldConstants& s, const ColliderView& cv, const ColliderPose* poses, Vec3 p) {
    for (uint32_t round = 0;; ++round) {
        const Vec3 walled = clamp_to_walls(s, p);
        if (cv.count == 0 || round + 1 == kProjectRounds || (walled.x == p.x && walled.y == p.y && walled.z == p.z))
            return walled;
        p = walled;
        if (!push_out_of_colliders(s, cv, poses, p, false, kWedgeSlack * s.radius)) return p;
    }
}

// Projects predicted position p (the particle was at x_old at the start of the substep) out of
// every collider whose step bounds its path's box (grown by the radius) meets, then into the
// walls (clamp_into_walls). A dynamic collider's push is recorded as its reaction (record_push).
// The candidates are those of the path's box; each is tested against the path to where the
// earlier contacts moved p.
PBF_HD Vec3 collide(const WorldConstants& s, const ColliderView& cv, Vec3 p, Vec3 x_old) {
    const Vec3 r{s.radius, s.radius, s.radius};
    for_each_collider_on_path(cv, x_old, p, s.radius, [&](uint32_t k) {
        const Collider& c = cv.shapes[k];
        if (!overlaps(c.bounds, min3(x_old, p) - r, max3(x_old, p) + r)) return;
        const Vec3 moved = contact(s, c, cv.prev[k], cv.cur[k], p, x_old, cv.meshes);
        const Vec3 push = moved - p;
        if (cv.impulses && (c.flags & kColliderDynamic) && length_sq(push) > 0.0f)
            record_push(cv, c, cv.cur[k], moved, push);
        p = moved;
    });
    return clamp_into_walls(s, cv, cv.cur, p);
}

// Moves p out of every collider it overlaps at the substep's start poses, to `radius` outside
// the surface as contact's projection does (no sweep, no friction, no reaction recorded), then
// into the walls. For overlaps no motion made (a collider created or teleported into the
// fluid, a block emitted into one): the caller moves x itself, so the move gives no velocity.
// With `mirror`, a particle a depth d inside ends r + d outside, along the same normal: the
// overlapped layers keep their order and spacing outside a flat face, where ending all at r
// outside piled them onto one sheet, whose particles have no direction between them to be
// separated along (the settling iterations that follow spread them only within it).
// Where the mirror carries a particle past a wall, it is folded back in by the same reflection
// at the wall: clamped, the overlapped layers beyond the wall would pile onto its face as one
// sheet, which the settling iterations leave compressed and whose pressure throws water along
// the wall (docs/physics.md, Overlaps).
PBF_HD float fold_into(float p, float lo, float hi) { return p < lo ? 2.0f * lo - p : p > hi ? 2.0f * hi - p : p; }
PBF_HD Vec3 project_out_at_start(const WorldConstants& s, const ColliderView& cv, Vec3 p, bool mirror = false) {
    if (!push_out_of_colliders(s, cv, cv.prev, p, mirror)) return clamp_into_walls(s, cv, cv.prev, p);
    if (mirror)
        p = Vec3{fold_into(p.x, s.wall_min.x, s.wall_max.x), fold_into(p.y, s.wall_min.y, s.wall_max.y),
                 fold_into(p.z, s.wall_min.z, s.wall_max.z)};
    push_out_in_rounds(s, cv, cv.prev, p);
    return clamp_into_walls(s, cv, cv.prev, p);
}

// ---- boundary density ------------------------------------------------------------------------
// A solid half-space at distance y from a particle, filled at rest density, adds ρ0·Φ(y/h)
// to its poly6 density, with Φ(t) = ∫_t^1 (315/256)(1 - s²)⁴ ds (the poly6 kernel integrated over
// the half-space): Φ(0) = 1/2, Φ(1) = 0. Walls and colliders are treated as locally flat at
// their closest point (exact for walls and planes; for spheres, capsules and boxes an
// approximation near curved parts, edges and corners). γ (boundary_scale) scales the continuum
// integral to the particle lattice, so a rest lattice against a wall has rest density.
PBF_HD float boundary_phi(float t) {
    if (t >= 1.0f) return 0.0f;
    t = fmaxf(t, 0.0f);
    const float t2 = t * t;
    // t - 4t³/3 + 6t⁵/5 - 4t⁷/7 + t⁹/9, by Horner in t²
    const float f = t * (1.0f + t2 * (-4.0f / 3.0f + t2 * (6.0f / 5.0f + t2 * (-4.0f / 7.0f + t2 * (1.0f / 9.0f)))));
    return 0.5f - (315.0f / 256.0f) * f;
}
// dΦ/dt = -(315/256)(1 - t²)⁴.
PBF_HD float boundary_phi_slope(float t) {
    if (t >= 1.0f) return 0.0f;
    t = fmaxf(t, 0.0f);
    const float u = 1.0f - t * t;
    const float u2 = u * u;
    return -(315.0f / 256.0f) * u2 * u2;
}

struct BoundarySample {
    float density_ratio;  // Σ γΦ: the boundary's share of ρ/ρ0
    Vec3 gradient;        // its gradient in x (1/m): points into the boundary
};

// One half-space at distance y along n: γΦ(y/h) and its gradient.
PBF_HD BoundarySample half_space(const WorldConstants& s, float y, Vec3 n) {
    const float t = y * (1.0f / s.h);
    return BoundarySample{s.boundary_scale * boundary_phi(t), n * (s.boundary_scale * boundary_phi_slope(t) / s.h)};
}

// The kernel mass within a half-space whose plane lies at signed depth u from the particle
// (u > 0: the particle is inside it), and its derivative in u.
PBF_HD float half_space_share(float u, float inv_h, float& slope) {
    const float t = fabsf(u) * inv_h;
    slope = -boundary_phi_slope(t) * inv_h;
    return u >= 0.0f ? 1.0f - boundary_phi(t) : boundary_phi(t);
}

// A box's share, from its three slabs: each slab's share S_a is exact (the kernel mass between
// two parallel planes), and the box's is Π S_a - κ (G_x G_y S_z + G_x G_z S_y + G_y G_z S_x).
// The product alone treats the kernel as separable, which poly6 on the particle lattice is not:
// it gave the quadrant beyond an edge (a particle one radius outside both faces) 37 % more than
// the rest lattice misses there and the site beside it 7 % less (the two always sum to the
// face's share), pushing the water off the edges: a 0.24 m box held at half depth felt 7 % more
// than ρgV_sub (its top edges are dry, so nothing cancels it as on a submerged box). The κ term
// is each edge quadrant's non-separable part, odd in the signed depth of either plane (so a
// quadrant and its neighbour across a plane still sum to the exact half-space): -κ g(u) g(v),
// g(u) = sgn(u) Φ(1 - 2Φ) at t = |u|/h (zero on the plane and beyond h), summed over a slab's two
// planes into G_a. κ (box_edge_scale, lattice.h) gives a rest lattice rest density at an edge's
// diagonal site, as γ does at a face; faces keep their exact share (G vanishes there).
// Approximation: corners take the edges' terms only. The closest point's half-space, which the
// other analytic shapes use, counts the whole tangent plane there: it packed too much boundary
// density around a box's edges and gave a submerged 0.24 m box 8 % more than ρgV.
//
// sgn(u) g(|u|/h) of a plane at signed depth u, and its derivative in u.
PBF_HD float box_edge_term(float u, float inv_h, float& slope) {
    const float t = fabsf(u) * inv_h, p = boundary_phi(t);
    slope = boundary_phi_slope(t) * (1.0f - 4.0f * p) * inv_h;
    const float g = p * (1.0f - 2.0f * p);
    return u >= 0.0f ? g : -g;
}

PBF_HD BoundarySample box_boundary(const WorldConstants& s, const Collider& c, const ColliderPose& pose, Vec3 p) {
    const Vec3 q = mul_transpose(pose.rotation, p - pose.position);
    const float inv_h = 1.0f / s.h;
    const float qa[3] = {q.x, q.y, q.z}, ea[3] = {c.half_extents.x, c.half_extents.y, c.half_extents.z};
    float S[3], dS[3], G[3], dG[3];
    for (int a = 0; a < 3; ++a) {
        float below, above;  // d/du of the faces at -e (depth e + q) and +e (depth e - q)
        S[a] = half_space_share(ea[a] + qa[a], inv_h, below) + half_space_share(ea[a] - qa[a], inv_h, above) - 1.0f;
        dS[a] = below - above;
        G[a] = box_edge_term(ea[a] + qa[a], inv_h, below) + box_edge_term(ea[a] - qa[a], inv_h, above);
        dG[a] = below - above;
    }
    const float k = s.box_edge_scale;
    const float share = S[0] * S[1] * S[2] - k * (G[0] * G[1] * S[2] + G[0] * G[2] * S[1] + G[1] * G[2] * S[0]);
    if (!(share > 0.0f)) return BoundarySample{0.0f, Vec3{0.0f, 0.0f, 0.0f}};
    const Vec3 g{dS[0] * S[1] * S[2] - k * (dG[0] * G[1] * S[2] + dG[0] * G[2] * S[1] + G[1] * G[2] * dS[0]),
                 S[0] * dS[1] * S[2] - k * (G[0] * dG[1] * S[2] + G[0] * G[2] * dS[1] + dG[1] * G[2] * S[0]),
                 S[0] * S[1] * dS[2] - k * (G[0] * G[1] * dS[2] + G[0] * dG[2] * S[1] + G[1] * dG[2] * S[0])};
    return BoundarySample{s.boundary_scale * share, mul(pose.rotation, g) * s.boundary_scale};
}

// Collider c's share at p, which lies at distance d < h from it along normal n: a mesh's from
// its precomputed field (exact at its edges, corners and curved parts: SdfBoundaryOp), a box's
// from its slabs (box_boundary), the other analytic shapes' from the half-space at their
// closest point.
PBF_HD BoundarySample collider_boundary(const WorldConstants& s, const Collider& c, const ColliderPose& pose, Vec3 p,
                                        float d, Vec3 n, const MeshView* meshes) {
    if (c.shape == kShapeBox) return box_boundary(s, c, pose, p);
    if (c.shape != kShapeMesh) return half_space(s, d, n);
    Vec3 g;
    const float share = mesh_boundary(meshes[c.mesh], mul_transpose(pose.rotation, p - pose.position), g);
    return BoundarySample{s.boundary_scale * share, mul(pose.rotation, g) * s.boundary_scale};
}

// Walls meeting at an edge or corner overlap: their shares combine as 1 - Π(1 - φ_k) (the
// overlap counted once, as if independent) rather than Σ φ_k, which over-counted a rest
// lattice's corner by ~9 %. W tracks P = Π(1 - φ_k) and its gradient.
struct WallProduct {
    float p = 1.0f;
    Vec3 grad{0.0f, 0.0f, 0.0f};
    PBF_HD void add(const BoundarySample& b) {
        grad = grad * (1.0f - b.density_ratio) - b.gradient * p;
        p *= 1.0f - b.density_ratio;
    }
};

// The walls' and colliders' contribution at position p. n points from the boundary into the
// fluid; the density falls along it. Colliders add to the walls (they rarely overlap them).
PBF_HD BoundarySample walls_boundary(const WorldConstants& s, Vec3 p) {
    WallProduct w;
    const Vec3 lo = p - s.boundary_min, hi = s.boundary_max - p;
    if (lo.x < s.h) w.add(half_space(s, lo.x, Vec3{1.0f, 0.0f, 0.0f}));
    if (hi.x < s.h) w.add(half_space(s, hi.x, Vec3{-1.0f, 0.0f, 0.0f}));
    if (lo.y < s.h) w.add(half_space(s, lo.y, Vec3{0.0f, 1.0f, 0.0f}));
    if (hi.y < s.h) w.add(half_space(s, hi.y, Vec3{0.0f, -1.0f, 0.0f}));
    if (lo.z < s.h) w.add(half_space(s, lo.z, Vec3{0.0f, 0.0f, 1.0f}));
    if (hi.z < s.h) w.add(half_space(s, hi.z, Vec3{0.0f, 0.0f, -1.0f}));
    return BoundarySample{1.0f - w.p, -w.grad};
}

// Calls f(k, collider, its share at p) for each collider (at its current pose) within h of p.
template <class F>
PBF_HD void for_each_collider_share(const WorldConstants& s, const ColliderView& cv, Vec3 p, F&& f) {
    for_each_collider_near(cv, p, s.h, [&](uint32_t k) {
        const Collider& col = cv.shapes[k];
        Vec3 n;
        const float d = collider_distance(col, cv.cur[k], p, n, cv.meshes);
        if (d < s.h) f(k, col, collider_boundary(s, col, cv.cur[k], p, d, n, cv.meshes));
    });
}

// The boundary's push on a particle at p (its share of Δp: ∇C_boundary·λ, DeltaOp) recorded
// as the reaction on each dynamic collider within h.
PBF_HD void record_boundary_push(const WorldConstants& s, const ColliderView& cv, Vec3 p, float lambda) {
    if (!cv.impulses || cv.dynamic_count == 0 || lambda == 0.0f) return;
    for_each_collider_share(s, cv, p, [&](uint32_t k, const Collider& c, const BoundarySample& share) {
        if (c.flags & kColliderDynamic) record_push(cv, c, cv.cur[k], p, share.gradient * lambda);
    });
}

// Which colliders near a particle take the reaction of its boundary push, in one register:
// none near, only static ones, several with a dynamic one among them (their parts are summed
// again by a second walk), or the index of the one collider near, which is dynamic (the usual
// case: its part is the colliders' whole share).
constexpr uint32_t kSeveralNear = 0xfffffffdu, kStaticNear = 0xfffffffeu, kNoneNear = 0xffffffffu;
PBF_HD uint32_t next_reacting(uint32_t state, uint32_t k, bool dynamic) {
    if (state == kNoneNear) return dynamic ? k : kStaticNear;
    if (state == kStaticNear) return dynamic ? kSeveralNear : kStaticNear;
    return kSeveralNear;
}

// The colliders' share at p (boundary_at without the walls) and which of them react.
struct ColliderShares {
    float density_ratio = 0.0f;
    Vec3 gradient{0.0f, 0.0f, 0.0f};
    uint32_t reacting = kNoneNear;
};
PBF_HD ColliderShares collider_shares(const WorldConstants& s, const ColliderView& cv, Vec3 p) {
    ColliderShares c;
    for_each_collider_share(s, cv, p, [&](uint32_t k, const Collider& col, const BoundarySample& part) {
        c.density_ratio += part.density_ratio;
        c.gradient += part.gradient;
        c.reacting = next_reacting(c.reacting, k, (col.flags & kColliderDynamic) != 0);
    });
    return c;
}

// The walls' and the colliders' share at p.
PBF_HD BoundarySample boundary_at(const WorldConstants& s, const ColliderView& cv, Vec3 p) {
    const BoundarySample walls = walls_boundary(s, p);
    const ColliderShares colliders = collider_shares(s, cv, p);
    return BoundarySample{walls.density_ratio + colliders.density_ratio, walls.gradient + colliders.gradient};
}

// record_boundary_push for shares taken at p: the one dynamic collider's from them, several by
// walking them again.
PBF_HD void record_shares_push(const WorldConstants& s, const ColliderView& cv, Vec3 p, const ColliderShares& c,
                               float lambda) {
    if (c.reacting >= kStaticNear || lambda == 0.0f) return;
    if (c.reacting == kSeveralNear)
        record_boundary_push(s, cv, p, lambda);
    else
        record_push(cv, cv.shapes[c.reacting], cv.cur[c.reacting], p, c.gradient * lambda);
}

}  // namespace pbf
