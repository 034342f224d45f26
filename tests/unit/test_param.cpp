// Unit tests for charts, chart UV maps (Tutte, Ceres energy) and parameterize(). The bake:
// test_bake.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "lodbake/atlas/atlas_apply.h"
#include "lodbake/core/errors.h"
#include "lodbake/param/chart_uv.h"
#include "lodbake/chart/charts.h"
#include "lodbake/param/parameterize.h"
#include "lodbake/core/closest_point.h"
#include "param/uv_check_detail.h"
#include "synthetic_meshes.h"

using namespace lodbake;

namespace {

// Lat-long sphere patch: pole vertex 0 at +z, `rings` rings down to polar angle maxTheta, `seg`
// segments per ring; maxTheta = pi/2 gives a hemisphere (a disk), with `closed` a full sphere.
TriMesh latLong(int rings, int seg, bool closed) {
    TriMesh m;
    m.positions.push_back({0, 0, 1});
    double maxTheta = closed ? kPi : kPi / 2;
    int ringCount = closed ? rings - 1 : rings;
    for (int r = 1; r <= ringCount; ++r) {
        double th = maxTheta * r / rings;
        for (int s = 0; s < seg; ++s) {
            double ph = 2 * kPi * s / seg;
            m.positions.push_back({std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)});
        }
    }
    auto ring = [&](int r, int s) { return uint32_t(1 + (r - 1) * seg + (s % seg)); };
    for (int s = 0; s < seg; ++s) m.triangles.push_back({0, ring(1, s), ring(1, s + 1)});
    for (int r = 1; r < ringCount; ++r)
        for (int s = 0; s < seg; ++s) {
            m.triangles.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
            m.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
        }
    if (closed) {
        uint32_t south = uint32_t(m.positions.size());
        m.positions.push_back({0, 0, -1});
        for (int s = 0; s < seg; ++s) m.triangles.push_back({ring(ringCount, s), south, ring(ringCount, s + 1)});
    }
    m.cornerWedges = m.triangles;
    m.wedges.vertex.resize(m.positions.size());
    for (uint32_t i = 0; i < m.positions.size(); ++i) m.wedges.vertex[i] = i;
    m.triangleMaterial.assign(m.triangles.size(), 0);
    return m;
}

ChartMesh asChart(const TriMesh& m) { return {m.positions, m.triangles, {}}; }

// A start map's contract: no flipped triangle, no crossing boundary edges, total UV area = 3D area.
void expectInjectiveAndAreaMatched(const ChartMesh& c, const std::vector<Vec2>& uv) {
    ASSERT_EQ(uv.size(), c.positions.size());
    EXPECT_EQ(countFlips(c, uv), 0u);
    EXPECT_EQ(countOverlaps(c, uv), 0u);
    double a2 = 0, a3 = 0;
    for (const Tri& t : c.triangles) {
        a2 += 0.5 * cross(uv[t[1]] - uv[t[0]], uv[t[2]] - uv[t[0]]);
        a3 += 0.5 * length(cross(c.positions[t[1]] - c.positions[t[0]], c.positions[t[2]] - c.positions[t[0]]));
    }
    EXPECT_NEAR(a2, a3, 1e-9 * a3);
}

}  // namespace

//      pole
//     /|\      hemisphere: 6 rings x 16 segments, boundary = equator (one loop)
//    /_|_\   .
TEST(ParamTutte, HemisphereHasNoFlipsOrOverlaps) {
    ChartMesh c = asChart(latLong(6, 16, false));
    expectInjectiveAndAreaMatched(c, tutteEmbedding(c));
}

TEST(ParamTutte, ClosedSphereIsRejected) {
    ChartMesh c = asChart(latLong(6, 8, true));
    EXPECT_THROW(tutteEmbedding(c), Error);
}

