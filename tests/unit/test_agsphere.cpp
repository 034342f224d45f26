// M-AGSphere (agsphere-build): sphere cells, regions, polygon triangulation, levels.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <queue>
#include <set>

#include "lodbake/agsphere/agsphere.h"
#include "lodbake/agsphere/polygon.h"
#include "synthetic_meshes.h"

using namespace lodbake;

namespace {

// Closed cube [-1,1]^3 whose six sides are n x n grids, welded, CCW seen from outside.
TriMesh cube(int n) {
    TriMesh m;
    std::map<std::array<long, 3>, uint32_t> ids;
    auto vertex = [&](Vec3 p) {
        std::array<long, 3> key{std::lround(p.x * 1000), std::lround(p.y * 1000), std::lround(p.z * 1000)};
        auto it = ids.find(key);
        if (it != ids.end()) return it->second;
        uint32_t id = uint32_t(m.positions.size());
        m.positions.push_back(p);
        ids.emplace(key, id);
        return id;
    };
    for (int axis = 0; axis < 3; ++axis)
        for (int side = -1; side <= 1; side += 2) {
            Vec3 nrm;
            nrm[axis] = side;
            Vec3 u, v;
            u[(axis + 1) % 3] = 1;
            v[(axis + 2) % 3] = 1;
            if (side < 0) std::swap(u, v);  // keep u x v = outward normal
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    auto at = [&](int a, int b) { return vertex(nrm + u * (2.0 * a / n - 1) + v * (2.0 * b / n - 1)); };
                    uint32_t p00 = at(i, j), p10 = at(i + 1, j), p11 = at(i + 1, j + 1), p01 = at(i, j + 1);
                    m.triangles.push_back({p00, p10, p11});
                    m.triangles.push_back({p00, p11, p01});
                }
        }
    test::addDefaultWedges(m);
    return m;
}

Vec3 triNormal(const TriMesh& m, const Tri& t) {
    return cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
}

// Every directed edge at most once; with `closed`, every directed edge has its reverse.
void expectManifold(const std::vector<Tri>& tris, bool closed, const std::string& what) {
    std::map<std::pair<uint32_t, uint32_t>, int> directed;
    for (const Tri& t : tris)
        for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
    size_t repeated = 0, open = 0;
    for (const auto& [e, n] : directed) {
        if (n > 1) ++repeated;
        if (!directed.count({e.second, e.first})) ++open;
    }
    EXPECT_EQ(repeated, 0u) << what;
    if (closed) {
        EXPECT_EQ(open, 0u) << what;
    }
}

AgsphereResult build(const TriMesh& m, std::vector<AgsphereTarget> targets, std::vector<Vec3> views = {}, int depth = 4) {
    AgsphereOptions o;
    o.levels = std::move(targets);
    o.maxDepth = depth;
    o.views = std::move(views);
    return buildAgsphere(m, o);
}

double polygonArea(const PlanarPolygon& p) {
    double a = 0;
    for (const auto& loop : p.loops)
        for (size_t i = 0; i < loop.size(); ++i) a += 0.5 * cross(p.points[loop[i]], p.points[loop[(i + 1) % loop.size()]]);
    return a;
}

}  // namespace

// ---- Sphere cells ----------------------------------------------------------------------------

TEST(AgsphereCells, OctantsAndQuadtree) {
    EXPECT_EQ(sphereCellCount(0), 8u);
    EXPECT_EQ(sphereCellCount(3), 8u * 64u);
    EXPECT_EQ(sphereCell({1, 1, 1}, 0), 0u);
    EXPECT_EQ(sphereCell({-1, 1, 1}, 0), 1u);
    EXPECT_EQ(sphereCell({1, -1, 1}, 0), 2u);
    EXPECT_EQ(sphereCell({1, 1, -1}, 0), 4u);
    EXPECT_EQ(sphereCell({-1, -1, -1}, 0), 7u);
    // Directions fall inside their cell's cone at every depth; children refine parents.
    uint32_t seed = 12345;
    auto rnd = [&] {
        seed = seed * 1664525u + 1013904223u;
        return double(seed >> 8) / double(1u << 24) * 2 - 1;
    };
    for (int i = 0; i < 500; ++i) {
        Vec3 n = normalize(Vec3{rnd(), rnd(), rnd()});
        for (int d = 0; d <= 5; ++d) {
            uint32_t c = sphereCell(n, d);
            ASSERT_LT(c, sphereCellCount(d));
            if (d > 0) {
                EXPECT_EQ(c / 4, sphereCell(n, d - 1));
            }
            double angle = std::acos(std::clamp(dot(n, sphereCellCenter(c, d)), -1.0, 1.0));
            EXPECT_LE(angle, sphereCellRadius(c, d) + 1e-9);
        }
    }
    // Cells shrink with depth; the octant's radius is the angle between (1,1,1) and an axis.
    EXPECT_NEAR(sphereCellRadius(0, 0), std::acos(1 / std::sqrt(3.0)), 1e-12);
    EXPECT_LT(sphereCellRadius(sphereCell({1, 2, 3}, 4), 4), 0.1);
}

