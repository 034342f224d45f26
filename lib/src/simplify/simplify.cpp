// Half-edge-collapse simplification with a region hierarchy.
//
// References
//   [Hoppe96]    H. Hoppe, "Progressive meshes", SIGGRAPH 1996 (collapse records, vertex hierarchy).
//   [Garland97]  M. Garland, P. Heckbert, "Surface simplification using quadric error metrics",
//                SIGGRAPH 1997 (the quadric part of the cost below).
//   [Thesis]     "Multiresolution model generation of texture-geometry for the real-time
//                rendering", ch. 2.3 (edge collapsing with region hierarchy) and ch. 3.2 (modified
//                multiresolution geometry generation: p-boundaries, the three region rules).
//   [meshopt]    A. Kapoulkine, meshoptimizer simplifier.cpp (pass-based collapsing: pick the best
//                collapse per vertex, sort, apply the non-conflicting ones under a per-pass error
//                limit; component pruning).
//
// Pipeline (simplify() at the bottom reads as this script):
//   1. validateInput        throw Impossible when there is nothing to simplify
//      renumberVertices     internal vertex ids in order of first use (memory locality); ties
//                           and outputs use the input ids (restoreInputIds at the end)
//   2. buildAdjacency       vertex -> incident live faces (FaceList: inline up to 10 faces)
//   3. classifyVertices     lock vertices on non-manifold edges / degenerate faces, mark pinch
//                           (bow-tie) vertices, find open-boundary vertices; label components and
//                           mark closed ones; per-component box diagonal
//   4. initQuadrics         per-vertex area-weighted plane quadrics (+ border planes)
//   5. initRegions          every face is its own region (rep = itself), per-region shape stats
//   6. planLevels           sort the targets finest first
//   7. passes (runPass) until the level's target; snapshotLevel at each target.
//
// Cost ("vertex deviation", model units). For a half-edge collapse v_i -> v_j:
//     cost = max( d(V_i, new fan),          thesis vertex deviation: distance from V_i to the faces
//                                           around v_i that survive, with v_i moved to v_j
//                 d(V_far, new fan),        V_far = the farthest removed point attached to v_i
//                                           (farPoint; one point per vertex, O(1) to carry)
//                 sqrt(Q_i(V_j) / W_i) )    Q_i = sum of the area-weighted planes of the original
//                                           faces around v_i (+ border planes), accumulated into
//                                           v_j on every collapse, W_i their total weight
//   O(valence) per outgoing half-edge; the quadric carries the shape of the earlier removed points,
//   no per-face point lists are re-projected during simplification. A vertex's candidate is its
//   valid outgoing half-edge first in quadric order. CollapseRecord::deviation is this cost.
//   Under an error target (LevelTarget::maxError) every collapse is additionally measured exactly
//   before it is applied (measureAttached: every removed point hanging under a vertex whose fan
//   changes, against that vertex's new fan) so no simplification pair exceeds the target; this is
//   O(attached points) per collapse and only runs for error-target levels.
//
// Passes (as meshoptimizer). Every pass
//   a. (re-)evaluates the vertices whose candidate may have changed: vertices whose fan changed in
//      the last pass, vertices whose target's fan changed, and rejected vertices next to one;
//      every other vertex keeps its cached candidate. Evaluation only reads the state, so it runs
//      on options.threads threads over fixed vertex chunks (per-thread scratch; the candidate
//      list is concatenated in chunk order): the result does not depend on the thread count.
//      A vertex whose cost is bounded from below (its smallest quadric term) by more than
//      kDeferFactor x the previous pass's limit is deferred, not evaluated: it cannot be under this
//      pass's limit unless the limit jumps, and then it is evaluated before the limit is taken
//      (1.1M-triangle bunny to 1%: 2.16M -> 1.52M evaluations);
//   b. keeps the valid candidates whose cost is within the level's error target, and computes the
//      pass error limit = 1.1 x the cost of the (remaining collapses / 3)-th cheapest candidate
//      (nth_element), so each pass takes about a third of the remaining reduction in cost order;
//   c. prunes closed components (see below) when the limit exceeds their size;
//   d. sorts the candidates under the limit by (deviation bucket, E_region key, deviation, vertex)
//      and walks them: a candidate is skipped when v_i or v_j already took part in a collapse of
//      this pass (each vertex moves at most once per pass); when the fan of v_i or of v_j changed
//      in this pass it is checked and costed again (and skipped when now invalid or above the
//      limit); its region plan is re-done unless nothing it reads changed since the candidate was
//      evaluated (no fan change at v_i or v_j, no relabelled face around v_i, an open component
//      so rule 1 is off, no normal-cone limit, no error target): then it is applied as cached,
//      which gives the same result as re-doing it. The walk stops as soon
//      as the live face count reaches the target (each collapse removes 1 or 2 faces, so the level
//      lands on the target or one below it).
//   A level that has no valid candidate left stops with the most frequent rejection reason; one
//   whose candidates all exceed its error target stops with "target".
//
// Validity (see kRejectReason): v_i not locked (nor a pinch whose fans were joined), v_j not locked; a border vertex
// only moves along a border edge; the link condition (one exception: a border collapse may close a three-vertex hole
// (v_i, v_j, b), the border flags of the ring are then refreshed) and no duplicate faces; no face
// of the new fan degenerates, turns by more than maxNormalChangeDeg, or faces away from its own
// original normal; a vertex whose whole fan would vanish (an "ear") is kept; region rule 1.
// Manifoldness ignores orientation: two faces that share an edge in the same direction
// (inconsistently wound neighbours, common in CAD exports) form a manifold edge; every geometric
// test compares a face with its own normal.
// Locked vertices: those on an edge with 3+ faces or that touch a degenerate face; they never
// move and nothing collapses into them. Pinch vertices: manifold edges, but faces forming several
// fans (a bow-tie; T-junction cracks welded by position make many). A pinch moves with all its fans
// while they are still apart; the regions of each fan merge on their own (merging across fans that
// only touch at a point would break region edge-connectivity), rule 3 does not apply, the fan of
// the edge must not vanish, and it may not close a three-vertex "hole" (on a crack that would join
// two sheets that share no edge). Its manifold neighbours may collapse into it: the link condition
// over all of its fans keeps the fans apart. The ring of every border collapse is re-classified;
// locks and pinches are sticky (a pinch whose fans were joined by later collapses still joins
// faces that are only vertex-connected in the original mesh, so it stays put). A pinch counts as
// open for rule 1.
//
// Regions (DESIGN.md). faceRegion[f] = representative face of f's region; region face lists are
// intrusive linked lists merged by union by size (the largest region keeps its label, even when its
// representative face has been removed), so relabelling is O(F log F) in total. A removed
// representative is replaced by the smallest surviving face of its region only when a level is
// snapshotted (fixDeadRepresentatives; those updates are recorded with the level's last collapse),
// so every level's representatives are surviving faces of their regions (except in pruned
// components, below).
//   - A spoke (v_i, w) is a p-boundary spoke when its two faces lie in different regions.
//   - Rule 3: v_i interior with exactly two p-boundary spokes (v_i, v_j) and (v_i, v_k), the
//     collapse goes along one of them (to v_j) and d(V_i, segment V_j V_k) <= eps with
//     eps = max(epsilonDeviationFactor * cost, epsilonBoxFactor * longest box side): the new edge
//     (v_j, v_k) stays a p-boundary, so the two sides keep their regions (nothing merges).
//   - Otherwise every region touching the fan of v_i merges into one (the collapse crosses or
//     ends the p-boundaries through v_i).
//   - Rule 1: on a closed component (no live border, pinch or locked vertex; a component whose
//     holes were closed becomes closed) a merge may not leave fewer than two regions. Collapses
//     inside one region merge nothing and stay allowed (a component closed after its regions had
//     merged into one keeps simplifying). When rule 1 (or the normal cone) forbids the merge and
//     the rule-3 geometry applies, the boundary is kept instead, the cost raised to its
//     displacement.
//   - Representative of a merge: the rep of the largest merged region (ties: a rep that survives
//     the collapse, then the smaller id). Rule 3 collapses change no label.
//   - Rule 2 is a secondary sort key: deviations are quantised into buckets of relative width
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
// Component pruning. A closed component (no open border, no locked vertex) cannot go below a
// tetrahedron with two regions, so assemblies of many small closed parts stall far above a low
// target. When a level is not reached yet and the pass error limit (or, when no collapse is left,
// the level's error target, unbounded by default) exceeds half a closed component's box diagonal,
// the whole component is removed, smallest diagonal first, only while the live face count stays at
// or above the target. Its faces leave the level (they keep their regions: no region update, so
// their representatives are not surviving faces); each of its surviving vertices gets a
// CollapseRecord with kept == removed (the vertex itself) and deviation = half the component's
// diagonal, which also enters the level's maxDeviation. Pruned vertices, and the removed vertices
// whose collapse chain ends in a pruned vertex, get no simplification pair. Open or non-manifold
// components are pruned only when simplification is stuck and their size is within the error
// already accepted (the running max deviation); the last faces are never pruned.
//
// Simplification pairs (computed only when a level is snapshotted; the projections run in parallel
// chunks, concatenated in input vertex order). Every removed vertex keeps the
// vertex it collapsed into; the chain is followed (memoised per snapshot) to a surviving vertex s,
// and V_i is projected onto the faces around s, preferring the faces of V_i's region (the region of
// a face kept by its collapse); when P lies on an edge of the chosen face that is a p-boundary at
// this level (e.g. a rule-3 boundary), the pair is written in edge form (coarse[2] == coarse[1]).
// Level::maxDeviation = max(previous level, running max of collapse costs, max pair deviation), so
// it never decreases; meanDeviation = mean pair deviation.
//
// Corner wedges: a surviving face keeps its own wedges; a corner moving from v_i to v_j takes the
// v_j wedge of a removed face (one containing edge v_i v_j) whose v_i corner used the same wedge,
// else a v_j wedge of the same material, else any v_j wedge. Seams and materials never block.