// A flat, developable chart: a 6 x 4 grid of unit squares bent 90 degrees along x = 3 (an L
// folded like a book). Tutte puts its boundary on a circle; LSCM unfolds it exactly.
//   +--+--+--+   (z up)
//   |  |  |  |
//   +--+--+--+--+--+--+  (y = 0 plane)
ChartMesh bentGrid(int nx = 6, int ny = 4) {
    ChartMesh c;
    const int fold = nx / 2;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i)
            c.positions.push_back(i <= fold ? Vec3{double(i), double(j), 0} : Vec3{double(fold), double(j), double(i - fold)});
    auto id = [&](int i, int j) { return uint32_t(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            c.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            c.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    return c;
}

// Every edge keeps its 3D length (the unfolding is an isometry; area matching keeps the scale).
void expectEdgeLengthsKept(const ChartMesh& c, const std::vector<Vec2>& uv) {
    for (const Tri& t : c.triangles)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = t[k], b = t[(k + 1) % 3];
            ASSERT_NEAR(std::sqrt(dot(uv[a] - uv[b], uv[a] - uv[b])), length(c.positions[a] - c.positions[b]), 1e-6);
        }
}

TEST(ParamLscm, DevelopableChartUnfoldsIsometrically) {
    ChartMesh c = bentGrid();
    std::vector<Vec2> uv = lscmEmbedding(c);
    expectInjectiveAndAreaMatched(c, uv);
    expectEdgeLengthsKept(c, uv);
    // So E_pixel is zero up to rounding, far below the Tutte start's.
    ChartEnergyOptions o;
    o.beta = 1;
    EXPECT_LT(chartEnergy(c, {}, uv, o).E, 1e-9);
    EXPECT_GT(chartEnergy(c, {}, tutteEmbedding(c), o).E, 1.0);
}

// A chart of 11,011 vertices: above the size from which the supernodal factorisation solves it.
TEST(ParamLscm, LargeDevelopableChartUnfoldsIsometrically) {
    ChartMesh c = bentGrid(120, 90);
    ASSERT_GT(2 * (c.positions.size() - 2), 20000u);
    std::vector<Vec2> uv = lscmEmbedding(c);
    expectInjectiveAndAreaMatched(c, uv);
    expectEdgeLengthsKept(c, uv);
}

TEST(ParamLscm, HemisphereIsInjectiveAndAreaMatched) {
    ChartMesh c = asChart(latLong(6, 16, false));
    expectInjectiveAndAreaMatched(c, lscmEmbedding(c));
    EXPECT_THROW(lscmEmbedding(asChart(latLong(6, 8, true))), Error);
}

TEST(ParamCeres, HemisphereLowersEnergyWithoutFolding) {
    ChartMesh c = asChart(latLong(6, 16, false));
    // Pairs: every second ring-2 vertex paired with the ring-1/ring-3 triangle around it, as a
    // simplification would (bary mid-way), deviation 0.05.
    std::vector<ChartPair> pairs;
    for (uint32_t s = 0; s < 16; s += 2) {
        ChartPair p;
        p.vertex = 1 + 16 + s;
        p.coarse = {1 + s, 1 + 32 + s, 1 + 32 + (s + 1) % 16};
        p.bary = {0.5, 0.25, 0.25};
        p.deviation = 0.05;
        pairs.push_back(p);
    }
    std::vector<Vec2> tutte = tutteEmbedding(c);
    ChartSolveOptions o;
    ChartSolveResult r = optimizeChartUV(c, pairs, tutte, o);
    EXPECT_TRUE(r.improved);
    EXPECT_LT(r.after.E, r.before.E);
    EXPECT_GT(r.iterations, 0);
    EXPECT_EQ(countFlips(c, r.uv), 0u);
    EXPECT_EQ(countOverlaps(c, r.uv), 0u);
    ChartEnergy e = chartEnergy(c, pairs, r.uv, o.energy);
    EXPECT_NEAR(e.E, r.after.E, 1e-12 + 1e-9 * e.E);
    EXPECT_NEAR(e.E, o.energy.beta * e.pixel + (1 - o.energy.beta) * e.poly, 1e-9 * (1 + e.E));
}

// A level triangle without 3D area (a level's collinear corners) that starts flipped must not
// stop the solve: its penalty, relative to that area, would be infinite at the start and Ceres
// would end before its first step. It has nothing to be pulled towards and is left out.
TEST(ParamCeres, FlippedLevelTriangleWithoutAreaDoesNotStopTheSolve) {
    ChartMesh c = asChart(latLong(6, 16, false));
    std::vector<Vec2> tutte = tutteEmbedding(c);
    const Tri& t = c.triangles[20];
    ASSERT_GT(cross(tutte[t[1]] - tutte[t[0]], tutte[t[2]] - tutte[t[0]]), 0);
    ChartLevelTriangle lt;
    lt.corner[0].vertex = {t[0], t[0], t[0]};
    lt.corner[1].vertex = {t[2], t[2], t[2]};  // reversed: flipped in the start map
    lt.corner[2].vertex = {t[1], t[1], t[1]};
    lt.area2 = 0;
    lt.level = 1;
    c.levelTriangles.push_back(lt);
    ChartSolveResult r = optimizeChartUV(c, {}, tutte, ChartSolveOptions{});
    EXPECT_GT(r.iterations, 1);
    EXPECT_TRUE(r.improved);
    EXPECT_LT(r.after.E, r.before.E);
    EXPECT_EQ(countFlips(c, r.uv), 0u);
}