TEST(AgsphereCells, EveryCellHasThreeSymmetricNeighbours) {
    for (int d = 0; d <= 2; ++d)
        for (uint32_t c = 0; c < sphereCellCount(d); ++c) {
            auto nb = sphereCellNeighbours(c, d);
            ASSERT_EQ(nb.size(), 3u) << "cell " << c << " depth " << d;
            for (uint32_t o : nb) {
                auto back = sphereCellNeighbours(o, d);
                EXPECT_NE(std::find(back.begin(), back.end(), c), back.end());
            }
        }
}

// ---- Regions ---------------------------------------------------------------------------------

TEST(AgsphereRegions, SphereGivesOneRegionPerOctant) {
    TriMesh s = test::sphere(3);  // faces never straddle an octant
    std::vector<uint32_t> region;
    EXPECT_EQ(agsphereRegions(s, 0, region), 8u);
    for (size_t f = 0; f < s.triangleCount(); ++f) {
        Vec3 n = triNormal(s, s.triangles[f]);
        EXPECT_EQ(sphereCell(n, 0), sphereCell(triNormal(s, s.triangles[region[f]]), 0));
    }
    // Finer depths refine the regions (hierarchy).
    std::vector<uint32_t> fine;
    uint32_t nFine = agsphereRegions(s, 2, fine);
    EXPECT_GT(nFine, 8u);
    for (size_t f = 0; f < s.triangleCount(); ++f)
        for (size_t g = 0; g < s.triangleCount(); ++g)
            if (fine[f] == fine[g]) {
                ASSERT_EQ(region[f], region[g]);
            }
}

TEST(AgsphereRegions, CubeSidesAndEdgeConnectivity) {
    TriMesh c = cube(3);
    std::vector<uint32_t> region;
    // Depth 0: +x, +y and +z normals all lie in octant 0 (zero components count as +), and those
    // three sides are edge-connected, so they form one region; the other three sides one each.
    EXPECT_EQ(agsphereRegions(c, 0, region), 4u);
    EXPECT_EQ(agsphereRegions(c, 1, region), 6u);
    // Regions are edge-connected: flood fill inside each region reaches all of it.
    std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>> edgeFaces;
    for (uint32_t f = 0; f < c.triangleCount(); ++f)
        for (int k = 0; k < 3; ++k) edgeFaces[std::minmax(c.triangles[f][k], c.triangles[f][(k + 1) % 3])].push_back(f);
    std::map<uint32_t, size_t> sizes;
    for (uint32_t r : region) ++sizes[r];
    for (auto [rep, size] : sizes) {
        std::set<uint32_t> seen{rep};
        std::queue<uint32_t> q;
        q.push(rep);
        while (!q.empty()) {
            uint32_t f = q.front();
            q.pop();
            for (int k = 0; k < 3; ++k)
                for (uint32_t g : edgeFaces[std::minmax(c.triangles[f][k], c.triangles[f][(k + 1) % 3])])
                    if (region[g] == rep && seen.insert(g).second) q.push(g);
        }
        EXPECT_EQ(seen.size(), size);
        EXPECT_EQ(*seen.begin(), rep);  // the representative is the smallest face
    }
}

// ---- Polygons --------------------------------------------------------------------------------

