// Unit tests for the bake (lib/src/bake/): base colour of faces and islands on two flat quads,
// regions of the page, thread counts, shared sources, vertex colours, the faces a layout's
// islands sample, and those a projected island samples. The channels beyond base colour:
// test_material_bake.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "lodbake/bake/bake.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"
#include "bake/island_bake.h"
#include "bake/texel_raster.h"
#include "lodbake/core/face_grid.h"
#include "synthetic_meshes.h"

using namespace lodbake;

namespace {

// Two unit quads side by side (x in [0,1] material 0, x in [1,2] material 1), mapped to the left
// and right thirds of the atlas:
//   +-----+-----+
//   | m0  | m1  |
//   +-----+-----+
Asset twoQuads(Vec4 c0, Vec4 c1) {
    Asset a;
    TriMesh& m = a.mesh;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}};
    m.triangles = {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}};
    m.cornerWedges = m.triangles;
    m.wedges.vertex = {0, 1, 2, 3, 4, 5};
    m.triangleMaterial = {0, 0, 1, 1};
    Material m0, m1;
    m0.baseColorFactor = c0;
    m1.baseColorFactor = c1;
    a.materials = {m0, m1};
    return a;
}

std::vector<std::array<Vec2, 3>> twoQuadsUV() {
    // glTF UVs (v down): left quad -> u in [0.05, 0.40], right quad -> u in [0.60, 0.95].
    auto uv = [](double x, double y) { return x <= 1 ? Vec2{0.05 + 0.35 * x, 0.95 - 0.9 * y} : Vec2{0.60 + 0.35 * (x - 1), 0.95 - 0.9 * y}; };
    Vec2 p0 = uv(0, 0), p1 = uv(1, 0), p3 = uv(0, 1), p4 = uv(1, 1);
    Vec2 q1{0.60, 0.95}, q2 = uv(2, 0), q4{0.60, 0.05}, q5 = uv(2, 1);
    return {{p0, p1, p4}, {p0, p4, p3}, {q1, q2, q5}, {q1, q5, q4}};
}

}  // namespace

TEST(Bake, ConstantColourFillsEveryTexel) {
    Vec4 red{1, 0, 0, 1};
    Asset a = twoQuads(red, red);
    BakeOptions o;
    o.size = 32;
    BakeResult r = bakeBaseColor(a, twoQuadsUV(), o);
    EXPECT_GT(r.coveredTexels, 0u);
    EXPECT_LT(r.coveredTexels, size_t(32 * 32));  // gaps existed before pull-push
    ASSERT_EQ(r.pixels.size(), size_t(32 * 32 * 3));
    for (size_t i = 0; i < 32 * 32; ++i) {
        ASSERT_NEAR(r.pixels[i * 3 + 0], 1.0, 1e-6) << "texel " << i;
        ASSERT_NEAR(r.pixels[i * 3 + 1], 0.0, 1e-6) << "texel " << i;
        ASSERT_NEAR(r.pixels[i * 3 + 2], 0.0, 1e-6) << "texel " << i;
    }
    ASSERT_GT(r.image.encoded.size(), 8u);
    EXPECT_EQ(r.image.encoded[1], 'P');  // PNG signature
    EXPECT_EQ(r.image.width, 32);
}

TEST(Bake, TwoMaterialsReproducePerRegion) {
    Asset a = twoQuads({1, 0, 0, 1}, {0, 1, 0, 1});
    BakeOptions o;
    o.size = 40;
    BakeResult r = bakeBaseColor(a, twoQuadsUV(), o);
    auto px = [&](int x, int y, int c) { return r.pixels[(size_t(y) * 40 + size_t(x)) * 3 + size_t(c)]; };
    // Texels well inside each chart.
    for (int y = 6; y < 34; ++y) {
        for (int x = 4; x < 15; ++x) {
            ASSERT_NEAR(px(x, y, 0), 1.0, 1e-6);
            ASSERT_NEAR(px(x, y, 1), 0.0, 1e-6);
        }
        for (int x = 26; x < 37; ++x) {
            ASSERT_NEAR(px(x, y, 0), 0.0, 1e-6);
            ASSERT_NEAR(px(x, y, 1), 1.0, 1e-6);
        }
    }
}