TEST(ParamCharts, ClosedSphereGivesAtLeastTwoDiskCharts) {
    TriMesh m = latLong(8, 12, true);
    ChartResult r = buildCharts(m, {}, {});  // every face its own base region
    ASSERT_EQ(r.faceChart.size(), m.triangleCount());
    EXPECT_GE(r.chartCount, 2u);
    EXPECT_LT(r.chartCount, m.triangleCount());  // merging happened
    std::vector<std::vector<uint32_t>> faces(r.chartCount);
    for (uint32_t f = 0; f < m.triangleCount(); ++f) {
        ASSERT_GE(r.faceChart[f], 0);
        faces[size_t(r.faceChart[f])].push_back(f);
    }
    for (const auto& fs : faces) EXPECT_TRUE(isDisk(m, fs));
    // The whole sphere is not a disk; the hemisphere is.
    std::vector<uint32_t> all(m.triangleCount());
    for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
    EXPECT_FALSE(isDisk(m, all));
    TriMesh h = latLong(4, 8, false);
    std::vector<uint32_t> hall(h.triangleCount());
    for (uint32_t f = 0; f < hall.size(); ++f) hall[f] = f;
    EXPECT_TRUE(isDisk(h, hall));
}

TEST(ParamCharts, DiskTestRejectsPinchesRingsAndFins) {
    // A 3x3 vertex grid (8 triangles) plus a fin vertex above the middle row.
    TriMesh m;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 3; ++x) m.positions.push_back({double(x), double(y), 0});
    m.positions.push_back({1, 1, 1});  // 9
    auto v = [](int x, int y) { return uint32_t(y * 3 + x); };
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 2; ++x) {
            m.triangles.push_back({v(x, y), v(x + 1, y), v(x + 1, y + 1)});
            m.triangles.push_back({v(x, y), v(x + 1, y + 1), v(x, y + 1)});
        }
    m.triangles.push_back({v(0, 1), v(1, 1), 9});  // 8: a third face on the edge (0,1)-(1,1)
    m.triangles.push_back({v(1, 1), v(1, 1), 9});  // 9: index-degenerate
    EXPECT_TRUE(isDisk(m, {0, 1, 2, 3, 4, 5, 6, 7}));
    EXPECT_TRUE(isDisk(m, {0}));
    EXPECT_TRUE(isDisk(m, {0, 1}));
    EXPECT_FALSE(isDisk(m, {}));
    EXPECT_FALSE(isDisk(m, {0, 7}));                 // two triangles touching at one vertex
    EXPECT_FALSE(isDisk(m, {0, 5}));                 // two separate triangles
    EXPECT_FALSE(isDisk(m, {0, 1, 2, 3, 5, 6, 7}));  // face 5 hangs on by two corners only
    EXPECT_FALSE(isDisk(m, {0, 1, 2, 3, 4, 5, 6, 7, 8}));  // an edge of three faces
    EXPECT_FALSE(isDisk(m, {0, 9}));
    // A ring: an 8-segment annulus has no single boundary loop.
    TriMesh ring;
    for (int i = 0; i < 8; ++i) {
        double a = 2 * 3.14159265358979 * i / 8;
        ring.positions.push_back({std::cos(a), std::sin(a), 0});
        ring.positions.push_back({2 * std::cos(a), 2 * std::sin(a), 0});
    }
    std::vector<uint32_t> all;
    for (uint32_t i = 0; i < 8; ++i) {
        uint32_t a = 2 * i, b = 2 * i + 1, c = 2 * ((i + 1) % 8), d = c + 1;
        ring.triangles.push_back({a, b, d});
        ring.triangles.push_back({a, d, c});
        all.push_back(2 * i);
        all.push_back(2 * i + 1);
    }
    EXPECT_FALSE(isDisk(ring, all));
    all.pop_back();
    all.pop_back();
    EXPECT_TRUE(isDisk(ring, all));  // the annulus cut open along one segment
}

