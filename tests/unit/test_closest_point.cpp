// The closest point of a plane triangle (lib/include/lodbake/core/closest_point.h): the one the
// bake's rasterisers measure every texel with (texel coverage, islands, the bake target) and
// texture deviation's UV lookups. Exact expectations on small triangles with dyadic coordinates.
#include <gtest/gtest.h>

#include <array>

#include "lodbake/core/closest_point.h"

using namespace lodbake;

namespace {

//   c (0,4)
//   | `.
//   |    `.
//   a ------ b
// (0,0)    (4,0)
const std::array<Vec2, 3> kTri{Vec2{0, 0}, Vec2{4, 0}, Vec2{0, 4}};

}  // namespace

TEST(ClosestPoint, PlaneTriangleInsideIsDistanceZeroWithItsBarycentrics) {
    std::array<double, 3> w{};
    EXPECT_EQ(closestOnTriangle(Vec2{1, 2}, kTri, w), 0.0);
    EXPECT_EQ(w, (std::array<double, 3>{0.25, 0.25, 0.5}));
    EXPECT_EQ(closestOnTriangle(Vec2{2, 0}, kTri, w), 0.0);  // on an edge: inside
    EXPECT_EQ(w, (std::array<double, 3>{0.5, 0.5, 0}));
}

TEST(ClosestPoint, PlaneTriangleOutsideTakesTheNearestEdgeOrCorner) {
    std::array<double, 3> w{};
    // Below edge ab: the foot of the perpendicular, squared distance 1.
    EXPECT_EQ(closestOnTriangle(Vec2{1, -1}, kTri, w), 1.0);
    EXPECT_EQ(w, (std::array<double, 3>{0.75, 0.25, 0}));
    // Beyond the hypotenuse bc: its midpoint (2, 2) from (3, 3).
    EXPECT_EQ(closestOnTriangle(Vec2{3, 3}, kTri, w), 2.0);
    EXPECT_EQ(w, (std::array<double, 3>{0, 0.5, 0.5}));
    // Beyond corner b: the corner itself (edge ab reaches it first, with all its weight on b).
    EXPECT_EQ(closestOnTriangle(Vec2{6, -2}, kTri, w), 8.0);
    EXPECT_EQ(w, (std::array<double, 3>{0, 1, 0}));
}

TEST(ClosestPoint, DegeneratePlaneTriangleIsMeasuredAlongItsEdges) {
    // All three corners on the x axis: no inside, the closest point of the segment [0, 4].
    const std::array<Vec2, 3> flat{Vec2{0, 0}, Vec2{4, 0}, Vec2{2, 0}};
    std::array<double, 3> w{};
    EXPECT_EQ(closestOnTriangle(Vec2{1, 2}, flat, w), 4.0);
    EXPECT_EQ(w, (std::array<double, 3>{0.75, 0.25, 0}));
}
