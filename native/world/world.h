// A world on the host side: its handles (emitters, colliders, materials, meshes) and their
// lifecycle, its parameters, and the backend that holds the particles. Inputs arrive validated
// by the C API layer; the world only applies them. The physics of a step (constants, substeps,
// emission) is the step plan's (solver/step_plan.h); this header names the solver only by
// forward declarations, and passes on the live buffers (common/live_buffers.h) to interop.
#pragma once
#include <memory>
#include <vector>

#include "../common/live_buffers.h"
#include "../common/slot_table.h"
#include "../common/status.h"
#include "../core/params.h"
#include "../core/sdf.h"
#include "pbf_c_api.h"

namespace pbf {

class Backend;
struct MaterialTable;
struct MeshBuild;

struct ColliderEntry {
    Collider collider;  // shape data; its poses are computed per substep
    uint32_t motion;    // pbf_collider_motion
    Vec3 position, target_position;
    float rotation[4], target_rotation[4];  // unit quaternions (x, y, z, w)
    pbf_mesh_id mesh{};                     // PBF_SHAPE_MESH: the mesh it uses
};

struct MeshEntry {
    uint32_t users = 0;  // colliders using it: destroy is refused until none
    float reach = 0.0f;  // farthest point of its solid from its origin
};

// Where a mesh's field lies (its own frame) and how many voxels it takes (meshes.cpp).
struct MeshLayout {
    MeshView grid{};
    int32_t bricks[3] = {};
    float half_thickness = 0.0f;
    float margin = 0.0f;  // triangles are binned to the bricks within this distance
    float kernel_radius = 0.0f;
    uint64_t voxels = 0;
};
// The layout of desc's field in a world of particle radius r and kernel radius h.
MeshLayout mesh_layout(const pbf_mesh_desc& desc, float r, float h);
// The host's part of the build: vertices, the non-degenerate triangles (the backend bins them); *reach
// = the farthest point of the solid from the mesh's origin.
MeshBuild prepare_mesh(const pbf_mesh_desc& desc, const MeshLayout& layout, float* reach);

struct EmitterEntry {
    pbf_emitter_desc desc;     // normalised direction
    float accumulator = 0.0f;  // fractional particles carried between substeps
    uint32_t sequence = 0;
};

// A material slot (world_materials.cpp). Slot 0 is the default material.
struct MaterialSlot {
    pbf_material_desc desc{};
    uint32_t generation = 0;
    bool alive = false;
};

// State another layer keeps with a world (the interop layer, native/interop): told after each
// successful step, destroyed with the world before its backend.
class WorldAttachment {
public:
    virtual ~WorldAttachment() = default;
    virtual Status after_step() = 0;
};

class World {
public:
    // desc is validated; *status says why creation failed.
    static std::unique_ptr<World> create(const pbf_world_desc& desc, Status* status);

    ~World();

    // Advances the world by one frame step of frame_dt seconds, in substeps (solver/step_plan.h).
    Status step(float frame_dt);
    const pbf_solver_params& solver_params() const { return desc_.solver; }
    void set_solver_params(const pbf_solver_params& p);
    void set_gravity(const float g[3]);
    void get_info(pbf_world_info* info) const;
    Status get_stats(pbf_step_stats* stats);

    Status emit_block(const pbf_block_desc& desc, uint32_t* emitted);
    Status create_emitter(const pbf_emitter_desc& desc, pbf_emitter_id* out);
    bool destroy_emitter(pbf_emitter_id id) { return emitters_.erase(id.index, id.generation); }
    EmitterEntry* find_emitter(pbf_emitter_id id) { return emitters_.find(id.index, id.generation); }

    Status create_collider(const pbf_collider_desc& desc, pbf_collider_id* out);
    bool destroy_collider(pbf_collider_id id);
    // The fluid's mean force and torque on a dynamic collider over the last step (waits for
    // it): INVALID_HANDLE when not live, INVALID_STATE when not dynamic.
    Status collider_force(pbf_collider_id id, pbf_collider_force* out);
    // The backend's table of them (max_colliders rows by handle index), for pbf_mapped_buffer.
    const void* collider_force_table() const;
    uint32_t max_colliders() const { return desc_.max_colliders; }
    ColliderEntry* find_collider(pbf_collider_id id) { return colliders_.find(id.index, id.generation); }

