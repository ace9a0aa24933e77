/* Headless renderer: a dam break or a nozzle filling a pool, drawn straight from libpbf's
 * buffers and written as PNG frames.
 *
 *   pbf_render_gl OUT_DIR [--mode surface|spheres] [--particles N=65536]
 *                         [--scene dam|pool|two_fluids|droplet|hanging_drops|container|floating_boxes]
 *                         [--frames N=180] [--every K=15] [--save F1,F2,...] [--size WxH=640x360]
 *                         [--backend auto|cpu|cuda] [--color speed|density]
 *                         [--splat-scale S=1.6] [--smooth-iterations N=3] [--smooth-sigma R=4]
 *                         [--write-background] [--bench N=0] [--bench-frames N=60]
 *
 * EGL on the device platform (no window, no X) with an OpenGL 4.3 core context. The vertex
 * buffers are registered with libpbf (pbf_world_register_gl_buffer, PBF_COPY_ON_STEP): each
 * pbf_world_step copies the particles GPU to GPU into them and writes the draw count, so the
 * frame loop reads nothing back. Without CUDA-GL interop (the CPU backend) the buffers are filled
 * through the host instead, and the log says so (render_scene.c).
 *
 * surface (default): smoothed positions + anisotropy drawn as a screen-space surface
 *   (render_surface.c); spheres: positions as shaded sphere impostors coloured by speed or
 *   density ratio (render_spheres.c). Both draw the diffuse particles where libpbf has them.
 *
 * Then it checks that the GL buffers equal pbf_world_copy_buffer, prints the library's
 * host<->device transfer count over the frame loop (0 expected on the zero-copy path), and times
 * the render path's copy at --bench particles. The last line is a one-line summary; the exit code
 * is 0 only if everything held, 77 when no EGL display could be created. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "render_passes.h"

typedef struct options {
    const char* out_dir;
    scene_options scene;
    long every, bench, bench_frames;
    long save[64];
    int save_count, width, height, color_by_density, write_background;
    surface_style style;
} options;

static void usage(void) {
    fprintf(stderr,
            "usage: pbf_render_gl OUT_DIR [--mode surface|spheres] [--particles N=65536]\n"
            "                     [--scene dam|pool|two_fluids|droplet|hanging_drops|container|floating_boxes]\n"
            "                     [--frames N=180] [--every K=15] [--save F1,F2,...] [--size WxH=640x360]\n"
            "                     [--backend auto|cpu|cuda] [--color speed|density]\n"
            "                     [--splat-scale S=1.6] [--smooth-iterations N=3] [--smooth-sigma R=4]\n"
            "                     [--write-background] [--bench N=0] [--bench-frames N=60]\n");
    exit(2);
}

/* Picks `value` among names[0..n); exits with the usage otherwise. */
static int choose(const char* value, const char* const* names, int n) {
    int k;
    for (k = 0; k < n; ++k)
        if (strcmp(value, names[k]) == 0) return k;
    usage();
    return 0;
}

static void parse_save(options* o, const char* list) {
    const char* p = list;
    char* end;
    o->save_count = 0;
    while (*p && o->save_count < 64) {
        o->save[o->save_count++] = strtol(p, &end, 10);
        if (end == p) usage();
        p = *end == ',' ? end + 1 : end;
    }
}

