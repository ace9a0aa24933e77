// pbf_bench: time full solver steps on either backend, for docs/perf.md.
//
//   pbf_bench [--backend cpu|cuda|both] [--scene dam,tank,puddle] [--particles 65536,262144,1000000]
//             [--iterations 1,2,4] [--ldc 0,1] [--render 0,1] [--diffuse 0,1000000] [--steps 100] [--warmup 20] [--stages]
//             [--collider none,box,mesh] [--mesh-triangles 100000] [--mesh-builds 3] [--level-size 0,1000]
//             [--grid auto,hashed] [--dynamic-colliders 0,256] [--csv FILE]   (--help lists the options with their defaults)
//
// --collider adds one static collider to the scene: an analytic box, or the same box as a
// triangle mesh with each face subdivided (about --mesh-triangles triangles). The mesh's
// creation (its distance field's build, which pbf_world_create_mesh waits for) is timed with a
// host clock around the call: once untimed (the first build also loads the build's kernels),
// then --mesh-builds times; "build ms" is their median ("first build ms" in the CSV).
//
// --dynamic-colliders N spreads N small boxes through the fluid, dynamic (force and torque
// recorded) and kinematic: every frame sets each box's target pose (a small bob and turn),
// steps, and reads every box's force back with pbf_collider_get_force (which waits for the
// step). "frame ms" is the host-clock median of that whole frame (poses, step, read-back,
// pbf_world_get_stats), the figure to compare across N; "ms median" stays the backend's step.
// "call ms" is the host clock inside pbf_world_step alone (median): what queuing a step costs the
// engine's thread, the GPU's work running on after it returns.
//
// --level-size L > 0 puts the scene in an open level (pbf_world_desc.walls = 0, a hashed grid):
// the same fluid 0.3 L, -0.2 L, 0.45 L from the origin, held by five static plane colliders
// where the box's floor and sides were (so the step also pays for five colliders); 0 keeps the
// walled box (a dense grid where it is small enough). The "grid" column gives the grid's kind
// and cell table (pbf_world_info.grid_bytes). The puddle scene is a 2a x 0.2a x 2a layer in a
// 2a box: 100k particles of radius 0.01 m there are the "100k puddle in a 2 m box".
// --grid hashed hashes the grid of a walled box too (pbf_world_desc.hashed_grid): the same scene
// on both grids, without the planes.
//
// One "step" is one solver step (pbf_world_step with substeps = 1): LDC when on, prediction,
// grid build on x*, the constraint iterations with collisions, velocity update, vorticity
// confinement and XSPH. dt keeps the fastest particle under 0.4 h per step, so the scene stays
// physical at every resolution. GPU times come from CUDA events recorded on the world's stream
// around each step (the backend's own step timer), CPU times from a steady clock.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "pbf_c_api.h"
#include "tool_support.h"