TEST(Bake, RegionBakeMatchesTheFullGridOnCoveredTexels) {
    // A 40 x 24 region of the 40 x 40 grid: the rows of the charts it holds are shaded exactly as in
    // the full bake; the gaps are filled from the region alone, and no PNG is made without encodePng.
    Asset a = twoQuads({1, 0, 0, 1}, {0, 1, 0, 1});
    a.mesh.wedges.color.resize(6);
    for (size_t v = 0; v < 6; ++v) a.mesh.wedges.color[v] = Vec4{0.2 + 0.1 * double(v), 0.5, 1 - 0.1 * double(v), 1};
    BakeOptions full;
    full.size = 40;
    full.fillGaps = false;
    BakeOptions region = full;
    region.height = 24;
    region.encodePng = false;
    BakeResult f = bakeBaseColor(a, twoQuadsUV(), full);
    BakeResult r = bakeBaseColor(a, twoQuadsUV(), region);
    ASSERT_EQ(r.pixels.size(), size_t(40 * 24 * 3));
    EXPECT_TRUE(r.image.encoded.empty());
    EXPECT_GT(r.coveredTexels, 0u);
    EXPECT_LT(r.coveredTexels, f.coveredTexels);
    for (size_t i = 0; i < r.pixels.size(); ++i) ASSERT_EQ(r.pixels[i], f.pixels[i]) << "value " << i;
    BakeOptions tooWide = full;
    tooWide.width = 41;
    EXPECT_THROW(bakeBaseColor(a, twoQuadsUV(), tooWide), InvalidInput);
}

TEST(Bake, SameTexelsForAnyThreadCount) {
    Asset a = twoQuads({1, 0.5, 0, 1}, {0, 1, 0.25, 1});
    a.mesh.wedges.color.resize(6);
    for (size_t v = 0; v < 6; ++v) a.mesh.wedges.color[v] = Vec4{1 - 0.15 * double(v), 0.3 + 0.1 * double(v), 0.7, 1};
    BakeOptions o;
    o.size = 64;
    o.width = 60;
    BakeResult one = bakeBaseColor(a, twoQuadsUV(), o);
    o.threads = 3;
    BakeResult three = bakeBaseColor(a, twoQuadsUV(), o);
    EXPECT_EQ(one.pixels, three.pixels);
    EXPECT_EQ(one.image.encoded, three.image.encoded);
    EXPECT_EQ(one.image.width, 60);
    EXPECT_EQ(one.coveredTexels, three.coveredTexels);
}

TEST(Bake, SharedSourcesBakeLikeOneOffBakes) {
    Asset a = twoQuads({1, 0.5, 0, 1}, {0, 1, 0.25, 1});
    const BakeSources sources(a);
    EXPECT_EQ(&sources.asset(), &a);
    for (int size : {24, 40}) {
        BakeOptions o;
        o.size = size;
        BakeResult shared = bakeBaseColor(sources, twoQuadsUV(), o);
        BakeResult alone = bakeBaseColor(a, twoQuadsUV(), o);
        EXPECT_EQ(shared.pixels, alone.pixels);
        EXPECT_EQ(shared.image.encoded, alone.image.encoded);
    }
}

TEST(Bake, VertexColoursBake) {
    Asset a = twoQuads({1, 1, 1, 1}, {1, 1, 1, 1});
    a.mesh.wedges.color.assign(6, Vec4{0, 0, 1, 1});
    BakeOptions o;
    o.size = 16;
    BakeResult r = bakeBaseColor(a, twoQuadsUV(), o);
    for (size_t i = 0; i < 16 * 16; ++i) ASSERT_NEAR(r.pixels[i * 3 + 2], 1.0, 1e-6);
    EXPECT_NEAR(r.pixels[0], 0.0, 1e-6);
}

