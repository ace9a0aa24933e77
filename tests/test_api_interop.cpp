// The graphics interop ABI without a GPU: the Direct3D 11 calls (pbf_world_register_d3d11_buffer,
// pbf_world_unregister_d3d11_buffer) and the OpenGL ones refuse bad arguments, stale handles and
// CPU worlds in every build, in the same order. Written for every platform: what depends on the
// build (D3D11 only in Windows builds with CUDA, GL in every CUDA build) is read from
// pbf_get_interop_support, so the suite also runs unchanged under Wine. The CUDA twins are in
// test_interop.cpp ([gpu]).
#include "support.h"

namespace {

uint32_t interop_support() {
    uint32_t flags = 0;
    REQUIRE_OK(pbf_get_interop_support(&flags));
    return flags;
}

bool is_zero(pbf_d3d11_buffer_id id) { return id.index == 0 && id.generation == 0; }

// A desc every check accepts: only the world or the build can refuse it.
pbf_d3d11_buffer_desc valid_d3d11_desc() {
    pbf_d3d11_buffer_desc d = pbf_d3d11_buffer_desc_default();
    d.buffer = reinterpret_cast<void*>(uintptr_t(0x1000));  // never dereferenced before a CUDA world has it
    d.capacity = 64;
    return d;
}

// The result a call with valid arguments on a CPU world gets: the build refuses first when it
// lacks `flag`, else the world's backend does.
pbf_result cpu_world_result(uint32_t flag) {
    return (interop_support() & flag) ? PBF_ERROR_INVALID_STATE : PBF_ERROR_BACKEND_UNAVAILABLE;
}

}  // namespace

TEST_CASE("interop: D3D11 exists only in Windows builds with CUDA; GL in every CUDA build", "[api][interop]") {
    const uint32_t have = interop_support();
    const bool cuda = (have & PBF_INTEROP_SUPPORT_CUDA) != 0;
#if defined(_WIN32)
    CHECK(((have & PBF_INTEROP_SUPPORT_D3D11) != 0) == cuda);
    CHECK((have & PBF_INTEROP_SUPPORT_EXTERNAL_FD) == 0u);
#else
    CHECK((have & PBF_INTEROP_SUPPORT_D3D11) == 0u);
    CHECK((have & PBF_INTEROP_SUPPORT_EXTERNAL_WIN32) == 0u);
#endif
    // GL buffers are names handed to the driver: no build with CUDA lacks them.
    CHECK(((have & PBF_INTEROP_SUPPORT_OPENGL) != 0) == cuda);
}

TEST_CASE("interop: pbf_d3d11_buffer_desc defaults and struct sizes", "[api][interop]") {
    const pbf_d3d11_buffer_desc d = pbf_d3d11_buffer_desc_default();
    CHECK(d.struct_size == sizeof d);
    CHECK(d.source == PBF_BUFFER_POSITIONS);
    CHECK(d.mode == PBF_COPY_ON_RENDER_EVENT);  // the render thread owns the D3D11 device context
    CHECK(d.buffer == nullptr);
    CHECK(d.draw_args_buffer == nullptr);
    CHECK(d.capacity == 0u);
    CHECK(d.offset_bytes == 0u);
    CHECK(d.draw_args_vertices == 0u);
    pbf_d3d11_buffer_desc e;
    CHECK_FAILS(pbf_d3d11_buffer_desc_init(&e, uint32_t(sizeof e - 8)), PBF_ERROR_STRUCT_SIZE, "struct_size");
    CHECK_FAILS(pbf_d3d11_buffer_desc_init(&e, 0), PBF_ERROR_STRUCT_SIZE, "pbf_d3d11_buffer_desc");
    CHECK_FAILS(pbf_d3d11_buffer_desc_init(nullptr, sizeof e), PBF_ERROR_INVALID_ARGUMENT, "NULL");
}

