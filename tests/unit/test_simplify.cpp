// Unit tests of simplify(): half-edge collapse with region hierarchy, on synthetic meshes.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <numeric>
#include <set>

#include "lodbake/core/errors.h"
#include "lodbake/simplify/simplify.h"
#include "unit/synthetic_meshes.h"

namespace lodbake {
namespace {

SimplifyOptions withLevels(std::vector<LevelTarget> levels) {
    SimplifyOptions o;
    o.levels = std::move(levels);
    return o;
}
LevelTarget ratio(double r) { return LevelTarget{r, 0, 0}; }
LevelTarget count(uint64_t n) { return LevelTarget{0, n, 0}; }

// faceRegion of `level` rebuilt from the identity by replaying the collapse records.
std::vector<uint32_t> replayRegions(size_t faceCount, const Multires& mr, const Level& level) {
    std::vector<uint32_t> rep(faceCount);
    std::iota(rep.begin(), rep.end(), 0u);
    for (uint32_t c = 0; c < level.collapseCount; ++c) {
        const CollapseRecord& r = mr.collapses[c];
        for (uint32_t u = r.regionBegin; u < r.regionEnd; ++u) {
            // Every face labelled oldRep (at least one) takes the label newRep.
            const RegionUpdate& up = mr.regionUpdates[u];
            EXPECT_NE(up.oldRep, up.newRep);
            size_t moved = 0;
            for (uint32_t& x : rep)
                if (x == up.oldRep) x = up.newRep, ++moved;
            EXPECT_GT(moved, 0u);
        }
    }
    return rep;
}

using EdgeMap = std::map<std::pair<uint32_t, uint32_t>, std::vector<uint32_t>>;  // undirected edge -> level triangles
EdgeMap edgesOf(const std::vector<Tri>& tris) {
    EdgeMap e;
    for (uint32_t t = 0; t < tris.size(); ++t)
        for (int k = 0; k < 3; ++k) e[std::minmax(tris[t][k], tris[t][(k + 1) % 3])].push_back(t);
    return e;
}

// Regions: consistent with the replay, every region keeps a surviving face and its surviving faces
// are edge-connected in the level mesh; regionCount is the number of distinct representatives; a
// representative is a surviving face of its own region.
void expectValidRegions(const TriMesh& mesh, const Multires& mr, const Level& level) {
    ASSERT_EQ(level.faceRegion.size(), mesh.triangleCount());
    EXPECT_EQ(replayRegions(mesh.triangleCount(), mr, level), level.faceRegion);
    std::set<uint32_t> reps(level.faceRegion.begin(), level.faceRegion.end());
    EXPECT_EQ(reps.size(), level.regionCount);
    std::set<uint32_t> alive(level.faces.begin(), level.faces.end());
    for (uint32_t r : reps) {
        EXPECT_TRUE(alive.count(r)) << "representative " << r << " is not a surviving face";
        EXPECT_EQ(level.faceRegion[r], r);
    }
    // Union-find over level triangles sharing an edge inside the same region.
    std::vector<uint32_t> parent(level.faces.size());
    std::iota(parent.begin(), parent.end(), 0u);
    std::function<uint32_t(uint32_t)> find = [&](uint32_t x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
    for (const auto& [edge, ts] : edgesOf(level.triangles))
        for (size_t a = 1; a < ts.size(); ++a)
            if (level.faceRegion[level.faces[ts[0]]] == level.faceRegion[level.faces[ts[a]]])
                parent[find(ts[0])] = find(ts[a]);
    std::map<uint32_t, std::set<uint32_t>> pieces;  // region -> union-find roots
    for (uint32_t t = 0; t < level.faces.size(); ++t) pieces[level.faceRegion[level.faces[t]]].insert(find(t));
    EXPECT_EQ(pieces.size(), reps.size()) << "a region lost all its surviving faces";
    for (const auto& [r, roots] : pieces) EXPECT_EQ(roots.size(), 1u) << "region " << r << " is not edge-connected";
}

Vec3 normalOf(const TriMesh& m, const Tri& t) {
    return cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
}

// Pairs: bary sums to 1, P reproduces, deviation <= maxDeviation, pair face survives.
void expectValidPairs(const TriMesh& mesh, const Level& level) {
    std::map<uint32_t, Tri> tri;
    for (size_t t = 0; t < level.faces.size(); ++t) tri[level.faces[t]] = level.triangles[t];
    std::set<uint32_t> kept;
    for (const Tri& t : level.triangles) kept.insert(t.begin(), t.end());
    size_t removed = 0;
    for (uint32_t v = 0; v < mesh.vertexCount(); ++v) removed += !kept.count(v);
    EXPECT_EQ(level.pairs.size(), removed);
    double sum = 0;
    for (const SimplificationPair& p : level.pairs) {
        EXPECT_FALSE(kept.count(p.vertex));
        EXPECT_NEAR(p.bary[0] + p.bary[1] + p.bary[2], 1.0, 1e-5);
        ASSERT_TRUE(tri.count(p.face));
        const Tri& t = tri[p.face];
        if (p.coarse[2] == p.coarse[1] && p.bary[2] == 0) {  // edge form: an edge of the face
            EXPECT_TRUE(std::count(t.begin(), t.end(), p.coarse[0]) > 0 && std::count(t.begin(), t.end(), p.coarse[1]) > 0);
        } else {
            EXPECT_EQ(p.coarse, t);
        }
        Vec3 P = mesh.positions[p.coarse[0]] * p.bary[0] + mesh.positions[p.coarse[1]] * p.bary[1] +
                 mesh.positions[p.coarse[2]] * p.bary[2];
        EXPECT_NEAR(length(P - mesh.positions[p.vertex]), p.deviation, 1e-5);
        EXPECT_LE(p.deviation, level.maxDeviation + 1e-6);
        sum += p.deviation;
    }
    if (!level.pairs.empty()) {
        EXPECT_NEAR(level.meanDeviation, sum / level.pairs.size(), 1e-6);
    }
}

// ------------------------------------------------------------------------------------------------

TEST(Simplify, NoTrianglesIsImpossible) {
    TriMesh m;
    m.positions = {{0, 0, 0}};
    EXPECT_THROW(simplify(m, withLevels({ratio(0.5)})), Impossible);
}

// Collapsing the centre of the flat hexagon costs 0 (every ring collapse cuts a corner), so the
// first collapse is 0 -> 1 (all quadric costs tie at 0; smallest id). Faces 0 (0,1,2) and
// 5 (0,6,1) vanish; the six single-face regions merge into one whose representative is the
// smallest surviving face, 1. Face 1 is already mapped to itself and is not recorded.
TEST(Simplify, HexagonCentreCollapseMergesAllSixFaces) {
    TriMesh m = test::hexagonFan();
    SimplifyResult r = simplify(m, withLevels({count(4)}));
    const Multires& mr = r.multires;
    ASSERT_EQ(mr.levels.size(), 1u);
    ASSERT_EQ(mr.collapses.size(), 1u);
    EXPECT_EQ(mr.collapses[0].removed, 0u);
    EXPECT_EQ(mr.collapses[0].kept, 1u);
    EXPECT_NEAR(mr.collapses[0].deviation, 0.f, 1e-7);
    const Level& l = mr.levels[0];
    EXPECT_EQ(l.stopReason, "target");
    EXPECT_EQ(l.faces, (std::vector<uint32_t>{1, 2, 3, 4}));
    EXPECT_EQ(l.triangles, (std::vector<Tri>{{1, 2, 3}, {1, 3, 4}, {1, 4, 5}, {1, 5, 6}}));
    EXPECT_EQ(l.regionCount, 1u);
    EXPECT_EQ(l.faceRegion, (std::vector<uint32_t>(6, 1)));
    // Five one-face regions join the region of face 1 (one record each).
    ASSERT_EQ(mr.collapses[0].regionEnd - mr.collapses[0].regionBegin, 5u);
    std::vector<uint32_t> updated;
    for (uint32_t u = mr.collapses[0].regionBegin; u < mr.collapses[0].regionEnd; ++u) {
        const RegionUpdate& up = mr.regionUpdates[u];
        EXPECT_EQ(up.newRep, 1u);
        updated.push_back(up.oldRep);
    }
    EXPECT_EQ(updated, (std::vector<uint32_t>{0, 2, 3, 4, 5}));
    // The centre projects onto the coarse surface exactly.
    ASSERT_EQ(l.pairs.size(), 1u);
    EXPECT_EQ(l.pairs[0].vertex, 0u);
    EXPECT_NEAR(l.pairs[0].deviation, 0.0, 1e-7);
    expectValidRegions(m, mr, l);
    expectValidPairs(m, l);
}

// Rule 3 on test::splitDisk: u and w collapse first (cheapest), merging the upper five faces into
// one region and the lower five into another. Then i (on the p-boundary k - i - j, with exactly two
// p-boundary spokes) collapses along it. When i lies within eps (= 0.01 * longest box side = 0.04)
// of the new edge, the edge stays a p-boundary: two regions, no merge. Lifted by 0.5 it is not:
// the two regions merge.
TEST(Simplify, Rule3KeepsStraightPBoundary) {
    for (double lift : {0.01, 0.5}) {
        SCOPED_TRACE(lift);
        TriMesh m = test::splitDisk(lift);
        SimplifyResult r = simplify(m, withLevels({count(4)}));
        const Multires& mr = r.multires;
        ASSERT_EQ(mr.collapses.size(), 3u);
        std::set<uint32_t> first{mr.collapses[0].removed, mr.collapses[1].removed};
        EXPECT_EQ(first, (std::set<uint32_t>{7, 8}));
        const CollapseRecord& last = mr.collapses[2];
        EXPECT_EQ(last.removed, 1u);
        EXPECT_TRUE(last.kept == 0u || last.kept == 2u);
        const Level& l = mr.levels[0];
        ASSERT_EQ(l.triangles.size(), 4u);
        if (lift < 0.04) {
            // No merge. The upper region's representative (face 0 = (u, k, i)) is removed by this
            // collapse, so its region is re-labelled to a surviving face: one rename record.
            ASSERT_EQ(last.regionEnd - last.regionBegin, 1u);
            EXPECT_EQ(mr.regionUpdates[last.regionBegin].oldRep, 0u);
            EXPECT_EQ(l.regionCount, 2u);
            // Upper faces (0..4) and lower faces (5..9) form the two regions.
            for (uint32_t f = 1; f < 5; ++f) EXPECT_EQ(l.faceRegion[f], l.faceRegion[0]);
            for (uint32_t f = 6; f < 10; ++f) EXPECT_EQ(l.faceRegion[f], l.faceRegion[5]);
            EXPECT_NE(l.faceRegion[0], l.faceRegion[5]);
        } else {
            EXPECT_GT(last.regionEnd, last.regionBegin);
            EXPECT_EQ(l.regionCount, 1u);
        }
        expectValidRegions(m, mr, l);
        expectValidPairs(m, l);
    }
}

TEST(Simplify, GridToAFewTriangles) {
    TriMesh m = test::grid(12, 12, [](int i, int j) { return 0.3 * std::sin(0.6 * i) * std::cos(0.4 * j); });
    SimplifyResult r = simplify(m, withLevels({ratio(0.5), count(8), ratio(0.1)}));
    const Multires& mr = r.multires;
    ASSERT_EQ(mr.levels.size(), 3u);
    EXPECT_LE(mr.levels[0].triangles.size(), 144u);  // 288 * 0.5; a collapse removes 1 or 2 faces
    EXPECT_GE(mr.levels[0].triangles.size(), 143u);
    EXPECT_LE(mr.levels[1].triangles.size(), 29u);
    EXPECT_GE(mr.levels[1].triangles.size(), 28u);
    EXPECT_LE(mr.levels[2].triangles.size(), 8u);
    for (const Level& l : mr.levels) {
        EXPECT_EQ(l.stopReason, "target");
        expectValidRegions(m, mr, l);
        expectValidPairs(m, l);
        EXPECT_GE(l.regionCount, 1u);
    }
    EXPECT_EQ(mr.levels[2].collapseCount, mr.collapses.size());
}

TEST(Simplify, ClosedSphereKeepsTwoRegionsWatertightAndUnflipped) {
    TriMesh m = test::sphere(4);  // 2048 faces
    SimplifyResult r = simplify(m, withLevels({ratio(0.02)}));
    const Level& l = r.multires.levels[0];
    EXPECT_EQ(l.stopReason, "target");
    EXPECT_LE(l.triangles.size(), 41u);
    EXPECT_GE(l.triangles.size(), 40u);
    EXPECT_GE(l.regionCount, 2u);
    for (const auto& [edge, ts] : edgesOf(l.triangles)) EXPECT_EQ(ts.size(), 2u);
    for (size_t t = 0; t < l.faces.size(); ++t) {
        Vec3 now = normalOf(m, l.triangles[t]), before = normalOf(m, m.triangles[l.faces[t]]);
        EXPECT_GT(dot(now, before), 0) << "face " << l.faces[t] << " flipped";
        // And it faces outwards.
        Vec3 c = (m.positions[l.triangles[t][0]] + m.positions[l.triangles[t][1]] + m.positions[l.triangles[t][2]]) / 3;
        EXPECT_GT(dot(now, c), 0);
    }
    expectValidRegions(m, r.multires, l);
    expectValidPairs(m, l);
    EXPECT_LT(l.maxDeviation, 0.5);
}

TEST(Simplify, ClosedSphereToOneTriangleStopsOnAConstraint) {
    TriMesh m = test::sphere(2);
    SimplifyResult r = simplify(m, withLevels({count(1)}));
    const Level& l = r.multires.levels[0];
    EXPECT_NE(l.stopReason, "target");
    EXPECT_GE(l.triangles.size(), 4u);
    EXPECT_GE(l.regionCount, 2u);
    for (const auto& [edge, ts] : edgesOf(l.triangles)) EXPECT_EQ(ts.size(), 2u);
}

TEST(Simplify, SeamsAndMaterialsDoNotBlock) {
    TriMesh m = test::seamGrid(40);  // 3200 faces
    SimplifyResult r = simplify(m, withLevels({ratio(0.02)}));
    const Level& l = r.multires.levels[0];
    EXPECT_EQ(l.stopReason, "target");
    EXPECT_LE(l.triangles.size(), 64u);
    EXPECT_GE(l.triangles.size(), 63u);  // within 2 % of 64
    ASSERT_EQ(l.cornerWedges.size(), l.triangles.size());
    for (size_t t = 0; t < l.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(m.wedges.vertex[l.cornerWedges[t][k]], l.triangles[t][k]);
    expectValidRegions(m, r.multires, l);
    expectValidPairs(m, l);
}

TEST(Simplify, DeviationsAndPairs) {
    TriMesh m = test::hemisphere(4);
    SimplifyResult r = simplify(m, withLevels({ratio(0.05), ratio(0.5), ratio(0.2)}));
    const Multires& mr = r.multires;
    ASSERT_EQ(mr.levels.size(), 3u);
    double prev = 0;
    for (const Level& l : mr.levels) {
        EXPECT_GE(l.maxDeviation, prev);
        prev = l.maxDeviation;
        expectValidPairs(m, l);
        expectValidRegions(m, mr, l);
    }
    EXPECT_GT(mr.levels[0].targetRatio, mr.levels[2].targetRatio);  // finest first
    float running = 0;
    for (const CollapseRecord& c : mr.collapses) {
        running = std::max(running, c.deviation);
        EXPECT_LE(running, mr.levels.back().maxDeviation + 1e-9);
    }
    EXPECT_NEAR(r.diagonal, std::sqrt(4.0 + 4.0 + 1.0), 1e-9);
}

TEST(Simplify, MaxErrorTargetStopsBeforeTheError) {
    TriMesh m = test::hemisphere(4);
    LevelTarget t;
    t.maxError = 0.01;
    SimplifyResult r = simplify(m, withLevels({t}));
    const Level& l = r.multires.levels[0];
    EXPECT_LT(l.triangles.size(), m.triangleCount());
    for (const CollapseRecord& c : r.multires.collapses) EXPECT_LE(c.deviation, 0.01 * r.diagonal * 1.0001);
    EXPECT_LE(l.maxDeviation, 0.01 * r.diagonal * 1.0001);
    EXPECT_EQ(l.stopReason, "target");
}

// Two runs gave the same hierarchy: collapses, region updates, level faces and pairs.
void expectSameMultires(const Multires& a, const Multires& b) {
    ASSERT_EQ(a.collapses.size(), b.collapses.size());
    for (size_t k = 0; k < a.collapses.size(); ++k) {
        EXPECT_EQ(a.collapses[k].removed, b.collapses[k].removed);
        EXPECT_EQ(a.collapses[k].kept, b.collapses[k].kept);
        EXPECT_EQ(a.collapses[k].deviation, b.collapses[k].deviation);
        EXPECT_EQ(a.collapses[k].regionEnd, b.collapses[k].regionEnd);
    }
    ASSERT_EQ(a.regionUpdates.size(), b.regionUpdates.size());
    for (size_t k = 0; k < a.regionUpdates.size(); ++k) {
        EXPECT_EQ(a.regionUpdates[k].oldRep, b.regionUpdates[k].oldRep);
        EXPECT_EQ(a.regionUpdates[k].newRep, b.regionUpdates[k].newRep);
    }
    for (size_t l = 0; l < a.levels.size(); ++l) {
        EXPECT_EQ(a.levels[l].triangles, b.levels[l].triangles);
        EXPECT_EQ(a.levels[l].cornerWedges, b.levels[l].cornerWedges);
        EXPECT_EQ(a.levels[l].faceRegion, b.levels[l].faceRegion);
        ASSERT_EQ(a.levels[l].pairs.size(), b.levels[l].pairs.size());
        for (size_t p = 0; p < a.levels[l].pairs.size(); ++p) {
            EXPECT_EQ(a.levels[l].pairs[p].face, b.levels[l].pairs[p].face);
            EXPECT_EQ(a.levels[l].pairs[p].bary, b.levels[l].pairs[p].bary);
            EXPECT_EQ(a.levels[l].pairs[p].deviation, b.levels[l].pairs[p].deviation);
        }
    }
}

TEST(Simplify, Deterministic) {
    TriMesh m = test::seamGrid(20);
    SimplifyOptions o = withLevels({ratio(0.3), ratio(0.05)});
    expectSameMultires(simplify(m, o).multires, simplify(m, o).multires);
}

// Candidates are evaluated and pairs projected in fixed vertex chunks (several here) whatever the
// thread count: 1, 2 and 3 threads give the same hierarchy.
TEST(Simplify, SameResultForAnyThreadCount) {
    TriMesh m = test::grid(110, 110, [](int i, int j) {
        return 3.0 * std::sin(0.05 * i) * std::cos(0.07 * j) + 0.02 * std::sin(12.9898 * i + 78.233 * j);
    });
    ASSERT_GT(m.positions.size(), 3u * 4096u);  // more than three evaluation chunks
    SimplifyOptions o = withLevels({ratio(0.1), ratio(0.01)});
    o.threads = 1;
    const Multires one = simplify(m, o).multires;
    ASSERT_EQ(one.levels.size(), 2u);
    EXPECT_LT(one.levels[1].triangles.size(), m.triangles.size() / 50);
    for (int threads : {2, 3}) {
        SCOPED_TRACE(threads);
        o.threads = threads;
        expectSameMultires(one, simplify(m, o).multires);
    }
}

// A fin: a third triangle (v, 6, 7) on the grid's interior edge 6-7 of grid(4, 4)... with a new apex
// above it, making edge (6, 7) non-manifold. Its vertices get locked; the rest simplifies.
TEST(Simplify, NonManifoldEdgeIsLockedNotFatal) {
    TriMesh m = test::grid(4, 4);
    uint32_t apex = uint32_t(m.positions.size());
    m.positions.push_back({1.5, 1.5, 1.0});
    m.triangles.push_back({6, 12, apex});  // edge 6-12 is the diagonal of quad (1,1): now 3 faces
    test::addDefaultWedges(m);
    SimplifyResult r = simplify(m, withLevels({ratio(0.5), count(1)}));
    ASSERT_EQ(r.multires.levels.size(), 2u);
    const Level& fine = r.multires.levels[0];
    EXPECT_EQ(fine.stopReason, "target");
    const Level& coarse = r.multires.levels[1];
    EXPECT_NE(coarse.stopReason, "target");
    EXPECT_FALSE(coarse.stopReason.empty());
    // The fin and its edge survive untouched.
    std::set<uint32_t> kept;
    for (const Tri& t : coarse.triangles) kept.insert(t.begin(), t.end());
    EXPECT_TRUE(kept.count(6) && kept.count(12) && kept.count(apex));
    expectValidRegions(m, r.multires, coarse);
    expectValidPairs(m, coarse);
}

TEST(Simplify, TwoComponentsAndABowTie) {
    TriMesh a = test::sphere(2), b = test::grid(6, 6);
    TriMesh m = a;
    uint32_t off = uint32_t(m.positions.size());
    for (Vec3 p : b.positions) m.positions.push_back(p + Vec3{3, 0, 0});
    for (Tri t : b.triangles) m.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
    // Bow-tie: two triangles meeting only at the sphere's vertex 0.
    uint32_t q = uint32_t(m.positions.size());
    m.positions.push_back({1.5, 0.5, 0});
    m.positions.push_back({1.5, -0.5, 0});
    m.triangles.push_back({0, q, q + 1});
    test::addDefaultWedges(m);
    // By size (the bow-tie's own behaviour): the unreachable 2-face level stops on a constraint.
    // By visual weight the sphere with its bow-tie, stuck and smaller than the error the pass
    // accepts, leaves the level whole and the grid reaches the target (checked at the end).
    SimplifyOptions o = withLevels({ratio(0.3), count(2)});
    o.visualWeight = false;
    o.grossError = 0;  // the 2-face level takes the grid further than the gross-error bound
    SimplifyResult r = simplify(m, o);
    ASSERT_EQ(r.multires.levels.size(), 2u);
    EXPECT_EQ(r.multires.levels[0].stopReason, "target");
    EXPECT_NE(r.multires.levels[1].stopReason, "target");
    const Level& l = r.multires.levels[1];
    // The sphere stays closed with >= 2 regions; every component keeps triangles.
    std::set<uint32_t> kept;
    for (const Tri& t : l.triangles) kept.insert(t.begin(), t.end());
    EXPECT_TRUE(kept.count(0));
    bool gridLeft = false;
    for (uint32_t v : kept) gridLeft |= v >= off && v < q;
    EXPECT_TRUE(gridLeft);
    expectValidRegions(m, r.multires, l);
    expectValidPairs(m, l);

    const SimplifyResult w = simplify(m, withLevels({ratio(0.3), count(2)}));
    EXPECT_EQ(w.multires.levels[0].triangles, r.multires.levels[0].triangles);
    EXPECT_EQ(w.multires.levels[1].stopReason, "target");
    for (const Tri& t : w.multires.levels[1].triangles)
        for (uint32_t v : t) EXPECT_TRUE(v >= off && v < q) << "the grid, the heavier part, stays";
}

// Inconsistent winding is not a lock: one face of a flat grid wound the other way round shares
// each of its edges in the same direction with a neighbour. The edges still have two faces (a
// manifold surface), so the grid simplifies to the target and the reversed face's corners may go.
TEST(Simplify, InconsistentWindingIsNotLocked) {
    TriMesh m = test::grid(6, 6);
    const uint32_t flipped = 2 * (3 * 6 + 3);  // lower triangle of quad (3, 3), in the middle
    std::swap(m.triangles[flipped][1], m.triangles[flipped][2]);
    test::addDefaultWedges(m);
    Tri corners = m.triangles[flipped];
    SimplifyResult r = simplify(m, withLevels({count(8)}));
    const Level& l = r.multires.levels[0];
    EXPECT_EQ(l.stopReason, "target");
    EXPECT_LE(l.triangles.size(), 8u);
    std::set<uint32_t> kept;
    for (const Tri& t : l.triangles) kept.insert(t.begin(), t.end());
    EXPECT_LT(std::count_if(corners.begin(), corners.end(), [&](uint32_t v) { return kept.count(v) > 0; }), 3);
    expectValidRegions(m, r.multires, l);
    expectValidPairs(m, l);
}

// Every region of the level is edge-connected in the ORIGINAL mesh (what a chart needs).
void expectRegionsConnectedInOriginal(const TriMesh& mesh, const Level& level) {
    std::vector<uint32_t> parent(mesh.triangleCount());
    std::iota(parent.begin(), parent.end(), 0u);
    std::function<uint32_t(uint32_t)> find = [&](uint32_t x) { return parent[x] == x ? x : parent[x] = find(parent[x]); };
    for (const auto& [edge, fs] : edgesOf(mesh.triangles))
        for (size_t a = 1; a < fs.size(); ++a)
            if (level.faceRegion[fs[0]] == level.faceRegion[fs[a]]) parent[find(fs[0])] = find(fs[a]);
    std::map<uint32_t, std::set<uint32_t>> pieces;
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f) pieces[level.faceRegion[f]].insert(find(f));
    for (const auto& [r, roots] : pieces) EXPECT_EQ(roots.size(), 1u) << "region " << r << " is not edge-connected";
}

// A pinch (bow-tie) vertex: two flat 4x4 grids touching only at one corner, vertex 24 = (4, 4).
// Both sheets simplify down to a few triangles (the pinch moves with both of its fans, its
// neighbours collapse into it), and no region joins the two sheets.
TEST(Simplify, BowTieSheetsSimplifyAndStayApart) {
    TriMesh m = test::grid(4, 4);
    TriMesh b = test::grid(4, 4);
    const uint32_t pinch = 24, off = uint32_t(m.positions.size());
    for (uint32_t v = 1; v < b.positions.size(); ++v) m.positions.push_back(b.positions[v] + Vec3{4, 4, 0});
    auto map = [&](uint32_t v) { return v == 0 ? pinch : off + v - 1; };
    for (const Tri& t : b.triangles) m.triangles.push_back({map(t[0]), map(t[1]), map(t[2])});
    test::addDefaultWedges(m);
    SimplifyResult r = simplify(m, withLevels({count(4)}));
    const Level& l = r.multires.levels[0];
    EXPECT_EQ(l.stopReason, "target");
    EXPECT_LE(l.triangles.size(), 4u);
    const uint32_t sheetFaces = uint32_t(b.triangles.size());
    for (uint32_t f = 0; f < m.triangleCount(); ++f)
        EXPECT_EQ(l.faceRegion[f] < sheetFaces, f < sheetFaces) << "face " << f << " joined the other sheet";
    expectValidRegions(m, r.multires, l);
    expectRegionsConnectedInOriginal(m, l);
    expectValidPairs(m, l);
}

// A T-junction crack: a 4x4 grid above a 8x4 grid of half-width columns; along y = 0 they share
// the integer vertices (pinches) but no edge. Both sheets simplify, and no region joins faces of
// the two sheets (every region stays edge-connected in the original mesh).
TEST(Simplify, CrackSheetsSimplifyWithoutJoining) {
    TriMesh m = test::grid(4, 4);  // y in [0, 4]; vertex (i, 0) is i
    std::vector<uint32_t> lower(9 * 5);  // lower grid vertex (i, j) at x = i / 2, y = -j
    for (int j = 0; j <= 4; ++j)
        for (int i = 0; i <= 8; ++i) {
            if (j == 0 && i % 2 == 0) {
                lower[size_t(i)] = uint32_t(i / 2);
                continue;
            }
            lower[size_t(j * 9 + i)] = uint32_t(m.positions.size());
            m.positions.push_back({0.5 * i, -double(j), 0});
        }
    auto below = [&](int i, int j) { return lower[size_t(j * 9 + i)]; };
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 8; ++i) {
            m.triangles.push_back({below(i, j), below(i + 1, j + 1), below(i + 1, j)});
            m.triangles.push_back({below(i, j), below(i, j + 1), below(i + 1, j + 1)});
        }
    test::addDefaultWedges(m);
    SimplifyResult r = simplify(m, withLevels({count(12)}));
    const Level& l = r.multires.levels[0];
    EXPECT_LE(l.triangles.size(), 24u);  // from 96
    expectValidRegions(m, r.multires, l);
    expectRegionsConnectedInOriginal(m, l);
    expectValidPairs(m, l);
}

// Rule 1 only forbids merges: a sphere with a three-vertex hole is open, so its regions may merge
// into one; once a border collapse closes the hole the component is closed again, and collapses
// inside its single region (which merge nothing) must still go on to the target.
TEST(Simplify, ClosedAgainWithOneRegionKeepsSimplifying) {
    TriMesh m = test::sphere(2);
    m.triangles.erase(m.triangles.begin());
    test::addDefaultWedges(m);
    SimplifyResult r = simplify(m, withLevels({count(6)}));
    const Level& l = r.multires.levels[0];
    EXPECT_EQ(l.stopReason, "target");
    EXPECT_LE(l.triangles.size(), 6u);
    expectValidRegions(m, r.multires, l);
    expectValidPairs(m, l);
}

// Rule 2, exact case: two flat hexagon fans, the large one first (smaller vertex ids). Both centres
// collapse at deviation 0; the small fan's merged region has the lower E_region, so its centre (7)
// goes first although the large fan's centre has the smaller id.
TEST(Simplify, Rule2SmallerRegionsMergeFirst) {
    TriMesh m = test::hexagonFan();
    test::append(m, test::hexagonFan(), 0.5, Vec3{5, 0, 0});
    ASSERT_EQ(m.triangleCount(), 12u);
    SimplifyOptions o = withLevels({count(10)});
    SimplifyResult r = simplify(m, o);
    ASSERT_EQ(r.multires.collapses.size(), 1u);
    EXPECT_EQ(r.multires.collapses[0].removed, 7u);
    EXPECT_NEAR(r.multires.collapses[0].deviation, 0.f, 1e-9);
    expectValidRegions(m, r.multires, r.multires.levels[0]);
    expectValidPairs(m, r.multires.levels[0]);
}

// Component pruning: a big closed sphere and 12 small closed spheres. Each small sphere cannot go
// below a tetrahedron with two regions, so 2 % is only reachable by removing them: they are pruned
// (a CollapseRecord with kept == removed per surviving vertex; no pairs for their vertices, nor for
// the vertices that had collapsed into them; their faces keep their regions) and the big sphere is
// simplified to the target.
TEST(Simplify, PrunesSmallClosedComponents) {
    TriMesh m = test::sphere(3);  // 512 faces, radius 1
    for (int k = 0; k < 12; ++k) test::append(m, test::sphere(1), 0.02, Vec3{3.0 + 0.2 * k, 0, 0});  // 32 faces each
    size_t bigVertices = test::sphere(3).positions.size();
    ASSERT_EQ(m.triangleCount(), 512u + 12 * 32);
    SimplifyResult r = simplify(m, withLevels({ratio(0.02)}));
    const Multires& mr = r.multires;
    const Level& l = mr.levels[0];
    uint64_t target = uint64_t(std::llround(0.02 * m.triangleCount()));
    EXPECT_EQ(l.stopReason, "target");
    EXPECT_LE(l.triangles.size(), target);
    EXPECT_GE(l.triangles.size(), target - 1);
    // Every surviving triangle is on the big sphere; it stays watertight with >= 2 regions.
    std::set<uint32_t> kept, pruned;
    for (const Tri& t : l.triangles)
        for (uint32_t v : t) {
            EXPECT_LT(v, bigVertices);
            kept.insert(v);
        }
    for (const auto& [edge, ts] : edgesOf(l.triangles)) EXPECT_EQ(ts.size(), 2u);
    std::set<uint32_t> bigRegions;
    for (uint32_t f : l.faces) bigRegions.insert(l.faceRegion[f]);
    EXPECT_GE(bigRegions.size(), 2u);
    // Pruned vertices: kept == removed, no region updates, deviation = half the small box diagonal.
    for (const CollapseRecord& c : mr.collapses)
        if (c.kept == c.removed) {
            pruned.insert(c.removed);
            EXPECT_GE(c.removed, bigVertices);
            EXPECT_EQ(c.regionBegin, c.regionEnd);
            EXPECT_NEAR(c.deviation, 0.5 * 0.02 * std::sqrt(12.0), 1e-5);
            EXPECT_LE(c.deviation, l.maxDeviation);
        }
    EXPECT_FALSE(pruned.empty());
    // Regions replay; surviving faces' regions are represented by surviving faces; pruned faces
    // keep their regions (each small sphere kept >= 2 regions, rule 1).
    EXPECT_EQ(replayRegions(m.triangleCount(), mr, l), l.faceRegion);
    std::set<uint32_t> alive(l.faces.begin(), l.faces.end());
    for (uint32_t f : l.faces) EXPECT_TRUE(alive.count(l.faceRegion[f]));
    for (int k = 0; k < 12; ++k) {
        std::set<uint32_t> regions;
        for (uint32_t f = 512 + 32 * uint32_t(k); f < 512 + 32 * uint32_t(k + 1); ++f) regions.insert(l.faceRegion[f]);
        EXPECT_GE(regions.size(), 2u);
    }
    std::set<uint32_t> reps(l.faceRegion.begin(), l.faceRegion.end());
    EXPECT_EQ(reps.size(), l.regionCount);
    // Pairs: the removed vertices of the big sphere only.
    EXPECT_EQ(l.pairs.size(), bigVertices - kept.size());
    for (const SimplificationPair& p : l.pairs) {
        EXPECT_LT(p.vertex, bigVertices);
        EXPECT_TRUE(alive.count(p.face));
        EXPECT_LE(p.deviation, l.maxDeviation + 1e-6);
    }
}

// Parts by visual weight: an open hemisphere (radius 1, 128 faces) holds 20 small "books" of
// three triangles sharing one edge (a non-manifold spine: locked, so each book is stuck at three
// faces). 60 stuck faces exceed a 40-face target: by size alone (visualWeight = false) the open
// books wait until the level is stuck, so the hemisphere is collapsed down to a sliver first; by
// visual weight every book smaller than the pass limit leaves in the pass and the hemisphere keeps
// the budget and most of its area.
//
//        c1  c2  c3         one book: faces (a, b, c_k), k = 1..3, around the spine a-b
//         \  |  /
//      a ---spine--- b
TEST(Simplify, StuckSmallPartsArePrunedBeforeALargeOpenSurfaceShrinks) {
    const TriMesh dome = test::hemisphere(3);
    TriMesh m = dome;
    for (int k = 0; k < 20; ++k) {
        const uint32_t o = uint32_t(m.positions.size());
        const double x = -0.5 + 0.05 * k, s = 0.04;
        m.positions.push_back({x, 0, 0.1});
        m.positions.push_back({x, 0, 0.1 + s});
        for (int page = 0; page < 3; ++page) {
            const double a = 2.0944 * page;
            m.positions.push_back({x + s * std::cos(a), s * std::sin(a), 0.1 + 0.5 * s});
            m.triangles.push_back({o, o + 1, o + 2 + uint32_t(page)});
        }
    }
    test::addDefaultWedges(m);
    auto areaOf = [&](const std::vector<Tri>& tris) {  // dome vertex ids are the same in m
        double sum = 0;
        for (const Tri& t : tris) {
            const auto& P = m.positions;
            sum += 0.5 * length(cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]));
        }
        return sum;
    };
    auto area = [&](const Level& l) { return areaOf(l.triangles); };
    const double domeArea = areaOf(dome.triangles);
    SimplifyOptions o = withLevels({count(40)});
    const SimplifyResult weighted = simplify(m, o);
    const Level& l = weighted.multires.levels[0];
    EXPECT_EQ(l.stopReason, "target");
    EXPECT_GE(l.triangles.size(), 39u);
    for (const Tri& t : l.triangles)
        for (uint32_t v : t) EXPECT_LT(v, dome.positions.size()) << "a book survived while the dome shrank";
    EXPECT_GT(area(l), 0.8 * domeArea);
    // Regions replay; the surviving faces' regions are represented by surviving faces.
    EXPECT_EQ(replayRegions(m.triangleCount(), weighted.multires, l), l.faceRegion);
    std::set<uint32_t> alive(l.faces.begin(), l.faces.end());
    for (uint32_t f : l.faces) EXPECT_TRUE(alive.count(l.faceRegion[f]));

