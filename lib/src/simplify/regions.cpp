// Regions, p-boundaries, region records and E_region (regions.h, docs/simplify.md).

#include "regions.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "lodbake/core/math.h"
#include "lodbake/core/parallel.h"

namespace lodbake::simplify_detail {

constexpr size_t kStatsChunk = 16384;  // faces per chunk of the initial region stats

void initRegions(RegionState& r, const CollapseState& s, int threads) {
    const auto& P = s.mesh.positions;
    r.faceRelabelPass.assign(s.faceCount, 0);
    r.faceRegion.resize(s.faceCount);
    std::iota(r.faceRegion.begin(), r.faceRegion.end(), 0u);
    r.regionNext.assign(s.faceCount, kNone);
    r.lists.resize(s.faceCount);
    for (uint32_t f = 0; f < s.faceCount; ++f) r.lists[f] = {f, f, 1};
    r.stats.resize(s.faceCount);
    parallelChunks(s.faceCount, kStatsChunk, threads, [&](size_t begin, size_t end, size_t) {
        for (size_t f = begin; f < end; ++f) {
            const Tri& t = s.tri[f];
            Vec3 n = cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);
            RegionStats& st = r.stats[f];
            st.area = 0.5 * length(n);
            st.normalSum = n * 0.5;
            for (int k = 0; k < 3; ++k) {
                st.bmin[k] = float(std::min({P[t[0]][k], P[t[1]][k], P[t[2]][k]}));
                st.bmax[k] = float(std::max({P[t[0]][k], P[t[1]][k], P[t[2]][k]}));
            }
        }
    });
    for (const RegionStats& st : r.stats) r.totalArea += st.area;  // in face order, one sum for any threads
    r.regionCount = uint32_t(s.faceCount);
    r.componentRegions.assign(s.components.count(), 0);
    for (const Tri& t : s.mesh.triangles) ++r.componentRegions[s.componentOf(t[0])];
}

void mergeStats(RegionStats& a, const RegionStats& b) {
    a.area += b.area;
    a.normalSum += b.normalSum;
    for (int k = 0; k < 3; ++k) {
        a.bmin[k] = std::min(a.bmin[k], b.bmin[k]);
        a.bmax[k] = std::max(a.bmax[k], b.bmax[k]);
    }
}

float regionShape(const RegionStats& r, double totalArea) {
    if (!(r.area > 0) || !(totalArea > 0)) return 0.f;
    Vec3 ext{double(r.bmax[0] - r.bmin[0]), double(r.bmax[1] - r.bmin[1]), double(r.bmax[2] - r.bmin[2])};
    double h = 0.5 * length(ext);
    double flat = std::max(0.0, 1.0 - length(r.normalSum) / r.area) * h;
    double spread = std::max(0.0, h - std::sqrt(r.area / kPi));
    return float(r.area / totalArea * (flat + spread));
}

static void sortUnique(std::vector<uint32_t>& v, size_t from) {
    std::sort(v.begin() + from, v.end());
    v.erase(std::unique(v.begin() + from, v.end()), v.end());
}

void collectMergeGroups(const CollapseState& s, const RegionState& r, uint32_t vi, const std::vector<uint32_t>& fan,
                        MergeGroups& out) {
    const auto& fs = s.vfaces[vi];
    out.regions.clear();
    out.start.assign(1, 0);
    if (!s.pinch[vi]) {
        for (uint32_t f : fs) out.regions.push_back(r.faceRegion[f]);
        sortUnique(out.regions, 0);
        out.start.push_back(uint32_t(out.regions.size()));
        return;
    }
    // Fans sharing a region are joined; each resulting group of fans is one merge.
    const uint32_t fans = fan.empty() ? 0 : *std::max_element(fan.begin(), fan.end()) + 1;
    std::vector<uint32_t> parent(fans);
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (size_t a = 0; a < fs.size(); ++a)
        for (size_t b = a + 1; b < fs.size(); ++b)
            if (fan[a] != fan[b] && r.faceRegion[fs[a]] == r.faceRegion[fs[b]]) parent[root(fan[a])] = root(fan[b]);
    for (uint32_t g = 0; g < fans; ++g) {
        size_t from = out.regions.size();
        for (size_t k = 0; k < fs.size(); ++k)
            if (root(fan[k]) == g) out.regions.push_back(r.faceRegion[fs[k]]);
        if (out.regions.size() == from) continue;
        sortUnique(out.regions, from);
        out.start.push_back(uint32_t(out.regions.size()));
    }
}