TEST(Bake, IslandSamplesTheClosestSurfacePoint) {
    // A triangle floating 0.3 above the right (green) quad, given its own UV island in the gap
    // between the two charts: its texels show the closest original point, i.e. green.
    Asset a = twoQuads({1, 0, 0, 1}, {0, 1, 0, 1});
    BakeOptions o;
    o.size = 40;
    o.fillGaps = false;
    BakeIsland isl;
    isl.position = {Vec3{1.2, 0.2, 0.3}, Vec3{1.8, 0.2, 0.3}, Vec3{1.5, 0.8, 0.3}};
    isl.uv = {Vec2{0.43, 0.8}, Vec2{0.57, 0.8}, Vec2{0.5, 0.2}};
    isl.faces = {0, 1, 2, 3};
    BakeResult r = bakeBaseColor(a, twoQuadsUV(), o, {isl});
    EXPECT_GT(r.islandTexels, 10u);
    auto px = [&](int x, int y, int c) { return r.pixels[(size_t(y) * 40 + size_t(x)) * 3 + size_t(c)]; };
    for (int y = 16; y < 28; ++y) {
        ASSERT_NEAR(px(20, y, 0), 0.0, 1e-6) << y;
        ASSERT_NEAR(px(20, y, 1), 1.0, 1e-6) << y;
    }
    BakeIsland none = isl;
    none.faces.clear();
    EXPECT_THROW(bakeBaseColor(a, twoQuadsUV(), o, {none}), InvalidInput);
}

// A thin wall seen edge-on (the page's texels come from islands only, as a projected level's):
//   z = 0.1  ------ outer sheet, facing +z, green
//   z = 0.03 ------ island facing +z  (nearer the inner sheet, reads the outer one)
//   z = 0.07 ------ island facing -z  (nearer the outer sheet, reads the inner one)
//   z = 0    ------ inner sheet, facing -z, red
// An island reads the nearest face that faces its way, not the nearest face.
TEST(Bake, IslandReadsTheSheetFacingItsWay) {
    Asset a;
    TriMesh& m = a.mesh;
    m.positions = {{0, 0, 0.1}, {1, 0, 0.1}, {1, 1, 0.1}, {0, 1, 0.1}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 6, 5}, {4, 7, 6}};
    m.cornerWedges = m.triangles;
    m.wedges.vertex = {0, 1, 2, 3, 4, 5, 6, 7};
    m.triangleMaterial = {0, 0, 1, 1};
    Material outer, inner;
    outer.baseColorFactor = {0, 1, 0, 1};
    inner.baseColorFactor = {1, 0, 0, 1};
    a.materials = {outer, inner};
    const std::vector<std::array<Vec2, 3>> offPage(4, {Vec2{-10, -10}, Vec2{-10, -10}, Vec2{-10, -10}});
    BakeOptions o;
    o.size = 40;
    o.fillGaps = false;
    BakeIsland up, down;
    up.position = {Vec3{0.2, 0.2, 0.03}, Vec3{0.8, 0.2, 0.03}, Vec3{0.5, 0.8, 0.03}};
    up.uv = {Vec2{0.05, 0.8}, Vec2{0.45, 0.8}, Vec2{0.25, 0.2}};
    down.position = {Vec3{0.2, 0.2, 0.07}, Vec3{0.5, 0.8, 0.07}, Vec3{0.8, 0.2, 0.07}};
    down.uv = {Vec2{0.55, 0.8}, Vec2{0.75, 0.2}, Vec2{0.95, 0.8}};
    up.faces = down.faces = {0, 1, 2, 3};
    BakeResult r = bakeBaseColor(a, offPage, o, {up, down});
    EXPECT_GT(r.islandTexels, 20u);
    auto px = [&](int x, int y, int c) { return r.pixels[(size_t(y) * 40 + size_t(x)) * 3 + size_t(c)]; };
    for (int y = 16; y < 28; ++y) {
        EXPECT_NEAR(px(10, y, 0), 0.0, 1e-6) << y;  // up: green
        EXPECT_NEAR(px(10, y, 1), 1.0, 1e-6) << y;
        EXPECT_NEAR(px(30, y, 0), 1.0, 1e-6) << y;  // down: red
        EXPECT_NEAR(px(30, y, 1), 0.0, 1e-6) << y;
    }
}

