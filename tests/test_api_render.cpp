// Render data through the C ABI (pbf_render_params, pbf_world_copy_buffer, the render buffers in
// pbf_device_buffers), CPU backend: what the anisotropy and the smoothed positions of known
// particle arrangements are, that a world without render data pays nothing for it, and the
// refusals. The CUDA twins are in test_interop.cpp ([gpu]).
#include "support.h"

using namespace scene;

namespace {

constexpr float kRadius = 0.025f, kSpacing = 0.05f, kH = 0.1f;

pbf_world_desc render_desc(uint32_t flags, uint32_t capacity = 4096) {
    pbf_world_desc d = small_desc(capacity);
    d.render.flags = flags;
    return d;
}
constexpr uint32_t kBoth = PBF_RENDER_SMOOTHED_POSITIONS | PBF_RENDER_ANISOTROPY;

float dot3(const float* a, const float* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Every particle: finite, axes unit and orthogonal, radii descending, positive, and within the
// stretch limit k_r.
void check_well_formed(const RenderData& r, float max_stretch) {
    for (uint32_t i = 0; i < r.count; ++i) {
        INFO("particle " << i);
        for (int k = 0; k < 3; ++k) {
            const float* a = r.row(i, k);
            for (int c = 0; c < 4; ++c) REQUIRE(std::isfinite(a[c]));
            CHECK(std::fabs(dot3(a, a) - 1.0f) < 1e-4f);
            CHECK(a[3] > 0.0f);
            for (int j = k + 1; j < 3; ++j) CHECK(std::fabs(dot3(a, r.row(i, j))) < 1e-3f);
        }
        CHECK(r.row(i, 0)[3] >= r.row(i, 1)[3]);
        CHECK(r.row(i, 1)[3] >= r.row(i, 2)[3]);
        CHECK(r.row(i, 0)[3] <= r.row(i, 2)[3] * max_stretch * 1.0001f);
    }
}

struct Box {
    float lo[3] = {1e9f, 1e9f, 1e9f}, hi[3] = {-1e9f, -1e9f, -1e9f};
};
Box bounds(const RenderData& r) {
    Box b;
    for (uint32_t i = 0; i < r.count; ++i)
        for (int a = 0; a < 3; ++a) {
            b.lo[a] = std::min(b.lo[a], r.pos[4 * i + a]);
            b.hi[a] = std::max(b.hi[a], r.pos[4 * i + a]);
        }
    return b;
}
// At least `margin` inside the box on the given axes.
bool inside_by(const RenderData& r, uint32_t i, const Box& b, float margin, std::initializer_list<int> axes) {
    for (int a : axes)
        if (r.pos[4 * i + a] < b.lo[a] + margin || r.pos[4 * i + a] > b.hi[a] - margin) return false;
    return true;
}

}  // namespace

TEST_CASE("render: defaults, and a lattice block: round inside, flat on top, smoothing keeps the interior",
          "[api][render]") {
    const pbf_render_params p = pbf_render_params_default();
    CHECK(p.struct_size == sizeof p);
    CHECK(p.flags == 0u);
    CHECK(p.smoothing == 0.9f);
    CHECK(p.max_stretch == 4.0f);
    CHECK(p.scale == 1.0f);
    CHECK(p.isolated_scale == 0.5f);
    CHECK(p.min_neighbors == 6u);
    CHECK(pbf_world_desc_default().render.struct_size == sizeof p);

    // A 10 x 10 x 10 lattice in mid-air; render data is computed by the emission itself.
    TestWorld w(render_desc(kBoth));
    REQUIRE(w.emit(block(-0.25f, 0.25f, -0.25f, 0.25f, 0.75f, 0.25f)) == 1000u);
    const RenderData r = read_render(w);
    REQUIRE(r.count == 1000u);
    check_well_formed(r, 4.0f);
    const Box b = bounds(r);
    int interior = 0, top = 0;
    for (uint32_t i = 0; i < r.count; ++i) {
        INFO("particle " << i << " at " << r.pos[4 * i] << ", " << r.pos[4 * i + 1] << ", " << r.pos[4 * i + 2]);
        // The smoothed position carries the position's density ratio.
        CHECK(r.smoothed[4 * i + 3] == r.pos[4 * i + 3]);
        if (inside_by(r, i, b, kH - 1e-4f, {0, 1, 2})) {
            // A full, symmetric neighbourhood: a sphere of k_s radii, and no displacement.
            ++interior;
            for (int k = 0; k < 3; ++k) CHECK(r.row(i, k)[3] == Approx(kRadius).epsilon(1e-3));
            for (int a = 0; a < 3; ++a) CHECK(std::fabs(r.smoothed[4 * i + a] - r.pos[4 * i + a]) < 1e-6f);
        } else if (r.pos[4 * i + 1] > b.hi[1] - 1e-4f && inside_by(r, i, b, kH - 1e-4f, {0, 2})) {
            // The flat top: the thin axis is the normal, the other two lie in the surface.
            ++top;
            CHECK(std::fabs(r.row(i, 2)[1]) > 0.999f);
            CHECK(std::fabs(r.row(i, 0)[1]) < 0.01f);
            CHECK(r.row(i, 0)[3] == Approx(r.row(i, 1)[3]).epsilon(1e-3));
            CHECK(r.row(i, 2)[3] < 0.8f * r.row(i, 0)[3]);
            // Smoothing pulls a surface particle inward, along the normal only.
            CHECK(r.smoothed[4 * i + 1] < r.pos[4 * i + 1] - 0.1f * kSpacing);
            CHECK(std::fabs(r.smoothed[4 * i] - r.pos[4 * i]) < 1e-6f);
            CHECK(std::fabs(r.smoothed[4 * i + 2] - r.pos[4 * i + 2]) < 1e-6f);
        }
    }
    CHECK(interior == 6 * 6 * 6);
    CHECK(top == 6 * 6);
}

TEST_CASE("render: isolated particles and small clusters stay round", "[api][render]") {
    TestWorld w(render_desc(PBF_RENDER_ANISOTROPY));
    // One particle, and a pair one spacing apart (2 neighbours each, under N_ε = 6), far apart.
    REQUIRE(w.emit(block(-0.3f, 0.5f, -0.3f, -0.3f + kSpacing, 0.5f + kSpacing, -0.3f + kSpacing)) == 1u);
    REQUIRE(w.emit(block(0.2f, 0.5f, 0.2f, 0.2f + 2 * kSpacing, 0.5f + kSpacing, 0.2f + kSpacing)) == 2u);
    for (int step = 0; step < 2; ++step) {
        INFO("after " << step << " steps");
        const RenderData r = read_render(w);
        REQUIRE(r.count == 3u);
        CHECK(r.smoothed.empty());
        for (uint32_t i = 0; i < r.count; ++i)
            for (int k = 0; k < 3; ++k) {
                CHECK(r.row(i, k)[3] == Approx(0.5f * kRadius));  // k_n = 0.5
                CHECK(r.row(i, k)[k] == 1.0f);                    // the world axes
            }
        REQUIRE_OK(pbf_world_step(w, kDt));
    }
}

TEST_CASE("render: a settled tank's free surface is flat, its particles stay well formed", "[api][render]") {
    pbf_world_desc d = tank(PBF_BACKEND_CPU, kRadius, 0.6f, 0.4f, 0.6f, 4096);
    d.render.flags = kBoth;
    TestWorld w(d);
    REQUIRE(fill(w, 0, 0, 0, 0.6f, 0.15f, 0.6f) == 12u * 3u * 12u);
    for (int s = 0; s < 90; ++s) REQUIRE_OK(pbf_world_step(w, kDt));
    const RenderData r = read_render(w);
    check_well_formed(r, 4.0f);
    const Box b = bounds(r);
    // Top-layer particles at least h from the side walls (which, having no particles, look like
    // free surfaces to the covariance: see README).
    double normal = 0, ratio = 0;
    int n = 0;
    for (uint32_t i = 0; i < r.count; ++i) {
        if (r.pos[4 * i + 1] < b.hi[1] - kSpacing || !inside_by(r, i, b, kH, {0, 2})) continue;
        normal += std::fabs(r.row(i, 2)[1]);
        ratio += r.row(i, 2)[3] / r.row(i, 0)[3];
        ++n;
    }
    INFO(n << " surface particles");
    REQUIRE(n >= 16);
    INFO("mean |thin axis . y| " << normal / n << ", mean thin / long radius " << ratio / n);
    CHECK(normal / n > 0.9);
    CHECK(ratio / n < 0.8);
}

TEST_CASE("render: off costs nothing; on, its bytes, passes and pointers are accounted for", "[api][render]") {
    const uint32_t cap = 4096;
    TestWorld off(render_desc(0, cap)), smooth(render_desc(PBF_RENDER_SMOOTHED_POSITIONS, cap)),
        aniso(render_desc(PBF_RENDER_ANISOTROPY, cap)), both(render_desc(kBoth, cap));
    for (TestWorld* t : {&off, &smooth, &aniso, &both}) {
        t->emit_default_block();
        for (int s = 0; s < 3; ++s) REQUIRE_OK(pbf_world_step(*t, kDt));
    }
    const pbf_world_info i0 = world_info(off), is = world_info(smooth), ia = world_info(aniso), ib = world_info(both);
    CHECK(i0.render_flags == 0u);
    CHECK(i0.render_bytes == 0u);
    CHECK(i0.render_updates == 0u);  // no render pass ran
    CHECK(is.render_bytes == uint64_t(cap) * 16u);
    CHECK(ia.render_bytes == uint64_t(cap) * 48u);
    CHECK(ib.render_bytes == uint64_t(cap) * 64u);
    // Nothing else differs: a world without render data allocates exactly what it did before.
    CHECK(is.device_bytes == i0.device_bytes + is.render_bytes);
    CHECK(ia.device_bytes == i0.device_bytes + ia.render_bytes);
    CHECK(ib.device_bytes == i0.device_bytes + ib.render_bytes);
    CHECK(ib.render_flags == kBoth);
    CHECK(ib.render_updates == 4u);  // the emission and 3 steps: one pass each

    // Profiled, the "render data" stage takes no time without render data: no pass ran.
    for (TestWorld* t : {&off, &both}) {
        const float ms = profiled_stage_ms(*t, "render data");
        if (t == &off)
            CHECK(ms == 0.0f);
        else
            CHECK(ms > 0.0f);
    }
    CHECK(world_info(off).render_updates == 0u);

    // Device pointers (host memory on the CPU backend) hold what copy-out returns.
    pbf_device_buffers m0, mb;
    std::memset(&m0, 0, sizeof m0);
    std::memset(&mb, 0, sizeof mb);
    m0.struct_size = mb.struct_size = sizeof m0;
    REQUIRE_OK(pbf_world_map_device_buffers(off, 0, &m0));
    CHECK(m0.smoothed_positions == nullptr);
    CHECK(m0.anisotropy == nullptr);
    CHECK(m0.render_flags == 0u);
    REQUIRE_OK(pbf_world_map_device_buffers(both, 0, &mb));
    CHECK(mb.render_flags == kBoth);
    CHECK(mb.anisotropy_stride_bytes == 48u);
    REQUIRE(mb.smoothed_positions != nullptr);
    REQUIRE(mb.anisotropy != nullptr);
    const RenderData r = read_render(both);
    REQUIRE(r.count == mb.count);
    CHECK(std::memcmp(mb.smoothed_positions, r.smoothed.data(), size_t(r.count) * 16) == 0);
    CHECK(std::memcmp(mb.anisotropy, r.aniso.data(), size_t(r.count) * 48) == 0);
    CHECK(std::memcmp(mb.positions, r.pos.data(), size_t(r.count) * 16) == 0);
    REQUIRE_OK(pbf_world_unmap(off));
    REQUIRE_OK(pbf_world_unmap(both));
    // The old copy-out calls and pbf_world_copy_buffer agree.
    CHECK(same_bits(both.positions(), r.pos));
}

TEST_CASE("render: pbf_world_copy_buffer and render params refuse bad input, and lose nothing", "[api][render]") {
    TestWorld off(render_desc(0)), on(render_desc(kBoth));
    off.emit_default_block();
    on.emit_default_block();
    const std::vector<float> before = off.positions();
    std::vector<float> out(size_t(216) * 12 + 12, -7.0f);
    uint32_t written = 99;

    SECTION("render data off: INVALID_STATE naming the flag") {
        CHECK_FAILS(pbf_world_copy_buffer(off, PBF_BUFFER_ANISOTROPY, out.data(), 48, &written),
                    PBF_ERROR_INVALID_STATE, "PBF_RENDER_ANISOTROPY");
        CHECK(written == 0u);
        CHECK_FAILS(pbf_world_copy_buffer(off, PBF_BUFFER_SMOOTHED_POSITIONS, out.data(), 16, &written),
                    PBF_ERROR_INVALID_STATE, "PBF_RENDER_SMOOTHED_POSITIONS");
        // Only smoothed positions on: anisotropy is still refused.
        TestWorld smooth(render_desc(PBF_RENDER_SMOOTHED_POSITIONS));
        CHECK_FAILS(pbf_world_copy_buffer(smooth, PBF_BUFFER_ANISOTROPY, out.data(), 48, &written),
                    PBF_ERROR_INVALID_STATE, "render data is off");
        CHECK(out[0] == -7.0f);
    }
    SECTION("NULL, wrong sizes, unknown sources, stale handles") {
        CHECK_FAILS(pbf_world_copy_buffer(on, PBF_BUFFER_ANISOTROPY, nullptr, 48, &written), PBF_ERROR_INVALID_ARGUMENT,
                    "NULL");
        CHECK_FAILS(pbf_world_copy_buffer(on, PBF_BUFFER_ANISOTROPY, out.data(), 47, &written),
                    PBF_ERROR_INVALID_ARGUMENT, "multiple of the source's element size 48");
        CHECK_FAILS(pbf_world_copy_buffer(on, PBF_BUFFER_SMOOTHED_POSITIONS, out.data(), 8, &written),
                    PBF_ERROR_INVALID_ARGUMENT, "element size 16");
        CHECK_FAILS(pbf_world_copy_buffer(on, static_cast<pbf_buffer>(0), out.data(), 48, &written),
                    PBF_ERROR_INVALID_ARGUMENT, "source");
        CHECK_FAILS(pbf_world_copy_buffer(on, static_cast<pbf_buffer>(-1), out.data(), 48, &written),
                    PBF_ERROR_INVALID_ARGUMENT, "source");
        CHECK_FAILS(pbf_world_copy_buffer(pbf_world_id{77, 3}, PBF_BUFFER_POSITIONS, out.data(), 16, &written),
                    PBF_ERROR_INVALID_HANDLE, "pbf_world_copy_buffer");
        CHECK(out[0] == -7.0f);
        // Zero bytes (NULL allowed) copy nothing; a short buffer gets the first particles only.
        REQUIRE_OK(pbf_world_copy_buffer(on, PBF_BUFFER_ANISOTROPY, nullptr, 0, &written));
        CHECK(written == 0u);
        REQUIRE_OK(pbf_world_copy_buffer(on, PBF_BUFFER_ANISOTROPY, out.data(), 5 * 48, &written));
        CHECK(written == 5u);
        CHECK(out[5 * 12] == -7.0f);
        REQUIRE_OK(pbf_world_copy_buffer(on, PBF_BUFFER_ANISOTROPY, out.data(), 5 * 48, nullptr));
    }
    SECTION("render params in the world desc") {
        pbf_world_desc d = render_desc(kBoth);
        d.render.struct_size = 8;
        pbf_world_id id{0, 0};
        CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_STRUCT_SIZE, "pbf_render_params");
        d = render_desc(kBoth);
        d.render.flags = 0x10;
        CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_INVALID_ARGUMENT, "render.flags");
        d = render_desc(kBoth);
        d.render.smoothing = kNaN;
        CHECK_FAILS(pbf_world_create(&d, &id), PBF_ERROR_INVALID_ARGUMENT, "render.smoothing");
        CHECK(id.generation == 0u);
        CHECK_FAILS(pbf_render_params_init(nullptr, sizeof(pbf_render_params)), PBF_ERROR_INVALID_ARGUMENT, "NULL");
        pbf_render_params p;
        CHECK_FAILS(pbf_render_params_init(&p, 4), PBF_ERROR_STRUCT_SIZE, "pbf_render_params");
    }
    // Nothing in the worlds was lost.
    CHECK(same_bits(off.positions(), before));
    off.require_usable(216);
    on.require_usable(216);
}