    // ---- materials (world_materials.cpp); descs arrive validated -------------------------------
    // The slot of a live material handle, 0 for a zeroed one (the default material), -1 otherwise.
    int material_slot(pbf_material_id id) const;
    float rest_density() const { return desc_.rest_density; }
    Status create_material(const pbf_material_desc& desc, pbf_material_id* out);
    // INVALID_STATE for the default material; *emitters / *particles: the users found (then refused).
    Status destroy_material(pbf_material_id id, uint32_t* emitters, uint32_t* particles);
    Status get_material(pbf_material_id id, pbf_material_desc* out) const;
    Status set_material(pbf_material_id id, const pbf_material_desc& desc);
    void material_handles(pbf_material_id out[PBF_MAX_MATERIALS]) const;
    // Meshes (meshes.cpp). desc validated, its field within PBF_MAX_MESH_FIELD_BYTES (mesh_layout).
    MeshLayout mesh_layout(const pbf_mesh_desc& desc) const;
    Status create_mesh(const pbf_mesh_desc& desc, pbf_mesh_id* out);
    // INVALID_HANDLE when not live, INVALID_STATE while a collider uses it.
    Status destroy_mesh(pbf_mesh_id id);

    Status particle_count(uint32_t* count);
    Status copy_positions(float* out, uint32_t max, uint32_t* written) {
        return copy_buffer(PBF_BUFFER_POSITIONS, out, max, written);
    }
    Status copy_velocities(float* out, uint32_t max, uint32_t* written) {
        return copy_buffer(PBF_BUFFER_VELOCITIES, out, max, written);
    }
    Status copy_ids(uint32_t* out, uint32_t max, uint32_t* written) {
        return copy_buffer(PBF_BUFFER_IDS, out, max, written);
    }
    // Any particle buffer (source valid; has_buffer(source) true).
    Status copy_buffer(pbf_buffer source, void* out, uint32_t max, uint32_t* written);
    // Bytes per particle of a buffer (1 materials, 4 ids, 48 anisotropy, else 16).
    static uint32_t element_bytes(pbf_buffer source) { return buffer_element_bytes(source); }
    // Whether the world has this buffer (the render buffers only when desc.render asked for them).
    bool has_buffer(pbf_buffer source) { return live_buffer(live_buffers(), source) != nullptr; }
    uint32_t render_flags() const { return desc_.render.flags; }
    const pbf_render_params& render_params() const { return desc_.render; }
    // params validated, with the world's flags.
    void set_render_params(const pbf_render_params& params);
    // Diffuse particles: params validated, with the world's max_diffuse; rows validated.
    const pbf_diffuse_params& diffuse_params() const { return desc_.diffuse; }
    void set_diffuse_params(const pbf_diffuse_params& params);
    Status add_diffuse(const float* positions, const float* velocities, uint32_t count, uint32_t* added);
    void unmap() { mapped_ = false; }
    bool mapped() const { return mapped_; }

    float rest_spacing() const { return 2.0f * desc_.particle_radius; }
    WorldAttachment* attachment() { return attachment_.get(); }
    void set_attachment(std::unique_ptr<WorldAttachment> a) { attachment_ = std::move(a); }