TEST(AgsphereTriangulate, SquareWithHoleAndComb) {
    //  3-----------2
    //  |  7-----6  |       outer CCW 0..3, hole CW 4..7
    //  |  |     |  |
    //  |  4-----5  |
    //  0-----------1
    PlanarPolygon p;
    p.points = {{0, 0}, {4, 0}, {4, 4}, {0, 4}, {1, 1}, {3, 1}, {3, 3}, {1, 3}};
    p.loops = {{0, 1, 2, 3}, {4, 7, 6, 5}};
    ASSERT_TRUE(polygonIsSimple(p));
    std::vector<Tri> tris;
    ASSERT_TRUE(triangulatePolygon(p, tris));
    EXPECT_EQ(tris.size(), 8u);  // n + 2h - 2
    double sum = 0;
    for (const Tri& t : tris) {
        double a = 0.5 * cross(p.points[t[1]] - p.points[t[0]], p.points[t[2]] - p.points[t[0]]);
        EXPECT_GT(a, 0);
        sum += a;
    }
    EXPECT_NEAR(sum, polygonArea(p), 1e-12);
    // A comb: many reflex vertices.
    PlanarPolygon comb;
    const int teeth = 12;
    comb.points.push_back({0, 0});
    comb.points.push_back({double(2 * teeth), 0});
    for (int i = teeth - 1; i >= 0; --i) {
        comb.points.push_back({2.0 * i + 2, 5});
        comb.points.push_back({2.0 * i + 1, 1});
    }
    comb.points.push_back({0, 5});
    std::vector<uint32_t> loop(comb.points.size());
    std::iota(loop.begin(), loop.end(), 0u);
    comb.loops = {loop};
    ASSERT_TRUE(polygonIsSimple(comb));
    tris.clear();
    ASSERT_TRUE(triangulatePolygon(comb, tris));
    EXPECT_EQ(tris.size(), comb.points.size() - 2);
    sum = 0;
    for (const Tri& t : tris) {
        double a = 0.5 * cross(comb.points[t[1]] - comb.points[t[0]], comb.points[t[2]] - comb.points[t[0]]);
        EXPECT_GT(a, 0);
        sum += a;
    }
    EXPECT_NEAR(sum, polygonArea(comb), 1e-9);
}

TEST(AgsphereTriangulate, RejectsNonSimple) {
    PlanarPolygon bowtie;
    bowtie.points = {{0, 0}, {2, 2}, {2, 0}, {0, 2}};
    bowtie.loops = {{0, 1, 2, 3}};
    EXPECT_FALSE(polygonIsSimple(bowtie));
    PlanarPolygon clockwise;
    clockwise.points = {{0, 0}, {0, 1}, {1, 0}};
    clockwise.loops = {{0, 1, 2}};
    EXPECT_FALSE(polygonIsSimple(clockwise));
    std::vector<Tri> tris;
    EXPECT_FALSE(triangulatePolygon(clockwise, tris));
    EXPECT_TRUE(tris.empty());
}

// ---- Levels ----------------------------------------------------------------------------------

// Checks a level against the Multires contract and the geometric promises.
void checkLevel(const TriMesh& m, const Level& L, bool closed, const std::string& what) {
    ASSERT_EQ(L.faces.size(), L.triangles.size()) << what;
    ASSERT_EQ(L.cornerWedges.size(), L.triangles.size()) << what;
    ASSERT_EQ(L.faceRegion.size(), m.triangleCount()) << what;
    // Region normals (area-weighted) of the original faces.
    std::map<uint32_t, Vec3> regionNormal;
    for (uint32_t f = 0; f < m.triangleCount(); ++f) regionNormal[L.faceRegion[f]] += triNormal(m, m.triangles[f]);
    EXPECT_EQ(regionNormal.size(), L.regionCount) << what;
    for (size_t t = 0; t < L.triangles.size(); ++t) {
        const Tri& tr = L.triangles[t];
        ASSERT_LT(L.faces[t], m.triangleCount());
        for (uint32_t v : tr) ASSERT_LT(v, m.vertexCount());
        Vec3 n = triNormal(m, tr);
        EXPECT_GT(length(n), 0) << what << " degenerate triangle " << t;
        EXPECT_GT(dot(n, regionNormal[L.faceRegion[L.faces[t]]]), 0) << what << " flipped triangle " << t;
        for (int k = 0; k < 3; ++k) EXPECT_EQ(m.wedges.vertex[L.cornerWedges[t][k]], tr[k]);
    }
    expectManifold(L.triangles, closed, what);
    for (const SimplificationPair& p : L.pairs) {
        Vec3 q = m.positions[p.coarse[0]] * p.bary[0] + m.positions[p.coarse[1]] * p.bary[1] + m.positions[p.coarse[2]] * p.bary[2];
        EXPECT_NEAR(p.deviation, length(m.positions[p.vertex] - q), 1e-5) << what;
        EXPECT_NEAR(p.bary[0] + p.bary[1] + p.bary[2], 1.0, 1e-5);
        EXPECT_LE(p.deviation, L.maxDeviation);
    }
}