// Merges the regions reps[0 .. n) (distinct) into one, union by size: every smaller region is
// relabelled into the largest (ties: a representative that survives the collapse (vi -> vj), then
// the smaller id), so each face is relabelled O(log F) times in total. The representative may be
// (or become) a removed face; fixDeadRepresentatives() re-elects a surviving one at a snapshot.
static void mergeRegionGroup(RegionState& r, const CollapseState& s, HierarchyRecorder& rec, const uint32_t* reps,
                             size_t n, uint32_t vi, uint32_t vj, uint32_t pass) {
    uint32_t newRep = kNone;
    bool newAlive = false;
    for (size_t k = 0; k < n; ++k) {
        uint32_t g = reps[k];
        bool alive = s.faceAlive[g] && !(s.corner(g, vi) >= 0 && s.corner(g, vj) >= 0);
        if (newRep == kNone || r.lists[g].size > r.lists[newRep].size ||
            (r.lists[g].size == r.lists[newRep].size && alive && !newAlive)) {
            newRep = g;
            newAlive = alive;
        }
    }
    for (size_t k = 0; k < n; ++k) {
        uint32_t g = reps[k];
        if (g == newRep) continue;
        rec.regionMoved(g, newRep);
        for (uint32_t f = r.lists[g].head; f != kNone; f = r.regionNext[f]) {
            r.faceRegion[f] = newRep;
            r.faceRelabelPass[f] = pass;
        }
        r.regionNext[r.lists[newRep].tail] = r.lists[g].head;
        r.lists[newRep].tail = r.lists[g].tail;
        r.lists[newRep].size += r.lists[g].size;
        mergeStats(r.stats[newRep], r.stats[g]);
        r.lists[g].size = 0;
    }
    r.regionCount -= uint32_t(n - 1);
}

void updateRegions(RegionState& r, const CollapseState& s, HierarchyRecorder& rec, uint32_t vi, uint32_t vj,
                   bool keepsBoundary, uint32_t pass, const MergeGroups* planned) {
    if (keepsBoundary) return;  // each side keeps its own region (a removed representative stays until the snapshot)
    if (!planned) {
        std::vector<uint32_t>& fan = r.fanScratch;
        if (s.pinch[vi]) {
            collectRing(s, vi, r.ringScratch);
            labelFans(s, vi, r.ringScratch, fan);
        }
        collectMergeGroups(s, r, vi, fan, r.groupScratch);
        planned = &r.groupScratch;
    }
    const MergeGroups& groups = *planned;
    for (size_t g = 0; g < groups.count(); ++g) {
        size_t n = groups.size(g);
        if (n < 2) continue;
        r.componentRegions[s.componentOf(vi)] -= uint32_t(n - 1);
        mergeRegionGroup(r, s, rec, groups.begin(g), n, vi, vj, pass);
    }
}

void fixDeadRepresentatives(RegionState& r, const CollapseState& s, HierarchyRecorder& rec, uint32_t pass) {
    if (rec.out.collapses.empty()) return;
    for (uint32_t g = 0; g < s.faceCount; ++g) {
        if (s.faceAlive[g] || r.lists[g].size == 0 || r.faceRegion[g] != g) continue;
        uint32_t m = kNone;
        for (uint32_t f = r.lists[g].head; f != kNone; f = r.regionNext[f])
            if (s.faceAlive[f] && f < m) m = f;
        if (m == kNone) continue;  // cannot happen: every region keeps a surviving face
        rec.regionMoved(g, m);
        for (uint32_t f = r.lists[g].head; f != kNone; f = r.regionNext[f]) {
            r.faceRegion[f] = m;
            r.faceRelabelPass[f] = pass;
        }
        r.lists[m] = r.lists[g];
        r.stats[m] = r.stats[g];
        r.lists[g].size = 0;
    }
    rec.out.collapses.back().regionEnd = rec.regionMark();
}

}  // namespace lodbake::simplify_detail
