// Chart building: base regions -> disk-shaped, planar, compact charts (thesis 3.3.1).
//
// Pipeline: (1) face adjacency over welded edges; (2) base regions from faceRegion, each split
// into connected disks (BFS halves grown from two far-apart faces) until every piece is a disk;
// (3) greedy merging of adjacent charts, cheapest merged E_region first, refusing merges that do
// not give a disk or whose normal cone / E_region exceeds the limits; (4) dense ids ordered by
// each chart's smallest face.
#include "lodbake/chart/charts.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <memory>
#include <map>
#include <unordered_map>

#include "lodbake/core/adjacency.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/math.h"
#include "lodbake/core/parallel.h"
#include "chart/shape_memo.h"

namespace lodbake {
namespace {

// The first candidate lists are measured on several threads from this many charts, in chunks of
// kListingChunk charts.
constexpr size_t kParallelListing = 256;
constexpr size_t kListingChunk = 64;

using chart_detail::Shape;
using chart_detail::ShapeMemo;

// Largest normal cone (degrees) and E_region a face set may have; 0 = no limit.
struct ShapeLimits {
    double coneDegrees = 0;
    double energy = 0;
    bool exceededBy(const Shape& s) const {
        return (coneDegrees > 0 && s.coneDegrees > coneDegrees) || (energy > 0 && s.energy > energy);
    }
};

Vec3 faceNormalArea(const TriMesh& m, uint32_t f) {
    const Tri& t = m.triangles[f];
    return cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]) * 0.5;
}

// Disk test and shape of face sets of one mesh. Tables indexed by vertex and by edge id, reset by
// a stamp, replace per-call hash maps: buildCharts measures every candidate merge, and a merge
// into a large chart re-measures all of its neighbours over the chart's full face list.
class SetMeasurer {
public:
    // `edges` = groupEdges(mesh.triangles): its groups are the edge ids. Half-edges of
    // index-degenerate faces have none; measure never reads them.
    SetMeasurer(const TriMesh& mesh, const EdgeGroups& edges) : mesh_(mesh) {
        const size_t nf = mesh.triangleCount();
        faceEdge_.assign(nf * 3, UINT32_MAX);
        for (uint32_t e = 0; e < edges.keys.size(); ++e)
            for (const uint32_t* h = edges.halfEdges.begin(e); h != edges.halfEdges.end(e); ++h) faceEdge_[*h] = e;
        const size_t edgeCount = edges.keys.size();
        edgeStamp_.assign(edgeCount, 0);
        edgeUses_.assign(edgeCount, 0);
        edgeFirst_.assign(edgeCount, 0);
        vertexStamp_.assign(mesh.vertexCount(), 0);
        vertexSlot_.assign(mesh.vertexCount(), 0);
        // Each face's terms once: every candidate merge sums them again over its faces.
        faceTerms_.resize(nf);
        for (uint32_t f = 0; f < nf; ++f) {
            FaceTerms& ft = faceTerms_[f];
            const Tri& t = mesh.triangles[f];
            ft.normalArea = faceNormalArea(mesh, f);
            ft.area = length(ft.normalArea);
            ft.weightedCentroid = (mesh.positions[t[0]] + mesh.positions[t[1]] + mesh.positions[t[2]]) * (ft.area / 3);
            ft.normal = normalize(ft.normalArea);
        }
    }