TEST(AgsphereLevels, SphereIsWatertightAndNested) {
    TriMesh s = test::sphere(4);  // 2048 faces
    AgsphereResult r = build(s, {{0.5, 0}, {0.1, 0}});
    ASSERT_EQ(r.multires.levels.size(), 2u);
    EXPECT_EQ(r.multires.generator, "agsphere-build");
    EXPECT_TRUE(r.multires.collapses.empty());
    const Level& fine = r.multires.levels[0];
    const Level& coarse = r.multires.levels[1];
    checkLevel(s, fine, true, "fine");
    checkLevel(s, coarse, true, "coarse");
    EXPECT_LT(fine.triangles.size(), s.triangleCount());
    EXPECT_LE(coarse.triangles.size(), fine.triangles.size());
    EXPECT_LE(coarse.regionCount, fine.regionCount);
    // Region hierarchy: faces sharing a fine region share the coarse one.
    std::map<uint32_t, uint32_t> parent;
    for (uint32_t f = 0; f < s.triangleCount(); ++f) {
        auto [it, inserted] = parent.emplace(fine.faceRegion[f], coarse.faceRegion[f]);
        EXPECT_EQ(it->second, coarse.faceRegion[f]);
    }
    // Every removed vertex has a pair; kept vertices are original vertices.
    std::set<uint32_t> used;
    for (const Tri& t : coarse.triangles) used.insert(t.begin(), t.end());
    EXPECT_EQ(used.size() + coarse.pairs.size(), s.vertexCount());
    // Euler characteristic of a closed sphere: V - E + F = 2.
    EXPECT_EQ(int64_t(used.size()) - int64_t(coarse.triangles.size() * 3 / 2) + int64_t(coarse.triangles.size()), 2);
}

TEST(AgsphereLevels, CubeSidesBecomeFewTriangles) {
    TriMesh c = cube(6);  // 432 faces
    AgsphereResult r = build(c, {{0, 12}}, {}, 3);
    const Level& L = r.multires.levels[0];
    checkLevel(c, L, true, "cube");
    // Flat sides: boundary runs are straight, each side is a square: 2 triangles per side.
    EXPECT_EQ(L.triangles.size(), 12u);
    EXPECT_LT(L.maxDeviation, 1e-6);  // float barycentrics
    double area = 0;
    for (const Tri& t : L.triangles) area += 0.5 * length(triNormal(c, t));
    EXPECT_NEAR(area, 24.0, 1e-9);
}

TEST(AgsphereLevels, HemisphereKeepsItsBorder) {
    TriMesh h = test::hemisphere(4);
    AgsphereResult r = build(h, {{0.3, 0}});
    const Level& L = r.multires.levels[0];
    checkLevel(h, L, false, "hemisphere");
    // Open edges of the level lie on the input's border (the border may be simplified, never moved).
    std::map<std::pair<uint32_t, uint32_t>, int> in, out;
    for (const Tri& t : h.triangles)
        for (int k = 0; k < 3; ++k) ++in[std::minmax(t[k], t[(k + 1) % 3])];
    std::set<uint32_t> borderVertices;
    for (const auto& [e, n] : in)
        if (n == 1) borderVertices.insert(e.first), borderVertices.insert(e.second);
    for (const Tri& t : L.triangles)
        for (int k = 0; k < 3; ++k) ++out[std::minmax(t[k], t[(k + 1) % 3])];
    size_t open = 0;
    for (const auto& [e, n] : out)
        if (n == 1) {
            ++open;
            EXPECT_TRUE(borderVertices.count(e.first) && borderVertices.count(e.second));
        }
    EXPECT_GT(open, 2u);
}

