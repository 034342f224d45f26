// The mesh during simplification and the half-edge collapse itself (docs/simplify.md).
//
// References: [Hoppe96] H. Hoppe, "Progressive meshes", SIGGRAPH 1996 (half-edge collapse, collapse
// records); [Garland97] M. Garland, P. Heckbert, "Surface simplification using quadric error
// metrics", SIGGRAPH 1997 (the per-vertex quadrics).
//
// Holds what every rule reads: the live faces around each vertex, vertex classes (locked, pinch,
// border), connected components, quadrics and the removed points hanging under each vertex. It
// also holds the visitor that records the simplification hierarchy (collapses, region updates).
// Private to lib/src/simplify.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"

namespace lodbake::simplify_detail {

constexpr uint32_t kNone = 0xffffffffu;

// Sum of weighted planes (n, d) with n . x + d = 0 [Garland97].
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
    // RMS distance of the accumulated planes to p (model units).
    double distance(Vec3 p) const { return w > 0 ? std::sqrt(eval(p) / w) : 0; }
};

struct Closest {
    double bary[3];
    double dist2;  // squared distance, model units squared
};

// Closest point on triangle abc to p, with its squared distance.
inline Closest closestWithDistance(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
    std::array<double, 3> u = closestOnTriangle(p, a, b, c);
    return Closest{{u[0], u[1], u[2]}, length2(p - (a * u[0] + b * u[1] + c * u[2]))};
}

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
    uint32_t f0, f1;  // f0 < f1; f1 == kNone when the edge has one face around v
};

enum class FanKind { Manifold, Pinch, NonManifold };

// Scratch of classifying one vertex's fan: its ring, faces per spoke, union-find of its faces.
struct FanScratch {
    std::vector<RingEntry> ring;
    std::vector<uint32_t> count, parent;
};

// Connected components of the input (over shared vertices), for rule 1 and pruning.
struct Components {
    std::vector<uint32_t> label;   // per vertex; kNone for a vertex no face uses
    std::vector<uint32_t> open;    // live border, pinch or locked vertices per component (0 = closed)
    std::vector<uint8_t> pruned;   // per component
    std::vector<double> size;      // half the box diagonal, model units
    std::vector<uint32_t> order;   // components, smallest size first
    std::vector<uint32_t> faces;   // live faces per component
    std::vector<uint32_t> vertexStart, vertices;  // compressed rows: vertices per component, input order
    size_t count() const { return open.size(); }
};

struct CollapseState {
    const TriMesh& mesh;   // positions and triangles, vertices renumbered (see renumberVertices)
    const TriMesh& input;  // the caller's mesh: corner wedges and materials
    std::vector<uint32_t> oldId;  // input id of each internal vertex id
    std::vector<uint32_t> newId;  // internal id of each input vertex
    size_t vertexCount = 0, faceCount = 0;
    double diagonal = 0, longestSide = 0;  // of the input's bounding box, model units

    FaceArray tri;                    // current corners (+ original normals)
    std::vector<Tri> wedge;           // current corner wedges (empty when the mesh has none)
    std::vector<uint8_t> faceAlive;
    bool oneMaterial = true;          // every face has the same material (or none)
    size_t aliveFaces = 0;
    std::vector<FaceList> vfaces;  // live faces around each vertex
    std::vector<uint8_t> locked, border, removed;
    std::vector<uint8_t> pinch;  // bow-tie vertices: several manifold fans meet at one point
    // Skinned input: the wedge of each vertex whose joints and weights it has (kNone: its wedges
    // bind differently); empty without influences.
    std::vector<uint32_t> influenceWedge;
    Components components;
    std::vector<Quadric> quadric;

