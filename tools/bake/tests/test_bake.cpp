// pbf_bake: bakes tiny scenes through bake::run_bake (the code pbf_bake runs) and reads every
// output back: PLY header and payload against the world's particles, the .pvd against the frames,
// each .vtp as XML (expat where built) against the particle count and positions, the .vdb with
// OpenVDB; and the scene checks' messages.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "bake_run.h"
#include "bake_scene.h"

#if defined(PBF_BAKE_TEST_EXPAT)
#include <expat.h>
#endif
#if defined(PBF_BAKE_HAVE_OPENVDB)
#include <openvdb/openvdb.h>
#endif

namespace fs = std::filesystem;

namespace {

std::string read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

std::string work_dir(const std::string& name) {
    const fs::path p = fs::path(PBF_BAKE_TEST_DIR) / name;
    fs::remove_all(p);
    return p.string();
}

// A small dam break: 8 x 10 x 4 = 320 particles, 6 frames at 30 fps with an emitter and a collider.
std::string tiny_scene(const std::string& out, const std::string& formats) {
    return R"({
      "world": { "particle_radius": 0.025, "domain_min": [0, 0, 0], "domain_max": [1.0, 0.8, 0.2],
                 "backend": "cpu", "max_particles": 2000 },
      "solver": { "iterations": 2, "substeps": 2, "ldc_enabled": true },
      "blocks": [ { "min": [0, 0, 0], "max": [0.4, 0.5, 0.2] } ],
      "emitters": [ { "type": "nozzle", "position": [0.8, 0.6, 0.1], "direction": [0, -1, 0],
                      "rate": 300, "speed": 5.0, "radius": 0.05, "start_frame": 1, "end_frame": 4 } ],
      "colliders": [ { "shape": "sphere", "position": [0.7, 0.1, 0.1], "radius": 0.08 } ],
      "frames": { "start": 0, "end": 5, "rate": 30 },
      "output": { "directory": ")" +
           out + R"(", "name": "tiny", "formats": )" + formats + R"( }
    })";
}

struct Particles {
    std::vector<float> xyzw, vel;
    std::vector<uint32_t> ids;
};

Particles copy_world(pbf_world_id w) {
    uint32_t n = 0, written = 0;
    REQUIRE(pbf_world_get_particle_count(w, &n) == PBF_OK);
    Particles p;
    p.xyzw.resize(4 * size_t(n));
    p.vel.resize(4 * size_t(n));
    p.ids.resize(n);
    REQUIRE(pbf_world_copy_positions(w, p.xyzw.data(), n, &written) == PBF_OK);
    REQUIRE(pbf_world_copy_velocities(w, p.vel.data(), n, &written) == PBF_OK);
    REQUIRE(pbf_world_copy_ids(w, p.ids.data(), n, &written) == PBF_OK);
    return p;
}

uint32_t le32(const unsigned char* p) {
    return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}
float lef(const unsigned char* p) {
    const uint32_t v = le32(p);
    float f;
    std::memcpy(&f, &v, 4);
    return f;
}

// Parses a pbf_bake PLY file: checks the header line by line and returns the payload's vertices.
Particles read_ply(const std::string& path) {
    const std::string data = read_all(path);
    const size_t end = data.find("end_header\n");
    REQUIRE(end != std::string::npos);
    std::istringstream header(data.substr(0, end));
    std::vector<std::string> lines;
    for (std::string l; std::getline(header, l);)
        if (l.rfind("comment", 0) != 0) lines.push_back(l);
    REQUIRE(lines.size() == 11);
    CHECK(lines[0] == "ply");
    CHECK(lines[1] == "format binary_little_endian 1.0");
    REQUIRE(lines[2].rfind("element vertex ", 0) == 0);
    const uint32_t n = uint32_t(std::stoul(lines[2].substr(15)));
    const char* props[] = {"float x", "float y", "float z", "float vx", "float vy", "float vz", "float density_ratio",
                           "uint id"};
    for (int k = 0; k < 8; ++k) CHECK(lines[3 + k] == std::string("property ") + props[k]);
    const size_t payload = end + std::strlen("end_header\n");
    REQUIRE(data.size() == payload + size_t(n) * 32);
    Particles p;
    const auto* b = reinterpret_cast<const unsigned char*>(data.data() + payload);
    for (uint32_t i = 0; i < n; ++i, b += 32) {
        p.xyzw.insert(p.xyzw.end(), {lef(b), lef(b + 4), lef(b + 8), lef(b + 24)});
        p.vel.insert(p.vel.end(), {lef(b + 12), lef(b + 16), lef(b + 20), 0.0f});
        p.ids.push_back(le32(b + 28));
    }
    return p;
}

