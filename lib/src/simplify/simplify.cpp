// Half-edge-collapse simplification with a region hierarchy.
//
// References
//   [Hoppe96]    H. Hoppe, "Progressive meshes", SIGGRAPH 1996 (collapse records, vertex hierarchy).
//   [Garland97]  M. Garland, P. Heckbert, "Surface simplification using quadric error metrics",
//                SIGGRAPH 1997 (the quadric proxy of the cost below).
//   [Thesis]     "Multiresolution model generation of texture-geometry for the real-time
//                rendering", ch. 2.3 (edge collapsing with region hierarchy) and ch. 3.2 (modified
//                multiresolution geometry generation: p-boundaries, the three region rules).
//   [meshopt]    A. Kapoulkine, meshoptimizer simplifier.cpp (kCanCollapse-style rule tables,
//                half-edge collapse ordering by error, boundary-locking rules).
//
// Pipeline (simplify() at the bottom reads as this script):
//   1. validateInput        throw Impossible when there is nothing to simplify
//   2. buildAdjacency       vertex -> incident live faces (small vectors)
//   3. classifyVertices     lock vertices on non-manifold edges / non-manifold fans /
//                           degenerate faces; find open-boundary vertices; label components and
//                           mark closed ones
//   4. initQuadrics         per-vertex area-weighted plane quadrics (+ border planes)
//   5. initRegions          every face is its own region (rep = itself), per-region shape stats
//   6. planLevels           sort the targets finest first
//   7. loop: pop the best vertex, re-evaluate it, applyCollapse, re-evaluate its new one-ring;
//            snapshotLevel whenever a target is reached or no collapse is left.
//
// Cost ("vertex deviation", model units). For a half-edge collapse v_i -> v_j:
//     cost = max( d(V_i, new fan),                    thesis vertex deviation
//                 max_{f in fan(v_i)} err(f),          memory: farthest removed point on the fan
//                 sqrt(Q_i(V_j) / W_i) )               quadric proxy of the accumulated shape
//   where "new fan" = the faces around v_i that survive, with v_i moved to v_j; err(f) = distance
//   of the farthest previously removed original vertex currently assigned to face f; Q_i = sum of
//   the (area-weighted) planes of the original faces merged into v_i, W_i their total weight.
//   Every removed vertex is assigned to the coarse face it projects to (closest point). When a
//   collapse is applied, all points assigned to the fan of v_i (and V_i itself) are re-projected
//   onto the new fan (exactly, not capped); the recorded CollapseRecord::deviation is the max of
//   the evaluated cost and the largest re-projected distance, so the running max of recorded
//   deviations bounds every simplification-pair deviation. Each face also keeps its farthest
//   assigned point (faceTop); the cost computed when a vertex is (re-)queued re-projects only those,
//   a lower bound of the exact cost. The exact re-projection of every point is measured once when
//   the candidate comes off the heap (and the candidate is re-queued if it is no longer the best).
//
// Collapse candidates: one heap entry per vertex (its best outgoing half-edge), lazy deletion by a
// per-vertex version. The evaluated candidate is stored per vertex (cand) with the epoch (collapse
// counter) of its evaluation. It stays valid until the vertex's fan changes (the vertex is then
// re-queued) or a region of its fan merges (regionEpoch): then, when popped, only the region part
// (rule 1, rule 3, E_region key) is re-planned (refreshRegions; the target cannot change: geometry
// is the same and rule 1 only gets stricter); a full re-evaluation happens only when the stored
// target is now rejected. A refreshed candidate is applied at once when it is still no worse than
// the heap's top, else re-queued. Link condition and neighbour sets use stamp arrays, no sorting.
//
// Validity (see kRejectReason): both ends unlocked; a border vertex only moves along a border
// edge; the link condition; no face of the new fan degenerates, turns by more than
// maxNormalChangeDeg, or faces away from its own original normal; a vertex whose whole fan would
// vanish (an "ear") is kept; region rule 1.
//
// Regions (DESIGN.md). faceRegion[f] = representative face of f's region; region face lists are
// intrusive linked lists merged by union by size (the largest region keeps its label, even when its
// representative face has been removed), so relabelling is O(F log F) in total. A removed
// representative is replaced by the smallest surviving face of its region only when a level is
// snapshotted (fixDeadRepresentatives; those updates are recorded with the level's last collapse),
// so every level's representatives are surviving faces of their regions.
//   - A spoke (v_i, w) is a p-boundary spoke when its two faces lie in different regions.
//   - Rule 3: v_i interior with exactly two p-boundary spokes (v_i, v_j) and (v_i, v_k), the
//     collapse goes along one of them (to v_j) and d(V_i, segment V_j V_k) <= eps with
//     eps = max(epsilonDeviationFactor * cost, epsilonBoxFactor * longest box side): the new edge
//     (v_j, v_k) stays a p-boundary, so the two sides keep their regions (nothing merges).
//   - Otherwise every region touching the fan of v_i merges into one (the collapse crosses or
//     ends the p-boundaries through v_i).
//   - Rule 1: on a closed component at least two regions must remain.
//   - Representative of a merge: the rep of the largest merged region (ties: a rep that survives
//     the collapse, then the smaller id). Rule 3 collapses change no label.
//   - Rule 2 is a secondary heap key: deviations are quantised into buckets of relative width
//     similarDeviation, and within a bucket the collapse whose resulting region has the lower
//     E_region goes first. E_region is approximated from per-region accumulated stats:
//       E = area(R)/area(M) * ( (1 - |sum a_f n_f| / area(R)) * h  +  max(0, h - sqrt(area(R)/pi)) )
//     with h = half the diagonal of R's bounding box: the first term stands for the distance to the
//     fitted plane (normal-cone spread times size), the second for max|x-c| - min|y-c| (a disk has
//     h ~ its radius ~ sqrt(A/pi)). The key is computed when the candidate is evaluated.
//   Known limit (\bug): the "region must stay a disk" test is only global for rule 1; a merge that
//   turns a region into an annulus on an open surface (two regions sharing two boundary runs) is
//   not detected.
//
// Simplification pairs: at each level, every removed original vertex V gets the closest point P on
// the coarse face it is assigned to (same region); when P lies on an edge of that face which is a
// p-boundary at this level, the pair is written in edge form (coarse[2] == coarse[1]).
//
// Corner wedges: a surviving face keeps its own wedges; a corner moving from v_i to v_j takes the
// v_j wedge of a removed face (one containing edge v_i v_j) whose v_i corner used the same wedge,
// else a v_j wedge of the same material, else any v_j wedge. Seams and materials never block.

#include "lodbake/simplify/simplify.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>

#include "lodbake/core/errors.h"