static void parse(options* o, int argc, char** argv) {
    static const char *const modes[] = {"spheres", "surface"}, *const backends[] = {"auto", "cpu", "cuda"},
                             *const colors[] = {"speed", "density"};
    static const pbf_backend backend_ids[] = {PBF_BACKEND_AUTO, PBF_BACKEND_CPU, PBF_BACKEND_CUDA};
    int i;
    memset(o, 0, sizeof *o);
    o->scene.kind = SCENE_DAM_BREAK;
    o->scene.particles = 65536;
    o->scene.frames = 180;
    o->scene.surface = 1;
    o->scene.backend = PBF_BACKEND_AUTO;
    o->every = 15;
    o->bench_frames = 60;
    o->width = 640;
    o->height = 360;
    o->style.splat_scale = 1.6f;
    o->style.smooth_iterations = 3;
    o->style.smooth_sigma = 4.0f;
    if (argc < 2 || argv[1][0] == '-') usage();
    o->out_dir = argv[1];
    for (i = 2; i < argc; ++i) {
        const char* a = argv[i];
        const char* v = i + 1 < argc ? argv[i + 1] : "";
        if (strcmp(a, "--write-background") == 0) {
            o->write_background = 1;
            continue;
        }
        if (i + 1 >= argc) usage();
        ++i;
        if (strcmp(a, "--mode") == 0)
            o->scene.surface = choose(v, modes, 2);
        else if (strcmp(a, "--scene") == 0)
            o->scene.kind = (scene_kind)choose(v, kSceneNames, SCENE_KIND_COUNT);
        else if (strcmp(a, "--backend") == 0)
            o->scene.backend = backend_ids[choose(v, backends, 3)];
        else if (strcmp(a, "--color") == 0)
            o->color_by_density = choose(v, colors, 2);
        else if (strcmp(a, "--particles") == 0)
            o->scene.particles = atol(v);
        else if (strcmp(a, "--frames") == 0)
            o->scene.frames = atol(v);
        else if (strcmp(a, "--every") == 0)
            o->every = atol(v);
        else if (strcmp(a, "--save") == 0)
            parse_save(o, v);
        else if (strcmp(a, "--bench") == 0)
            o->bench = atol(v);
        else if (strcmp(a, "--bench-frames") == 0)
            o->bench_frames = atol(v);
        else if (strcmp(a, "--splat-scale") == 0)
            o->style.splat_scale = (float)atof(v);
        else if (strcmp(a, "--smooth-iterations") == 0)
            o->style.smooth_iterations = atoi(v);
        else if (strcmp(a, "--smooth-sigma") == 0)
            o->style.smooth_sigma = (float)atof(v);
        else if (strcmp(a, "--size") == 0) {
            if (sscanf(v, "%dx%d", &o->width, &o->height) != 2) usage();
        } else
            usage();
    }
    if (o->scene.particles < 64 || o->scene.frames < 1 || o->every < 1 || o->width < 16 || o->height < 16 ||
        o->bench < 0 || o->bench_frames < 1 || o->style.splat_scale <= 0.0f || o->style.smooth_iterations < 0 ||
        o->style.smooth_sigma <= 0.0f)
        usage();
}

static int is_saved(const options* o, long frame) {
    int k;
    if (o->save_count == 0) return frame % o->every == 0 || frame == o->scene.frames;
    for (k = 0; k < o->save_count; ++k)
        if (o->save[k] == frame) return 1;
    return 0;
}

/* mkdir -p. */
static void make_directories(const char* path) {
    char buffer[4096];
    size_t k, n = strlen(path);
    if (n >= sizeof buffer) die("output path too long");
    snprintf(buffer, sizeof buffer, "%s", path);
    for (k = 1; k <= n; ++k)
        if (buffer[k] == '/' || buffer[k] == '\0') {
            char c = buffer[k];
            buffer[k] = '\0';
            mkdir(buffer, 0755);
            buffer[k] = c;
        }
}

static void draw(pbf_egl* e, const target* t, const camera* c, const scene* s, const options* o) {
    if (o->scene.surface)
        draw_surface(e, t, c, s, &o->style);
    else
        draw_spheres(e, t, c, s, o->color_by_density);
    draw_diffuse(e, t, c, s);
}

static int save_frame(pbf_egl* e, target* t, GLuint fbo, const char* dir, const char* name) {
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    e->gl.BindFramebuffer(GL_FRAMEBUFFER, fbo);
    return write_png(e, t->width, t->height, t->pixels, path);
}

/* The render path's cost at o->bench particles: per step, the GPU time of map + copy of the
 * mode's buffers + draw count + unmap, against the step's own GPU time. */
