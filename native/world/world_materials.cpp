// The world's fluid materials: a fixed table of kMaxMaterials slots, slot 0 the default material
// (the world's rest density and solver parameters); the step plan derives the solver's constants
// from their table (solver/step_plan.h, MaterialTable).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "world.h"

#include "../solver/step_plan.h"

namespace pbf {

void World::init_materials() {
    // The default material: the world's rest density, no surface forces, pbf_material_desc's
    // colour; its viscosity and LDC gain are the solver parameters (material_desc).
    MaterialSlot& d = materials_[0];
    d.desc = pbf_material_desc{};
    d.desc.struct_size = sizeof d.desc;
    d.desc.rest_density = desc_.rest_density;
    const float color[4] = {0.2f, 0.45f, 0.9f, 1.0f};
    std::copy(color, color + 4, d.desc.color);
    d.generation = 1;
    d.alive = true;
}

pbf_material_desc World::material_desc(int slot) const {
    pbf_material_desc d = materials_[slot].desc;
    if (slot == 0) {  // one value: the solver parameters hold the default material's
        d.viscosity = desc_.solver.xsph_c;
        d.ldc_gain = desc_.solver.ldc_gain;
    }
    return d;
}

MaterialTable World::material_table() const {
    MaterialTable t;
    for (uint32_t k = 0; k < kMaxMaterials; ++k) {
        t.alive[k] = materials_[k].alive;
        if (t.alive[k]) t.desc[k] = material_desc(int(k));
    }
    return t;
}

int World::material_slot(pbf_material_id id) const {
    if (id.index == 0 && id.generation == 0) return 0;
    if (id.index >= kMaxMaterials || id.generation == 0) return -1;
    const MaterialSlot& s = materials_[id.index];
    return s.alive && s.generation == id.generation ? int(id.index) : -1;
}

Status World::create_material(const pbf_material_desc& desc, pbf_material_id* out) {
    for (uint32_t k = 1; k < kMaxMaterials; ++k) {
        MaterialSlot& s = materials_[k];
        if (s.alive) continue;
        s.desc = desc;
        s.generation = s.generation + 1 == 0 ? 1 : s.generation + 1;  // never 0: a zeroed handle
        s.alive = true;
        *out = pbf_material_id{k, s.generation};
        update_constants();
        return Status{};
    }
    return Status::error(PBF_ERROR_CAPACITY,
                         "the world holds PBF_MAX_MATERIALS = " + std::to_string(kMaxMaterials) + " materials already");
}

Status World::destroy_material(pbf_material_id id, uint32_t* emitters, uint32_t* particles) {
    *emitters = *particles = 0;
    const int slot = material_slot(id);
    if (slot < 0 || (id.index == 0 && id.generation == 0))
        return Status::error(PBF_ERROR_INVALID_HANDLE, "material is not live");
    if (slot == 0) return Status::error(PBF_ERROR_INVALID_STATE, "the default material cannot be destroyed");
    emitters_.for_each([&](EmitterEntry& e) {
        if (e.desc.type == PBF_EMITTER_NOZZLE && material_slot(e.desc.material) == slot) ++*emitters;
    });
    // Particles: the slot bytes are read back once (a rare call; it waits for the last step).
    uint32_t count = 0;
    Status st = backend_->particle_count(&count);
    if (!st.ok()) return st;
    std::vector<uint8_t> bytes(count);
    uint32_t written = 0;
    if (count > 0) st = backend_->copy_buffer(PBF_BUFFER_MATERIALS, bytes.data(), count, &written);
    if (!st.ok()) return st;
    *particles = uint32_t(std::count(bytes.begin(), bytes.begin() + written, uint8_t(slot)));
    if (*emitters > 0 || *particles > 0) return Status::error(PBF_ERROR_INVALID_STATE, "material in use");
    materials_[slot].alive = false;
    update_constants();
    return Status{};
}

Status World::get_material(pbf_material_id id, pbf_material_desc* out) const {
    const int slot = material_slot(id);
    if (slot < 0 || (id.index == 0 && id.generation == 0))
        return Status::error(PBF_ERROR_INVALID_HANDLE, "material is not live");
    *out = material_desc(slot);
    return Status{};
}

Status World::set_material(pbf_material_id id, const pbf_material_desc& desc) {
    const int slot = material_slot(id);
    if (slot < 0 || (id.index == 0 && id.generation == 0))
        return Status::error(PBF_ERROR_INVALID_HANDLE, "material is not live");
    materials_[slot].desc = desc;
    if (slot == 0) {  // the default material's viscosity and LDC gain are the solver parameters
        desc_.solver.xsph_c = desc.viscosity;
        desc_.solver.ldc_gain = desc.ldc_gain;
    }
    update_constants();
    return Status{};
}

void World::material_handles(pbf_material_id out[PBF_MAX_MATERIALS]) const {
    for (uint32_t k = 0; k < kMaxMaterials; ++k)
        out[k] = materials_[k].alive ? pbf_material_id{k, materials_[k].generation} : pbf_material_id{0, 0};
}

}  // namespace pbf
