// M-AGSphere levels (thesis 2.4; DESIGN.md "M-AGSphere"). See agsphere.h for the model.
//
// Pipeline, in execution order:
//   buildTopology      face normals and areas, half-edge twins (manifold edges only), vertex ->
//                      faces, each face's cell at the finest depth (faces without a normal take a
//                      neighbour's)
//   outline faces      (views/lights, contour.cpp) faces of the contour edges on each view's
//                      projected outline: pinned, i.e. kept unchanged as one-face regions whose
//                      boundary runs keep every vertex
//   depth statistics   for every uniform depth: regions, cell error thresholds, boundary runs,
//                      simplified runs -> estimated triangles per cell (drives the selection)
//   selectCut          per level: leaves of the quadtree refined round by round (silhouette
//                      cells, then the others, then reference cells; within a class the largest
//                      error first) until the estimated triangle count reaches the target;
//                      neighbouring cells at most two depths apart; coarser levels' cuts are
//                      contained in finer ones (region hierarchy)
//   buildLevel         regions of the cut -> runs -> Douglas-Peucker per run -> ear clipping per
//                      region in its cell's plane -> fallbacks (restore runs, keep original faces)
//                      until the level is manifold where the input is and no new triangle pokes
//                      out of a view's outline -> faces, wedges, pairs
//
// Cell error threshold (thesis: "each cell has maximum vertex deviation as an error threshold"):
// the largest distance of a region vertex to its region's plane (area-weighted normal through the
// area-weighted centroid) over the regions of the cell: the deviation flattening the region makes.
#include "lodbake/agsphere/agsphere.h"

#include <algorithm>
#include <functional>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

#include "agsphere/contour.h"
#include "agsphere/sphere_table.h"
#include "lodbake/agsphere/polygon.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"

namespace lodbake {
namespace {

constexpr uint32_t kNone = UINT32_MAX;         // no twin: mesh border
constexpr uint32_t kNonManifold = UINT32_MAX - 1;  // edge with 3+ faces or inconsistent orientation
constexpr double kPi = 3.14159265358979323846;
// A region of at least this many faces that has to keep its original faces gets its cell split.
constexpr uint32_t kRefineKeptFaces = 16;
// Smallest cosine between a new triangle's normal and its region's area-weighted normal.
constexpr double kMinFacingCos = 0.01;
// Levels are rebuilt until their triangle count is within this fraction of the target (or after
// kCalibrationRounds extra builds).
constexpr int kCalibrationRounds = 3;
constexpr double kCalibrationTolerance = 0.05;

uint64_t edgeKey(uint32_t a, uint32_t b) {
    if (a > b) std::swap(a, b);
    return (uint64_t(a) << 32) | b;
}
uint64_t directedKey(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; }

double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// ---- 1. Topology --------------------------------------------------------------------------

// The sphere's frame: rows of the rotation from model directions to sphere directions.
struct Frame {
    Vec3 r0{1, 0, 0}, r1{0, 1, 0}, r2{0, 0, 1};
    Vec3 toSphere(Vec3 v) const { return {dot(r0, v), dot(r1, v), dot(r2, v)}; }
    Vec3 toModel(Vec3 v) const { return r0 * v.x + r1 * v.y + r2 * v.z; }
};

// Rotation taking unit a onto unit b (Rodrigues), as a Frame.
Frame rotationOnto(Vec3 a, Vec3 b) {
    Frame f;
    Vec3 k = cross(a, b);
    double s = length(k), c = dot(a, b);
    if (s < 1e-12) {
        if (c < 0) {  // half turn about an axis orthogonal to a
            Vec3 axis = normalize(cross(a, std::fabs(a.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0}));
            f.r0 = axis * (2 * axis.x) - Vec3{1, 0, 0};
            f.r1 = axis * (2 * axis.y) - Vec3{0, 1, 0};
            f.r2 = axis * (2 * axis.z) - Vec3{0, 0, 1};
        }
        return f;
    }
    // R = I + [k]x + [k]x^2 (1 - c) / s^2.
    double m[3][3] = {{0, -k.z, k.y}, {k.z, 0, -k.x}, {-k.y, k.x, 0}};
    double r[3][3];
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double m2 = 0;
            for (int q = 0; q < 3; ++q) m2 += m[i][q] * m[q][j];
            r[i][j] = (i == j ? 1.0 : 0.0) + m[i][j] + m2 * (1 - c) / (s * s);
        }
    f.r0 = {r[0][0], r[0][1], r[0][2]};
    f.r1 = {r[1][0], r[1][1], r[1][2]};
    f.r2 = {r[2][0], r[2][1], r[2][2]};
    return f;
}

// The first view (else the first light) goes to the centre of octant 0, (1,1,1)/sqrt(3): that
// octant is the reference cell, the opposite octant faces away, the six others hold the
// silhouette. Without views and lights the sphere is not rotated.
Frame alignedFrame(const AgsphereOptions& o) {
    if (o.views.empty() && o.lights.empty()) return {};
    Vec3 d = normalize(!o.views.empty() ? o.views[0] : o.lights[0]);
    return rotationOnto(d, normalize(Vec3{1, 1, 1}));
}

struct Topology {
    const TriMesh* mesh = nullptr;
    Frame frame;
    uint32_t nf = 0, nv = 0;
    int maxDepth = 0;
    std::vector<Vec3> normal;        // unit face normal
    std::vector<char> degenerate;    // repeated vertex index
    std::vector<uint32_t> twin;      // per half-edge 3f+k (t[k] -> t[k+1]): twin half-edge, kNone, kNonManifold
    std::vector<uint32_t> vfOffset, vfFace;  // vertex -> faces (ascending)
    std::vector<uint32_t> finestCell;        // per face, cell at maxDepth
    // Per face (empty = none): an outline face of a view, kept unchanged as a region of its own
    // (its boundary runs keep every vertex).
    std::vector<char> pinned;
    OutlineFaces outline;  // the views' rasters (keepOutline): new triangles must not leave the outline
    bool isPinned(uint32_t f) const { return !pinned.empty() && pinned[f]; }
    double diagonal = 0;
    const Vec3& P(uint32_t v) const { return mesh->positions[v]; }
    const Tri& T(uint32_t f) const { return mesh->triangles[f]; }
};

Topology buildTopology(const TriMesh& mesh, int maxDepth, const Frame& frame = {}) {
    Topology t;
    t.mesh = &mesh;
    t.frame = frame;
    t.nf = uint32_t(mesh.triangleCount());
    t.nv = uint32_t(mesh.vertexCount());
    t.maxDepth = maxDepth;
    t.diagonal = bounds(mesh).diagonal();
    t.normal.assign(t.nf, Vec3{});
    t.degenerate.assign(t.nf, 0);
    std::vector<char> hasNormal(t.nf, 0);
    for (uint32_t f = 0; f < t.nf; ++f) {
        const Tri& tr = mesh.triangles[f];
        if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2]) {
            t.degenerate[f] = 1;
            continue;
        }
        Vec3 n = cross(t.P(tr[1]) - t.P(tr[0]), t.P(tr[2]) - t.P(tr[0]));
        double l = length(n);
        if (l > 0 && std::isfinite(l)) {
            t.normal[f] = n / l;
            hasNormal[f] = 1;
        }
    }
    // Twins: group half-edges by undirected edge.
    std::vector<std::pair<uint64_t, uint32_t>> he;
    he.reserve(size_t(t.nf) * 3);
    for (uint32_t f = 0; f < t.nf; ++f) {
        if (t.degenerate[f]) continue;
        const Tri& tr = mesh.triangles[f];
        for (uint32_t k = 0; k < 3; ++k) he.push_back({edgeKey(tr[k], tr[(k + 1) % 3]), 3 * f + k});
    }
    std::sort(he.begin(), he.end());
    t.twin.assign(size_t(t.nf) * 3, kNonManifold);
    for (size_t i = 0; i < he.size();) {
        size_t j = i;
        while (j < he.size() && he[j].first == he[i].first) ++j;
        if (j - i == 1) {
            t.twin[he[i].second] = kNone;
        } else if (j - i == 2) {
            uint32_t a = he[i].second, b = he[i + 1].second;
            uint32_t fa = a / 3, fb = b / 3;
            uint32_t a0 = t.T(fa)[a % 3], b0 = t.T(fb)[b % 3];
            if (fa != fb && a0 != b0) {
                t.twin[a] = b;
                t.twin[b] = a;
            }
        }
        i = j;
    }
    // Vertex -> faces.
    t.vfOffset.assign(t.nv + 1, 0);
    for (uint32_t f = 0; f < t.nf; ++f)
        for (uint32_t v : t.T(f)) ++t.vfOffset[v + 1];
    for (uint32_t v = 0; v < t.nv; ++v) t.vfOffset[v + 1] += t.vfOffset[v];
    t.vfFace.resize(t.vfOffset[t.nv]);
    std::vector<uint32_t> fill(t.vfOffset.begin(), t.vfOffset.end() - 1);
    for (uint32_t f = 0; f < t.nf; ++f)
        for (uint32_t v : t.T(f)) t.vfFace[fill[v]++] = f;
    // Faces without a normal take the normal of a neighbour (breadth-first over twins).
    std::vector<uint32_t> queue;
    for (uint32_t f = 0; f < t.nf; ++f)
        if (hasNormal[f]) queue.push_back(f);
    for (size_t q = 0; q < queue.size(); ++q) {
        uint32_t f = queue[q];
        for (uint32_t k = 0; k < 3; ++k) {
            uint32_t o = t.twin[3 * f + k];
            if (o >= kNonManifold) continue;
            uint32_t g = o / 3;
            if (hasNormal[g] || t.degenerate[g]) continue;
            hasNormal[g] = 1;
            t.normal[g] = t.normal[f];
            queue.push_back(g);
        }
    }
    for (uint32_t f = 0; f < t.nf; ++f)
        if (!hasNormal[f]) t.normal[f] = {0, 0, 1};
    t.finestCell.resize(t.nf);
    for (uint32_t f = 0; f < t.nf; ++f) t.finestCell[f] = sphereCell(frame.toSphere(t.normal[f]), maxDepth);
    return t;
}