namespace lodbake {
namespace {

constexpr uint32_t kNone = 0xffffffffu;

// ---------------------------------------------------------------------------------------------
// Rule table: why a vertex could not collapse. The stop reason of a level that cannot reach its
// target is the most frequent reason among the remaining vertices.
enum class Reject : uint8_t { None, Locked, Border, Link, Flip, Degenerate, Ear, Rule1, Isolated, Count };

constexpr const char* kRejectReason[] = {
    "target",                           // None
    "locked: non-manifold",             // Locked: the vertex or its target touches a non-manifold edge/fan
    "border: no collapse along the open boundary",  // Border
    "topology: link condition",         // Link
    "no valid collapse: face flip",     // Flip
    "no valid collapse: degenerate face",  // Degenerate
    "no valid collapse: corner",        // Ear: the whole fan would vanish
    "rule1: last p-boundary",           // Rule1
    "no valid collapse",                // Isolated
};
static_assert(sizeof(kRejectReason) / sizeof(kRejectReason[0]) == size_t(Reject::Count), "rule table");

// ---------------------------------------------------------------------------------------------
// Small math.

struct Quadric {
    double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0, b0 = 0, b1 = 0, b2 = 0, c = 0, w = 0;

    void addPlane(Vec3 n, double d, double weight) {
        a00 += weight * n.x * n.x; a01 += weight * n.x * n.y; a02 += weight * n.x * n.z;
        a11 += weight * n.y * n.y; a12 += weight * n.y * n.z; a22 += weight * n.z * n.z;
        b0 += weight * n.x * d; b1 += weight * n.y * d; b2 += weight * n.z * d;
        c += weight * d * d; w += weight;
    }
    void add(const Quadric& q) {
        a00 += q.a00; a01 += q.a01; a02 += q.a02; a11 += q.a11; a12 += q.a12; a22 += q.a22;
        b0 += q.b0; b1 += q.b1; b2 += q.b2; c += q.c; w += q.w;
    }
    double eval(Vec3 p) const {
        double r = a00 * p.x * p.x + a11 * p.y * p.y + a22 * p.z * p.z +
                   2 * (a01 * p.x * p.y + a02 * p.x * p.z + a12 * p.y * p.z) +
                   2 * (b0 * p.x + b1 * p.y + b2 * p.z) + c;
        return r > 0 ? r : 0;
    }
    // RMS distance of the accumulated planes to p.
    double distance(Vec3 p) const { return w > 0 ? std::sqrt(eval(p) / w) : 0; }
};

struct Closest {
    double bary[3];
    double dist2;
};

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
Closest closestOnTriangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
    auto make = [&](double u, double v, double w) {
        Vec3 q = a * u + b * v + c * w;
        return Closest{{u, v, w}, length2(p - q)};
    };
    Vec3 ab = b - a, ac = c - a, ap = p - a;
    double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return make(1, 0, 0);
    Vec3 bp = p - b;
    double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return make(0, 1, 0);
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        return make(1 - v, v, 0);
    }
    Vec3 cp = p - c;
    double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return make(0, 0, 1);
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        return make(1 - w, 0, w);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return make(0, 1 - w, w);
    }
    double denom = va + vb + vc;
    if (!(std::fabs(denom) > 0)) return make(1, 0, 0);  // degenerate triangle
    double v = vb / denom, w = vc / denom;
    return make(1 - v - w, v, w);
}

