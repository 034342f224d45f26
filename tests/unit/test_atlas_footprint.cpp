// The page search's private helpers (lib/src/atlas/chart_footprint.h, bitmap_page.h) against
// brute force: the conservative rasterisation tests each cell's four corners, the blocks cover
// their footprint once, and the lowest free position is the first (row, then column) that
// meets no set texel; a dense chart's orientation is that of its hull's corners.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "atlas/bitmap_page.h"
#include "atlas/chart_footprint.h"

using namespace lodbake;
using namespace lodbake::atlas_detail;

namespace {

// chartMask's rule at radius 0, cell by cell: a triangle marks the cells of its corners, and every
// cell of its bounding box that no edge normal separates from it (the extent over all four corners).
std::vector<uint8_t> bruteMask(const Oriented& c, double t, int gw, int gh) {
    std::vector<uint8_t> mask(size_t(gw) * size_t(gh), 0);
    auto mark = [&](int x, int y) {
        if (x >= 0 && y >= 0 && x < gw && y < gh) mask[size_t(y) * size_t(gw) + size_t(x)] = 1;
    };
    for (const auto& tri : c.triangles) {
        std::array<Vec2, 3> q{Vec2{tri[0].x * t, tri[0].y * t}, Vec2{tri[1].x * t, tri[1].y * t}, Vec2{tri[2].x * t, tri[2].y * t}};
        for (const Vec2& v : q) mark(int(std::floor(v.x)), int(std::floor(v.y)));
        if (std::abs(cross(q[1] - q[0], q[2] - q[0])) < 1e-12) continue;
        const int x0 = std::max(0, int(std::floor(std::min({q[0].x, q[1].x, q[2].x}))));
        const int x1 = std::min(gw - 1, int(std::floor(std::max({q[0].x, q[1].x, q[2].x}))));
        const int y0 = std::max(0, int(std::floor(std::min({q[0].y, q[1].y, q[2].y}))));
        const int y1 = std::min(gh - 1, int(std::floor(std::max({q[0].y, q[1].y, q[2].y}))));
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                bool separated = false;
                for (int k = 0; k < 3 && !separated; ++k) {
                    const Vec2 e = q[size_t((k + 1) % 3)] - q[size_t(k)];
                    const Vec2 n{-e.y, e.x};
                    const double scale = std::sqrt(dot(n, n));
                    if (scale == 0) continue;
                    const double t0 = dot(n, q[0]), t1 = dot(n, q[1]), t2 = dot(n, q[2]);
                    const double tMin = std::min({t0, t1, t2}), tMax = std::max({t0, t1, t2}), margin = 1e-6 * scale;
                    const Vec2 cell[4] = {{double(x), double(y)}, {x + 1.0, double(y)}, {x + 1.0, y + 1.0}, {double(x), y + 1.0}};
                    double cMin = 1e300, cMax = -1e300;
                    for (const Vec2& p : cell) { cMin = std::min(cMin, dot(n, p)); cMax = std::max(cMax, dot(n, p)); }
                    separated = cMax <= tMin + margin || tMax <= cMin + margin;
                }
                if (!separated) mark(x, y);
            }
    }
    return mask;
}

// A chart of random triangles in [0, 1]^2, some of them slivers along a row or a column.
Oriented randomChart(std::mt19937& rng, int triangles) {
    std::uniform_real_distribution<double> u(0, 1);
    Oriented c;
    c.w = c.h = 1;
    for (int i = 0; i < triangles; ++i) {
        std::array<Vec2, 3> tri{Vec2{u(rng), u(rng)}, Vec2{u(rng), u(rng)}, Vec2{u(rng), u(rng)}};
        if (i % 5 == 1) tri[1].y = tri[0].y;  // an edge along a row
        if (i % 5 == 2) tri[2].x = tri[0].x;  // an edge along a column
        c.triangles.push_back(tri);
    }
    return c;
}