std::vector<unsigned char> unbase64(const std::string& s) {
    std::vector<unsigned char> out;
    uint32_t acc = 0;
    int bits = 0;
    for (char c : s) {
        int v;
        if (c >= 'A' && c <= 'Z')
            v = c - 'A';
        else if (c >= 'a' && c <= 'z')
            v = c - 'a' + 26;
        else if (c >= '0' && c <= '9')
            v = c - '0' + 52;
        else if (c == '+')
            v = 62;
        else if (c == '/')
            v = 63;
        else
            continue;  // whitespace and padding
        acc = acc << 6 | uint32_t(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(uint8_t(acc >> bits));
        }
    }
    return out;
}

// What a .vtp holds, as its XML says.
struct Vtp {
    bool well_formed = false;
    std::string error;
    std::string root;
    std::map<std::string, std::string> piece;       // attributes of <Piece>
    std::map<std::string, std::string> array_text;  // DataArray Name -> text
    std::map<std::string, std::string> array_type;  // DataArray Name -> type
};

#if defined(PBF_BAKE_TEST_EXPAT)
struct ExpatState {
    Vtp* v;
    std::string current;
    int depth = 0;
};
Vtp parse_vtp(const std::string& text) {
    Vtp v;
    ExpatState st{&v, "", 0};
    XML_Parser p = XML_ParserCreate(nullptr);
    XML_SetUserData(p, &st);
    XML_SetElementHandler(
        p,
        [](void* ud, const XML_Char* name, const XML_Char** atts) {
            auto* s = static_cast<ExpatState*>(ud);
            if (s->depth++ == 0) s->v->root = name;
            std::map<std::string, std::string> a;
            for (int i = 0; atts[i]; i += 2) a[atts[i]] = atts[i + 1];
            if (std::strcmp(name, "Piece") == 0) s->v->piece = a;
            if (std::strcmp(name, "DataArray") == 0) {
                s->current = a["Name"];
                s->v->array_type[s->current] = a["type"];
                s->v->array_text[s->current].clear();
            }
        },
        [](void* ud, const XML_Char* name) {
            auto* s = static_cast<ExpatState*>(ud);
            --s->depth;
            if (std::strcmp(name, "DataArray") == 0) s->current.clear();
        });
    XML_SetCharacterDataHandler(p, [](void* ud, const XML_Char* t, int len) {
        auto* s = static_cast<ExpatState*>(ud);
        if (!s->current.empty()) s->v->array_text[s->current].append(t, size_t(len));
    });
    v.well_formed = XML_Parse(p, text.data(), int(text.size()), 1) == XML_STATUS_OK;
    if (!v.well_formed) v.error = XML_ErrorString(XML_GetErrorCode(p));
    XML_ParserFree(p);
    return v;
}
#else
// Without expat: the structure pbf_bake writes, read with string searches (no XML parser).
Vtp parse_vtp(const std::string& text) {
    Vtp v;
    auto attr = [&](size_t from, const std::string& key) {
        const size_t a = text.find(key + "=\"", from);
        const size_t b = text.find('"', a + key.size() + 2);
        return text.substr(a + key.size() + 2, b - a - key.size() - 2);
    };
    v.root = text.find("<VTKFile ") != std::string::npos ? "VTKFile" : "";
    const size_t piece = text.find("<Piece ");
    if (piece != std::string::npos) v.piece["NumberOfPoints"] = attr(piece, "NumberOfPoints");
    for (size_t at = text.find("<DataArray "); at != std::string::npos; at = text.find("<DataArray ", at + 1)) {
        const std::string name = attr(at, "Name");
        v.array_type[name] = attr(at, "type");
        const size_t open = text.find('>', at) + 1;
        v.array_text[name] = text.substr(open, text.find("</DataArray>", open) - open);
    }
    v.well_formed =
        text.rfind("</VTKFile>") != std::string::npos && text.find_first_of(std::string("\0", 1)) == std::string::npos;
    return v;
}
#endif

