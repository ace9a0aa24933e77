// Zero-copy rendering: what a world keeps for copying its particles into graphics API buffers
// (OpenGL buffer objects and Direct3D 11 buffers through CUDA graphics interop, Vulkan/Direct3D
// allocations through CUDA external memory and semaphores). CUDA's graphics interop is used here
// and nowhere else: the world only exposes its live buffers (World::live_buffers), its stream and
// its device's driver context.
//
// Inputs arrive validated by the C API layer (native/api/interop_calls.cpp): descs are
// complete and consistent, handles have been checked with has_*. What only the device can tell
// (sizes of GL buffers, handle imports) is checked here and reported as a Status.
#pragma once
#include <cstdint>
#include <memory>

#include "../world/world.h"
#include "pbf_c_api.h"

namespace pbf {

// PBF_INTEROP_SUPPORT_* of this build.
uint32_t interop_support();

class Interop : public WorldAttachment {
public:
    // The world's interop state, created and attached to the world on first use; the world must
    // run on CUDA (an error otherwise, or when this build has no CUDA).
    static Status of(World& world, Interop** out);
    // The world's interop state if it has one (null otherwise: no interop handle can be valid).
    static Interop* existing(World& world);
    // A new interop state for world (null and *status on failure); of() calls it.
    static std::unique_ptr<Interop> create(World& world, Status* status);

    virtual bool has_gl_buffer(pbf_gl_buffer_id id) = 0;
    virtual bool has_d3d11_buffer(pbf_d3d11_buffer_id id) = 0;
    virtual bool has_external_buffer(pbf_external_buffer_id id) = 0;
    virtual bool has_semaphore(pbf_semaphore_id id) = 0;
    virtual pbf_copy_mode gl_buffer_mode(pbf_gl_buffer_id id) = 0;
    virtual pbf_copy_mode external_buffer_mode(pbf_external_buffer_id id) = 0;

    virtual Status record_event(void** out_event) = 0;
    virtual Status wait_event(void* event) = 0;

    virtual Status register_gl_buffer(const pbf_gl_buffer_desc& desc, pbf_gl_buffer_id* out) = 0;
    virtual Status unregister_gl_buffer(pbf_gl_buffer_id id) = 0;
    virtual Status copy_to_gl_buffer(pbf_gl_buffer_id id) = 0;
    virtual Status register_d3d11_buffer(const pbf_d3d11_buffer_desc& desc, pbf_d3d11_buffer_id* out) = 0;
    virtual Status unregister_d3d11_buffer(pbf_d3d11_buffer_id id) = 0;

    virtual Status import_external_buffer(const pbf_external_buffer_desc& desc, pbf_external_buffer_id* out) = 0;
    virtual Status release_external_buffer(pbf_external_buffer_id id) = 0;
    virtual Status import_semaphore(const pbf_semaphore_desc& desc, pbf_semaphore_id* out) = 0;
    virtual Status release_semaphore(pbf_semaphore_id id) = 0;
    virtual Status copy_to_external_buffer(pbf_external_buffer_id id, const pbf_external_sync* sync) = 0;
    virtual void set_external_sync(pbf_external_buffer_id id, const pbf_external_sync* sync) = 0;

    // Whether a render event has anything to do for this world.
    virtual bool wants_render_events() = 0;
    // The render thread's share: pending registrations, copies, pending unregistrations.
    virtual Status render_event() = 0;
    virtual void get_info(pbf_interop_info* out) = 0;
};

}  // namespace pbf
