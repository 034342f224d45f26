// Chart building: base regions -> disk-shaped, planar, compact charts (thesis 3.3.1).
//
// Pipeline: (1) face adjacency over welded edges; (2) base regions from faceRegion, each split
// into connected disks (BFS halves grown from two far-apart faces) until every piece is a disk;
// (3) greedy merging of adjacent charts, cheapest merged E_region first, refusing merges that do
// not give a disk or whose normal cone / E_region exceeds the limits; (4) dense ids ordered by
// each chart's smallest face.
#include "lodbake/chart/charts.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <queue>
#include <unordered_map>
#include <unordered_set>

#include "lodbake/core/errors.h"

namespace lodbake {
namespace {

constexpr double kPi = 3.14159265358979323846;

uint64_t edgeKey(uint32_t a, uint32_t b) {
    if (a > b) std::swap(a, b);
    return (uint64_t(a) << 32) | b;
}

bool degenerateIndices(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

// Face adjacency across welded edges (all faces sharing an edge are neighbours, also on
// non-manifold edges).
struct Adjacency {
    std::vector<uint32_t> offsets;  // CSR over faces
    std::vector<uint32_t> faces;
};

Adjacency buildAdjacency(const TriMesh& mesh) {
    const size_t nf = mesh.triangleCount();
    std::vector<std::pair<uint64_t, uint32_t>> edges;
    edges.reserve(nf * 3);
    for (uint32_t f = 0; f < nf; ++f) {
        const Tri& t = mesh.triangles[f];
        if (degenerateIndices(t)) continue;
        for (int k = 0; k < 3; ++k) edges.push_back({edgeKey(t[k], t[(k + 1) % 3]), f});
    }
    std::sort(edges.begin(), edges.end());
    std::vector<std::vector<uint32_t>> nb(nf);
    for (size_t i = 0; i < edges.size();) {
        size_t j = i;
        while (j < edges.size() && edges[j].first == edges[i].first) ++j;
        for (size_t a = i; a < j; ++a)
            for (size_t b = i; b < j; ++b)
                if (a != b && edges[a].second != edges[b].second) nb[edges[a].second].push_back(edges[b].second);
        i = j;
    }
    Adjacency adj;
    adj.offsets.assign(nf + 1, 0);
    for (size_t f = 0; f < nf; ++f) {
        std::sort(nb[f].begin(), nb[f].end());
        nb[f].erase(std::unique(nb[f].begin(), nb[f].end()), nb[f].end());
        adj.offsets[f + 1] = adj.offsets[f] + uint32_t(nb[f].size());
    }
    adj.faces.reserve(adj.offsets[nf]);
    for (size_t f = 0; f < nf; ++f) adj.faces.insert(adj.faces.end(), nb[f].begin(), nb[f].end());
    return adj;
}

// Shape of a face set: E_region and the normal cone, plus the disk test.
struct Shape {
    bool disk = false;
    double energy = 0;      // E_region with lengths relative to the diagonal
    double coneDegrees = 0;
};

Vec3 faceNormalArea(const TriMesh& m, uint32_t f) {
    const Tri& t = m.triangles[f];
    return cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]) * 0.5;
}

// Disk test and shape in one pass over `faces`.
Shape measure(const TriMesh& mesh, const std::vector<uint32_t>& faces, double totalArea, double diagonal,
              bool wantShape) {
    Shape s;
    if (faces.empty()) return s;
    // Edge counts inside the set.
    std::unordered_map<uint64_t, int> edgeCount;
    edgeCount.reserve(faces.size() * 2);
    std::unordered_map<uint32_t, uint32_t> vertexSlot;  // vertex -> local index
    vertexSlot.reserve(faces.size());
    for (uint32_t f : faces) {
        const Tri& t = mesh.triangles[f];
        if (degenerateIndices(t)) return s;
        for (int k = 0; k < 3; ++k) {
            ++edgeCount[edgeKey(t[k], t[(k + 1) % 3])];
            vertexSlot.emplace(t[k], uint32_t(vertexSlot.size()));
        }
    }
    long V = long(vertexSlot.size()), E = long(edgeCount.size()), F = long(faces.size());
    bool ok = (V - E + F == 1);
    // Boundary edges: each boundary vertex has exactly two, and they form one loop.
    std::vector<std::vector<uint32_t>> bnext(vertexSlot.size());
    size_t boundaryEdges = 0;
    for (const auto& [key, c] : edgeCount) {
        if (c > 2) ok = false;
        if (c == 1) {
            uint32_t a = uint32_t(key >> 32), b = uint32_t(key & 0xffffffffu);
            bnext[vertexSlot[a]].push_back(vertexSlot[b]);
            bnext[vertexSlot[b]].push_back(vertexSlot[a]);
            ++boundaryEdges;
        }
    }
    uint32_t start = UINT32_MAX;
    for (uint32_t v = 0; v < bnext.size() && ok; ++v) {
        if (!bnext[v].empty() && bnext[v].size() != 2) ok = false;
        if (bnext[v].size() == 2 && start == UINT32_MAX) start = v;
    }
    if (ok && start == UINT32_MAX) ok = false;  // closed
    if (ok) {
        size_t steps = 0;
        uint32_t prev = start, cur = bnext[start][0];
        ++steps;
        while (cur != start && steps <= boundaryEdges) {
            uint32_t nxt = bnext[cur][0] == prev ? bnext[cur][1] : bnext[cur][0];
            prev = cur;
            cur = nxt;
            ++steps;
        }
        if (steps != boundaryEdges) ok = false;
    }
    if (ok) {
        // Connectivity over interior edges and single fans per vertex: union-find on face corners.
        // Two corners (f, v) and (g, v) are joined when f and g share an edge containing v; faces
        // are joined when they share an edge.
        std::unordered_map<uint32_t, uint32_t> faceSlot;
        faceSlot.reserve(faces.size());
        for (uint32_t i = 0; i < faces.size(); ++i) faceSlot.emplace(faces[i], i);
        std::vector<uint32_t> parent(faces.size() * 3);
        for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
        auto find = [&](uint32_t x) {
            while (parent[x] != x) x = parent[x] = parent[parent[x]];
            return x;
        };
        auto unite = [&](uint32_t a, uint32_t b) {
            a = find(a);
            b = find(b);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        };
        std::unordered_map<uint64_t, std::pair<uint32_t, int>> firstEdge;  // edge -> (face slot, corner)
        firstEdge.reserve(edgeCount.size());
        for (uint32_t i = 0; i < faces.size(); ++i) {
            const Tri& t = mesh.triangles[faces[i]];
            for (int k = 0; k < 3; ++k) {
                uint64_t key = edgeKey(t[k], t[(k + 1) % 3]);
                auto it = firstEdge.find(key);
                if (it == firstEdge.end()) {
                    firstEdge.emplace(key, std::make_pair(i, k));
                    continue;
                }
                uint32_t j = it->second.first;
                const Tri& u = mesh.triangles[faces[j]];
                // corners of vertex t[k] and t[k+1] in face j
                for (int a = 0; a < 2; ++a) {
                    uint32_t v = t[(k + a) % 3];
                    int cj = u[0] == v ? 0 : (u[1] == v ? 1 : 2);
                    unite(i * 3 + uint32_t((k + a) % 3), j * 3 + uint32_t(cj));
                }
            }
        }
        // Fans: corners of the same vertex must all be in one set; and all faces connected.
        std::unordered_map<uint32_t, uint32_t> vertexRoot;
        vertexRoot.reserve(vertexSlot.size());
        for (uint32_t i = 0; i < faces.size() && ok; ++i) {
            const Tri& t = mesh.triangles[faces[i]];
            for (int k = 0; k < 3; ++k) {
                uint32_t r = find(i * 3 + uint32_t(k));
                auto [it, inserted] = vertexRoot.emplace(t[k], r);
                if (!inserted && it->second != r) ok = false;
            }
        }
        if (ok) {
            // Face connectivity: corners of one face belong together.
            std::vector<uint32_t> fparent(faces.size());
            for (uint32_t i = 0; i < faces.size(); ++i) fparent[i] = i;
            auto ffind = [&](uint32_t x) {
                while (fparent[x] != x) x = fparent[x] = fparent[fparent[x]];
                return x;
            };
            for (uint32_t i = 0; i < faces.size(); ++i)
                for (int k = 0; k < 3; ++k) {
                    uint32_t r = find(i * 3 + uint32_t(k)) / 3;
                    uint32_t a = ffind(i), b = ffind(r);
                    if (a != b) fparent[std::max(a, b)] = std::min(a, b);
                }
            for (uint32_t i = 0; i < faces.size() && ok; ++i)
                if (ffind(i) != 0) ok = false;
        }
    }
    s.disk = ok;
    if (!wantShape) return s;

    // Shape: plane through the area-weighted centroid with the mean normal.
    Vec3 nsum{}, csum{};
    double area = 0;
    for (uint32_t f : faces) {
        Vec3 na = faceNormalArea(mesh, f);
        double a = length(na);
        const Tri& t = mesh.triangles[f];
        nsum += na;
        csum += (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) * (a / 3);
        area += a;
    }
    Vec3 n = normalize(nsum);
    Vec3 c = area > 0 ? csum / area : mesh.positions[mesh.triangles[faces[0]][0]];
    double minCos = 1;
    for (uint32_t f : faces) {
        Vec3 nf = normalize(faceNormalArea(mesh, f));
        if (length2(nf) > 0) minCos = std::min(minCos, dot(nf, n));
    }
    if (length2(n) == 0) minCos = -1;
    s.coneDegrees = std::acos(std::clamp(minCos, -1.0, 1.0)) * 180 / kPi;
    double maxPlane = 0;
    for (const auto& [v, slot] : vertexSlot) maxPlane = std::max(maxPlane, std::fabs(dot(mesh.positions[v] - c, n)));
    double bmax = 0, bmin = 1e300;
    for (const auto& [v, slot] : vertexSlot) {
        if (bnext[slot].empty()) continue;
        double d = length(mesh.positions[v] - c);
        bmax = std::max(bmax, d);
        bmin = std::min(bmin, d);
    }
    if (bmin > bmax) bmin = bmax;
    double diag = diagonal > 0 ? diagonal : 1;
    s.energy = (totalArea > 0 ? area / totalArea : 0) * (maxPlane + bmax - bmin) / diag;
    return s;
}

// Connected components of `faces` (edge adjacency restricted to the set), each sorted.
std::vector<std::vector<uint32_t>> components(const Adjacency& adj, const std::vector<uint32_t>& faces,
                                              std::vector<int32_t>& mark, int32_t tag) {
    for (uint32_t f : faces) mark[f] = tag;
    std::vector<std::vector<uint32_t>> out;
    for (uint32_t seed : faces) {
        if (mark[seed] != tag) continue;
        std::vector<uint32_t> comp{seed};
        mark[seed] = -1;
        for (size_t i = 0; i < comp.size(); ++i)
            for (uint32_t k = adj.offsets[comp[i]]; k < adj.offsets[comp[i] + 1]; ++k) {
                uint32_t g = adj.faces[k];
                if (mark[g] == tag) {
                    mark[g] = -1;
                    comp.push_back(g);
                }
            }
        std::sort(comp.begin(), comp.end());
        out.push_back(std::move(comp));
    }
    for (uint32_t f : faces) mark[f] = -1;
    return out;
}

// Multi-source BFS from two far-apart faces of a connected set; returns the two halves.
std::pair<std::vector<uint32_t>, std::vector<uint32_t>> splitInTwo(const Adjacency& adj,
                                                                   const std::vector<uint32_t>& faces,
                                                                   std::vector<int32_t>& mark) {
    const int32_t inSet = -2;
    for (uint32_t f : faces) mark[f] = inSet;
    auto farthest = [&](uint32_t seed) {
        std::vector<uint32_t> order{seed};
        std::unordered_set<uint32_t> seen{seed};
        for (size_t i = 0; i < order.size(); ++i)
            for (uint32_t k = adj.offsets[order[i]]; k < adj.offsets[order[i] + 1]; ++k) {
                uint32_t g = adj.faces[k];
                if (mark[g] == inSet && seen.insert(g).second) order.push_back(g);
            }
        return order.back();
    };
    uint32_t a = farthest(faces.front());
    uint32_t b = farthest(a);
    std::vector<uint32_t> queue{a, b};
    mark[a] = 0;
    mark[b] = 1;
    for (size_t i = 0; i < queue.size(); ++i) {
        uint32_t f = queue[i];
        for (uint32_t k = adj.offsets[f]; k < adj.offsets[f + 1]; ++k) {
            uint32_t g = adj.faces[k];
            if (mark[g] == inSet) {
                mark[g] = mark[f];
                queue.push_back(g);
            }
        }
    }
    std::pair<std::vector<uint32_t>, std::vector<uint32_t>> halves;
    for (uint32_t f : faces) (mark[f] == 0 ? halves.first : halves.second).push_back(f);
    for (uint32_t f : faces) mark[f] = -1;
    return halves;
}

struct Chart {
    std::vector<uint32_t> faces;  // sorted
    uint32_t version = 0;
    bool alive = true;
};

struct Candidate {
    double cost;
    uint32_t a, b, va, vb;
    bool operator>(const Candidate& o) const {
        if (cost != o.cost) return cost > o.cost;
        if (a != o.a) return a > o.a;
        return b > o.b;
    }
};

}  // namespace