    // Disk test of `faces` and, with wantShape, its normal cone and E_region (lengths relative to
    // `diagonal`, area relative to `totalArea`). A set with an index-degenerate face is no disk.
    // With wantShape, a shape over `limits` is marked overLimits and skips the fan test (the
    // costliest part; its set is refused whatever the test says), so `disk` stays false.
    Shape measure(const std::vector<uint32_t>& faces, double totalArea, double diagonal, bool wantShape,
                  const ShapeLimits& limits = {}) {
        Shape s;
        if (faces.empty()) return s;
        for (uint32_t f : faces)
            if (degenerateIndices(mesh_.triangles[f])) return s;
        FaceSums sums;
        if (wantShape) {
            sums = faceSums(faces, s);
            // A cone over the limit refuses the set whatever the rest says.
            if (limits.coneDegrees > 0 && s.coneDegrees > limits.coneDegrees) {
                s.overLimits = true;
                return s;
            }
        }
        collect(faces);
        const bool loop = singleBoundaryLoop(faces);  // also the boundary degrees regionShape reads
        if (wantShape) {
            regionShape(sums, totalArea, diagonal, s);
            s.overLimits = limits.exceededBy(s);
            if (s.overLimits) return s;
        }
        s.disk = loop && connectedWithSingleFans(faces);
        return s;
    }

private:
    // The vertices (local slots in first-use order) and edges of the set, with how many of its
    // faces use each edge and the first (face slot, corner) using it.
    void collect(const std::vector<uint32_t>& faces) {
        if (++stamp_ == 0) {  // wrapped: no table entry may look current
            std::fill(edgeStamp_.begin(), edgeStamp_.end(), 0);
            std::fill(vertexStamp_.begin(), vertexStamp_.end(), 0);
            stamp_ = 1;
        }
        vertices_.clear();
        edges_.clear();
        for (uint32_t i = 0; i < faces.size(); ++i) {
            const Tri& t = mesh_.triangles[faces[i]];
            for (uint32_t k = 0; k < 3; ++k) {
                uint32_t e = faceEdge_[size_t(faces[i]) * 3 + k];
                if (edgeStamp_[e] != stamp_) {
                    edgeStamp_[e] = stamp_;
                    edgeUses_[e] = 0;
                    edgeFirst_[e] = i * 3 + k;
                    edges_.push_back(e);
                }
                ++edgeUses_[e];
                if (vertexStamp_[t[k]] != stamp_) {
                    vertexStamp_[t[k]] = stamp_;
                    vertexSlot_[t[k]] = uint32_t(vertices_.size());
                    vertices_.push_back(t[k]);
                }
            }
        }
    }