#include "lodbake/simplify/simplify.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <exception>
#include <functional>
#include <limits>
#include <numeric>
#include <string>
#include <thread>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"

namespace lodbake {
namespace {

constexpr uint32_t kNone = 0xffffffffu;

// ---------------------------------------------------------------------------------------------
// Rule table: why a vertex could not collapse. The stop reason of a level that cannot reach its
// target is the most frequent reason among the remaining vertices.
enum class Reject : uint8_t { None, Locked, Border, Link, Flip, Degenerate, Ear, Rule1, Cone, Isolated, Count };

constexpr const char* kRejectReason[] = {
    "target",                           // None
    "locked: non-manifold edge or pinch vertex",  // Locked: see the header comment
    "border: no collapse along the open boundary",  // Border
    "topology: link condition",         // Link
    "no valid collapse: face flip",     // Flip
    "no valid collapse: degenerate face",  // Degenerate
    "no valid collapse: corner",        // Ear: the whole fan would vanish
    "rule1: last p-boundary",           // Rule1
    "region: normal cone",              // Cone: the merged region would turn too far to be a chart
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

// Closest point on triangle abc to p, with its squared distance.
Closest closestWithDistance(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
    std::array<double, 3> u = closestOnTriangle(p, a, b, c);
    return Closest{{u[0], u[1], u[2]}, length2(p - (a * u[0] + b * u[1] + c * u[2]))};
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

struct Candidate {
    Reject reason = Reject::Isolated;
    uint32_t target = kNone;
    double dev = 0;
    float farDist = 0;  // distance of v_i's farthest attached point to the new fan
    float shape = 0;
    bool rule3 = false;
    uint32_t evalPass = 0;  // pass whose start evaluated this candidate
};

// A sortable candidate of one pass.
struct PassEntry {
    int64_t bucket;
    float shape;
    double dev;
    uint32_t vertex;
    uint32_t key;  // the vertex's input id: ties go to the smaller input id
    bool operator<(const PassEntry& b) const {
        if (bucket != b.bucket) return bucket < b.bucket;
        if (shape != b.shape) return shape < b.shape;
        if (dev != b.dev) return dev < b.dev;
        return key < b.key;
    }
};

// The live faces around one vertex: up to kInline stored in place (no pointer chase, no heap
// block for the common valences), more on the heap. Erasing keeps the order.
class FaceList {
public:
    FaceList() {}
    FaceList(const FaceList&) = delete;
    FaceList& operator=(const FaceList&) = delete;
    FaceList(FaceList&& o) noexcept : n_(o.n_), cap_(o.cap_) {
        if (o.cap_ > kInline) {
            heap_ = o.heap_;
            o.cap_ = kInline;
            o.n_ = 0;
        } else {
            std::memcpy(in_, o.in_, sizeof in_);
        }
    }
    FaceList& operator=(FaceList&&) = delete;
    ~FaceList() { release(); }

    const uint32_t* begin() const { return data(); }
    const uint32_t* end() const { return data() + n_; }
    size_t size() const { return n_; }
    bool empty() const { return n_ == 0; }
    uint32_t operator[](size_t k) const { return data()[k]; }
    uint32_t front() const { return data()[0]; }
    void reserve(uint32_t n) {
        if (n > cap_) grow(n);
    }
    void push_back(uint32_t f) {
        if (n_ == cap_) grow(cap_ * 2);
        data()[n_++] = f;
    }
    void eraseValue(uint32_t f) {
        uint32_t* d = data();
        uint32_t* it = std::find(d, d + n_, f);
        if (it == d + n_) return;
        std::move(it + 1, d + n_, it);
        --n_;
    }
    void release() {
        if (cap_ > kInline) delete[] heap_;
        cap_ = kInline;
        n_ = 0;
    }

private:
    static constexpr uint32_t kInline = 10;
    uint32_t* data() { return cap_ > kInline ? heap_ : in_; }
    const uint32_t* data() const { return cap_ > kInline ? heap_ : in_; }
    void grow(uint32_t cap) {
        uint32_t* p = new uint32_t[cap];
        std::memcpy(p, data(), n_ * sizeof(uint32_t));
        if (cap_ > kInline) delete[] heap_;
        heap_ = p;
        cap_ = cap;
    }
    uint32_t n_ = 0, cap_ = kInline;
    union {
        uint32_t in_[kInline];
        uint32_t* heap_;
    };
};

// Current corners of every face with its original unit normal (zero when degenerate) in the same
// record: the validity checks read both, one cache line instead of two.
struct FaceRec {
    Tri t;
    std::array<float, 3> n;
};
struct FaceArray {
    std::vector<FaceRec> rec;
    Tri& operator[](size_t f) { return rec[f].t; }
    const Tri& operator[](size_t f) const { return rec[f].t; }
};

// One neighbour w of a vertex v: the faces around v containing edge (v, w).
struct RingEntry {
    uint32_t w;
    uint32_t f0, f1;  // f1 == kNone when the edge has one face around v
};

// An outgoing half-edge of the vertex being evaluated: its quadric term and ring slot.
struct Option {
    double q;
    uint32_t k;
};

// Per-thread scratch of candidate evaluation.
struct Scratch {
    std::vector<RingEntry> ring;           // ring of the vertex being evaluated
    std::vector<Option> options;           // one per ring entry (ringOptions)
    std::vector<uint32_t> markI, markJ;    // per-vertex stamps: one-ring of vi, neighbours of vj
    uint32_t stampI = 0, stampJ = 0;
    std::vector<uint32_t> regions;
    std::vector<uint32_t> fan;  // fan id of each face of vfaces[vi] (pinch vertices only)
    std::vector<uint32_t> faceMark;  // per-face stamps of the pair search (sized on first use)
    uint32_t faceStamp = 0;
};

struct State {
    const TriMesh& mesh;   // positions and triangles, vertices renumbered (see renumberVertices)
    const TriMesh& input;  // the caller's mesh: corner wedges and materials
    const SimplifyOptions& options;
    std::vector<uint32_t> oldId;  // input id of each internal vertex id
    std::vector<uint32_t> newId;  // internal id of each input vertex
    size_t vertexCount = 0, faceCount = 0;

    FaceArray tri;                    // current corners (+ original normals)
    std::vector<Tri> wedge;           // current corner wedges (empty when the mesh has none)
    std::vector<uint8_t> faceAlive;
    std::vector<FaceList> vfaces;  // live faces around each vertex
    std::vector<uint8_t> locked, border, removed;
    std::vector<uint8_t> pinch;  // bow-tie vertices: several manifold fans meet at one point
    std::vector<uint32_t> component;  // per vertex
    std::vector<uint8_t> componentClosed, componentPruned;  // componentClosed: as classified (sizes)
    std::vector<uint32_t> componentOpen;  // live border or locked vertices per component (0 = closed)
    std::vector<uint32_t> componentRegions;
    std::vector<double> componentSize;     // half the box diagonal
    std::vector<uint32_t> componentOrder;  // components, smallest size first
    std::vector<uint32_t> componentFaces;  // live faces per component
    std::vector<uint32_t> componentVertexStart, componentVertices;  // CSR: vertices per component
    std::vector<Quadric> quadric;

    // Regions.
    std::vector<uint32_t> faceRelabelPass;  // pass of each face's last relabel
    std::vector<uint32_t> faceRegion, regionNext, regionHead, regionTail, regionSize;
    std::vector<RegionStats> regionStats;
    uint32_t regionCount = 0;
    double totalArea = 0;

    // Collapse hierarchy: the vertex each removed vertex collapsed into (kNone: pruned) and a face
    // its collapse kept (its region is the region V_i belongs to).
    std::vector<uint32_t> collapsedInto, keptFace;
    // The farthest removed point attached to each surviving vertex (kNone: none) and its distance
    // when last measured: the cost re-projects it, a cheap stand-in for the old exact point lists.
    std::vector<uint32_t> farPoint;
    std::vector<float> farDist;
    // Removed points attached to each surviving vertex (intrusive lists spliced on collapse); only
    // read under an error target (measureAttached).
    std::vector<uint32_t> attachHead, attachTail, attachNext;

    // Candidates.
    std::vector<Candidate> cand;
    // Deferred vertices: not evaluated while a lower bound of their cost (costBound) is above the
    // pass's deferral bound; their cand is empty (see runPass).
    std::vector<uint8_t> deferred;
    std::vector<double> costBound;
    double lastLimit = std::numeric_limits<double>::infinity();  // the previous pass's error limit
    std::vector<uint32_t> dirtyPass, touchedPass;  // pass number of the last mark
    uint32_t pass = 0;
    std::vector<PassEntry> entries;
    std::vector<std::vector<PassEntry>> chunkEntries;  // per evaluation chunk

    size_t aliveFaces = 0;
    double diagonal = 0, longestSide = 0, cosMaxNormalChange = 0, minRegionCoherence = 0;
    double runningMax = 0;  // running max of recorded collapse deviations
    double levelMax = 0;    // maxDeviation of the previous level

    Multires out;

    // Scratch.
    std::vector<RingEntry> classRing;
    std::vector<uint32_t> classCount, classParent;
    std::vector<uint32_t> repScratch, fanScratch, keptScratch, removedScratch;
    uint32_t collapseSource = kNone, collapseTarget = kNone;
    std::vector<Scratch> work;  // one per evaluation thread; work[0] also serves the collapse walk

    State(const TriMesh& m, const TriMesh& in, const SimplifyOptions& o) : mesh(m), input(in), options(o) {}

    // Counted in componentOpen: a live vertex on an open border, a pinch or a locked vertex.
    bool isOpen(uint32_t v) const { return border[v] || locked[v] || pinch[v]; }
    int corner(uint32_t f, uint32_t v) const {
        const Tri& t = tri[f];
        return t[0] == v ? 0 : (t[1] == v ? 1 : (t[2] == v ? 2 : -1));
    }
    int32_t material(uint32_t f) const {
        return f < input.triangleMaterial.size() ? input.triangleMaterial[f] : -1;
    }
};

// Calls fn(begin, end, thread) over [0, count) in fixed chunks on up to `threads` threads (the
// thread index selects the caller's scratch). Results must not depend on which thread ran a chunk.
constexpr size_t kChunk = 4096;
constexpr double kDeferFactor = 1.5;  // deferral bound of a pass: this times the previous pass's limit
static void parallelChunks(size_t count, size_t threads, const std::function<void(size_t, size_t, size_t)>& fn) {
    size_t chunks = (count + kChunk - 1) / kChunk;
    size_t n = std::min(threads, chunks);
    if (n <= 1) {
        if (count) fn(0, count, 0);
        return;
    }
    std::atomic<size_t> next{0};
    std::exception_ptr error;
    std::atomic<bool> failed{false};
    auto worker = [&](size_t t) {
        for (;;) {
            size_t c = next.fetch_add(1);
            if (c >= chunks || failed.load()) return;
            try {
                fn(c * kChunk, std::min(count, (c + 1) * kChunk), t);
            } catch (...) {
                if (!failed.exchange(true)) error = std::current_exception();
                return;
            }
        }
    };
    std::vector<std::thread> pool;
    for (size_t t = 1; t < n; ++t) pool.emplace_back(worker, t);
    worker(0);
    for (auto& th : pool) th.join();
    if (error) std::rethrow_exception(error);
}

// ---------------------------------------------------------------------------------------------
// 1. Input.

static void validateInput(const TriMesh& mesh) {
    if (mesh.triangles.empty()) throw Impossible("simplify: the mesh has no triangles");
    for (const Tri& t : mesh.triangles)
        for (uint32_t v : t)
            if (v >= mesh.positions.size()) throw InvalidInput("simplify: triangle index out of range");
}

// Vertex renumbering. Inputs often list vertices far from the faces that use them (subdivided or
// re-indexed meshes: the three corners of a face hundreds of thousands of ids apart), and every
// per-vertex array is then read at random. Internally, vertices are numbered in order of first
// use by the faces (unused ones last), which keeps each neighbourhood's data close in memory.
// Every tie-break compares input ids (oldId) and every output is mapped back (restoreInputIds),
// so the result is the same as without renumbering.
static TriMesh renumberVertices(const TriMesh& mesh, std::vector<uint32_t>& oldId, std::vector<uint32_t>& newId) {
    size_t n = mesh.positions.size();
    newId.assign(n, kNone);
    oldId.clear();
    oldId.reserve(n);
    for (const Tri& t : mesh.triangles)
        for (uint32_t v : t)
            if (newId[v] == kNone) {
                newId[v] = uint32_t(oldId.size());
                oldId.push_back(v);
            }
    for (uint32_t v = 0; v < n; ++v)
        if (newId[v] == kNone) {
            newId[v] = uint32_t(oldId.size());
            oldId.push_back(v);
        }
    TriMesh local;
    local.positions.resize(n);
    for (uint32_t v = 0; v < n; ++v) local.positions[v] = mesh.positions[oldId[v]];
    local.triangles.resize(mesh.triangles.size());
    for (size_t f = 0; f < mesh.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) local.triangles[f][k] = newId[mesh.triangles[f][k]];
    return local;
}

// Maps every vertex id of the output back to the input's ids.
static void restoreInputIds(State& s) {
    const std::vector<uint32_t>& id = s.oldId;
    for (CollapseRecord& c : s.out.collapses) {
        c.removed = id[c.removed];
        c.kept = id[c.kept];
    }
    for (Level& l : s.out.levels) {
        for (Tri& t : l.triangles)
            for (uint32_t& v : t) v = id[v];
        for (SimplificationPair& p : l.pairs) {
            p.vertex = id[p.vertex];
            for (uint32_t& v : p.coarse) v = id[v];
        }
    }
}

// 2. Adjacency.

static void buildAdjacency(State& s) {
    const TriMesh& m = s.mesh;
    s.vertexCount = m.positions.size();
    s.faceCount = m.triangles.size();
    s.tri.rec.resize(m.triangles.size());
    for (size_t f = 0; f < m.triangles.size(); ++f) s.tri.rec[f] = {m.triangles[f], {0, 0, 0}};
    if (s.input.cornerWedges.size() == m.triangles.size()) s.wedge = s.input.cornerWedges;
    s.faceAlive.assign(s.faceCount, 1);
    s.aliveFaces = s.faceCount;
    std::vector<uint32_t> valence(s.vertexCount, 0);
    for (const Tri& t : s.mesh.triangles)
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

enum class FanKind { Manifold, Pinch, NonManifold };

// A vertex is manifold when every edge around it has one or two faces and its faces form one fan
// (connected through shared edges); a pinch (bow-tie) when its edges are manifold but its faces
// form several fans. Orientation is not required: two faces sharing an edge in the same direction
// (inconsistently wound neighbours) are a manifold edge like any other; every geometric test
// compares a face with its own normal. `open`: some edge around v has one face.
static FanKind classifyFan(State& s, uint32_t v, bool& open) {
    const auto& fs = s.vfaces[v];
    size_t n = fs.size();
    std::vector<RingEntry>& ring = s.classRing;
    std::vector<uint32_t>& faceCount = s.classCount;
    std::vector<uint32_t>& parent = s.classParent;
    ring.clear();
    faceCount.clear();
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0u);
    bool bad = false;
    open = false;
    for (size_t k = 0; k < n; ++k) {
        const Tri& t = s.tri[fs[k]];
        int c = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        for (int d = 1; d <= 2; ++d) {
            uint32_t w = t[(c + d) % 3];
            size_t e = 0;
            while (e < ring.size() && ring[e].w != w) ++e;
            if (e == ring.size()) {
                ring.push_back({w, uint32_t(k), kNone});
                faceCount.push_back(1);
            } else {
                if (++faceCount[e] > 2) bad = true;  // an edge with 3+ faces
                parent[findRoot(parent, uint32_t(k))] = findRoot(parent, ring[e].f0);
            }
        }
    }
    for (uint32_t c : faceCount) open |= c == 1;
    if (bad) return FanKind::NonManifold;
    uint32_t root = findRoot(parent, 0);
    for (size_t a = 1; a < n; ++a)
        if (findRoot(parent, uint32_t(a)) != root) return FanKind::Pinch;
    return FanKind::Manifold;
}

static void classifyVertices(State& s) {
    s.locked.assign(s.vertexCount, 0);
    s.pinch.assign(s.vertexCount, 0);
    s.border.assign(s.vertexCount, 0);
    s.removed.assign(s.vertexCount, 0);
    // Faces with a repeated corner: lock their vertices (they never move).
    for (const Tri& t : s.mesh.triangles)
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
            for (uint32_t v : t) s.locked[v] = 1;

    for (uint32_t v = 0; v < s.vertexCount; ++v) {
        if (s.vfaces[v].empty() || s.locked[v]) continue;
        bool open = false;
        FanKind k = classifyFan(s, v, open);
        s.locked[v] = k == FanKind::NonManifold;
        s.pinch[v] = k == FanKind::Pinch;
        s.border[v] = open;
    }
    // Only the non-manifold vertices themselves are locked (every vertex of a non-manifold edge has
    // a non-manifold fan): a manifold neighbour may still collapse, never into a locked vertex, and
    // the link condition keeps the non-manifold edges intact.

    // Components over faces (union of their vertices).
    std::vector<uint32_t> parent(s.vertexCount);
    std::iota(parent.begin(), parent.end(), 0u);
    for (const Tri& t : s.mesh.triangles) {
        uint32_t r0 = findRoot(parent, t[0]);
        parent[findRoot(parent, t[1])] = r0;
        parent[findRoot(parent, t[2])] = r0;
    }
    s.component.assign(s.vertexCount, kNone);
    uint32_t count = 0;
    std::vector<uint32_t> label(s.vertexCount, kNone);
    for (uint32_t u = 0; u < s.vertexCount; ++u) {  // in input order: labels as without renumbering
        uint32_t v = s.newId[u];
        if (s.vfaces[v].empty()) continue;
        uint32_t r = findRoot(parent, v);
        if (label[r] == kNone) label[r] = count++;
        s.component[v] = label[r];
    }
    s.componentClosed.assign(count, 1);
    s.componentRegions.assign(count, 0);
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (s.component[v] != kNone && s.isOpen(v)) s.componentClosed[s.component[v]] = 0;
    s.componentOpen.assign(count, 0);
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (s.component[v] != kNone && s.isOpen(v)) ++s.componentOpen[s.component[v]];
    for (const Tri& t : s.mesh.triangles) ++s.componentRegions[s.component[t[0]]];
}

// 4. Quadrics.

static void initQuadrics(State& s) {
    s.quadric.assign(s.vertexCount, Quadric{});
    const auto& P = s.mesh.positions;
    for (uint32_t f = 0; f < s.faceCount; ++f) {
        const Tri& t = s.tri[f];
        Vec3 n = cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);
        double l = length(n);
        s.totalArea += 0.5 * l;
        if (!(l > 0)) continue;
        n = n / l;
        s.tri.rec[f].n = {float(n.x), float(n.y), float(n.z)};
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

// Component sizes (closed components only are ever pruned), smallest first.
static void measureComponents(State& s) {
    size_t n = s.componentClosed.size();
    std::vector<Box3> box(n);
    const auto& P = s.mesh.positions;
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (s.component[v] != kNone) box[s.component[v]].extend(P[v]);
    s.componentSize.assign(n, 0);
    s.componentPruned.assign(n, 0);
    s.componentFaces.assign(n, 0);
    for (const Tri& t : s.mesh.triangles) ++s.componentFaces[s.component[t[0]]];
    s.componentVertexStart.assign(n + 1, 0);
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (s.component[v] != kNone) ++s.componentVertexStart[s.component[v] + 1];
    for (size_t c = 0; c < n; ++c) s.componentVertexStart[c + 1] += s.componentVertexStart[c];
    s.componentVertices.resize(s.componentVertexStart[n]);
    {
        std::vector<uint32_t> at(s.componentVertexStart.begin(), s.componentVertexStart.end() - 1);
        for (uint32_t u = 0; u < s.vertexCount; ++u) {  // in input order (pruning records)
            uint32_t v = s.newId[u];
            if (s.component[v] != kNone) s.componentVertices[at[s.component[v]]++] = v;
        }
    }
    for (size_t c = 0; c < n; ++c) {
        s.componentSize[c] = 0.5 * box[c].diagonal();
        s.componentOrder.push_back(uint32_t(c));
    }
    std::stable_sort(s.componentOrder.begin(), s.componentOrder.end(),
                     [&](uint32_t a, uint32_t b) { return s.componentSize[a] < s.componentSize[b]; });
}

// 5. Regions.

static void initRegions(State& s) {
    const auto& P = s.mesh.positions;
    s.faceRelabelPass.assign(s.faceCount, 0);
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
    s.collapsedInto.assign(s.vertexCount, kNone);
    s.keptFace.assign(s.vertexCount, kNone);
    s.farPoint.assign(s.vertexCount, kNone);
    s.farDist.assign(s.vertexCount, 0.f);
    s.attachHead.assign(s.vertexCount, kNone);
    s.attachTail.assign(s.vertexCount, kNone);
    s.attachNext.assign(s.vertexCount, kNone);
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

static void collectRing(const State& s, uint32_t v, std::vector<RingEntry>& ring) {
    // Each neighbour w shares an edge (v, w) with one or two faces around a manifold vertex,
    // whatever their orientations (a non-manifold fan is locked and never evaluated; a third face
    // of an edge is ignored here). Entries are in order of first appearance.
    ring.clear();
    for (uint32_t f : s.vfaces[v]) {
        const Tri& t = s.tri[f];
        int c = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        for (int k = 1; k <= 2; ++k) {
            uint32_t w = t[(c + k) % 3];
            bool found = false;
            for (RingEntry& e : ring)
                if (e.w == w) {
                    if (e.f1 == kNone) e.f1 = f;
                    found = true;
                    break;
                }
            if (!found) ring.push_back({w, f, kNone});
        }
    }
    for (RingEntry& e : ring)
        if (e.f1 != kNone && e.f1 < e.f0) std::swap(e.f0, e.f1);
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

// Fans of v: fan[k] = fan id of the k-th face of vfaces[v], faces joined through shared spokes;
// ids are dense from 0 in order of first face. Returns the number of fans. ring: the ring of v.
static uint32_t labelFans(const State& s, uint32_t v, const std::vector<RingEntry>& ring, std::vector<uint32_t>& fan) {
    const auto& fs = s.vfaces[v];
    const size_t n = fs.size();
    auto slot = [&](uint32_t f) { return uint32_t(std::find(fs.begin(), fs.end(), f) - fs.begin()); };
    fan.resize(n);
    std::iota(fan.begin(), fan.end(), 0u);
    auto root = [&](uint32_t x) {
        while (fan[x] != x) x = fan[x] = fan[fan[x]];
        return x;
    };
    for (const RingEntry& e : ring)
        if (e.f1 != kNone) fan[root(slot(e.f0))] = root(slot(e.f1));
    std::vector<uint32_t> roots(n), id(n, kNone);
    for (size_t k = 0; k < n; ++k) roots[k] = root(uint32_t(k));
    uint32_t count = 0;
    for (size_t k = 0; k < n; ++k) {
        if (id[roots[k]] == kNone) id[roots[k]] = count++;
        fan[k] = id[roots[k]];
    }
    return count;
}

// Region groups that a collapse of the pinch vi merges: the regions of each fan separately (the fans
// only meet at vi, so merging across them would join regions that share no edge); fans that share
// a region form one group (groups of one region merge nothing). fan: labelFans of vi.
static std::vector<std::vector<uint32_t>> pinchMergeGroups(const State& s, uint32_t vi, const std::vector<uint32_t>& fan) {
    const auto& fs = s.vfaces[vi];
    const uint32_t fans = fan.empty() ? 0 : *std::max_element(fan.begin(), fan.end()) + 1;
    std::vector<uint32_t> parent(fans);
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](uint32_t x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (size_t a = 0; a < fs.size(); ++a)
        for (size_t b = a + 1; b < fs.size(); ++b)
            if (fan[a] != fan[b] && s.faceRegion[fs[a]] == s.faceRegion[fs[b]]) parent[root(fan[a])] = root(fan[b]);
    std::vector<std::vector<uint32_t>> groups(fans);
    for (size_t k = 0; k < fs.size(); ++k) groups[root(fan[k])].push_back(s.faceRegion[fs[k]]);
    std::vector<std::vector<uint32_t>> out;
    for (auto& g : groups) {
        std::sort(g.begin(), g.end());
        g.erase(std::unique(g.begin(), g.end()), g.end());
        if (!g.empty()) out.push_back(std::move(g));
    }
    return out;
}

// Topology and geometry of (vi -> vj); on success fills dev.
static Reject checkCollapse(const State& s, Scratch& w, uint32_t vi, const RingEntry& edge, double q, double& dev, float& farDist) {
    uint32_t vj = edge.w;
    if (s.locked[vj]) return Reject::Locked;
    bool borderEdge = edge.f1 == kNone;
    if (s.border[vi] && !borderEdge) return Reject::Border;
    size_t fanFaces = s.vfaces[vi].size();
    if (s.pinch[vi]) {  // the fan of the edge must not vanish (w.fan labels vfaces[vi])
        const auto& fs = s.vfaces[vi];
        uint32_t f0 = w.fan[size_t(std::find(fs.begin(), fs.end(), edge.f0) - fs.begin())];
        fanFaces = size_t(std::count(w.fan.begin(), w.fan.end(), f0));
    }
    if (fanFaces <= (borderEdge ? 1u : 2u)) return Reject::Ear;
    // Link condition: the common neighbours are exactly the opposite vertices of the edge's faces.
    // (markI[w] == stampI marks the one-ring of vi; markJ dedupes the neighbours of vj.)
    size_t common = 0;
    uint32_t stampJ = ++w.stampJ;
    uint32_t commonV[3] = {kNone, kNone, kNone};
    for (uint32_t f : s.vfaces[vj])
        for (uint32_t u : s.tri[f]) {
            if (u == vj || w.markJ[u] == stampJ) continue;
            w.markJ[u] = stampJ;
            if (w.markI[u] == w.stampI) {
                if (common < 3) commonV[common] = u;
                ++common;
            }
        }
    // (Not for a pinch: its "hole" may be a crack between sheets that only share vertices, and
    // closing it would join faces whose regions were kept apart.)
    if (borderEdge && common == 2 && !s.pinch[vi]) {
        // Closing a three-vertex hole (vi, vj, b): allowed, the edge (vj, b) gets its second face.
        const Tri& t0 = s.tri[edge.f0];
        uint32_t opposite = t0[0] != vi && t0[0] != vj ? t0[0] : (t0[1] != vi && t0[1] != vj ? t0[1] : t0[2]);
        uint32_t b = commonV[0] == opposite ? commonV[1] : commonV[0];
        bool holeI = false;
        for (const RingEntry& e : w.ring)
            if (e.w == b) holeI = e.f1 == kNone;
        size_t facesJB = 0;
        for (uint32_t f : s.vfaces[vj]) facesJB += s.corner(f, b) >= 0;
        if (!holeI || facesJB != 1 || s.locked[b]) return Reject::Link;
    } else if (common != (borderEdge ? 1u : 2u)) {
        return Reject::Link;
    }

    const auto& P = s.mesh.positions;
    Vec3 pi = P[vi], pj = P[vj];
    uint32_t far = s.farPoint[vi];
    Vec3 pf = far != kNone ? P[far] : pi;
    double best2 = std::numeric_limits<double>::infinity(), far2 = best2;
    for (uint32_t f : s.vfaces[vi]) {
        if (f == edge.f0 || f == edge.f1) continue;
        const Tri& t = s.tri[f];
        int c = s.corner(f, vi);
        // No duplicate faces (the link condition on vertices misses the tetrahedron): a moved face
        // (vj, x, y) must not already exist around vj.
        uint32_t x = t[(c + 1) % 3], y = t[(c + 2) % 3];
        // (Only possible when x and y are both neighbours of vj, marked by the link loop above.)
        if (w.markJ[x] == stampJ && w.markJ[y] == stampJ)
            for (uint32_t g : s.vfaces[vj])
                if (g != edge.f0 && g != edge.f1 && s.corner(g, x) >= 0 && s.corner(g, y) >= 0) return Reject::Link;
        Vec3 qv[3] = {P[t[0]], P[t[1]], P[t[2]]};
        Vec3 n0 = cross(qv[1] - qv[0], qv[2] - qv[0]);
        qv[c] = pj;
        Vec3 e1 = qv[1] - qv[0], e2 = qv[2] - qv[0];
        Vec3 n1 = cross(e1, e2);
        double l1 = length(n1);
        double scale = std::max({length2(e1), length2(e2), length2(qv[2] - qv[1])});
        if (!(l1 > 1e-12 * scale)) return Reject::Degenerate;
        double l0 = length(n0);
        if (l0 > 0 && dot(n0, n1) <= s.cosMaxNormalChange * l0 * l1) return Reject::Flip;
        const auto& on = s.tri.rec[f].n;
        if (n1.x * on[0] + n1.y * on[1] + n1.z * on[2] <= 0 && (on[0] != 0 || on[1] != 0 || on[2] != 0))
            return Reject::Flip;
        // The distance to the face's plane bounds the distance to the face from below: skip the
        // exact query when the plane is already farther than the best face (with a margin far
        // above rounding, so the minimum is the same as without the test).
        double inv = 1.0 / (l1 * l1);
        double dp = dot(pi - qv[0], n1);
        if (dp * dp * inv <= best2 * (1 + 1e-6))
            best2 = std::min(best2, closestWithDistance(pi, qv[0], qv[1], qv[2]).dist2);
        if (far != kNone) {
            double df = dot(pf - qv[0], n1);
            if (df * df * inv <= far2 * (1 + 1e-6))
                far2 = std::min(far2, closestWithDistance(pf, qv[0], qv[1], qv[2]).dist2);
        }
    }
    farDist = far != kNone ? float(std::sqrt(far2)) : 0.f;
    dev = std::max({std::sqrt(best2), double(farDist), q});
    return Reject::None;
}

// Region plan of a valid collapse: rule 3 or merge; rule 1 check; E_region key. ringI must hold
// the ring of vi.
static Reject planRegions(const State& s, Scratch& w, uint32_t vi, const RingEntry& edge, Candidate& c) {
    // Rule 3 applies to a collapse along one of exactly two p-boundary spokes of an interior vertex
    // when each side keeps a surviving face: the new edge (v_j, v_k) stays a p-boundary.
    c.rule3 = false;
    double chord = -1;  // distance of V_i to the new boundary edge; < 0: rule 3 does not apply
    uint32_t rA = kNone, rB = kNone;
    if (!s.border[vi] && !s.pinch[vi] && isPBoundarySpoke(s, edge)) {
        uint32_t spokes = 0, vk = kNone;
        for (const RingEntry& e : w.ring)
            if (isPBoundarySpoke(s, e)) {
                ++spokes;
                if (e.w != edge.w) vk = e.w;
            }
        if (spokes == 2 && vk != kNone) {
            rA = s.faceRegion[edge.f0];
            rB = s.faceRegion[edge.f1];
            bool keptA = false, keptB = false;
            for (uint32_t f : s.vfaces[vi]) {
                if (f == edge.f0 || f == edge.f1) continue;
                keptA |= s.faceRegion[f] == rA;
                keptB |= s.faceRegion[f] == rB;
            }
            const auto& P = s.mesh.positions;
            if (keptA && keptB) chord = distanceToSegment(P[vi], P[edge.w], P[vk]);
        }
    }
    auto keepBoundary = [&] {
        c.rule3 = true;
        c.shape = std::max(regionShape(s, s.regionStats[rA]), regionShape(s, s.regionStats[rB]));
        return Reject::None;
    };
    double eps = std::max(s.options.epsilonDeviationFactor * c.dev, s.options.epsilonBoxFactor * s.longestSide);
    if (chord >= 0 && chord <= eps) return keepBoundary();
    if (s.pinch[vi]) {
        // Each fan's regions merge on their own (a pinch counts as open: rule 1 does not apply).
        double shape = 0;
        for (const auto& g : pinchMergeGroups(s, vi, w.fan)) {
            RegionStats merged = s.regionStats[g[0]];
            for (size_t k = 1; k < g.size(); ++k) mergeStats(merged, s.regionStats[g[k]]);
            if (g.size() > 1 && length(merged.normalSum) < s.minRegionCoherence * merged.area) return Reject::Cone;
            shape = std::max(shape, double(regionShape(s, merged)));
        }
        c.shape = float(shape);
        return Reject::None;
    }
    // Otherwise every region of the fan merges, unless rule 1 or the normal cone forbids it. When
    // the cone forbids it, a rule-3 collapse is still allowed, its cost raised to the boundary's
    // displacement (the texture error of keeping the chart cut on the new edge).
    w.regions.clear();
    for (uint32_t f : s.vfaces[vi]) w.regions.push_back(s.faceRegion[f]);
    std::sort(w.regions.begin(), w.regions.end());
    w.regions.erase(std::unique(w.regions.begin(), w.regions.end()), w.regions.end());
    uint32_t comp = s.component[vi];
    uint32_t after = s.componentRegions[comp] - uint32_t(w.regions.size() - 1);
    Reject merge = Reject::None;
    RegionStats merged = s.regionStats[w.regions[0]];
    for (size_t k = 1; k < w.regions.size(); ++k) mergeStats(merged, s.regionStats[w.regions[k]]);
    if (s.componentOpen[comp] == 0 && after < 2 && w.regions.size() > 1)
        merge = Reject::Rule1;

    else if (w.regions.size() > 1 && length(merged.normalSum) < s.minRegionCoherence * merged.area)
        // Regions become texture charts: a merge may not turn a region further than a cap of
        // maxRegionConeDeg half-angle (measured by the mean resultant length of its normals).
        merge = Reject::Cone;
    if (merge != Reject::None) {
        if (chord < 0) return merge;
        c.dev = std::max(c.dev, chord);
        return keepBoundary();
    }
    c.shape = regionShape(s, merged);
    return Reject::None;
}

// The ring of vi and the quadric term of each outgoing half-edge (w.ring, w.options, unsorted).
// Quadric distances below rounding noise (relative to the model size) tie at 0, so equal costs
// fall back to the smaller target id deterministically. Returns the smallest term: a lower bound
// of vi's collapse cost (every option costs at least its quadric term; 0 without neighbours).
static double ringOptions(const State& s, Scratch& w, uint32_t vi) {
    collectRing(s, vi, w.ring);
    const Quadric& Q = s.quadric[vi];
    const double noise = 1e-9 * s.diagonal;
    const size_t n = w.ring.size();
    w.options.resize(n);
    double bound = n ? std::numeric_limits<double>::infinity() : 0.0;
    for (size_t k = 0; k < n; ++k) {
        double q = Q.distance(s.mesh.positions[w.ring[k].w]);
        w.options[k] = {q > noise ? q : 0.0, uint32_t(k)};
        bound = std::min(bound, w.options[k].q);
    }
    return bound;
}

// The best collapse of vi: its outgoing half-edges in quadric order, the first valid one.
// `prepared`: ringOptions(vi) already filled the scratch.
static Candidate evaluateVertex(const State& s, Scratch& w, uint32_t vi, bool prepared = false) {
    Candidate best;
    if (s.removed[vi] || s.vfaces[vi].empty()) return best;
    if (s.locked[vi]) {
        best.reason = Reject::Locked;
        return best;
    }
    if (!prepared) ringOptions(s, w, vi);
    // A pinch moves with all its fans, which must still be apart: a sticky pinch whose fans were
    // joined by later collapses stays (its faces are only vertex-connected in the original mesh).
    if (s.pinch[vi] && labelFans(s, vi, w.ring, w.fan) < 2) {
        best.reason = Reject::Locked;
        return best;
    }
    ++w.stampI;
    for (const RingEntry& e : w.ring) w.markI[e.w] = w.stampI;
    Option* o = w.options.data();
    const size_t n = w.options.size();
    const double noise = 1e-9 * s.diagonal;
    std::sort(o, o + n, [&](const Option& a, const Option& b) {
        return a.q != b.q ? a.q < b.q : s.oldId[w.ring[a.k].w] < s.oldId[w.ring[b.k].w];
    });
    Reject last = Reject::Isolated;
    best.reason = Reject::Isolated;
    bool found = false;
    for (size_t k = 0; k < n; ++k) {
        if (found && o[k].q >= best.dev) break;  // the cost is at least the quadric term
        const RingEntry& edge = w.ring[o[k].k];
        double dev = 0;
        float farDist = 0;
        Reject r = checkCollapse(s, w, vi, edge, o[k].q, dev, farDist);
        if (dev <= noise) dev = 0;  // rounding noise: ties go to the smaller target id
        if (r != Reject::None) {
            if (last == Reject::Isolated || r == Reject::Rule1 || r == Reject::Cone) last = r;
            continue;
        }
        Candidate c;
        c.target = edge.w;
        c.dev = dev;
        c.farDist = farDist;
        r = planRegions(s, w, vi, edge, c);
        if (r != Reject::None) {
            last = r;
            continue;
        }
        c.reason = Reject::None;
        if (!found || c.dev < best.dev) best = c;
        found = true;
    }
    if (!found) best.reason = last;
    best.evalPass = s.pass;
    return best;
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
        s.out.regionUpdates.push_back({r, newRep});
        for (uint32_t f = s.regionHead[r]; f != kNone; f = s.regionNext[f]) {
            s.faceRegion[f] = newRep;
            s.faceRelabelPass[f] = s.pass;
        }
        s.regionNext[s.regionTail[newRep]] = s.regionHead[r];
        s.regionTail[newRep] = s.regionTail[r];
        s.regionSize[newRep] += s.regionSize[r];
        mergeStats(s.regionStats[newRep], s.regionStats[r]);
        s.regionSize[r] = 0;
    }
    s.regionCount -= uint32_t(reps.size() - 1);
}

static void updateRegions(State& s, uint32_t vi, const Candidate& c, const std::vector<uint32_t>& fan) {
    if (c.rule3) return;  // each side keeps its own region (a removed representative stays until the snapshot)
    if (s.pinch[vi]) {  // each fan's regions merge on their own (see planRegions)
        std::vector<RingEntry> ring;
        std::vector<uint32_t> fans;
        collectRing(s, vi, ring);
        labelFans(s, vi, ring, fans);
        s.collapseSource = vi;
        s.collapseTarget = c.target;
        for (const auto& g : pinchMergeGroups(s, vi, fans)) {
            if (g.size() < 2) continue;
            s.componentRegions[s.component[vi]] -= uint32_t(g.size() - 1);
            mergeRegionGroup(s, g);
        }
        return;
    }
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
    for (uint32_t r = 0; r < s.faceCount; ++r) {
        if (s.faceAlive[r] || s.regionSize[r] == 0 || s.faceRegion[r] != r) continue;
        uint32_t m = kNone;
        for (uint32_t f = s.regionHead[r]; f != kNone; f = s.regionNext[f])
            if (s.faceAlive[f] && f < m) m = f;
        if (m == kNone) continue;  // cannot happen: every region keeps a surviving face
        s.out.regionUpdates.push_back({r, m});
        for (uint32_t f = s.regionHead[r]; f != kNone; f = s.regionNext[f]) {
            s.faceRegion[f] = m;
            s.faceRelabelPass[f] = s.pass;
        }
        s.regionHead[m] = s.regionHead[r];
        s.regionTail[m] = s.regionTail[r];
        s.regionSize[m] = s.regionSize[r];
        s.regionStats[m] = s.regionStats[r];
        s.regionSize[r] = 0;
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

// Applies the collapse (its region plan c must be current).
static void applyCollapse(State& s, uint32_t vi, const Candidate& c) {
    uint32_t vj = c.target;
    std::vector<uint32_t>& fan = s.fanScratch;
    std::vector<uint32_t>& kept = s.keptScratch;
    std::vector<uint32_t>& removedFaces = s.removedScratch;
    fan.assign(s.vfaces[vi].begin(), s.vfaces[vi].end());
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
            s.vfaces[u].eraseValue(r);
        }
    }
    for (uint32_t f : kept) s.vfaces[vj].push_back(f);
    if (s.isOpen(vi)) {
        // A border collapse may close a three-vertex hole: refresh the border and pinch flags of
        // the ring.
        uint32_t comp = s.component[vi];
        --s.componentOpen[comp];
        s.border[vi] = s.pinch[vi] = 0;
        std::vector<uint32_t>& ring = s.repScratch;
        ring.clear();
        for (uint32_t f : fan)
            for (uint32_t u : s.tri[f])
                if (u != vi && !s.locked[u]) ring.push_back(u);
        std::sort(ring.begin(), ring.end());
        ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
        for (uint32_t u : ring) {
            if (s.vfaces[u].empty()) continue;
            bool wasOpen = s.isOpen(u), open = false;
            FanKind k = classifyFan(s, u, open);
            // Locks and pinches are sticky: a pinch whose fans got joined by later collapses
            // still has fans that are only vertex-connected in the original mesh, and merging
            // their regions through it would break region edge-connectivity.
            s.locked[u] |= k == FanKind::NonManifold;
            s.pinch[u] |= k == FanKind::Pinch;
            s.border[u] = open;
            if (s.isOpen(u) != wasOpen) {
                if (wasOpen) --s.componentOpen[comp]; else ++s.componentOpen[comp];
            }
        }
    }
    s.vfaces[vi].release();
    s.removed[vi] = 1;
    s.collapsedInto[vi] = vj;
    s.keptFace[vi] = kept.empty() ? kNone : kept.front();

    s.aliveFaces -= removedFaces.size();
    s.componentFaces[s.component[vi]] -= uint32_t(removedFaces.size());
    s.quadric[vj].add(s.quadric[vi]);
    // The farthest attached point of vj: vi itself, vi's farthest point or vj's own.
    // (Ties by input id; kNone ranks last.)
    auto key = [&](uint32_t v) { return v == kNone ? kNone : s.oldId[v]; };
    float farD = s.farDist[vj];
    uint32_t farP = s.farPoint[vj];
    auto offer = [&](float d, uint32_t p) {
        if (d > farD || (d == farD && key(p) > key(farP))) farD = d, farP = p;
    };
    offer(float(c.dev), vi);
    if (s.farPoint[vi] != kNone) offer(c.farDist, s.farPoint[vi]);
    s.farDist[vj] = farD;
    s.farPoint[vj] = farP;
    // vi and its attached points now hang under vj.
    s.attachNext[vi] = s.attachHead[vi];
    uint32_t tail = s.attachTail[vi] == kNone ? vi : s.attachTail[vi];
    s.attachNext[tail] = s.attachHead[vj];
    if (s.attachHead[vj] == kNone) s.attachTail[vj] = tail;
    s.attachHead[vj] = vi;
    s.attachHead[vi] = s.attachTail[vi] = kNone;
    s.out.collapses.push_back({vi, vj, float(c.dev), begin, end});
    s.runningMax = std::max(s.runningMax, double(float(c.dev)));
}

// Removes closed component `comp` entirely (see the header comment).
static void pruneComponent(State& s, uint32_t comp) {
    s.componentPruned[comp] = 1;
    float dev = float(s.componentSize[comp]);
    uint32_t at = uint32_t(s.out.regionUpdates.size());
    for (uint32_t k = s.componentVertexStart[comp]; k < s.componentVertexStart[comp + 1]; ++k) {
        uint32_t v = s.componentVertices[k];
        if (s.removed[v] || s.vfaces[v].empty()) continue;
        for (uint32_t f : s.vfaces[v])
            if (s.faceAlive[f]) {
                s.faceAlive[f] = 0;
                --s.aliveFaces;
            }
    }
    for (uint32_t k = s.componentVertexStart[comp]; k < s.componentVertexStart[comp + 1]; ++k) {
        uint32_t v = s.componentVertices[k];
        if (s.removed[v] || s.vfaces[v].empty()) continue;
        s.vfaces[v].release();
        s.removed[v] = 1;
        s.collapsedInto[v] = kNone;
        s.cand[v] = Candidate{};
        s.out.collapses.push_back({v, v, dev, at, at});
    }
    s.componentFaces[comp] = 0;
    s.runningMax = std::max(s.runningMax, double(dev));
}

// Prunes components (closed ones only when closedOnly) whose size is below `limit`, smallest first,
// while the live count stays at or above `target`. Returns whether anything was pruned.
static bool pruneComponents(State& s, double limit, uint64_t target, bool closedOnly) {
    bool any = false;
    for (uint32_t comp : s.componentOrder) {
        if (s.aliveFaces <= target) break;
        if (!(s.componentSize[comp] < limit)) break;
        if (s.componentPruned[comp] || (closedOnly && s.componentOpen[comp] != 0)) continue;
        // Never undershoot the target, never prune the last faces.
        if (s.aliveFaces - s.componentFaces[comp] < std::max<uint64_t>(target, 1)) continue;
        pruneComponent(s, comp);
        any = true;
    }
    return any;
}

static const char* summariseStop(const State& s) {
    size_t counts[size_t(Reject::Count)] = {};
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (!s.removed[v] && !s.vfaces[v].empty()) ++counts[size_t(s.cand[v].reason)];
    // Rule 1 and locks are what the user can act on: name them when they block anything.
    if (counts[size_t(Reject::Rule1)]) return kRejectReason[size_t(Reject::Rule1)];
    size_t best = size_t(Reject::Isolated);
    for (size_t k = 1; k < size_t(Reject::Count); ++k)
        if (counts[k] > counts[best]) best = k;
    return kRejectReason[best];
}


// Root of the collapse chain of removed vertex v (kNone when it ends in a pruned vertex), memoised
// for one snapshot in root[].
static uint32_t chainRoot(const State& s, uint32_t v, std::vector<uint32_t>& root) {
    uint32_t u = v;
    while (s.removed[u] && root[u] == kNone - 1) {
        uint32_t next = s.collapsedInto[u];
        if (next == kNone) break;
        u = next;
    }
    uint32_t r = !s.removed[u] ? u : (root[u] != kNone - 1 ? root[u] : kNone);
    for (uint32_t w = v; w != u && s.removed[w];) {  // path compression
        uint32_t next = s.collapsedInto[w];
        root[w] = r;
        if (next == kNone) break;
        w = next;
    }
    if (s.removed[u]) root[u] = r;
    return r;
}

static void computePairs(State& s, Level& level) {
    const auto& P = s.mesh.positions;
    // Chain roots first (sequential, memoised), then the projections in parallel chunks whose
    // pairs are concatenated in vertex order.
    std::vector<uint32_t> root(s.vertexCount, kNone - 1), rootOf(s.vertexCount, kNone);
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (s.removed[v] && s.collapsedInto[v] != kNone) rootOf[v] = chainRoot(s, v, root);
    root.clear();
    root.shrink_to_fit();
    double runningMax2 = s.runningMax * s.runningMax;
    size_t chunks = (s.vertexCount + kChunk - 1) / kChunk;
    std::vector<std::vector<SimplificationPair>> chunkPairs(chunks);
    parallelChunks(s.vertexCount, s.work.size(), [&](size_t begin, size_t end, size_t t) {
        Scratch& w = s.work[t];
        if (w.faceMark.size() != s.faceCount) w.faceMark.assign(s.faceCount, 0);
        std::vector<SimplificationPair>& out = chunkPairs[begin / kChunk];
        for (uint32_t u = uint32_t(begin); u < end; ++u) {  // in input order
            uint32_t v = s.newId[u];
            uint32_t r = rootOf[v];
            if (r == kNone || s.vfaces[r].empty()) continue;
            uint32_t region = s.keptFace[v] == kNone ? kNone : s.faceRegion[s.keptFace[v]];
            double bestAny = std::numeric_limits<double>::infinity(), bestRegion = bestAny;
            uint32_t fAny = kNone, fRegion = kNone;
            Closest cAny{}, cRegion{};
            auto consider = [&](uint32_t f) {
                const Tri& t = s.tri[f];
                Closest cp = closestWithDistance(P[v], P[t[0]], P[t[1]], P[t[2]]);
                if (cp.dist2 < bestAny) bestAny = cp.dist2, fAny = f, cAny = cp;
                if (s.faceRegion[f] == region && cp.dist2 < bestRegion) bestRegion = cp.dist2, fRegion = f, cRegion = cp;
            };
            for (uint32_t f : s.vfaces[r]) consider(f);
            // Farther than any collapse cost: the closest point may lie one ring out.
            double found = fRegion != kNone ? bestRegion : bestAny;
            if (found > runningMax2) {
                uint32_t stamp = ++w.faceStamp;
                for (uint32_t f : s.vfaces[r]) w.faceMark[f] = stamp;
                for (uint32_t f : s.vfaces[r])
                    for (uint32_t u : s.tri[f])
                        for (uint32_t g : s.vfaces[u])
                            if (w.faceMark[g] != stamp) {
                                w.faceMark[g] = stamp;
                                consider(g);
                            }
            }
            uint32_t f = fRegion != kNone ? fRegion : fAny;
            const Closest& cp = fRegion != kNone ? cRegion : cAny;
            const Tri& t = s.tri[f];
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
            out.push_back(pair);
        }
    });
    double sum = 0, maxPair = 0;
    size_t total = 0;
    for (const auto& c : chunkPairs) total += c.size();
    level.pairs.reserve(total);
    for (auto& c : chunkPairs) {
        for (const SimplificationPair& pair : c) {
            sum += pair.deviation;
            maxPair = std::max(maxPair, double(pair.deviation));
        }
        level.pairs.insert(level.pairs.end(), c.begin(), c.end());
        std::vector<SimplificationPair>().swap(c);
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

// 7c. Passes.

// Whether v's cached candidate may be stale after the previous pass (see the header comment).
static bool needsEvaluation(const State& s, uint32_t v) {
    uint32_t prev = s.pass - 1;
    if (s.pass == 1 || s.dirtyPass[v] == prev) return true;
    const Candidate& c = s.cand[v];
    if (c.reason == Reject::None) return s.dirtyPass[c.target] == prev;
    if (c.reason == Reject::Locked && (s.locked[v] || s.pinch[v])) return false;
    for (uint32_t f : s.vfaces[v])
        for (uint32_t u : s.tri[f])
            if (s.dirtyPass[u] == prev) return true;
    return false;
}

// Under an error target: the largest distance, after collapse (vi -> vj), of every removed point
// attached to a vertex whose fan changes (and of V_i), to the new fan of the vertex it then hangs
// under. Pairs are projected onto (at least) that fan, so a collapse measured here within the
// target keeps every pair within it.
static double measureAttached(State& s, uint32_t vi, uint32_t vj) {
    Scratch& w = s.work[0];
    const auto& P = s.mesh.positions;
    auto newCorners = [&](uint32_t f, Tri& t) {  // false when f vanishes
        t = s.tri[f];
        int ci = s.corner(f, vi);
        if (ci < 0) return true;
        if (s.corner(f, vj) >= 0) return false;
        t[ci] = vj;
        return true;
    };
    auto dist2ToFan = [&](uint32_t p, uint32_t x) {
        double best = std::numeric_limits<double>::infinity();
        Tri t;
        for (uint32_t f : s.vfaces[x])
            if (newCorners(f, t)) best = std::min(best, closestWithDistance(P[p], P[t[0]], P[t[1]], P[t[2]]).dist2);
        if (x == vj)
            for (uint32_t f : s.vfaces[vi])
                if (s.corner(f, vj) < 0 && newCorners(f, t))
                    best = std::min(best, closestWithDistance(P[p], P[t[0]], P[t[1]], P[t[2]]).dist2);
        return best;
    };
    double worst = dist2ToFan(vi, vj);
    for (uint32_t p = s.attachHead[vi]; p != kNone; p = s.attachNext[p]) worst = std::max(worst, dist2ToFan(p, vj));
    ++w.stampJ;
    for (uint32_t f : s.vfaces[vi])
        for (uint32_t x : s.tri[f]) {
            if (x == vi || w.markJ[x] == w.stampJ) continue;
            w.markJ[x] = w.stampJ;
            for (uint32_t p = s.attachHead[x]; p != kNone; p = s.attachNext[p]) worst = std::max(worst, dist2ToFan(p, x));
        }
    return std::sqrt(worst);
}

// Whether a cached candidate of vi may have changed since it was evaluated: the fans of vi or of
// its target changed, a face of vi's fan was relabelled, rule 1 may apply (closed component), the
// normal-cone limit reads region stats, or the pass needs exact measuring (error target).
static bool candidateStale(const State& s, uint32_t vi, const Candidate& c) {
    if (c.evalPass == 0 || s.dirtyPass[vi] >= c.evalPass || s.dirtyPass[c.target] >= c.evalPass) return true;
    if (s.componentOpen[s.component[vi]] == 0 || s.minRegionCoherence > 0) return true;
    for (uint32_t f : s.vfaces[vi])
        if (s.faceRelabelPass[f] >= c.evalPass) return true;
    return false;
}

static void applyCandidate(State& s, uint32_t vi, const Candidate& c) {
    for (uint32_t f : s.vfaces[vi])
        for (uint32_t u : s.tri[f]) s.dirtyPass[u] = s.pass;
    s.touchedPass[vi] = s.touchedPass[c.target] = s.pass;
    applyCollapse(s, vi, c);
    s.cand[vi] = Candidate{};
}

enum class PassResult { Progress, Idle, NoCandidate, ErrorReached };

// Whether v has a current candidate after this pass's evaluation: v is evaluated when its cached
// candidate may be stale (needsEvaluation), unless a lower bound of its cost is above `bound`
// (deferred: its candidate cannot be under this pass's limit; the bound is kept, and refreshed
// when v's fan changes).
static bool evaluateOrDefer(State& s, Scratch& w, uint32_t v, double bound) {
    bool prepared = false;
    if (s.deferred[v]) {
        if (s.dirtyPass[v] == s.pass - 1) {
            s.costBound[v] = ringOptions(s, w, v);
            prepared = true;
        }
        if (s.costBound[v] > bound) return false;
        s.deferred[v] = 0;
    } else if (!needsEvaluation(s, v)) {
        return true;
    } else if (bound < std::numeric_limits<double>::infinity() && !s.locked[v] && !s.pinch[v]) {
        double lb = ringOptions(s, w, v);
        prepared = true;
        if (lb > bound) {
            s.deferred[v] = 1;
            s.costBound[v] = lb;
            s.cand[v] = Candidate{};
            return false;
        }
    }
    s.cand[v] = evaluateVertex(s, w, v, prepared);
    return true;
}

// The pass entry of v's valid candidate c (bucket filled in once the pass limit is known).
static PassEntry passEntry(const State& s, uint32_t v, const Candidate& c) {
    return {0, s.options.similarDeviation > 0 ? c.shape : 0.f, c.dev, v, s.oldId[v]};
}

// Evaluates the deferred vertices whose bound is at most `upTo` (in parallel), appending the valid
// ones within `maxCost` to `entries` (when given); returns how many stay deferred.
static size_t resolveDeferred(State& s, double upTo, double maxCost, std::vector<PassEntry>* entries, bool* anyValid) {
    const size_t chunks = (s.vertexCount + kChunk - 1) / kChunk;
    std::vector<size_t> left(chunks, 0);
    std::vector<std::vector<PassEntry>> found(chunks);
    std::vector<uint8_t> valid(chunks, 0);
    parallelChunks(s.vertexCount, s.work.size(), [&](size_t begin, size_t end, size_t t) {
        const size_t k = begin / kChunk;
        for (uint32_t v = uint32_t(begin); v < end; ++v) {
            if (!s.deferred[v] || s.removed[v] || s.vfaces[v].empty()) continue;
            if (s.costBound[v] > upTo) {
                ++left[k];
                continue;
            }
            s.deferred[v] = 0;
            s.cand[v] = evaluateVertex(s, s.work[t], v);
            const Candidate& c = s.cand[v];
            if (c.reason != Reject::None) continue;
            valid[k] = 1;
            if (c.dev <= maxCost) found[k].push_back(passEntry(s, v, c));
        }
    });
    size_t stay = 0;
    for (size_t k = 0; k < chunks; ++k) {
        stay += left[k];
        if (anyValid) *anyValid |= valid[k] != 0;
        if (entries) entries->insert(entries->end(), found[k].begin(), found[k].end());
    }
    return stay;
}

// One pass toward `plan` (see the header comment).
static PassResult runPass(State& s, const PlannedLevel& plan) {
    Scratch& w = s.work[0];
    ++s.pass;
    s.entries.clear();
    double maxCost = plan.error;
    bool anyValid = false;
    // a. Candidates, in parallel: each depends only on the state, so the result is the same for
    //    any thread count.
    //    Each chunk also lists its valid candidates within the error target, concatenated in
    //    chunk order.
    //    Vertices whose cost is bounded from below by more than kDeferFactor x the previous
    //    pass's limit are deferred (the limit mostly grows by 1.05-1.5x per pass): when this
    //    pass's limit stays below every deferred bound, as it mostly does, the pass is what
    //    evaluating them now would give; otherwise they are evaluated before the limit is taken.
    const double bound = kDeferFactor * s.lastLimit;
    size_t chunks = (s.vertexCount + kChunk - 1) / kChunk;
    s.chunkEntries.resize(chunks);
    std::vector<uint8_t> chunkValid(chunks, 0);
    std::vector<size_t> chunkDeferred(chunks, 0);
    parallelChunks(s.vertexCount, s.work.size(), [&](size_t begin, size_t end, size_t t) {
        Scratch& ws = s.work[t];
        std::vector<PassEntry>& out = s.chunkEntries[begin / kChunk];
        out.clear();
        for (uint32_t v = uint32_t(begin); v < end; ++v) {
            if (s.removed[v] || s.vfaces[v].empty()) continue;
            if (!evaluateOrDefer(s, ws, v, bound)) {
                ++chunkDeferred[begin / kChunk];
                continue;
            }
            const Candidate& c = s.cand[v];
            if (c.reason != Reject::None) continue;
            chunkValid[begin / kChunk] = 1;
            if (c.dev > maxCost) continue;
            out.push_back(passEntry(s, v, c));
        }
    });
    size_t deferred = 0;
    for (size_t k = 0; k < chunks; ++k) {
        anyValid |= chunkValid[k] != 0;
        deferred += chunkDeferred[k];
        s.entries.insert(s.entries.end(), s.chunkEntries[k].begin(), s.chunkEntries[k].end());
    }
    uint64_t target = plan.triangles;
    // Pass error limit: 1.1 x the cost of the (remaining collapses / 3)-th cheapest candidate.
    const size_t need = size_t((s.aliveFaces - target + 1) / 2);
    auto byDev = [](const PassEntry& a, const PassEntry& b) { return a.dev < b.dev; };
    if (deferred) {
        // The deferred candidates cost more than `bound`: they do not move a goal-th cheapest
        // below it. Otherwise (or when there are too few candidates) evaluate them all.
        bool exact = need / 3 < s.entries.size();
        if (exact) {
            std::nth_element(s.entries.begin(), s.entries.begin() + need / 3, s.entries.end(), byDev);
            exact = s.entries[need / 3].dev < bound;
        }
        if (!exact) deferred = resolveDeferred(s, std::numeric_limits<double>::infinity(), maxCost, &s.entries, &anyValid);
    }
    double limit = maxCost;
    if (!s.entries.empty()) {
        size_t goal = std::min(s.entries.size() - 1, need / 3);
        std::nth_element(s.entries.begin(), s.entries.begin() + goal, s.entries.end(), byDev);
        limit = std::min(maxCost, s.entries[goal].dev * 1.1);
    }
    // Deferred candidates that may be under the limit join the pass.
    if (deferred && limit >= bound) deferred = resolveDeferred(s, limit, maxCost, &s.entries, &anyValid);
    s.lastLimit = limit;
    // Component pruning when the limit exceeds a closed component's size (or nothing else is left).
    if (pruneComponents(s, limit, target, true)) {
        // Candidates of pruned vertices are gone.
        s.entries.erase(std::remove_if(s.entries.begin(), s.entries.end(),
                                       [&](const PassEntry& e) { return s.removed[e.vertex] != 0; }),
                        s.entries.end());
        if (s.aliveFaces <= target) return PassResult::Progress;
    }
    if (s.entries.empty()) return anyValid ? PassResult::ErrorReached : PassResult::NoCandidate;
    // Candidates under the limit, in (bucket, E_region, deviation, vertex) order.
    size_t o = 0;
    for (const PassEntry& e : s.entries)
        if (e.dev <= limit) s.entries[o++] = {bucketOf(s, e.dev), e.shape, e.dev, e.vertex, e.key};
    s.entries.resize(o);
    std::sort(s.entries.begin(), s.entries.end());
    size_t applied = 0;
    const size_t entryCount = s.entries.size();
    for (size_t k = 0; k < entryCount; ++k) {
        const PassEntry& e = s.entries[k];
        if (s.aliveFaces <= target) break;
        // The walk visits vertices in cost order, i.e. at random: fetch ahead what it reads first
        // (the vertex's candidate and face list, then the faces of a nearer entry).
        if (k + 16 < entryCount) {
            uint32_t a = s.entries[k + 16].vertex;
            __builtin_prefetch(&s.cand[a]);
            __builtin_prefetch(&s.vfaces[a]);
            __builtin_prefetch(&s.touchedPass[a]);
        }
        if (k + 8 < entryCount) {
            uint32_t a = s.entries[k + 8].vertex;
            for (uint32_t f : s.vfaces[a]) __builtin_prefetch(&s.tri.rec[f]);
            __builtin_prefetch(&s.touchedPass[s.cand[a].target]);
        }
        uint32_t vi = e.vertex;
        if (s.removed[vi] || s.touchedPass[vi] == s.pass) continue;
        Candidate c = s.cand[vi];
        uint32_t vj = c.target;
        if (s.touchedPass[vj] == s.pass) continue;
        if (!std::isfinite(maxCost) && !candidateStale(s, vi, c)) {
            // Nothing the candidate depends on changed since it was evaluated: apply it as is.
            applyCandidate(s, vi, c);
            ++applied;
            continue;
        }
        collectRing(s, vi, w.ring);
        const RingEntry* edge = nullptr;
        for (const RingEntry& r : w.ring)
            if (r.w == vj) edge = &r;
        if (!edge || (s.pinch[vi] && labelFans(s, vi, w.ring, w.fan) < 2)) {
            s.dirtyPass[vi] = s.pass;  // re-evaluate next pass
            continue;
        }
        if (s.dirtyPass[vi] == s.pass || s.dirtyPass[vj] == s.pass) {
            // The fan of vi or of vj changed in this pass: check and cost the collapse again.
            ++w.stampI;
            for (const RingEntry& r : w.ring) w.markI[r.w] = w.stampI;
            double q = s.quadric[vi].distance(s.mesh.positions[vj]);
            if (checkCollapse(s, w, vi, *edge, q, c.dev, c.farDist) != Reject::None || c.dev > limit) {
                s.dirtyPass[vi] = s.pass;
                continue;
            }
        }
        // The region plan is re-done (labels may have merged).
        if (planRegions(s, w, vi, *edge, c) != Reject::None || c.dev > limit) {
            s.dirtyPass[vi] = s.pass;  // re-evaluate next pass
            continue;
        }
        if (std::isfinite(maxCost)) {
            // Error target: measure every attached point exactly (see measureAttached).
            double d = measureAttached(s, vi, c.target);
            if (d > maxCost) {
                s.cand[vi].dev = std::max(s.cand[vi].dev, d);  // out of this level until re-evaluated
                ++applied;  // not idle: the candidate set shrank
                continue;
            }
            c.dev = std::max(c.dev, d);
        }
        applyCandidate(s, vi, c);
        ++applied;
    }
    return applied ? PassResult::Progress : PassResult::Idle;
}

}  // namespace

SimplifyResult simplify(const TriMesh& mesh, const SimplifyOptions& options) {
    using Clock = std::chrono::steady_clock;
    validateInput(mesh);
    std::vector<uint32_t> oldId, newId;
    TriMesh local = renumberVertices(mesh, oldId, newId);
    State s(local, mesh, options);
    s.oldId = std::move(oldId);
    s.newId = std::move(newId);
    Box3 box = bounds(mesh);
    s.diagonal = box.diagonal();
    s.longestSide = box.longestSide();
    s.cosMaxNormalChange = std::cos(std::clamp(options.maxNormalChangeDeg, 0.0, 180.0) * M_PI / 180.0);
    // A spherical cap of half-angle t has |sum of area-weighted normals| / area = (1 + cos t) / 2.
    s.minRegionCoherence = 0.5 * (1 + std::cos(std::clamp(options.maxRegionConeDeg, 0.0, 180.0) * M_PI / 180.0));

    buildAdjacency(s);
    s.work.resize(size_t(std::max(1, options.threads)));
    for (Scratch& w : s.work) {
        w.markI.assign(s.vertexCount, 0);
        w.markJ.assign(s.vertexCount, 0);
    }
    classifyVertices(s);
    measureComponents(s);
    initQuadrics(s);
    initRegions(s);
    std::vector<PlannedLevel> plan = planLevels(s);
    s.cand.assign(s.vertexCount, Candidate{});
    s.deferred.assign(s.vertexCount, 0);
    s.costBound.assign(s.vertexCount, 0);
    s.dirtyPass.assign(s.vertexCount, 0);
    s.touchedPass.assign(s.vertexCount, 0);

    uint64_t finalTarget = plan.empty() ? s.faceCount : plan.back().triangles;
    double start = double(s.faceCount), span = std::max(1.0, start - double(std::min<uint64_t>(finalTarget, s.faceCount)));
    auto levelStart = Clock::now();
    for (const PlannedLevel& level : plan) {
        std::string stop = kRejectReason[0];
        int idle = 0;
        while (s.aliveFaces > level.triangles) {
            PassResult r = runPass(s, level);
            if (r == PassResult::ErrorReached) break;  // error target reached
            idle = r == PassResult::Idle ? idle + 1 : 0;
            if (r == PassResult::NoCandidate || idle > 2) {
                // Stuck: prune closed components up to the level's error target; then any
                // component (open or non-manifold ones too, which are stuck on locks) no larger
                // than the error already accepted, so pruning never raises maxDeviation; last, for
                // a triangle target, small parts (options.pruneStuckSize of the diagonal), smallest
                // first, whose size enters maxDeviation.
                if (pruneComponents(s, level.error, level.triangles, true) ||
                    pruneComponents(s, std::min(level.error, s.runningMax * (1 + 1e-9)), level.triangles, false) ||
                    (!std::isfinite(level.error) &&
                     pruneComponents(s, s.options.pruneStuckSize * s.diagonal, level.triangles, false))) {
                    idle = 0;
                    continue;
                }
                resolveDeferred(s, std::numeric_limits<double>::infinity(), level.error, nullptr, nullptr);
                stop = summariseStop(s);
                break;
            }
            if (options.progress && !options.progress(std::clamp((start - double(s.aliveFaces)) / span, 0.0, 1.0)))
                throw Impossible("simplify: cancelled");
        }
        auto now = Clock::now();
        snapshotLevel(s, level, stop, std::chrono::duration<double>(now - levelStart).count());
        levelStart = Clock::now();
    }
    if (options.progress && !options.progress(1.0)) throw Impossible("simplify: cancelled");

    restoreInputIds(s);
    SimplifyResult result;
    result.multires = std::move(s.out);
    result.diagonal = s.diagonal;
    return result;
}

}  // namespace lodbake
