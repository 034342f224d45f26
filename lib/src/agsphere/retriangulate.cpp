// Retriangulation of the regions of one cut (thesis 2.4: "each region is retriangulated in its
// cell's plane"), and the fallbacks that keep the level valid.
//
//   retriangulate   ear clipping (polygon.cpp) of the region's kept boundary loops, projected onto
//                   the plane orthogonal to the region's area-weighted normal, else onto its cell's
//                   plane; ears facing away from the region are vetoed
//   fail            a region that cannot be built, or whose new triangles push a view's outline
//                   out, gets its runs restored (its neighbours are rebuilt), then keeps its
//                   original faces
//   validate        regions whose triangles repeat a directed edge, or use an undirected edge more
//                   than twice where the input does not, are retried once keeping off the edges
//                   every other region uses, then failed
#include "agsphere/retriangulate.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <unordered_map>
#include <unordered_set>

#include "lodbake/agsphere/polygon.h"

namespace lodbake::agsphere_detail {
namespace {

// Smallest cosine between a new triangle's normal and its region's area-weighted normal.
constexpr double kMinFacingCos = 0.01;
// Rounds of building and validating a level before it is taken as it is.
constexpr int kMaxPasses = 1000;

using EdgeCounts = std::unordered_map<uint64_t, uint32_t>;

template <class Fn>
void forEachEdge(const Tri& tr, Fn&& fn) {
    for (int k = 0; k < 3; ++k) fn(tr[size_t(k)], tr[size_t((k + 1) % 3)]);
}

// Retriangulates region i from its loops; false when it cannot. The boundary is projected onto
// the plane orthogonal to the region's area-weighted normal (where positive orientation is exactly
// "facing the region's surface"), else onto its cell's plane (thesis) with that facing condition
// as a veto on the ears. forbidden (may be null): undirected edges (edgeKey) no ear may create.
bool retriangulate(const Topology& t, const Regions& r, const Runs& R, uint32_t i, RegionOut& out,
                   const std::unordered_set<uint64_t>* forbidden) {
    out.tris.clear();
    auto loops = regionLoops(t, r, R, i);
    if (loops.empty()) return false;
    Vec3 rn;
    for (uint32_t k = r.faceOffset[i]; k < r.faceOffset[i + 1]; ++k) {
        const Tri& tr = t.T(r.faces[k]);
        rn += cross(t.P(tr[1]) - t.P(tr[0]), t.P(tr[2]) - t.P(tr[0]));
    }
    rn = normalize(rn);
    const Vec3 cellAxis = t.frame.toModel(sphereCellCenter(r.cell[i].index, r.cell[i].depth));
    // Loop vertices renumbered densely (local ids index `global`).
    std::unordered_map<uint32_t, uint32_t> local;
    std::vector<uint32_t> global;
    std::vector<std::vector<uint32_t>> ids;
    for (const auto& loop : loops) {
        ids.emplace_back();
        for (uint32_t v : loop) {
            auto [it, inserted] = local.emplace(v, uint32_t(global.size()));
            if (inserted) global.push_back(v);
            ids.back().push_back(it->second);
        }
    }
    std::function<bool(uint32_t, uint32_t)> allow;
    if (forbidden)
        allow = [&](uint32_t a, uint32_t b) { return !forbidden->count(edgeKey(global[a], global[b])); };
    auto facing = [&](uint32_t a, uint32_t b, uint32_t c) {
        Vec3 pa = t.P(global[a]);
        Vec3 n = normalize(cross(t.P(global[b]) - pa, t.P(global[c]) - pa));
        return dot(n, rn) > kMinFacingCos;
    };
    for (Vec3 n : {rn, cellAxis}) {
        if (!(length(n) > 0.5)) continue;
        Vec3 a = std::fabs(n.x) < 0.6 ? Vec3{1, 0, 0} : (std::fabs(n.y) < 0.6 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
        Vec3 u = normalize(cross(n, a)), w = cross(n, u);
        PlanarPolygon poly;
        poly.loops = ids;
        for (uint32_t v : global) poly.points.push_back({dot(t.P(v), u), dot(t.P(v), w)});
        if (!polygonIsSimple(poly)) continue;
        std::vector<Tri> tris;
        if (!triangulatePolygon(poly, tris, allow, facing)) continue;
        for (const Tri& tr : tris) out.tris.push_back({global[tr[0]], global[tr[1]], global[tr[2]]});
        out.axis = n;
        return true;
    }
    return false;
}

// Retriangulates region i. With outline views (keepOutline), new triangles that cover, seen from
// a view, what the original leaves uncovered (flattening across a concave stretch of the outline)
// count as a failure.
bool tryRegion(const Topology& t, LevelBuild& L, uint32_t i, const std::unordered_set<uint64_t>* forbidden) {
    RegionOut& o = L.out[i];
    if (!retriangulate(t, L.regions, L.runs, i, o, forbidden)) return false;
    if (!t.outline.views.empty())
        for (const Tri& tr : o.tris)
            if (protrudes(t.outline, t.P(tr[0]), t.P(tr[1]), t.P(tr[2]))) {
                o.tris.clear();
                return false;
            }
    return true;
}

// Marks a failed region: restores its runs (appending the regions on both sides to `rebuild`)
// or, when they are all restored already, keeps its original faces.
void failRegion(const Topology& t, LevelBuild& L, const std::vector<std::vector<uint32_t>>& runsOf, uint32_t i,
                std::vector<uint32_t>& rebuild) {
    bool any = false;
    for (uint32_t ri : runsOf[i]) {
        Run& run = L.runs.runs[ri];
        if (run.restored || run.nonManifold) continue;
        run.restored = true;
        ++L.restoredRuns;
        simplifyRun(t, run, L.runs.kept);
        any = true;
        rebuild.push_back(run.regionA);
        if (run.regionB != kNone) rebuild.push_back(run.regionB);
    }
    if (!any) {
        RegionOut& o = L.out[i];
        o.state = RegionState::Kept;
        o.tris.clear();
        for (uint32_t k = L.regions.faceOffset[i]; k < L.regions.faceOffset[i + 1]; ++k)
            o.tris.push_back(t.T(L.regions.faces[k]));
    }
}

// Degenerate regions are empty, pinned ones keep their face; returns the regions to build.
std::vector<uint32_t> initialRegionStates(const Topology& t, LevelBuild& L) {
    std::vector<uint32_t> work;
    for (uint32_t i = 0; i < L.regions.count(); ++i) {
        if (t.degenerate[L.regions.rep[i]]) {
            L.out[i].state = RegionState::Empty;
            continue;
        }
        if (t.isPinned(L.regions.rep[i])) {
            L.out[i].state = RegionState::Kept;
            L.out[i].tris = {t.T(L.regions.rep[i])};
            continue;
        }
        work.push_back(i);
    }
    return work;
}

// Builds the regions in `work` (ascending, once each), and the neighbours of failed ones, until
// none is left.
void buildPending(const Topology& t, LevelBuild& L, const std::vector<std::vector<uint32_t>>& runsOf,
                  std::vector<uint32_t>& work) {
    while (!work.empty()) {
        std::sort(work.begin(), work.end());
        work.erase(std::unique(work.begin(), work.end()), work.end());
        std::vector<uint32_t> rebuild;
        for (uint32_t i : work) {
            RegionOut& o = L.out[i];
            if (o.state == RegionState::Kept || o.state == RegionState::Empty) continue;
            if (tryRegion(t, L, i, nullptr)) o.state = RegionState::Retriangulated;
            else failRegion(t, L, runsOf, i, rebuild);
        }
        work = std::move(rebuild);
    }
}

// Retriangulated regions with a triangle edge that repeats a directed edge or makes an undirected
// edge non-manifold, where the input's own edge is not used more than twice already.
std::vector<uint32_t> regionsBreakingManifold(const Topology& t, const LevelBuild& L) {
    const uint32_t nr = L.regions.count();
    EdgeCounts directed, undirected;
    for (uint32_t i = 0; i < nr; ++i)
        for (const Tri& tr : L.out[i].tris)
            forEachEdge(tr, [&](uint32_t a, uint32_t b) {
                ++directed[directedEdgeKey(a, b)];
                ++undirected[edgeKey(a, b)];
            });
    auto breaks = [&](uint32_t a, uint32_t b) { return directed[directedEdgeKey(a, b)] > 1 || undirected[edgeKey(a, b)] > 2; };
    std::vector<uint32_t> blamed;
    for (uint32_t i = 0; i < nr; ++i) {
        if (L.out[i].state != RegionState::Retriangulated) continue;
        bool bad = false;
        for (const Tri& tr : L.out[i].tris)
            forEachEdge(tr, [&](uint32_t a, uint32_t b) { bad = bad || breaks(a, b); });
        if (bad) blamed.push_back(i);
    }
    if (blamed.empty()) return {};
    // Edges that the input itself has more than twice are not the retriangulation's fault.
    EdgeCounts input;
    for (uint32_t f = 0; f < t.nf; ++f)
        if (!t.degenerate[f]) forEachEdge(t.T(f), [&](uint32_t a, uint32_t b) { ++input[edgeKey(a, b)]; });
    std::vector<uint32_t> really;
    for (uint32_t i : blamed) {
        bool bad = false;
        for (const Tri& tr : L.out[i].tris)
            forEachEdge(tr, [&](uint32_t a, uint32_t b) {
                if (bad) return;
                auto it = input.find(edgeKey(a, b));
                bool inputBad = it != input.end() && it->second > 2;
                if (!inputBad && breaks(a, b)) bad = true;
            });
        if (bad) really.push_back(i);
    }
    return really;
}

// Each region of `bad` in turn: retriangulated once more keeping off the edges every other region
// uses (then those counts include its new triangles), else failed; regions to rebuild go to `work`.
void retryAvoidingOtherEdges(const Topology& t, LevelBuild& L, const std::vector<std::vector<uint32_t>>& runsOf,
                             const std::vector<uint32_t>& bad, std::vector<char>& triedForbidden,
                             std::vector<uint32_t>& work) {
    EdgeCounts uses;
    for (const RegionOut& o : L.out)
        for (const Tri& tr : o.tris) forEachEdge(tr, [&](uint32_t a, uint32_t b) { ++uses[edgeKey(a, b)]; });
    for (uint32_t i : bad) {
        RegionOut& o = L.out[i];
        std::unordered_set<uint64_t> forbidden;
        for (const Tri& tr : o.tris)
            forEachEdge(tr, [&](uint32_t a, uint32_t b) {
                uint64_t e = edgeKey(a, b);
                if (--uses[e] == 0) uses.erase(e);
            });
        for (const auto& [e, n] : uses) forbidden.insert(e);
        bool ok = !triedForbidden[i] && tryRegion(t, L, i, &forbidden);
        triedForbidden[i] = 1;
        if (!ok) failRegion(t, L, runsOf, i, work);
        for (const Tri& tr : o.tris) forEachEdge(tr, [&](uint32_t a, uint32_t b) { ++uses[edgeKey(a, b)]; });
    }
}

}  // namespace

LevelBuild buildLevelGeometry(const Topology& t, const Cut& cut, double boundaryTolerance) {
    LevelBuild L;
    L.regions = buildRegions(t, cut);
    L.runs = buildBoundaryRuns(t, L.regions, boundaryTolerance);
    const uint32_t nr = L.regions.count();
    L.out.assign(nr, {});
    const auto runsOf = regionRuns(L.runs, nr);
    std::vector<uint32_t> work = initialRegionStates(t, L);
    std::vector<char> triedForbidden(nr, 0);
    for (int pass = 0; pass < kMaxPasses && !work.empty(); ++pass) {
        buildPending(t, L, runsOf, work);
        std::vector<uint32_t> bad = regionsBreakingManifold(t, L);
        if (!bad.empty()) retryAvoidingOtherEdges(t, L, runsOf, bad, triedForbidden, work);
    }
    return L;
}

uint64_t levelTriangleCount(const LevelBuild& level) {
    uint64_t n = 0;
    for (const RegionOut& o : level.out) n += o.tris.size();
    return n;
}

}  // namespace lodbake::agsphere_detail
