/* Fluids of several materials: each particle's material colour reaches the surface
 * through its id. PBF_BUFFER_MATERIALS cannot be copied into a GL buffer (include/pbf_c_api.h),
 * but the ids can, and a particle keeps its id and its material for life: so the ids stream into
 * a GL buffer with the other render data (zero-copy), and a table id -> material index, built once
 * here from one copy-out of ids and materials before the frame loop, is a texture buffer the
 * splat shader reads. Particles emitted after this call (a nozzle of a coloured material) would
 * need the table rebuilt; the scenes that use it emit everything first.
 *
 * Optics. The default material's colour (0.2, 0.45, 0.9) gives the water of the dam and pool scenes: absorption
 * k = (6, 2.2, 1.1) /m and deep colour (0.02, 0.12, 0.20). Another colour c scales them per
 * channel: k_c = k_water · ln c / ln c_water (a channel the colour keeps is absorbed less) and
 * deep_c = deep_water · c / c_water, with c clamped to 0.02..0.98. The surface pass sums k·chord
 * (the optical depth of a ray through mixed fluids, Beer-Lambert) and deep·chord per pixel. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_scene.h"

static const float kWaterColor[3] = {0.2f, 0.45f, 0.9f}, kWaterAbsorption[3] = {6.0f, 2.2f, 1.1f},
                   kWaterDeep[3] = {0.02f, 0.12f, 0.20f};

static void material_optics(const float color[4], float absorption[3], float deep[3]) {
    int a;
    for (a = 0; a < 3; ++a) {
        const float c = fminf(fmaxf(color[a], 0.02f), 0.98f);
        absorption[a] = kWaterAbsorption[a] * logf(c) / logf(kWaterColor[a]);
        deep[a] = fminf(kWaterDeep[a] * c / kWaterColor[a], 1.0f);
    }
}

void materials_prepare(pbf_egl* e, scene* s) {
    pbf_material_id ids[PBF_MAX_MATERIALS];
    pbf_material_desc m;
    float base[4] = {0, 0, 0, 0};
    uint32_t count = 0, written = 0, i, max_id = 0;
    uint32_t* particle_ids;
    uint8_t *particle_materials, *table;
    int k, distinct = 0;
    scene_materials* sm = &s->materials;
    CHECK(pbf_world_get_materials(s->world, ids));
    for (k = 0; k < PBF_MAX_MATERIALS; ++k) {
        memcpy(sm->absorption[k], kWaterAbsorption, sizeof kWaterAbsorption);
        memcpy(sm->deep[k], kWaterDeep, sizeof kWaterDeep);
        if (ids[k].generation == 0) continue;
        m = pbf_material_desc_default();
        CHECK(pbf_world_get_material(s->world, ids[k], &m));
        material_optics(m.color, sm->absorption[k], sm->deep[k]);
        if (k == 0)
            memcpy(base, m.color, sizeof base);
        else if (memcmp(base, m.color, 3 * sizeof(float)) != 0)
            distinct = 1;
    }
    if (!distinct) return; /* one colour: the surface pass as before */
    sm->on = 1;
    CHECK(pbf_world_get_particle_count(s->world, &count));
    particle_ids = (uint32_t*)malloc((size_t)count * 4 + 4);
    particle_materials = (uint8_t*)malloc((size_t)count + 1);
    if (!particle_ids || !particle_materials) die("out of memory");
    CHECK(pbf_world_copy_buffer(s->world, PBF_BUFFER_IDS, particle_ids, (uint64_t)count * 4, &written));
    CHECK(pbf_world_copy_buffer(s->world, PBF_BUFFER_MATERIALS, particle_materials, count, &written));
    for (i = 0; i < written; ++i) max_id = particle_ids[i] > max_id ? particle_ids[i] : max_id;
    table = (uint8_t*)calloc((size_t)max_id + 1, 1);
    if (!table) die("out of memory");
    for (i = 0; i < written; ++i) table[particle_ids[i]] = particle_materials[i];
    e->gl.GenBuffers(1, &sm->table_buffer);
    e->gl.BindBuffer(GL_TEXTURE_BUFFER, sm->table_buffer);
    e->gl.BufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)max_id + 1, table, GL_STATIC_DRAW);
    e->gl.GenTextures(1, &sm->table_texture);
    e->gl.BindTexture(GL_TEXTURE_BUFFER, sm->table_texture);
    e->gl.TexBuffer(GL_TEXTURE_BUFFER, GL_R8UI, sm->table_buffer);
    e->gl.BindTexture(GL_TEXTURE_BUFFER, 0);
    check_gl(e, "building the material table");
    printf("materials: %u particles, ids 0..%u, colours from pbf_world_get_material (id -> material table)\n", written,
           max_id);
    free(particle_ids);
    free(particle_materials);
    free(table);
}

void materials_destroy(pbf_egl* e, scene* s) {
    if (!s->materials.on) return;
    e->gl.DeleteTextures(1, &s->materials.table_texture);
    e->gl.DeleteBuffers(1, &s->materials.table_buffer);
}