TEST(ParamCharts, NonDiskRegionIsSplit) {
    // One base region holding the whole closed sphere must be split into disks.
    TriMesh m = latLong(6, 8, true);
    std::vector<uint32_t> region(m.triangleCount(), 0);
    ChartResult r = buildCharts(m, region, {});
    EXPECT_EQ(r.splitRegions, 1u);
    EXPECT_GE(r.chartCount, 2u);
}

TEST(ParamPipeline, SphereAtlasIsInjectiveAndInsideTheUnitSquare) {
    TriMesh m = latLong(8, 12, true);
    Multires mr;  // no levels: every face starts as its own region
    ParameterizeOptions o;
    o.textureSize = 256;
    ParameterizeResult r = parameterize(m, mr, o);
    EXPECT_GE(r.charts.chartCount, 2u);
    EXPECT_EQ(r.flips, 0u);
    EXPECT_EQ(r.overlaps, 0u);
    EXPECT_LE(r.finalTotal.E, r.initialTotal.E + 1e-12);
    ASSERT_EQ(r.cornerUV.size(), m.triangleCount());
    for (const auto& c : r.cornerUV)
        for (const Vec2& p : c) {
            EXPECT_GT(p.x, 0);
            EXPECT_LT(p.x, 1);
            EXPECT_GT(p.y, 0);
            EXPECT_LT(p.y, 1);
        }
    uint32_t histogramTotal = 0;
    for (uint32_t b : r.areaRatioHistogram) histogramTotal += b;
    EXPECT_EQ(histogramTotal, m.triangleCount());
    EXPECT_GE(r.stretchL2, 1.0 - 1e-9);
}

namespace {

// A flat 5 x 5 vertex grid (z = 0, normal +z) as the original mesh, one base region, and one
// level of hand-made triangles over original vertices: A (large) contains B (overlap), C is
// apart, D is clockwise (flipped in any orientation-preserving chart map).
struct FoldedLevel {
    TriMesh mesh;
    Multires mr;
};

FoldedLevel foldedLevel() {
    FoldedLevel r;
    TriMesh& m = r.mesh;
    auto v = [](int x, int y) { return uint32_t(y * 5 + x); };
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 5; ++x) m.positions.push_back({double(x), double(y), 0});
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x) {
            m.triangles.push_back({v(x, y), v(x + 1, y), v(x + 1, y + 1)});
            m.triangles.push_back({v(x, y), v(x + 1, y + 1), v(x, y + 1)});
        }
    m.cornerWedges = m.triangles;
    m.wedges.vertex.resize(m.positions.size());
    for (uint32_t i = 0; i < m.positions.size(); ++i) m.wedges.vertex[i] = i;
    m.triangleMaterial.assign(m.triangles.size(), 0);
    Level L;
    L.triangles = {{v(0, 0), v(4, 0), v(0, 4)},   // A
                   {v(1, 1), v(3, 1), v(1, 3)},   // B, inside A
                   {v(4, 4), v(2, 4), v(4, 2)},   // C
                   {v(3, 4), v(4, 4), v(4, 3)}};  // D, clockwise
    L.faces = {0, 10, 31, 30};
    L.cornerWedges = L.triangles;
    L.faceRegion.assign(m.triangleCount(), 0);
    L.regionCount = 1;
    r.mr.levels.push_back(L);
    return r;
}

}  // namespace