double distanceToSegment(Vec3 p, Vec3 a, Vec3 b) {
    Vec3 ab = b - a;
    double l2 = length2(ab);
    double t = l2 > 0 ? std::clamp(dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
    return length(p - (a + ab * t));
}

// ---------------------------------------------------------------------------------------------
// State.

struct RegionStats {
    double area = 0;
    Vec3 normalSum;  // sum of area-weighted unit normals
    float bmin[3], bmax[3];
};

struct Key {
    int64_t bucket;
    float shape;
    double dev;
    uint32_t vertex;
    uint32_t version;
};
struct KeyGreater {  // min-heap order: bucket, then E_region, then deviation, then vertex id
    bool operator()(const Key& a, const Key& b) const {
        if (a.bucket != b.bucket) return a.bucket > b.bucket;
        if (a.shape != b.shape) return a.shape > b.shape;
        if (a.dev != b.dev) return a.dev > b.dev;
        return a.vertex > b.vertex;
    }
};

struct Candidate {
    Reject reason = Reject::Isolated;
    uint32_t target = kNone;
    double dev = 0;
    double devGeom = 0;  // dev before the re-projection of the removed points (rule 3's epsilon)
    float shape = 0;
    bool rule3 = false;
    bool exact = false;  // dev includes the exact re-projection of every removed point of the fan
};

// One neighbour w of a vertex v: the faces around v containing edge (v, w).
struct RingEntry {
    uint32_t w;
    uint32_t f0, f1;  // f1 == kNone when the edge has one face around v
};

struct State {
    const TriMesh& mesh;
    const SimplifyOptions& options;
    size_t vertexCount = 0, faceCount = 0;

    std::vector<Tri> tri;             // current corners
    std::vector<Tri> wedge;           // current corner wedges (empty when the mesh has none)
    std::vector<uint8_t> faceAlive;
    std::vector<std::vector<uint32_t>> vfaces;  // live faces around each vertex
    std::vector<uint8_t> locked, border, removed;
    std::vector<uint32_t> component;  // per vertex
    std::vector<uint8_t> componentClosed;
    std::vector<uint32_t> componentRegions;
    std::vector<std::array<float, 3>> originalNormal;  // unit, per face (zero when degenerate)
    std::vector<Quadric> quadric;

    // Regions.
    std::vector<uint32_t> faceRegion, regionNext, regionHead, regionTail, regionSize;
    std::vector<RegionStats> regionStats;
    uint32_t regionCount = 0;
    double totalArea = 0;

    // Removed points assigned to coarse faces.
    std::vector<uint32_t> pointHead, pointNext, pointFace;
    std::vector<float> pointDist, faceErr;
    static constexpr int kTop = 1;  // the farthest points of each face, used by the cost
    std::vector<std::array<uint32_t, kTop>> faceTop;

    // Heap.
    std::vector<Key> heap;  // binary min-heap (std::push_heap with KeyGreater), lazy deletion
    std::vector<uint32_t> version;
    std::vector<Reject> lastReject;

    size_t aliveFaces = 0;
    double diagonal = 0, longestSide = 0, cosMaxNormalChange = 0;
    double runningMax = 0;  // running max of recorded collapse deviations
    double levelMax = 0;    // maxDeviation of the previous level

    Multires out;

    // Scratch.
    std::vector<RingEntry> ringI;
    std::vector<uint32_t> ringJ, scratch, repScratch, fanScratch, keptScratch, removedScratch, pointScratch,
        sameRegionScratch;
    uint32_t collapseSource = kNone, collapseTarget = kNone;
    std::vector<uint32_t> markI, markJ;
    std::vector<Candidate> cand;
    std::vector<uint32_t> pushEpoch, regionEpoch;
    uint32_t epoch = 0;
    uint32_t stampI = 0, stampJ = 0;

    State(const TriMesh& m, const SimplifyOptions& o) : mesh(m), options(o) {}

    int corner(uint32_t f, uint32_t v) const {
        const Tri& t = tri[f];
        return t[0] == v ? 0 : (t[1] == v ? 1 : (t[2] == v ? 2 : -1));
    }
    int32_t material(uint32_t f) const {
        return f < mesh.triangleMaterial.size() ? mesh.triangleMaterial[f] : -1;
    }
};

// ---------------------------------------------------------------------------------------------
// 1. Input.

static void validateInput(const TriMesh& mesh) {
    if (mesh.triangles.empty()) throw Impossible("simplify: the mesh has no triangles");
    for (const Tri& t : mesh.triangles)
        for (uint32_t v : t)
            if (v >= mesh.positions.size()) throw InvalidInput("simplify: triangle index out of range");
}

// 2. Adjacency.

static void buildAdjacency(State& s) {
    const TriMesh& m = s.mesh;
    s.vertexCount = m.positions.size();
    s.faceCount = m.triangles.size();
    s.tri = m.triangles;
    if (m.cornerWedges.size() == m.triangles.size()) s.wedge = m.cornerWedges;
    s.faceAlive.assign(s.faceCount, 1);
    s.aliveFaces = s.faceCount;
    std::vector<uint32_t> valence(s.vertexCount, 0);
    for (const Tri& t : s.tri)
        for (uint32_t v : t) ++valence[v];
    s.vfaces.resize(s.vertexCount);
    for (size_t v = 0; v < s.vertexCount; ++v) s.vfaces[v].reserve(valence[v]);
    for (uint32_t f = 0; f < s.faceCount; ++f) {
        const Tri& t = s.tri[f];
        s.vfaces[t[0]].push_back(f);
        if (t[1] != t[0]) s.vfaces[t[1]].push_back(f);
        if (t[2] != t[0] && t[2] != t[1]) s.vfaces[t[2]].push_back(f);
    }
}

// 3. Locks, borders, components.

static uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

static void classifyVertices(State& s) {
    s.locked.assign(s.vertexCount, 0);
    s.border.assign(s.vertexCount, 0);
    s.removed.assign(s.vertexCount, 0);
    // Faces with a repeated corner: lock their vertices (they never move).
    for (const Tri& t : s.tri)
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            for (uint32_t v : t) s.locked[v] = 1;

    std::vector<uint32_t> outs, ins, parent;
    for (uint32_t v = 0; v < s.vertexCount; ++v) {
        const auto& fs = s.vfaces[v];
        if (fs.empty() || s.locked[v]) continue;
        size_t n = fs.size();
        outs.resize(n);
        ins.resize(n);
        for (size_t k = 0; k < n; ++k) {
            int c = s.corner(fs[k], v);
            outs[k] = s.tri[fs[k]][(c + 1) % 3];
            ins[k] = s.tri[fs[k]][(c + 2) % 3];
        }
        bool bad = false, open = false;
        parent.resize(n);
        std::iota(parent.begin(), parent.end(), 0u);
        for (size_t a = 0; a < n && !bad; ++a) {
            size_t matches = 0;
            for (size_t b = 0; b < n; ++b) {
                if (b != a && outs[b] == outs[a]) bad = true;  // two faces with the same directed edge
                if (ins[b] == outs[a]) {
                    ++matches;
                    parent[findRoot(parent, uint32_t(a))] = findRoot(parent, uint32_t(b));
                }
            }
            if (matches == 0) open = true;
            bool hasOut = false;
            for (size_t b = 0; b < n; ++b) hasOut |= outs[b] == ins[a];
            if (!hasOut) open = true;
        }
        if (!bad) {
            uint32_t root = findRoot(parent, 0);
            for (size_t a = 1; a < n; ++a) bad |= findRoot(parent, uint32_t(a)) != root;  // bow-tie
        }
        if (bad) {
            s.locked[v] = 1;
            for (uint32_t f : fs)
                for (uint32_t u : s.tri[f]) s.locked[u] |= 2;  // neighbours touch the bad edge/fan
        }
        s.border[v] = open;
    }
    // Vertices flagged via a neighbour are only locked if they share a non-manifold edge; keeping
    // it simple and safe: any vertex adjacent to a non-manifold vertex is locked too.
    for (auto& l : s.locked) l = l ? 1 : 0;

    // Components over faces (union of their vertices).
    parent.resize(s.vertexCount);
    std::iota(parent.begin(), parent.end(), 0u);
    for (const Tri& t : s.tri) {
        uint32_t r0 = findRoot(parent, t[0]);
        parent[findRoot(parent, t[1])] = r0;
        parent[findRoot(parent, t[2])] = r0;
    }
    s.component.assign(s.vertexCount, kNone);
    uint32_t count = 0;
    std::vector<uint32_t> label(s.vertexCount, kNone);
    for (uint32_t v = 0; v < s.vertexCount; ++v) {
        if (s.vfaces[v].empty()) continue;
        uint32_t r = findRoot(parent, v);
        if (label[r] == kNone) label[r] = count++;
        s.component[v] = label[r];
    }
    s.componentClosed.assign(count, 1);
    s.componentRegions.assign(count, 0);
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (s.component[v] != kNone && (s.border[v] || s.locked[v])) s.componentClosed[s.component[v]] = 0;
    for (const Tri& t : s.tri) ++s.componentRegions[s.component[t[0]]];
}

// 4. Quadrics.

static void initQuadrics(State& s) {
    s.quadric.assign(s.vertexCount, Quadric{});
    s.originalNormal.assign(s.faceCount, {0, 0, 0});
    const auto& P = s.mesh.positions;
    for (uint32_t f = 0; f < s.faceCount; ++f) {
        const Tri& t = s.tri[f];
        Vec3 n = cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);
        double l = length(n);
        s.totalArea += 0.5 * l;
        if (!(l > 0)) continue;
        n = n / l;
        s.originalNormal[f] = {float(n.x), float(n.y), float(n.z)};
        double d = -dot(n, P[t[0]]);
        for (uint32_t v : t) s.quadric[v].addPlane(n, d, 0.5 * l);
        // Border edges: a plane through the edge, perpendicular to the face, weighted by the
        // squared edge length, so open borders are not eaten away.
        for (int e = 0; e < 3; ++e) {
            uint32_t a = t[e], b = t[(e + 1) % 3];
            if (!s.border[a] || !s.border[b]) continue;
            bool shared = false;
            for (uint32_t g : s.vfaces[a])
                if (g != f && s.corner(g, b) >= 0) shared = true;
            if (shared) continue;
            Vec3 en = normalize(cross(P[b] - P[a], n));
            double w = length2(P[b] - P[a]);
            s.quadric[a].addPlane(en, -dot(en, P[a]), w);
            s.quadric[b].addPlane(en, -dot(en, P[a]), w);
        }
    }
}

// 5. Regions and removed-point lists.