// A 21 x 21 vertex grid (z = 0) in two charts (left and right halves, 800 faces in all) and two
// layout islands: a small one across the chart border and one spanning the grid. An island's
// faces are only those near it, yet the bake's closest-point faces (facesNearTriangle) are the
// same as over every face of the charts holding its corners, in the same order.
TEST(Bake, LayoutIslandFacesAreTheNearOnesOfTheirCharts) {
    TriMesh m;
    auto v = [](int x, int y) { return uint32_t(y * 21 + x); };
    for (int y = 0; y <= 20; ++y)
        for (int x = 0; x <= 20; ++x) m.positions.push_back({0.1 * x, 0.1 * y, 0});
    ChartLayout layout;
    layout.chartCount = 2;
    for (int y = 0; y < 20; ++y)
        for (int x = 0; x < 20; ++x) {
            m.triangles.push_back({v(x, y), v(x + 1, y), v(x + 1, y + 1)});
            m.triangles.push_back({v(x, y), v(x + 1, y + 1), v(x, y + 1)});
            layout.faceChart.insert(layout.faceChart.end(), 2, x < 10 ? 0u : 1u);
        }
    layout.cornerUV.assign(m.triangles.size(), {Vec2{0, 0}, Vec2{1, 0}, Vec2{0, 1}});
    LayoutIsland small, large;
    small.vertices = {v(9, 5), v(11, 5), v(10, 7)};
    large.vertices = {v(0, 0), v(20, 0), v(10, 20)};
    layout.islands = {small, large};
    std::vector<BakeIsland> islands = layoutBakeIslands(m, layout);
    ASSERT_EQ(islands.size(), 2u);
    EXPECT_LT(islands[0].faces.size(), 400u);  // of the 800 faces of its two charts
    for (const BakeIsland& isl : islands) {
        std::vector<uint32_t> all(m.triangles.size());
        for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
        std::stable_sort(all.begin(), all.end(), [&](uint32_t a, uint32_t b) { return layout.faceChart[a] < layout.faceChart[b]; });
        EXPECT_EQ(facesNearTriangle(m, isl.faces, isl.position), facesNearTriangle(m, all, isl.position));
    }
}

// projectedIslandNear and nearFaces find around the island what the bake keeps of every face in
// the box:
// facesNearTriangle of the faces facing the island's way (cosine above -0.8), all of them when
// none does. A thin wall (a sphere inside a slightly larger one, wound inward) puts faces facing
// both ways near every island; boxes from the island's own to the whole model, degenerate islands
// (no normal: every face kept) and boxes that hold no face at all.
TEST(ProjectedIslandNear, SameFacesAndClosestPointsAsTheBakesFilterOfTheWholeBox) {
    TriMesh mesh = test::sphere(4);
    TriMesh inner = test::sphere(4);
    for (Tri& t : inner.triangles) std::swap(t[1], t[2]);
    test::append(mesh, inner, 0.97, {0, 0, 0});
    test::append(mesh, test::sphere(4), 1.0, {0, 0, 0});  // coincident copies of the outer sheet
    const FaceGrid grid(mesh);
    auto expected = [&](const std::array<Vec3, 3>& tri, Vec3 lo, Vec3 hi) {
        const std::vector<uint32_t> box = grid.facesIn(lo, hi);
        const Vec3 n = cross(tri[1] - tri[0], tri[2] - tri[0]);
        std::vector<uint32_t> facing;
        for (uint32_t f : box) {
            const Tri& t = mesh.triangles[f];
            const Vec3 nf = cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]);
            if (dot(nf, n) > -0.8 * length(nf) * length(n)) facing.push_back(f);
        }
        return facesNearTriangle(mesh, facing.empty() ? box : facing, tri);
    };
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 1), radius(0.9, 1.05), size(0.001, 0.3);
    int checked = 0;
    for (int i = 0; i < 300; ++i) {
        const Vec3 centre = normalize(Vec3{u(rng), u(rng), u(rng)}) * radius(rng);
        const double s = size(rng);
        std::array<Vec3, 3> tri;
        for (Vec3& p : tri) p = centre + Vec3{u(rng), u(rng), u(rng)} * s;
        if (i % 10 == 0) tri[2] = (tri[0] + tri[1]) * 0.5;  // degenerate: no normal
        if (i % 7 == 0) std::swap(tri[1], tri[2]);           // facing inward
        Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
        for (const Vec3& p : tri)
            for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
        const double reach = (i % 3 == 0 ? 0.0 : i % 3 == 1 ? 0.05 : 2.0) + (i % 50 == 0 ? 10.0 : 0.0);
        lo = lo - Vec3{reach, reach, reach};
        hi = hi + Vec3{reach, reach, reach};
        if (i % 25 == 0) lo = hi = Vec3{5, 5, 5};  // a box beside the model: no face
        const std::vector<uint32_t> want = expected(tri, lo, hi);
        IslandNear near;
        ASSERT_EQ(projectedIslandNear(mesh, grid, tri, lo, hi, near), !want.empty()) << "island " << i;
        if (want.empty()) continue;
        const std::vector<uint32_t> listed = nearFaces(mesh, near, tri);
        EXPECT_EQ(listed, want) << "island " << i;
        ++checked;
        // Each point of the triangle and just beyond its edges (a dilated texel) finds the face and
        // barycentrics a scan of the list finds, ties (shared edges, the copies) included.
        const BoxedFaces boxed(mesh, listed);
        const Vec3 n = cross(tri[1] - tri[0], tri[2] - tri[0]);
        std::uniform_real_distribution<double> w(-0.1, 1.1);
        for (int k = 0; k < 20; ++k) {
            const double a = w(rng), b = w(rng) * (1 - a);
            const Vec3 X = k == 0 ? mesh.positions[mesh.triangles[listed[0]][0]] : tri[0] * a + tri[1] * b + tri[2] * (1 - a - b);
            uint32_t wantFace = 0, face = 0;
            std::array<double, 3> wantBary{}, bary{};
            boxed.closest(X, ~0u, wantFace, wantBary);
            ASSERT_LT(bake_detail::closestNearFace(mesh, near, n, X, k % 2 ? 1e-6 : 0.05, face, bary), 1e300);
            EXPECT_EQ(face, wantFace) << "island " << i << " point " << k;
            EXPECT_EQ(bary, wantBary);
        }
    }
    EXPECT_GT(checked, 200);
}

