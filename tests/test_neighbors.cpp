// The neighbour grid (grid.h), dense and hashed: walked, recorded and replayed neighbour sets
// against brute force.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <map>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <utility>
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

    SortedCloud(std::vector<Vec3> points, Vec3 origin, int32_t nx, int32_t ny, int32_t nz)
        : SortedCloud(std::move(points), dense_grid(origin, 1.0f / 0.1f, nx, ny, nz)) {}
    SortedCloud(std::vector<Vec3> points, const GridDims& grid) {
        g = grid;
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
    // The plain walk (for_each_neighbor), each candidate exactly once; candidates counts them
    // all, within h or not.
    std::set<uint32_t> walked(uint32_t i, size_t* candidates = nullptr) const {
        std::set<uint32_t> all, out;
        for_each_neighbor(g, cell_begin.data(), xyz(pos[i]), [&](uint32_t j) {
            CHECK(all.insert(j).second);
            if (length_sq(xyz(pos[i]) - xyz(pos[j])) < h * h) out.insert(j);
        });
        if (candidates) *candidates += all.size();
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
                p.push_back(
                    Vec3{(x + 0.5f) * spacing + u(rng), (y + 0.5f) * spacing + u(rng), (z + 0.5f) * spacing + u(rng)});
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

// Every 7th particle's recorded and replayed neighbours against brute force; the rows left unlisted.
static size_t check_every_seventh(SortedCloud& c) {
    size_t unlisted = 0;
    for (uint32_t i = 0; i < c.n(); i += 7) {
        const std::set<uint32_t> truth = c.brute(i);
        REQUIRE(c.recorded(i) == truth);
        REQUIRE(c.replayed(i) == truth);
        for (int r = 0; r < kMaskRows; ++r) unlisted += c.rows[r * c.n() + i] == kRowUnlisted;
    }
    return unlisted;
}

TEST_CASE("over-packed rows fall back to a full walk and still find every neighbour", "[neighbors]") {
    // Spacing h/4: ~64 particles a cell, so rows hold far more than 32 candidates.
    SortedCloud c(jittered_lattice(0.025f, 16, 12, 12, 0.005f, 9u), Vec3{0, 0, 0}, 4, 3, 3);
    CHECK(check_every_seventh(c) > 0);
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

// ---- the hashed grid ---------------------------------------------------------------------------
namespace {

// The shortest non-zero vector (max norm, in cells) of the hashed grid's collision lattice
// {v : v.x + stride_y v.y + stride_z v.z ≡ 0 mod 2^bits}, searched up to |v.y|, |v.z| <= reach
// (reach + 1 when none is shorter).
uint32_t shortest_collision(uint32_t bits, uint32_t reach) {
    const GridDims g = hashed_grid(Vec3{0, 0, 0}, 1.0f, bits);
    uint32_t best = reach + 1;
    for (int32_t dz = -int32_t(reach); dz <= int32_t(reach); ++dz)
        for (int32_t dy = -int32_t(reach); dy <= int32_t(reach); ++dy) {
            if (dy == 0 && dz == 0) continue;              // then only multiples of num_cells along x collide
            const uint32_t r = key_of_cell(g, 0, dy, dz);  // v.x ≡ -r: the nearest is -r or N - r
            const uint32_t dx = std::min(r, g.num_cells - r);
            best = std::min(best, std::max({dx, uint32_t(std::abs(dy)), uint32_t(std::abs(dz))}));
        }
    return best;
}

// The hashed grid of a cloud in cells of h = 0.1, with 2^12 keys.
GridDims small_hashed_grid() { return hashed_grid(Vec3{0, 0, 0}, 1.0f / 0.1f, kMinHashBits); }

std::vector<Vec3> shifted(std::vector<Vec3> p, Vec3 by) {
    for (Vec3& v : p) v = v + by;
    return p;
}

}  // namespace

TEST_CASE("hashed strides: no two cells of one query share a key, and collisions lie far apart", "[grid][neighbors]") {
    for (uint32_t bits = kMinHashBits; bits <= kMaxHashBits; ++bits) {
        const HashStrides& st = kHashStrides[bits - kMinHashBits];
        INFO("bits " << bits);
        CHECK(shortest_collision(bits, st.shortest) == st.shortest);  // the table's claim
        // A query's cells lie |Δ| <= 2 apart: a lattice vector that short would count twice.
        CHECK(st.shortest >= 3u);
        CHECK(double(st.shortest) >= 0.83 * std::cbrt(double(uint64_t(1) << bits)));
    }
    CHECK(hashed_grid_bits(1) == kMinHashBits);
    CHECK(hashed_grid_bits(100000) == 17u);
    CHECK(hashed_grid_bits(131072) == 17u);
    CHECK(hashed_grid_bits(1u << 30) == kMaxHashBits);
}

TEST_CASE("hashed grid: walk, record and replay find exactly the particles within h, across the key wrap",
          "[grid][neighbors]") {
    // A cloud straddling the origin: cell (-1, 0, 0) has key num_cells - 1, so windows wrap.
    SortedCloud c(shifted(jittered_lattice(0.05f, 14, 12, 10, 0.01f, 21u), Vec3{-0.35f, -0.3f, -0.25f}),
                  small_hashed_grid());
    REQUIRE(c.keys.back() == c.g.num_cells - 1u);  // sorted: the last particle sits at the top key
    size_t listed_rows = 0;
    for (uint32_t i = 0; i < c.n(); ++i) {
        const std::set<uint32_t> truth = c.brute(i);
        REQUIRE(c.walked(i) == truth);
        REQUIRE(c.recorded(i) == truth);
        REQUIRE(c.replayed(i) == truth);
        for (int r = 0; r < kMaskRows; ++r) listed_rows += c.rows[r * c.n() + i] != kRowUnlisted;
    }
    CHECK(listed_rows == size_t(c.n()) * kMaskRows);
    // Over-packed rows (spacing h/4) fall back to the full walk there too.
    SortedCloud packed(shifted(jittered_lattice(0.025f, 16, 12, 12, 0.005f, 9u), Vec3{-0.2f, -0.15f, -0.15f}),
                       small_hashed_grid());
    CHECK(check_every_seventh(packed) > 0);
}

TEST_CASE("hashed grid: two far-apart fluids whose cells share keys are not neighbours", "[grid][neighbors]") {
    const GridDims g = small_hashed_grid();
    // (dx, 1, 0) with dx ≡ -stride_y (mod num_cells) is a collision vector: a fluid shifted by it
    // lands on exactly the keys of the first one, dx cells (~34 m) away.
    const int32_t dx = int32_t(g.num_cells - g.stride_y);
    const int32_t lattice_dx = dx < int32_t(g.num_cells / 2) ? dx : dx - int32_t(g.num_cells);
    REQUIRE(key_of_cell(g, lattice_dx, 1, 0) == key_of_cell(g, 0, 0, 0));
    const std::vector<Vec3> near = jittered_lattice(0.05f, 10, 10, 10, 0.01f, 4u);
    const std::vector<Vec3> far = shifted(near, Vec3{float(lattice_dx) * 0.1f, 0.1f, 0.0f});
    std::vector<Vec3> both = near;
    both.insert(both.end(), far.begin(), far.end());
    SortedCloud alone(near, g), pair(both, g);
    size_t candidates_alone = 0, candidates_pair = 0;
    for (uint32_t i = 0; i < alone.n(); ++i) alone.walked(i, &candidates_alone);
    for (uint32_t i = 0; i < pair.n(); ++i) {
        const std::set<uint32_t> truth = pair.brute(i);
        REQUIRE(pair.walked(i, &candidates_pair) == truth);
        REQUIRE(pair.recorded(i) == truth);
        REQUIRE(pair.replayed(i) == truth);
    }
    // The collision is real: each fluid's queries also walk the other's particles...
    CHECK(candidates_pair > 2 * candidates_alone + candidates_alone / 2);
    // ...and yet every particle's neighbourhood, hence its density, is what it is alone.
    std::multiset<size_t> sizes_alone, sizes_near;
    for (uint32_t i = 0; i < alone.n(); ++i) sizes_alone.insert(alone.brute(i).size());
    for (uint32_t i = 0; i < pair.n(); ++i)
        if (pair.pos[i].x < 10.0f) sizes_near.insert(pair.recorded(i).size());
    CHECK(sizes_near == sizes_alone);
    // The density sums (Σ (h² - r²)³ over the walked candidates within h) of the near fluid's
    // particles, matched by position: the far fluid adds nothing to any of them.
    auto density = [](const SortedCloud& c, uint32_t i) {
        double rho = 0.0;
        for_each_neighbor(c.g, c.cell_begin.data(), xyz(c.pos[i]), [&](uint32_t j) {
            const double r2 = length_sq(xyz(c.pos[i]) - xyz(c.pos[j])), d = double(c.h) * c.h - r2;
            if (d > 0.0) rho += d * d * d;
        });
        return rho;
    };
    std::map<std::array<float, 3>, double> alone_rho;
    for (uint32_t i = 0; i < alone.n(); ++i)
        alone_rho[{alone.pos[i].x, alone.pos[i].y, alone.pos[i].z}] = density(alone, i);
    size_t matched = 0;
    for (uint32_t i = 0; i < pair.n(); ++i) {
        const auto it = alone_rho.find({pair.pos[i].x, pair.pos[i].y, pair.pos[i].z});
        if (it == alone_rho.end()) continue;
        ++matched;
        REQUIRE(density(pair, i) == Approx(it->second).epsilon(1e-12));
    }
    CHECK(matched == alone.n());
}

TEST_CASE("grid cells of non-finite and far positions are clamped, never converted out of range", "[grid]") {
    const GridDims g = small_hashed_grid();
    int32_t cx, cy, cz;
    cell_coords(g, Vec3{1e30f, -1e30f, std::numeric_limits<float>::quiet_NaN()}, cx, cy, cz);
    CHECK(cx == kHashCellLimit);
    CHECK(cy == -kHashCellLimit);
    CHECK(cz == -kHashCellLimit);
    cell_coords(g, Vec3{std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(), -0.05f}, cx,
                cy, cz);
    CHECK(cx == kHashCellLimit);
    CHECK(cy == -kHashCellLimit);
    CHECK(cz == -1);
    // A query far out walks valid key ranges only (cell_begin has num_cells + 1 entries).
    SortedCloud c(jittered_lattice(0.05f, 4, 4, 4, 0.0f, 1u), g);
    for (const Vec3 p : {Vec3{1e30f, 1e30f, 1e30f}, Vec3{-3e9f, 2e9f, 0.0f},
                         Vec3{std::numeric_limits<float>::quiet_NaN(), 0.0f, 0.0f}}) {
        size_t visits = 0;
        for_each_neighbor(g, c.cell_begin.data(), p, [&](uint32_t j) {
            REQUIRE(j < c.n());
            ++visits;
        });
        CHECK(visits <= c.n());
    }
}