static void initRegions(State& s) {
    const auto& P = s.mesh.positions;
    s.faceRegion.resize(s.faceCount);
    std::iota(s.faceRegion.begin(), s.faceRegion.end(), 0u);
    s.regionNext.assign(s.faceCount, kNone);
    s.regionHead.resize(s.faceCount);
    std::iota(s.regionHead.begin(), s.regionHead.end(), 0u);
    s.regionTail = s.regionHead;
    s.regionSize.assign(s.faceCount, 1);
    s.regionStats.resize(s.faceCount);
    for (uint32_t f = 0; f < s.faceCount; ++f) {
        const Tri& t = s.tri[f];
        Vec3 n = cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);
        RegionStats& r = s.regionStats[f];
        r.area = 0.5 * length(n);
        r.normalSum = n * 0.5;
        for (int k = 0; k < 3; ++k) {
            r.bmin[k] = float(std::min({P[t[0]][k], P[t[1]][k], P[t[2]][k]}));
            r.bmax[k] = float(std::max({P[t[0]][k], P[t[1]][k], P[t[2]][k]}));
        }
    }
    s.regionCount = uint32_t(s.faceCount);
    s.pointHead.assign(s.faceCount, kNone);
    s.faceErr.assign(s.faceCount, 0.f);
    std::array<uint32_t, State::kTop> none;
    none.fill(kNone);
    s.faceTop.assign(s.faceCount, none);
    s.pointNext.assign(s.vertexCount, kNone);
    s.pointFace.assign(s.vertexCount, kNone);
    s.pointDist.assign(s.vertexCount, 0.f);
}

static void mergeStats(RegionStats& a, const RegionStats& b) {
    a.area += b.area;
    a.normalSum += b.normalSum;
    for (int k = 0; k < 3; ++k) {
        a.bmin[k] = std::min(a.bmin[k], b.bmin[k]);
        a.bmax[k] = std::max(a.bmax[k], b.bmax[k]);
    }
}

// E_region approximation (see the header comment).
static float regionShape(const State& s, const RegionStats& r) {
    if (!(r.area > 0) || !(s.totalArea > 0)) return 0.f;
    Vec3 ext{double(r.bmax[0] - r.bmin[0]), double(r.bmax[1] - r.bmin[1]), double(r.bmax[2] - r.bmin[2])};
    double h = 0.5 * length(ext);
    double flat = std::max(0.0, 1.0 - length(r.normalSum) / r.area) * h;
    double spread = std::max(0.0, h - std::sqrt(r.area / M_PI));
    return float(r.area / s.totalArea * (flat + spread));
}

// 6. Targets.

struct PlannedLevel {
    LevelTarget target;
    uint64_t triangles;  // stop when the live count is <= this
    double error;        // stop before a collapse costs more than this (model units); inf = none
};

static std::vector<PlannedLevel> planLevels(const State& s) {
    std::vector<PlannedLevel> plan;
    for (const LevelTarget& t : s.options.levels) {
        PlannedLevel p{t, 0, std::numeric_limits<double>::infinity()};
        if (t.ratio > 0) p.triangles = uint64_t(std::llround(std::min(1.0, t.ratio) * double(s.faceCount)));
        if (t.triangles > 0) p.triangles = std::max(p.triangles, t.triangles);
        if (t.maxError > 0) p.error = t.maxError * s.diagonal;
        plan.push_back(p);
    }
    std::stable_sort(plan.begin(), plan.end(), [](const PlannedLevel& a, const PlannedLevel& b) {
        if (a.triangles != b.triangles) return a.triangles > b.triangles;
        return a.error < b.error;
    });
    return plan;
}

// 7a. Candidate evaluation.

static void collectRing(State& s, uint32_t v, std::vector<RingEntry>& ring) {
    ring.clear();
    for (uint32_t f : s.vfaces[v]) {
        int c = s.corner(f, v);
        ring.push_back({s.tri[f][(c + 1) % 3], f, kNone});
        ring.push_back({s.tri[f][(c + 2) % 3], f, kNone});
    }
    std::sort(ring.begin(), ring.end(), [](const RingEntry& a, const RingEntry& b) {
        return a.w != b.w ? a.w < b.w : a.f0 < b.f0;
    });
    size_t o = 0;
    for (size_t k = 0; k < ring.size(); ++k) {
        if (o > 0 && ring[o - 1].w == ring[k].w) {
            ring[o - 1].f1 = ring[k].f0;
            continue;
        }
        ring[o++] = ring[k];
    }
    ring.resize(o);
}

static void collectNeighbours(State& s, uint32_t v, std::vector<uint32_t>& out) {
    out.clear();
    for (uint32_t f : s.vfaces[v])
        for (uint32_t u : s.tri[f])
            if (u != v) out.push_back(u);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
}

static bool isPBoundarySpoke(const State& s, const RingEntry& e) {
    return e.f1 != kNone && s.faceRegion[e.f0] != s.faceRegion[e.f1];
}

static int64_t bucketOf(const State& s, double dev) {
    double sim = s.options.similarDeviation;
    if (!(sim > 0)) return 0;
    if (!(dev > 1e-12 * s.diagonal)) return std::numeric_limits<int64_t>::min();
    return int64_t(std::floor(std::log(dev / s.diagonal) / std::log1p(sim)));
}

