// The world's diffuse particles (desc.diffuse): their constants for the solver, new parameters
// between steps, and particles the API adds.
#include <cstring>
#include <vector>

#include "world.h"

namespace pbf {

DiffuseConstants diffuse_constants(const pbf_diffuse_params& p) {
    DiffuseConstants d;
    d.capacity = p.max_diffuse;
    d.trapped_air_min = p.trapped_air_min;
    d.trapped_air_max = p.trapped_air_max;
    d.wave_crest_min = p.wave_crest_min;
    d.wave_crest_max = p.wave_crest_max;
    d.energy_min = p.energy_min;
    d.energy_max = p.energy_max;
    d.trapped_air_rate = p.trapped_air_rate;
    d.wave_crest_rate = p.wave_crest_rate;
    d.lifetime = p.lifetime;
    d.spray_max_neighbors = p.spray_max_neighbors;
    d.bubble_min_neighbors = p.bubble_min_neighbors;
    d.buoyancy = p.buoyancy;
    d.bubble_drag = p.bubble_drag;
    d.spray_drag = p.spray_drag;
    return d;
}

void World::set_diffuse_params(const pbf_diffuse_params& params) {
    desc_.diffuse = params;
    backend_->set_diffuse_constants(diffuse_constants(params));
}

Status World::add_diffuse(const float* positions, const float* velocities, uint32_t count, uint32_t* added) {
    std::vector<Vec4> rows(size_t(count) * 2);
    if (count) {
        std::memcpy(rows.data(), positions, size_t(count) * sizeof(Vec4));
        std::memcpy(rows.data() + count, velocities, size_t(count) * sizeof(Vec4));
    }
    Status st = backend_->add_diffuse(rows.data(), count, added);
    if (*added > 0) mapped_ = false;
    if (st.ok() && *added == 0 && count > 0)
        return Status::error(PBF_ERROR_CAPACITY, "the world holds max_diffuse = " +
                                                     std::to_string(desc_.diffuse.max_diffuse) +
                                                     " diffuse particles already; nothing was added");
    return st;
}

}  // namespace pbf