// ---- 2. A cut and its regions ---------------------------------------------------------------

// A cut of the quadtree: for every finest cell, the depth of its selected ancestor.
using Cut = std::vector<uint8_t>;

struct CellId {
    uint8_t depth = 0;
    uint32_t index = 0;
};

CellId faceCell(const Topology& t, const Cut& cut, uint32_t f) {
    uint32_t fc = t.finestCell[f];
    uint8_t d = cut[fc];
    return {d, fc >> (2 * (t.maxDepth - d))};
}

uint64_t cellKey(CellId c) { return (uint64_t(c.depth) << 32) | c.index; }

struct Regions {
    std::vector<uint32_t> of;     // face -> dense region id
    std::vector<uint32_t> rep;    // region -> smallest face id
    std::vector<CellId> cell;     // region -> its cell
    std::vector<uint32_t> faceOffset, faces;  // region -> faces (ascending)
    std::vector<double> flatness;  // region -> max vertex distance to its plane
    uint32_t count() const { return uint32_t(rep.size()); }
};

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

Regions buildRegions(const Topology& t, const Cut& cut) {
    std::vector<uint32_t> parent(t.nf);
    std::iota(parent.begin(), parent.end(), 0u);
    std::vector<uint64_t> key(t.nf);
    for (uint32_t f = 0; f < t.nf; ++f) key[f] = cellKey(faceCell(t, cut, f));
    for (uint32_t f = 0; f < t.nf; ++f) {
        if (t.degenerate[f]) continue;
        for (uint32_t k = 0; k < 3; ++k) {
            uint32_t o = t.twin[3 * f + k];
            if (o >= kNonManifold) continue;
            uint32_t g = o / 3;
            if (g < f || key[g] != key[f] || t.isPinned(f) || t.isPinned(g)) continue;
            uint32_t a = findRoot(parent, f), b = findRoot(parent, g);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    }
    Regions r;
    r.of.assign(t.nf, kNone);
    for (uint32_t f = 0; f < t.nf; ++f) {
        uint32_t root = findRoot(parent, f);
        if (root == f) {
            r.of[f] = uint32_t(r.rep.size());
            r.rep.push_back(f);
            r.cell.push_back(faceCell(t, cut, f));
        } else {
            r.of[f] = r.of[root];  // root < f: already numbered
        }
    }
    const uint32_t nr = r.count();
    r.faceOffset.assign(nr + 1, 0);
    for (uint32_t f = 0; f < t.nf; ++f) ++r.faceOffset[r.of[f] + 1];
    for (uint32_t i = 0; i < nr; ++i) r.faceOffset[i + 1] += r.faceOffset[i];
    r.faces.resize(t.nf);
    std::vector<uint32_t> fill(r.faceOffset.begin(), r.faceOffset.end() - 1);
    for (uint32_t f = 0; f < t.nf; ++f) r.faces[fill[r.of[f]]++] = f;
    // Flatness: distance of region vertices to the region's plane.
    r.flatness.assign(nr, 0);
    for (uint32_t i = 0; i < nr; ++i) {
        Vec3 n, c;
        double area = 0;
        for (uint32_t k = r.faceOffset[i]; k < r.faceOffset[i + 1]; ++k) {
            const Tri& tr = t.T(r.faces[k]);
            Vec3 w = cross(t.P(tr[1]) - t.P(tr[0]), t.P(tr[2]) - t.P(tr[0]));
            double a = 0.5 * length(w);
            n += w;
            c += (t.P(tr[0]) + t.P(tr[1]) + t.P(tr[2])) * (a / 3);
            area += a;
        }
        if (!(area > 0) || !(length(n) > 0)) continue;
        c = c / area;
        n = normalize(n);
        double m = 0;
        for (uint32_t k = r.faceOffset[i]; k < r.faceOffset[i + 1]; ++k)
            for (uint32_t v : t.T(r.faces[k])) m = std::max(m, std::fabs(dot(t.P(v) - c, n)));
        r.flatness[i] = m;
    }
    return r;
}

// ---- 3. Boundary runs -----------------------------------------------------------------------

bool isBoundary(const Topology& t, const Regions& r, uint32_t h) {
    uint32_t o = t.twin[h];
    return o >= kNonManifold || r.of[o / 3] != r.of[h / 3];
}

struct Run {
    std::vector<uint32_t> vertices;  // v0 .. vm (closed when v0 == vm)
    uint32_t regionA = kNone, regionB = kNone;  // regionB = kNone: mesh border or non-manifold
    bool nonManifold = false;
    bool restored = false;  // keeps every vertex
    double tolerance = 0;
};

struct Runs {
    std::vector<Run> runs;
    std::vector<char> junction;     // per vertex
    std::vector<uint32_t> runOf;    // per vertex: the run of a non-junction boundary vertex, else kNone
    std::vector<uint32_t> posInRun; // per vertex: its index in that run
    std::vector<char> kept;         // per vertex: on a boundary and kept after simplification
};

struct BoundaryEdge {
    uint32_t a, b;     // vertices
    uint32_t h;        // a half-edge carrying it
    uint32_t regionA, regionB;
    bool nonManifold;
};

Runs buildRuns(const Topology& t, const Regions& r) {
    Runs out;
    out.junction.assign(t.nv, 0);
    out.runOf.assign(t.nv, kNone);
    out.posInRun.assign(t.nv, 0);
    out.kept.assign(t.nv, 0);
    std::vector<BoundaryEdge> edges;
    for (uint32_t f = 0; f < t.nf; ++f) {
        if (t.degenerate[f]) continue;
        for (uint32_t k = 0; k < 3; ++k) {
            uint32_t h = 3 * f + k;
            if (!isBoundary(t, r, h)) continue;
            uint32_t o = t.twin[h];
            if (o < kNonManifold && o < h) continue;  // the twin already made it
            BoundaryEdge e;
            e.a = t.T(f)[k];
            e.b = t.T(f)[(k + 1) % 3];
            e.h = h;
            e.regionA = r.of[f];
            e.regionB = o < kNonManifold ? r.of[o / 3] : kNone;
            if (e.regionB != kNone && e.regionB < e.regionA) std::swap(e.regionA, e.regionB);
            e.nonManifold = o == kNonManifold;
            edges.push_back(e);
        }
    }
    // Vertex -> boundary edges.
    std::vector<uint32_t> off(t.nv + 1, 0), inc;
    for (const auto& e : edges) ++off[e.a + 1], ++off[e.b + 1];
    for (uint32_t v = 0; v < t.nv; ++v) off[v + 1] += off[v];
    inc.resize(off[t.nv]);
    {
        std::vector<uint32_t> fill(off.begin(), off.end() - 1);
        for (uint32_t i = 0; i < edges.size(); ++i) inc[fill[edges[i].a]++] = i, inc[fill[edges[i].b]++] = i;
    }
    for (uint32_t v = 0; v < t.nv; ++v) {
        uint32_t n = off[v + 1] - off[v];
        if (n == 0) continue;
        if (n != 2) {
            out.junction[v] = 1;
            continue;
        }
        const BoundaryEdge& e0 = edges[inc[off[v]]];
        const BoundaryEdge& e1 = edges[inc[off[v] + 1]];
        if (e0.nonManifold || e1.nonManifold || e0.regionA != e1.regionA || e0.regionB != e1.regionB) out.junction[v] = 1;
    }
    std::vector<char> used(edges.size(), 0);
    auto walk = [&](uint32_t start, uint32_t firstEdge) {
        Run run;
        const BoundaryEdge& e = edges[firstEdge];
        run.regionA = e.regionA;
        run.regionB = e.regionB;
        run.nonManifold = e.nonManifold;
        run.vertices.push_back(start);
        uint32_t v = start, ei = firstEdge;
        for (;;) {
            used[ei] = 1;
            uint32_t w = edges[ei].a == v ? edges[ei].b : edges[ei].a;
            run.vertices.push_back(w);
            if (out.junction[w]) break;
            uint32_t next = kNone;
            for (uint32_t k = off[w]; k < off[w + 1]; ++k)
                if (!used[inc[k]]) next = inc[k];
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
    };
    for (uint32_t v = 0; v < t.nv; ++v) {
        if (!out.junction[v]) continue;
        for (uint32_t k = off[v]; k < off[v + 1]; ++k)
            if (!used[inc[k]]) walk(v, inc[k]);
    }
    // Closed runs without a junction: anchored at their smallest vertex.
    for (uint32_t i = 0; i < edges.size(); ++i) {
        if (used[i]) continue;
        uint32_t v = edges[i].a, ei = i, smallest = v;
        std::vector<uint32_t> loopEdges;
        std::unordered_set<uint32_t> seen;
        for (;;) {
            if (!seen.insert(ei).second) break;
            loopEdges.push_back(ei);
            uint32_t w = edges[ei].a == v ? edges[ei].b : edges[ei].a;
            smallest = std::min(smallest, w);
            uint32_t next = kNone;
            for (uint32_t k = off[w]; k < off[w + 1]; ++k)
                if (inc[k] != ei && !seen.count(inc[k])) next = inc[k];
            if (next == kNone) break;
            v = w;
            ei = next;
        }
        out.junction[smallest] = 1;
        for (uint32_t k = off[smallest]; k < off[smallest + 1]; ++k)
            if (!used[inc[k]]) {
                walk(smallest, inc[k]);
                break;
            }
    }
    for (uint32_t v = 0; v < t.nv; ++v) out.kept[v] = out.junction[v];
    return out;
}

double pointSegmentDistance(Vec3 p, Vec3 a, Vec3 b, double* param = nullptr) {
    Vec3 ab = b - a;
    double l2 = length2(ab);
    double s = l2 > 0 ? std::clamp(dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    if (param) *param = s;
    return length(p - (a + ab * s));
}

// Douglas-Peucker on one run: marks kept vertices. Closed runs keep at least 3 vertices, runs
// whose two ends are the same vertex at least 2 interior ones.
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

// Simplifies every run; where two runs' simplified edges coincide (a thin region between two
// others would vanish), the later run keeps one more vertex, or is restored.
void simplifyRuns(const Topology& t, Runs& R) {
    for (Run& run : R.runs) simplifyRun(t, run, R.kept);
    for (int round = 0; round < 256; ++round) {
        std::unordered_map<uint64_t, uint32_t> owner;
        std::vector<std::pair<uint32_t, uint32_t>> clash;  // (later run, earlier run)
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
        bool changed = false;
        std::unordered_set<uint32_t> touched;
        for (auto [a, b] : clash) {
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

// ---- 4. Region loops and retriangulation ---------------------------------------------------

// Boundary loops of region i (kept vertices only), walking boundary half-edges with the region
// on the left.
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

enum class RegionState : uint8_t { Pending, Retriangulated, Kept, Empty };

struct RegionOut {
    RegionState state = RegionState::Pending;
    std::vector<Tri> tris;
    Vec3 axis;  // projection direction (cell centre)
};

// Retriangulates region i from its loops in its cell's plane; false when it cannot.
// Retriangulates region i from its loops; false when it cannot. The boundary is projected onto
// the plane orthogonal to the region's area-weighted normal (where positive orientation is exactly
// "facing the region's surface"), else onto its cell's plane (thesis) with that facing condition
// as a veto on the ears.
bool retriangulate(const Topology& t, const Regions& r, const Runs& R, uint32_t i, RegionOut& out,
                   const std::unordered_set<uint64_t>* forbidden = nullptr) {
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

// Runs adjacent to each region.
std::vector<std::vector<uint32_t>> regionRuns(const Runs& R, uint32_t regionCount) {
    std::vector<std::vector<uint32_t>> out(regionCount);
    for (uint32_t i = 0; i < R.runs.size(); ++i) {
        out[R.runs[i].regionA].push_back(i);
        if (R.runs[i].regionB != kNone) out[R.runs[i].regionB].push_back(i);
    }
    return out;
}

// ---- 5. Cell thresholds and run tolerances -------------------------------------------------

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

// ---- 6. A level from a cut -----------------------------------------------------------------

struct LevelBuild {
    Regions regions;
    Runs runs;
    std::vector<RegionOut> out;
    uint32_t restoredRuns = 0;
};

// Marks a failed region: restores its runs (neighbours need rebuilding) or, when they are all
// restored already, keeps its original faces. Returns regions to rebuild.
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

LevelBuild buildLevelGeometry(const Topology& t, const Cut& cut, double boundaryTolerance) {
    LevelBuild L;
    L.regions = buildRegions(t, cut);
    L.runs = buildRuns(t, L.regions);
    setTolerances(t, L.regions, L.runs, boundaryTolerance);
    if (boundaryTolerance <= 0)
        for (Run& run : L.runs.runs) run.tolerance = 1e-9 * t.diagonal;
    pinRuns(t, L.regions, L.runs);
    simplifyRuns(t, L.runs);
    const uint32_t nr = L.regions.count();
    L.out.assign(nr, {});
    auto runsOf = regionRuns(L.runs, nr);
    std::vector<uint32_t> work;
    for (uint32_t i = 0; i < nr; ++i) {
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
    std::vector<char> triedForbidden(nr, 0);
    // Retriangulates region i. Outline (keepOutline): new triangles that cover, seen from a view,
    // what the original leaves uncovered (flattening across a concave stretch of the outline) count
    // as a failure, so the region gets its runs restored, then keeps its original faces.
    auto tryRegion = [&](uint32_t i, const std::unordered_set<uint64_t>* forbidden) {
        RegionOut& o = L.out[i];
        if (!retriangulate(t, L.regions, L.runs, i, o, forbidden)) return false;
        if (!t.outline.views.empty())
            for (const Tri& tr : o.tris)
                if (protrudes(t.outline, t.P(tr[0]), t.P(tr[1]), t.P(tr[2]))) {
                    o.tris.clear();
                    return false;
                }
        return true;
    };
    for (int pass = 0; pass < 1000 && !work.empty(); ++pass) {
        while (!work.empty()) {
            std::sort(work.begin(), work.end());
            work.erase(std::unique(work.begin(), work.end()), work.end());
            std::vector<uint32_t> rebuild;
            for (uint32_t i : work) {
                RegionOut& o = L.out[i];
                if (o.state == RegionState::Kept || o.state == RegionState::Empty) continue;
                if (tryRegion(i, nullptr)) o.state = RegionState::Retriangulated;
                else failRegion(t, L, runsOf, i, rebuild);
            }
            work = std::move(rebuild);
        }
        // Validation: no directed edge twice, no undirected edge more than twice, except where
        // the input already is so.
        std::unordered_map<uint64_t, uint32_t> directed;
        std::unordered_map<uint64_t, uint32_t> undirected;
        for (uint32_t i = 0; i < nr; ++i)
            for (const Tri& tr : L.out[i].tris)
                for (int k = 0; k < 3; ++k) {
                    ++directed[directedKey(tr[size_t(k)], tr[size_t((k + 1) % 3)])];
                    ++undirected[edgeKey(tr[size_t(k)], tr[size_t((k + 1) % 3)])];
                }
        std::vector<uint32_t> blamed;
        for (uint32_t i = 0; i < nr; ++i) {
            if (L.out[i].state != RegionState::Retriangulated) continue;
            bool bad = false;
            for (const Tri& tr : L.out[i].tris)
                for (int k = 0; k < 3 && !bad; ++k) {
                    uint32_t a = tr[size_t(k)], b = tr[size_t((k + 1) % 3)];
                    if (directed[directedKey(a, b)] > 1 || undirected[edgeKey(a, b)] > 2) bad = true;
                }
            if (bad) blamed.push_back(i);
        }
        // Edges that the input itself has more than twice are not the retriangulation's fault.
        if (!blamed.empty()) {
            std::unordered_map<uint64_t, uint32_t> input;
            for (uint32_t f = 0; f < t.nf; ++f)
                if (!t.degenerate[f])
                    for (int k = 0; k < 3; ++k) ++input[edgeKey(t.T(f)[size_t(k)], t.T(f)[size_t((k + 1) % 3)])];
            std::vector<uint32_t> really;
            for (uint32_t i : blamed) {
                bool bad = false;
                for (const Tri& tr : L.out[i].tris)
                    for (int k = 0; k < 3 && !bad; ++k) {
                        uint32_t a = tr[size_t(k)], b = tr[size_t((k + 1) % 3)];
                        uint64_t e = edgeKey(a, b);
                        auto it = input.find(e);
                        bool inputBad = it != input.end() && it->second > 2;
                        if (!inputBad && (directed[directedKey(a, b)] > 1 || undirected[e] > 2)) bad = true;
                    }
                if (bad) really.push_back(i);
            }
            // First try again keeping off the edges every other region uses, one region at a time.
            std::unordered_map<uint64_t, uint32_t> uses;
            for (uint32_t i = 0; i < nr; ++i)
                for (const Tri& tr : L.out[i].tris)
                    for (int k = 0; k < 3; ++k) ++uses[edgeKey(tr[size_t(k)], tr[size_t((k + 1) % 3)])];
            for (uint32_t i : really) {
                RegionOut& o = L.out[i];
                std::unordered_set<uint64_t> mine, forbidden;
                for (const Tri& tr : o.tris)
                    for (int k = 0; k < 3; ++k) {
                        uint64_t e = edgeKey(tr[size_t(k)], tr[size_t((k + 1) % 3)]);
                        if (--uses[e] == 0) uses.erase(e);
                    }
                for (const auto& [e, n] : uses) forbidden.insert(e);
                bool ok = !triedForbidden[i] && tryRegion(i, &forbidden);
                triedForbidden[i] = 1;
                if (!ok) failRegion(t, L, runsOf, i, work);
                for (const Tri& tr : o.tris)
                    for (int k = 0; k < 3; ++k) ++uses[edgeKey(tr[size_t(k)], tr[size_t((k + 1) % 3)])];
            }
        }
    }
    return L;
}

// Closest point among triangles (brute force below a size, else a uniform grid).
struct ClosestFinder {
    const Topology& t;
    const std::vector<Tri>& tris;
    Vec3 lo;
    double h = 1;
    int n[3] = {1, 1, 1};
    std::vector<std::vector<uint32_t>> cells;
    std::vector<uint32_t> stamp;
    uint32_t clock = 0;

    ClosestFinder(const Topology& top, const std::vector<Tri>& tr) : t(top), tris(tr) {
        if (tris.size() <= 48) return;
        Box3 b;
        for (const Tri& x : tris)
            for (uint32_t v : x) b.extend(t.P(v));
        lo = b.min;
        Vec3 ext = b.max - b.min;
        double longest = std::max({ext.x, ext.y, ext.z, 1e-300});
        int res = std::clamp(int(std::cbrt(double(tris.size())) * 1.5), 1, 48);
        h = longest / res;
        for (int k = 0; k < 3; ++k) n[k] = std::clamp(int(std::ceil(ext[k] / h)), 1, 48);
        cells.resize(size_t(n[0]) * n[1] * n[2]);
        stamp.assign(tris.size(), 0);
        for (uint32_t i = 0; i < tris.size(); ++i) {
            Box3 tb;
            for (uint32_t v : tris[i]) tb.extend(t.P(v));
            int a[3], z[3];
            for (int k = 0; k < 3; ++k) a[k] = cellOf(tb.min[k], k), z[k] = cellOf(tb.max[k], k);
            for (int x = a[0]; x <= z[0]; ++x)
                for (int y = a[1]; y <= z[1]; ++y)
                    for (int q = a[2]; q <= z[2]; ++q) cells[index(x, y, q)].push_back(i);
        }
    }
    int cellOf(double v, int axis) const { return std::clamp(int(std::floor((v - lo[axis]) / h)), 0, n[axis] - 1); }
    size_t index(int x, int y, int z) const { return (size_t(z) * n[1] + y) * n[0] + x; }

    // Returns the triangle index, barycentrics and squared distance.
    uint32_t find(Vec3 p, std::array<double, 3>& bary, double& best) {
        best = std::numeric_limits<double>::infinity();
        uint32_t bi = 0;
        auto test = [&](uint32_t i) {
            const Tri& x = tris[i];
            auto b = closestOnTriangle(p, t.P(x[0]), t.P(x[1]), t.P(x[2]));
            Vec3 q = t.P(x[0]) * b[0] + t.P(x[1]) * b[1] + t.P(x[2]) * b[2];
            double d = length2(q - p);
            if (d < best || (d == best && i < bi)) best = d, bi = i, bary = b;
        };
        if (cells.empty()) {
            for (uint32_t i = 0; i < tris.size(); ++i) test(i);
            return bi;
        }
        ++clock;
        int c[3];
        for (int k = 0; k < 3; ++k) c[k] = cellOf(p[k], k);
        int maxR = std::max({n[0], n[1], n[2]});
        for (int r = 0; r <= maxR; ++r) {
            for (int x = c[0] - r; x <= c[0] + r; ++x)
                for (int y = c[1] - r; y <= c[1] + r; ++y)
                    for (int z = c[2] - r; z <= c[2] + r; ++z) {
                        if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r) continue;
                        if (x < 0 || y < 0 || z < 0 || x >= n[0] || y >= n[1] || z >= n[2]) continue;
                        for (uint32_t i : cells[index(x, y, z)])
                            if (stamp[i] != clock) stamp[i] = clock, test(i);
                    }
            // Everything not visited lies outside the cube of cells within ring r.
            double lb = std::numeric_limits<double>::infinity();
            for (int k = 0; k < 3; ++k) {
                double lower = lo[k] + (c[k] - r) * h, upper = lo[k] + (c[k] + r + 1) * h;
                lb = std::min({lb, p[k] - lower, upper - p[k]});
            }
            if (lb > 0 && best <= lb * lb) break;
        }
        return bi;
    }
};

Level assembleLevel(const Topology& t, const LevelBuild& L) {
    const TriMesh& m = *t.mesh;
    const Regions& r = L.regions;
    Level level;
    level.faceRegion.resize(t.nf);
    for (uint32_t f = 0; f < t.nf; ++f) level.faceRegion[f] = r.rep[r.of[f]];
    level.regionCount = r.count();
    const bool wedges = m.cornerWedges.size() == m.triangles.size();
    // Triangles, faces, wedges, region by region.
    std::vector<uint32_t> triRegion;
    for (uint32_t i = 0; i < r.count(); ++i) {
        const RegionOut& o = L.out[i];
        if (o.state == RegionState::Kept) {
            for (uint32_t k = r.faceOffset[i]; k < r.faceOffset[i + 1]; ++k) {
                uint32_t f = r.faces[k];
                level.faces.push_back(f);
                level.triangles.push_back(m.triangles[f]);
                if (wedges) level.cornerWedges.push_back(m.cornerWedges[f]);
                triRegion.push_back(i);
            }
            continue;
        }
        if (o.state != RegionState::Retriangulated) continue;
        for (const Tri& tr : o.tris) {
            // The region's face incident to most corners (then the smallest id).
            uint32_t bestFace = kNone;
            int bestScore = 0;
            for (uint32_t c : tr)
                for (uint32_t k = t.vfOffset[c]; k < t.vfOffset[c + 1]; ++k) {
                    uint32_t f = t.vfFace[k];
                    if (r.of[f] != i) continue;
                    int score = 0;
                    for (uint32_t x : tr) score += (t.T(f)[0] == x) + (t.T(f)[1] == x) + (t.T(f)[2] == x);
                    if (score > bestScore || (score == bestScore && f < bestFace)) bestScore = score, bestFace = f;
                }
            if (bestFace == kNone) bestFace = r.rep[i];
            level.faces.push_back(bestFace);
            level.triangles.push_back(tr);
            triRegion.push_back(i);
            if (!wedges) continue;
            Tri cw{};
            for (int c = 0; c < 3; ++c) {
                uint32_t v = tr[size_t(c)];
                uint32_t wedge = kNone;
                for (int k = 0; k < 3; ++k)
                    if (t.T(bestFace)[size_t(k)] == v) wedge = m.cornerWedges[bestFace][size_t(k)];
                for (uint32_t k = t.vfOffset[v]; k < t.vfOffset[v + 1] && wedge == kNone; ++k) {
                    uint32_t f = t.vfFace[k];
                    if (r.of[f] != i) continue;
                    for (int j = 0; j < 3; ++j)
                        if (t.T(f)[size_t(j)] == v) wedge = m.cornerWedges[f][size_t(j)];
                }
                for (uint32_t k = t.vfOffset[v]; k < t.vfOffset[v + 1] && wedge == kNone; ++k) {
                    uint32_t f = t.vfFace[k];
                    for (int j = 0; j < 3; ++j)
                        if (t.T(f)[size_t(j)] == v) wedge = m.cornerWedges[f][size_t(j)];
                }
                cw[size_t(c)] = wedge == kNone ? 0 : wedge;
            }
            level.cornerWedges.push_back(cw);
        }
    }
    // Pairs. Directed edge -> level triangle (for the edge form of removed run vertices).
    std::unordered_map<uint64_t, uint32_t> edgeTri;
    for (uint32_t i = 0; i < level.triangles.size(); ++i)
        for (int k = 0; k < 3; ++k)
            edgeTri.emplace(directedKey(level.triangles[i][size_t(k)], level.triangles[i][size_t((k + 1) % 3)]), i);
    std::vector<char> present(t.nv, 0);
    for (const Tri& tr : level.triangles)
        for (uint32_t v : tr) present[v] = 1;
    double sum = 0, maxDev = 0;
    // (a) interior vertices of retriangulated regions.
    for (uint32_t i = 0; i < r.count(); ++i) {
        if (L.out[i].state != RegionState::Retriangulated) continue;
        std::vector<uint32_t> removed;
        for (uint32_t k = r.faceOffset[i]; k < r.faceOffset[i + 1]; ++k)
            for (uint32_t v : t.T(r.faces[k]))
                if (!present[v] && L.runs.runOf[v] == kNone && !L.runs.junction[v]) removed.push_back(v);
        std::sort(removed.begin(), removed.end());
        removed.erase(std::unique(removed.begin(), removed.end()), removed.end());
        if (removed.empty()) continue;
        const std::vector<Tri>& tris = L.out[i].tris;
        ClosestFinder finder(t, tris);
        // Level triangle index of the region's first triangle (triangles are region-contiguous).
        uint32_t firstTri = uint32_t(std::lower_bound(triRegion.begin(), triRegion.end(), i) - triRegion.begin());
        for (uint32_t v : removed) {
            std::array<double, 3> b{};
            double d2 = 0;
            uint32_t k = finder.find(t.P(v), b, d2);
            SimplificationPair p;
            p.vertex = v;
            p.coarse = tris[k];
            p.bary = {float(b[0]), float(b[1]), float(b[2])};
            p.face = level.faces[firstTri + k];
            Vec3 q = t.P(p.coarse[0]) * p.bary[0] + t.P(p.coarse[1]) * p.bary[1] + t.P(p.coarse[2]) * p.bary[2];
            p.deviation = float(length(t.P(v) - q));
            level.pairs.push_back(p);
        }
    }
    // (b) removed run vertices: closest point on their simplified edge.
    for (uint32_t v = 0; v < t.nv; ++v) {
        uint32_t ri = L.runs.runOf[v];
        if (ri == kNone || L.runs.kept[v] || present[v]) continue;
        const auto& rv = L.runs.runs[ri].vertices;
        size_t pos = L.runs.posInRun[v];
        size_t a = pos, b = pos;
        while (a > 0 && !L.runs.kept[rv[a]]) --a;
        while (b + 1 < rv.size() && !L.runs.kept[rv[b]]) ++b;
        uint32_t va = rv[a], vb = rv[b];
        double s = 0;
        double d = pointSegmentDistance(t.P(v), t.P(va), t.P(vb), &s);
        SimplificationPair p;
        p.vertex = v;
        p.coarse = {va, vb, vb};
        p.bary = {float(1 - s), float(s), 0.f};
        auto it = edgeTri.find(directedKey(va, vb));
        if (it == edgeTri.end()) it = edgeTri.find(directedKey(vb, va));
        p.face = it != edgeTri.end() ? level.faces[it->second] : r.rep[L.runs.runs[ri].regionA];
        p.deviation = float(d);
        level.pairs.push_back(p);
    }
    std::sort(level.pairs.begin(), level.pairs.end(),
              [](const SimplificationPair& x, const SimplificationPair& y) { return x.vertex < y.vertex; });
    for (const auto& p : level.pairs) sum += p.deviation, maxDev = std::max(maxDev, double(p.deviation));
    level.maxDeviation = maxDev;
    level.meanDeviation = level.pairs.empty() ? 0 : sum / double(level.pairs.size());
    return level;
}

// ---- 7. Depth statistics (estimates that drive the selection) ------------------------------

struct DepthTables {
    std::vector<std::vector<uint32_t>> estimate;  // [depth][cell] estimated triangles
    std::vector<std::vector<float>> threshold;    // [depth][cell] error threshold
};

uint64_t estimateRegionTriangles(const Topology& t, const Regions& r, const Runs& R, uint32_t i) {
    if (t.degenerate[r.rep[i]]) return 0;
    auto loops = regionLoops(t, r, R, i);
    uint64_t n = 0;
    for (const auto& l : loops) {
        if (l.size() < 3) return r.faceOffset[i + 1] - r.faceOffset[i];
        n += l.size();
    }
    if (loops.empty()) return r.faceOffset[i + 1] - r.faceOffset[i];
    return n + 2 * (loops.size() - 1) - 2;
}

// ---- 8. Selection --------------------------------------------------------------------------

enum class CellClass : uint8_t { Orthogonal = 0, Other = 1, Reference = 2, Coarsest = 3 };

CellClass classify(const AgsphereOptions& o, uint32_t cell, int depth) {
    if (o.views.empty() && o.lights.empty()) return CellClass::Other;
    Vec3 c = sphereCellCenter(cell, depth);
    double rho = sphereCellRadius(cell, depth);
    const double band = o.silhouetteBandDeg * kPi / 180, right = kPi / 2;
    auto angle = [&](Vec3 d) { return std::acos(std::clamp(dot(c, normalize(d)), -1.0, 1.0)); };
    bool sil = false, ref = false, lit = false, allBack = !o.lights.empty();
    bool viewBack = !o.views.empty();  // facing away from every view: never seen
    for (Vec3 v : o.views) {
        double th = angle(v);
        if (th - rho <= right + band && th + rho >= right - band) sil = true;
        if (th - rho <= 0 || th + rho <= kPi / 3) ref = true;
        if (!(th - rho > right + band)) viewBack = false;
    }
    for (Vec3 l : o.lights) {
        double th = angle(l);
        if (th - rho <= right + band && th + rho >= right - band) sil = true;
        if (!(th - rho > right + band)) allBack = false;
        if (th + rho < right - band) lit = true;
    }
    if (sil) return CellClass::Orthogonal;
    if (allBack || (o.backCellsCoarsest && viewBack)) return CellClass::Coarsest;
    if (ref || (o.views.empty() && lit)) return CellClass::Reference;
    return CellClass::Other;
}

struct Leaf {
    uint8_t depth;
    uint32_t cell;
    CellClass cls;
};

struct Selection {
    Cut cut;
    uint64_t estimate = 0;
    std::string stopReason;
};

void balanceCut(const Topology& t, const std::vector<std::array<uint32_t, 3>>& nb, Cut& cut) {
    const int D = t.maxDepth;
    for (bool changed = true; changed;) {
        changed = false;
        for (uint32_t x = 0; x < cut.size(); ++x)
            for (uint32_t y : nb[x]) {
                if (cut[y] <= cut[x] + 2) continue;
                uint8_t d = cut[x];
                uint32_t leaf = x >> (2 * (D - d));
                uint32_t span = 1u << (2 * (D - d));
                for (uint32_t z = leaf * span; z < (leaf + 1) * span; ++z) cut[z] = uint8_t(d + 1);
                changed = true;
            }
    }
}

Selection selectCut(const Topology& t, const AgsphereOptions& o, const DepthTables& tables, uint64_t target) {
    const int D = t.maxDepth;
    std::vector<Leaf> leaves;
    for (uint32_t c = 0; c < 8; ++c) leaves.push_back({0, c, classify(o, c, 0)});
    auto est = [&](const Leaf& l) { return uint64_t(tables.estimate[l.depth][l.cell]); };
    auto children = [&](const Leaf& l) {
        std::array<Leaf, 4> ch;
        for (uint32_t k = 0; k < 4; ++k) {
            uint32_t c = l.cell * 4 + k;
            ch[k] = {uint8_t(l.depth + 1), c, classify(o, c, l.depth + 1)};
        }
        return ch;
    };
    // Default offsets: silhouette cells two depths finer than reference cells, others one. When
    // that is already above the target, the offsets shrink (by `relax` depths) so that the rounds
    // below can still trade reference detail for silhouette detail.
    auto minDepth = [&](CellClass c, int relax) {
        if (o.views.empty() && o.lights.empty()) return 0;
        int base = c == CellClass::Orthogonal ? 2 : (c == CellClass::Other ? 1 : 0);
        return std::max(0, std::min(base - relax, D));
    };
    std::vector<Leaf> roots = leaves;
    for (int relax = 0; relax <= 2; ++relax) {
        leaves = roots;
        for (bool changed = true; changed;) {
            changed = false;
            std::vector<Leaf> next;
            for (const Leaf& l : leaves) {
                if (l.depth < minDepth(l.cls, relax)) {
                    for (const Leaf& c : children(l)) next.push_back(c);
                    changed = true;
                } else {
                    next.push_back(l);
                }
            }
            leaves = std::move(next);
        }
        uint64_t sum = 0;
        for (const Leaf& l : leaves) sum += est(l);
        if (sum <= target) break;
    }
    uint64_t total = 0;
    for (const Leaf& l : leaves) total += est(l);
    Selection s;
    s.stopReason = "target";
    // Rounds: silhouette cells, then the others, then reference cells; largest error first.
    bool reached = total >= target;
    if (reached && total > target) s.stopReason = "coarsest cut";  // the sphere cannot go lower
    uint64_t before = total;
    int lastLeaf = -1;
    std::array<Leaf, 4> lastChildren{};
    Leaf lastParent{};
    while (!reached) {
        bool expanded = false;
        for (CellClass cls : {CellClass::Orthogonal, CellClass::Other, CellClass::Reference}) {
            std::vector<uint32_t> order;
            for (uint32_t i = 0; i < leaves.size(); ++i)
                if (leaves[i].cls == cls && leaves[i].depth < D && est(leaves[i]) > 0) order.push_back(i);
            std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
                float ta = tables.threshold[leaves[a].depth][leaves[a].cell];
                float tb = tables.threshold[leaves[b].depth][leaves[b].cell];
                if (ta != tb) return ta > tb;
                return cellKey({leaves[a].depth, leaves[a].cell}) < cellKey({leaves[b].depth, leaves[b].cell});
            });
            std::vector<Leaf> added;
            std::vector<char> gone(leaves.size(), 0);
            for (uint32_t i : order) {
                if (total >= target) break;
                before = total;
                auto ch = children(leaves[i]);
                total -= est(leaves[i]);
                for (const Leaf& c : ch) total += est(c), added.push_back(c);
                gone[i] = 1;
                lastParent = leaves[i];
                lastChildren = ch;
                lastLeaf = 1;
                expanded = true;
            }
            std::vector<Leaf> next;
            for (uint32_t i = 0; i < leaves.size(); ++i)
                if (!gone[i]) next.push_back(leaves[i]);
            for (const Leaf& c : added) next.push_back(c);
            leaves = std::move(next);
            if (total >= target) break;
        }
        if (total >= target) reached = true;
        if (!expanded) {
            s.stopReason = "finest depth";
            break;
        }
    }
    // The last expansion is undone when the count before it was closer to the target.
    if (reached && lastLeaf >= 0 && before < target && target - before < total - target) {
        std::vector<Leaf> next;
        for (const Leaf& l : leaves) {
            bool isChild = false;
            for (const Leaf& c : lastChildren) isChild |= c.depth == l.depth && c.cell == l.cell;
            if (!isChild) next.push_back(l);
        }
        next.push_back(lastParent);
        leaves = std::move(next);
        total = before;
    }
    s.cut.assign(sphereCellCount(D), 0);
    for (const Leaf& l : leaves) {
        uint32_t span = 1u << (2 * (D - l.depth));
        for (uint32_t z = l.cell * span; z < (l.cell + 1) * span; ++z) s.cut[z] = l.depth;
    }
    s.estimate = total;
    return s;
}

}  // namespace

uint32_t agsphereRegions(const TriMesh& mesh, int depth, std::vector<uint32_t>& faceRegion) {
    if (depth < 0 || depth > kAgsphereMaxDepth) throw InvalidInput("agsphere depth out of range");
    Topology t = buildTopology(mesh, depth);
    Cut cut(sphereCellCount(depth), uint8_t(depth));
    Regions r = buildRegions(t, cut);
    faceRegion.resize(t.nf);
    for (uint32_t f = 0; f < t.nf; ++f) faceRegion[f] = r.rep[r.of[f]];
    return r.count();
}

AgsphereResult buildAgsphere(const TriMesh& mesh, const AgsphereOptions& options) {
    if (mesh.triangleCount() == 0) throw Impossible("the mesh has no triangles");
    if (options.maxDepth < 0 || options.maxDepth > kAgsphereMaxDepth)
        throw Impossible("sphere depth must be in [0, " + std::to_string(kAgsphereMaxDepth) + "]");
    if (options.levels.empty()) throw Impossible("no level targets given");
    auto progress = [&](double f) {
        if (options.progress && !options.progress(f)) throw Impossible("cancelled");
    };
    AgsphereResult res;
    res.multires.generator = "agsphere-build";
    const int D = options.maxDepth;

    auto t0 = std::chrono::steady_clock::now();
    // Views and lights in the sphere's frame (classification works there).
    const Frame frame = alignedFrame(options);
    AgsphereOptions sphereOptions = options;
    for (Vec3& v : sphereOptions.views) v = frame.toSphere(normalize(v));
    for (Vec3& v : sphereOptions.lights) v = frame.toSphere(normalize(v));
    Topology t = buildTopology(mesh, D, frame);
    res.diagonal = t.diagonal;
    if (options.keepOutline && (!options.views.empty() || !options.lights.empty())) {
        // Views at their eye distance; lights at infinity (the outline seen from a light is the
        // light silhouette: the shadow's outline).
        OutlineOptions oo;
        oo.viewDistance = options.viewDistance;
        oo.rings = options.outlineRings;
        OutlineFaces of = outlineFaces(mesh, options.views, oo);
        oo.viewDistance = 0;
        OutlineFaces lit = outlineFaces(mesh, options.lights, oo);
        for (uint32_t f = 0; f < t.nf; ++f) of.keep[f] = !t.degenerate[f] && (of.keep[f] || lit.keep[f]);
        for (OutlineView& v : lit.views) of.views.push_back(std::move(v));
        res.contourEdges = of.contourEdges + lit.contourEdges;
        res.outlineEdges = of.outlineEdges + lit.outlineEdges;
        t.pinned = std::move(of.keep);
        t.outline = std::move(of);
        for (char k : t.pinned) res.outlineFaces += k != 0;
    }
    auto nb = sphereNeighbourTable(D);
    res.secondsCells = secondsSince(t0);
    progress(0.05);

    // Depth statistics.
    auto t1 = std::chrono::steady_clock::now();
    DepthTables tables;
    tables.estimate.resize(size_t(D) + 1);
    tables.threshold.resize(size_t(D) + 1);
    for (int d = 0; d <= D; ++d) {
        Cut cut(sphereCellCount(D), uint8_t(d));
        Regions r = buildRegions(t, cut);
        Runs R = buildRuns(t, r);
        setTolerances(t, r, R, options.boundaryTolerance);
        pinRuns(t, r, R);
        simplifyRuns(t, R);
        tables.estimate[size_t(d)].assign(sphereCellCount(d), 0);
        tables.threshold[size_t(d)].assign(sphereCellCount(d), 0.f);
        AgsphereDepthStats st;
        st.depth = d;
        st.regions = r.count();
        for (uint32_t i = 0; i < r.count(); ++i) {
            uint64_t e = estimateRegionTriangles(t, r, R, i);
            tables.estimate[size_t(d)][r.cell[i].index] += uint32_t(e);
            float& th = tables.threshold[size_t(d)][r.cell[i].index];
            th = std::max(th, float(r.flatness[i]));
            st.estimatedTriangles += e;
            st.maxThreshold = std::max(st.maxThreshold, r.flatness[i]);
        }
        for (uint32_t c = 0; c < sphereCellCount(d); ++c) st.cells += tables.estimate[size_t(d)][c] > 0;
        res.depths.push_back(st);
        progress(0.05 + 0.35 * double(d + 1) / double(D + 1));
    }
    res.secondsDepths = secondsSince(t1);

    // Selection: finest level first; coarser cuts contained in finer ones.
    auto t2 = std::chrono::steady_clock::now();
    struct Planned {
        AgsphereTarget target;
        uint64_t triangles;
        Selection sel;
    };
    std::vector<Planned> plan;
    for (const AgsphereTarget& g : options.levels) {
        uint64_t n = g.triangles;
        if (g.ratio > 0) n = uint64_t(std::llround(g.ratio * double(t.nf)));
        if (n == 0) n = 1;
        plan.push_back({g, n, {}});
    }
    std::stable_sort(plan.begin(), plan.end(), [](const Planned& a, const Planned& b) { return a.triangles > b.triangles; });
    for (Planned& p : plan) {
        p.sel = selectCut(t, sphereOptions, tables, p.triangles);
        balanceCut(t, nb, p.sel.cut);
    }
    res.secondsSelect = secondsSince(t2);

    // Levels, coarsest first: a region that keeps its original faces (its boundary is not a
    // simple polygon in its cell's plane) has its cell split and the level rebuilt; each cut then
    // contains the next coarser level's final cut, so regions nest across levels.
    auto t3 = std::chrono::steady_clock::now();
    std::vector<Level> built(plan.size());
    std::vector<AgsphereLevelStats> builtStats(plan.size());
    Cut coarser;
    for (size_t k = plan.size(); k-- > 0;) {
        auto tl = std::chrono::steady_clock::now();
        Planned& p = plan[k];
        // The estimates behind the selection ignore restored runs and split cells, so the level
        // is rebuilt (up to kCalibrationRounds times) with the estimate target scaled by
        // target / reached, keeping the build closest to the target.
        auto buildCut = [&](Cut& cut) {
            if (!coarser.empty())
                for (size_t z = 0; z < cut.size(); ++z) cut[z] = std::max(cut[z], coarser[z]);
            balanceCut(t, nb, cut);
            LevelBuild B = buildLevelGeometry(t, cut, options.boundaryTolerance);
            for (int round = 0; round < 8; ++round) {
                bool refined = false;
                for (uint32_t i = 0; i < B.regions.count(); ++i) {
                    if (B.out[i].state != RegionState::Kept) continue;
                    CellId c = B.regions.cell[i];
                    if (B.regions.faceOffset[i + 1] - B.regions.faceOffset[i] < kRefineKeptFaces || c.depth >= D) continue;
                    uint32_t span = 1u << (2 * (D - c.depth));
                    for (uint32_t z = c.index * span; z < (c.index + 1) * span; ++z)
                        cut[z] = std::max<uint8_t>(cut[z], uint8_t(c.depth + 1));
                    refined = true;
                }
                if (!refined) break;
                balanceCut(t, nb, cut);
                B = buildLevelGeometry(t, cut, options.boundaryTolerance);
            }
            return B;
        };
        auto triangles = [](const LevelBuild& B) {
            uint64_t n = 0;
            for (const RegionOut& o : B.out) n += o.tris.size();
            return n;
        };
        const double goal = double(p.triangles);
        LevelBuild L = buildCut(p.sel.cut);
        uint64_t reached = triangles(L);
        double estimateTarget = goal;
        for (int round = 0; round < kCalibrationRounds && p.sel.stopReason == "target"; ++round) {
            if (std::fabs(double(reached) - goal) <= kCalibrationTolerance * goal) break;
            estimateTarget = std::max(1.0, estimateTarget * goal / double(std::max<uint64_t>(reached, 1)));
            Selection sel = selectCut(t, sphereOptions, tables, uint64_t(std::llround(estimateTarget)));
            balanceCut(t, nb, sel.cut);
            LevelBuild B = buildCut(sel.cut);
            uint64_t n = triangles(B);
            if (std::fabs(double(n) - goal) < std::fabs(double(reached) - goal)) {
                L = std::move(B);
                reached = n;
                p.sel = std::move(sel);
            }
        }
        coarser = p.sel.cut;
        Level level = assembleLevel(t, L);
        level.targetRatio = p.target.ratio;
        level.targetTriangles = p.triangles;
        level.stopReason = p.sel.stopReason;
        level.seconds = secondsSince(tl);
        AgsphereLevelStats st;
        st.stopReason = p.sel.stopReason;
        st.estimatedTriangles = p.sel.estimate;
        st.cellsPerDepth.assign(size_t(D) + 1, 0);
        std::unordered_set<uint64_t> seen;
        for (uint32_t z = 0; z < p.sel.cut.size(); ++z) {
            uint8_t d = p.sel.cut[z];
            uint32_t c = z >> (2 * (D - d));
            if (!seen.insert(cellKey({d, c})).second) continue;
            ++st.cellsPerDepth[d];
            switch (classify(sphereOptions, c, d)) {
                case CellClass::Orthogonal: ++st.orthogonalCells; break;
                case CellClass::Reference: ++st.referenceCells; break;
                case CellClass::Coarsest: ++st.coarsestCells; break;
                default: ++st.otherCells; break;
            }
        }
        for (uint32_t i = 0; i < L.regions.count(); ++i) {
            const RegionOut& o = L.out[i];
            bool pinned = t.isPinned(L.regions.rep[i]);
            st.retriangulatedRegions += o.state == RegionState::Retriangulated;
            st.keptRegions += o.state == RegionState::Kept && !pinned;
            st.outlineFaces += pinned;
        }
        st.restoredRuns = L.restoredRuns;
        st.runs = uint32_t(L.runs.runs.size());
        for (const Run& run : L.runs.runs) {
            if (run.restored || run.nonManifold) continue;
            for (size_t i = 1; i + 1 < run.vertices.size(); ++i)
                if (!L.runs.kept[run.vertices[i]]) {
                    ++st.simplifiedRuns;
                    break;
                }
        }
        built[k] = std::move(level);
        builtStats[k] = std::move(st);
        progress(0.4 + 0.6 * double(plan.size() - k) / double(plan.size()));
    }
    res.multires.levels = std::move(built);
    res.levelStats = std::move(builtStats);
    res.secondsLevels = secondsSince(t3);
    return res;
}

}  // namespace lodbake
