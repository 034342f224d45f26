// absorbIslands (lib/src/lod/level_islands.h): islands of a level baked by projection are
// unfolded onto neighbouring charts without folds or overlaps, in the triangles' own shape.
#include <gtest/gtest.h>

#include <cmath>

#include "lod/level_islands.h"

using namespace lodbake;
using namespace lodbake::lod_detail;

namespace {

double signedUvArea(const std::array<Vec2, 3>& t) { return cross(t[1] - t[0], t[2] - t[0]); }

bool interiorsOverlap(const std::array<Vec2, 3>& a, const std::array<Vec2, 3>& b) {
    for (const auto* t : {&a, &b})
        for (size_t i = 0; i < 3; ++i) {
            Vec2 e = (*t)[(i + 1) % 3] - (*t)[i];
            Vec2 n{-e.y, e.x};
            double aMin = 1e300, aMax = -1e300, bMin = 1e300, bMax = -1e300;
            for (const Vec2& p : a) { aMin = std::min(aMin, dot(p, n)); aMax = std::max(aMax, dot(p, n)); }
            for (const Vec2& p : b) { bMin = std::min(bMin, dot(p, n)); bMax = std::max(bMax, dot(p, n)); }
            if (aMax <= bMin + 1e-9 || bMax <= aMin + 1e-9) return false;
        }
    return true;
}

// An n x n grid of unit quads on a cylinder-like bent strip (so the layout is not the 3D shape):
// the left half's triangles in layout chart 0 (UV = the flat grid coordinates), every triangle of
// the right half an island of its own, placed far apart.
struct Strip {
    std::vector<Vec3> positions;
    std::vector<Tri> triangles;
    std::vector<uint32_t> chart;
    std::vector<std::array<Vec2, 3>> uv;
    uint32_t firstIsland = 1;
};

Strip strip(int n) {
    Strip s;
    std::vector<Vec2> flat;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) {
            s.positions.push_back({double(x), double(y), 0});
            flat.push_back({double(x), double(y)});
        }
    auto id = [&](int x, int y) { return uint32_t(y * (n + 1) + x); };
    uint32_t island = s.firstIsland;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (Tri t : {Tri{id(x, y), id(x + 1, y), id(x + 1, y + 1)}, Tri{id(x, y), id(x + 1, y + 1), id(x, y + 1)}}) {
                s.triangles.push_back(t);
                std::array<Vec2, 3> u{flat[t[0]], flat[t[1]], flat[t[2]]};
                if (x < n / 2) {
                    s.chart.push_back(0);
                } else {  // an island far from everything, same orientation
                    Vec2 off{100.0 * island, 0};
                    for (Vec2& p : u) p = p + off;
                    s.chart.push_back(island++);
                }
                s.uv.push_back(u);
            }
    return s;
}

}  // namespace

TEST(LevelIslands, IslandsJoinTheirNeighbourWithoutFoldsOrOverlaps) {
    const Strip s = strip(6);
    const LevelChartSet set = absorbIslands(s.positions, s.triangles, s.chart, s.uv, s.firstIsland, 1.0);
    ASSERT_EQ(set.chart.size(), s.triangles.size());
    EXPECT_EQ(set.uvArea.size(), 1u);  // the flat strip unfolds into the one chart
    EXPECT_EQ(set.absorbed, s.triangles.size() / 2);
    double area = 0;
    for (size_t t = 0; t < set.uv.size(); ++t) {
        EXPECT_GT(signedUvArea(set.uv[t]), 0) << "triangle " << t;
        area += 0.5 * std::abs(signedUvArea(set.uv[t]));
        for (size_t o = 0; o < t; ++o) EXPECT_FALSE(interiorsOverlap(set.uv[t], set.uv[o])) << t << " / " << o;
        // Unfolded at the layout's scale (1 UV unit per model unit): the triangle keeps its shape.
        for (size_t j = 0; j < 3; ++j) {
            const Vec3 e3 = s.positions[s.triangles[t][(j + 1) % 3]] - s.positions[s.triangles[t][j]];
            const Vec2 e2 = set.uv[t][(j + 1) % 3] - set.uv[t][j];
            EXPECT_NEAR(std::sqrt(dot(e2, e2)), length(e3), 1e-9);
        }
    }
    EXPECT_NEAR(set.uvArea[0], area, 1e-9);
    EXPECT_NEAR(area, 36.0, 1e-9);
}

TEST(LevelIslands, IslandsWithoutALayoutNeighbourGrowTheirOwnChart) {
    Strip s = strip(4);
    for (uint32_t& c : s.chart)
        if (c == 0) c = 1000;  // no layout chart: every triangle is an island
    uint32_t next = s.firstIsland;
    for (uint32_t& c : s.chart) c = next++;
    const LevelChartSet set = absorbIslands(s.positions, s.triangles, s.chart, s.uv, s.firstIsland, 1.0);
    EXPECT_EQ(set.uvArea.size(), 1u);
    EXPECT_EQ(set.grouped, s.triangles.size() - 1);
    for (size_t t = 0; t < set.uv.size(); ++t) {
        EXPECT_GT(signedUvArea(set.uv[t]), 0);
        for (size_t o = 0; o < t; ++o) EXPECT_FALSE(interiorsOverlap(set.uv[t], set.uv[o]));
    }
}

TEST(LevelIslands, AnIslandWhoseUnfoldingOverlapsItsChartStaysApart) {
    // Chart 0: triangle 0 at the unit corner and triangle 1 (vertices of another part) covering
    // x in [-1, 0]. The island (0, 2, 3) unfolds across edge (0, 2) to x < 0, onto triangle 1.
    std::vector<Vec3> positions{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.5, 0.5, 0}, {5, 0, 0}, {6, 0, 0}, {5, 1, 0}};
    std::vector<Tri> triangles{{0, 1, 2}, {4, 5, 6}, {0, 2, 3}};
    std::vector<uint32_t> chart{0, 0, 1};
    std::vector<std::array<Vec2, 3>> uv{{Vec2{0, 0}, Vec2{1, 0}, Vec2{0, 1}},
                                        {Vec2{-1, 0}, Vec2{-0.01, 0.3}, Vec2{-1, 1}},
                                        {Vec2{50, 0}, Vec2{50, 1}, Vec2{49.5, 0.5}}};
    const LevelChartSet set = absorbIslands(positions, triangles, chart, uv, 1, 1.0);
    EXPECT_EQ(set.uvArea.size(), 2u);
    EXPECT_EQ(set.absorbed + set.grouped, 0u);
    EXPECT_NE(set.chart[2], set.chart[0]);
    for (size_t j = 0; j < 3; ++j) EXPECT_EQ(set.uv[2][j].x, uv[2][j].x);  // keeps its layout UVs
}