namespace {

using tool::split_list;

struct Config {
    std::string scene;
    uint32_t particles, iterations, ldc;
    pbf_backend backend;
    uint32_t render;         // 1: smoothed positions and anisotropy each step (pbf_render_params)
    uint32_t diffuse;        // diffuse capacity (pbf_diffuse_params.max_diffuse); 0: off
    uint32_t materials = 1;  // 2: two fluids (the default and one of half its density), both with
                             // surface tension and cohesion
    float surface_tension = 0, cohesion = 0;
    std::string collider = "none";  // none, box or mesh
    uint32_t mesh_triangles = 0;
    float level_size = 0;            // > 0: an open level (no walls) of this extent
    uint32_t hashed_grid = 0;        // 1: pbf_world_desc.hashed_grid
    uint32_t mesh_builds = 3;        // timed builds of the mesh (after one untimed)
    uint32_t dynamic_colliders = 0;  // small dynamic kinematic boxes in the fluid, forces read each frame
};

struct Result {
    double create_ms =
        0.0;  // pbf_world_create (the first of a process includes opening the driver and loading the kernels)
    bool ok = false;
    std::string device, error;
    double ms_median = 0, ms_min = 0, ms_max = 0, bytes_per_particle = 0, error_mean = 0, error_max = 0;
    uint32_t count = 0;
    uint32_t diffuse_count = 0;  // live diffuse particles after the last step
    float dt = 0;
    double stage_ms[PBF_PROFILE_MAX_STAGES] = {};  // per step, averaged
    double build_ms = 0, first_build_ms = 0;       // the mesh's creation (its field's build): median, first
    uint32_t triangles = 0;
    uint32_t grid_hashed = 0;
    uint64_t grid_bytes = 0;
    double frame_ms = 0;  // host clock: target poses, step, force read-back, stats (median)
    double call_ms = 0;   // host clock inside pbf_world_step alone: what queuing the step costs the caller (median)
};

// The solver's stages, as the library names them (pbf_profile_stage_name).
uint32_t stage_count() {
    uint32_t n = 0;
    while (n < PBF_PROFILE_MAX_STAGES && pbf_profile_stage_name(n)) ++n;
    return n;
}

void set3(float* d, float x, float y, float z) {
    d[0] = x;
    d[1] = y;
    d[2] = z;
}

// The box [-e, e]³ with each face cut into n x n squares of two triangles (12 n² in all),
// counter-clockwise seen from outside.
void subdivided_box(float e, int n, std::vector<float>* v, std::vector<uint32_t>* tri) {
    // Face k: normal axis a = k / 2, side s = ±1; (u, w) span the other two axes, ordered so
    // that u x w points along the normal.
    for (int k = 0; k < 6; ++k) {
        const int a = k / 2;
        const float side = k % 2 ? 1.0f : -1.0f;
        const int u = (a + 1) % 3, w = (a + 2) % 3;
        const uint32_t base = uint32_t(v->size() / 3);
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                float p[3];
                p[a] = side * e;
                p[u] = -e + 2 * e * i / n;
                p[w] = -e + 2 * e * j / n;
                v->insert(v->end(), p, p + 3);
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const uint32_t q = base + uint32_t(j * (n + 1) + i), r = q + 1, t = q + uint32_t(n + 1), x = t + 1;
                if (side > 0)
                    tri->insert(tri->end(), {q, r, x, q, x, t});
                else
                    tri->insert(tri->end(), {q, x, r, q, t, x});
            }
    }
}

// A static plane through p whose solid lies below rotation q's +y.
bool add_plane(pbf_world_id w, float x, float y, float z, const float q[4]) {
    pbf_collider_desc d = pbf_collider_desc_default();
    d.shape = PBF_SHAPE_PLANE;
    set3(d.position, x, y, z);
    std::memcpy(d.rotation, q, sizeof d.rotation);
    pbf_collider_id id;
    return pbf_world_create_collider(w, &d, &id) == PBF_OK;
}

// The floor and four sides of the box [o, o + size] as planes (an open level's container).
bool add_box_planes(pbf_world_id w, const float o[3], const float size[3]) {
    const float s = 0.70710678f;
    const float up[4] = {0, 0, 0, 1}, px[4] = {0, 0, -s, s}, nx[4] = {0, 0, s, s}, pz[4] = {s, 0, 0, s},
                nz[4] = {-s, 0, 0, s};
    return add_plane(w, o[0], o[1], o[2], up) && add_plane(w, o[0], o[1], o[2], px) &&
           add_plane(w, o[0] + size[0], o[1], o[2], nx) && add_plane(w, o[0], o[1], o[2], pz) &&
           add_plane(w, o[0], o[1], o[2] + size[2], nz);
}

// The scene's collider (none, box or mesh): a box of half size a/4 in the middle of the fluid.
bool add_collider(pbf_world_id w, const Config& c, float a, const float o[3], Result* r) {
    if (c.collider == "none") return true;
    pbf_collider_desc d = pbf_collider_desc_default();
    set3(d.position, o[0] + a, o[1] + 0.5f * a, o[2] + 0.5f * a);
    const float e = 0.25f * a;
    if (c.collider == "box") {
        d.shape = PBF_SHAPE_BOX;
        set3(d.half_extents, e, e, e);
    } else {
        std::vector<float> v;
        std::vector<uint32_t> tri;
        subdivided_box(e, std::max(1, int(std::lround(std::sqrt(c.mesh_triangles / 12.0)))), &v, &tri);
        pbf_mesh_desc m = pbf_mesh_desc_default();
        m.vertices = v.data();
        m.vertex_count = uint32_t(v.size() / 3);
        m.indices = tri.data();
        m.triangle_count = uint32_t(tri.size() / 3);
        r->triangles = m.triangle_count;
        std::vector<double> builds;
        for (uint32_t k = 0; k <= c.mesh_builds; ++k) {
            if (k > 0 && pbf_world_destroy_mesh(w, d.mesh) != PBF_OK) return false;
            const auto t0 = std::chrono::steady_clock::now();
            if (pbf_world_create_mesh(w, &m, &d.mesh) != PBF_OK) return false;
            const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
            if (k == 0)
                r->first_build_ms = ms;
            else
                builds.push_back(ms);
        }
        std::sort(builds.begin(), builds.end());
        r->build_ms = builds.empty() ? r->first_build_ms : builds[builds.size() / 2];
        d.shape = PBF_SHAPE_MESH;
    }
    pbf_collider_id id;
    return pbf_world_create_collider(w, &d, &id) == PBF_OK;
}

