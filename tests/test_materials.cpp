// Fluid materials on the CPU backend: the scenes of materials_scenes.h ([gpu] twins
// in test_gpu_materials.cpp) and the API: defaults, the default material, per-particle read-back,
// refusals, and that a world without materials runs exactly as before.
//
// Honey piles up because the walls take part in its viscosity (no-slip for a viscous fluid,
// material_ops.h): without that, XSPH on free-slip walls let a column of viscosity 0.9 slump
// (front 0.95 m where water reached 1.19 m after 0.5 s; the bound needs at most 0.69 m).
#include "materials_scenes.h"

using namespace materials;

// ---- scenes ------------------------------------------------------------------------------------
TEST_CASE("materials: a cube with surface tension relaxes to a sphere and stays together", "[materials]") {
    check_sphere(PBF_BACKEND_CPU);
}

TEST_CASE("materials: two fluids of 1000 and 500 kg/m3 stratify without extra compression", "[materials]") {
    check_stratification(PBF_BACKEND_CPU);
}

TEST_CASE("materials: a drop hangs under a sphere by adhesion and falls without it", "[materials]") {
    check_adhesion(PBF_BACKEND_CPU);
}

TEST_CASE("materials: viscosity dissipates the same energy at 2 and 8 substeps", "[materials]") {
    check_viscosity_substeps(PBF_BACKEND_CPU);
}

TEST_CASE("materials: honey piles up where water spreads", "[materials]") { check_honey(PBF_BACKEND_CPU); }

TEST_CASE("materials: a sliding plate carries honey along and leaves water behind", "[materials]") {
    check_plate_drag(PBF_BACKEND_CPU);
}

// ---- API -----------------------------------------------------------------------------------------
namespace {
pbf_material_desc desc_of(pbf_world_id w, pbf_material_id m) {
    pbf_material_desc d = pbf_material_desc_default();
    REQUIRE_OK(pbf_world_get_material(w, m, &d));
    return d;
}
std::vector<pbf_material_id> handles(pbf_world_id w) {
    std::vector<pbf_material_id> ids(PBF_MAX_MATERIALS);
    REQUIRE_OK(pbf_world_get_materials(w, ids.data()));
    return ids;
}
}  // namespace

TEST_CASE("materials: defaults, and the default material is the world's", "[materials][api]") {
    const pbf_material_desc d = pbf_material_desc_default();
    CHECK(d.struct_size == sizeof d);
    CHECK(d.rest_density == 1000.0f);
    CHECK(d.viscosity == 0.01f);
    CHECK(d.ldc_gain == 0.3f);
    CHECK(d.surface_tension == 0.0f);
    CHECK(d.cohesion == 0.0f);
    CHECK(d.adhesion == 0.0f);
    CHECK(d.color[3] == 1.0f);
    CHECK(pbf_block_desc_default().material.generation == 0u);
    CHECK(pbf_emitter_desc_default().material.generation == 0u);

    pbf_world_desc wd = small_desc();
    wd.rest_density = 800.0f;
    wd.solver.xsph_c = 0.05f;
    TestWorld w(wd);
    const std::vector<pbf_material_id> ids = handles(w);
    REQUIRE(ids[0].generation != 0u);
    for (int k = 1; k < PBF_MAX_MATERIALS; ++k) CHECK(ids[k].generation == 0u);
    const pbf_material_desc def = desc_of(w, ids[0]);
    CHECK(def.rest_density == 800.0f);
    CHECK(def.viscosity == 0.05f);
    // Setting the default material's viscosity sets the solver's, and the other way round.
    pbf_material_desc changed = def;
    changed.viscosity = 0.2f;
    changed.surface_tension = 10.0f;
    REQUIRE_OK(pbf_world_set_material(w, ids[0], &changed));
    CHECK(w.params().xsph_c == 0.2f);
    pbf_solver_params p = w.params();
    p.xsph_c = 0.03f;
    REQUIRE_OK(pbf_world_set_solver_params(w, &p));
    CHECK(desc_of(w, ids[0]).viscosity == 0.03f);
    CHECK(desc_of(w, ids[0]).surface_tension == 10.0f);
    changed.rest_density = 1000.0f;
    CHECK_FAILS(pbf_world_set_material(w, ids[0], &changed), PBF_ERROR_INVALID_ARGUMENT,
                "default material's rest_density");
}