    // Euler characteristic 1, no edge used by more than two faces, and the boundary edges form one
    // closed loop through vertices of exactly two boundary edges each. Fills boundaryDegree_ and
    // boundaryNext_ per local vertex (the first two neighbours along the boundary).
    bool singleBoundaryLoop(const std::vector<uint32_t>& faces) {
        const long V = long(vertices_.size()), E = long(edges_.size()), F = long(faces.size());
        bool ok = (V - E + F == 1);
        boundaryDegree_.assign(vertices_.size(), 0);
        boundaryNext_.resize(vertices_.size());
        size_t boundaryEdges = 0;
        for (uint32_t e : edges_) {
            if (edgeUses_[e] > 2) ok = false;
            if (edgeUses_[e] != 1) continue;
            const uint32_t first = edgeFirst_[e];
            const Tri& t = mesh_.triangles[faces[first / 3]];
            const uint32_t a = vertexSlot_[t[first % 3]], b = vertexSlot_[t[(first % 3 + 1) % 3]];
            if (boundaryDegree_[a] < 2) boundaryNext_[a][boundaryDegree_[a]] = b;
            if (boundaryDegree_[b] < 2) boundaryNext_[b][boundaryDegree_[b]] = a;
            ++boundaryDegree_[a];
            ++boundaryDegree_[b];
            ++boundaryEdges;
        }
        uint32_t start = UINT32_MAX;
        for (uint32_t v = 0; v < vertices_.size() && ok; ++v) {
            if (boundaryDegree_[v] != 0 && boundaryDegree_[v] != 2) ok = false;
            if (boundaryDegree_[v] == 2 && start == UINT32_MAX) start = v;
        }
        if (ok && start == UINT32_MAX) ok = false;  // closed
        if (ok) {
            size_t steps = 1;
            uint32_t prev = start, cur = boundaryNext_[start][0];
            while (cur != start && steps <= boundaryEdges) {
                uint32_t nxt = boundaryNext_[cur][0] == prev ? boundaryNext_[cur][1] : boundaryNext_[cur][0];
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
    // \pre every edge of the set is used by at most two of its faces.
    bool connectedWithSingleFans(const std::vector<uint32_t>& faces) {
        parent_.resize(faces.size() * 3);
        for (uint32_t i = 0; i < parent_.size(); ++i) parent_[i] = i;
        auto find = [&](uint32_t x) {
            while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
            return x;
        };
        auto unite = [&](uint32_t a, uint32_t b) {
            a = find(a);
            b = find(b);
            if (a != b) parent_[std::max(a, b)] = std::min(a, b);
        };
        for (uint32_t i = 0; i < faces.size(); ++i) {
            const Tri& t = mesh_.triangles[faces[i]];
            for (uint32_t k = 0; k < 3; ++k) {
                const uint32_t e = faceEdge_[size_t(faces[i]) * 3 + k];
                const uint32_t first = edgeFirst_[e];
                if (first == i * 3 + k) continue;
                const uint32_t j = first / 3;
                const Tri& u = mesh_.triangles[faces[j]];
                for (uint32_t a = 0; a < 2; ++a) {
                    uint32_t v = t[(k + a) % 3];
                    uint32_t cj = u[0] == v ? 0 : (u[1] == v ? 1 : 2);
                    unite(i * 3 + (k + a) % 3, j * 3 + cj);
                }
            }
        }
        // Fans: corners of the same vertex must all be in one set.
        vertexRoot_.assign(vertices_.size(), UINT32_MAX);
        for (uint32_t i = 0; i < faces.size(); ++i) {
            const Tri& t = mesh_.triangles[faces[i]];
            for (uint32_t k = 0; k < 3; ++k) {
                uint32_t r = find(i * 3 + k);
                uint32_t& root = vertexRoot_[vertexSlot_[t[k]]];
                if (root == UINT32_MAX) root = r;
                else if (root != r) return false;
            }
        }
        // Face connectivity: corners of one face belong together.
        std::vector<uint32_t>& fparent = vertexRoot_;  // reused: one slot per face now
        fparent.resize(faces.size());
        for (uint32_t i = 0; i < faces.size(); ++i) fparent[i] = i;
        auto ffind = [&](uint32_t x) {
            while (fparent[x] != x) x = fparent[x] = fparent[fparent[x]];
            return x;
        };
        for (uint32_t i = 0; i < faces.size(); ++i)
            for (uint32_t k = 0; k < 3; ++k) {
                uint32_t r = find(i * 3 + k) / 3;
                uint32_t a = ffind(i), b = ffind(r);
                if (a != b) fparent[std::max(a, b)] = std::min(a, b);
            }
        for (uint32_t i = 0; i < faces.size(); ++i)
            if (ffind(i) != 0) return false;
        return true;
    }

    // Area-weighted sums over a face set (in its order) and its normal cone (degrees, into s).
    struct FaceSums {
        Vec3 normal, centroid;
        double area = 0;
    };
    FaceSums faceSums(const std::vector<uint32_t>& faces, Shape& s) const {
        Vec3 nsum{}, csum{};
        double area = 0;
        for (uint32_t f : faces) {
            const FaceTerms& ft = faceTerms_[f];
            nsum += ft.normalArea;
            csum += ft.weightedCentroid;
            area += ft.area;
        }
        FaceSums out;
        out.normal = normalize(nsum);
        out.centroid = area > 0 ? csum / area : mesh_.positions[mesh_.triangles[faces[0]][0]];
        out.area = area;
        double minCos = 1;
        for (uint32_t f : faces) {
            const Vec3& nf = faceTerms_[f].normal;
            if (length2(nf) > 0) minCos = std::min(minCos, dot(nf, out.normal));
        }
        if (length2(out.normal) == 0) minCos = -1;
        s.coneDegrees = std::acos(std::clamp(minCos, -1.0, 1.0)) * 180 / kPi;
        return out;
    }

    // E_region of a face set with its FaceSums: the plane through the area-weighted centroid with
    // the mean normal; E_region = (set area / total area) x (largest distance to that plane + spread
    // of the boundary vertices' distances to the centroid) / diagonal.
    void regionShape(const FaceSums& sums, double totalArea, double diagonal, Shape& s) const {
        const TriMesh& mesh = mesh_;
        const Vec3 n = sums.normal, c = sums.centroid;
        const double area = sums.area;
        double maxPlane = 0;
        for (uint32_t v : vertices_) maxPlane = std::max(maxPlane, std::fabs(dot(mesh.positions[v] - c, n)));
        double bmax = 0, bmin = 1e300;
        for (uint32_t slot = 0; slot < vertices_.size(); ++slot) {
            if (boundaryDegree_[slot] == 0) continue;
            double d = length(mesh.positions[vertices_[slot]] - c);
            bmax = std::max(bmax, d);
            bmin = std::min(bmin, d);
        }
        if (bmin > bmax) bmin = bmax;
        double diag = diagonal > 0 ? diagonal : 1;
        s.energy = (totalArea > 0 ? area / totalArea : 0) * (maxPlane + bmax - bmin) / diag;
    }

    struct FaceTerms {
        Vec3 normalArea, weightedCentroid, normal;  // weightedCentroid = centroid x area
        double area = 0;
    };
    const TriMesh& mesh_;
    std::vector<FaceTerms> faceTerms_;
    std::vector<uint32_t> faceEdge_;                 // edge id of face f's edge (t[k], t[k+1]) at 3f+k
    std::vector<uint32_t> edgeStamp_, edgeUses_, edgeFirst_;  // per edge id; first = 3 x face slot + corner
    std::vector<uint32_t> vertexStamp_, vertexSlot_;  // per mesh vertex
    uint32_t stamp_ = 0;
    std::vector<uint32_t> vertices_, edges_;          // of the current set, in first-use order
    std::vector<uint32_t> boundaryDegree_, parent_, vertexRoot_;
    std::vector<std::array<uint32_t, 2>> boundaryNext_;
};

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
    const int32_t inSet = -2, reached = -3;
    for (uint32_t f : faces) mark[f] = inSet;
    auto farthest = [&](uint32_t seed) {
        std::vector<uint32_t> order{seed};
        mark[seed] = reached;
        for (size_t i = 0; i < order.size(); ++i)
            for (uint32_t k = adj.offsets[order[i]]; k < adj.offsets[order[i] + 1]; ++k) {
                uint32_t g = adj.items[k];
                if (mark[g] == inSet) mark[g] = reached, order.push_back(g);
            }
        for (uint32_t f : order) mark[f] = inSet;
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

// The candidate merges, cheapest first, as one sorted list per chart (the candidates pushed when
// that chart was last merged into, or at the start) and a heap of the lists' heads. A merge makes
// every candidate of its two charts stale; listing them under the chart that pushed them lets
// those go at once, and the heap holds one head per list instead of every candidate, so it stays
// small. Candidates other lists hold for changed charts are skipped as the lists advance. The
// live candidates are distinct and totally ordered by Candidate::operator>, and a stale one
// never becomes live again, so pops come in exactly the order of one heap of all candidates.
class MergeQueue {
public:
    explicit MergeQueue(size_t charts) : lists_(charts), gen_(charts, 0) {}

    // Replaces chart c's list by `candidates` (any order).
    template <class Valid>
    void relist(uint32_t c, std::vector<Candidate> candidates, const Valid& valid) {
        std::sort(candidates.begin(), candidates.end(), std::greater<Candidate>());  // cheapest last
        lists_[c] = std::move(candidates);
        ++gen_[c];
        pushHead(c, valid);
    }

    // The cheapest live candidate; false when none is left.
    template <class Valid>
    bool pop(Candidate& out, const Valid& valid) {
        while (!heap_.empty()) {
            std::pop_heap(heap_.begin(), heap_.end(), std::greater<Head>());
            const Head h = heap_.back();
            heap_.pop_back();
            if (h.gen != gen_[h.chart]) continue;  // that list was replaced
            lists_[h.chart].pop_back();
            pushHead(h.chart, valid);
            if (valid(h.cand)) {
                out = h.cand;
                return true;
            }
        }
        return false;
    }

private:
    struct Head {
        Candidate cand;
        uint32_t chart, gen;
        bool operator>(const Head& o) const { return cand > o.cand; }
    };
    // Drops c's stale candidates from its cheap end and queues the first live one.
    template <class Valid>
    void pushHead(uint32_t c, const Valid& valid) {
        std::vector<Candidate>& l = lists_[c];
        while (!l.empty() && !valid(l.back())) l.pop_back();
        if (l.empty()) return;
        heap_.push_back({l.back(), c, gen_[c]});
        std::push_heap(heap_.begin(), heap_.end(), std::greater<Head>());
    }

    std::vector<std::vector<Candidate>> lists_;  // per chart, dearest first
    std::vector<uint32_t> gen_;
    std::vector<Head> heap_;
};

}  // namespace

bool isDisk(const TriMesh& mesh, const std::vector<uint32_t>& faces) {
    return SetMeasurer(mesh, groupEdges(mesh.triangles)).measure(faces, 0, 1, false).disk;
}

ChartResult buildCharts(const TriMesh& mesh, const std::vector<uint32_t>& faceRegion, const ChartOptions& options) {
    const size_t nf = mesh.triangleCount();
    if (!faceRegion.empty() && faceRegion.size() != nf)
        throw InvalidInput("faceRegion has " + std::to_string(faceRegion.size()) + " entries for " +
                           std::to_string(nf) + " faces");
    ChartResult result;
    result.faceChart.assign(nf, -1);
    if (nf == 0) return result;
    const EdgeGroups edges = groupEdges(mesh.triangles);
    const CompressedRows adj = faceNeighbours(edges, nf);  // across welded edges, non-manifold ones too
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
    SetMeasurer measurer(mesh, edges);
    std::vector<Chart> charts;
    for (auto& [rep, faces] : regions) {
        std::vector<std::vector<uint32_t>> work = components(adj, faces, mark, 1);
        bool split = work.size() > 1;
        while (!work.empty()) {
            std::vector<uint32_t> part = std::move(work.back());
            work.pop_back();
            // A piece is kept when it is a disk within the normal-cone limit (a base region may
            // cover most of a closed surface: a sphere minus one triangle is a disk but flattens badly).
            Shape shape = measurer.measure(part, totalArea, diagonal, options.splitNormalConeDegrees > 0);
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
    // Neighbour charts, kept per chart across merges: a merged chart's neighbours are the union of
    // its two parts' lists, and ids of charts merged away since a list was written resolve to the
    // chart that absorbed them. This replaces a walk over every face's adjacency after each merge
    // (a face of coincident copies has hundreds of neighbours).
    std::vector<uint32_t> absorbedBy(charts.size());
    for (uint32_t c = 0; c < charts.size(); ++c) absorbedBy[c] = c;
    auto owner = [&](uint32_t c) {
        while (absorbedBy[c] != c) c = absorbedBy[c] = absorbedBy[absorbedBy[c]];
        return c;
    };
    std::vector<std::vector<uint32_t>> chartNeighbours(charts.size());
    for (uint32_t c = 0; c < charts.size(); ++c) {
        std::vector<uint32_t>& out = chartNeighbours[c];
        for (uint32_t f : charts[c].faces)
            for (uint32_t k = adj.offsets[f]; k < adj.offsets[f + 1]; ++k) {
                uint32_t o = faceOwner[adj.items[k]];
                if (o != UINT32_MAX && o != c) out.push_back(o);
            }
        std::sort(out.begin(), out.end());
        out.erase(std::unique(out.begin(), out.end()), out.end());
    }
    // Resolves chart c's list to current charts, sorted and without c. A merged chart's list holds
    // many ids that resolve alike (a face of coincident copies borders hundreds of charts): they
    // are dropped before the sort, through the stamp of the last list each chart entered.
    std::vector<uint32_t> listedIn(charts.size(), UINT32_MAX);
    uint32_t listing = 0;
    auto neighbours = [&](uint32_t c) -> const std::vector<uint32_t>& {
        std::vector<uint32_t>& out = chartNeighbours[c];
        ++listing;
        listedIn[c] = listing;
        size_t kept = 0;
        for (uint32_t o : out) {
            o = owner(o);
            if (listedIn[o] != listing) listedIn[o] = listing, out[kept++] = o;
        }
        out.resize(kept);
        std::sort(out.begin(), out.end());
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
    std::vector<uint32_t> merged;  // scratch: the face list of the candidate merge being measured
    ShapeMemo memo(mesh);
    const bool useMemo = memo.worthwhile();
    // Measurers of the threads listing the first candidates besides this one (made when first used).
    std::vector<std::unique_ptr<SetMeasurer>> listingMeasurers;
    const int listingThreads = resolveThreads(options.threads);
    auto runPhase = [&](bool relaxed) {
        MergeQueue queue(charts.size());
        auto valid = [&](const Candidate& c) {
            return charts[c.a].alive && charts[c.b].alive && charts[c.a].version == c.va && charts[c.b].version == c.vb;
        };
        // The relaxed phase ignores the normal-cone and E_region limits, never the disk rule.
        const ShapeLimits limits = relaxed ? ShapeLimits{} : ShapeLimits{options.maxNormalConeDegrees, options.maxRegionEnergy};
        // Adds the merge of charts a and b to `out` when its shape allows it, measured by `m` over
        // the scratch list `faces`.
        auto candidate = [&](uint32_t a, uint32_t b, SetMeasurer& m, std::vector<uint32_t>& faces, std::vector<Candidate>& out) {
            if (a > b) std::swap(a, b);
            auto measure = [&] {
                faces.clear();
                std::merge(charts[a].faces.begin(), charts[a].faces.end(), charts[b].faces.begin(), charts[b].faces.end(),
                           std::back_inserter(faces));
                return m.measure(faces, totalArea, diagonal, true, limits);
            };
            const Shape s = useMemo ? memo.shape(charts[a].faces, charts[b].faces, measure) : measure();
            if (s.overLimits || !s.disk) return;
            out.push_back({s.energy, a, b, charts[a].version, charts[b].version});
        };
        std::vector<Candidate> batch;  // the candidates of the chart being (re)listed
        auto push = [&](uint32_t a, uint32_t b) { candidate(a, b, measurer, merged, batch); };
        // The first lists: every chart's pairs with its higher neighbours. No chart changes while
        // they are listed, so each chart's list is measured on its own (on several threads, each
        // with its measurer, when no memo is shared) and the lists are queued in chart order.
        if (!useMemo && listingThreads > 1 && charts.size() >= kParallelListing) {
            for (uint32_t c = 0; c < charts.size(); ++c)
                if (charts[c].alive) neighbours(c);  // resolved once, before the threads read them
            listingMeasurers.resize(size_t(listingThreads));
            std::vector<std::vector<Candidate>> lists(charts.size());
            std::vector<std::vector<uint32_t>> scratch(static_cast<size_t>(listingThreads));
            parallelChunks(charts.size(), kListingChunk, listingThreads, [&](size_t begin, size_t end, size_t thread) {
                std::unique_ptr<SetMeasurer>& own = listingMeasurers[thread];
                if (thread > 0 && !own) own = std::make_unique<SetMeasurer>(mesh, edges);
                SetMeasurer& m = thread > 0 ? *own : measurer;
                for (size_t c = begin; c < end; ++c) {
                    if (!charts[c].alive) continue;
                    for (uint32_t o : chartNeighbours[c])
                        if (o > c) candidate(uint32_t(c), o, m, scratch[thread], lists[c]);
                }
            });
            for (uint32_t c = 0; c < charts.size(); ++c)
                if (charts[c].alive) queue.relist(c, std::move(lists[c]), valid);
        } else {
            for (uint32_t c = 0; c < charts.size(); ++c) {
                if (!charts[c].alive) continue;
                batch.clear();
                for (uint32_t o : neighbours(c))
                    if (o > c) push(c, o);
                queue.relist(c, batch, valid);
            }
        }
        Candidate cand;
        while (!(options.maxCharts > 0 && alive <= options.maxCharts) && queue.pop(cand, valid)) {
            Chart& A = charts[cand.a];
            Chart& B = charts[cand.b];
            A.faces = mergedFaces(cand.a, cand.b);
            B.faces.clear();
            absorbedBy[cand.b] = cand.a;
            std::vector<uint32_t>& na = chartNeighbours[cand.a];
            na.insert(na.end(), chartNeighbours[cand.b].begin(), chartNeighbours[cand.b].end());
            std::vector<uint32_t>().swap(chartNeighbours[cand.b]);
            B.alive = false;
            ++A.version;
            --alive;
            ++result.merges;
            // Every listed candidate of A or B is stale now: B's list goes, A's is rebuilt.
            queue.relist(cand.b, {}, valid);
            batch.clear();
            for (uint32_t o : neighbours(cand.a)) push(cand.a, o);
            queue.relist(cand.a, batch, valid);
        }
    };
    runPhase(false);
    memo.clear();  // its shapes were measured against the first phase's limits
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
