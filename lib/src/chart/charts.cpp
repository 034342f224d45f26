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

#include "lodbake/core/adjacency.h"
#include "lodbake/core/errors.h"

namespace lodbake {
namespace {

constexpr double kPi = 3.14159265358979323846;

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

// The vertices and undirected edges of a face set, with how many of its faces use each edge.
struct FaceSetEdges {
    std::unordered_map<uint64_t, int> edgeCount;       // edgeKey -> faces of the set using the edge
    std::unordered_map<uint32_t, uint32_t> vertexSlot;  // vertex -> local index, in first-use order
};

// \pre no face of `faces` is index-degenerate (checked by the caller).
FaceSetEdges collectEdges(const TriMesh& mesh, const std::vector<uint32_t>& faces) {
    FaceSetEdges e;
    e.edgeCount.reserve(faces.size() * 2);
    e.vertexSlot.reserve(faces.size());
    for (uint32_t f : faces) {
        const Tri& t = mesh.triangles[f];
        for (int k = 0; k < 3; ++k) {
            ++e.edgeCount[edgeKey(t[k], t[(k + 1) % 3])];
            e.vertexSlot.emplace(t[k], uint32_t(e.vertexSlot.size()));
        }
    }
    return e;
}

// Euler characteristic 1, no edge used by more than two faces, and the boundary edges form one
// closed loop through vertices of exactly two boundary edges each. `boundaryNext` receives, per
// local vertex, its neighbours along the boundary (empty for interior vertices).
bool singleBoundaryLoop(const FaceSetEdges& e, size_t faceCount, std::vector<std::vector<uint32_t>>& boundaryNext) {
    long V = long(e.vertexSlot.size()), E = long(e.edgeCount.size()), F = long(faceCount);
    bool ok = (V - E + F == 1);
    boundaryNext.assign(e.vertexSlot.size(), {});
    size_t boundaryEdges = 0;
    for (const auto& [key, c] : e.edgeCount) {
        if (c > 2) ok = false;
        if (c == 1) {
            uint32_t a = e.vertexSlot.at(uint32_t(key >> 32)), b = e.vertexSlot.at(uint32_t(key & 0xffffffffu));
            boundaryNext[a].push_back(b);
            boundaryNext[b].push_back(a);
            ++boundaryEdges;
        }
    }
    uint32_t start = UINT32_MAX;
    for (uint32_t v = 0; v < boundaryNext.size() && ok; ++v) {
        if (!boundaryNext[v].empty() && boundaryNext[v].size() != 2) ok = false;
        if (boundaryNext[v].size() == 2 && start == UINT32_MAX) start = v;
    }
    if (ok && start == UINT32_MAX) ok = false;  // closed
    if (ok) {
        size_t steps = 0;
        uint32_t prev = start, cur = boundaryNext[start][0];
        ++steps;
        while (cur != start && steps <= boundaryEdges) {
            uint32_t nxt = boundaryNext[cur][0] == prev ? boundaryNext[cur][1] : boundaryNext[cur][0];
            prev = cur;
            cur = nxt;
            ++steps;
        }
        if (steps != boundaryEdges) ok = false;
    }
    return ok;
}

// Every vertex has a single fan of faces (its corners are joined through shared edges) and the
// faces form one edge-connected piece: union-find on face corners, where corners (f, v) and
// (g, v) are joined when f and g share an edge containing v.
bool connectedWithSingleFans(const TriMesh& mesh, const std::vector<uint32_t>& faces, const FaceSetEdges& e) {
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
    firstEdge.reserve(e.edgeCount.size());
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
    // Fans: corners of the same vertex must all be in one set.
    std::unordered_map<uint32_t, uint32_t> vertexRoot;
    vertexRoot.reserve(e.vertexSlot.size());
    for (uint32_t i = 0; i < faces.size(); ++i) {
        const Tri& t = mesh.triangles[faces[i]];
        for (int k = 0; k < 3; ++k) {
            uint32_t r = find(i * 3 + uint32_t(k));
            auto [it, inserted] = vertexRoot.emplace(t[k], r);
            if (!inserted && it->second != r) return false;
        }
    }
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
    for (uint32_t i = 0; i < faces.size(); ++i)
        if (ffind(i) != 0) return false;
    return true;
}

// Normal cone and E_region of a face set: the plane through the area-weighted centroid with the
// mean normal; E_region = (set area / total area) x (largest distance to that plane + spread of
// the boundary vertices' distances to the centroid) / diagonal.
void regionShape(const TriMesh& mesh, const std::vector<uint32_t>& faces, const FaceSetEdges& e,
                 const std::vector<std::vector<uint32_t>>& boundaryNext, double totalArea, double diagonal, Shape& s) {
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
    for (const auto& [v, slot] : e.vertexSlot) maxPlane = std::max(maxPlane, std::fabs(dot(mesh.positions[v] - c, n)));
    double bmax = 0, bmin = 1e300;
    for (const auto& [v, slot] : e.vertexSlot) {
        if (boundaryNext[slot].empty()) continue;
        double d = length(mesh.positions[v] - c);
        bmax = std::max(bmax, d);
        bmin = std::min(bmin, d);
    }
    if (bmin > bmax) bmin = bmax;
    double diag = diagonal > 0 ? diagonal : 1;
    s.energy = (totalArea > 0 ? area / totalArea : 0) * (maxPlane + bmax - bmin) / diag;
}

// Disk test of `faces` and, with wantShape, its normal cone and E_region (lengths relative to
// `diagonal`, area relative to `totalArea`). A set with an index-degenerate face is no disk.
Shape measure(const TriMesh& mesh, const std::vector<uint32_t>& faces, double totalArea, double diagonal,
              bool wantShape) {
    Shape s;
    if (faces.empty()) return s;
    for (uint32_t f : faces)
        if (degenerateIndices(mesh.triangles[f])) return s;
    const FaceSetEdges e = collectEdges(mesh, faces);
    std::vector<std::vector<uint32_t>> boundaryNext;
    s.disk = singleBoundaryLoop(e, faces.size(), boundaryNext) && connectedWithSingleFans(mesh, faces, e);
    if (wantShape) regionShape(mesh, faces, e, boundaryNext, totalArea, diagonal, s);
    return s;
}

// Connected components of `faces` (edge adjacency restricted to the set), each sorted.
std::vector<std::vector<uint32_t>> components(const CompressedRows& adj, const std::vector<uint32_t>& faces,
                                              std::vector<int32_t>& mark, int32_t tag) {
    for (uint32_t f : faces) mark[f] = tag;
    std::vector<std::vector<uint32_t>> out;
    for (uint32_t seed : faces) {
        if (mark[seed] != tag) continue;
        std::vector<uint32_t> comp{seed};
        mark[seed] = -1;
        for (size_t i = 0; i < comp.size(); ++i)
            for (uint32_t k = adj.offsets[comp[i]]; k < adj.offsets[comp[i] + 1]; ++k) {
                uint32_t g = adj.items[k];
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
std::pair<std::vector<uint32_t>, std::vector<uint32_t>> splitInTwo(const CompressedRows& adj,
                                                                   const std::vector<uint32_t>& faces,
                                                                   std::vector<int32_t>& mark) {
    const int32_t inSet = -2;
    for (uint32_t f : faces) mark[f] = inSet;
    auto farthest = [&](uint32_t seed) {
        std::vector<uint32_t> order{seed};
        std::unordered_set<uint32_t> seen{seed};
        for (size_t i = 0; i < order.size(); ++i)
            for (uint32_t k = adj.offsets[order[i]]; k < adj.offsets[order[i] + 1]; ++k) {
                uint32_t g = adj.items[k];
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
            uint32_t g = adj.items[k];
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
    const CompressedRows adj = faceNeighbours(mesh.triangles);  // across welded edges, non-manifold ones too
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
                uint32_t o = faceOwner[adj.items[k]];
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