// N small boxes on a lattice through the fluid (the tank's 2a x a x a or the dam's column),
// dynamic and kinematic.
struct DynamicBoxes {
    std::vector<pbf_collider_id> ids;
    std::vector<std::array<float, 3>> home;
    float half = 0;
};

bool add_dynamic_boxes(pbf_world_id w, uint32_t n, const float o[3], const float fluid_max[3], DynamicBoxes* out) {
    if (n == 0) return true;
    // A lattice of nx x ny x nz >= n sites in proportion to the fluid's sides.
    const float volume = fluid_max[0] * fluid_max[1] * fluid_max[2];
    const float site = std::cbrt(volume / float(n));
    int cells[3];
    for (int a = 0; a < 3; ++a) cells[a] = std::max(1, int(std::lround(fluid_max[a] / site)));
    while (uint32_t(cells[0] * cells[1] * cells[2]) < n) ++cells[0];
    out->half = 0.2f * site;  // boxes of 0.4 of the lattice spacing: fluid flows between them
    for (uint32_t k = 0; k < n; ++k) {
        const int i = int(k) % cells[0], j = (int(k) / cells[0]) % cells[1], l = int(k) / (cells[0] * cells[1]);
        pbf_collider_desc d = pbf_collider_desc_default();
        d.shape = PBF_SHAPE_BOX;
        d.motion = PBF_MOTION_KINEMATIC;
        d.dynamic = 1;
        set3(d.half_extents, out->half, out->half, out->half);
        set3(d.position, o[0] + fluid_max[0] * (i + 0.5f) / cells[0], o[1] + fluid_max[1] * (j + 0.5f) / cells[1],
             o[2] + fluid_max[2] * (l + 0.5f) / cells[2]);
        pbf_collider_id id;
        if (pbf_world_create_collider(w, &d, &id) != PBF_OK) return false;
        out->ids.push_back(id);
        out->home.push_back({d.position[0], d.position[1], d.position[2]});
    }
    return true;
}

// Frame k's target poses (each box bobs by a quarter of its size and turns about y, out of
// phase with its neighbours), then after the step every box's force and torque read back.
bool move_dynamic_boxes(pbf_world_id w, const DynamicBoxes& b, int frame, float dt) {
    for (size_t k = 0; k < b.ids.size(); ++k) {
        const float phase = 6.2831853f * (float(frame) * dt + 0.1f * float(k));
        const float p[3] = {b.home[k][0], b.home[k][1] + 0.25f * b.half * std::sin(phase), b.home[k][2]};
        const float angle = 0.2f * std::sin(phase);
        const float q[4] = {0.0f, std::sin(0.5f * angle), 0.0f, std::cos(0.5f * angle)};
        if (pbf_collider_set_target_pose(w, b.ids[k], p, q) != PBF_OK) return false;
    }
    return true;
}

bool read_dynamic_forces(pbf_world_id w, const DynamicBoxes& b, double* checksum) {
    for (const pbf_collider_id& id : b.ids) {
        pbf_collider_force f;
        if (pbf_collider_get_force(w, id, &f) != PBF_OK) return false;
        *checksum += f.force[1];
    }
    return true;
}

