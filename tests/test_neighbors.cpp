// Neighbour masks (grid.h): the recorded and replayed neighbour sets against brute force.
#include <catch2/catch.hpp>

#include <algorithm>
#include <numeric>
#include <random>
#include <set>
#include <vector>

#include "../native/core/grid.h"

using namespace pbf;

namespace {

// Particles sorted by cell on a grid of cell size h, with the arrays the passes see.
struct SortedCloud {
    GridDims g{};
    float h = 0.1f;
    std::vector<Vec4> pos;
    std::vector<uint32_t> keys, cell_begin, rows;

    SortedCloud(std::vector<Vec3> points, Vec3 origin, int32_t nx, int32_t ny, int32_t nz) {
        g = GridDims{origin, 1.0f / h, nx, ny, nz, uint32_t(nx * ny * nz)};
        std::vector<uint32_t> k(points.size());
        for (size_t i = 0; i < points.size(); ++i) k[i] = cell_key(g, points[i]);
        std::vector<uint32_t> order(points.size());
        std::iota(order.begin(), order.end(), 0u);
        std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return k[a] < k[b]; });
        for (uint32_t o : order) {
            pos.push_back(make_vec4(points[o], 0.0f));
            keys.push_back(k[o]);
        }
        cell_begin.assign(g.num_cells + 1, 0u);
        for (uint32_t c = 0; c <= g.num_cells; ++c)
            cell_begin[c] = uint32_t(std::lower_bound(keys.begin(), keys.end(), c) - keys.begin());
        rows.assign(pos.size() * kMaskRows, 0xDEADBEEFu);  // garbage: recording must overwrite all
    }
    uint32_t n() const { return uint32_t(pos.size()); }
    NeighborMasks masks() { return NeighborMasks{rows.data(), keys.data(), n()}; }

    std::set<uint32_t> brute(uint32_t i) const {
        std::set<uint32_t> out;
        for (uint32_t j = 0; j < n(); ++j)
            if (length_sq(xyz(pos[i]) - xyz(pos[j])) < h * h) out.insert(j);
        return out;
    }
    std::set<uint32_t> recorded(uint32_t i) {
        std::set<uint32_t> out;
        for_each_neighbor_recording(g, cell_begin.data(), pos.data(), h * h, masks(), i, xyz(pos[i]),
                                    [&](uint32_t j) { CHECK(out.insert(j).second); });
        return out;
    }
    // Replay, keeping what lies within h of the current positions (as every pass does).
    std::set<uint32_t> replayed(uint32_t i) {
        std::set<uint32_t> out;
        for_each_listed_neighbor(g, cell_begin.data(), masks(), i, [&](uint32_t j) {
            if (length_sq(xyz(pos[i]) - xyz(pos[j])) < h * h) CHECK(out.insert(j).second);
        });
        return out;
    }
};

std::vector<Vec3> jittered_lattice(float spacing, int nx, int ny, int nz, float jitter, uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-jitter, jitter);
    std::vector<Vec3> p;
    for (int z = 0; z < nz; ++z)
        for (int y = 0; y < ny; ++y)
            for (int x = 0; x < nx; ++x)
                p.push_back(Vec3{(x + 0.5f) * spacing + u(rng), (y + 0.5f) * spacing + u(rng),
                                 (z + 0.5f) * spacing + u(rng)});
    return p;
}

}  // namespace

TEST_CASE("neighbour masks record exactly the particles within h, and replay them", "[neighbors]") {
    // h = 2 spacings: ~8 particles a cell, ~33 neighbours, rows of <= 32 candidates.
    SortedCloud c(jittered_lattice(0.05f, 14, 12, 10, 0.01f, 5u), Vec3{0, 0, 0}, 7, 6, 5);
    size_t listed_rows = 0;
    for (uint32_t i = 0; i < c.n(); ++i) {
        const std::set<uint32_t> truth = c.brute(i);
        REQUIRE(c.recorded(i) == truth);
        REQUIRE(c.replayed(i) == truth);
        for (int r = 0; r < kMaskRows; ++r) listed_rows += c.rows[r * c.n() + i] != kRowUnlisted;
    }
    CHECK(listed_rows == size_t(c.n()) * kMaskRows);  // at rest density every row fits 32 bits
}

TEST_CASE("over-packed rows fall back to a full walk and still find every neighbour", "[neighbors]") {
    // Spacing h/4: ~64 particles a cell, so rows hold far more than 32 candidates.
    SortedCloud c(jittered_lattice(0.025f, 16, 12, 12, 0.005f, 9u), Vec3{0, 0, 0}, 4, 3, 3);
    size_t unlisted = 0;
    for (uint32_t i = 0; i < c.n(); i += 7) {
        const std::set<uint32_t> truth = c.brute(i);
        REQUIRE(c.recorded(i) == truth);
        REQUIRE(c.replayed(i) == truth);
        for (int r = 0; r < kMaskRows; ++r) unlisted += c.rows[r * c.n() + i] == kRowUnlisted;
    }
    CHECK(unlisted > 0);
}

TEST_CASE("after particles move, the replay is the recorded set within h of the new positions", "[neighbors]") {
    SortedCloud c(jittered_lattice(0.05f, 10, 10, 10, 0.01f, 11u), Vec3{0, 0, 0}, 5, 5, 5);
    std::vector<std::set<uint32_t>> at_build(c.n());
    for (uint32_t i = 0; i < c.n(); ++i) at_build[i] = c.recorded(i);
    std::mt19937 rng(3u);
    std::uniform_real_distribution<float> u(-0.01f, 0.01f);  // a tenth of h, as an iteration might
    for (Vec4& p : c.pos) p = Vec4{p.x + u(rng), p.y + u(rng), p.z + u(rng), 0.0f};
    size_t lost = 0;
    for (uint32_t i = 0; i < c.n(); ++i) {
        std::set<uint32_t> expect;
        for (uint32_t j : at_build[i])
            if (length_sq(xyz(c.pos[i]) - xyz(c.pos[j])) < c.h * c.h) expect.insert(j);
        REQUIRE(c.replayed(i) == expect);
        lost += at_build[i].size() - expect.size();
    }
    CHECK(lost > 0);  // the motion was large enough to matter
}

TEST_CASE("a dead slot (key = num_cells) records and replays no neighbours", "[neighbors]") {
    SortedCloud c(jittered_lattice(0.05f, 6, 6, 6, 0.0f, 1u), Vec3{0, 0, 0}, 3, 3, 3);
    c.keys.back() = c.g.num_cells;
    // Where a slot without the guard would find neighbours: key num_cells decodes to cell
    // (0, 0, nz), whose lower rows lie in the top layer next to this position.
    c.pos.back() = Vec4{0.025f, 0.025f, 0.275f, 0.0f};
    CHECK(c.recorded(c.n() - 1).empty());
    CHECK(c.replayed(c.n() - 1).empty());
}
