#include "bake_run.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <utility>

#include "bake_progress.h"

namespace bake {

namespace {

// A failed libpbf call: the scene element, the call, the result and the library's message.
void check(pbf_result r, const std::string& where, const char* call) {
    if (r == PBF_OK) return;
    throw Error(where + ": " + call + " failed: " + pbf_last_error_message());  // the message names the result
}

// Destroys the world on every way out.
struct WorldGuard {
    pbf_world_id id{0, 0};
    ~WorldGuard() {
        if (id.generation != 0) pbf_world_destroy(id);
    }
};

}  // namespace

std::string frame_file(const Scene& s, int64_t frame, const char* ext) {
    char num[32];
    std::snprintf(num, sizeof num, "_%04lld.", (long long)frame);
    return s.output.name + num + ext;
}

VdbSettings vdb_settings(const Scene& s) {
    const double r = s.world.particle_radius;
    VdbSettings v;
    v.voxel_size = s.output.vdb_voxel_size > 0 ? s.output.vdb_voxel_size : 0.5 * r;
    v.sphere_radius = s.output.vdb_sphere_radius > 0 ? s.output.vdb_sphere_radius : 2.0 * r;
    v.half_width = s.output.vdb_half_width;
    return v;
}

RunResult run_bake(const Scene& s, const RunOptions& o) {
    namespace fs = std::filesystem;
    const std::string& file = s.file;
    const unsigned formats = s.output.formats;
    if ((formats & kVdb) && !have_vdb())
        throw Error(file +
                    ": /output/formats: \"vdb\" asked for, but this pbf_bake was built without OpenVDB "
                    "(install libopenvdb-dev and reconfigure)");
    const VdbSettings vdb = vdb_settings(s);
    if ((formats & kVdb) && vdb.sphere_radius / vdb.voxel_size < 1.5)
        throw Error(file + ": /output/vdb: sphere_radius / voxel_size is " +
                    std::to_string(vdb.sphere_radius / vdb.voxel_size) +
                    "; OpenVDB's ParticlesToLevelSet skips spheres under 1.5 voxels: expected at least 1.5");

    std::error_code ec;
    fs::create_directories(s.output.directory, ec);
    if (ec) throw Error(s.output.directory + ": cannot create the output directory: " + ec.message());

    // ---- the world -----------------------------------------------------------------------
    WorldGuard world;
    check(pbf_world_create(&s.world, &world.id), file + ": /world", "pbf_world_create");
    pbf_world_info info;
    std::memset(&info, 0, sizeof info);
    info.struct_size = sizeof info;
    check(pbf_world_get_info(world.id, &info), file, "pbf_world_get_info");

    for (size_t i = 0; i < s.blocks.size(); ++i) {
        uint32_t emitted = 0;
        check(pbf_world_emit_block(world.id, &s.blocks[i].desc, &emitted), file + ": /blocks/" + std::to_string(i),
              "pbf_world_emit_block");
    }
    Progress progress(s.frame_end - s.frame_start + 1, o.progress);
    // A full world is not an error for libpbf (a block emits what fits, nozzles stop), but the
    // artist should know: warn once, naming the key to raise.
    bool warned_full = false;
    auto warn_if_full = [&](uint32_t count, const std::string& when) {
        if (warned_full || count < info.max_particles) return;
        warned_full = true;
        progress.break_line();
        std::fprintf(stderr,
                     "pbf_bake: warning: %s: the world is full (%u particles): %s; raise /world/max_particles\n",
                     file.c_str(), info.max_particles, when.c_str());
    };
    {
        uint32_t count = 0;
        check(pbf_world_get_particle_count(world.id, &count), file, "pbf_world_get_particle_count");
        warn_if_full(count, "the blocks were cut short");
    }
    std::vector<pbf_emitter_id> emitters(s.emitters.size());
    std::vector<uint32_t> emitter_on(s.emitters.size());
    auto emitter_wanted = [&](size_t i, int64_t frame) -> uint32_t {
        const EmitterSpec& e = s.emitters[i];
        return e.desc.enabled && frame >= e.start_frame && (e.end_frame < 0 || frame < e.end_frame) ? 1u : 0u;
    };
    for (size_t i = 0; i < s.emitters.size(); ++i) {
        pbf_emitter_desc d = s.emitters[i].desc;
        d.enabled = emitter_on[i] = emitter_wanted(i, 0);
        check(pbf_world_create_emitter(world.id, &d, &emitters[i]), file + ": /emitters/" + std::to_string(i),
              "pbf_world_create_emitter");
    }
    std::vector<pbf_collider_id> colliders(s.colliders.size());
    for (size_t i = 0; i < s.colliders.size(); ++i)
        check(pbf_world_create_collider(world.id, &s.colliders[i].desc, &colliders[i]),
              file + ": /colliders/" + std::to_string(i), "pbf_world_create_collider");

    // ---- frames --------------------------------------------------------------------------
    const double frame_dt = 1.0 / s.frame_rate;
    const float step_dt = float(frame_dt / s.steps_per_frame);
    progress.update(0, 0);

    Frame fr;
    fr.xyzw.resize(size_t(info.max_particles) * 4);
    fr.vel.resize(size_t(info.max_particles) * 4);
    fr.ids.resize(info.max_particles);
    std::vector<std::pair<double, std::string>> pvd_entries;
    const std::string dir = s.output.directory;
    const std::string pvd_path = (fs::path(dir) / (s.output.name + ".pvd")).string();
    RunResult result;
    result.device = info.device_name;
    double pvd_written_at = -1.0;

    for (int64_t k = 0; k <= s.frame_end; ++k) {
        if (k >= s.frame_start) {
            fr.index = k;
            fr.time = double(k) * frame_dt;
            uint32_t count = 0, written = 0;
            check(pbf_world_get_particle_count(world.id, &count), file, "pbf_world_get_particle_count");
            check(pbf_world_copy_positions(world.id, fr.xyzw.data(), count, &written), file,
                  "pbf_world_copy_positions");
            check(pbf_world_copy_velocities(world.id, fr.vel.data(), count, &written), file,
                  "pbf_world_copy_velocities");
            check(pbf_world_copy_ids(world.id, fr.ids.data(), count, &written), file, "pbf_world_copy_ids");
            fr.count = count;
            if (!s.emitters.empty()) warn_if_full(count, "nozzles stop emitting from frame " + std::to_string(k));
            std::vector<std::string> files;
            if (formats & kPly) {
                files.push_back((fs::path(dir) / frame_file(s, k, "ply")).string());
                write_ply(files.back(), fr);
            }
            if (formats & kVtk) {
                const std::string name = frame_file(s, k, "vtp");
                files.push_back((fs::path(dir) / name).string());
                write_vtp(files.back(), fr);
                pvd_entries.emplace_back(fr.time, name);
                // Rewritten at least every 2 s and after the last frame, so that a stopped bake
                // still opens (without rewriting a long list after every frame).
                const double now = progress.seconds();
                if (k == s.frame_end || pvd_written_at < 0.0 || now - pvd_written_at >= 2.0) {
                    write_pvd(pvd_path, pvd_entries);
                    pvd_written_at = now;
                }
            }
            if (formats & kVdb) {
                files.push_back((fs::path(dir) / frame_file(s, k, "vdb")).string());
                result.vdb_active_voxels = write_vdb(files.back(), fr, vdb);
            }
            ++result.frames_written;
            result.particles = count;
            if (o.on_frame) o.on_frame(fr, world.id, files);
            progress.update(result.frames_written, count);
        }
        if (k == s.frame_end) break;
        // Emitters switched on and off at frame boundaries; kinematic colliders follow their
        // keyframes, each step aiming at the pose of its end time.
        for (size_t i = 0; i < emitters.size(); ++i) {
            const uint32_t want = emitter_wanted(i, k);
            if (want != emitter_on[i])
                check(pbf_emitter_set_enabled(world.id, emitters[i], want), file + ": /emitters/" + std::to_string(i),
                      "pbf_emitter_set_enabled");
            emitter_on[i] = want;
        }
        for (uint32_t j = 1; j <= s.steps_per_frame; ++j) {
            const double f = double(k) + double(j) / double(s.steps_per_frame);
            for (size_t i = 0; i < colliders.size(); ++i) {
                if (s.colliders[i].desc.motion != PBF_MOTION_KINEMATIC) continue;
                const Keyframe p = pose_at(s.colliders[i].keys, f);
                check(pbf_collider_set_target_pose(world.id, colliders[i], p.position, p.rotation),
                      file + ": /colliders/" + std::to_string(i), "pbf_collider_set_target_pose");
            }
            check(pbf_world_step(world.id, step_dt), file, "pbf_world_step");
        }
    }
    result.seconds = progress.seconds();
    if (formats & kVtk) result.pvd = pvd_path;
    return result;
}

}  // namespace bake
