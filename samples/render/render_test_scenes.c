/* The scenes of the tests, drawn (particle radius 0.02 m, the tests' sizes and settings, so the
 * frames show what the tests check):
 *   two_fluids     tests/materials_scenes.h two_fluids(): a lock exchange of a 500 kg/m³ fluid
 *                  (amber) beside water on a film of water, which stratifies;
 *   droplet        cube_in_zero_gravity(): a 12³ cube with surface tension and cohesion 100 /s²
 *                  relaxing to a sphere in zero gravity;
 *   hanging_drops  drop_under_sphere(), twice in one world: the drop with adhesion 3000 /s²
 *                  (blue) stays under its sphere, the one without (red) falls; both cohesion 200;
 *   container      tests/mesh_scenes.h shaken_container(): a closed hollow-box mesh, half full,
 *                  moved 20 particle radii and turned 30° per frame by the engine (the leak test);
 *   floating_boxes tests/coupling_scenes.h release_box() as samples/floating_box.c, twice: boxes
 *                  of 500 and 2000 kg/m³ released on a pool; this program plays the engine and
 *                  integrates both bodies (upright, vertical, as the test) from the force the
 *                  water exerted (pbf_collider_get_force). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_scene.h"

static const float kR = 0.02f, kIdentity[4] = {0, 0, 0, 1};

static void set3(float v[3], float x, float y, float z) {
    v[0] = x;
    v[1] = y;
    v[2] = z;
}

static void fill(scene* s, pbf_material_id m, float x0, float y0, float z0, float x1, float y1, float z1) {
    pbf_block_desc b = pbf_block_desc_default();
    uint32_t n = 0;
    set3(b.box_min, x0, y0, z0);
    set3(b.box_max, x1, y1, z1);
    b.material = m;
    CHECK(pbf_world_emit_block(s->world, &b, &n));
    s->emitted += n;
}

static pbf_material_id add_material(scene* s, float rest_density, float surface_tension, float cohesion, float adhesion,
                                    const float color[3]) {
    pbf_material_desc m = pbf_material_desc_default();
    pbf_material_id id;
    m.rest_density = rest_density;
    m.surface_tension = surface_tension;
    m.cohesion = cohesion;
    m.adhesion = adhesion;
    if (color) memcpy(m.color, color, 3 * sizeof(float));
    CHECK(pbf_world_create_material(s->world, &m, &id));
    return id;
}

/* ---- the container: a hollow box mesh moved along a circle ------------------------------------ */
static const float kInner[3] = {0.16f, 0.12f, 0.16f}, kWall = 2.0f * 0.02f, kStepAngle = 0.5f;
static const float kCircle[3] = {0.0f, 1.1f, 0.0f}; /* raised above the floor the renderer draws */

/* The box [-e, e], counter-clockwise seen from outside (inward: from inside, a cavity). */
static void add_box(float* v, uint32_t* nv, uint32_t* idx, uint32_t* nt, const float e[3], int inward) {
    static const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                         {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    const uint32_t base = *nv;
    uint32_t k;
    for (k = 0; k < 8; ++k, ++*nv) set3(&v[3 * *nv], k & 1 ? e[0] : -e[0], k & 2 ? e[1] : -e[1], k & 4 ? e[2] : -e[2]);
    for (k = 0; k < 6; ++k, *nt += 2) {
        const uint32_t a = base + quads[k][0], b = base + quads[k][1], c = base + quads[k][2], d = base + quads[k][3];
        const uint32_t out[6] = {a, b, c, a, c, d}, in[6] = {a, c, b, a, d, c};
        memcpy(&idx[3 * *nt], inward ? in : out, sizeof out);
    }
}

static float container_path_radius(void) { return 0.5f * 20.0f * kR / sinf(0.5f * kStepAngle); }

static void container_pose(long frame, float pos[3], float q[4]) {
    const float a = kStepAngle * (float)frame, r = container_path_radius();
    const float axis[3] = {0.3f, 1.0f, 0.5f}, turn = (float)frame * 30.0f * 3.14159265f / 180.0f;
    const float n = sqrtf(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]), sn = sinf(0.5f * turn) / n;
    set3(pos, kCircle[0] + r * cosf(a), kCircle[1] + r * sinf(a), kCircle[2]);
    set3(q, axis[0] * sn, axis[1] * sn, axis[2] * sn);
    q[3] = cosf(0.5f * turn);
}