Result run(const Config& c, int warmup, int steps, bool stages) {
    Result r;
    // Dam: column a x 2a x a/2 in a 4a x 2.5a x a/2 tank. Tank: fluid 2a x a x a in 2a x 2a x a.
    // Puddle: fluid 2a x 0.2a x 2a in 2a x 2a x 2a.
    const bool dam = c.scene == "dam", puddle = c.scene == "puddle";
    const float a = 1.0f;
    const float box[3] = {dam ? 4 * a : 2 * a, dam ? 2.5f * a : 2 * a, dam ? 0.5f * a : puddle ? 2 * a : a};
    const float fluid[3] = {dam ? a : 2 * a, dam ? 2 * a : puddle ? 0.2f * a : a, dam ? 0.5f * a : puddle ? 2 * a : a};
    const float fluid_volume = fluid[0] * fluid[1] * fluid[2];
    const float spacing = std::cbrt(fluid_volume / float(c.particles));
    const float h = 2.0f * spacing;
    const float depth = fluid[1];
    const bool open = c.level_size > 0.0f;
    const float o[3] = {open ? 0.3f * c.level_size : 0.0f, open ? -0.2f * c.level_size : 0.0f,
                        open ? 0.45f * c.level_size : 0.0f};
    const float dt = std::min(1.0f / 60.0f, 0.4f * h / std::sqrt(2.0f * 9.81f * depth));
    r.dt = dt;

    pbf_world_desc d = pbf_world_desc_default();
    d.backend = c.backend;
    d.max_particles = c.particles + c.particles / 8 + 1024;
    d.particle_radius = 0.5f * spacing;
    set3(d.domain_min, 0, 0, 0);
    set3(d.domain_max, box[0], box[1], box[2]);
    d.walls = open ? 0u : 1u;
    d.hashed_grid = c.hashed_grid;
    d.solver.iterations = c.iterations;
    d.solver.substeps = 1;  // one step = one substep, whatever the automatic rule would pick
    d.solver.ldc_enabled = c.ldc;
    d.render.flags = c.render ? PBF_RENDER_SMOOTHED_POSITIONS | PBF_RENDER_ANISOTROPY : 0u;
    d.diffuse.max_diffuse = c.diffuse;
    d.max_colliders =
        std::max(d.max_colliders, c.dynamic_colliders + 6);  // + the --collider one and an open level's 5 planes
    pbf_world_id w;
    const auto created = std::chrono::steady_clock::now();
    if (pbf_world_create(&d, &w) != PBF_OK) {
        r.error = pbf_last_error_message();
        return r;
    }
    r.create_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - created).count();
    pbf_world_info info;
    tool::read_info(w, &info);
    r.device = info.device_name;
    r.bytes_per_particle = double(info.device_bytes) / d.max_particles;
    r.grid_hashed = info.grid_hashed;
    r.grid_bytes = info.grid_bytes;

    pbf_block_desc b = pbf_block_desc_default();
    set3(b.box_min, o[0], o[1], o[2]);
    // A hair of slack: far from the origin the float box may hold a hair less than n spacings.
    const float slack = open ? 0.01f * spacing : 0.0f;
    set3(b.box_max, o[0] + fluid[0] + slack, o[1] + fluid[1] + slack, o[2] + fluid[2] + slack);
    uint32_t emitted = 0, second = 0;
    bool ok = true;
    if (c.materials == 2) {
        // The fluid in two halves along x: the default material and a second of half its
        // density, both with surface tension and cohesion.
        pbf_material_id ids[PBF_MAX_MATERIALS];
        pbf_material_desc m = pbf_material_desc_default();
        ok = pbf_world_get_materials(w, ids) == PBF_OK && pbf_world_get_material(w, ids[0], &m) == PBF_OK;
        m.surface_tension = c.surface_tension;
        m.cohesion = c.cohesion;
        ok = ok && pbf_world_set_material(w, ids[0], &m) == PBF_OK;
        m.rest_density *= 0.5f;
        ok = ok && pbf_world_create_material(w, &m, &b.material) == PBF_OK;
        const float half = 0.5f * (b.box_min[0] + b.box_max[0]);
        pbf_block_desc first = b;
        first.material = pbf_material_id{0, 0};
        first.box_max[0] = half;
        b.box_min[0] = half;
        ok = ok && pbf_world_emit_block(w, &first, &second) == PBF_OK;
    }
    if (!ok || pbf_world_emit_block(w, &b, &emitted) != PBF_OK) {
        r.error = pbf_last_error_message();
        pbf_world_destroy(w);
        return r;
    }
    r.count = emitted + second;
    DynamicBoxes boxes;
    if (!add_collider(w, c, a, o, &r) || (open && !add_box_planes(w, o, box)) ||
        !add_dynamic_boxes(w, c.dynamic_colliders, o, fluid, &boxes)) {
        r.error = pbf_last_error_message();
        pbf_world_destroy(w);
        return r;
    }
    if (stages) pbf_world_set_profiling(w, 1);

    pbf_step_stats s;
    std::memset(&s, 0, sizeof s);
    s.struct_size = sizeof s;
    std::vector<double> times, frames, calls;
    double force_checksum = 0;
    for (int k = 0; k < warmup + steps; ++k) {
        const auto t0 = std::chrono::steady_clock::now();
        bool ok = move_dynamic_boxes(w, boxes, k, dt);
        const auto call = std::chrono::steady_clock::now();
        ok = ok && pbf_world_step(w, dt) == PBF_OK;
        const double call_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - call).count();
        if (!ok || !read_dynamic_forces(w, boxes, &force_checksum) || pbf_world_get_stats(w, &s) != PBF_OK) {
            r.error = pbf_last_error_message();
            pbf_world_destroy(w);
            return r;
        }
        const double frame = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        if (k < warmup) continue;
        times.push_back(s.step_time_ms);
        frames.push_back(frame);
        calls.push_back(call_ms);
        r.error_mean += s.density_error_mean;
        r.error_max = std::max<double>(r.error_max, s.density_error_max);
        if (stages) {
            pbf_step_profile t;
            std::memset(&t, 0, sizeof t);
            t.struct_size = sizeof t;
            if (pbf_world_get_profile(w, &t) == PBF_OK)
                for (uint32_t i = 0; i < t.stage_count; ++i) r.stage_ms[i] += t.stage_ms[i] / steps;
        }
    }
    r.error_mean /= steps;
    r.diffuse_count = s.diffuse_count;
    std::sort(times.begin(), times.end());
    r.ms_median = times[times.size() / 2];
    r.ms_min = times.front();
    r.ms_max = times.back();
    std::sort(frames.begin(), frames.end());
    r.frame_ms = frames[frames.size() / 2];
    std::sort(calls.begin(), calls.end());
    r.call_ms = calls[calls.size() / 2];
    r.ok = std::isfinite(s.kinetic_energy) && std::isfinite(force_checksum);
    if (!r.ok) r.error = "simulation diverged";
    pbf_world_destroy(w);
    return r;
}

}  // namespace

