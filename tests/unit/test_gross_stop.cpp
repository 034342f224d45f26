// Unit tests of the gross-error stop of simplify(): a triangle-count level keeps the triangles it
// has rather than go further than SimplifyOptions::grossError of the diagonal from the input.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "lodbake/simplify/simplify.h"
#include "unit/synthetic_meshes.h"

namespace lodbake {
namespace {

// The unit cube as 12 outward triangles on its 8 corners (a box asset's geometry).
TriMesh cube() {
    TriMesh m;
    for (int k = 0; k < 8; ++k) m.positions.push_back({double(k & 1), double((k >> 1) & 1), double((k >> 2) & 1)});
    // Each side as two triangles, counter-clockwise seen from outside.
    const uint32_t quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    test::addDefaultWedges(m);
    return m;
}

SimplifyOptions ratios(double grossError) {
    SimplifyOptions o;
    for (double r : {0.5, 0.1, 0.02}) o.levels.push_back(LevelTarget{r, 0, 0});
    o.grossError = grossError;
    return o;
}

std::set<uint32_t> usedVertices(const Level& l) {
    std::set<uint32_t> v;
    for (const Tri& t : l.triangles) v.insert(t.begin(), t.end());
    return v;
}

TEST(GrossStop, CubeLevelsKeepTheirCornersWithinTheBound) {
    const TriMesh m = cube();
    const SimplifyResult r = simplify(m, ratios(0.25));
    ASSERT_EQ(r.multires.levels.size(), 3u);  // every level is still there
    for (const Level& l : r.multires.levels) {
        EXPECT_EQ(usedVertices(l).size(), 8u);
        EXPECT_EQ(l.triangles.size(), 12u);
        EXPECT_LE(l.maxDeviation, 0.25 * r.diagonal);
        EXPECT_EQ(l.stopReason.rfind("gross error: ", 0), 0u) << l.stopReason;
        EXPECT_NE(l.stopReason.find("over the bound 0.25"), std::string::npos) << l.stopReason;
        EXPECT_DOUBLE_EQ(l.grossErrorBound, 0.25 * r.diagonal);
        EXPECT_GT(l.grossErrorRefused, l.grossErrorBound);
    }
}

TEST(GrossStop, ZeroTurnsItOff) {
    const SimplifyResult r = simplify(cube(), ratios(0));
    const Level& l1 = r.multires.levels[0];
    EXPECT_EQ(l1.triangles.size(), 6u);  // the wedge the bound prevents
    EXPECT_GT(l1.maxDeviation, 0.25 * r.diagonal);
    for (const Level& l : r.multires.levels) EXPECT_EQ(l.grossErrorBound, 0.0);
}

TEST(GrossStop, LevelsUnderTheBoundAreUnchanged) {
    const TriMesh m = test::sphere(3);
    const SimplifyResult on = simplify(m, ratios(0.25)), off = simplify(m, ratios(0));
    ASSERT_EQ(on.multires.levels.size(), off.multires.levels.size());
    for (size_t k = 0; k < on.multires.levels.size(); ++k) {
        const Level &a = on.multires.levels[k], &b = off.multires.levels[k];
        ASSERT_LE(b.maxDeviation, 0.25 * off.diagonal);
        EXPECT_EQ(a.triangles, b.triangles);
        EXPECT_EQ(a.faceRegion, b.faceRegion);
        EXPECT_EQ(a.maxDeviation, b.maxDeviation);
        EXPECT_EQ(a.stopReason, b.stopReason);
        EXPECT_EQ(a.grossErrorBound, 0.0);
    }
    EXPECT_EQ(on.multires.collapses.size(), off.multires.collapses.size());
}

TEST(GrossStop, ErrorTargetsSetTheirOwnBound) {
    SimplifyOptions o;
    o.levels = {LevelTarget{0, 0, 0.5}};
    const SimplifyResult r = simplify(cube(), o);
    const Level& l = r.multires.levels[0];
    EXPECT_LT(l.triangles.size(), 12u);
    EXPECT_GT(l.maxDeviation, 0.25 * r.diagonal);
    EXPECT_EQ(l.grossErrorBound, 0.0);
}

}  // namespace
}  // namespace lodbake