bool isDisk(const TriMesh& mesh, const std::vector<uint32_t>& faces) {
    return measure(mesh, faces, 0, 1, false).disk;
}

ChartResult buildCharts(const TriMesh& mesh, const std::vector<uint32_t>& faceRegion, const ChartOptions& options) {
    const size_t nf = mesh.triangleCount();
    if (!faceRegion.empty() && faceRegion.size() != nf)
        throw InvalidInput("faceRegion has " + std::to_string(faceRegion.size()) + " entries for " +
                           std::to_string(nf) + " faces");
    ChartResult result;
    result.faceChart.assign(nf, -1);
    if (nf == 0) return result;
    const Adjacency adj = buildAdjacency(mesh);
    double totalArea = 0;
    for (uint32_t f = 0; f < nf; ++f) totalArea += length(faceNormalArea(mesh, f));
    const double diagonal = bounds(mesh).diagonal();

    // (2) Base regions -> disks.
    std::map<uint32_t, std::vector<uint32_t>> regions;
    std::vector<uint32_t> degenerate;
    for (uint32_t f = 0; f < nf; ++f) {
        uint32_t r = faceRegion.empty() ? f : faceRegion[f];
        if (r >= nf) throw InvalidInput("faceRegion entry out of range at face " + std::to_string(f));
        if (degenerateIndices(mesh.triangles[f])) degenerate.push_back(f);
        else regions[r].push_back(f);
    }
    result.baseRegions = uint32_t(regions.size());
    std::vector<int32_t> mark(nf, -1);
    std::vector<Chart> charts;
    for (auto& [rep, faces] : regions) {
        std::vector<std::vector<uint32_t>> work = components(adj, faces, mark, 1);
        bool split = work.size() > 1;
        while (!work.empty()) {
            std::vector<uint32_t> part = std::move(work.back());
            work.pop_back();
            // A piece is kept when it is a disk within the normal-cone limit (a base region may
            // cover most of a closed surface: a sphere minus one triangle is a disk but flattens badly).
            Shape shape = measure(mesh, part, totalArea, diagonal, options.splitNormalConeDegrees > 0);
            bool coneOk = options.splitNormalConeDegrees <= 0 || shape.coneDegrees <= options.splitNormalConeDegrees;
            if (part.size() == 1 || (shape.disk && coneOk)) {
                charts.push_back({std::move(part), 0, true});
                continue;
            }
            split = true;
            auto halves = splitInTwo(adj, part, mark);
            for (auto* h : {&halves.first, &halves.second}) {
                auto comps = components(adj, *h, mark, 1);
                for (auto& c : comps) work.push_back(std::move(c));
            }
        }
        if (split) ++result.splitRegions;
    }

    // (3) Greedy merging.
    std::vector<uint32_t> faceOwner(nf, UINT32_MAX);
    for (uint32_t c = 0; c < charts.size(); ++c)
        for (uint32_t f : charts[c].faces) faceOwner[f] = c;
    auto neighbours = [&](uint32_t c) {
        std::vector<uint32_t> out;
        for (uint32_t f : charts[c].faces)
            for (uint32_t k = adj.offsets[f]; k < adj.offsets[f + 1]; ++k) {
                uint32_t o = faceOwner[adj.faces[k]];
                if (o != UINT32_MAX && o != c) out.push_back(o);
            }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
        return out;
    };
    auto mergedFaces = [&](uint32_t a, uint32_t b) {
        std::vector<uint32_t> m;
        m.reserve(charts[a].faces.size() + charts[b].faces.size());
        std::merge(charts[a].faces.begin(), charts[a].faces.end(), charts[b].faces.begin(), charts[b].faces.end(),
                   std::back_inserter(m));
        return m;
    };
    size_t alive = charts.size();
    auto runPhase = [&](bool relaxed) {
        std::priority_queue<Candidate, std::vector<Candidate>, std::greater<Candidate>> heap;
        auto push = [&](uint32_t a, uint32_t b) {
            if (a > b) std::swap(a, b);
            Shape s = measure(mesh, mergedFaces(a, b), totalArea, diagonal, true);
            if (!s.disk) return;
            if (!relaxed) {
                if (options.maxNormalConeDegrees > 0 && s.coneDegrees > options.maxNormalConeDegrees) return;
                if (options.maxRegionEnergy > 0 && s.energy > options.maxRegionEnergy) return;
            }
            heap.push({s.energy, a, b, charts[a].version, charts[b].version});
        };
        for (uint32_t c = 0; c < charts.size(); ++c)
            if (charts[c].alive)
                for (uint32_t o : neighbours(c))
                    if (o > c) push(c, o);
        while (!heap.empty()) {
            if (options.maxCharts > 0 && alive <= options.maxCharts) break;
            Candidate cand = heap.top();
            heap.pop();
            Chart& A = charts[cand.a];
            Chart& B = charts[cand.b];
            if (!A.alive || !B.alive || A.version != cand.va || B.version != cand.vb) continue;
            A.faces = mergedFaces(cand.a, cand.b);
            for (uint32_t f : B.faces) faceOwner[f] = cand.a;
            B.faces.clear();
            B.alive = false;
            ++A.version;
            --alive;
            ++result.merges;
            for (uint32_t o : neighbours(cand.a)) push(cand.a, o);
        }
    };
    runPhase(false);
    if (options.maxCharts > 0 && alive > options.maxCharts) runPhase(true);

    // (4) Dense ids by smallest face; degenerate faces join a chart sharing a vertex.
    std::vector<uint32_t> order;
    for (uint32_t c = 0; c < charts.size(); ++c)
        if (charts[c].alive && !charts[c].faces.empty()) order.push_back(c);
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return charts[a].faces.front() < charts[b].faces.front(); });
    for (uint32_t id = 0; id < order.size(); ++id)
        for (uint32_t f : charts[order[id]].faces) result.faceChart[f] = int32_t(id);
    result.chartCount = uint32_t(order.size());
    if (!degenerate.empty()) {
        std::unordered_map<uint32_t, int32_t> vertexChart;
        for (uint32_t f = 0; f < nf; ++f)
            if (result.faceChart[f] >= 0)
                for (uint32_t v : mesh.triangles[f]) vertexChart.emplace(v, result.faceChart[f]);
        for (uint32_t f : degenerate) {
            int32_t c = 0;
            for (uint32_t v : mesh.triangles[f]) {
                auto it = vertexChart.find(v);
                if (it != vertexChart.end()) {
                    c = it->second;
                    break;
                }
            }
            if (result.chartCount == 0) result.chartCount = 1;
            result.faceChart[f] = c;
        }
    }
    return result;
}

}  // namespace lodbake