    // ---- doors for the API and interop layers (world_access.cpp) -----------------------------
    // Everything native/api and native/interop ask of a world goes through these (and the calls
    // above); neither reaches the backend. Inputs arrive validated; normalisation happens here.
    // Whether CUDA device `device` can run a world: ok, or PBF_ERROR_BACKEND_UNAVAILABLE with why not.
    static Status cuda_available(int32_t device);
    // What pbf_get_backend_info reports for backend on device.
    static void describe_backend(pbf_backend backend, int32_t device, pbf_backend_info* out);
    pbf_backend backend_kind() const;
    // Emitters: false / INVALID_HANDLE when the handle is not live. A nozzle takes (position,
    // direction), the direction normalised here; a drain takes (box_min, box_max).
    bool set_emitter_enabled(pbf_emitter_id id, bool enabled);
    Status set_emitter_transform(pbf_emitter_id id, const float a[3], const float b[3]);
    // The pose a kinematic collider reaches at the end of the next step (rotation normalised
    // here): INVALID_HANDLE when not live, INVALID_STATE when static.
    Status set_collider_target(pbf_collider_id id, const float position[3], const float rotation[4]);
    // Any collider: its pose now, without motion (the next step starts and ends there).
    Status teleport_collider(pbf_collider_id id, const float position[3], const float rotation[4]);
    // The one route to map the particles: the live buffers in backend memory, valid until the
    // next step or emission, and the live count (read back unless !wait_for_count on CUDA, where
    // it is PBF_COUNT_ON_DEVICE and only *live.count holds it). Marks the world mapped.
    struct Mapping {
        LiveBuffers live;
        uint32_t count = 0;
        uint32_t diffuse_count = 0;  // as count, for the diffuse particles (0 without them)
        bool device = false;         // CUDA device memory (else host memory)
        void* cuda_stream = nullptr;
    };
    Status map_particles(bool wait_for_count, Mapping* out);
    // Interop: the live buffers without mapping, and the world's CUDA stream.
    LiveBuffers live_buffers();
    void* cuda_stream() const;
    Status set_cuda_stream(void* stream);
    // Per-stage timing (pbf_bench): on or off, and the last step's milliseconds per stage
    // (out validated); a stage's name, null past the last stage.
    void set_profiling(bool on);
    Status get_profile(pbf_step_profile* out);
    static const char* stage_name(uint32_t stage);

private:
    World() = default;
    void update_constants();
    void init_materials();
    // A material slot's desc as it is now (slot 0's viscosity and LDC gain: the solver
    // parameters), and the table of them the step plan reads.
    pbf_material_desc material_desc(int slot) const;
    MaterialTable material_table() const;
    Status check_nozzle(const pbf_emitter_desc& d, Vec3 position) const;
    static void set_nozzle_direction(pbf_emitter_desc& d, Vec3 direction);
    Status colliders_changed();
    // The step's colliders: shapes (bounds over the motion from the current pose to the
    // target) and keys; returns how many are dynamic.
    uint32_t gather_colliders(bool moving, std::vector<Collider>* shapes, std::vector<ColliderKey>* keys);

    // The world's parameters, one value each: the solver parameters, gravity, render and diffuse
    // parameters as last set (the default material's viscosity and LDC gain are solver.xsph_c
    // and solver.ldc_gain). constants_ is derived from them (update_constants).
    pbf_world_desc desc_{};
    WorldConstants constants_{};
    float emitted_speed_ = 0.0f;  // fastest particle emitted since the last step (block velocity)
    float emitted_depth_ = 0.0f;  // tallest block emitted since the last step, along gravity (m)
    // A collider created or teleported, or a block emitted, since the last step: particles may
    // overlap a collider without having moved into it (the step's first substep settles them).
    bool overlaps_pending_ = false;
    float carried_dt_ = 0.0f;  // frame steps too short to simulate, waiting for the next (plan_step)
    std::unique_ptr<Backend> backend_;
    SlotTable<EmitterEntry> emitters_;
    SlotTable<ColliderEntry> colliders_;
    MaterialSlot materials_[kMaxMaterials];
    SlotTable<MeshEntry> meshes_;  // a mesh's handle index is its row of the backend's mesh table
    uint64_t step_index_ = 0;
    uint32_t last_iterations_ = 0;
    uint32_t last_substeps_ = 0;
    float last_simulated_dt_ = 0.0f;  // the time the last step advanced (its dt unless capped)
    bool mapped_ = false;
    std::unique_ptr<WorldAttachment> attachment_;  // declared after backend_: destroyed before it
};

}  // namespace pbf
