// The defaults the header's comments state are the library's: every "(default X)" or
// "(defaults A and B)" in a desc's field comment is read from the header's text and compared with
// what the pbf_*_default() inline (the library's *_init) fills in. A user reads the header, not
// defaults.cpp; a comment left behind when a default changes fails here. A field whose comment
// states a numeric default that this test does not read fails too, so a new field is covered.
#include "support.h"

#include <cmath>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace {

// The header's text, embedded at configure time (tests/CMakeLists.txt), so the test needs no path
// to the source tree when it runs (under Wine, say).
const char kHeader[] =
#include "pbf_c_api_text.inc"
    ;

using Values = std::vector<double>;

// For each field of `typedef struct name { ... } name;` whose comment states numeric defaults:
// field -> the numbers (a list such as "0, -9.81, 0" or "-1,0,-1 .. 1,2,1", or "2 and 8").
std::map<std::string, Values> stated_defaults(const std::string& header, const std::string& name) {
    const std::string open = "typedef struct " + name + " {", close = "} " + name + ";";
    const size_t begin = header.find(open), end = header.find(close, begin);
    REQUIRE(begin != std::string::npos);
    REQUIRE(end != std::string::npos);
    const std::regex field(R"(^\s+(?:const\s+)?\w+\**\s+\**(\w+)(?:\[\d+\])?;(.*)$)");
    const std::string number = R"(-?\d+(?:\.\d+)?(?:e[+-]?\d+)?)";
    // "(default 0.5)", "(defaults 2 and 8)", "(default 0, -9.81, 0)", or "1 (default)".
    const std::regex stated(
        "defaults?\\s+(" + number + "(?:\\s*(?:,|and|\\.\\.)\\s*" + number + ")*)|(" + number + ")\\s+\\(default\\)",
        std::regex::icase);
    const std::regex each(number);

    // Each field's comment runs from its declaration to the next declaration.
    std::vector<std::pair<std::string, std::string>> comments;
    std::istringstream lines(header.substr(begin + open.size(), end - begin - open.size()));
    for (std::string line; std::getline(lines, line);) {
        std::smatch m;
        if (std::regex_match(line, m, field))
            comments.emplace_back(m[1].str(), m[2].str());
        else if (!comments.empty())
            comments.back().second += " " + line;
    }
    std::map<std::string, Values> result;
    for (const auto& [f, comment] : comments) {
        std::smatch m;
        if (!std::regex_search(comment, m, stated)) continue;
        const std::string list = m[1].matched ? m[1].str() : m[2].str();
        Values v;
        for (auto it = std::sregex_iterator(list.begin(), list.end(), each); it != std::sregex_iterator(); ++it)
            v.push_back(std::stod(it->str()));
        result[f] = v;
    }
    return result;
}

struct Expected {
    const char* desc;
    const char* field;  // the field whose comment states the default(s)
    Values values;      // what the library's default struct holds
};

template <size_t N>
Values vec(const float (&a)[N]) {
    return Values(a, a + N);
}
Values cat(Values a, const Values& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

// The header's numbers against the library's; one number for an array field ("velocity[3]
// (default 0)") stands for every element.
bool same(const Values& header, const Values& library) {
    if (header.size() != library.size() && header.size() != 1) return false;
    for (size_t i = 0; i < library.size(); ++i) {
        const double h = header[header.size() == 1 ? 0 : i];
        if (std::fabs(h - library[i]) > 1e-6 * std::fmax(1.0, std::fabs(library[i]))) return false;
    }
    return true;
}

std::string str(const Values& v) {
    std::ostringstream s;
    for (size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i];
    return s.str();
}

}  // namespace