TEST_CASE("materials: particles carry their material through steps and copy-out", "[materials][api]") {
    TestWorld w;
    pbf_material_desc m = pbf_material_desc_default();
    m.rest_density = 700.0f;
    m.user_id = 42;
    pbf_material_id oil{};
    REQUIRE_OK(pbf_world_create_material(w, &m, &oil));
    CHECK(oil.index == 1u);
    CHECK(desc_of(w, oil).user_id == 42u);
    pbf_block_desc water = block(-0.4f, 0.0f, -0.4f, -0.1f, 0.3f, -0.1f);
    pbf_block_desc oily = block(0.1f, 0.0f, 0.1f, 0.4f, 0.3f, 0.4f);
    oily.material = oil;
    const uint32_t n_water = w.emit(water), n_oil = w.emit(oily);
    pbf_emitter_desc nozzle = nozzle_desc();
    nozzle.material = oil;
    pbf_emitter_id e{};
    REQUIRE_OK(pbf_world_create_emitter(w, &nozzle, &e));
    for (int s = 0; s < 10; ++s) REQUIRE_OK(pbf_world_step(w, kDt));
    const uint32_t n = w.count();
    REQUIRE(n > n_water + n_oil);  // the nozzle added oil
    const std::vector<uint8_t> mat = read_materials(w, n);
    const std::vector<uint32_t> ids = w.ids();  // the same storage order; water took ids 0..n_water-1
    for (uint32_t i = 0; i < n; ++i) CHECK(uint32_t(mat[i]) == (ids[i] < n_water ? 0u : oil.index));
    // Byte-wise copy-out: any out_bytes, fewer than the count copies that many.
    uint8_t few[5] = {7, 7, 7, 7, 7};
    uint32_t written = 0;
    REQUIRE_OK(pbf_world_copy_buffer(w, PBF_BUFFER_MATERIALS, few, 3, &written));
    CHECK(written == 3u);
    CHECK(few[3] == 7u);
    // The device pointers carry it too (host memory on the CPU).
    pbf_device_buffers b;
    std::memset(&b, 0, sizeof b);
    b.struct_size = sizeof b;
    REQUIRE_OK(pbf_world_map_device_buffers(w, 0, &b));
    REQUIRE(b.materials != nullptr);
    CHECK(std::memcmp(b.materials, mat.data(), n) == 0);
    REQUIRE_OK(pbf_world_unmap(w));
}