TEST_CASE("interop: pbf_world_register_d3d11_buffer refuses bad arguments before anything else", "[api][interop]") {
    TestWorld w;
    const char* fn = "pbf_world_register_d3d11_buffer";
    pbf_d3d11_buffer_id id{7, 7};
    pbf_d3d11_buffer_desc d = valid_d3d11_desc();

    CHECK_FAILS(pbf_world_register_d3d11_buffer(w.id, &d, nullptr), PBF_ERROR_INVALID_ARGUMENT, "out_buffer");
    CHECK_FAILS(pbf_world_register_d3d11_buffer(w.id, nullptr, &id), PBF_ERROR_INVALID_ARGUMENT,
                "pbf_d3d11_buffer_desc");
    CHECK(is_zero(id));  // cleared on every failure

    struct Case {
        const char* what;
        void (*spoil)(pbf_d3d11_buffer_desc&);
        pbf_result code;
        const char* needle;
    };
    const Case cases[] = {
        {"struct_size", [](pbf_d3d11_buffer_desc& x) { x.struct_size -= 8; }, PBF_ERROR_STRUCT_SIZE, "struct_size"},
        {"NULL buffer", [](pbf_d3d11_buffer_desc& x) { x.buffer = nullptr; }, PBF_ERROR_INVALID_ARGUMENT,
         "ID3D11Buffer"},
        {"unknown source",
         [](pbf_d3d11_buffer_desc& x) {
             const int32_t bad = 9;  // past the last pbf_buffer
             std::memcpy(&x.source, &bad, sizeof bad);
         },
         PBF_ERROR_INVALID_ARGUMENT, "source"},
        {"materials (bytes)", [](pbf_d3d11_buffer_desc& x) { x.source = PBF_BUFFER_MATERIALS; },
         PBF_ERROR_INVALID_ARGUMENT, "graphics buffers"},
        {"unknown mode",
         [](pbf_d3d11_buffer_desc& x) {
             const int32_t bad = 7;
             std::memcpy(&x.mode, &bad, sizeof bad);
         },
         PBF_ERROR_INVALID_ARGUMENT, "PBF_COPY_ON_RENDER_EVENT or PBF_COPY_ON_STEP"},
        {"manual mode", [](pbf_d3d11_buffer_desc& x) { x.mode = PBF_COPY_MANUAL; }, PBF_ERROR_INVALID_ARGUMENT,
         "no manual copy"},
        {"capacity 0", [](pbf_d3d11_buffer_desc& x) { x.capacity = 0; }, PBF_ERROR_INVALID_ARGUMENT, "capacity"},
        {"offset not a multiple of 16", [](pbf_d3d11_buffer_desc& x) { x.offset_bytes = 8; },
         PBF_ERROR_INVALID_ARGUMENT, "multiple of 16"},
        {"draw args offset not a multiple of 4", [](pbf_d3d11_buffer_desc& x) { x.draw_args_offset_bytes = 2; },
         PBF_ERROR_INVALID_ARGUMENT, "draw_args_offset_bytes"},
        {"reserved0", [](pbf_d3d11_buffer_desc& x) { x.reserved0 = 1; }, PBF_ERROR_INVALID_ARGUMENT, "reserved0"},
    };
    for (const Case& c : cases) {
        INFO(c.what);
        pbf_d3d11_buffer_desc bad = valid_d3d11_desc();
        c.spoil(bad);
        id = pbf_d3d11_buffer_id{7, 7};
        // Argument faults come before the build, the world handle and the backend.
        CHECK_FAILS(pbf_world_register_d3d11_buffer(w.id, &bad, &id), c.code, c.needle);
        CHECK_FAILS(pbf_world_register_d3d11_buffer(pbf_world_id{99, 5}, &bad, &id), c.code, fn);
        CHECK(is_zero(id));
    }
    // Ids are 4 bytes: offsets need only be multiples of 4 for them.
    d.source = PBF_BUFFER_IDS;
    d.offset_bytes = 4;
    CHECK_FAILS(pbf_world_register_d3d11_buffer(w.id, &d, &id), cpu_world_result(PBF_INTEROP_SUPPORT_D3D11), fn);
}