    // Collapse hierarchy: the vertex each removed vertex collapsed into (kNone: pruned) and a face
    // its collapse kept (its region is the region V_i belongs to).
    std::vector<uint32_t> collapsedInto, keptFace;
    // The farthest removed point attached to each surviving vertex (kNone: none) and its distance
    // when last measured: the cost re-projects it.
    std::vector<uint32_t> farPoint;
    std::vector<float> farDist;
    // Removed points attached to each surviving vertex (intrusive lists spliced on collapse); only
    // read under an error target (measureAttached).
    std::vector<uint32_t> attachHead, attachTail, attachNext;

    // Scratch of applyCollapse (and its classifyFan).
    FanScratch classScratch;
    std::vector<uint32_t> fanScratch, ringScratch, keptScratch, removedScratch;

    CollapseState(const TriMesh& m, const TriMesh& in) : mesh(m), input(in) {}

    // Counted in Components::open: a live vertex on an open border, a pinch or a locked vertex.
    bool isOpen(uint32_t v) const { return border[v] || locked[v] || pinch[v]; }
    int corner(uint32_t f, uint32_t v) const {
        const Tri& t = tri[f];
        return t[0] == v ? 0 : (t[1] == v ? 1 : (t[2] == v ? 2 : -1));
    }
    // Materials are only compared with each other: with one material for all faces every face
    // reads -1 and the random read of the input's material array is skipped.
    int32_t material(uint32_t f) const {
        return !oneMaterial && f < input.triangleMaterial.size() ? input.triangleMaterial[f] : -1;
    }
    uint32_t componentOf(uint32_t v) const { return components.label[v]; }
};

// The visitor that records the simplification hierarchy as it happens: collapse records, region
// updates, and the running maximum of accepted deviations.
struct HierarchyRecorder {
    Multires out;
    double runningMax = 0;  // running max of recorded collapse deviations, model units
    double levelMax = 0;    // maxDeviation of the previous level

    uint32_t regionMark() const { return uint32_t(out.regionUpdates.size()); }
    void regionMoved(uint32_t from, uint32_t to) { out.regionUpdates.push_back({from, to}); }
    void collapsed(const CollapseRecord& c) { out.collapses.push_back(c); }
    void accepted(double deviation) { runningMax = std::max(runningMax, deviation); }
};

// Internal vertex ids in order of first use by the faces, unused vertices last (memory locality).
// Every tie-break compares input ids (oldId) and every output is mapped back (restoreInputIds),
// so the result is the same as without renumbering.
TriMesh renumberVertices(const TriMesh& mesh, std::vector<uint32_t>& oldId, std::vector<uint32_t>& newId);
// Maps every vertex id of the output back to the input's ids.
void restoreInputIds(const std::vector<uint32_t>& oldId, Multires& out);

// Live faces per vertex (a face that repeats a vertex is listed once), corners and wedges.
void buildAdjacency(CollapseState& s);
// Locked, pinch and border vertices (on up to `threads` threads); component labels and open-vertex
// counts.
void classifyVertices(CollapseState& s, int threads);
// Component sizes, face counts and vertex lists.
void measureComponents(CollapseState& s);
// Area-weighted plane quadrics per vertex, plus planes through open border edges.
void initQuadrics(CollapseState& s);

// The ring of v: each neighbour w once, in order of first appearance, with the faces of edge (v, w).
void collectRing(const CollapseState& s, uint32_t v, std::vector<RingEntry>& ring);
// Fans of v: fan[k] = fan id of the k-th face of vfaces[v], faces joined through shared spokes;
// ids are dense from 0 in order of first face. Returns the number of fans. ring: the ring of v.
uint32_t labelFans(const CollapseState& s, uint32_t v, const std::vector<RingEntry>& ring, std::vector<uint32_t>& fan);

// Moves every face of vi's fan to vj (removing those containing vj), updates adjacency, vertex
// classes around an open vi, quadrics, farthest points and attached points. `deviation` and
// `farDistance` are the collapse's cost and the distance of vi's farthest point to the new fan.
// Regions are not touched (regions.h updates them first, from the pre-collapse fan).
void applyCollapse(CollapseState& s, uint32_t vi, uint32_t vj, double deviation, float farDistance);

}  // namespace lodbake::simplify_detail
