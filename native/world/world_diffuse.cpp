// The world's diffuse particles (desc.diffuse): new parameters between steps, and particles the
// API adds.
#include <cstring>
#include <vector>

#include "world.h"

#include "../solver/step_plan.h"

namespace pbf {

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
        return Status::error(PBF_ERROR_CAPACITY,
                             "the world holds max_diffuse = " + std::to_string(desc_.diffuse.max_diffuse) +
                                 " diffuse particles already; nothing was added");
    return st;
}

}  // namespace pbf