TEST_CASE("interop: graphics buffer registrations on a CPU world, a stale world, a missing source", "[api][interop]") {
    const uint32_t have = interop_support();
    const bool d3d11 = (have & PBF_INTEROP_SUPPORT_D3D11) != 0;
    const bool gl = (have & PBF_INTEROP_SUPPORT_OPENGL) != 0;
    TestWorld w;  // CPU, no render data
    w.emit_default_block();
    pbf_d3d11_buffer_id id{7, 7};
    const pbf_d3d11_buffer_desc d = valid_d3d11_desc();
    pbf_gl_buffer_desc g = pbf_gl_buffer_desc_default();
    g.buffer = 3;
    g.capacity = 64;
    pbf_gl_buffer_id gid{7, 7};

    SECTION("valid descs on a CPU world: the build refuses first, then the backend") {
        // Builds without the API say so (BACKEND_UNAVAILABLE, naming why); builds with it refuse
        // the CPU world (INVALID_STATE): the same order for both APIs.
        CHECK_FAILS(pbf_world_register_d3d11_buffer(w.id, &d, &id), cpu_world_result(PBF_INTEROP_SUPPORT_D3D11),
                    d3d11 ? "CPU backend" : ((have & PBF_INTEROP_SUPPORT_CUDA) ? "Windows builds" : "without CUDA"));
        CHECK(is_zero(id));
        CHECK_FAILS(pbf_world_register_gl_buffer(w.id, &g, &gid), cpu_world_result(PBF_INTEROP_SUPPORT_OPENGL),
                    gl ? "CPU backend" : "without CUDA");
        CHECK((gid.index == 0 && gid.generation == 0));
        pbf_d3d11_buffer_desc step = d;
        step.mode = PBF_COPY_ON_STEP;
        CHECK_FAILS(pbf_world_register_d3d11_buffer(w.id, &step, &id), cpu_world_result(PBF_INTEROP_SUPPORT_D3D11),
                    "pbf_world_register_d3d11_buffer");
        // The world is untouched: it steps, and has no interop state to report.
        const uint32_t before = w.count();
        REQUIRE_OK(pbf_world_step(w.id, kDt));
        CHECK(w.count() == before);
        pbf_interop_info info;
        std::memset(&info, 0, sizeof info);
        info.struct_size = sizeof info;
        REQUIRE_OK(pbf_world_get_interop_info(w.id, &info));
        CHECK(info.cuda_device == -1);
        CHECK(info.pending_render_work == 0u);
        CHECK(info.gl_buffers == 0u);
    }
    SECTION("a destroyed world: INVALID_HANDLE where the build has the API") {
        pbf_world_id gone = w.id;
        REQUIRE_OK(pbf_world_destroy(gone));
        w.release();
        CHECK_FAILS(pbf_world_register_d3d11_buffer(gone, &d, &id),
                    d3d11 ? PBF_ERROR_INVALID_HANDLE : PBF_ERROR_BACKEND_UNAVAILABLE,
                    "pbf_world_register_d3d11_buffer");
        CHECK(is_zero(id));
        CHECK_FAILS(pbf_world_unregister_d3d11_buffer(gone, pbf_d3d11_buffer_id{0, 1}),
                    d3d11 ? PBF_ERROR_INVALID_HANDLE : PBF_ERROR_BACKEND_UNAVAILABLE,
                    "pbf_world_unregister_d3d11_buffer");
    }
    SECTION("a source the world does not compute: INVALID_STATE naming the flag, where the build has the API") {
        pbf_d3d11_buffer_desc smooth = d;
        smooth.source = PBF_BUFFER_SMOOTHED_POSITIONS;
        if (d3d11)
            CHECK_FAILS(pbf_world_register_d3d11_buffer(w.id, &smooth, &id), PBF_ERROR_INVALID_STATE,
                        "PBF_RENDER_SMOOTHED_POSITIONS");
        else
            CHECK_FAILS(pbf_world_register_d3d11_buffer(w.id, &smooth, &id), PBF_ERROR_BACKEND_UNAVAILABLE,
                        "pbf_world_register_d3d11_buffer");
        CHECK(is_zero(id));
    }
    SECTION("unregistering a handle the world never gave out") {
        // No interop state on a CPU world: every handle is stale (or the build lacks the API).
        for (pbf_d3d11_buffer_id forged :
             {pbf_d3d11_buffer_id{0, 0}, pbf_d3d11_buffer_id{0, 1}, pbf_d3d11_buffer_id{5, 77}})
            CHECK_FAILS(pbf_world_unregister_d3d11_buffer(w.id, forged),
                        d3d11 ? PBF_ERROR_INVALID_HANDLE : PBF_ERROR_BACKEND_UNAVAILABLE,
                        d3d11 ? "not live in this world" : "pbf_world_unregister_d3d11_buffer");
        CHECK_FAILS(pbf_world_unregister_gl_buffer(w.id, pbf_gl_buffer_id{0, 1}),
                    gl ? PBF_ERROR_INVALID_HANDLE : PBF_ERROR_BACKEND_UNAVAILABLE, "pbf_world_unregister_gl_buffer");
    }
    // Nothing was queued for the render thread: a render event for this world or all is harmless.
    pbf_render_event_fn render = pbf_get_render_event_func();
    REQUIRE(render != nullptr);
    render(PBF_RENDER_EVENT_ALL_WORLDS);
}
