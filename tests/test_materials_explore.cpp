#include "materials_scenes.h"
using namespace materials;
TEST_CASE("explore cube", "[.][explore_cube]") {
    for (auto pr : std::vector<std::pair<float,float>>{{100,100},{200,0},{50,50}}) { float st = pr.first, coh = pr.second;
        Shape s = cube_in_zero_gravity(PBF_BACKEND_CPU, st, coh, 3.0f);
        printf("st %g coh %g: sph %.3f maxd %.3f req %.3f\n", st, coh, s.sphericity, s.max_distance, s.equal_radius);
    }
}
TEST_CASE("explore strat", "[.][explore_strat]") {
    Stratification a = two_fluids(PBF_BACKEND_CPU, 1000.0f, 4.0f);
    printf("single: depth mean %.4f %.4f max %.4f %.4f\n", a.depth_mean[0], a.depth_mean[1], a.depth_max[0], a.depth_max[1]);
    for (float t : {4.0f}) for (uint32_t ldc : {1u}) {
    Stratification b = two_fluids(PBF_BACKEND_CPU, 500.0f, t, ldc);
    printf("t %g ldc %u ", t, ldc);
    printf("two: above %.3f err mean %.4f %.4f max %.4f %.4f\n", b.light_above, b.error_mean[0], b.error_mean[1], b.error_max[0], b.error_max[1]);
    }
}
TEST_CASE("explore drop", "[.][explore_drop]") {
    for (float adh : {0.0f, 1000.0f, 3000.0f}) for (float coh : {0.0f, 200.0f}) {
        Drop d = drop_under_sphere(PBF_BACKEND_CPU, adh, coh, 2.0f);
        printf("adh %g coh %g: y %.3f\n", adh, coh, d.centroid_y);
    }
}
TEST_CASE("explore visc", "[.][explore_visc]") {
    for (float v : {0.0f, 0.02f, 0.05f, 0.1f}) {
        printf("visc %g: loss2 %.4f loss8 %.4f\n", v, shear_loss(PBF_BACKEND_CPU, v, 2), shear_loss(PBF_BACKEND_CPU, v, 8));
    }
    for (float t : {0.3f, 0.5f}) for (float v : {0.01f, 0.5f, 0.9f}) { Spread s = collapse(PBF_BACKEND_CPU, v, t); printf("collapse t %g visc %g: front %.3f height %.3f\n", t, v, s.front, s.height); }
}
TEST_CASE("explore layers", "[.][explore_layers]") {
    pbf_world_desc d = box_world(PBF_BACKEND_CPU, 0.48f, 0.8f, 0.32f, 9.81f);
    pbf_world_id w = scene::create(d);
    pbf_material_desc m = pbf_material_desc_default();
    m.rest_density = 500;
    const pbf_material_id light = add_material(w, m);
    const float lo_l[3] = {0, 0.08f, 0}, hi_l[3] = {0.24f, 0.72f, 0.32f};
    const float lo_h[3] = {0.24f, 0.08f, 0}, hi_h[3] = {0.48f, 0.72f, 0.32f};
    const float lo_f[3] = {0, 0, 0}, hi_f[3] = {0.48f, 0.08f, 0.32f};
    fill(w, light, lo_l, hi_l); fill(w, pbf_material_id{0,0}, lo_h, hi_h); fill(w, pbf_material_id{0,0}, lo_f, hi_f);
    run(w, 3.0f);
    const scene::Particles p = scene::read(w);
    const std::vector<uint8_t> mat = read_materials(w, p.count);
    int hl[40] = {0}, hh[40] = {0};
    for (uint32_t i = 0; i < p.count; ++i) { int b = int(p.pos[4*i+1] / 0.04f); if (b > 39) b = 39; (mat[i] ? hl : hh)[b]++; }
    for (int b = 0; b < 20; ++b) printf("y %.2f light %d heavy %d\n", b*0.04, hl[b], hh[b]);
    pbf_world_destroy(w);
}