// Decodes an inline binary DataArray: UInt64 byte count, then the data.
std::vector<unsigned char> array_bytes(const Vtp& v, const std::string& name) {
    REQUIRE(v.array_text.count(name) == 1);
    std::vector<unsigned char> b = unbase64(v.array_text.at(name));
    REQUIRE(b.size() >= 8);
    uint64_t n = 0;
    for (int k = 7; k >= 0; --k) n = n << 8 | b[size_t(k)];
    REQUIRE(n == b.size() - 8);
    return std::vector<unsigned char>(b.begin() + 8, b.end());
}

}  // namespace

TEST_CASE("bake: PLY frames hold the world's particles, byte for byte", "[bake]") {
    const std::string out = work_dir("ply");
    bake::Scene s = bake::parse_scene(tiny_scene(out, R"(["ply"])"), "tiny.json");
    int frames = 0;
    uint32_t counts_seen_max = 0;
    std::vector<uint32_t> counts;
    bake::RunOptions o;
    o.progress = false;
    o.on_frame = [&](const bake::Frame& f, pbf_world_id w, const std::vector<std::string>& files) {
        REQUIRE(files.size() == 1);
        const Particles world = copy_world(w);
        const Particles ply = read_ply(files[0]);
        INFO("frame " << f.index);
        REQUIRE(ply.ids.size() == world.ids.size());
        CHECK(ply.xyzw == world.xyzw);
        CHECK(ply.ids == world.ids);
        for (size_t i = 0; i < world.ids.size(); ++i)
            for (int c = 0; c < 3; ++c) REQUIRE(ply.vel[4 * i + c] == world.vel[4 * i + c]);
        counts_seen_max = std::max<uint32_t>(counts_seen_max, uint32_t(world.ids.size()));
        counts.push_back(uint32_t(world.ids.size()));
        ++frames;
    };
    const bake::RunResult r = bake::run_bake(s, o);
    CHECK(frames == 6);
    CHECK(r.frames_written == 6);
    CHECK(counts_seen_max > 320);  // the nozzle added particles
    // The block's 8 x 10 x 4 lattice; the nozzle is on for the steps out of frames 1, 2 and 3 only.
    REQUIRE(counts.size() == 6);
    CHECK(counts[0] == 320);
    CHECK(counts[1] == 320);
    CHECK(counts[4] > 320);
    CHECK(counts[5] == counts[4]);
    for (int k = 0; k <= 5; ++k) CHECK(fs::exists(fs::path(out) / bake::frame_file(s, k, "ply")));
    CHECK_FALSE(fs::exists(fs::path(out) / "tiny.pvd"));
}

