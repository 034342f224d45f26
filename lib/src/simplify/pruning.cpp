// Removal of small and stuck parts (pruning.h, docs/simplify.md).

#include "pruning.h"

#include <algorithm>
#include <limits>
#include <vector>

namespace lodbake::simplify_detail {

// Removes component `comp` entirely: its faces leave the level (they keep their regions, so their
// representatives are not surviving faces) and its vertices are removed without a collapse target.
static void pruneComponent(CollapseState& s, HierarchyRecorder& rec, uint32_t comp) {
    Components& c = s.components;
    c.pruned[comp] = 1;
    float dev = float(c.size[comp]);
    uint32_t at = rec.regionMark();
    for (uint32_t k = c.vertexStart[comp]; k < c.vertexStart[comp + 1]; ++k) {
        uint32_t v = c.vertices[k];
        if (s.removed[v] || s.vfaces[v].empty()) continue;
        for (uint32_t f : s.vfaces[v])
            if (s.faceAlive[f]) {
                s.faceAlive[f] = 0;
                --s.aliveFaces;
            }
    }
    for (uint32_t k = c.vertexStart[comp]; k < c.vertexStart[comp + 1]; ++k) {
        uint32_t v = c.vertices[k];
        if (s.removed[v] || s.vfaces[v].empty()) continue;
        s.vfaces[v].release();
        s.removed[v] = 1;
        s.collapsedInto[v] = kNone;
        rec.collapsed({v, v, dev, at, at});
    }
    c.faces[comp] = 0;
    rec.accepted(double(dev));
}

void orderByVisualWeight(CollapseState& s) {
    Components& c = s.components;
    std::vector<double> area(c.count(), 0.0);
    const auto& P = s.mesh.positions;
    for (const Tri& t : s.mesh.triangles)
        area[c.label[t[0]]] += triangleArea(P[t[0]], P[t[1]], P[t[2]]);
    std::sort(c.order.begin(), c.order.end(), [&](uint32_t a, uint32_t b) {
        if (area[a] != area[b]) return area[a] < area[b];
        if (c.size[a] != c.size[b]) return c.size[a] < c.size[b];
        return a < b;
    });
}

std::vector<uint8_t> stuckComponents(const CollapseState& s, const CandidateState& c) {
    const Components& comps = s.components;
    std::vector<uint8_t> stuck(comps.count(), 1);
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (!s.removed[v] && !s.vfaces[v].empty() && (c.deferred[v] || c.cand[v].reason == Reject::None))
            stuck[comps.label[v]] = 0;
    return stuck;
}

bool anyPrunable(const CollapseState& s, double limit, uint64_t target) {
    if (s.aliveFaces <= target) return false;
    const Components& c = s.components;
    for (uint32_t comp : c.order)
        if (!c.pruned[comp]) return c.size[comp] < limit;
    return false;
}

bool pruneComponents(CollapseState& s, HierarchyRecorder& rec, double limit, uint64_t target, bool closedOnly,
                     const std::vector<uint8_t>* stuck) {
    const Components& c = s.components;
    bool any = false;
    for (uint32_t comp : c.order) {
        if (s.aliveFaces <= target) break;
        if (c.pruned[comp]) continue;
        if (!(c.size[comp] < limit)) break;
        if (c.open[comp] != 0 && (closedOnly || (stuck && !(*stuck)[comp]))) continue;
        // Never undershoot the target, never prune the last faces.
        if (s.aliveFaces - c.faces[comp] < std::max<uint64_t>(target, 1)) continue;
        pruneComponent(s, rec, comp);
        any = true;
    }
    return any;
}

double nextPrunableSize(const CollapseState& s, uint64_t target, bool closedOnly) {
    const Components& c = s.components;
    if (s.aliveFaces <= target) return std::numeric_limits<double>::infinity();
    for (uint32_t comp : c.order) {
        if (c.pruned[comp] || (closedOnly && c.open[comp] != 0)) continue;
        if (s.aliveFaces - c.faces[comp] < std::max<uint64_t>(target, 1)) continue;
        return c.size[comp];
    }
    return std::numeric_limits<double>::infinity();
}

}  // namespace lodbake::simplify_detail
