// Boundary runs of the regions of a cut and their simplification (thesis 2.4: each shared
// boundary is simplified once, the same way for both regions, so neighbours never crack).
//
//   collect      every boundary edge once, with the (ordered) pair of regions it separates
//   junctions    vertices where the boundary branches, ends, or changes its region pair
//   walk         runs from junction to junction; closed loops anchored at their smallest vertex
//   tolerances   per run: scale * the smaller error threshold of its two cells (with a floor)
//   simplify     Douglas-Peucker per run, then extra vertices where two runs' simplified edges
//                coincide (a thin region between them would vanish)
#include "agsphere/boundary_runs.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

namespace lodbake::agsphere_detail {
namespace {

struct BoundaryEdge {
    uint32_t a, b;     // vertices
    uint32_t h;        // a half-edge carrying it
    uint32_t regionA, regionB;
    bool nonManifold;
};

// The boundary edges and, per vertex, the boundary edges at it.
struct BoundaryGraph {
    std::vector<BoundaryEdge> edges;
    CompressedRows incident;  // vertex -> edge ids
};

BoundaryGraph collectBoundaryEdges(const Topology& t, const Regions& r) {
    BoundaryGraph g;
    for (uint32_t f = 0; f < t.nf; ++f) {
        if (t.degenerate[f]) continue;
        for (uint32_t k = 0; k < 3; ++k) {
            uint32_t h = 3 * f + k;
            if (!isBoundary(t, r, h)) continue;
            uint32_t o = t.twin[h];
            if (o < kNonManifoldEdge && o < h) continue;  // the twin already made it
            BoundaryEdge e;
            e.a = t.T(f)[k];
            e.b = t.T(f)[(k + 1) % 3];
            e.h = h;
            e.regionA = r.of[f];
            e.regionB = o < kNonManifoldEdge ? r.of[o / 3] : kNone;
            if (e.regionB != kNone && e.regionB < e.regionA) std::swap(e.regionA, e.regionB);
            e.nonManifold = o == kNonManifoldEdge;
            g.edges.push_back(e);
        }
    }
    auto& off = g.incident.offsets;
    auto& inc = g.incident.items;
    off.assign(t.nv + 1, 0);
    for (const auto& e : g.edges) ++off[e.a + 1], ++off[e.b + 1];
    for (uint32_t v = 0; v < t.nv; ++v) off[v + 1] += off[v];
    inc.resize(off[t.nv]);
    std::vector<uint32_t> fill(off.begin(), off.end() - 1);
    for (uint32_t i = 0; i < g.edges.size(); ++i) inc[fill[g.edges[i].a]++] = i, inc[fill[g.edges[i].b]++] = i;
    return g;
}

// Junctions: boundary vertices without exactly two boundary edges of the same region pair.
void markJunctions(const Topology& t, const BoundaryGraph& g, Runs& out) {
    for (uint32_t v = 0; v < t.nv; ++v) {
        size_t n = g.incident.size(v);
        if (n == 0) continue;
        if (n != 2) {
            out.junction[v] = 1;
            continue;
        }
        const BoundaryEdge& e0 = g.edges[g.incident.begin(v)[0]];
        const BoundaryEdge& e1 = g.edges[g.incident.begin(v)[1]];
        if (e0.nonManifold || e1.nonManifold || e0.regionA != e1.regionA || e0.regionB != e1.regionB) out.junction[v] = 1;
    }
}

// Appends the run leaving junction `start` along unused edge `firstEdge`, up to the next junction.
void walkRun(const BoundaryGraph& g, uint32_t start, uint32_t firstEdge, std::vector<char>& used, Runs& out) {
    Run run;
    const BoundaryEdge& e = g.edges[firstEdge];
    run.regionA = e.regionA;
    run.regionB = e.regionB;
    run.nonManifold = e.nonManifold;
    run.vertices.push_back(start);
    uint32_t v = start, ei = firstEdge;
    for (;;) {
        used[ei] = 1;
        uint32_t w = g.edges[ei].a == v ? g.edges[ei].b : g.edges[ei].a;
        run.vertices.push_back(w);
        if (out.junction[w]) break;
        uint32_t next = kNone;
        for (const uint32_t* k = g.incident.begin(w); k != g.incident.end(w); ++k)
            if (!used[*k]) next = *k;
        if (next == kNone) break;
        v = w;
        ei = next;
    }
    uint32_t id = uint32_t(out.runs.size());
    for (size_t i = 1; i + 1 < run.vertices.size(); ++i) {
        out.runOf[run.vertices[i]] = id;
        out.posInRun[run.vertices[i]] = uint32_t(i);
    }
    out.runs.push_back(std::move(run));
}

// Closed loops without a junction: their smallest vertex becomes one, and the loop a run.
void walkClosedLoops(const BoundaryGraph& g, std::vector<char>& used, Runs& out) {
    for (uint32_t i = 0; i < g.edges.size(); ++i) {
        if (used[i]) continue;
        uint32_t v = g.edges[i].a, ei = i, smallest = v;
        std::unordered_set<uint32_t> seen;
        for (;;) {
            if (!seen.insert(ei).second) break;
            uint32_t w = g.edges[ei].a == v ? g.edges[ei].b : g.edges[ei].a;
            smallest = std::min(smallest, w);
            uint32_t next = kNone;
            for (const uint32_t* k = g.incident.begin(w); k != g.incident.end(w); ++k)
                if (*k != ei && !seen.count(*k)) next = *k;
            if (next == kNone) break;
            v = w;
            ei = next;
        }
        out.junction[smallest] = 1;
        for (const uint32_t* k = g.incident.begin(smallest); k != g.incident.end(smallest); ++k)
            if (!used[*k]) {
                walkRun(g, smallest, *k, used, out);
                break;
            }
    }
}

Runs buildRuns(const Topology& t, const Regions& r) {
    Runs out;
    out.junction.assign(t.nv, 0);
    out.runOf.assign(t.nv, kNone);
    out.posInRun.assign(t.nv, 0);
    out.kept.assign(t.nv, 0);
    const BoundaryGraph g = collectBoundaryEdges(t, r);
    markJunctions(t, g, out);
    std::vector<char> used(g.edges.size(), 0);
    for (uint32_t v = 0; v < t.nv; ++v) {
        if (!out.junction[v]) continue;
        for (const uint32_t* k = g.incident.begin(v); k != g.incident.end(v); ++k)
            if (!used[*k]) walkRun(g, v, *k, used, out);
    }
    walkClosedLoops(g, used, out);
    for (uint32_t v = 0; v < t.nv; ++v) out.kept[v] = out.junction[v];
    return out;
}

// Cell error threshold (thesis: "each cell has maximum vertex deviation as an error threshold"):
// the largest flatness over the regions of the cell.
std::unordered_map<uint64_t, double> cellThresholds(const Regions& r) {
    std::unordered_map<uint64_t, double> tau;
    for (uint32_t i = 0; i < r.count(); ++i) {
        double& v = tau[cellKey(r.cell[i])];
        v = std::max(v, r.flatness[i]);
    }
    return tau;
}

void setTolerances(const Topology& t, const Regions& r, Runs& R, double scale) {
    auto tau = cellThresholds(r);
    const double floor = 1e-9 * t.diagonal;
    for (Run& run : R.runs) {
        double a = tau[cellKey(r.cell[run.regionA])];
        double b = run.regionB != kNone ? tau[cellKey(r.cell[run.regionB])] : a;
        run.tolerance = std::max(scale * std::min(a, b), floor);
    }
}

// Runs next to an outline face keep every vertex (the face stays as it is).
void pinRuns(const Topology& t, const Regions& r, Runs& R) {
    if (t.pinned.empty()) return;
    for (Run& run : R.runs)
        if (t.isPinned(r.rep[run.regionA]) || (run.regionB != kNone && t.isPinned(r.rep[run.regionB])))
            run.restored = true;
}

// Keeps one more vertex of a run: the removed one farthest from its simplified edge. Returns
// false when every vertex is kept already.
bool refineRun(const Topology& t, const Run& run, std::vector<char>& kept) {
    const auto& v = run.vertices;
    size_t best = 0;
    double bestD = -1;
    for (size_t a = 0; a + 1 < v.size();) {
        size_t b = a + 1;
        while (b + 1 < v.size() && !kept[v[b]]) ++b;
        for (size_t k = a + 1; k < b; ++k) {
            double d = pointSegmentDistance(t.P(v[k]), t.P(v[a]), t.P(v[b]));
            if (d > bestD) bestD = d, best = k;
        }
        a = b;
    }
    if (bestD < 0) return false;
    kept[v[best]] = 1;
    return true;
}

// Pairs (later run, earlier run) whose simplified edges coincide.
std::vector<std::pair<uint32_t, uint32_t>> coincidingRuns(const Runs& R) {
    std::unordered_map<uint64_t, uint32_t> owner;
    std::vector<std::pair<uint32_t, uint32_t>> clash;
    for (uint32_t i = 0; i < R.runs.size(); ++i) {
        const auto& v = R.runs[i].vertices;
        uint32_t prev = v[0];
        for (size_t k = 1; k < v.size(); ++k) {
            if (k + 1 < v.size() && !R.kept[v[k]]) continue;
            auto [it, inserted] = owner.emplace(edgeKey(prev, v[k]), i);
            if (!inserted) clash.push_back({i, it->second});
            prev = v[k];
        }
    }
    return clash;
}

// Simplifies every run; where two runs' simplified edges coincide, the later run (else the
// earlier) keeps one more vertex, round by round (at most 256 rounds).
void simplifyRuns(const Topology& t, Runs& R) {
    for (Run& run : R.runs) simplifyRun(t, run, R.kept);
    for (int round = 0; round < 256; ++round) {
        bool changed = false;
        std::unordered_set<uint32_t> touched;
        for (auto [a, b] : coincidingRuns(R)) {
            if (touched.count(a) || touched.count(b)) continue;
            bool fixed = false;
            for (uint32_t i : {a, b}) {
                Run& run = R.runs[i];
                if (run.restored || run.nonManifold) continue;
                if (refineRun(t, run, R.kept)) {
                    fixed = true;
                    touched.insert(i);
                    break;
                }
            }
            changed |= fixed;
        }
        if (!changed) break;
    }
}

}  // namespace

Runs buildBoundaryRuns(const Topology& t, const Regions& r, double toleranceScale) {
    Runs runs = buildRuns(t, r);
    setTolerances(t, r, runs, toleranceScale);
    pinRuns(t, r, runs);
    simplifyRuns(t, runs);
    return runs;
}

double pointSegmentDistance(Vec3 p, Vec3 a, Vec3 b, double* param) {
    Vec3 ab = b - a;
    double l2 = length2(ab);
    double s = l2 > 0 ? std::clamp(dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    if (param) *param = s;
    return length(p - (a + ab * s));
}

void simplifyRun(const Topology& t, Run& run, std::vector<char>& kept) {
    const auto& v = run.vertices;
    const size_t m = v.size() - 1;
    for (size_t i = 1; i < m; ++i) kept[v[i]] = 0;
    if (run.restored || run.nonManifold) {
        for (size_t i = 1; i < m; ++i) kept[v[i]] = 1;
        return;
    }
    std::vector<std::pair<size_t, size_t>> stack;
    auto farthest = [&](size_t i, size_t j, double& dist) {
        size_t best = i;
        dist = -1;
        for (size_t k = i + 1; k < j; ++k) {
            double d = pointSegmentDistance(t.P(v[k]), t.P(v[i]), t.P(v[j]));
            if (d > dist) dist = d, best = k;
        }
        return best;
    };
    if (v.front() == v.back()) {
        if (m < 3) return;
        // Split at the vertex farthest from v0, then keep the farthest of the remaining.
        size_t far = 1;
        double fd = -1;
        for (size_t k = 1; k < m; ++k) {
            double d = length(t.P(v[k]) - t.P(v[0]));
            if (d > fd) fd = d, far = k;
        }
        kept[v[far]] = 1;
        double d1 = -1, d2 = -1;
        size_t k1 = farthest(0, far, d1), k2 = farthest(far, m, d2);
        size_t third = d1 >= d2 ? k1 : k2;
        if (third != 0 && third != far) kept[v[third]] = 1;
        std::vector<size_t> anchors = {0, far, m};
        if (third != 0 && third != far) anchors.push_back(third);
        std::sort(anchors.begin(), anchors.end());
        for (size_t a = 0; a + 1 < anchors.size(); ++a) stack.push_back({anchors[a], anchors[a + 1]});
    } else {
        stack.push_back({0, m});
    }
    while (!stack.empty()) {
        auto [i, j] = stack.back();
        stack.pop_back();
        if (j <= i + 1) continue;
        double d = 0;
        size_t k = farthest(i, j, d);
        if (d > run.tolerance) {
            kept[v[k]] = 1;
            stack.push_back({i, k});
            stack.push_back({k, j});
        }
    }
}

std::vector<std::vector<uint32_t>> regionRuns(const Runs& R, uint32_t regionCount) {
    std::vector<std::vector<uint32_t>> out(regionCount);
    for (uint32_t i = 0; i < R.runs.size(); ++i) {
        out[R.runs[i].regionA].push_back(i);
        if (R.runs[i].regionB != kNone) out[R.runs[i].regionB].push_back(i);
    }
    return out;
}

std::vector<std::vector<uint32_t>> regionLoops(const Topology& t, const Regions& r, const Runs& R, uint32_t i) {
    std::vector<std::vector<uint32_t>> loops;
    std::unordered_set<uint32_t> visited;
    for (uint32_t k = r.faceOffset[i]; k < r.faceOffset[i + 1]; ++k) {
        uint32_t f = r.faces[k];
        for (uint32_t e = 0; e < 3; ++e) {
            uint32_t h0 = 3 * f + e;
            if (!isBoundary(t, r, h0) || visited.count(h0)) continue;
            std::vector<uint32_t> loop;
            uint32_t h = h0;
            size_t guard = 0;
            do {
                visited.insert(h);
                uint32_t a = t.T(h / 3)[h % 3];
                if (R.kept[a]) loop.push_back(a);
                // Next boundary half-edge leaving the head vertex, rotating inside the region.
                uint32_t hn = 3 * (h / 3) + (h % 3 + 1) % 3;
                size_t spin = 0;
                while (!isBoundary(t, r, hn)) {
                    uint32_t o = t.twin[hn];
                    hn = 3 * (o / 3) + (o % 3 + 1) % 3;
                    if (++spin > 100000) return {};
                }
                h = hn;
                if (++guard > size_t(t.nf) * 3) return {};
            } while (h != h0);
            loops.push_back(std::move(loop));
        }
    }
    return loops;
}

}  // namespace lodbake::agsphere_detail