// A footprint from a random blob: a union of rectangles in a w x h grid.
Footprint randomFootprint(std::mt19937& rng, int w, int h, int rotation) {
    std::vector<uint8_t> mask(size_t(w) * size_t(h), 0);
    std::uniform_int_distribution<int> x(0, w - 1), y(0, h - 1);
    for (int r = 0; r < 3; ++r) {
        int ax = x(rng), bx = x(rng), ay = y(rng), by = y(rng);
        for (int j = std::min(ay, by); j <= std::max(ay, by); ++j)
            for (int i = std::min(ax, bx); i <= std::max(ax, bx); ++i) mask[size_t(j) * size_t(w) + size_t(i)] = 1;
    }
    return rotatedFootprint(mask, w, h, rotation);
}

bool overlaps(const std::vector<uint8_t>& page, int W, const Footprint& f, int x, int y) {
    for (int i = 0; i < f.h; ++i)
        for (const auto& [a, b] : f.rows[size_t(i)])
            for (int c = a; c <= b; ++c)
                if (page[size_t(y + i) * size_t(W) + size_t(x + c)]) return true;
    return false;
}

}  // namespace

TEST(ChartFootprint, MaskMatchesTheCellByCellTest) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 40; ++trial) {
        const Oriented c = randomChart(rng, 12);
        const double t = 3 + trial * 1.7;
        int gw = 0, gh = 0;
        size_t raster = 0;
        const std::vector<uint8_t> mask = chartMask(c, t, 0, gw, gh, &raster);
        EXPECT_EQ(mask, bruteMask(c, t, gw, gh)) << "trial " << trial;
        EXPECT_EQ(raster, size_t(std::count(mask.begin(), mask.end(), uint8_t(1))));
    }
}

//   ..#....        radius 1:  .###...
//   .......                   .#####.
//   ....#..                   ...###.
TEST(ChartFootprint, GrowthSetsTheSquareAroundEachCell) {
    std::mt19937 rng(5);
    for (int trial = 0; trial < 60; ++trial) {
        const int w = 1 + trial % 29, h = 1 + trial % 41, radius = trial % 7;
        std::vector<uint8_t> mask(size_t(w) * size_t(h), 0);
        std::bernoulli_distribution on(0.03 + 0.01 * (trial % 10));
        for (auto& m : mask) m = on(rng);
        RowRuns cells;
        cells.w = w;
        cells.h = h;
        cells.first.assign(1, 0);
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x)
                if (mask[size_t(y) * size_t(w) + size_t(x)]) {
                    if (x > 0 && mask[size_t(y) * size_t(w) + size_t(x) - 1]) cells.runs.back().second = x;
                    else cells.runs.push_back({x, x});
                }
            cells.first.push_back(cells.runs.size());
        }
        const RowRuns grown = growByRadius(cells, radius);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                bool near = false;
                for (int j = std::max(0, y - radius); j <= std::min(h - 1, y + radius); ++j)
                    for (int i = std::max(0, x - radius); i <= std::min(w - 1, x + radius); ++i) near = near || mask[size_t(j) * size_t(w) + size_t(i)];
                bool set = false;
                for (size_t k = grown.first[size_t(y)]; k < grown.first[size_t(y) + 1]; ++k)
                    set = set || (grown.runs[k].first <= x && x <= grown.runs[k].second);
                ASSERT_EQ(set, near) << "trial " << trial << " cell " << x << ", " << y;
            }
        for (int y = 0; y < h; ++y)  // disjoint and not touching
            for (size_t k = grown.first[size_t(y)] + 1; k < grown.first[size_t(y) + 1]; ++k) {
                ASSERT_GT(grown.runs[k].first, grown.runs[k - 1].second + 1);
            }
    }
}