int main(int argc, char** argv) {
    std::string backends = "both", scenes = "dam,tank", particles = "65536,262144,1000000", iterations = "4",
                ldcs = "0,1", renders = "0", diffuses = "0", colliders = "none", levels = "0", grids = "auto", csv_path;
    int steps = 100, warmup = 20;
    uint32_t mesh_triangles = 100000, mesh_builds = 3;
    std::string dynamics = "0";
    bool stages = false;
    std::string materials = "1";
    float surface_tension = 100.0f, cohesion = 100.0f;
    CLI::App app{
        "pbf_bench: time full solver steps (pbf_world_step, one substep) on either backend, for "
        "docs/perf.md. Every combination of the comma-separated lists below is run; a Markdown table goes "
        "to stdout.",
        "pbf_bench"};
    app.option_defaults()->always_capture_default()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
    app.add_option("--backend", backends, "backends: cpu, cuda or both (comma-separated)");
    app.add_option("--scene", scenes,
                   "scenes: dam (a x 2a x a/2 column in a 4a tank), tank (resting layer), puddle (2a x 0.2a x 2a "
                   "layer in a 2a box)");
    app.add_option("--level-size", levels,
                   "0: the scene's walled box; L > 0: an open level (no walls, hashed grid), the fluid 0.3 L to "
                   "0.45 L from the origin in five plane colliders (comma-separated)");
    app.add_option("--grid", grids, "auto: the library's choice; hashed: always the hashed grid (comma-separated)");
    app.add_option("--particles", particles, "particle counts (comma-separated)");
    app.add_option("--iterations", iterations, "constraint iterations per step (comma-separated)");
    app.add_option("--ldc", ldcs, "Local Density Calibration off/on: 0, 1 (comma-separated)");
    app.add_option("--render", renders,
                   "render data off/on: 0, 1 (smoothed positions + anisotropy after every step; comma-separated)");
    app.add_option("--diffuse", diffuses,
                   "diffuse capacities: 0 (off) or max_diffuse (spray, foam and bubbles each step; comma-separated)");
    app.add_option("--steps", steps, "timed steps per configuration (>= 1)")->check(CLI::Range(1, 1 << 30));
    app.add_option("--warmup", warmup, "untimed steps before them (>= 0)")->check(CLI::Range(0, 1 << 30));
    app.add_option("--materials", materials,
                   "1: one fluid (no surface forces); 2: two fluids of 1000 and 500 kg/m3, both with surface "
                   "tension and cohesion (comma-separated)");
    app.add_option("--surface-tension", surface_tension, "with --materials 2: surface tension, 1/s^2 (default 100)");
    app.add_option("--cohesion", cohesion, "with --materials 2: cohesion, 1/s^2 (default 100)");
    app.add_option("--collider", colliders,
                   "one static collider in the fluid: none, box (analytic) or mesh (the same "
                   "box as a subdivided triangle mesh) (comma-separated)");
    app.add_option("--mesh-triangles", mesh_triangles, "about how many triangles the mesh box has")
        ->check(CLI::Range(12, 1 << 22));
    app.add_option("--mesh-builds", mesh_builds, "timed builds of the mesh after one untimed (median reported)")
        ->check(CLI::Range(1, 100));
    app.add_option("--dynamic-colliders", dynamics,
                   "small dynamic kinematic boxes spread through the fluid, posed every frame and their forces "
                   "read back every frame (comma-separated counts, e.g. 0,256)");
    app.add_flag("--stages", stages, "per-stage times (profiled run; stage marks add a little overhead)");
    app.add_option("--csv", csv_path, "also write the results, with per-stage columns, to this CSV file");
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        return app.exit(e) == 0 ? 0 : 2;  // --help: 0; a bad argument: 2, as before
    }

    std::vector<pbf_backend> backend_list;
    for (const std::string& b : split_list(backends)) {
        if (b == "cpu" || b == "both") backend_list.push_back(PBF_BACKEND_CPU);
        if (b == "cuda" || b == "both") backend_list.push_back(PBF_BACKEND_CUDA);
    }

    FILE* csv = csv_path.empty() ? nullptr : std::fopen(csv_path.c_str(), "w");
    if (csv) {
        std::fprintf(
            csv,
            "scene,particles,iterations,ldc,render,backend,device,ms_median,ms_min,ms_max,particle_steps_per_s,"
            "bytes_per_particle,density_error_mean,density_error_max,dt,diffuse,diffuse_count,collider,triangles,"
            "build_ms,level_size,grid_hashed,grid_bytes,first_build_ms,dynamic_colliders,frame_ms,call_ms");
        for (uint32_t k = 0; k < stage_count(); ++k) std::fprintf(csv, ",stage_%s_ms", pbf_profile_stage_name(k));
        std::fprintf(csv, "\n");
    }
    std::printf(
        "| scene | particles | iter | LDC | render | diffuse cap/live | backend | device | ms median | min | max | "
        "particle-steps/s | B/particle | density err mean | max | collider | triangles | build ms | level | grid | "
        "dynamic | frame ms | call ms |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    int failures = 0;
    std::vector<double> create_ms;
    std::vector<std::pair<Config, Result>> staged;
    for (pbf_backend backend : backend_list)
        for (const std::string& scene : split_list(scenes))
            for (const std::string& n : split_list(particles))
                for (const std::string& it : split_list(iterations))
                    for (const std::string& l : split_list(ldcs))
                        for (const std::string& rd : split_list(renders))
                            for (const std::string& df : split_list(diffuses))
                                for (const std::string& mt : split_list(materials))
                                    for (const std::string& col : split_list(colliders))
                                        for (const std::string& lv : split_list(levels))
                                            for (const std::string& gr : split_list(grids))
                                                for (const std::string& dyn : split_list(dynamics)) {
                                                    const Config c{scene,
                                                                   uint32_t(std::strtoul(n.c_str(), nullptr, 10)),
                                                                   uint32_t(std::atoi(it.c_str())),
                                                                   uint32_t(std::atoi(l.c_str())),
                                                                   backend,
                                                                   uint32_t(std::atoi(rd.c_str())),
                                                                   uint32_t(std::strtoul(df.c_str(), nullptr, 10)),
                                                                   uint32_t(std::atoi(mt.c_str())),
                                                                   surface_tension,
                                                                   cohesion,
                                                                   col,
                                                                   mesh_triangles,
                                                                   std::strtof(lv.c_str(), nullptr),
                                                                   gr == "hashed" ? 1u : 0u,
                                                                   mesh_builds,
                                                                   uint32_t(std::strtoul(dyn.c_str(), nullptr, 10))};
                                                    const Result r = run(c, warmup, steps, stages);
                                                    const char* bname =
                                                        c.materials == 2
                                                            ? (backend == PBF_BACKEND_CUDA ? "cuda 2-mat" : "cpu 2-mat")
                                                            : (backend == PBF_BACKEND_CUDA ? "cuda" : "cpu");
                                                    if (!r.ok) {
                                                        std::printf(
                                                            "| %s | %u | %u | %u | %u | %u | %s | - | failed: %s |\n",
                                                            scene.c_str(), c.particles, c.iterations, c.ldc, c.render,
                                                            c.diffuse, bname, r.error.c_str());
                                                        ++failures;
                                                        continue;
                                                    }
                                                    const double rate = r.count / (r.ms_median / 1000.0);
                                                    std::printf(
                                                        "| %s | %u | %u | %u | %u | %u/%u | %s | %s | %.3f | %.3f | "
                                                        "%.3f | %.3g | %.1f | %.5f | %.4f "
                                                        "| %s | %u | %.1f | %s | %s %.1f KB | %u | %.3f | %.3f |\n",
                                                        scene.c_str(), r.count, c.iterations, c.ldc, c.render,
                                                        c.diffuse, r.diffuse_count, bname, r.device.c_str(),
                                                        r.ms_median, r.ms_min, r.ms_max, rate, r.bytes_per_particle,
                                                        r.error_mean, r.error_max, c.collider.c_str(), r.triangles,
                                                        r.build_ms, c.level_size > 0 ? lv.c_str() : "box",
                                                        r.grid_hashed ? "hashed" : "dense", r.grid_bytes / 1024.0,
                                                        c.dynamic_colliders, r.frame_ms, r.call_ms);
                                                    std::fflush(stdout);
                                                    if (csv) {
                                                        std::fprintf(csv,
                                                                     "%s,%u,%u,%u,%u,%s,%s,%.4f,%.4f,%.4f,%.6g,%.2f,%."
                                                                     "6f,%.6f,%.6f",
                                                                     scene.c_str(), r.count, c.iterations, c.ldc,
                                                                     c.render, bname, r.device.c_str(), r.ms_median,
                                                                     r.ms_min, r.ms_max, rate, r.bytes_per_particle,
                                                                     r.error_mean, r.error_max, r.dt);
                                                        std::fprintf(
                                                            csv, ",%u,%u,%s,%u,%.3f,%g,%u,%llu,%.3f,%u,%.4f,%.4f",
                                                            c.diffuse, r.diffuse_count, c.collider.c_str(), r.triangles,
                                                            r.build_ms, c.level_size, r.grid_hashed,
                                                            (unsigned long long)r.grid_bytes, r.first_build_ms,
                                                            c.dynamic_colliders, r.frame_ms, r.call_ms);
                                                        for (uint32_t k = 0; k < stage_count(); ++k)
                                                            std::fprintf(csv, ",%.4f", r.stage_ms[k]);
                                                        std::fprintf(csv, "\n");
                                                    }
                                                    if (stages) staged.push_back({c, r});
                                                    create_ms.push_back(r.create_ms);
                                                }
    if (!create_ms.empty()) {
        std::printf(
            "\nWorld creation: the first %.1f ms (for CUDA: opening the driver and loading the kernels included)",
            create_ms[0]);
        if (create_ms.size() > 1) {
            std::vector<double> rest(create_ms.begin() + 1, create_ms.end());
            std::sort(rest.begin(), rest.end());
            std::printf(", the others %.1f ms median", rest[rest.size() / 2]);
        }
        std::printf("\n");
    }
    if (stages && !staged.empty()) {
        std::printf("\nPer-stage ms per step (profiled run; stage marks add a little overhead):\n| config |");
        for (uint32_t k = 0; k < stage_count(); ++k) std::printf(" %s |", pbf_profile_stage_name(k));
        std::printf("\n|---|");
        for (uint32_t k = 0; k < stage_count(); ++k) std::printf("---|");
        std::printf("\n");
        for (const auto& [c, r] : staged) {
            std::printf("| %s %u it%u ldc%u render%u diffuse%u mat%u %s |", c.scene.c_str(), r.count, c.iterations,
                        c.ldc, c.render, c.diffuse, c.materials, c.backend == PBF_BACKEND_CUDA ? "cuda" : "cpu");
            for (uint32_t k = 0; k < stage_count(); ++k) std::printf(" %.3f |", r.stage_ms[k]);
            std::printf("\n");
        }
    }
    if (csv) std::fclose(csv);
    return failures ? 1 : 0;
}