static void bench(pbf_egl* e, target* t, const options* o) {
    scene b;
    scene_options so = o->scene;
    double copy_gpu = 0.0, copy_host = 0.0, step_gpu = 0.0, copyout_ms = 0.0;
    float* host_copy;
    uint32_t written = 0;
    const long warmup = 5;
    long i;
    camera c;
    pbf_interop_info info;
    pbf_step_stats stats;
    /* One substep per step, as pbf_bench's "step" (so the share compares with its numbers). */
    so.particles = o->bench;
    so.substeps = 1;
    so.kind = SCENE_DAM_BREAK;
    scene_create(e, &b, &so);
    if (!b.zero_copy) {
        printf("bench: skipped (the copy path has no GPU-to-GPU copy to time)\n");
        scene_destroy(e, &b);
        return;
    }
    for (i = 0; i < warmup + o->bench_frames; ++i) {
        scene_step(e, &b);
        memset(&info, 0, sizeof info);
        info.struct_size = sizeof info;
        CHECK(pbf_world_get_interop_info(b.world, &info)); /* waits for the copy */
        memset(&stats, 0, sizeof stats);
        stats.struct_size = sizeof stats;
        CHECK(pbf_world_get_stats(b.world, &stats));
        if (i >= warmup) {
            copy_gpu += info.last_copy_gpu_ms;
            copy_host += info.last_copy_host_ms;
            step_gpu += stats.step_time_ms;
        }
    }
    copy_gpu /= (double)o->bench_frames;
    copy_host /= (double)o->bench_frames;
    step_gpu /= (double)o->bench_frames;
    /* For scale: the same positions through the host (what zero-copy avoids). */
    host_copy = (float*)malloc((size_t)b.capacity * 16);
    if (!host_copy) die("out of memory");
    for (i = 0; i < 5; ++i) {
        double t0 = now_ms();
        CHECK(pbf_world_copy_positions(b.world, host_copy, b.capacity, &written));
        copyout_ms += now_ms() - t0;
    }
    copyout_ms /= 5.0;
    free(host_copy);
    camera_look(&c, b.eye, b.at, 40.0f, t->width, t->height);
    draw(e, t, &c, &b, o);
    {
        char name[64];
        snprintf(name, sizeof name, "bench_%ld.png", o->bench);
        save_frame(e, t, t->fbo, o->out_dir, name);
    }
    printf(
        "render path at %u particles (%s, %ld steps of 1 substep): copy %.4f ms GPU (map..unmap), %.4f ms host; "
        "step %.3f ms GPU; render path = %.2f %% of a step (copy-out of the positions through the host: %.3f ms)\n",
        b.emitted,
        o->scene.surface ? "smoothed positions + anisotropy + draw count" : "positions + velocities + draw count",
        o->bench_frames, copy_gpu, copy_host, step_gpu, step_gpu > 0 ? 100.0 * copy_gpu / step_gpu : 0.0, copyout_ms);
    printf(
        "BENCH render_path mode=%s particles=%u substeps=1 copy_gpu_ms=%.4f copy_host_ms=%.4f step_gpu_ms=%.4f "
        "percent=%.3f copyout_host_ms=%.3f\n",
        o->scene.surface ? "surface" : "spheres", b.emitted, copy_gpu, copy_host, step_gpu,
        step_gpu > 0 ? 100.0 * copy_gpu / step_gpu : 0.0, copyout_ms);
    scene_destroy(e, &b);
}