// Topology and geometry of (vi -> vj); on success fills dev.
static Reject checkCollapse(State& s, uint32_t vi, const RingEntry& edge, double& dev) {
    uint32_t vj = edge.w;
    if (s.locked[vj]) return Reject::Locked;
    bool borderEdge = edge.f1 == kNone;
    if (s.border[vi] && !borderEdge) return Reject::Border;
    // Link condition: the common neighbours are exactly the opposite vertices of the edge's faces.
    // (markI[w] == stampI marks the one-ring of vi; markJ dedupes the neighbours of vj.)
    size_t common = 0;
    uint32_t stampJ = ++s.stampJ;
    for (uint32_t f : s.vfaces[vj])
        for (uint32_t u : s.tri[f]) {
            if (u == vj || s.markJ[u] == stampJ) continue;
            s.markJ[u] = stampJ;
            common += s.markI[u] == s.stampI;
        }
    if (common != (borderEdge ? 1u : 2u)) return Reject::Link;
    if (s.vfaces[vi].size() <= (borderEdge ? 1u : 2u)) return Reject::Ear;
    // No duplicate faces (the link condition on vertices misses the tetrahedron): a moved face
    // (vj, x, y) must not already exist around vj.
    for (uint32_t f : s.vfaces[vi]) {
        if (f == edge.f0 || f == edge.f1) continue;
        int c = s.corner(f, vi);
        uint32_t x = s.tri[f][(c + 1) % 3], y = s.tri[f][(c + 2) % 3];
        for (uint32_t g : s.vfaces[vj])
            if (g != edge.f0 && g != edge.f1 && s.corner(g, x) >= 0 && s.corner(g, y) >= 0) return Reject::Link;
    }

    const auto& P = s.mesh.positions;
    Vec3 pi = P[vi], pj = P[vj];
    double best2 = std::numeric_limits<double>::infinity();
    float err = 0;
    for (uint32_t f : s.vfaces[vi]) {
        err = std::max(err, s.faceErr[f]);
        if (f == edge.f0 || f == edge.f1) continue;
        const Tri& t = s.tri[f];
        Vec3 q[3] = {P[t[0]], P[t[1]], P[t[2]]};
        Vec3 n0 = cross(q[1] - q[0], q[2] - q[0]);
        int c = s.corner(f, vi);
        q[c] = pj;
        Vec3 e1 = q[1] - q[0], e2 = q[2] - q[0];
        Vec3 n1 = cross(e1, e2);
        double l1 = length(n1);
        double scale = std::max({length2(e1), length2(e2), length2(q[2] - q[1])});
        if (!(l1 > 1e-12 * scale)) return Reject::Degenerate;
        double l0 = length(n0);
        if (l0 > 0 && dot(n0, n1) <= s.cosMaxNormalChange * l0 * l1) return Reject::Flip;
        const auto& on = s.originalNormal[f];
        if (n1.x * on[0] + n1.y * on[1] + n1.z * on[2] <= 0 && (on[0] != 0 || on[1] != 0 || on[2] != 0))
            return Reject::Flip;
        best2 = std::min(best2, closestOnTriangle(pi, q[0], q[1], q[2]).dist2);
    }
    dev = std::max({std::sqrt(best2), double(err), s.quadric[vi].distance(pj)});
    return Reject::None;
}

// Region plan of a valid collapse: rule 3 or merge; rule 1 check; E_region key.
static Reject planRegions(State& s, uint32_t vi, const RingEntry& edge, Candidate& c) {
    // Rule 3.
    c.rule3 = false;
    if (!s.border[vi] && isPBoundarySpoke(s, edge)) {
        uint32_t spokes = 0, vk = kNone;
        for (const RingEntry& e : s.ringI)
            if (isPBoundarySpoke(s, e)) {
                ++spokes;
                if (e.w != edge.w) vk = e.w;
            }
        if (spokes == 2 && vk != kNone) {
            const auto& P = s.mesh.positions;
            double eps = std::max(s.options.epsilonDeviationFactor * c.dev, s.options.epsilonBoxFactor * s.longestSide);
            if (distanceToSegment(P[vi], P[edge.w], P[vk]) <= eps) {
                // Each side must keep a surviving face (otherwise its region would vanish here).
                uint32_t rA = s.faceRegion[edge.f0], rB = s.faceRegion[edge.f1];
                bool keptA = false, keptB = false;
                for (uint32_t f : s.vfaces[vi]) {
                    if (f == edge.f0 || f == edge.f1) continue;
                    keptA |= s.faceRegion[f] == rA;
                    keptB |= s.faceRegion[f] == rB;
                }
                if (keptA && keptB) {
                    c.rule3 = true;
                    c.shape = std::max(regionShape(s, s.regionStats[rA]), regionShape(s, s.regionStats[rB]));
                    return Reject::None;
                }
            }
        }
    }
    // Merge every region of the fan.
    s.scratch.clear();
    for (uint32_t f : s.vfaces[vi]) s.scratch.push_back(s.faceRegion[f]);
    std::sort(s.scratch.begin(), s.scratch.end());
    s.scratch.erase(std::unique(s.scratch.begin(), s.scratch.end()), s.scratch.end());
    uint32_t comp = s.component[vi];
    uint32_t after = s.componentRegions[comp] - uint32_t(s.scratch.size() - 1);
    if (s.componentClosed[comp] && after < 2) return Reject::Rule1;
    RegionStats merged = s.regionStats[s.scratch[0]];
    for (size_t k = 1; k < s.scratch.size(); ++k) mergeStats(merged, s.regionStats[s.scratch[k]]);
    c.shape = regionShape(s, merged);
    return Reject::None;
}

static Candidate evaluateVertex(State& s, uint32_t vi) {
    Candidate best;
    if (s.removed[vi] || s.vfaces[vi].empty()) return best;
    if (s.locked[vi]) {
        best.reason = Reject::Locked;
        return best;
    }
    collectRing(s, vi, s.ringI);
    ++s.stampI;
    for (const RingEntry& e : s.ringI) s.markI[e.w] = s.stampI;
    // Order the outgoing half-edges by the quadric proxy; the first valid one is the candidate.
    struct Option {
        double q;
        uint32_t k;
    };
    Option opts[64];
    std::vector<Option> big;
    Option* o = opts;
    size_t n = s.ringI.size();
    if (n > 64) {
        big.resize(n);
        o = big.data();
    }
    for (size_t k = 0; k < n; ++k) o[k] = {s.quadric[vi].distance(s.mesh.positions[s.ringI[k].w]), uint32_t(k)};
    std::sort(o, o + n, [&](const Option& a, const Option& b) {
        return a.q != b.q ? a.q < b.q : s.ringI[a.k].w < s.ringI[b.k].w;
    });
    Reject last = Reject::Isolated;
    for (size_t k = 0; k < n; ++k) {
        RingEntry edge = s.ringI[o[k].k];
        double dev = 0;
        Reject r = checkCollapse(s, vi, edge, dev);
        if (r != Reject::None) {
            if (last == Reject::Isolated || r == Reject::Rule1) last = r;
            continue;
        }
        Candidate c;
        c.target = edge.w;
        c.dev = dev;
        r = planRegions(s, vi, edge, c);
        if (r != Reject::None) {
            last = r;
            continue;
        }
        c.reason = Reject::None;
        return c;
    }
    best.reason = last;
    return best;
}

static void pushKey(State& s, const Key& k) {
    s.heap.push_back(k);
    std::push_heap(s.heap.begin(), s.heap.end(), KeyGreater());
}

static Key popKey(State& s) {
    std::pop_heap(s.heap.begin(), s.heap.end(), KeyGreater());
    Key k = s.heap.back();
    s.heap.pop_back();
    return k;
}

// Drop stale entries once they outnumber the live ones (keeps the heap small and cache-friendly).
static void compactHeap(State& s, size_t liveVertices) {
    if (s.heap.size() < 2 * liveVertices + 4096) return;
    s.heap.erase(std::remove_if(s.heap.begin(), s.heap.end(),
                                [&](const Key& k) { return k.version != s.version[k.vertex]; }),
                 s.heap.end());
    std::make_heap(s.heap.begin(), s.heap.end(), KeyGreater());
}

static double measureReprojection(State& s, uint32_t vi, const Candidate& c, bool full);

