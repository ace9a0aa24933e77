// pbf_bake: bakes a scene file (tools/bake/README.md) into per-frame PLY point clouds, a VTK
// PolyData series with a ParaView .pvd collection and, where built with OpenVDB, level sets.
// Public C API of libpbf only.
//
//   pbf_bake [--frames [START:]END] [--out DIR] [--format ply,vtk,vdb] [--backend auto|cpu|cuda]
//            [--quiet] [--check] scene.json
//
// Exit status: 0 baked; 1 a libpbf or output error; 2 a scene or argument error.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>

#include "bake_run.h"
#include "bake_scene.h"

namespace {

// "END" or "START:END" (inclusive).
void apply_frames(bake::Scene& s, const std::string& v) {
    auto number = [&](const std::string& t) -> int64_t {
        size_t used = 0;
        long long x = -1;
        try {
            x = std::stoll(t, &used);
        } catch (...) {
            used = 0;
        }
        if (t.empty() || used != t.size() || x < 0)
            throw bake::Error("--frames " + v + ": expected END or START:END, non-negative frame numbers");
        return int64_t(x);
    };
    const size_t colon = v.find(':');
    if (colon == std::string::npos) {
        s.frame_end = number(v);
    } else {
        s.frame_start = number(v.substr(0, colon));
        s.frame_end = number(v.substr(colon + 1));
    }
    if (s.frame_end < s.frame_start)
        throw bake::Error("--frames " + v + ": expected END >= START (" + std::to_string(s.frame_start) + ")");
}

std::string version_string() {
    const uint32_t v = pbf_get_version();
    char buf[128];
    std::snprintf(buf, sizeof buf, "pbf_bake %d.%d.%d (libpbf %u.%u.%u%s%s)", PBF_VERSION_MAJOR, PBF_VERSION_MINOR,
                  PBF_VERSION_PATCH, v >> 22, (v >> 12) & 0x3FFu, v & 0xFFFu, bake::have_vdb() ? ", OpenVDB" : "",
                  bake::have_toml() ? ", TOML" : "");
    return buf;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"pbf_bake: bake a libpbf fluid scene (JSON" + std::string(bake::have_toml() ? " or TOML" : "") +
                     ") into frames for Blender, ParaView and Houdini: binary PLY point clouds, a VTK .vtp series "
                     "with a .pvd collection" +
                     std::string(bake::have_vdb() ? ", OpenVDB level sets" : "") +
                     ". See tools/bake/README.md for the scene format.",
                 "pbf_bake"};
    std::string scene_path, frames, out, formats, backend;
    bool quiet = false, check_only = false;
    app.add_option("scene", scene_path, "scene file (.json" + std::string(bake::have_toml() ? " or .toml" : "") + ")")
        ->required();
    app.add_option("--frames", frames,
                   "frames to write: END or START:END, inclusive (frame k is time k/rate; "
                   "overrides the scene's frames.start/end)");
    app.add_option("--out", out, "output directory (overrides output.directory)");
    app.add_option("--format", formats,
                   std::string("comma-separated output formats: ply, vtk") +
                       (bake::have_vdb() ? ", vdb" : " (vdb: not in this build)") + " (overrides output.formats)");
    app.add_option("--backend", backend, "override world.backend")->check(CLI::IsMember({"auto", "cpu", "cuda"}));
    app.add_flag("-q,--quiet", quiet, "no progress bar");
    app.add_flag("--check", check_only, "validate the scene and exit");
    app.set_version_flag("--version", version_string());
    CLI11_PARSE(app, argc, argv);

    bake::Scene scene;
    try {
        scene = bake::load_scene(scene_path);
        if (!frames.empty()) apply_frames(scene, frames);
        if (!out.empty()) scene.output.directory = out;
        if (!formats.empty()) scene.output.formats = bake::parse_formats(formats, "--format " + formats);
        if (!backend.empty())
            scene.world.backend = backend == "cpu"    ? PBF_BACKEND_CPU
                                  : backend == "cuda" ? PBF_BACKEND_CUDA
                                                      : PBF_BACKEND_AUTO;
        if ((scene.output.formats & bake::kVdb) && !bake::have_vdb())
            throw bake::Error(
                "vdb output asked for, but this pbf_bake was built without OpenVDB "
                "(install libopenvdb-dev and reconfigure)");
    } catch (const bake::Error& e) {
        std::fprintf(stderr, "pbf_bake: %s\n", e.what());
        return 2;
    }
    if (check_only) {
        std::printf(
            "pbf_bake: %s is valid: frames %lld..%lld at %g fps, %zu blocks, %zu emitters, %zu colliders, "
            "formats %s into %s\n",
            scene_path.c_str(), (long long)scene.frame_start, (long long)scene.frame_end, scene.frame_rate,
            scene.blocks.size(), scene.emitters.size(), scene.colliders.size(),
            bake::format_list(scene.output.formats).c_str(), scene.output.directory.c_str());
        return 0;
    }
    try {
        bake::RunOptions o;
        o.progress = !quiet;
        const bake::RunResult r = bake::run_bake(scene, o);
        std::printf("pbf_bake: %lld frames (%lld..%lld) of %s on %s in %.1f s: %u particles at the end; %s in %s%s%s\n",
                    (long long)r.frames_written, (long long)scene.frame_start, (long long)scene.frame_end,
                    scene_path.c_str(), r.device.c_str(), r.seconds, r.particles,
                    bake::format_list(scene.output.formats).c_str(), scene.output.directory.c_str(),
                    r.pvd.empty() ? "" : " (ParaView: open ", r.pvd.empty() ? "" : (r.pvd + ")").c_str());
        if (scene.output.formats & bake::kVdb) {
            const bake::VdbSettings v = bake::vdb_settings(scene);
            std::printf(
                "pbf_bake: OpenVDB level sets: voxel %g m, particle spheres of radius %g m, narrow band %g voxels; "
                "%llu active voxels in the last frame\n",
                v.voxel_size, v.sphere_radius, v.half_width, (unsigned long long)r.vdb_active_voxels);
        }
    } catch (const bake::Error& e) {
        std::fprintf(stderr, "\npbf_bake: %s\n", e.what());
        return 1;
    }
    return 0;
}
