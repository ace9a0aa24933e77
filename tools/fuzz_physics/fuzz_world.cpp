// Drawing a random valid world (fuzz_world.h). Ranges are the header's documented valid ranges
// where it gives one; where it gives none (particle radius, rest density, speeds, sizes) they
// span what games use, in units of the particle spacing s = 2·radius so every world is resolved
// alike. Worlds stay small (a few hundred to ~2k particles, 20-40 frames) so a thousand of them
// run in minutes on two CPU cores.
#include "fuzz_world.h"

#include <cstdio>
#include <sstream>

namespace fuzz {

namespace {

constexpr float kPi = 3.14159265358979f;

V3 lerp3(const V3& lo, const V3& hi, Rng& rng) {
    return {rng.uniform(lo[0], hi[0]), rng.uniform(lo[1], hi[1]), rng.uniform(lo[2], hi[2])};
}

pbf_solver_params draw_solver(Rng& rng) {
    pbf_solver_params p = pbf_solver_params_default();
    if (rng.chance(0.35)) return p;  // the defaults, as most games ship them
    auto maybe = [&](double probability) { return rng.chance(probability); };
    if (maybe(0.5)) p.iterations = rng.chance(0.9) ? uint32_t(rng.integer(1, 8)) : uint32_t(rng.integer(9, 64));
    if (maybe(0.25)) p.substeps = uint32_t(rng.integer(1, 64));
    if (maybe(0.3)) p.relaxation = rng.log_uniform(0.05, 20.0);
    if (maybe(0.3)) p.scorr_k = rng.uniform(0.0, 1.0);
    if (maybe(0.3)) p.scorr_n = rng.uniform(1.0, 8.0);
    if (maybe(0.3)) p.scorr_dq = rng.uniform(0.01, 0.99);
    if (maybe(0.3)) p.xsph_c = rng.uniform(0.0, 1.0);
    if (maybe(0.5)) p.vorticity_epsilon = rng.chance(0.6) ? 0.0f : rng.log_uniform(1e-4, 1.0);
    if (maybe(0.3)) p.ldc_enabled = rng.chance(0.5) ? 1u : 0u;
    if (maybe(0.3)) p.ldc_gain = rng.uniform(0.0, 1.0);
    if (maybe(0.2)) p.max_speed = rng.log_uniform(1.0, 1000.0);
    if (maybe(0.3)) p.adaptive_error_target = rng.log_uniform(1e-3, 0.9);
    if (maybe(0.3)) p.max_substeps = uint32_t(rng.integer(1, 64));
    if (maybe(0.3)) p.substep_travel = rng.uniform(0.05, 1.0);
    if (maybe(0.3)) p.sound_speed = rng.log_uniform(10.0, 400.0);
    // Cost, not validity: the product of a fixed substep count and the iterations is kept to what
    // a few dozen frames of ~2k particles run in well under a second.
    while (std::max(p.substeps, 1u) * p.iterations > 256u) p.iterations = std::max(1u, p.iterations / 2);
    while (p.max_substeps * p.iterations > 512u) p.iterations = std::max(1u, p.iterations / 2);
    return p;
}

V3 draw_gravity(Rng& rng) {
    const double pick = rng.unit();
    if (pick < 0.65) return {0.0f, -9.81f, 0.0f};
    if (pick < 0.80) return {0.0f, 0.0f, 0.0f};
    const V3 d = rng.direction();
    const float g = rng.uniform(0.0, 20.0);
    return {d[0] * g, d[1] * g - (rng.chance(0.5) ? 0.0f : g), d[2] * g};
}

std::vector<float> draw_dts(Rng& rng, int frames, std::string& pattern) {
    std::vector<float> dts(size_t(frames), 1.0f / 60.0f);
    const double pick = rng.unit();
    if (pick < 0.2) {
        pattern = "fixed 1/60 s";
    } else if (pick < 0.4) {
        pattern = "jittery 1/240..1/20 s";
        for (auto& dt : dts) dt = rng.uniform(1.0 / 240.0, 1.0 / 20.0);
    } else if (pick < 0.55) {
        pattern = "1/60 s, then tiny 1e-7..1e-4 s";
        for (int k = frames / 2; k < frames; ++k) dts[size_t(k)] = rng.log_uniform(1e-7, 1e-4);
    } else if (pick < 0.65) {
        pattern = "1/60 s with huge 0.1..1 s steps";
        for (auto& dt : dts)
            if (rng.chance(0.15)) dt = rng.uniform(0.1, 1.0);
    } else if (pick < 0.8) {
        pattern = "1/60 s, one huge step, then small";
        const int k = rng.integer(frames / 4, frames / 2);
        dts[size_t(k)] = rng.chance(0.5) ? 1.0f : rng.uniform(0.2, 1.0);
        const float after = std::array<float, 4>{1e-7f, 1e-5f, 1e-3f, 1.0f / 60.0f}[size_t(rng.integer(0, 3))];
        for (int j = k + 1; j < frames; ++j) dts[size_t(j)] = after;
    } else {
        pattern = "mixed 1e-7..1 s";
        for (auto& dt : dts) dt = rng.log_uniform(1e-7, 1.0);
    }
    return dts;
}

}  // namespace

float collider_reach(const ColliderSpec& c) {
    switch (c.shape) {
        case PBF_SHAPE_SPHERE:
            return c.radius;
        case PBF_SHAPE_CAPSULE:
            return c.radius + c.half_height;
        case PBF_SHAPE_PLANE:
            return INFINITY;
        default: {
            const V3& e = c.half_extents;
            return std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        }
    }
}

MeshData mesh_of(const ColliderSpec& c) {
    MeshData m;
    const V3& e = c.half_extents;
    if (c.mesh == MeshKind::closed_box) {
        for (int k = 0; k < 8; ++k)
            m.vertices.insert(m.vertices.end(),
                              {(k & 1) ? e[0] : -e[0], (k & 2) ? e[1] : -e[1], (k & 4) ? e[2] : -e[2]});
        // Counter-clockwise seen from outside.
        m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                     2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    } else if (c.mesh == MeshKind::octahedron) {
        m.vertices = {e[0], 0, 0, -e[0], 0, 0, 0, e[1], 0, 0, -e[1], 0, 0, 0, e[2], 0, 0, -e[2]};
        m.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
    } else {  // an open terrain piece: a 4 x 4 grid of quads with bumps up to half_extents.y
        m.closed = false;
        const int n = 4;
        for (int z = 0; z <= n; ++z)
            for (int x = 0; x <= n; ++x) {
                const float bump = e[1] * std::sin(1.7f * float(x)) * std::cos(2.3f * float(z));
                m.vertices.insert(m.vertices.end(), {-e[0] + 2 * e[0] * x / n, bump, -e[2] + 2 * e[2] * z / n});
            }
        for (int z = 0; z < n; ++z)
            for (int x = 0; x < n; ++x) {
                const uint32_t a = uint32_t(z * (n + 1) + x), b = a + 1, cc = a + uint32_t(n + 1), d = cc + 1;
                m.indices.insert(m.indices.end(), {a, cc, d, a, d, b});
            }
    }
    return m;
}

WorldSpec draw_world(uint64_t seed, uint64_t index, pbf_backend backend) {
    Rng rng(mix64(seed) ^ mix64(index + 0x51ED270B27E3A5F1ull));
    WorldSpec w;
    w.seed = seed;
    w.index = index;
    pbf_world_desc& d = w.desc;
    d = pbf_world_desc_default();
    d.backend = backend;
    const float r = rng.log_uniform(0.005, 0.1), s = 2 * r;
    d.particle_radius = r;
    d.rest_density = rng.log_uniform(10.0, 10000.0);
    // One world in ten is isolated: zero gravity, no walls, colliders, nozzles or drains, only
    // blocks emitted before the first step (drops flying into each other), where momentum and
    // angular momentum must be kept.
    const bool isolated = rng.chance(0.1);
    const bool overlaps = rng.chance(0.25);
    const V3 g = isolated ? V3{0.0f, 0.0f, 0.0f} : draw_gravity(rng);
    std::copy(g.begin(), g.end(), d.gravity);
    d.walls = !isolated && rng.chance(0.75) ? 1u : 0u;
    d.solver = draw_solver(rng);
    // The scene's box (the walls, or the region an open level's objects are placed in).
    const float lx = float(rng.integer(8, 24)) * s, ly = float(rng.integer(12, 32)) * s,
                lz = float(rng.integer(8, 24)) * s;
    const V3 lo{-lx / 2, 0.0f, -lz / 2}, hi{lx / 2, ly, lz / 2};
    std::copy(lo.begin(), lo.end(), d.domain_min);
    std::copy(hi.begin(), hi.end(), d.domain_max);
    const int frames = rng.integer(20, 40);
    w.dts = draw_dts(rng, frames, w.dt_pattern);

    // Materials: none in most worlds; up to three, densities across the documented 0.1..10 x.
    const int materials = rng.chance(0.6) ? 0 : rng.integer(1, 3);
    for (int k = 0; k < materials; ++k) {
        MaterialSpec m;
        m.desc = pbf_material_desc_default();
        m.desc.rest_density = d.rest_density * rng.log_uniform(0.1, 10.0);
        if (rng.chance(0.5)) m.desc.viscosity = rng.uniform(0.0, 1.0);
        if (rng.chance(0.3)) m.desc.ldc_gain = rng.uniform(0.0, 1.0);
        if (rng.chance(0.15)) m.desc.surface_tension = rng.log_uniform(1.0, 1e4);
        if (rng.chance(0.15)) m.desc.cohesion = rng.log_uniform(1.0, 1e4);
        if (rng.chance(0.15)) m.desc.adhesion = rng.log_uniform(1.0, 1e4);
        w.materials.push_back(m);
    }
    auto material = [&]() { return materials == 0 || rng.chance(0.3) ? -1 : rng.integer(0, materials - 1); };

    // Cost, not validity: a world's particle count is capped so that its particle-substep-
    // iterations stay near what runs in a second on one core (~1.5e6 of them: 0.4 us each on
    // the CPU backend), halving a fixed substep count that leaves room for fewer than 100.
    auto per_particle = [&]() {
        double cost = 0;
        for (float dt : w.dts) {
            const pbf_solver_params& p = d.solver;
            const double substeps =
                p.substeps ? p.substeps : (dt >= 0.05f ? p.max_substeps : std::min(p.max_substeps, 4u));
            cost += substeps * (p.iterations + 3);
        }
        return cost;
    };
    constexpr double kCostCap = 1.5e6;
    while (per_particle() * 100 > kCostCap &&
           (d.solver.substeps > 1 || d.solver.max_substeps > 1 || d.solver.iterations > 1)) {
        if (d.solver.substeps > 1)
            d.solver.substeps /= 2;
        else if (d.solver.max_substeps > 1)
            d.solver.max_substeps /= 2;
        else
            d.solver.iterations /= 2;
    }
    const int affordable = int(kCostCap / per_particle());

    // Blocks: the first fills the bottom of the box; later ones (a game pouring more water) go
    // into its upper part, above where the first one started.
    const int target = std::max(60, std::min(affordable, rng.integer(200, 2000)));
    int planned = 0;
    const int blocks = rng.integer(1, 3);
    for (int k = 0; k < blocks; ++k) {
        BlockSpec b;
        const int share =
            k == 0 ? std::max(100, target * rng.integer(50, 100) / 100) : std::max(8, (target - planned) / 2);
        if (k > 0 && share <= 8) break;
        b.frame = k == 0 || isolated ? 0 : (rng.chance(0.5) ? 0 : rng.integer(1, frames - 1));
        // Isolated worlds stack their drops in separate bands, so none is emitted into another.
        // Each block has its own band of heights, so none is emitted into another's start.
        const float upper = isolated ? float(k) * 0.34f * ly : (k == 0 ? 0.0f : (0.55f + 0.22f * float(k - 1)) * ly);
        // A box of about `share` lattice sites: nx·ny·nz with nx, nz within the box.
        const int nx = std::min(int(lx / s) - 1, rng.integer(3, 14)),
                  nz = std::min(int(lz / s) - 1, rng.integer(3, 14));
        const int max_ny = std::max(1, int((isolated ? 0.3f * ly : (k == 0 ? 0.45f * ly : 0.2f * ly)) / s));
        const int ny = std::max(1, std::min(max_ny, share / std::max(1, nx * nz)));
        const float x0 = rng.uniform(lo[0], hi[0] - nx * s), z0 = rng.uniform(lo[2], hi[2] - nz * s);
        const float y0 = upper + (k == 0 || isolated ? 0.0f : rng.uniform(0.0, std::max(0.0f, 0.2f * ly - ny * s)));
        b.lo = {x0, y0, z0};
        b.hi = {x0 + nx * s, y0 + ny * s, z0 + nz * s};
        if (rng.chance(isolated ? 0.8 : 0.3)) {
            const V3 dir = rng.direction();
            const float speed = rng.uniform(0.0, 5.0);
            b.velocity = {dir[0] * speed, dir[1] * speed, dir[2] * speed};
        }
        b.material = material();
        planned += nx * ny * nz;
        w.blocks.push_back(b);
    }

    // Nozzles: the rate must fit through the disc at rest spacing (validated by the library).
    const int nozzles = isolated || rng.chance(0.5) ? 0 : rng.integer(1, 2);
    for (int k = 0; k < nozzles; ++k) {
        NozzleSpec n;
        n.radius = std::min(rng.uniform(1.5, 4.0) * s, 0.5f * std::min({lx, lz, ly}) - 1.5f * s);
        // The disc inside the walls, but for one nozzle in ten (the library checks the centre only).
        const float in = rng.chance(0.9) ? n.radius + s : 1.5f * r;
        const V3 inner_lo{lo[0] + in, 0.5f * ly, lo[2] + in}, inner_hi{hi[0] - in, ly - std::max(in, s), hi[2] - in};
        n.position = lerp3(inner_lo, inner_hi, rng);
        n.direction = rng.direction();
        if (n.direction[1] > 0 && rng.chance(0.7)) n.direction[1] = -n.direction[1];
        n.speed = rng.log_uniform(0.2, 8.0);
        const float fit = kPi * n.radius * n.radius / (s * s) * n.speed / s;
        n.rate = fit * rng.uniform(0.1, 0.95);
        n.create_frame = rng.chance(0.6) ? 0 : rng.integer(1, frames - 1);
        if (rng.chance(0.2)) n.destroy_frame = rng.integer(n.create_frame + 1, frames);
        if (rng.chance(0.2)) n.toggle_frame = rng.integer(0, frames - 1);
        if (rng.chance(0.2)) {
            n.move_frame = rng.integer(0, frames - 1);
            n.moved_position = lerp3(inner_lo, inner_hi, rng);
            n.moved_direction = rng.direction();
        }
        n.material = material();
        w.nozzles.push_back(n);
    }

    const int drains = isolated || rng.chance(0.6) ? 0 : rng.integer(1, 2);
    for (int k = 0; k < drains; ++k) {
        DrainSpec dr;
        auto box = [&](V3& a, V3& b) {
            const V3 size{rng.uniform(2, 8) * s, rng.uniform(2, 8) * s, rng.uniform(2, 8) * s};
            a = lerp3({lo[0] - s, lo[1] - s, lo[2] - s}, {hi[0] - size[0], 0.5f * ly, hi[2] - size[2]}, rng);
            b = {a[0] + size[0], a[1] + size[1], a[2] + size[2]};
        };
        box(dr.lo, dr.hi);
        dr.create_frame = rng.chance(0.6) ? 0 : rng.integer(1, frames - 1);
        if (rng.chance(0.3)) {
            dr.move_frame = rng.integer(0, frames - 1);
            box(dr.moved_lo, dr.moved_hi);
        }
        w.drains.push_back(dr);
    }

    // An open level usually has a floor to land on (a static plane or box); without one its
    // fluid falls for the whole run.
    if (!d.walls && !isolated && rng.chance(0.7)) {
        ColliderSpec f;
        if (rng.chance(0.6)) {
            f.shape = PBF_SHAPE_PLANE;
            f.centre = {0.0f, 0.0f, 0.0f};
        } else {
            f.shape = PBF_SHAPE_BOX;
            f.half_extents = {lx, 4 * s, lz};
            f.centre = {0.0f, -4 * s, 0.0f};
        }
        f.friction = rng.chance(0.3) ? rng.uniform(0.0, 1.0) : 0.0f;
        w.colliders.push_back(f);
    }
    const int colliders = isolated || rng.chance(0.3) ? 0 : rng.integer(1, 4);
    for (int k = 0; k < colliders; ++k) {
        ColliderSpec c;
        const double pick = rng.unit();
        if (pick < 0.1)
            c.shape = PBF_SHAPE_PLANE;
        else if (pick < 0.35)
            c.shape = PBF_SHAPE_SPHERE;
        else if (pick < 0.55)
            c.shape = PBF_SHAPE_CAPSULE;
        else if (pick < 0.8)
            c.shape = PBF_SHAPE_BOX;
        else {
            c.shape = PBF_SHAPE_MESH;
            const double m = rng.unit();
            c.mesh = m < 0.4 ? MeshKind::closed_box : (m < 0.7 ? MeshKind::octahedron : MeshKind::open_terrain);
        }
        c.radius = rng.uniform(1.5, 5.0) * s;
        c.half_height = rng.uniform(0.0, 4.0) * s;
        c.half_extents = {rng.uniform(1.0, 5.0) * s, rng.uniform(1.0, 5.0) * s, rng.uniform(1.0, 5.0) * s};
        if (c.mesh == MeshKind::open_terrain) c.half_extents[1] = rng.uniform(0.0, 1.0) * s;
        c.rotation = c.shape == PBF_SHAPE_PLANE ? Q4{0, 0, 0, 1} : rng.rotation();
        if (c.shape == PBF_SHAPE_PLANE) {  // tilted up to ~30 degrees, somewhere in the lower half
            const float tx = rng.uniform(-0.25, 0.25), tz = rng.uniform(-0.25, 0.25);
            const float n = std::sqrt(tx * tx + tz * tz + 1.0f);
            c.rotation = {tx / n, 0.0f, tz / n, 1.0f / n};
            c.centre = {0.0f, rng.uniform(-0.1, 0.4) * ly, 0.0f};
        } else {
            c.centre = lerp3(lo, hi, rng);
        }
        c.friction = rng.chance(0.3) ? rng.uniform(0.0, 1.0) : 0.0f;
        const double motion = rng.unit();
        const bool can_be_body =
            c.shape == PBF_SHAPE_SPHERE || c.shape == PBF_SHAPE_BOX || c.shape == PBF_SHAPE_CAPSULE;
        if (motion < 0.35 || (motion >= 0.85 && !can_be_body)) {
            c.kinematic = true;
            const double vpick = rng.unit();
            const float vmax = vpick < 0.1 ? 0.0f : (vpick < 0.7 ? rng.uniform(0.0, 3.0) : rng.uniform(3.0, 20.0));
            float extent = std::min({lx, ly, lz}) * 0.5f;
            c.omega = rng.log_uniform(0.5, 20.0);
            if (vmax / c.omega > extent) c.omega = vmax / extent;
            const V3 dir = c.shape == PBF_SHAPE_PLANE ? V3{0.0f, 1.0f, 0.0f} : rng.direction();
            for (int a = 0; a < 3; ++a) c.amplitude[a] = dir[a] * vmax / c.omega;
            c.phase = {rng.uniform(0.0, 6.3), rng.uniform(0.0, 6.3), rng.uniform(0.0, 6.3)};
            if (c.shape != PBF_SHAPE_PLANE && rng.chance(0.5)) {
                const V3 axis = rng.direction();
                const float rate = rng.uniform(0.0, 10.0) / collider_reach(c);
                c.spin = {axis[0] * rate, axis[1] * rate, axis[2] * rate};
            }
            c.dynamic = true;  // every moving collider reports its force: the fluid's energy budget reads its work
        } else if (motion >= 0.85) {
            c.body = c.kinematic = c.dynamic = true;
            c.body_density = d.rest_density * rng.uniform(0.3, 3.0);
            c.centre[1] = rng.uniform(0.4, 0.9) * ly;
        } else {
            c.dynamic = rng.chance(0.3);  // a static collider that measures its load
        }
        c.create_frame = rng.chance(0.7) ? 0 : rng.integer(1, frames - 1);
        // In three worlds of four, what exists at the start does not overlap: colliders of frame 0
        // are placed clear of the blocks of frame 0 and of the nozzles' discs, planes under them.
        // The rest keep their overlaps (a game that spawns water into its level geometry).
        if (!overlaps && c.create_frame == 0) {
            if (c.shape == PBF_SHAPE_PLANE) {
                float bottom = hi[1];
                for (const auto& b : w.blocks)
                    if (b.frame == 0) bottom = std::min(bottom, b.lo[1]);
                c.centre[1] = bottom - 0.9f * (lx + lz) / 2 - std::fabs(c.amplitude[1]);
            } else {
                const float reach = collider_reach(c) +
                                    std::sqrt(c.amplitude[0] * c.amplitude[0] + c.amplitude[1] * c.amplitude[1] +
                                              c.amplitude[2] * c.amplitude[2]) +
                                    2 * r;
                auto clear = [&](const V3& p) {
                    for (const auto& b : w.blocks) {
                        if (b.frame != 0) continue;
                        float d2 = 0;
                        for (int a = 0; a < 3; ++a) {
                            const float e = std::max({b.lo[a] - p[a], 0.0f, p[a] - b.hi[a]});
                            d2 += e * e;
                        }
                        if (d2 < reach * reach) return false;
                    }
                    for (const auto& n : w.nozzles) {
                        const float dx = n.position[0] - p[0], dy = n.position[1] - p[1], dz = n.position[2] - p[2];
                        if (dx * dx + dy * dy + dz * dz < (reach + n.radius) * (reach + n.radius)) return false;
                    }
                    return true;
                };
                bool placed = clear(c.centre);
                for (int attempt = 0; attempt < 20 && !placed; ++attempt) {
                    c.centre = lerp3(lo, hi, rng);
                    placed = clear(c.centre);
                }
                if (!placed) c.create_frame = rng.integer(1, frames - 1);  // no room: it appears later
            }
        }
        if (rng.chance(0.15)) c.destroy_frame = rng.integer(c.create_frame + 1, frames);
        if (rng.chance(0.15) && c.shape != PBF_SHAPE_PLANE) {
            c.teleport_frame = rng.integer(c.create_frame + 1, frames);
            c.teleport_to = lerp3(lo, hi, rng);
        }
        w.colliders.push_back(c);
    }

    if (!isolated && rng.chance(0.1)) {
        w.gravity_frame = rng.integer(1, frames - 1);
        w.gravity_after = draw_gravity(rng);
    }
    if (rng.chance(0.1)) {
        w.solver_frame = rng.integer(1, frames - 1);
        w.solver_after = draw_solver(rng);
    }
    // Capacity: room for what the nozzles add, or (sometimes) exactly the blocks, so emission
    // meets a full world.
    d.max_particles = uint32_t(planned + (rng.chance(0.1) ? 0 : rng.integer(0, std::min(1000, affordable))));
    d.max_colliders = uint32_t(std::max<size_t>(1, w.colliders.size() + (rng.chance(0.5) ? 0 : 4)));
    return w;
}

std::string describe(const WorldSpec& w) {
    std::ostringstream o;
    const pbf_world_desc& d = w.desc;
    const pbf_solver_params& p = d.solver;
    o << "world: radius " << d.particle_radius << " m, rest density " << d.rest_density << " kg/m3, gravity ("
      << d.gravity[0] << ", " << d.gravity[1] << ", " << d.gravity[2] << "), "
      << (d.walls ? "walls " : "open level, box ") << d.domain_min[0] << ".." << d.domain_max[0] << " x "
      << d.domain_min[1] << ".." << d.domain_max[1] << " x " << d.domain_min[2] << ".." << d.domain_max[2]
      << ", max_particles " << d.max_particles << "\n";
    o << "solver: iterations " << p.iterations << ", substeps " << p.substeps << ", relaxation " << p.relaxation
      << ", scorr k/n/dq " << p.scorr_k << "/" << p.scorr_n << "/" << p.scorr_dq << ", xsph " << p.xsph_c
      << ", vorticity " << p.vorticity_epsilon << ", ldc " << p.ldc_enabled << " gain " << p.ldc_gain << ", max_speed "
      << p.max_speed << ", adaptive " << p.adaptive_error_target << ", max_substeps " << p.max_substeps << ", travel "
      << p.substep_travel << ", sound_speed " << p.sound_speed << "\n";
    for (size_t k = 0; k < w.materials.size(); ++k) {
        if (!w.materials[k].on) continue;
        const pbf_material_desc& m = w.materials[k].desc;
        o << "material m" << k << ": rest density " << m.rest_density << ", viscosity " << m.viscosity << ", ldc_gain "
          << m.ldc_gain << ", sigma " << m.surface_tension << ", kappa " << m.cohesion << ", beta " << m.adhesion
          << "\n";
    }
    for (size_t k = 0; k < w.blocks.size(); ++k) {
        const BlockSpec& b = w.blocks[k];
        if (!b.on) continue;
        o << "block b" << k << " (frame " << b.frame << "): (" << b.lo[0] << ", " << b.lo[1] << ", " << b.lo[2]
          << ")..(" << b.hi[0] << ", " << b.hi[1] << ", " << b.hi[2] << "), velocity (" << b.velocity[0] << ", "
          << b.velocity[1] << ", " << b.velocity[2] << "), material " << b.material << "\n";
    }
    for (size_t k = 0; k < w.nozzles.size(); ++k) {
        const NozzleSpec& n = w.nozzles[k];
        if (!n.on) continue;
        o << "nozzle n" << k << " (frames " << n.create_frame << ".." << n.destroy_frame << ", toggled "
          << n.toggle_frame << ", moved " << n.move_frame << "): at (" << n.position[0] << ", " << n.position[1] << ", "
          << n.position[2] << "), direction (" << n.direction[0] << ", " << n.direction[1] << ", " << n.direction[2]
          << "), speed " << n.speed << " m/s, radius " << n.radius << ", " << n.rate << "/s, material " << n.material
          << "\n";
    }
    for (size_t k = 0; k < w.drains.size(); ++k) {
        const DrainSpec& dr = w.drains[k];
        if (!dr.on) continue;
        o << "drain d" << k << " (frame " << dr.create_frame << ", moved " << dr.move_frame << "): (" << dr.lo[0]
          << ", " << dr.lo[1] << ", " << dr.lo[2] << ")..(" << dr.hi[0] << ", " << dr.hi[1] << ", " << dr.hi[2]
          << ")\n";
    }
    static const char* shapes[] = {"?", "plane", "sphere", "capsule", "box", "mesh"};
    static const char* meshes[] = {"", " (closed box)", " (octahedron)", " (open terrain)"};
    for (size_t k = 0; k < w.colliders.size(); ++k) {
        const ColliderSpec& c = w.colliders[k];
        if (!c.on) continue;
        o << "collider c" << k << ": " << shapes[c.shape] << meshes[int(c.mesh)]
          << (c.body ? " body" : (c.kinematic ? " kinematic" : " static")) << (c.dynamic ? " dynamic" : "")
          << ", frames " << c.create_frame << ".." << c.destroy_frame << ", teleport " << c.teleport_frame
          << ", centre (" << c.centre[0] << ", " << c.centre[1] << ", " << c.centre[2] << "), r " << c.radius << ", hh "
          << c.half_height << ", half (" << c.half_extents[0] << ", " << c.half_extents[1] << ", " << c.half_extents[2]
          << "), amplitude (" << c.amplitude[0] << ", " << c.amplitude[1] << ", " << c.amplitude[2] << ") omega "
          << c.omega << ", spin (" << c.spin[0] << ", " << c.spin[1] << ", " << c.spin[2] << "), friction "
          << c.friction << "\n";
    }
    if (w.gravity_frame >= 0)
        o << "gravity (" << w.gravity_after[0] << ", " << w.gravity_after[1] << ", " << w.gravity_after[2]
          << ") from frame " << w.gravity_frame << "\n";
    if (w.solver_frame >= 0)
        o << "solver params changed at frame " << w.solver_frame << " (iterations " << w.solver_after.iterations
          << ", substeps " << w.solver_after.substeps << ")\n";
    o << "steps (" << w.dt_pattern << "):";
    for (float dt : w.dts) o << " " << dt;
    o << "\n";
    return o.str();
}

}  // namespace fuzz