static void container_before_step(scene* s) {
    float pos[3], q[4];
    container_pose(s->frame, pos, q);
    body_set_target(s, &s->bodies[0], pos, q);
}

static void container_populate(pbf_egl* e, scene* s) {
    const float outer[3] = {kInner[0] + kWall, kInner[1] + kWall, kInner[2] + kWall};
    const float glass[4] = {0.75f, 0.85f, 0.95f, 0.18f};
    float v[16 * 3], pos[3], q[4];
    uint32_t idx[24 * 3], nv = 0, nt = 0;
    pbf_mesh_desc md = pbf_mesh_desc_default();
    pbf_collider_desc c = pbf_collider_desc_default();
    add_box(v, &nv, idx, &nt, outer, 0);
    add_box(v, &nv, idx, &nt, kInner, 1);
    md.vertices = v;
    md.vertex_count = nv;
    md.indices = idx;
    md.triangle_count = nt;
    c.shape = PBF_SHAPE_MESH;
    c.motion = PBF_MOTION_KINEMATIC;
    CHECK(pbf_world_create_mesh(s->world, &md, &c.mesh));
    container_pose(0, pos, q);
    memcpy(c.position, pos, sizeof pos);
    memcpy(c.rotation, kIdentity, sizeof kIdentity);
    body_create(e, s, &c, v, nv, idx, nt, glass);
    /* Half full: the lower half of the cavity. */
    fill(s, (pbf_material_id){0, 0}, pos[0] - kInner[0], pos[1] - kInner[1], pos[2] - kInner[2], pos[0] + kInner[0],
         pos[1], pos[2] + kInner[2]);
    s->before_step = container_before_step;
}

/* ---- floating boxes: the engine's rigid bodies ------------------------------------------------ */
/* One step of a body from the water's force, as release_box() and samples/floating_box.c: upright,
 * vertical motion only (semi-implicit Euler, v += (F/m - g) dt, y += v dt), the tank's floor as the
 * engine's contact. */
static void body_integrate(scene* s, scene_body* b) {
    pbf_collider_force f;
    float p[3];
    CHECK(pbf_collider_get_force(s->world, b->id, &f));
    memcpy(p, b->target, sizeof p);
    b->velocity[1] += (f.force[1] / b->mass - 9.81f) * s->dt;
    p[1] += b->velocity[1] * s->dt;
    if (p[1] - b->half < s->box_min[1]) {
        p[1] = s->box_min[1] + b->half;
        b->velocity[1] = 0.0f;
    }
    body_set_target(s, b, p, kIdentity);
}

static void floating_after_step(scene* s) {
    int k;
    for (k = 0; k < s->body_count; ++k) body_integrate(s, &s->bodies[k]);
}

static void floating_populate(pbf_egl* e, scene* s) {
    static const float densities[2] = {500.0f, 2000.0f}, xs[2] = {0.36f, 0.84f};
    static const float colors[2][4] = {{0.78f, 0.58f, 0.34f, 1.0f}, {0.62f, 0.30f, 0.26f, 1.0f}};
    const float half = 0.12f;
    int k;
    fill(s, (pbf_material_id){0, 0}, 0, 0, 0, s->box_max[0], 0.36f, s->box_max[2]);
    for (k = 0; k < 2; ++k) {
        pbf_collider_desc c = pbf_collider_desc_default();
        scene_body* b;
        c.shape = PBF_SHAPE_BOX;
        c.motion = PBF_MOTION_KINEMATIC;
        c.dynamic = 1;
        set3(c.position, xs[k], 0.37f + half, 0.36f);
        set3(c.half_extents, half, half, half);
        b = body_create_analytic(e, s, &c, colors[k]);
        b->half = half;
        b->mass = densities[k] * 8.0f * half * half * half;
    }
    s->after_step = floating_after_step;
}

/* ---- the materials scenes ---------------------------------------------------------------------- */
static void two_fluids_populate(scene* s) {
    static const float amber[3] = {0.95f, 0.62f, 0.16f};
    const pbf_material_id light = add_material(s, 500.0f, 0.0f, 0.0f, 0.0f, amber), water = {0, 0};
    fill(s, light, 0, 0.08f, 0, 0.24f, 0.72f, 0.32f);
    fill(s, water, 0.24f, 0.08f, 0, 0.48f, 0.72f, 0.32f);
    fill(s, water, 0, 0, 0, 0.48f, 0.08f, 0.32f);
}