TEST_CASE("header: the defaults its comments state are the library's", "[api][defaults]") {
    const pbf_solver_params s = pbf_solver_params_default();
    const pbf_render_params r = pbf_render_params_default();
    const pbf_diffuse_params d = pbf_diffuse_params_default();
    const pbf_world_desc w = pbf_world_desc_default();
    const pbf_block_desc b = pbf_block_desc_default();
    const pbf_emitter_desc e = pbf_emitter_desc_default();
    const pbf_mesh_desc m = pbf_mesh_desc_default();
    const pbf_collider_desc c = pbf_collider_desc_default();
    const pbf_material_desc mat = pbf_material_desc_default();
    const pbf_gl_buffer_desc gl = pbf_gl_buffer_desc_default();
    const pbf_d3d11_buffer_desc d3d11 = pbf_d3d11_buffer_desc_default();
    const pbf_external_buffer_desc ext = pbf_external_buffer_desc_default();
    const pbf_semaphore_desc sem = pbf_semaphore_desc_default();

    const std::vector<Expected> expected = {
        {"pbf_solver_params", "iterations", {double(s.iterations)}},
        {"pbf_solver_params", "substeps", {double(s.substeps)}},
        {"pbf_solver_params", "relaxation", {s.relaxation}},
        {"pbf_solver_params", "scorr_k", {s.scorr_k}},
        {"pbf_solver_params", "scorr_n", {s.scorr_n}},
        {"pbf_solver_params", "scorr_dq", {s.scorr_dq}},
        {"pbf_solver_params", "xsph_c", {s.xsph_c}},
        {"pbf_solver_params", "vorticity_epsilon", {s.vorticity_epsilon}},
        {"pbf_solver_params", "ldc_enabled", {double(s.ldc_enabled)}},
        {"pbf_solver_params", "ldc_gain", {s.ldc_gain}},
        {"pbf_solver_params", "max_speed", {s.max_speed}},
        {"pbf_solver_params", "adaptive_error_target", {s.adaptive_error_target}},
        {"pbf_solver_params", "max_substeps", {double(s.max_substeps)}},
        {"pbf_solver_params", "substep_travel", {s.substep_travel}},
        {"pbf_solver_params", "sound_speed", {s.sound_speed}},
        {"pbf_render_params", "flags", {double(r.flags)}},
        {"pbf_render_params", "smoothing", {r.smoothing}},
        {"pbf_render_params", "max_stretch", {r.max_stretch}},
        {"pbf_render_params", "scale", {r.scale}},
        {"pbf_render_params", "isolated_scale", {r.isolated_scale}},
        {"pbf_render_params", "min_neighbors", {double(r.min_neighbors)}},
        {"pbf_diffuse_params", "max_diffuse", {double(d.max_diffuse)}},
        {"pbf_diffuse_params", "trapped_air_max", {d.trapped_air_min, d.trapped_air_max}},
        {"pbf_diffuse_params", "wave_crest_max", {d.wave_crest_min, d.wave_crest_max}},
        {"pbf_diffuse_params", "energy_max", {d.energy_min, d.energy_max}},
        {"pbf_diffuse_params", "trapped_air_rate", {d.trapped_air_rate}},
        {"pbf_diffuse_params", "wave_crest_rate", {d.wave_crest_rate}},
        {"pbf_diffuse_params", "lifetime", {d.lifetime}},
        {"pbf_diffuse_params", "spray_max_neighbors", {double(d.spray_max_neighbors)}},
        {"pbf_diffuse_params", "bubble_min_neighbors", {double(d.bubble_min_neighbors)}},
        {"pbf_diffuse_params", "buoyancy", {d.buoyancy}},
        {"pbf_diffuse_params", "bubble_drag", {d.bubble_drag}},
        {"pbf_diffuse_params", "spray_drag", {d.spray_drag}},
        {"pbf_world_desc", "cuda_device", {double(w.cuda_device)}},
        {"pbf_world_desc", "max_particles", {double(w.max_particles)}},
        {"pbf_world_desc", "particle_radius", {w.particle_radius}},
        {"pbf_world_desc", "rest_density", {w.rest_density}},
        {"pbf_world_desc", "gravity", vec(w.gravity)},
        {"pbf_world_desc", "domain_max", cat(vec(w.domain_min), vec(w.domain_max))},
        {"pbf_world_desc", "max_colliders", {double(w.max_colliders)}},
        {"pbf_world_desc", "walls", {double(w.walls)}},
        {"pbf_world_desc", "hashed_grid", {double(w.hashed_grid)}},
        {"pbf_block_desc", "velocity", vec(b.velocity)},
        {"pbf_emitter_desc", "enabled", {double(e.enabled)}},
        {"pbf_emitter_desc", "direction", vec(e.direction)},
        {"pbf_mesh_desc", "closed", {double(m.closed)}},
        {"pbf_collider_desc", "friction", {c.friction}},
        {"pbf_collider_desc", "dynamic", {double(c.dynamic)}},
        {"pbf_collider_desc", "center_of_mass", vec(c.center_of_mass)},
        {"pbf_material_desc", "rest_density", {mat.rest_density}},
        {"pbf_material_desc", "viscosity", {mat.viscosity}},
        {"pbf_material_desc", "ldc_gain", {mat.ldc_gain}},
        {"pbf_material_desc", "surface_tension", {mat.surface_tension}},
        {"pbf_material_desc", "cohesion", {mat.cohesion}},
        {"pbf_material_desc", "adhesion", {mat.adhesion}},
        {"pbf_material_desc", "color", vec(mat.color)},
        {"pbf_material_desc", "user_id", {double(mat.user_id)}},
        {"pbf_gl_buffer_desc", "offset_bytes", {double(gl.offset_bytes)}},
        {"pbf_gl_buffer_desc", "draw_args_offset_bytes", {double(gl.draw_args_offset_bytes)}},
        {"pbf_gl_buffer_desc", "draw_args_vertices", {double(gl.draw_args_vertices)}},
        {"pbf_d3d11_buffer_desc", "offset_bytes", {double(d3d11.offset_bytes)}},
        {"pbf_d3d11_buffer_desc", "draw_args_offset_bytes", {double(d3d11.draw_args_offset_bytes)}},
        {"pbf_d3d11_buffer_desc", "draw_args_vertices", {double(d3d11.draw_args_vertices)}},
        {"pbf_external_buffer_desc", "offset_bytes", {double(ext.offset_bytes)}},
        {"pbf_external_buffer_desc", "fd", {double(ext.fd)}},
        {"pbf_external_buffer_desc", "dedicated", {double(ext.dedicated)}},
        {"pbf_external_buffer_desc", "write_draw_args", {double(ext.write_draw_args)}},
        {"pbf_external_buffer_desc", "draw_args_vertices", {double(ext.draw_args_vertices)}},
        {"pbf_semaphore_desc", "fd", {double(sem.fd)}},
    };

    const std::string header(kHeader);
    std::map<std::string, std::map<std::string, Values>> stated;
    for (const Expected& x : expected)
        if (!stated.count(x.desc)) stated[x.desc] = stated_defaults(header, x.desc);

    // Every default this test reads is stated, and equals the library's.
    for (const Expected& x : expected) {
        INFO(x.desc << "." << x.field);
        const auto& fields = stated[x.desc];
        const auto it = fields.find(x.field);
        CHECK(it != fields.end());  // the header states no numeric default for it
        if (it == fields.end()) continue;
        INFO("header: " << str(it->second) << "; library: " << str(x.values));
        CHECK(same(it->second, x.values));
    }
    // Every numeric default the header states is read here.
    for (const auto& [desc, fields] : stated)
        for (const auto& [field, values] : fields) {
            bool read = false;
            for (const Expected& x : expected) read = read || (desc == x.desc && field == x.field);
            INFO(desc << "." << field << " states default " << str(values) << ": add it to this test");
            CHECK(read);
        }
}