// Evaluates v completely (including the re-projection of its removed points) and stores the
// candidate; returns false when v has no valid collapse.
static bool evaluateAndStore(State& s, uint32_t v) {
    Candidate c = evaluateVertex(s, v);
    s.lastReject[v] = c.reason;
    ++s.version[v];
    if (c.reason != Reject::None) return false;
    c.devGeom = c.dev;
    c.dev = std::max(c.dev, measureReprojection(s, v, c, false));
    c.exact = false;
    s.cand[v] = c;
    s.pushEpoch[v] = s.epoch;
    return true;
}

// Re-plans only the region part of v's stored candidate (the geometry and its target cannot have
// changed: v's fan did not change since the push, and rule 1 only gets stricter, so earlier
// outgoing edges stay rejected). Returns false when the full evaluation is needed.
static bool refreshRegions(State& s, uint32_t v) {
    Candidate c = s.cand[v];
    collectRing(s, v, s.ringI);
    const RingEntry* edge = nullptr;
    for (const RingEntry& e : s.ringI)
        if (e.w == c.target) edge = &e;
    if (!edge) return false;
    double dev = c.dev;
    c.dev = c.devGeom;
    bool wasRule3 = c.rule3;
    if (planRegions(s, v, *edge, c) != Reject::None) return false;
    if (c.rule3 || wasRule3) {
        c.dev = std::max(c.devGeom, measureReprojection(s, v, c, false));
        c.exact = false;
    } else {
        c.dev = dev;
    }
    s.cand[v] = c;
    s.pushEpoch[v] = s.epoch;
    ++s.version[v];
    return true;
}

static Key keyOf(const State& s, uint32_t v) {
    const Candidate& c = s.cand[v];
    return {bucketOf(s, c.dev), c.shape, c.dev, v, s.version[v]};
}

static void pushVertex(State& s, uint32_t v) {
    if (evaluateAndStore(s, v)) pushKey(s, keyOf(s, v));
}

// A stored candidate stays exact until the vertex's fan changes (then it is re-pushed) or a region
// of its fan changes (merge: regionEpoch) or rule 1 may start to bite on its component.
static bool candidateDirty(const State& s, uint32_t v) {
    uint32_t e = s.pushEpoch[v];
    for (uint32_t f : s.vfaces[v])
        if (s.regionEpoch[s.faceRegion[f]] > e) return true;
    uint32_t comp = s.component[v];
    return s.componentClosed[comp] && s.componentRegions[comp] < 256;
}

// 7b. Applying a collapse.

// Merge the regions `reps` (distinct) into one, union by size: every smaller region is relabelled
// into the largest (ties: a representative that survives this collapse, then the smaller id), so
// each face is relabelled O(log F) times in total. The representative may be (or become) a removed
// face; fixDeadRepresentatives() re-elects a surviving one when a level is snapshotted.
static void mergeRegionGroup(State& s, const std::vector<uint32_t>& reps) {
    uint32_t newRep = kNone;
    bool newAlive = false;
    for (uint32_t r : reps) {
        bool alive = s.faceAlive[r] && !(s.corner(r, s.collapseSource) >= 0 && s.corner(r, s.collapseTarget) >= 0);
        if (newRep == kNone || s.regionSize[r] > s.regionSize[newRep] ||
            (s.regionSize[r] == s.regionSize[newRep] && alive && !newAlive)) {
            newRep = r;
            newAlive = alive;
        }
    }
    for (uint32_t r : reps) {
        if (r == newRep) continue;
        for (uint32_t f = s.regionHead[r]; f != kNone; f = s.regionNext[f]) {
            s.out.regionUpdates.push_back({f, r, newRep});
            s.faceRegion[f] = newRep;
        }
        s.regionNext[s.regionTail[newRep]] = s.regionHead[r];
        s.regionTail[newRep] = s.regionTail[r];
        s.regionSize[newRep] += s.regionSize[r];
        mergeStats(s.regionStats[newRep], s.regionStats[r]);
        s.regionSize[r] = 0;
    }
    s.regionEpoch[newRep] = s.epoch;
    s.regionCount -= uint32_t(reps.size() - 1);
}

static void updateRegions(State& s, uint32_t vi, const Candidate& c, const std::vector<uint32_t>& fan) {
    if (c.rule3) return;  // each side keeps its own region (a removed representative stays until the snapshot)
    std::vector<uint32_t>& reps = s.repScratch;
    reps.clear();
    for (uint32_t f : fan) reps.push_back(s.faceRegion[f]);
    std::sort(reps.begin(), reps.end());
    reps.erase(std::unique(reps.begin(), reps.end()), reps.end());
    s.componentRegions[s.component[vi]] -= uint32_t(reps.size() - 1);
    s.collapseSource = vi;
    s.collapseTarget = c.target;
    mergeRegionGroup(s, reps);
}

// Every region whose representative is a removed face moves to its smallest surviving face; the
// updates are recorded with the last collapse (so a replay up to any level sees surviving reps).
static void fixDeadRepresentatives(State& s) {
    if (s.out.collapses.empty()) return;
    ++s.epoch;
    for (uint32_t r = 0; r < s.faceCount; ++r) {
        if (s.faceAlive[r] || s.regionSize[r] == 0 || s.faceRegion[r] != r) continue;
        uint32_t m = kNone;
        for (uint32_t f = s.regionHead[r]; f != kNone; f = s.regionNext[f])
            if (s.faceAlive[f] && f < m) m = f;
        if (m == kNone) continue;  // cannot happen: every region keeps a surviving face
        for (uint32_t f = s.regionHead[r]; f != kNone; f = s.regionNext[f]) {
            s.out.regionUpdates.push_back({f, r, m});
            s.faceRegion[f] = m;
        }
        s.regionHead[m] = s.regionHead[r];
        s.regionTail[m] = s.regionTail[r];
        s.regionSize[m] = s.regionSize[r];
        s.regionStats[m] = s.regionStats[r];
        s.regionSize[r] = 0;
        s.regionEpoch[m] = s.epoch;
    }
    s.out.collapses.back().regionEnd = uint32_t(s.out.regionUpdates.size());
}

static uint32_t chooseWedge(const State& s, uint32_t f, int c, uint32_t vi, uint32_t vj,
                            const std::vector<uint32_t>& removedFaces) {
    uint32_t w = s.wedge[f][c];
    int32_t mat = s.material(f);
    uint32_t sameWedge = kNone;
    for (uint32_t r : removedFaces) {
        int ci = s.corner(r, vi), cj = s.corner(r, vj);
        if (s.wedge[r][ci] != w) continue;
        if (s.material(r) == mat) return s.wedge[r][cj];  // same wedge and same material: best
        if (sameWedge == kNone) sameWedge = s.wedge[r][cj];
    }
    if (sameWedge != kNone) return sameWedge;
    for (uint32_t g : s.vfaces[vj])
        if (s.material(g) == mat) return s.wedge[g][s.corner(g, vj)];
    uint32_t g = s.vfaces[vj].front();
    return s.wedge[g][s.corner(g, vj)];
}