int main(int argc, char** argv) {
    options o;
    char err[512], name[64];
    pbf_egl e;
    scene s;
    target t;
    camera c;
    uint64_t transfers_before = 0, transfers_after = 0;
    uint32_t verified_count = 0;
    long mismatches, i;
    int pngs = 0, ok = 1, k;
    double loop_ms;

    parse(&o, argc, argv);
    make_directories(o.out_dir);
    if (!pbf_egl_init(&e, 0, err, sizeof err)) {
        fprintf(stderr, "pbf_render_gl: no EGL display, nothing rendered (skipped): %s\n", err);
        return 77;
    }
    printf("GL: %s | %s | EGL device %d%s\n", (const char*)e.gl.GetString(GL_RENDERER),
           (const char*)e.gl.GetString(GL_VERSION), e.egl_device_index,
           e.matched_cuda_device ? " (= CUDA device 0)" : " (CUDA ordinal not reported; first device)");

    target_create(&e, &t, o.width, o.height);
    scene_create(&e, &s, &o.scene);
    camera_look(&c, s.eye, s.at, 40.0f, o.width, o.height);
    printf("%s: %u particles at start, radius %.4f m, %ld frames of 1/60 s, %dx%d, mode %s%s, diffuse particles: %s\n",
           o.scene.kind == SCENE_POOL        ? "pool"
           : o.scene.kind == SCENE_DAM_BREAK ? "dam break"
                                             : kSceneNames[o.scene.kind],
           s.emitted, s.radius, o.scene.frames, o.width, o.height, o.scene.surface ? "surface" : "spheres",
           o.scene.surface ? "" : (o.color_by_density ? " (colour by density ratio)" : " (colour by speed)"),
           s.has_diffuse ? "drawn"
           : (o.scene.kind == SCENE_DAM_BREAK || o.scene.kind == SCENE_POOL)
               ? "not in this libpbf (built without PBF_BUFFER_DIFFUSE_POSITIONS)"
               : "off (as in the test)");

    /* The frame loop: step (which copies into the GL buffers on the GPU), draw, sometimes save.
     * Nothing in it asks libpbf for data on the host (on the zero-copy path). */
    CHECK(pbf_debug_get_transfer_count(&transfers_before, NULL));
    loop_ms = now_ms();
    for (i = 1; i <= o.scene.frames; ++i) {
        scene_step(&e, &s);
        /* On the copy path (a machine without a GPU, llvmpipe) only the saved frames are drawn:
         * drawing dominates there. The zero-copy path draws every frame, as an engine would. */
        if (s.zero_copy || is_saved(&o, i)) draw(&e, &t, &c, &s, &o);
        if (is_saved(&o, i)) {
            snprintf(name, sizeof name, "frame_%04ld.png", i);
            if (save_frame(&e, &t, t.fbo, o.out_dir, name))
                ++pngs;
            else
                ok = 0;
        }
    }
    e.gl.Finish();
    loop_ms = now_ms() - loop_ms;
    CHECK(pbf_debug_get_transfer_count(&transfers_after, NULL));
    printf("frame loop: %ld frames in %.1f ms (%.2f ms/frame incl. PNG writes%s), %d PNGs in %s\n", o.scene.frames,
           loop_ms, loop_ms / (double)o.scene.frames, s.zero_copy ? "" : "; copy path: only saved frames drawn", pngs,
           o.out_dir);
    if (o.write_background && o.scene.surface) {
        /* The last frame's background pass alone: the frame equals it wherever no fluid is drawn. */
        if (save_frame(&e, &t, t.surface.background_fbo, o.out_dir, "background.png"))
            ++pngs;
        else
            ok = 0;
    }
    if (s.zero_copy) {
        /* Scenes with colliders: the steps upload the poses and the engine reads forces back
         * (counted around them by scene_step); everything else must add none. */
        const uint64_t render_transfers = transfers_after - transfers_before - s.engine_transfers;
        printf(
            "library host<->device transfers during the frame loop: %llu, of which steps + engine calls of a scene "
            "with colliders %llu (render path adds none: %s)\n",
            (unsigned long long)(transfers_after - transfers_before), (unsigned long long)s.engine_transfers,
            render_transfers == 0 ? "yes" : "NO");
        if (render_transfers != 0) ok = 0;
    } else {
        printf("library host<->device transfers: not checked (copy path)\n");
    }

    for (k = 0; k < STREAM_COUNT; ++k) {
        if (!s.stream_on[k]) continue;
        mismatches = scene_verify(&e, &s, k, &verified_count);
        printf("GL buffer %d == pbf_world_copy_buffer(source %d): %s (%u elements, %ld mismatching floats)\n", k,
               (int)s.streams[k].source, mismatches == 0 ? "yes" : "NO", verified_count, mismatches);
        if (mismatches != 0) ok = 0;
    }
    if (s.zero_copy) {
        pbf_interop_info info;
        memset(&info, 0, sizeof info);
        info.struct_size = sizeof info;
        CHECK(pbf_world_get_interop_info(s.world, &info));
        printf("interop: %u GL buffers, %llu copies, last copy batch %.4f ms GPU, %.4f ms host\n", info.gl_buffers,
               (unsigned long long)info.copies, info.last_copy_gpu_ms, info.last_copy_host_ms);
    }
    test_scene_report(&s, &o.scene);
    scene_destroy(&e, &s);
    if (o.bench > 0) bench(&e, &t, &o);

    target_destroy(&e, &t);
    pbf_egl_shutdown(&e);
    printf("pbf_render_gl: %s (%d PNGs in %s)\n", ok ? "OK" : "FAILED", pngs, o.out_dir);
    return ok ? 0 : 1;
}