TEST_CASE("bake: the .pvd lists every frame and each .vtp is XML with the frame's points", "[bake]") {
    const std::string out = work_dir("vtk");
    bake::Scene s = bake::parse_scene(tiny_scene(out, R"(["vtk", "ply"])"), "tiny.json");
    s.frame_start = 2;  // frames 2..5: the frames before are simulated, not written
    std::map<int64_t, Particles> seen;
    bake::RunOptions o;
    o.progress = false;
    o.on_frame = [&](const bake::Frame& f, pbf_world_id w, const std::vector<std::string>&) {
        seen[f.index] = copy_world(w);
    };
    const bake::RunResult r = bake::run_bake(s, o);
    REQUIRE(r.frames_written == 4);
    REQUIRE(r.pvd == (fs::path(out) / "tiny.pvd").string());

    const std::string pvd = read_all(r.pvd);
    const Vtp collection = parse_vtp(pvd);
    CHECK(collection.well_formed);
    CHECK(collection.root == "VTKFile");
    CHECK(pvd.find("type=\"Collection\"") != std::string::npos);
    size_t datasets = 0;
    for (size_t at = pvd.find("<DataSet "); at != std::string::npos; at = pvd.find("<DataSet ", at + 1)) ++datasets;
    CHECK(datasets == 4);
    for (int64_t k = 2; k <= 5; ++k) {
        INFO("frame " << k);
        const std::string name = bake::frame_file(s, k, "vtp");
        char entry[128];
        std::snprintf(entry, sizeof entry, "timestep=\"%.9g\" group=\"\" part=\"0\" file=\"%s\"", double(k) / 30.0,
                      name.c_str());
        CHECK(pvd.find(entry) != std::string::npos);

        const Vtp v = parse_vtp(read_all((fs::path(out) / name).string()));
        INFO(v.error);
        REQUIRE(v.well_formed);
        CHECK(v.root == "VTKFile");
        const Particles& p = seen.at(k);
        const size_t n = p.ids.size();
        CHECK(v.piece.at("NumberOfPoints") == std::to_string(n));
        CHECK(v.array_type.at("Points") == "Float32");
        const std::vector<unsigned char> pts = array_bytes(v, "Points");
        REQUIRE(pts.size() == 12 * n);
        for (size_t i = 0; i < n; ++i)
            for (int c = 0; c < 3; ++c) REQUIRE(lef(&pts[12 * i + 4 * size_t(c)]) == p.xyzw[4 * i + size_t(c)]);
        const std::vector<unsigned char> ids = array_bytes(v, "id");
        REQUIRE(ids.size() == 4 * n);
        for (size_t i = 0; i < n; ++i) REQUIRE(le32(&ids[4 * i]) == p.ids[i]);
        CHECK(array_bytes(v, "velocity").size() == 12 * n);
        CHECK(array_bytes(v, "density_ratio").size() == 4 * n);
        const std::vector<unsigned char> offsets = array_bytes(v, "offsets");
        REQUIRE(offsets.size() == 8 * n);
        if (n) CHECK(le32(&offsets[8 * (n - 1)]) == n);
    }
    CHECK_FALSE(fs::exists(fs::path(out) / bake::frame_file(s, 1, "vtp")));
}