TEST(AgsphereLevels, ViewLevelRefinesSilhouette) {
    TriMesh s = test::sphere(5);  // 8192 faces
    const Vec3 view{0, 0, 1};
    AgsphereResult r = build(s, {{0, 1500}}, {view}, 5);
    const Level& L = r.multires.levels[0];
    checkLevel(s, L, true, "view");
    // Triangle density (per unit area of the original sphere) near the silhouette (normals
    // orthogonal to the view) is higher than on the front cap facing the view.
    double silArea = 0, capArea = 0;
    size_t silTris = 0, capTris = 0;
    for (const Tri& t : s.triangles) {
        Vec3 c = normalize(s.positions[t[0]] + s.positions[t[1]] + s.positions[t[2]]);
        double a = 0.5 * length(triNormal(s, t));
        if (std::fabs(dot(c, view)) < 0.2) silArea += a;
        if (dot(c, view) > 0.8) capArea += a;
    }
    for (const Tri& t : L.triangles) {
        Vec3 c = normalize(s.positions[t[0]] + s.positions[t[1]] + s.positions[t[2]]);
        if (std::fabs(dot(c, view)) < 0.2) ++silTris;
        if (dot(c, view) > 0.8) ++capTris;
    }
    EXPECT_GT(silTris / silArea, 2 * capTris / capArea);
    EXPECT_GT(r.levelStats[0].orthogonalCells, 0u);
}

TEST(AgsphereLevels, DeterministicAcrossThreads) {
    TriMesh s = test::sphere(4);
    AgsphereOptions o;
    o.levels = {{0.3, 0}};
    o.threads = 1;
    AgsphereResult a = buildAgsphere(s, o);
    o.threads = 2;
    AgsphereResult b = buildAgsphere(s, o);
    EXPECT_EQ(a.multires.levels[0].triangles, b.multires.levels[0].triangles);
    EXPECT_EQ(a.multires.levels[0].faces, b.multires.levels[0].faces);
    EXPECT_EQ(a.multires.levels[0].faceRegion, b.multires.levels[0].faceRegion);
}

namespace {

// Orthographic coverage of the faces of `tris` facing `view`, on an n x n raster over [-s, s]^2
// of the plane orthogonal to `view` (pixel centres inside or on a projected triangle).
// With eyeDistance > 0: perspective from the eye at eyeDistance * view (unit), coordinates divided
// by the depth.
std::vector<char> coverage(const TriMesh& m, const std::vector<Tri>& tris, Vec3 view, int n, double s,
                           double eyeDistance = 0) {
    Vec3 d = normalize(view);
    Vec3 u = normalize(cross(d, Vec3{1, 0, 0})), w = cross(d, u);
    Vec3 eye = d * eyeDistance;
    std::vector<char> img(size_t(n) * n, 0);
    for (const Tri& t : tris) {
        Vec3 facing = eyeDistance > 0 ? eye - m.positions[t[0]] : d;
        if (!(dot(triNormal(m, t), facing) > 0)) continue;
        double x[3], y[3];
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = m.positions[t[k]];
            double z = eyeDistance > 0 ? dot(eye - p, d) : 1;
            x[k] = (dot(p, u) / z + s) / (2 * s) * n;
            y[k] = (dot(p, w) / z + s) / (2 * s) * n;
        }
        double area = (x[1] - x[0]) * (y[2] - y[0]) - (y[1] - y[0]) * (x[2] - x[0]);
        if (area == 0) continue;
        double sg = area > 0 ? 1 : -1;
        int x0 = std::max(0, int(std::min({x[0], x[1], x[2]}))), x1 = std::min(n - 1, int(std::max({x[0], x[1], x[2]})));
        int y0 = std::max(0, int(std::min({y[0], y[1], y[2]}))), y1 = std::min(n - 1, int(std::max({y[0], y[1], y[2]})));
        for (int py = y0; py <= y1; ++py)
            for (int px = x0; px <= x1; ++px) {
                double qx = px + 0.5, qy = py + 0.5;
                bool in = true;
                for (int k = 0; k < 3 && in; ++k) {
                    int j = (k + 1) % 3;
                    in = sg * ((x[j] - x[k]) * (qy - y[k]) - (y[j] - y[k]) * (qx - x[k])) >= 0;
                }
                if (in) img[size_t(py) * n + px] = 1;
            }
    }
    return img;
}