static void assignPoint(State& s, uint32_t v, const std::vector<uint32_t>& faces, double& maxDist) {
    const auto& P = s.mesh.positions;
    double best = std::numeric_limits<double>::infinity();
    uint32_t bestFace = faces.front();
    for (uint32_t f : faces) {
        const Tri& t = s.tri[f];
        double d2 = closestOnTriangle(P[v], P[t[0]], P[t[1]], P[t[2]]).dist2;
        if (d2 < best) best = d2, bestFace = f;
    }
    float d = float(std::sqrt(best));
    s.pointFace[v] = bestFace;
    s.pointDist[v] = d;
    s.pointNext[v] = s.pointHead[bestFace];
    s.pointHead[bestFace] = v;
    s.faceErr[bestFace] = std::max(s.faceErr[bestFace], d);
    // Keep the kTop farthest points of the face, farthest first.
    auto& top = s.faceTop[bestFace];
    uint32_t p = v;
    for (int k = 0; k < State::kTop; ++k) {
        if (top[k] == kNone) {
            top[k] = p;
            break;
        }
        if (s.pointDist[p] > s.pointDist[top[k]]) std::swap(p, top[k]);
    }
    maxDist = std::max(maxDist, double(d));
}

// The largest distance the points assigned to the fan of vi (and V_i) would have after the
// collapse, without changing anything (the exact part of the cost, computed once per pop).
static double measureReprojection(State& s, uint32_t vi, const Candidate& c, bool full) {
    const auto& P = s.mesh.positions;
    uint32_t vj = c.target;
    double worst2 = 0;
    auto dist2To = [&](uint32_t p, bool sameRegionOnly) {
        double best = std::numeric_limits<double>::infinity();
        uint32_t r = p == vi ? kNone : s.faceRegion[s.pointFace[p]];
        for (int pass = 0; pass < 2 && !std::isfinite(best); ++pass)
            for (uint32_t f : s.vfaces[vi]) {
                if (s.corner(f, vj) >= 0) continue;
                if (pass == 0 && sameRegionOnly && r != kNone && s.faceRegion[f] != r) continue;
                Tri t = s.tri[f];
                t[s.corner(f, vi)] = vj;
                best = std::min(best, closestOnTriangle(P[p], P[t[0]], P[t[1]], P[t[2]]).dist2);
            }
        return best;
    };
    worst2 = dist2To(vi, false);
    // Only the farthest few points of each face (the others are bounded by faceErr in the cost;
    // the recorded deviation is exact, see applyCollapse).
    if (full) {
        for (uint32_t f : s.vfaces[vi])
            for (uint32_t p = s.pointHead[f]; p != kNone; p = s.pointNext[p]) worst2 = std::max(worst2, dist2To(p, c.rule3));
    } else {
        for (uint32_t f : s.vfaces[vi])
            for (uint32_t p : s.faceTop[f]) {
                if (p == kNone) break;
                worst2 = std::max(worst2, dist2To(p, c.rule3));
            }
    }
    return std::sqrt(worst2);
}

// Returns the largest distance of a re-projected point.
static double applyCollapse(State& s, uint32_t vi, const Candidate& c) {
    uint32_t vj = c.target;
    std::vector<uint32_t>& fan = s.fanScratch;
    std::vector<uint32_t>& kept = s.keptScratch;
    std::vector<uint32_t>& removedFaces = s.removedScratch;
    fan = s.vfaces[vi];
    kept.clear();
    removedFaces.clear();
    for (uint32_t f : fan) (s.corner(f, vj) >= 0 ? removedFaces : kept).push_back(f);

    // Regions first (they read the pre-collapse fan).
    uint32_t begin = uint32_t(s.out.regionUpdates.size());
    updateRegions(s, vi, c, fan);
    uint32_t end = uint32_t(s.out.regionUpdates.size());

    // Corners and wedges.
    for (uint32_t f : kept) {
        int ci = s.corner(f, vi);
        if (!s.wedge.empty()) s.wedge[f][ci] = chooseWedge(s, f, ci, vi, vj, removedFaces);
        s.tri[f][ci] = vj;
    }
    // Adjacency.
    for (uint32_t r : removedFaces) {
        s.faceAlive[r] = 0;
        for (uint32_t u : s.tri[r]) {
            if (u == vi) continue;
            auto& l = s.vfaces[u];
            l.erase(std::find(l.begin(), l.end(), r));
        }
    }
    for (uint32_t f : kept) s.vfaces[vj].push_back(f);
    s.vfaces[vi].clear();
    s.vfaces[vi].shrink_to_fit();
    s.removed[vi] = 1;
    s.aliveFaces -= removedFaces.size();
    s.quadric[vj].add(s.quadric[vi]);

    // Re-project the removed points of the fan (and V_i) onto the new fan, within their region.
    std::vector<uint32_t>& points = s.pointScratch;
    points.assign(1, vi);
    for (uint32_t f : fan) {
        for (uint32_t p = s.pointHead[f]; p != kNone; p = s.pointNext[p]) points.push_back(p);
        s.pointHead[f] = kNone;
        s.faceErr[f] = 0;
        s.faceTop[f].fill(kNone);
    }
    double maxDist = 0;
    std::vector<uint32_t>& sameRegion = s.sameRegionScratch;
    for (uint32_t p : points) {
        const std::vector<uint32_t>* target = &kept;
        if (c.rule3 && p != vi) {
            uint32_t r = s.faceRegion[s.pointFace[p]];
            sameRegion.clear();
            for (uint32_t f : kept)
                if (s.faceRegion[f] == r) sameRegion.push_back(f);
            if (!sameRegion.empty()) target = &sameRegion;
        }
        assignPoint(s, p, *target, maxDist);
    }
    double dev = std::max(c.dev, maxDist);
    s.out.collapses.push_back({vi, vj, float(dev), begin, end});
    s.runningMax = std::max(s.runningMax, double(float(dev)));
    return dev;
}

// 7c. Levels.

static const char* summariseStop(const State& s) {
    size_t counts[size_t(Reject::Count)] = {};
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (!s.removed[v] && !s.vfaces[v].empty()) ++counts[size_t(s.lastReject[v])];
    // Rule 1 and locks are what the user can act on: name them when they block anything.
    if (counts[size_t(Reject::Rule1)]) return kRejectReason[size_t(Reject::Rule1)];
    size_t best = size_t(Reject::Isolated);
    for (size_t k = 1; k < size_t(Reject::Count); ++k)
        if (counts[k] > counts[best]) best = k;
    return kRejectReason[best];
}