TEST(ParamIslands, FoldedLevelTrianglesGetIslandsAndEveryLevelIsInjective) {
    FoldedLevel fl = foldedLevel();
    ParameterizeOptions o;
    o.textureSize = 128;
    o.levelIslands = false;
    ParameterizeResult folded = parameterize(fl.mesh, fl.mr, o);
    ASSERT_EQ(folded.levels.size(), 1u);
    UVInjectivity before = checkUVInjectivity(folded.levels[0].uv);
    EXPECT_EQ(before.flips, 1u);     // D
    EXPECT_EQ(before.overlaps, 2u);  // A and B
    EXPECT_TRUE(folded.islands.empty());

    o.levelIslands = true;
    ParameterizeResult r = parameterize(fl.mesh, fl.mr, o);
    ASSERT_EQ(r.islands.size(), 2u);  // D, and the smaller of the overlapping pair (B)
    EXPECT_EQ(r.levels[0].islands, 2u);
    UVInjectivity after = checkUVInjectivity(r.levels[0].uv);
    EXPECT_EQ(after.flips, 0u);
    EXPECT_EQ(after.overlaps, 0u);
    // Islands are inside the atlas and keep texels (at 128 texels, >= ~2 texels high).
    for (const LevelIsland& isl : r.islands) {
        EXPECT_FALSE(isl.faces.empty());
        for (const Vec2& p : isl.uv) {
            EXPECT_GT(p.x, 0);
            EXPECT_LT(p.x, 1);
            EXPECT_GT(p.y, 0);
            EXPECT_LT(p.y, 1);
        }
        Vec2 a{isl.uv[0].x, -isl.uv[0].y}, b{isl.uv[1].x, -isl.uv[1].y}, c{isl.uv[2].x, -isl.uv[2].y};
        EXPECT_GT(0.5 * cross(b - a, c - a) * 128 * 128, 1.0);
    }
    // Written into the asset: the level's wedges carry exactly these injective UVs, and the
    // texture deviation of an island triangle is its distance to the surface (0 here: flat).
    Asset asset;
    asset.mesh = fl.mesh;
    Multires mr = fl.mr;
    Image img;
    AtlasApplyStats st = applyAtlas(asset, mr, r, img);
    EXPECT_EQ(st.islandTriangles, 2u);
    UVInjectivity written = checkLevelUVs(asset.mesh, mr.levels[0].triangles, mr.levels[0].cornerWedges);
    EXPECT_EQ(written.flips + written.overlaps, 0u);
    // The island triangles alone (B and D): every sample is measured on an island.
    Level islandsOnly;
    for (size_t t : {size_t(1), size_t(3)}) {
        islandsOnly.triangles.push_back(mr.levels[0].triangles[t]);
        islandsOnly.faces.push_back(mr.levels[0].faces[t]);
        islandsOnly.cornerWedges.push_back(mr.levels[0].cornerWedges[t]);
    }
    TextureDeviationOptions dopt;
    dopt.samples = 2000;
    dopt.islands = &r.islands;
    TextureDeviation dev = textureDeviation(asset.mesh, islandsOnly, mr.charts, dopt);
    EXPECT_EQ(dev.islandSamples, dev.samples);
    EXPECT_GT(dev.samples, 1000u);
    EXPECT_EQ(dev.outside, 0u);
    EXPECT_LT(dev.maxRelative, 1e-9);
    // The whole level, on three threads: the same figures as on one.
    dopt.threads = 1;
    TextureDeviation one = textureDeviation(asset.mesh, mr.levels[0], mr.charts, dopt);
    dopt.threads = 3;
    TextureDeviation three = textureDeviation(asset.mesh, mr.levels[0], mr.charts, dopt);
    EXPECT_GT(one.samples, one.islandSamples);  // chart samples too
    EXPECT_EQ(one.samples, three.samples);
    EXPECT_EQ(one.islandSamples, three.islandSamples);
    EXPECT_EQ(one.outside, three.outside);
    EXPECT_EQ(one.mean, three.mean);
    EXPECT_EQ(one.rms, three.rms);
    EXPECT_EQ(one.max, three.max);
}

