/* What the tests measure in their scenes, measured at the end of the run (after the frame loop
 * and its transfer check: a copy-out of positions and materials) and printed as one "measured:"
 * line beside the test's bound, so the frames' log says whether the drawn run did what the test
 * checks. Sizes as render_test_scenes.c (radius 0.02 m, spacing 0.04 m). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render_scene.h"

static const float kR = 0.02f, kSpacing = 0.04f;

typedef struct particles {
    float* pos; /* x, y, z, density ratio */
    uint8_t* material;
    uint32_t count;
} particles;

static particles read_particles(scene* s) {
    particles p;
    uint32_t n = 0;
    CHECK(pbf_world_get_particle_count(s->world, &p.count));
    p.pos = (float*)malloc((size_t)p.count * 16 + 16);
    p.material = (uint8_t*)malloc((size_t)p.count + 1);
    if (!p.pos || !p.material) die("out of memory");
    CHECK(pbf_world_copy_positions(s->world, p.pos, p.count, &n));
    CHECK(pbf_world_copy_buffer(s->world, PBF_BUFFER_MATERIALS, p.material, p.count, &n));
    return p;
}

static int by_height(const void* a, const void* b) {
    const float ya = ((const float*)a)[1], yb = ((const float*)b)[1];
    return (ya > yb) - (ya < yb);
}

/* materials_scenes.h two_fluids(): the light fluid among the particles above the lowest N_heavy. */
static void report_two_fluids(const particles* p) {
    float* rows = (float*)malloc((size_t)p->count * 8 + 8);
    uint32_t i, heavy = 0, light_above = 0;
    if (!rows) die("out of memory");
    for (i = 0; i < p->count; ++i) {
        rows[2 * i] = (float)p->material[i];
        rows[2 * i + 1] = p->pos[4 * i + 1];
        heavy += p->material[i] == 0;
    }
    qsort(rows, p->count, 8, by_height);
    for (i = heavy; i < p->count; ++i) light_above += rows[2 * i] != 0.0f;
    printf("measured: light fluid above the interface %.3f (%u of %u; the test: >= 0.95 after 4 s)\n",
           (double)light_above / (double)(p->count - heavy), light_above, p->count - heavy);
    free(rows);
}

/* cube_in_zero_gravity(): the radius of the sphere of the cloud's volume over its largest extent. */
static void report_droplet(const particles* p) {
    double c[3] = {0, 0, 0}, farthest = 0.0, equal;
    uint32_t i;
    int a;
    for (i = 0; i < p->count; ++i)
        for (a = 0; a < 3; ++a) c[a] += p->pos[4 * i + a] / (double)p->count;
    for (i = 0; i < p->count; ++i) {
        const double dx = p->pos[4 * i] - c[0], dy = p->pos[4 * i + 1] - c[1], dz = p->pos[4 * i + 2] - c[2];
        farthest = fmax(farthest, sqrt(dx * dx + dy * dy + dz * dz));
    }
    equal = cbrt(3.0 * (double)p->count * kSpacing * kSpacing * kSpacing / (4.0 * 3.14159265358979));
    printf("measured: sphericity %.3f (the test: >= 0.95 after 3 s)\n", equal / (farthest + kR));
}

/* drop_under_sphere(): each drop's centroid height (material 1: adhesion, 2: none). */
static void report_hanging_drops(const particles* p) {
    double y[3] = {0, 0, 0};
    uint32_t n[3] = {0, 0, 0}, i;
    for (i = 0; i < p->count; ++i)
        if (p->material[i] < 3) {
            y[p->material[i]] += p->pos[4 * i + 1];
            ++n[p->material[i]];
        }
    printf("measured: centroid height with adhesion %.3f m, without %.3f m (the test: >= 0.20 and < 0.10 after 2 s)\n",
           n[1] ? y[1] / n[1] : -1.0, n[2] ? y[2] / n[2] : -1.0);
}

/* mesh_scenes.h shaken_container(): particles outside the cavity (in the container's frame, one
 * radius of tolerance) at the last frame; the test counts every frame. */