TEST(TexelRaster, WideDilationKeepsEachTexelsNearestFace) {
    // Thousands of sub-texel faces (a dense LOD0) and a few large ones, at a dilation of many
    // texels: every texel keeps what the plain rule gives, the first face at the least distance.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1), small(-0.004, 0.004);
    TriMesh mesh;
    std::vector<std::array<Vec2, 3>> uv;
    for (int i = 0; i < 6000; ++i) {
        const Vec2 c{0.2 + 0.5 * u(rng), 0.15 + 0.6 * u(rng)};
        uv.push_back({c, Vec2{c.x + small(rng), c.y + small(rng)}, Vec2{c.x + small(rng), c.y + small(rng)}});
    }
    for (int i = 0; i < 12; ++i) uv.push_back({Vec2{u(rng), u(rng)}, Vec2{u(rng), u(rng)}, Vec2{u(rng), u(rng)}});
    uv.push_back(uv[5]);  // a copy ties its original everywhere
    mesh.triangles.assign(uv.size(), Tri{0, 1, 2});
    const bake_detail::TexelRegion g{200, 190, 150};
    for (double dilation : {1.0, 7.0}) {
        std::vector<bake_detail::TexelHit> want(size_t(g.w) * size_t(g.h)), got;
        for (uint32_t f = 0; f < uv.size(); ++f) {
            Vec2 P[3];
            for (int k = 0; k < 3; ++k) P[k] = uv[f][size_t(k)] * double(g.size);
            if (std::fabs(cross(P[1] - P[0], P[2] - P[0])) < 1e-12) continue;
            bake_detail::forEachTexelNear(P, g, dilation, [&](int x, int y, double d, const std::array<double, 3>& b) {
                if (float(d) < want[g.at(x, y)].dist) want[g.at(x, y)] = {int32_t(f), float(d), {float(b[0]), float(b[1]), float(b[2])}};
            });
        }
        bake_detail::rasterizeTriangles(mesh, uv, g, dilation, 2, got);
        size_t hit = 0;
        for (size_t i = 0; i < want.size(); ++i) {
            ASSERT_EQ(got[i].face, want[i].face) << "dilation " << dilation << " texel " << i;
            ASSERT_EQ(got[i].dist, want[i].dist);
            ASSERT_EQ(got[i].bary, want[i].bary);
            hit += want[i].face >= 0;
        }
        EXPECT_GT(hit, size_t(g.w) * size_t(g.h) / 2);
    }
}