//   footprint      blocks (bands of 16, 8, 4, 2, 1 rows)
//   ..####..       each band's block: the columns all its rows occupy, less its enclosing
//   .######.       band's; together they hold every occupied cell once
TEST(ChartFootprint, BlocksCoverTheFootprintOnce) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 200; ++trial) {
        const Footprint f = randomFootprint(rng, 1 + trial % 23, 1 + trial % 37 + (trial % 3) * 20, trial % 4);
        std::vector<int> covered(size_t(f.w) * size_t(f.h), 0);
        for (const Footprint::Block& k : f.blocks) {
            ASSERT_GE(k.rows, 1);
            ASSERT_LE(k.rows, kBlockRows);
            ASSERT_LE(1 << k.level, k.rows);
            ASSERT_GT(2 << k.level, k.rows);
            for (int i = k.top; i < k.top + k.rows; ++i)
                for (int x = k.a; x <= k.b; ++x) ++covered[size_t(i) * size_t(f.w) + size_t(x)];
        }
        for (int i = 0; i < f.h; ++i)
            for (int x = 0; x < f.w; ++x) {
                const auto& runs = f.rows[size_t(i)];
                const bool on = std::any_of(runs.begin(), runs.end(), [&](auto r) { return r.first <= x && x <= r.second; });
                EXPECT_EQ(covered[size_t(i) * size_t(f.w) + size_t(x)], on ? 1 : 0) << "trial " << trial;
            }
    }
}

//   page (random charts placed)     a footprint's lowest position:
//   ##..###....                     the first row, then the first column, where none of its
//   #...#####..                     texels meets a set one
TEST(BitmapPage, FindsTheLowestFreePosition) {
    std::mt19937 rng(3);
    for (int trial = 0; trial < 30; ++trial) {
        const int W = 70 + trial * 5, H = 60 + trial * 3;  // some widths past one 64-bit word
        BitmapPage page(W, H);
        std::vector<uint8_t> cells(size_t(W) * size_t(H), 0);
        std::uniform_int_distribution<int> side(1, 24);
        for (int k = 0; k < 80; ++k) {
            const Footprint f = randomFootprint(rng, side(rng), side(rng), k % 4);
            if (f.w > W || f.h > H) continue;
            int x = 0, y = 0;
            const bool found = page.find(f, 0, 1e300, x, y);
            int bx = -1, by = -1;
            for (int yy = 0; yy + f.h <= H && by < 0; ++yy)
                for (int xx = 0; xx + f.w <= W; ++xx)
                    if (!overlaps(cells, W, f, xx, yy)) { bx = xx; by = yy; break; }
            ASSERT_EQ(found, by >= 0) << "trial " << trial << " chart " << k;
            if (!found) continue;
            ASSERT_EQ(x, bx);
            ASSERT_EQ(y, by);
            page.place(f, x, y);
            for (int i = 0; i < f.h; ++i)
                for (const auto& [a, b] : f.rows[size_t(i)])
                    for (int c = a; c <= b; ++c) cells[size_t(y + i) * size_t(W) + size_t(x + c)] = 1;
        }
    }
}

TEST(ChartFootprint, DenseChartTurnsLikeItsHullCorners) {
    // A rotated rectangle's corners and edge points, then thousands of points inside it (a dense
    // chart: the orientation drops them before the hull).
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    const double c = std::cos(0.3), s = std::sin(0.3);
    auto at = [&](double x, double y) { return Vec2{0.2 + c * x * 0.5 - s * y * 0.3, 0.1 + s * x * 0.5 + c * y * 0.3}; };
    AtlasChart ring;
    for (double t : {0.0, 0.25, 0.5, 1.0}) {
        ring.points.push_back(at(t, 0));
        ring.points.push_back(at(1, t));
        ring.points.push_back(at(1 - t, 1));
        ring.points.push_back(at(0, 1 - t));
    }
    ring.triangles = {{at(0, 0), at(1, 0), at(1, 1)}, {at(0, 0), at(1, 1), at(0, 1)}};
    AtlasChart dense = ring;
    for (int i = 0; i < 5000; ++i) dense.points.push_back(at(u(rng), u(rng)));
    std::shuffle(dense.points.begin(), dense.points.end(), rng);
    const Oriented a = chartOrientations(ring, false)[0], b = chartOrientations(dense, false)[0];
    EXPECT_EQ(a.c, b.c);
    EXPECT_EQ(a.s, b.s);
    EXPECT_EQ(a.minX, b.minX);
    EXPECT_EQ(a.minY, b.minY);
    EXPECT_EQ(a.w, b.w);
    EXPECT_EQ(a.h, b.h);
}