TEST_CASE("render: parameters change between steps, flags stay the creation's", "[api][render]") {
    TestWorld w(render_desc(kBoth));
    REQUIRE(w.emit(block(-0.25f, 0.25f, -0.25f, 0.25f, 0.75f, 0.25f)) == 1000u);
    pbf_render_params p = pbf_render_params_default();
    REQUIRE_OK(pbf_world_get_render_params(w, &p));
    CHECK(p.flags == kBoth);
    CHECK(p.smoothing == 0.9f);

    // No smoothing, twice the radii, a tighter stretch: seen from the next step on.
    const RenderData before = read_render(w);
    p.smoothing = 0.0f;
    p.scale = 2.0f;
    p.isolated_scale = 1.0f;
    p.max_stretch = 2.0f;
    REQUIRE_OK(pbf_world_set_render_params(w, &p));
    pbf_render_params q = pbf_render_params_default();
    REQUIRE_OK(pbf_world_get_render_params(w, &q));
    CHECK(std::memcmp(&p, &q, sizeof p) == 0);
    CHECK(read_render(w).aniso == before.aniso);  // nothing recomputed yet
    REQUIRE_OK(pbf_world_step(w, kDt));
    const RenderData r = read_render(w);
    check_well_formed(r, 2.0f);
    for (uint32_t i = 0; i < r.count; ++i)
        for (int a = 0; a < 3; ++a) CHECK(r.smoothed[4 * i + a] == r.pos[4 * i + a]);  // λ = 0: the positions
    const Box b = bounds(r);
    int interior = 0;
    for (uint32_t i = 0; i < r.count; ++i) {
        if (!inside_by(r, i, b, 2 * kH, {0, 1, 2})) continue;
        ++interior;
        CHECK(r.row(i, 0)[3] > 1.5f * kRadius);  // k_s = 2: about two radii after one step of falling
    }
    CHECK(interior > 0);

    SECTION("refusals leave the parameters as they were") {
        pbf_render_params bad = q;
        bad.flags = PBF_RENDER_ANISOTROPY;
        CHECK_FAILS(pbf_world_set_render_params(w, &bad), PBF_ERROR_INVALID_STATE, "fixed at world creation");
        bad = q;
        bad.max_stretch = 0.0f;
        CHECK_FAILS(pbf_world_set_render_params(w, &bad), PBF_ERROR_INVALID_ARGUMENT, "render.max_stretch");
        bad = q;
        bad.struct_size = 4;
        CHECK_FAILS(pbf_world_set_render_params(w, &bad), PBF_ERROR_STRUCT_SIZE, "pbf_render_params");
        CHECK_FAILS(pbf_world_set_render_params(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "NULL");
        CHECK_FAILS(pbf_world_get_render_params(w, nullptr), PBF_ERROR_INVALID_ARGUMENT, "NULL");
        bad = q;
        CHECK_FAILS(pbf_world_get_render_params(pbf_world_id{5, 5}, &bad), PBF_ERROR_INVALID_HANDLE,
                    "pbf_world_get_render_params");
        pbf_render_params now = pbf_render_params_default();
        REQUIRE_OK(pbf_world_get_render_params(w, &now));
        CHECK(std::memcmp(&now, &q, sizeof q) == 0);
        // A world without render data keeps it off: its parameters change, its flags cannot.
        TestWorld off(render_desc(0));
        pbf_render_params o = pbf_render_params_default();
        o.flags = kBoth;
        CHECK_FAILS(pbf_world_set_render_params(off, &o), PBF_ERROR_INVALID_STATE, "this world has 0");
        o.flags = 0;
        REQUIRE_OK(pbf_world_set_render_params(off, &o));
        CHECK(world_info(off).render_bytes == 0u);
    }
}