static void computePairs(State& s, Level& level) {
    const auto& P = s.mesh.positions;
    double sum = 0, maxPair = 0;
    for (uint32_t v = 0; v < s.vertexCount; ++v) {
        if (!s.removed[v]) continue;
        uint32_t f = s.pointFace[v];
        const Tri& t = s.tri[f];
        Closest cp = closestOnTriangle(P[v], P[t[0]], P[t[1]], P[t[2]]);
        SimplificationPair pair;
        pair.vertex = v;
        pair.face = f;
        pair.coarse = t;
        for (int k = 0; k < 3; ++k) pair.bary[k] = float(cp.bary[k]);
        // Edge form when P lies on an edge of the face that is a p-boundary at this level.
        for (int k = 0; k < 3; ++k) {
            if (cp.bary[k] != 0) continue;
            uint32_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
            bool pb = false;
            for (uint32_t g : s.vfaces[a])
                if (g != f && s.corner(g, b) >= 0 && s.faceRegion[g] != s.faceRegion[f]) pb = true;
            if (!pb) continue;
            pair.coarse = {a, b, b};
            pair.bary = {float(cp.bary[(k + 1) % 3]), float(cp.bary[(k + 2) % 3]), 0.f};
            break;
        }
        float sumB = pair.bary[0] + pair.bary[1] + pair.bary[2];
        for (float& b : pair.bary) b /= sumB;
        Vec3 q = P[pair.coarse[0]] * pair.bary[0] + P[pair.coarse[1]] * pair.bary[1] + P[pair.coarse[2]] * pair.bary[2];
        pair.deviation = float(length(P[v] - q));
        sum += pair.deviation;
        maxPair = std::max(maxPair, double(pair.deviation));
        level.pairs.push_back(pair);
    }
    level.meanDeviation = level.pairs.empty() ? 0 : sum / double(level.pairs.size());
    s.levelMax = std::max({s.levelMax, s.runningMax, maxPair});
    level.maxDeviation = s.levelMax;
}

static void snapshotLevel(State& s, const PlannedLevel& plan, const std::string& stopReason, double seconds) {
    fixDeadRepresentatives(s);
    Level level;
    level.targetRatio = plan.target.ratio;
    level.targetTriangles = plan.triangles;
    level.targetError = std::isfinite(plan.error) ? plan.error : 0;
    level.stopReason = stopReason;
    level.faces.reserve(s.aliveFaces);
    level.triangles.reserve(s.aliveFaces);
    for (uint32_t f = 0; f < s.faceCount; ++f) {
        if (!s.faceAlive[f]) continue;
        level.faces.push_back(f);
        level.triangles.push_back(s.tri[f]);
        if (!s.wedge.empty()) level.cornerWedges.push_back(s.wedge[f]);
    }
    level.faceRegion = s.faceRegion;
    level.regionCount = s.regionCount;
    level.collapseCount = uint32_t(s.out.collapses.size());
    computePairs(s, level);
    level.seconds = seconds;
    s.out.levels.push_back(std::move(level));
}

}  // namespace

SimplifyResult simplify(const TriMesh& mesh, const SimplifyOptions& options) {
    using Clock = std::chrono::steady_clock;
    auto started = Clock::now();
    validateInput(mesh);
    State s(mesh, options);
    Box3 box = bounds(mesh);
    s.diagonal = box.diagonal();
    s.longestSide = box.longestSide();
    s.cosMaxNormalChange = std::cos(std::clamp(options.maxNormalChangeDeg, 0.0, 180.0) * M_PI / 180.0);

    buildAdjacency(s);
    s.markI.assign(s.vertexCount, 0);
    s.markJ.assign(s.vertexCount, 0);
    classifyVertices(s);
    initQuadrics(s);
    initRegions(s);
    std::vector<PlannedLevel> plan = planLevels(s);

    // Every vertex gets its best collapse.
    s.version.assign(s.vertexCount, 0);
    s.cand.assign(s.vertexCount, Candidate{});
    s.pushEpoch.assign(s.vertexCount, 0);
    s.regionEpoch.assign(s.faceCount, 0);
    s.lastReject.assign(s.vertexCount, Reject::Isolated);
    for (uint32_t v = 0; v < s.vertexCount; ++v) pushVertex(s, v);

    uint64_t finalTarget = plan.empty() ? s.faceCount : plan.back().triangles;
    double expected = std::max(1.0, double(s.faceCount - std::min<uint64_t>(finalTarget, s.faceCount)) / 2.0);
    size_t collapses = 0;
    std::vector<uint32_t> ring;
    auto levelStart = Clock::now();
    for (const PlannedLevel& level : plan) {
        std::string stop = kRejectReason[0];
        while (s.aliveFaces > level.triangles) {
            if (s.heap.empty()) {
                stop = summariseStop(s);
                break;
            }
            Key top = popKey(s);
            uint32_t vi = top.vertex;
            if (top.version != s.version[vi]) continue;
            // Re-evaluate only when region merges since the push may have changed rule 1, rule 3
            // or the E_region key.
            if (candidateDirty(s, vi)) {
                if (!refreshRegions(s, vi) && !evaluateAndStore(s, vi)) continue;
                Key fresh = keyOf(s, vi);
                // Still the best of what is left: apply now (popping it again would re-evaluate
                // it to the same key). Otherwise re-queue it with the fresh key.
                if (!s.heap.empty() && KeyGreater()(fresh, s.heap.front())) {
                    pushKey(s, fresh);
                    continue;
                }
                top = fresh;
            }
            if (!s.cand[vi].exact) {
                // The key used the farthest few points per face: measure every point now.
                Candidate& e = s.cand[vi];
                e.dev = std::max(e.dev, measureReprojection(s, vi, e, true));
                e.exact = true;
                ++s.version[vi];
                Key fresh = keyOf(s, vi);
                // Still the best of what is left: apply now (popping it again would re-evaluate
                // it to the same key). Otherwise re-queue it with the fresh key.
                if (!s.heap.empty() && KeyGreater()(fresh, s.heap.front())) {
                    pushKey(s, fresh);
                    continue;
                }
                top = fresh;
            }
            Candidate c = s.cand[vi];
            if (c.dev > level.error) {
                pushKey(s, top);
                break;  // error target reached
            }
            ++s.version[vi];
            ++s.epoch;
            applyCollapse(s, vi, c);
            // The new one-ring of v_j changed shape: re-evaluate it.
            uint32_t vj = c.target;
            pushVertex(s, vj);
            collectNeighbours(s, vj, ring);
            for (uint32_t u : ring) pushVertex(s, u);
            ++collapses;
            if (collapses % 1024 == 0) compactHeap(s, s.vertexCount - collapses);
            if (collapses % 4096 == 0 && options.progress &&
                !options.progress(std::min(1.0, double(collapses) / expected)))
                throw Impossible("simplify: cancelled");
        }
        auto now = Clock::now();
        snapshotLevel(s, level, stop, std::chrono::duration<double>(now - levelStart).count());
        levelStart = Clock::now();
    }
    if (options.progress && !options.progress(1.0)) throw Impossible("simplify: cancelled");
    (void)started;

    SimplifyResult result;
    result.multires = std::move(s.out);
    result.diagonal = s.diagonal;
    return result;
}

}  // namespace lodbake