TEST_CASE("bake: scene errors name the file, the JSON path and what was expected", "[bake]") {
    auto message = [](const std::string& text) {
        try {
            bake::parse_scene(text, "s.json");
        } catch (const bake::Error& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    const std::string blocks = R"("blocks": [ { "min": [0, 0, 0], "max": [0.2, 0.2, 0.2] } ])";
    CHECK_THAT(message("{" + blocks + R"(, "solver": { "iteratons": 3 } })"),
               Catch::StartsWith(
                   "s.json: /solver/iteratons: unknown key \"iteratons\" (expected one of: iterations, substeps"));
    CHECK(message("{" + blocks + R"(, "wrld": {} })").rfind("s.json: /wrld: unknown key", 0) == 0);
    CHECK(message("{" + blocks + R"(, "world": { "gravity": [0, "down", 0] } })") ==
          "s.json: /world/gravity/1: expected a number, got a string (\"down\")");
    CHECK(message("{" + blocks + R"(, "world": { "max_particles": 2.5 } })") ==
          "s.json: /world/max_particles: expected an integer, got a number (2.5)");
    CHECK(message("{" + blocks + R"(, "solver": { "iterations": 0 } })") ==
          "s.json: /solver/iterations: expected an integer in [1, 64], got a number (0)");
    CHECK(message("{" + blocks + R"(, "solver": { "ldc_enabled": "yes" } })") ==
          "s.json: /solver/ldc_enabled: expected true or false (or 0 / 1), got a string (\"yes\")");
    CHECK(message(R"({ "blocks": [ { "min": [0, 0, 0], "max": [0.2, -1, 0.2] } ] })") ==
          "s.json: /blocks/0/max/1: expected max above the minimum corner on every axis, got -1 <= 0");
    CHECK(message(R"({ "emitters": [ { "type": "hose" } ] })") ==
          "s.json: /emitters/0/type: expected one of \"nozzle, drain\", got a string (\"hose\")");
    CHECK(message(R"({ "emitters": [ { "type": "drain", "min": [0, 0, 0] } ] })") ==
          "s.json: /emitters/0/max: missing (expected an array of 3 numbers)");
    CHECK(message("{" + blocks +
                  R"(, "colliders": [ { "shape": "sphere", "radius": 0.1, "half_extents": [1, 1, 1] } ] })")
              .rfind("s.json: /colliders/0/half_extents: unknown key", 0) == 0);
    CHECK(
        message(
            "{" + blocks +
            R"(, "colliders": [ { "shape": "box", "half_extents": [1, 1, 1], "keyframes": [ { "frame": 0 } ] } ] })") ==
        "s.json: /colliders/0/keyframes: keyframes need \"motion\": \"kinematic\"");
    CHECK(message("{" + blocks + R"(, "output": { "formats": ["ply", "obj"] } })") ==
          "s.json: /output/formats/1: expected one of \"ply, vtk, vdb\", got a string (\"obj\")");
    CHECK(message("{" + blocks + R"(, "frames": { "start": 10, "end": 5 } })") ==
          "s.json: /frames/end: expected end >= start (10), got 5");
    CHECK(message(R"({ "frames": { "end": 5 } })") ==
          "s.json: /: the scene has no fluid: expected at least one entry in \"blocks\" or \"emitters\"");
    CHECK(message("[1, 2]") == "s.json: /: expected an object, got an array ([1,2])");
    CHECK_THAT(message("{\n  \"world\": {\n    \"particle_radius\": 0.02,,\n  }\n}"),
               Catch::StartsWith("s.json:3:29: not valid JSON: "));
    try {
        bake::load_scene(std::string(PBF_BAKE_TEST_DIR) + "/does_not_exist.json");
        FAIL("no error for a missing file");
    } catch (const bake::Error& e) {
        CHECK_THAT(e.what(),
                   Catch::EndsWith("does_not_exist.json: cannot open the scene file: No such file or directory"));
    }
    CHECK(bake::parse_formats("ply,vtk", "--format") == (bake::kPly | bake::kVtk));
    CHECK_THROWS_WITH(bake::parse_formats("ply,gif", "--format ply,gif"),
                      "--format ply,gif: unknown format \"gif\" (expected a comma-separated list of ply, vtk, vdb)");
}

TEST_CASE("bake: every solver parameter is settable by name and reaches the world", "[bake]") {
    const std::string out = work_dir("solver");
    const bake::Scene s = bake::parse_scene(R"({
      "world": { "backend": "cpu", "max_particles": 1000 },
      "solver": { "iterations": 7, "substeps": 3, "relaxation": 2.0, "scorr_k": 0.05, "scorr_n": 3,
                  "scorr_dq": 0.3, "xsph_c": 0.02, "vorticity_epsilon": 0.001, "ldc_enabled": false,
                  "ldc_gain": 0.2, "max_speed": 50, "adaptive_error_target": 0.01, "max_substeps": 12,
                  "substep_travel": 0.25, "sound_speed": 20 },
      "blocks": [ { "min": [-0.1, 0, -0.1], "max": [0.1, 0.1, 0.1] } ],
      "frames": { "end": 0 },
      "output": { "directory": ")" + out + R"(", "formats": ["ply"] } })",
                                            "solver.json");
    // Every field after struct_size is 4 bytes today: a new field of pbf_solver_params shows here.
    INFO(
        "pbf_solver_params has fields that scene files cannot set: add them to kSolverFields in "
        "tools/bake/bake_scene.cpp (and to tools/bake/README.md)");
    CHECK(sizeof(pbf_solver_params) == sizeof(uint32_t) * (1 + bake::solver_field_names().size()));
    bake::RunOptions o;
    o.progress = false;
    o.on_frame = [&](const bake::Frame&, pbf_world_id w, const std::vector<std::string>&) {
        pbf_solver_params p = pbf_solver_params_default();
        REQUIRE(pbf_world_get_solver_params(w, &p) == PBF_OK);
        CHECK(p.iterations == 7);
        CHECK(p.substeps == 3);
        CHECK(p.relaxation == 2.0f);
        CHECK(p.scorr_k == 0.05f);
        CHECK(p.scorr_n == 3.0f);
        CHECK(p.scorr_dq == 0.3f);
        CHECK(p.xsph_c == 0.02f);
        CHECK(p.vorticity_epsilon == 0.001f);
        CHECK(p.ldc_enabled == 0u);
        CHECK(p.ldc_gain == 0.2f);
        CHECK(p.max_speed == 50.0f);
        CHECK(p.adaptive_error_target == 0.01f);
        CHECK(p.max_substeps == 12u);
        CHECK(p.substep_travel == 0.25f);
        CHECK(p.sound_speed == 20.0f);
    };
    CHECK(bake::run_bake(s, o).frames_written == 1);
}