static void hanging_drops_populate(pbf_egl* e, scene* s) {
    static const float blue[3] = {0.2f, 0.45f, 0.9f}, red[3] = {0.9f, 0.22f, 0.16f};
    static const float grey[4] = {0.72f, 0.72f, 0.74f, 1.0f};
    const pbf_material_id sticky = add_material(s, 1000.0f, 0.0f, 200.0f, 3000.0f, blue);
    const pbf_material_id plain = add_material(s, 1000.0f, 0.0f, 200.0f, 0.0f, red);
    int k;
    for (k = 0; k < 2; ++k) {
        const float x = 0.4f + 0.8f * (float)k;
        pbf_collider_desc c = pbf_collider_desc_default();
        c.shape = PBF_SHAPE_SPHERE;
        c.radius = 0.2f;
        set3(c.position, x, 0.5f, 0.4f);
        body_create_analytic(e, s, &c, grey);
        fill(s, k == 0 ? sticky : plain, x - 0.08f, 0.18f, 0.32f, x + 0.08f, 0.30f, 0.48f);
    }
}

void test_scene_configure(scene* s, const scene_options* o, pbf_world_desc* d) {
    float lo[3] = {0, 0, 0}, hi[3], eye[3], at[3];
    d->particle_radius = kR;
    d->max_particles = 8192;
    switch (o->kind) {
        case SCENE_TWO_FLUIDS:
            set3(hi, 0.48f, 0.8f, 0.32f), set3(eye, 0.64f, 0.62f, 1.62f), set3(at, 0.24f, 0.34f, 0.16f);
            d->solver.ldc_enabled = 1;
            break;
        case SCENE_DROPLET:
            set3(hi, 1.2f, 1.2f, 1.2f), set3(eye, 0.95f, 0.95f, 1.95f), set3(at, 0.6f, 0.6f, 0.6f);
            set3(d->gravity, 0, 0, 0);
            break;
        case SCENE_HANGING_DROPS:
            set3(hi, 1.6f, 0.8f, 0.8f), set3(eye, 0.8f, 0.52f, 1.6f), set3(at, 0.8f, 0.34f, 0.4f);
            break;
        case SCENE_CONTAINER: { /* the test's domain around the circle, raised with it */
            const float extent = container_path_radius() + 0.6f;
            set3(lo, kCircle[0] - extent, kCircle[1] - extent, -0.6f);
            set3(hi, kCircle[0] + extent, kCircle[1] + extent, 0.6f);
            set3(eye, 0.0f, 1.25f, 3.7f), set3(at, 0.0f, 1.1f, 0.0f);
            d->solver.max_substeps = 64;
            s->draw_walls = 0;
            break;
        }
        case SCENE_FLOATING_BOXES:
            set3(hi, 1.2f, 0.8f, 0.72f), set3(eye, 0.6f, 0.95f, 2.0f), set3(at, 0.6f, 0.28f, 0.36f);
            d->max_colliders = 8;
            break;
        default:
            die("test_scene_configure: not a test scene");
    }
    memcpy(d->domain_min, lo, sizeof lo);
    memcpy(d->domain_max, hi, sizeof hi);
    memcpy(s->eye, eye, sizeof eye);
    memcpy(s->at, at, sizeof at);
}

void test_scene_populate(pbf_egl* e, scene* s, const scene_options* o) {
    switch (o->kind) {
        case SCENE_TWO_FLUIDS:
            two_fluids_populate(s);
            break;
        case SCENE_DROPLET:
            fill(s, add_material(s, 1000.0f, 100.0f, 100.0f, 0.0f, NULL), 0.36f, 0.36f, 0.36f, 0.84f, 0.84f, 0.84f);
            break;
        case SCENE_HANGING_DROPS:
            hanging_drops_populate(e, s);
            break;
        case SCENE_CONTAINER:
            container_populate(e, s);
            break;
        case SCENE_FLOATING_BOXES:
            floating_populate(e, s);
            break;
        default:
            die("test_scene_populate: not a test scene");
    }
}