// Island samples are queried out of sequence order (so each query starts near the previous
// answer): the figures must still be the exact closest distances summed in sequence order.
TEST(TextureDeviation, IslandSamplesAreExactClosestDistancesInSequenceOrder) {
    TriMesh mesh;
    const int n = 12;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double u = double(x) / (n - 1), v = double(y) / (n - 1);
            mesh.positions.push_back({u, v, 0.1 * std::sin(3 * u) * std::cos(2 * v)});
        }
    for (uint32_t y = 0; y + 1 < n; ++y)
        for (uint32_t x = 0; x + 1 < n; ++x) {
            const uint32_t a = y * n + x, b = a + 1, c = a + n, d = c + 1;
            mesh.triangles.push_back({a, b, d});
            mesh.triangles.push_back({a, d, c});
        }
    const size_t nf = mesh.triangleCount();
    mesh.cornerWedges.assign(nf, Tri{0, 0, 0});
    // One coarse triangle over the whole grid, laid out as an island over every face.
    Level level;
    level.triangles = {Tri{0, n - 1, n * n - 1}};
    level.faces = {0};
    level.cornerWedges = {Tri{0, 0, 0}};
    ChartLayout layout;
    layout.chartCount = 1;
    layout.faceChart.assign(nf, 0);
    layout.cornerUV.assign(nf, {Vec2{0, 0}, Vec2{1, 0}, Vec2{0, 1}});
    std::vector<LevelIsland> islands(1);
    islands[0].vertices = level.triangles[0];
    islands[0].uv = {Vec2{0.1, 0.9}, Vec2{0.9, 0.9}, Vec2{0.9, 0.1}};
    for (uint32_t f = 0; f < nf; ++f) islands[0].faces.push_back(f);
    TextureDeviationOptions dopt;
    dopt.samples = 3000;
    dopt.islands = &islands;
    const TextureDeviation dev = textureDeviation(mesh, level, layout, dopt);
    ASSERT_EQ(dev.samples, 3000u);
    EXPECT_EQ(dev.islandSamples, dev.samples);
    // The reference: every sample in sequence order (R2 points warped onto the triangle), its
    // distance to the closest face by a linear scan.
    const Tri& v = level.triangles[0];
    const double g1 = 1.32471795724474602596, a1 = 1 / g1, a2 = 1 / (g1 * g1);
    double sum = 0, sum2 = 0, max = 0;
    for (size_t seq = 0; seq < dopt.samples; ++seq) {
        const double r1 = std::fmod(0.5 + a1 * double(seq + 1), 1.0), r2 = std::fmod(0.5 + a2 * double(seq + 1), 1.0);
        const double sq = std::sqrt(r1);
        const std::array<double, 3> b{1 - sq, sq * (1 - r2), sq * r2};
        const Vec3 p = mesh.positions[v[0]] * b[0] + mesh.positions[v[1]] * b[1] + mesh.positions[v[2]] * b[2];
        uint32_t face = 0;
        std::array<double, 3> w{};
        const double d = std::sqrt(closestSurfacePoint(mesh, islands[0].faces, p, face, w));
        sum += d;
        sum2 += d * d;
        max = std::max(max, d);
    }
    EXPECT_GT(max, 0.01);  // the grid is curved: the samples are off the surface
    EXPECT_EQ(dev.mean, sum / 3000.0);
    EXPECT_EQ(dev.rms, std::sqrt(sum2 / 3000.0));
    EXPECT_EQ(dev.max, max);
}

TEST(UVFolds, CrowdedCellsFindThePairsEveryPairTestFinds) {
    // Most triangles crowded into a corner (a chart packed far denser than the grid's cells), the
    // rest spread out, some overlapping: the pairs are those the rule gives each pair on its own.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 1), d(-0.01, 0.01);
    std::vector<std::array<Vec2, 3>> tris;
    for (int i = 0; i < 420; ++i) {
        const Vec2 c = i < 300 ? Vec2{0.02 * u(rng), 0.02 * u(rng)} : Vec2{u(rng), u(rng)};
        const double s = i < 300 ? 0.2 : 8.0;
        std::array<Vec2, 3> t{c, Vec2{c.x + s * std::fabs(d(rng)), c.y + s * d(rng)}, Vec2{c.x + s * d(rng), c.y + s * std::fabs(d(rng))}};
        if (cross(t[1] - t[0], t[2] - t[0]) > 0) std::swap(t[1], t[2]);  // glTF UVs: v down
        tris.push_back(t);
    }
    const param_detail::UVFolds all = param_detail::findUVFolds(tris, 1e-7);
    std::vector<std::pair<uint32_t, uint32_t>> want;
    for (uint32_t i = 0; i < tris.size(); ++i)
        for (uint32_t j = i + 1; j < tris.size(); ++j)
            if (!all.flipped[i] && !all.flipped[j] && !param_detail::findUVFolds({tris[i], tris[j]}, 1e-7).overlapping.empty())
                want.push_back({i, j});
    EXPECT_GT(want.size(), 100u);
    std::vector<std::pair<uint32_t, uint32_t>> got(all.overlapping.begin(), all.overlapping.end());
    EXPECT_EQ(got, want);
    EXPECT_EQ(param_detail::findUVFolds(tris, 1e-7, 3).overlapping, all.overlapping);
}