TEST_CASE("materials: refusals name the field, the handle or the use", "[materials][api]") {
    TestWorld w;
    pbf_material_desc m = pbf_material_desc_default();
    pbf_material_id id{};
    auto refused = [&](pbf_material_desc bad, pbf_result code, const char* needle) {
        CHECK_FAILS(pbf_world_create_material(w, &bad, &id), code, needle);
        CHECK(id.generation == 0u);
    };
    pbf_material_desc bad = m;
    bad.rest_density = 50.0f;
    refused(bad, PBF_ERROR_INVALID_ARGUMENT, "rest_density");
    for (float v : kBad) {
        bad = m;
        bad.viscosity = v;
        refused(bad, PBF_ERROR_INVALID_ARGUMENT, "viscosity");
        bad = m;
        bad.cohesion = v;
        refused(bad, PBF_ERROR_INVALID_ARGUMENT, "cohesion");
    }
    bad = m;
    bad.surface_tension = 1e5f;
    refused(bad, PBF_ERROR_INVALID_ARGUMENT, "surface_tension");
    bad = m;
    bad.adhesion = -1.0f;
    refused(bad, PBF_ERROR_INVALID_ARGUMENT, "adhesion");
    bad = m;
    bad.ldc_gain = 2.0f;
    refused(bad, PBF_ERROR_INVALID_ARGUMENT, "ldc_gain");
    bad = m;
    bad.color[1] = 1.5f;
    refused(bad, PBF_ERROR_INVALID_ARGUMENT, "color");
    bad = m;
    bad.reserved0 = 1;
    refused(bad, PBF_ERROR_INVALID_ARGUMENT, "reserved0");
    bad = m;
    bad.struct_size = 8;
    refused(bad, PBF_ERROR_STRUCT_SIZE, "pbf_material_desc");
    CHECK_FAILS(pbf_world_create_material(w, nullptr, &id), PBF_ERROR_INVALID_ARGUMENT,
                "pbf_material_desc pointer is NULL");
    CHECK_FAILS(pbf_world_create_material(w, &m, nullptr), PBF_ERROR_INVALID_ARGUMENT, "out_material");

    // The default material stays; a material in use stays; a full table refuses.
    const pbf_material_id def = handles(w)[0];
    CHECK_FAILS(pbf_world_destroy_material(w, def), PBF_ERROR_INVALID_STATE, "default material");
    REQUIRE_OK(pbf_world_create_material(w, &m, &id));
    pbf_block_desc b = block(-0.1f, 0.0f, -0.1f, 0.1f, 0.2f, 0.1f);
    b.material = id;
    const uint32_t emitted = w.emit(b);
    CHECK_FAILS(pbf_world_destroy_material(w, id), PBF_ERROR_INVALID_STATE, "particle(s) carry it");
    pbf_emitter_desc nozzle = nozzle_desc();
    nozzle.material = id;
    pbf_emitter_id e{};
    REQUIRE_OK(pbf_world_create_emitter(w, &nozzle, &e));
    CHECK_FAILS(pbf_world_destroy_material(w, id), PBF_ERROR_INVALID_STATE, "1 emitter(s)");
    std::vector<pbf_material_id> more;
    for (int k = 2; k < PBF_MAX_MATERIALS; ++k) {
        pbf_material_id x{};
        REQUIRE_OK(pbf_world_create_material(w, &m, &x));
        more.push_back(x);
    }
    CHECK_FAILS(pbf_world_create_material(w, &m, &id), PBF_ERROR_CAPACITY, "PBF_MAX_MATERIALS");
    CHECK(w.count() == emitted);  // nothing refused touched the particles

    // A destroyed material's handle is stale everywhere; its slot is reused under a new generation.
    const pbf_material_id gone = more.back();
    REQUIRE_OK(pbf_world_destroy_material(w, gone));
    CHECK_FAILS(pbf_world_destroy_material(w, gone), PBF_ERROR_INVALID_HANDLE, "material is not live");
    pbf_material_desc out = m;
    CHECK_FAILS(pbf_world_get_material(w, gone, &out), PBF_ERROR_INVALID_HANDLE, "material");
    CHECK_FAILS(pbf_world_set_material(w, gone, &m), PBF_ERROR_INVALID_HANDLE, "material");
    b.material = gone;
    uint32_t n = 7;
    CHECK_FAILS(pbf_world_emit_block(w, &b, &n), PBF_ERROR_INVALID_HANDLE, "material");
    CHECK(n == 0u);
    nozzle.material = pbf_material_id{3, 12345};
    CHECK_FAILS(pbf_world_create_emitter(w, &nozzle, &e), PBF_ERROR_INVALID_HANDLE, "material");
    CHECK(w.count() == emitted);
    pbf_material_id again{};
    REQUIRE_OK(pbf_world_create_material(w, &m, &again));
    CHECK(again.index == gone.index);
    CHECK(again.generation != gone.generation);
    CHECK_FAILS(pbf_world_copy_buffer(w, PBF_BUFFER_MATERIALS, nullptr, 4, &n), PBF_ERROR_INVALID_ARGUMENT, "out");
}

// A world that never creates a material, and one whose materials equal the default, step exactly
// as before materials existed (the multiphase and surface passes do not run).
TEST_CASE("materials: a material equal to the default changes nothing, bit for bit", "[materials][api]") {
    auto run_world = [](bool with_material) {
        TestWorld w;
        pbf_block_desc b = block(-0.3f, 0.0f, -0.3f, 0.0f, 0.4f, 0.3f);
        if (with_material) {
            pbf_material_desc m = pbf_material_desc_default();  // = the world's: 1000 kg/m3, xsph 0.01
            REQUIRE_OK(pbf_world_create_material(w, &m, &b.material));
        }
        w.emit(b);
        for (int s = 0; s < 20; ++s) REQUIRE_OK(pbf_world_step(w, kDt));
        return w.positions();
    };
    CHECK(same_bits(run_world(false), run_world(true)));
}