    o.visualWeight = false;
    o.grossError = 0;  // by size the dome shrinks further than the gross-error bound
    const SimplifyResult bySize = simplify(m, o);
    EXPECT_LT(area(bySize.multires.levels[0]), 0.5 * domeArea);
}

// Without a reachable target nothing is pruned: the last faces always stay.
TEST(Simplify, PruningKeepsTheLastComponent) {
    TriMesh m = test::sphere(1);
    test::append(m, test::sphere(1), 0.1, Vec3{3, 0, 0});
    SimplifyResult r = simplify(m, withLevels({count(1)}));
    const Level& l = r.multires.levels[0];
    EXPECT_NE(l.stopReason, "target");
    EXPECT_GE(l.triangles.size(), 4u);
}

TEST(Simplify, ProgressCanCancel) {
    TriMesh m = test::sphere(5);
    SimplifyOptions o = withLevels({ratio(0.01)});
    int calls = 0;
    o.progress = [&](double f) {
        EXPECT_GE(f, 0.0);
        EXPECT_LE(f, 1.0);
        return ++calls < 1;
    };
    // The caller's decision, not a verdict on the input: Cancelled, not Impossible.
    EXPECT_THROW(simplify(m, o), Cancelled);
}

// Benchmark, not a test: LODBAKE_BENCH=1 to run. ~1M-triangle noisy grid to 1 %; writes
// /tmp/lodbake_bench.obj so gltfpack can be timed on the same input.
TEST(Simplify, Benchmark1M) {
    if (!std::getenv("LODBAKE_BENCH")) GTEST_SKIP() << "set LODBAKE_BENCH=1";
    int n = 708;
    TriMesh m = test::grid(n, n, [](int i, int j) {
        return 3.0 * std::sin(0.05 * i) * std::cos(0.07 * j) + 0.02 * std::sin(12.9898 * i + 78.233 * j);
    });
    auto t0 = std::chrono::steady_clock::now();
    SimplifyResult r = simplify(m, withLevels({ratio(0.01)}));
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("simplify %zu -> %zu triangles in %.2f s (regions %u, maxDev %.4g)\n", m.triangleCount(),
                r.multires.levels[0].triangles.size(), s, r.multires.levels[0].regionCount,
                r.multires.levels[0].maxDeviation);
    if (FILE* f = std::fopen("/tmp/lodbake_bench.obj", "w")) {
        for (Vec3 p : m.positions) std::fprintf(f, "v %.6f %.6f %.6f\n", p.x, p.y, p.z);
        for (Tri t : m.triangles) std::fprintf(f, "f %u %u %u\n", t[0] + 1, t[1] + 1, t[2] + 1);
        std::fclose(f);
    }
}

}  // namespace
}  // namespace lodbake