size_t differingPixels(const std::vector<char>& a, const std::vector<char>& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.size(); ++i) n += a[i] != b[i];
    return n;
}

// A sphere with bumps: folds seen from the view make contour edges inside the outline.
TriMesh bumpySphere(int levels) {
    TriMesh s = test::sphere(levels);
    for (Vec3& p : s.positions) p = p * (1 + 0.08 * std::sin(9 * p.x) * std::sin(7 * p.y + 1) * std::sin(8 * p.z + 2));
    return s;
}

}  // namespace

TEST(AgsphereOutline, ViewLevelKeepsTheOutlineExactly) {
    TriMesh s = bumpySphere(5);  // 8192 faces
    const Vec3 view{0.2, 0.1, 1};
    AgsphereOptions o;
    o.levels = {{0, 2500}};
    o.maxDepth = 5;
    o.views = {view};
    AgsphereResult r = buildAgsphere(s, o);
    const Level& L = r.multires.levels[0];
    checkLevel(s, L, true, "outline");
    EXPECT_LT(L.triangles.size(), s.triangleCount() / 2);
    // Outline edges are a strict subset of the contour edges (the bumps fold inside the outline).
    EXPECT_GT(r.outlineEdges, 0u);
    EXPECT_LT(r.outlineEdges, r.contourEdges);
    EXPECT_EQ(r.levelStats[0].outlineFaces, r.outlineFaces);
    // Seen from the view, the level covers exactly the original's pixels.
    const int n = 256;
    auto original = coverage(s, s.triangles, view, n, 1.2);
    auto kept = coverage(s, L.triangles, view, n, 1.2);
    size_t covered = 0;
    for (char c : original) covered += c;
    EXPECT_GT(covered, size_t(n) * n / 3);
    EXPECT_EQ(differingPixels(original, kept), 0u);
    // Without keeping the outline, the same budget moves it.
    o.keepOutline = false;
    o.levels = {{0, L.triangles.size()}};
    AgsphereResult plain = buildAgsphere(s, o);
    auto moved = coverage(s, plain.multires.levels[0].triangles, view, n, 1.2);
    EXPECT_GT(differingPixels(original, moved), 20u);
}

TEST(AgsphereOutline, PerspectiveOutlineIsKeptForItsEye) {
    TriMesh s = test::sphere(5);  // unit sphere: bounding radius 1
    const Vec3 view{0.2, 0.1, 1};
    AgsphereOptions o;
    o.levels = {{0, 2500}};
    o.maxDepth = 5;
    o.views = {view};
    AgsphereResult ortho = buildAgsphere(s, o);
    o.viewDistance = 2;  // seen from 2 radii, the outline is the circle 60 degrees from the view
    AgsphereResult near = buildAgsphere(s, o);
    checkLevel(s, near.multires.levels[0], true, "perspective");
    // Convex: every contour edge is on the outline.
    EXPECT_EQ(ortho.outlineEdges, ortho.contourEdges);
    EXPECT_EQ(near.outlineEdges, near.contourEdges);
    const int n = 256;
    auto original = coverage(s, s.triangles, view, n, 1.2);
    EXPECT_EQ(differingPixels(original, coverage(s, ortho.multires.levels[0].triangles, view, n, 1.2)), 0u);
    auto originalNear = coverage(s, s.triangles, view, n, 0.8, 2);
    EXPECT_EQ(differingPixels(originalNear, coverage(s, near.multires.levels[0].triangles, view, n, 0.8, 2)), 0u);
    // The orthographic outline is not the one seen from 2 radii.
    EXPECT_GT(differingPixels(originalNear, coverage(s, ortho.multires.levels[0].triangles, view, n, 0.8, 2)), 0u);
}
