// Scene files for pbf_bake: JSON read with nlohmann-json, every value checked, every error naming
// the file, the JSON path (RFC 6901 pointer, e.g. /emitters/0/speed) and what was expected.
#include "bake_scene.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

#include <nlohmann/json.hpp>

#if defined(PBF_BAKE_HAVE_TOML)
#include <toml++/toml.h>
#endif

namespace bake {

using json = nlohmann::json;

namespace {

// ---- error helpers -----------------------------------------------------------------------

std::string describe(const json& v) {
    std::string s = v.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    const char* kind = v.is_null()      ? "null"
                       : v.is_boolean() ? "a boolean"
                       : v.is_number()  ? "a number"
                       : v.is_string()  ? "a string"
                       : v.is_array()   ? "an array"
                                        : "an object";
    return std::string(kind) + " (" + s + ")";
}

struct Ctx {
    std::string file;
    [[noreturn]] void fail(const std::string& path, const std::string& what) const {
        throw Error(file + ": " + (path.empty() ? "/" : path) + ": " + what);
    }
    [[noreturn]] void expected(const std::string& path, const std::string& what, const json& got) const {
        fail(path, "expected " + what + ", got " + describe(got));
    }
};

std::string join(const std::vector<std::string>& v) {
    std::string out;
    for (size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + v[i];
    return out;
}

// An object whose keys must all be among `allowed`.
void check_keys(const Ctx& c, const json& obj, const std::string& path, const std::vector<std::string>& allowed) {
    if (!obj.is_object()) c.expected(path, "an object", obj);
    for (auto it = obj.begin(); it != obj.end(); ++it)
        if (std::find(allowed.begin(), allowed.end(), it.key()) == allowed.end())
            c.fail(path + "/" + it.key(), "unknown key \"" + it.key() + "\" (expected one of: " + join(allowed) + ")");
}

std::string fmt(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// A finite number in [lo, hi] (either bound may be infinite); `open_lo`: strictly above lo.
double number(const Ctx& c, const json& v, const std::string& path, double lo, double hi, bool open_lo = false) {
    if (!v.is_number()) c.expected(path, "a number", v);
    const double x = v.get<double>();
    const bool lo_ok = std::isinf(lo) ? true : (open_lo ? x > lo : x >= lo);
    const bool hi_ok = std::isinf(hi) ? true : x <= hi;
    if (!std::isfinite(x) || !lo_ok || !hi_ok) {
        std::string range;
        if (!std::isinf(lo) && !std::isinf(hi))
            range = " in " + std::string(open_lo ? "(" : "[") + fmt(lo) + ", " + fmt(hi) + "]";
        else if (!std::isinf(lo))
            range = std::string(open_lo ? " > " : " >= ") + fmt(lo);
        else if (!std::isinf(hi))
            range = " <= " + fmt(hi);
        c.expected(path, "a number" + range, v);
    }
    return x;
}

int64_t integer(const Ctx& c, const json& v, const std::string& path, int64_t lo, int64_t hi) {
    if (!v.is_number_integer() && !(v.is_number_float() && std::floor(v.get<double>()) == v.get<double>()))
        c.expected(path, "an integer", v);
    const double x = v.get<double>();
    if (x < double(lo) || x > double(hi))
        c.expected(path, "an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]", v);
    return int64_t(x);
}

bool boolean(const Ctx& c, const json& v, const std::string& path) {
    if (v.is_boolean()) return v.get<bool>();
    if (v.is_number_integer() && (v.get<int64_t>() == 0 || v.get<int64_t>() == 1)) return v.get<int64_t>() == 1;
    c.expected(path, "true or false (or 0 / 1)", v);
}

std::string string(const Ctx& c, const json& v, const std::string& path) {
    if (!v.is_string()) c.expected(path, "a string", v);
    return v.get<std::string>();
}

template <size_t N>
void vec(const Ctx& c, const json& v, const std::string& path, float (&out)[N]) {
    if (!v.is_array() || v.size() != N) c.expected(path, "an array of " + std::to_string(N) + " numbers", v);
    for (size_t i = 0; i < N; ++i) {
        const double x = number(c, v[i], path + "/" + std::to_string(i), -std::numeric_limits<double>::infinity(),
                                std::numeric_limits<double>::infinity());
        out[i] = float(x);
    }
}

const json* find(const json& obj, const char* key) {
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
}

const json& require(const Ctx& c, const json& obj, const std::string& path, const char* key, const char* what) {
    const json* v = find(obj, key);
    if (!v) c.fail(path + "/" + key, std::string("missing (expected ") + what + ")");
    return *v;
}

std::string choice(const Ctx& c, const json& v, const std::string& path, const std::vector<std::string>& options) {
    const std::string s = v.is_string() ? v.get<std::string>() : std::string();
    if (!v.is_string() || std::find(options.begin(), options.end(), s) == options.end())
        c.expected(path, "one of \"" + join(options) + "\"", v);
    return s;
}

constexpr double kInf = std::numeric_limits<double>::infinity();

// ---- solver parameters: every field of pbf_solver_params by name -------------------------

struct SolverField {
    const char* name;
    size_t offset;
    bool is_uint;   // uint32_t; else float
    bool is_bool;   // a uint32_t flag (true/false or 0/1)
    double lo, hi;  // the API's documented range (the library checks again)
    bool open_lo;
};

// One line per field of pbf_solver_params after struct_size. A field added to the header must be
// added here too: the bake test "every solver parameter is settable by name" checks the count
// against sizeof(pbf_solver_params).
#define PBF_FIELD(name, u, b, lo, hi, open) \
    { #name, offsetof(pbf_solver_params, name), u, b, lo, hi, open }
const SolverField kSolverFields[] = {
    PBF_FIELD(iterations, true, false, 1, 64, false),
    PBF_FIELD(substeps, true, false, 0, 64, false),  // 0: automatic
    PBF_FIELD(relaxation, false, false, 0, kInf, true),
    PBF_FIELD(scorr_k, false, false, 0, kInf, false),
    PBF_FIELD(scorr_n, false, false, 1, 8, false),
    PBF_FIELD(scorr_dq, false, false, 0, 1, false),
    PBF_FIELD(xsph_c, false, false, 0, 1, false),
    PBF_FIELD(vorticity_epsilon, false, false, 0, kInf, false),
    PBF_FIELD(ldc_enabled, true, true, 0, 1, false),
    PBF_FIELD(ldc_gain, false, false, 0, 1, false),
    PBF_FIELD(max_speed, false, false, 0, kInf, true),
    PBF_FIELD(adaptive_error_target, false, false, 0, 1, false),
    PBF_FIELD(max_substeps, true, false, 1, 64, false),
    PBF_FIELD(substep_travel, false, false, 0.05, 1, false),
    PBF_FIELD(sound_speed, false, false, 0, kInf, true),
};
#undef PBF_FIELD

void parse_solver(const Ctx& c, const json& j, const std::string& path, pbf_solver_params& p) {
    check_keys(c, j, path, solver_field_names());
    for (const SolverField& f : kSolverFields) {
        const json* v = find(j, f.name);
        if (!v) continue;
        const std::string at = path + "/" + f.name;
        char* base = reinterpret_cast<char*>(&p) + f.offset;
        if (f.is_bool) {
            const uint32_t x = boolean(c, *v, at) ? 1u : 0u;
            std::memcpy(base, &x, sizeof x);
        } else if (f.is_uint) {
            const uint32_t x = uint32_t(integer(c, *v, at, int64_t(f.lo), int64_t(f.hi)));
            std::memcpy(base, &x, sizeof x);
        } else {
            const float x = float(number(c, *v, at, f.lo, f.hi, f.open_lo));
            std::memcpy(base, &x, sizeof x);
        }
    }
}

// ---- world ---------------------------------------------------------------------------------

void parse_world(const Ctx& c, const json& j, const std::string& path, pbf_world_desc& d) {
    check_keys(c, j, path,
               {"particle_radius", "rest_density", "domain_min", "domain_max", "gravity", "backend", "cuda_device",
                "max_particles"});
    if (const json* v = find(j, "particle_radius"))
        d.particle_radius = float(number(c, *v, path + "/particle_radius", 0, kInf, true));
    if (const json* v = find(j, "rest_density"))
        d.rest_density = float(number(c, *v, path + "/rest_density", 0, kInf, true));
    if (const json* v = find(j, "domain_min")) vec(c, *v, path + "/domain_min", d.domain_min);
    if (const json* v = find(j, "domain_max")) vec(c, *v, path + "/domain_max", d.domain_max);
    if (const json* v = find(j, "gravity")) vec(c, *v, path + "/gravity", d.gravity);
    if (const json* v = find(j, "backend")) {
        const std::string b = choice(c, *v, path + "/backend", {"auto", "cpu", "cuda"});
        d.backend = b == "cpu" ? PBF_BACKEND_CPU : b == "cuda" ? PBF_BACKEND_CUDA : PBF_BACKEND_AUTO;
    }
    if (const json* v = find(j, "cuda_device")) d.cuda_device = int32_t(integer(c, *v, path + "/cuda_device", 0, 1024));
    if (const json* v = find(j, "max_particles"))
        d.max_particles = uint32_t(integer(c, *v, path + "/max_particles", 1, int64_t(UINT32_MAX) - 1));
    for (int k = 0; k < 3; ++k)
        if (!(d.domain_max[k] > d.domain_min[k]))
            c.fail(path + "/domain_max/" + std::to_string(k),
                   "expected domain_max above domain_min on every axis, got " + fmt(d.domain_max[k]) +
                       " <= " + fmt(d.domain_min[k]));
}

void check_box(const Ctx& c, const std::string& path, const char* max_key, const float* lo, const float* hi) {
    for (int k = 0; k < 3; ++k)
        if (!(hi[k] > lo[k]))
            c.fail(path + "/" + max_key + "/" + std::to_string(k), std::string("expected ") + max_key +
                                                                       " above the minimum corner on every axis, got " +
                                                                       fmt(hi[k]) + " <= " + fmt(lo[k]));
}

BlockSpec parse_block(const Ctx& c, const json& j, const std::string& path) {
    check_keys(c, j, path, {"min", "max", "velocity"});
    BlockSpec b{pbf_block_desc_default()};
    vec(c, require(c, j, path, "min", "an array of 3 numbers"), path + "/min", b.desc.box_min);
    vec(c, require(c, j, path, "max", "an array of 3 numbers"), path + "/max", b.desc.box_max);
    if (const json* v = find(j, "velocity")) vec(c, *v, path + "/velocity", b.desc.velocity);
    check_box(c, path, "max", b.desc.box_min, b.desc.box_max);
    return b;
}

EmitterSpec parse_emitter(const Ctx& c, const json& j, const std::string& path) {
    if (!j.is_object()) c.expected(path, "an object", j);
    const std::string type =
        choice(c, require(c, j, path, "type", "\"nozzle\" or \"drain\""), path + "/type", {"nozzle", "drain"});
    EmitterSpec e{pbf_emitter_desc_default()};
    if (type == "nozzle") {
        check_keys(c, j, path,
                   {"type", "position", "direction", "rate", "speed", "radius", "enabled", "start_frame", "end_frame"});
        e.desc.type = PBF_EMITTER_NOZZLE;
        vec(c, require(c, j, path, "position", "an array of 3 numbers"), path + "/position", e.desc.position);
        if (const json* v = find(j, "direction")) {
            vec(c, *v, path + "/direction", e.desc.direction);
            const float* d = e.desc.direction;
            if (!(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 0.0f))
                c.expected(path + "/direction", "a non-zero vector", *v);
        }
        e.desc.particles_per_second =
            float(number(c, require(c, j, path, "rate", "particles per second, > 0"), path + "/rate", 0, kInf, true));
        e.desc.speed =
            float(number(c, require(c, j, path, "speed", "a speed in m/s, > 0"), path + "/speed", 0, kInf, true));
        e.desc.radius =
            float(number(c, require(c, j, path, "radius", "a disc radius in m, > 0"), path + "/radius", 0, kInf, true));
    } else {
        check_keys(c, j, path, {"type", "min", "max", "enabled", "start_frame", "end_frame"});
        e.desc.type = PBF_EMITTER_DRAIN;
        vec(c, require(c, j, path, "min", "an array of 3 numbers"), path + "/min", e.desc.box_min);
        vec(c, require(c, j, path, "max", "an array of 3 numbers"), path + "/max", e.desc.box_max);
        check_box(c, path, "max", e.desc.box_min, e.desc.box_max);
    }
    if (const json* v = find(j, "enabled")) e.desc.enabled = boolean(c, *v, path + "/enabled") ? 1u : 0u;
    if (const json* v = find(j, "start_frame")) e.start_frame = integer(c, *v, path + "/start_frame", 0, INT32_MAX);
    if (const json* v = find(j, "end_frame")) e.end_frame = integer(c, *v, path + "/end_frame", 0, INT32_MAX);
    if (e.end_frame >= 0 && e.end_frame <= e.start_frame)
        c.fail(path + "/end_frame", "expected end_frame above start_frame (" + std::to_string(e.start_frame) +
                                        "), got " + std::to_string(e.end_frame));
    return e;
}

// The unit quaternion that turns (0, 1, 0) onto n (normalised).
void rotation_from_normal(const float n_in[3], float q[4]) {
    const double len = std::sqrt(double(n_in[0]) * n_in[0] + double(n_in[1]) * n_in[1] + double(n_in[2]) * n_in[2]);
    const double n[3] = {n_in[0] / len, n_in[1] / len, n_in[2] / len};
    // axis = y × n = (n.z, 0, -n.x); cos θ = n.y
    const double dot = n[1];
    if (dot < -0.999999) {  // upside down: half a turn about x
        q[0] = 1;
        q[1] = 0;
        q[2] = 0;
        q[3] = 0;
        return;
    }
    double x = n[2], y = 0.0, z = -n[0], w = 1.0 + dot;
    const double m = std::sqrt(x * x + y * y + z * z + w * w);
    q[0] = float(x / m);
    q[1] = float(y / m);
    q[2] = float(z / m);
    q[3] = float(w / m);
}

void parse_rotation(const Ctx& c, const json& j, const std::string& path, float q[4]) {
    float r[4];
    vec(c, j, path, r);
    if (!(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3] > 1e-12f))
        c.expected(path, "a non-zero quaternion [x, y, z, w]", j);
    std::memcpy(q, r, sizeof r);
}

ColliderSpec parse_collider(const Ctx& c, const json& j, const std::string& path) {
    if (!j.is_object()) c.expected(path, "an object", j);
    const std::string shape = choice(c, require(c, j, path, "shape", "\"plane\", \"sphere\", \"capsule\" or \"box\""),
                                     path + "/shape", {"plane", "sphere", "capsule", "box"});
    std::vector<std::string> keys = {"shape", "motion", "position", "rotation", "friction", "keyframes"};
    if (shape == "plane") keys.push_back("normal");
    if (shape == "sphere" || shape == "capsule") keys.push_back("radius");
    if (shape == "capsule") keys.push_back("half_height");
    if (shape == "box") keys.push_back("half_extents");
    check_keys(c, j, path, keys);

    ColliderSpec s{pbf_collider_desc_default(), {}};
    pbf_collider_desc& d = s.desc;
    d.shape = shape == "plane"     ? PBF_SHAPE_PLANE
              : shape == "sphere"  ? PBF_SHAPE_SPHERE
              : shape == "capsule" ? PBF_SHAPE_CAPSULE
                                   : PBF_SHAPE_BOX;
    if (const json* v = find(j, "motion"))
        d.motion = choice(c, *v, path + "/motion", {"static", "kinematic"}) == "kinematic" ? PBF_MOTION_KINEMATIC
                                                                                           : PBF_MOTION_STATIC;
    if (const json* v = find(j, "position")) vec(c, *v, path + "/position", d.position);
    if (const json* v = find(j, "rotation")) parse_rotation(c, *v, path + "/rotation", d.rotation);
    if (const json* v = find(j, "normal")) {
        if (find(j, "rotation")) c.fail(path + "/normal", "give either \"normal\" or \"rotation\", not both");
        float n[3];
        vec(c, *v, path + "/normal", n);
        if (!(n[0] * n[0] + n[1] * n[1] + n[2] * n[2] > 0.0f)) c.expected(path + "/normal", "a non-zero vector", *v);
        rotation_from_normal(n, d.rotation);
    }
    if (const json* v = find(j, "friction")) d.friction = float(number(c, *v, path + "/friction", 0, 1));
    if (shape == "sphere" || shape == "capsule")
        d.radius =
            float(number(c, require(c, j, path, "radius", "a radius in m, > 0"), path + "/radius", 0, kInf, true));
    if (shape == "capsule")
        d.half_height = float(
            number(c, require(c, j, path, "half_height", "a half height in m, >= 0"), path + "/half_height", 0, kInf));
    if (shape == "box") {
        vec(c, require(c, j, path, "half_extents", "an array of 3 numbers > 0"), path + "/half_extents",
            d.half_extents);
        for (int k = 0; k < 3; ++k)
            if (!(d.half_extents[k] > 0.0f))
                c.expected(path + "/half_extents/" + std::to_string(k), "a number > 0", j["half_extents"][k]);
    }

    if (const json* v = find(j, "keyframes")) {
        const std::string kp = path + "/keyframes";
        if (d.motion != PBF_MOTION_KINEMATIC) c.fail(kp, "keyframes need \"motion\": \"kinematic\"");
        if (!v->is_array() || v->empty()) c.expected(kp, "a non-empty array of {frame, position, rotation}", *v);
        for (size_t i = 0; i < v->size(); ++i) {
            const std::string ip = kp + "/" + std::to_string(i);
            const json& kj = (*v)[i];
            check_keys(c, kj, ip, {"frame", "position", "rotation"});
            Keyframe k;
            k.frame = number(c, require(c, kj, ip, "frame", "a frame number"), ip + "/frame", 0, kInf);
            std::memcpy(k.position, d.position, sizeof k.position);
            std::memcpy(k.rotation, d.rotation, sizeof k.rotation);
            if (const json* p = find(kj, "position")) vec(c, *p, ip + "/position", k.position);
            if (const json* r = find(kj, "rotation")) parse_rotation(c, *r, ip + "/rotation", k.rotation);
            if (!s.keys.empty() && !(k.frame > s.keys.back().frame))
                c.fail(ip + "/frame", "expected keyframes in increasing frame order, got " + fmt(k.frame) + " after " +
                                          fmt(s.keys.back().frame));
            s.keys.push_back(k);
        }
        // The collider starts at the pose of frame 0.
        const Keyframe k0 = pose_at(s.keys, 0.0);
        std::memcpy(d.position, k0.position, sizeof d.position);
        std::memcpy(d.rotation, k0.rotation, sizeof d.rotation);
    } else if (d.motion == PBF_MOTION_KINEMATIC) {
        Keyframe k;  // a kinematic collider without keyframes stays where it is
        std::memcpy(k.position, d.position, sizeof k.position);
        std::memcpy(k.rotation, d.rotation, sizeof k.rotation);
        s.keys.push_back(k);
    }
    return s;
}

void parse_frames(const Ctx& c, const json& j, const std::string& path, Scene& s) {
    check_keys(c, j, path, {"start", "end", "rate", "steps_per_frame"});
    if (const json* v = find(j, "start")) s.frame_start = integer(c, *v, path + "/start", 0, INT32_MAX);
    if (const json* v = find(j, "end")) s.frame_end = integer(c, *v, path + "/end", 0, INT32_MAX);
    if (const json* v = find(j, "rate")) s.frame_rate = number(c, *v, path + "/rate", 1.0, 100000.0);
    if (const json* v = find(j, "steps_per_frame"))
        s.steps_per_frame = uint32_t(integer(c, *v, path + "/steps_per_frame", 1, 1000));
    if (s.frame_end < s.frame_start)
        c.fail(path + "/end",
               "expected end >= start (" + std::to_string(s.frame_start) + "), got " + std::to_string(s.frame_end));
}

void parse_output(const Ctx& c, const json& j, const std::string& path, OutputSpec& o) {
    check_keys(c, j, path, {"directory", "name", "formats", "vdb"});
    if (const json* v = find(j, "directory")) {
        o.directory = string(c, *v, path + "/directory");
        if (o.directory.empty()) c.expected(path + "/directory", "a non-empty path", *v);
    }
    if (const json* v = find(j, "name")) {
        o.name = string(c, *v, path + "/name");
        if (o.name.empty() || o.name.find_first_of("/\\") != std::string::npos)
            c.expected(path + "/name", "a non-empty file prefix without slashes", *v);
    }
    if (const json* v = find(j, "formats")) {
        const std::string fp = path + "/formats";
        if (!v->is_array() || v->empty()) c.expected(fp, "a non-empty array of \"ply\", \"vtk\", \"vdb\"", *v);
        o.formats = 0;
        for (size_t i = 0; i < v->size(); ++i) {
            const std::string f = choice(c, (*v)[i], fp + "/" + std::to_string(i), {"ply", "vtk", "vdb"});
            o.formats |= f == "ply" ? kPly : f == "vtk" ? kVtk : kVdb;
        }
    }
    if (const json* v = find(j, "vdb")) {
        const std::string vp = path + "/vdb";
        check_keys(c, *v, vp, {"voxel_size", "sphere_radius", "half_width"});
        if (const json* x = find(*v, "voxel_size")) o.vdb_voxel_size = number(c, *x, vp + "/voxel_size", 0, kInf, true);
        if (const json* x = find(*v, "sphere_radius"))
            o.vdb_sphere_radius = number(c, *x, vp + "/sphere_radius", 0, kInf, true);
        if (const json* x = find(*v, "half_width")) o.vdb_half_width = number(c, *x, vp + "/half_width", 1, 100);
    }
}

std::string stem_of(const std::string& path) {
    const size_t slash = path.find_last_of("/\\");
    std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
    const size_t dot = base.find_last_of('.');
    if (dot != std::string::npos && dot > 0) base = base.substr(0, dot);
    return base.empty() ? "scene" : base;
}

bool ends_with(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

#if defined(PBF_BAKE_HAVE_TOML)
json from_toml(const toml::node& n) {
    if (const auto* t = n.as_table()) {
        json o = json::object();
        for (const auto& [k, v] : *t) o[std::string(k.str())] = from_toml(v);
        return o;
    }
    if (const auto* a = n.as_array()) {
        json o = json::array();
        for (const auto& v : *a) o.push_back(from_toml(v));
        return o;
    }
    if (const auto* s = n.as_string()) return s->get();
    if (const auto* i = n.as_integer()) return i->get();
    if (const auto* f = n.as_floating_point()) return f->get();
    if (const auto* b = n.as_boolean()) return b->get();
    return n.is_value() ? json(nullptr) : json();  // dates and times: refused as wrong types later
}
#endif

}  // namespace

std::vector<std::string> solver_field_names() {
    std::vector<std::string> out;
    for (const SolverField& f : kSolverFields) out.push_back(f.name);
    return out;
}

bool have_vdb() {
#if defined(PBF_BAKE_HAVE_OPENVDB)
    return true;
#else
    return false;
#endif
}

bool have_toml() {
#if defined(PBF_BAKE_HAVE_TOML)
    return true;
#else
    return false;
#endif
}

unsigned parse_formats(const std::string& list, const std::string& where) {
    unsigned out = 0;
    std::stringstream ss(list);
    std::string item;
    while (std::getline(ss, item, ',')) {
        if (item == "ply")
            out |= kPly;
        else if (item == "vtk" || item == "vtp")
            out |= kVtk;
        else if (item == "vdb")
            out |= kVdb;
        else
            throw Error(where + ": unknown format \"" + item + "\" (expected a comma-separated list of ply, vtk, vdb)");
    }
    if (!out) throw Error(where + ": expected a comma-separated list of ply, vtk, vdb, got \"" + list + "\"");
    return out;
}

std::string format_list(unsigned f) {
    std::vector<std::string> v;
    if (f & kPly) v.push_back("ply");
    if (f & kVtk) v.push_back("vtk");
    if (f & kVdb) v.push_back("vdb");
    std::string s;
    for (size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
    return s;
}

Keyframe pose_at(const std::vector<Keyframe>& keys, double f) {
    if (keys.empty()) return Keyframe{};
    if (f <= keys.front().frame) return keys.front();
    if (f >= keys.back().frame) return keys.back();
    size_t i = 1;
    while (keys[i].frame < f) ++i;
    const Keyframe& a = keys[i - 1];
    const Keyframe& b = keys[i];
    const double t = (f - a.frame) / (b.frame - a.frame);
    Keyframe k;
    k.frame = f;
    for (int c = 0; c < 3; ++c) k.position[c] = float(a.position[c] + t * (b.position[c] - a.position[c]));
    double dot = 0.0;
    for (int c = 0; c < 4; ++c) dot += double(a.rotation[c]) * b.rotation[c];
    const double sign = dot < 0.0 ? -1.0 : 1.0;  // the shorter way round
    double q[4], m = 0.0;
    for (int c = 0; c < 4; ++c) {
        q[c] = (1.0 - t) * a.rotation[c] + t * sign * b.rotation[c];
        m += q[c] * q[c];
    }
    m = std::sqrt(m);
    for (int c = 0; c < 4; ++c) k.rotation[c] = float(m > 0 ? q[c] / m : (c == 3 ? 1.0 : 0.0));
    return k;
}

Scene parse_scene(const std::string& text, const std::string& file, bool toml) {
    const Ctx c{file};
    json root;
    if (toml) {
#if defined(PBF_BAKE_HAVE_TOML)
        try {
            root = from_toml(toml::parse(text, file));
        } catch (const toml::parse_error& e) {
            throw Error(file + ":" + std::to_string(e.source().begin.line) + ":" +
                        std::to_string(e.source().begin.column) + ": not valid TOML: " + std::string(e.description()));
        }
#else
        throw Error(file + ": this pbf_bake was built without TOML support (toml++ was not found); use a JSON scene");
#endif
    } else {
        try {
            root = json::parse(text);
        } catch (const json::parse_error& e) {
            // Turn the byte offset into a line and column.
            size_t line = 1, col = 1;
            for (size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
                if (text[i] == '\n')
                    ++line, col = 1;
                else
                    ++col;
            }
            // "[json.exception.parse_error.101] parse error at line 3, column 29: syntax error ...":
            // keep what follows the position.
            std::string what = e.what();
            const size_t at = what.find("parse error");
            const size_t p = at == std::string::npos ? std::string::npos : what.find(": ", at);
            if (p != std::string::npos) what = what.substr(p + 2);
            throw Error(file + ":" + std::to_string(line) + ":" + std::to_string(col) + ": not valid JSON: " + what);
        }
    }
    check_keys(c, root, "", {"world", "solver", "blocks", "emitters", "colliders", "frames", "output", "description"});

    Scene s;
    s.file = file;
    s.world = pbf_world_desc_default();
    s.world.solver = pbf_solver_params_default();
    if (const json* v = find(root, "description")) (void)string(c, *v, "/description");
    if (const json* v = find(root, "world")) parse_world(c, *v, "/world", s.world);
    if (const json* v = find(root, "solver")) parse_solver(c, *v, "/solver", s.world.solver);
    auto list = [&](const char* key, auto&& each) {
        const json* v = find(root, key);
        if (!v) return;
        const std::string p = std::string("/") + key;
        if (!v->is_array()) c.expected(p, "an array", *v);
        for (size_t i = 0; i < v->size(); ++i) each((*v)[i], p + "/" + std::to_string(i));
    };
    list("blocks", [&](const json& j, const std::string& p) { s.blocks.push_back(parse_block(c, j, p)); });
    list("emitters", [&](const json& j, const std::string& p) { s.emitters.push_back(parse_emitter(c, j, p)); });
    list("colliders", [&](const json& j, const std::string& p) { s.colliders.push_back(parse_collider(c, j, p)); });
    // The world is made to hold every collider of the scene (the library's limit is 2048).
    if (s.colliders.size() > 2048)
        c.fail("/colliders", "at most 2048 colliders, got " + std::to_string(s.colliders.size()));
    s.world.max_colliders = std::max<uint32_t>(s.world.max_colliders, uint32_t(s.colliders.size()));
    if (const json* v = find(root, "frames")) parse_frames(c, *v, "/frames", s);
    s.output.name = stem_of(file);
    s.output.directory = s.output.name + "_bake";
    if (const json* v = find(root, "output")) parse_output(c, *v, "/output", s.output);
    if (s.blocks.empty() && s.emitters.empty())
        c.fail("", "the scene has no fluid: expected at least one entry in \"blocks\" or \"emitters\"");
    return s;
}

Scene load_scene(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open the scene file: " + std::strerror(errno));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw Error(path + ": cannot read the scene file: " + std::strerror(errno));
    return parse_scene(text.str(), path, ends_with(path, ".toml"));
}

}  // namespace bake
