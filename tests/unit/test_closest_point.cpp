// Closest points (lib/include/lodbake/core/closest_point.h). In the plane: the one the bake's
// rasterisers measure every texel with (texel coverage, islands, the bake target) and texture
// deviation's UV lookups, with exact expectations on small triangles with dyadic coordinates. On a
// surface: the near-face filter and the boxed search give the full search's answer.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "lodbake/core/closest_point.h"
#include "synthetic_meshes.h"

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

TEST(ClosestPoint, NearFacesAndBoxedSearchMatchTheFullSearch) {
    // A bumpy 12 x 12 grid; a floating triangle over it: for points of the triangle and points on
    // the faces themselves (distance 0), facesNearTriangle + BoxedFaces with any hint give exactly
    // closestSurfacePoint over every face (face, barycentrics and distance).
    TriMesh m = test::grid(12, 12, [](int i, int j) { return 0.3 * std::sin(0.9 * i) * std::cos(0.7 * j); });
    std::vector<uint32_t> all(m.triangleCount());
    for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
    const std::array<Vec3, 3> tri{Vec3{3.2, 4.1, 0.6}, Vec3{6.9, 4.4, 0.8}, Vec3{5.1, 7.7, 0.5}};
    std::vector<uint32_t> near = facesNearTriangle(m, all, tri);
    EXPECT_LT(near.size(), all.size());
    const BoxedFaces boxed(m, near);
    std::vector<Vec3> points;
    for (int a = 0; a <= 10; ++a)
        for (int b = 0; a + b <= 10; ++b) points.push_back(tri[0] * (1 - 0.1 * (a + b)) + tri[1] * (0.1 * a) + tri[2] * (0.1 * b));
    for (uint32_t f : {40u, 41u, 100u, 150u}) {  // on faces the triangle hangs over: distance 0
        const Tri& t = m.triangles[f];
        points.push_back(m.positions[t[0]] * 0.2 + m.positions[t[1]] * 0.3 + m.positions[t[2]] * 0.5);
    }
    uint32_t hint = 0xffffffffu;
    for (const Vec3& p : points) {
        uint32_t f0 = 0, f1 = 0;
        std::array<double, 3> b0{}, b1{};
        double d0 = closestSurfacePoint(m, all, p, f0, b0);
        double d1 = boxed.closest(p, hint, f1, b1);
        ASSERT_EQ(f0, f1);
        ASSERT_EQ(d0, d1);
        ASSERT_EQ(b0, b1);
        hint = (f1 * 7 + 3) % uint32_t(m.triangleCount());  // any face, near or not
    }
}

TEST(ClosestPoint, CoincidentCopiesLeftOutChangeNoAnswer) {
    // The grid three times over (instances at the same place, as a skinned part instanced per
    // skeleton flattens), the second copy's corners listed in a turned order: withoutCopies drops
    // exactly the third copy (same corners, same order), and the closest face, its barycentrics and
    // the distance over what remains are the full set's for points on and off the surface.
    TriMesh m = test::grid(6, 6, [](int i, int j) { return 0.2 * std::sin(1.3 * i + 0.4 * j); });
    const size_t n = m.triangleCount(), vertices = m.positions.size();
    for (int copy = 1; copy <= 2; ++copy) {
        for (size_t v = 0; v < vertices; ++v) m.positions.push_back(m.positions[v]);
        for (size_t f = 0; f < n; ++f) {
            Tri t = m.triangles[f];
            for (uint32_t& v : t) v += uint32_t(copy * vertices);
            if (copy == 1) t = Tri{t[1], t[2], t[0]};
            m.triangles.push_back(t);
        }
    }
    std::vector<uint32_t> all(m.triangleCount());
    for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
    const std::vector<uint32_t> kept = withoutCopies(m, all);
    ASSERT_EQ(kept.size(), 2 * n);
    for (size_t i = 0; i < kept.size(); ++i) EXPECT_EQ(kept[i], uint32_t(i));
    for (int a = 0; a <= 12; ++a)
        for (int b = 0; b <= 12; ++b)
            for (double z : {0.0, 0.7, -0.4}) {
                const Vec3 p{0.45 * a - 0.2, 0.45 * b - 0.1, z + 0.2 * std::sin(1.3 * 0.45 * a)};
                uint32_t f0 = 0, f1 = 0;
                std::array<double, 3> b0{}, b1{};
                ASSERT_EQ(closestSurfacePoint(m, all, p, f0, b0), closestSurfacePoint(m, kept, p, f1, b1));
                ASSERT_EQ(f0, f1);
                ASSERT_EQ(b0, b1);
            }
}
