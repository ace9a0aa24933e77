#include "bake_writers.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "bake_scene.h"

namespace bake {

namespace {

// Files are written through stdio; every failure names the file and the system's reason.
struct File {
    std::string path;
    FILE* f = nullptr;
    explicit File(const std::string& p) : path(p) {
        f = std::fopen(p.c_str(), "wb");
        if (!f) throw Error(p + ": cannot create: " + std::strerror(errno));
    }
    ~File() {
        if (f) std::fclose(f);
    }
    void write(const void* data, size_t bytes) {
        if (bytes && std::fwrite(data, 1, bytes, f) != bytes)
            throw Error(path + ": write failed: " + std::strerror(errno));
    }
    void text(const std::string& s) { write(s.data(), s.size()); }
    void close() {
        const int rc = std::fclose(f);
        f = nullptr;
        if (rc != 0) throw Error(path + ": write failed: " + std::strerror(errno));
    }
};

// Little-endian bytes whatever the host.
void put_u32(unsigned char* p, uint32_t v) {
    p[0] = uint8_t(v);
    p[1] = uint8_t(v >> 8);
    p[2] = uint8_t(v >> 16);
    p[3] = uint8_t(v >> 24);
}
void put_f32(unsigned char* p, float x) {
    uint32_t v;
    std::memcpy(&v, &x, 4);
    put_u32(p, v);
}
void put_u64(unsigned char* p, uint64_t v) {
    put_u32(p, uint32_t(v));
    put_u32(p + 4, uint32_t(v >> 32));
}

// One inline binary DataArray: base64 of (UInt64 byte count, then the little-endian data).
std::string data_array(const std::vector<unsigned char>& payload) {
    std::vector<unsigned char> block(8 + payload.size());
    put_u64(block.data(), payload.size());
    if (!payload.empty()) std::memcpy(block.data() + 8, payload.data(), payload.size());
    return base64(block.data(), block.size());
}

// A whole inline binary <DataArray> element at the Piece's data indent: the opening tag (with
// NumberOfComponents where it is more than 1), the data, the closing tag.
void put_data_array(File& f, const char* type, const char* name, int components,
                    const std::vector<unsigned char>& payload) {
    std::string open = std::string("        <DataArray type=\"") + type + "\" Name=\"" + name + "\"";
    if (components > 1) open += " NumberOfComponents=\"" + std::to_string(components) + "\"";
    f.text(open + " format=\"binary\">\n");
    f.text(data_array(payload));
    f.text("\n        </DataArray>\n");
}

std::string xml_escape(const std::string& s) {
    std::string out;
    for (char ch : s) {
        switch (ch) {
            case '&':
                out += "&amp;";
                break;
            case '<':
                out += "&lt;";
                break;
            case '>':
                out += "&gt;";
                break;
            case '"':
                out += "&quot;";
                break;
            default:
                out += ch;
        }
    }
    return out;
}

}  // namespace

std::string base64(const void* data, size_t bytes) {
    static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const auto* p = static_cast<const unsigned char*>(data);
    std::string out;
    out.reserve((bytes + 2) / 3 * 4);
    size_t i = 0;
    for (; i + 3 <= bytes; i += 3) {
        const uint32_t v = uint32_t(p[i]) << 16 | uint32_t(p[i + 1]) << 8 | p[i + 2];
        out += kAlphabet[v >> 18];
        out += kAlphabet[(v >> 12) & 63];
        out += kAlphabet[(v >> 6) & 63];
        out += kAlphabet[v & 63];
    }
    if (i < bytes) {
        const uint32_t v = uint32_t(p[i]) << 16 | (i + 1 < bytes ? uint32_t(p[i + 1]) << 8 : 0u);
        out += kAlphabet[v >> 18];
        out += kAlphabet[(v >> 12) & 63];
        out += i + 1 < bytes ? kAlphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

void write_ply(const std::string& path, const Frame& fr) {
    File f(path);
    char header[512];
    std::snprintf(header, sizeof header,
                  "ply\n"
                  "format binary_little_endian 1.0\n"
                  "comment libpbf pbf_bake frame %lld time %.6f\n"
                  "element vertex %u\n"
                  "property float x\n"
                  "property float y\n"
                  "property float z\n"
                  "property float vx\n"
                  "property float vy\n"
                  "property float vz\n"
                  "property float density_ratio\n"
                  "property uint id\n"
                  "end_header\n",
                  (long long)fr.index, fr.time, fr.count);
    f.text(header);
    constexpr size_t kStride = 32;
    std::vector<unsigned char> chunk;
    const uint32_t per_chunk = 16384;
    for (uint32_t start = 0; start < fr.count; start += per_chunk) {
        const uint32_t n = std::min(per_chunk, fr.count - start);
        chunk.resize(size_t(n) * kStride);
        for (uint32_t k = 0; k < n; ++k) {
            const size_t i = start + k;
            unsigned char* p = chunk.data() + size_t(k) * kStride;
            put_f32(p + 0, fr.xyzw[4 * i + 0]);
            put_f32(p + 4, fr.xyzw[4 * i + 1]);
            put_f32(p + 8, fr.xyzw[4 * i + 2]);
            put_f32(p + 12, fr.vel[4 * i + 0]);
            put_f32(p + 16, fr.vel[4 * i + 1]);
            put_f32(p + 20, fr.vel[4 * i + 2]);
            put_f32(p + 24, fr.xyzw[4 * i + 3]);
            put_u32(p + 28, fr.ids[i]);
        }
        f.write(chunk.data(), chunk.size());
    }
    f.close();
}

void write_vtp(const std::string& path, const Frame& fr) {
    const size_t n = fr.count;
    std::vector<unsigned char> points(n * 12), velocity(n * 12), density(n * 4), ids(n * 4), conn(n * 8), offs(n * 8);
    for (size_t i = 0; i < n; ++i) {
        for (int c = 0; c < 3; ++c) {
            put_f32(points.data() + 12 * i + 4 * c, fr.xyzw[4 * i + c]);
            put_f32(velocity.data() + 12 * i + 4 * c, fr.vel[4 * i + c]);
        }
        put_f32(density.data() + 4 * i, fr.xyzw[4 * i + 3]);
        put_u32(ids.data() + 4 * i, fr.ids[i]);
        put_u64(conn.data() + 8 * i, i);
        put_u64(offs.data() + 8 * i, i + 1);  // version 1.0: the end of each cell
    }
    File f(path);
    char head[512];
    std::snprintf(head, sizeof head,
                  "<?xml version=\"1.0\"?>\n"
                  "<!-- libpbf pbf_bake frame %lld time %.6f -->\n"
                  "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
                  "  <PolyData>\n"
                  "    <Piece NumberOfPoints=\"%zu\" NumberOfVerts=\"%zu\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
                  "NumberOfPolys=\"0\">\n",
                  (long long)fr.index, fr.time, n, n);
    f.text(head);
    f.text("      <PointData Scalars=\"density_ratio\" Vectors=\"velocity\">\n");
    put_data_array(f, "Float32", "velocity", 3, velocity);
    put_data_array(f, "Float32", "density_ratio", 1, density);
    put_data_array(f, "UInt32", "id", 1, ids);
    f.text("      </PointData>\n      <Points>\n");
    put_data_array(f, "Float32", "Points", 3, points);
    f.text("      </Points>\n      <Verts>\n");
    put_data_array(f, "Int64", "connectivity", 1, conn);
    put_data_array(f, "Int64", "offsets", 1, offs);
    f.text("      </Verts>\n    </Piece>\n  </PolyData>\n</VTKFile>\n");
    f.close();
}

void write_pvd(const std::string& path, const std::vector<std::pair<double, std::string>>& entries) {
    File f(path);
    f.text(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "  <Collection>\n");
    for (const auto& [t, name] : entries) {
        char line[96];
        std::snprintf(line, sizeof line, "    <DataSet timestep=\"%.9g\" group=\"\" part=\"0\" file=\"", t);
        f.text(line);
        f.text(xml_escape(name) + "\"/>\n");
    }
    f.text("  </Collection>\n</VTKFile>\n");
    f.close();
}

#if !defined(PBF_BAKE_HAVE_OPENVDB)
uint64_t write_vdb(const std::string& path, const Frame&, const VdbSettings&) {
    throw Error(path +
                ": this pbf_bake was built without OpenVDB (libopenvdb-dev was not found when it was configured)");
}
#endif

}  // namespace bake