TEST_CASE("bake: kinematic keyframes interpolate position and rotation", "[bake]") {
    const bake::Scene s = bake::parse_scene(R"({
      "blocks": [ { "min": [-0.1, 0, -0.1], "max": [0.1, 0.1, 0.1] } ],
      "colliders": [ { "shape": "capsule", "radius": 0.05, "half_height": 0.1, "motion": "kinematic",
                       "keyframes": [ { "frame": 10, "position": [0, 0.5, 0] },
                                      { "frame": 20, "position": [1, 0.5, 0], "rotation": [0, 0, 1, 0] } ] },
                     { "shape": "plane", "normal": [1, 0, 0], "position": [-0.9, 0, 0] } ] })",
                                            "kin.json");
    const auto& keys = s.colliders[0].keys;
    REQUIRE(keys.size() == 2);
    CHECK(s.colliders[0].desc.position[0] == 0.0f);  // starts at the first keyframe's pose
    const bake::Keyframe mid = bake::pose_at(keys, 15.0);
    CHECK(mid.position[0] == Approx(0.5));
    CHECK(mid.rotation[2] == Approx(std::sqrt(0.5)));
    CHECK(mid.rotation[3] == Approx(std::sqrt(0.5)));
    CHECK(bake::pose_at(keys, 30.0).position[0] == 1.0f);
    // The plane's normal (1, 0, 0) = rotation · (0, 1, 0).
    const float* q = s.colliders[1].desc.rotation;
    const float x = q[0], y = q[1], z = q[2], w = q[3];
    CHECK(2 * (x * y - w * z) == Approx(1.0).margin(1e-6));
    CHECK(1 - 2 * (x * x + z * z) == Approx(0.0).margin(1e-6));
}

#if defined(PBF_BAKE_HAVE_OPENVDB)
TEST_CASE("bake: the .vdb holds a level set grid with active voxels", "[bake]") {
    const std::string out = work_dir("vdb");
    bake::Scene s = bake::parse_scene(tiny_scene(out, R"(["vdb"])"), "tiny.json");
    s.frame_end = 1;
    bake::RunOptions o;
    o.progress = false;
    const bake::RunResult r = bake::run_bake(s, o);
    CHECK(r.frames_written == 2);
    CHECK(r.vdb_active_voxels > 0);
    openvdb::initialize();
    for (int k = 0; k <= 1; ++k) {
        openvdb::io::File file((fs::path(out) / bake::frame_file(s, k, "vdb")).string());
        file.open();
        openvdb::GridBase::Ptr base = file.readGrid("surface");
        file.close();
        REQUIRE(base);
        CHECK(base->getGridClass() == openvdb::GRID_LEVEL_SET);
        openvdb::FloatGrid::Ptr grid = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        REQUIRE(grid);
        CHECK(grid->activeVoxelCount() > 0);
        CHECK(grid->voxelSize()[0] == Approx(0.5 * 0.025));  // particle_radius / 2
        // Inside the fluid block the level set is negative, far outside it is the background.
        const openvdb::Coord inside = grid->transform().worldToIndexCellCentered(openvdb::Vec3d(0.2, 0.1, 0.1));
        CHECK(grid->getConstAccessor().getValue(inside) < 0.0f);
    }
}
#endif