static void report_container(const scene* s, const particles* p) {
    static const float inner[3] = {0.16f, 0.12f, 0.16f};
    const float* q = s->bodies[0].rotation;
    uint32_t i, outside = 0;
    for (i = 0; i < p->count; ++i) {
        float v[3], c1[3], l[3];
        int a, in = 1;
        for (a = 0; a < 3; ++a) v[a] = p->pos[4 * i + a] - s->bodies[0].position[a];
        /* the inverse rotation: v + 2w (u x v) + 2 u x (u x v), u = -q.xyz */
        c1[0] = -q[1] * v[2] + q[2] * v[1], c1[1] = -q[2] * v[0] + q[0] * v[2], c1[2] = -q[0] * v[1] + q[1] * v[0];
        l[0] = v[0] + 2 * q[3] * c1[0] + 2 * (-q[1] * c1[2] + q[2] * c1[1]);
        l[1] = v[1] + 2 * q[3] * c1[1] + 2 * (-q[2] * c1[0] + q[0] * c1[2]);
        l[2] = v[2] + 2 * q[3] * c1[2] + 2 * (-q[0] * c1[1] + q[1] * c1[0]);
        for (a = 0; a < 3; ++a) in = in && fabsf(l[a]) <= inner[a] + kR;
        outside += !in;
    }
    printf("measured: %u of %u particles outside the cavity at the last frame (the test: none in any of 600 frames)\n",
           outside, p->count);
}

/* coupling_scenes.h release_box(): each box's bottom and its submerged fraction against the free
 * surface away from the boxes (mean highest centre per lattice column farther than 0.12 m from
 * any box, plus one radius). */
static void report_floating_boxes(const scene* s, const particles* p) {
    double sum = 0.0;
    uint32_t columns = 0, i;
    int cx, cz, k;
    float* top = (float*)calloc(64 * 64, sizeof(float));
    if (!top) die("out of memory");
    for (i = 0; i < p->count; ++i) {
        const float x = p->pos[4 * i], y = p->pos[4 * i + 1], z = p->pos[4 * i + 2];
        int near = 0;
        for (k = 0; k < s->body_count; ++k) {
            const scene_body* b = &s->bodies[k];
            near |= fabsf(x - b->position[0]) < b->half + 0.12f && fabsf(z - b->position[2]) < b->half + 0.12f;
        }
        cx = (int)floorf(x / kSpacing), cz = (int)floorf(z / kSpacing);
        if (near || cx < 0 || cz < 0 || cx >= 64 || cz >= 64) continue;
        if (y > top[cx * 64 + cz]) top[cx * 64 + cz] = y;
    }
    for (i = 0; i < 64 * 64; ++i)
        if (top[i] > 0.0f) sum += top[i], ++columns;
    free(top);
    if (!columns) return;
    sum = sum / columns + kR;
    for (k = 0; k < s->body_count; ++k) {
        const scene_body* b = &s->bodies[k];
        const double bottom = b->position[1] - b->half;
        printf(
            "measured: box of %.0f kg/m³: bottom %.3f m, submerged %.3f (surface %.3f m; the test: 500 floats "
            "half submerged within 5 %%, 2000 reaches the floor, bottom <= 0.05 m)\n",
            b->mass / (8.0 * b->half * b->half * b->half), bottom, fmin((sum - bottom) / (2.0 * b->half), 1.0), sum);
    }
}

void test_scene_report(scene* s, const scene_options* o) {
    particles p;
    if (o->kind == SCENE_DAM_BREAK || o->kind == SCENE_POOL) return;
    p = read_particles(s);
    if (o->kind == SCENE_TWO_FLUIDS)
        report_two_fluids(&p);
    else if (o->kind == SCENE_DROPLET)
        report_droplet(&p);
    else if (o->kind == SCENE_HANGING_DROPS)
        report_hanging_drops(&p);
    else if (o->kind == SCENE_CONTAINER)
        report_container(s, &p);
    else if (o->kind == SCENE_FLOATING_BOXES)
        report_floating_boxes(s, &p);
    free(p.pos);
    free(p.material);
}