TEST_CASE("bake: a TOML scene reads as its JSON twin", "[bake]") {
    if (!bake::have_toml()) {
        WARN("pbf_bake was built without toml++: TOML scenes are refused with a message");
        CHECK_THROWS_WITH(bake::parse_scene("a = 1", "x.toml", true),
                          Catch::Contains("x.toml: this pbf_bake was built without TOML support"));
        return;
    }
    const bake::Scene j = bake::load_scene(std::string(PBF_BAKE_SCENES_DIR) + "/nozzle_fill.json");
    const bake::Scene t = bake::load_scene(std::string(PBF_BAKE_TOML_SCENE));
    CHECK(std::memcmp(&j.world, &t.world, sizeof j.world) == 0);
    REQUIRE(t.emitters.size() == 2);
    REQUIRE(t.colliders.size() == 2);
    for (size_t i = 0; i < 2; ++i) {
        CHECK(std::memcmp(&j.emitters[i].desc, &t.emitters[i].desc, sizeof j.emitters[i].desc) == 0);
        CHECK(j.emitters[i].start_frame == t.emitters[i].start_frame);
        CHECK(j.emitters[i].end_frame == t.emitters[i].end_frame);
        CHECK(std::memcmp(&j.colliders[i].desc, &t.colliders[i].desc, sizeof j.colliders[i].desc) == 0);
    }
    CHECK(j.frame_end == t.frame_end);
    CHECK(j.frame_rate == t.frame_rate);
    CHECK(j.output.formats == t.output.formats);
    CHECK(j.output.directory == t.output.directory);
    CHECK_THROWS_WITH(bake::parse_scene("[world]\nparticle_radius = \"big\"\n", "s.toml", true),
                      "s.toml: /world/particle_radius: expected a number, got a string (\"big\")");
    CHECK_THROWS_WITH(bake::parse_scene("[world]\nparticle_radius = \n", "s.toml", true),
                      Catch::StartsWith("s.toml:2:") && Catch::Contains("not valid TOML"));
}

TEST_CASE("bake: a keyframed kinematic collider moves through the fluid", "[bake]") {
    const std::string out = work_dir("kinematic");
    // A resting layer; a sphere keyframed from above the box down into the layer's middle.
    const bake::Scene s = bake::parse_scene(R"({
      "world": { "particle_radius": 0.025, "domain_min": [0, 0, 0], "domain_max": [0.6, 0.6, 0.6],
                 "backend": "cpu", "max_particles": 4000 },
      "solver": { "iterations": 3, "substeps": 4 },
      "blocks": [ { "min": [0, 0, 0], "max": [0.6, 0.2, 0.6] } ],
      "colliders": [ { "shape": "sphere", "radius": 0.1, "motion": "kinematic",
                       "keyframes": [ { "frame": 0, "position": [0.3, 0.45, 0.3] },
                                      { "frame": 12, "position": [0.3, 0.1, 0.3] } ] } ],
      "frames": { "end": 15, "rate": 60 },
      "output": { "directory": ")" + out + R"(", "formats": ["ply"] } })",
                                            "kinematic.json");
    float closest_end = 0.0f;
    bake::RunOptions o;
    o.progress = false;
    o.on_frame = [&](const bake::Frame& f, pbf_world_id, const std::vector<std::string>&) {
        float closest = 1e9f;
        for (uint32_t i = 0; i < f.count; ++i) {
            const float dx = f.xyzw[4 * i] - 0.3f, dy = f.xyzw[4 * i + 1] - 0.1f, dz = f.xyzw[4 * i + 2] - 0.3f;
            closest = std::min(closest, std::sqrt(dx * dx + dy * dy + dz * dz));
        }
        if (f.index == 0) CHECK(closest < 0.05f);  // the sphere's final place starts full of fluid
        closest_end = closest;
    };
    CHECK(bake::run_bake(s, o).frames_written == 16);
    CHECK(closest_end > 0.09f);  // the sphere (radius 0.1) pushed the fluid out of its way
}
