// The mesh during simplification and the half-edge collapse (collapse_state.h, docs/simplify.md).

#include "collapse_state.h"

#include <numeric>

#include "lodbake/core/adjacency.h"
#include "lodbake/core/parallel.h"

namespace lodbake::simplify_detail {

constexpr size_t kClassifyChunk = 16384;  // vertices per classification chunk

// Inputs often list vertices far from the faces that use them (subdivided or re-indexed meshes:
// the three corners of a face hundreds of thousands of ids apart), and every per-vertex array is
// then read at random; numbering vertices in order of first use keeps each neighbourhood close.
TriMesh renumberVertices(const TriMesh& mesh, std::vector<uint32_t>& oldId, std::vector<uint32_t>& newId) {
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

void restoreInputIds(const std::vector<uint32_t>& id, Multires& out) {
    for (CollapseRecord& c : out.collapses) {
        c.removed = id[c.removed];
        c.kept = id[c.kept];
    }
    for (Level& l : out.levels) {
        for (Tri& t : l.triangles)
            for (uint32_t& v : t) v = id[v];
        for (SimplificationPair& p : l.pairs) {
            p.vertex = id[p.vertex];
            for (uint32_t& v : p.coarse) v = id[v];
        }
    }
}

// FaceLists rather than core/adjacency.h's vertexFaces: they shrink and grow as collapses happen,
// and list a face that repeats a vertex once.
void buildAdjacency(CollapseState& s) {
    const TriMesh& m = s.mesh;
    s.vertexCount = m.positions.size();
    s.faceCount = m.triangles.size();
    s.tri.rec.resize(m.triangles.size());
    for (size_t f = 0; f < m.triangles.size(); ++f) s.tri.rec[f] = {m.triangles[f], {0, 0, 0}};
    if (s.input.cornerWedges.size() == m.triangles.size()) s.wedge = s.input.cornerWedges;
    const std::vector<int32_t>& mat = s.input.triangleMaterial;
    const size_t withMat = std::min(mat.size(), m.triangles.size());
    // Faces past the material array read -1: one material only when that is also every listed one.
    const int32_t first = withMat ? mat[0] : -1;
    s.oneMaterial = (withMat == m.triangles.size() || first == -1) &&
                    std::all_of(mat.begin(), mat.begin() + ptrdiff_t(withMat), [&](int32_t x) { return x == first; });
    const Wedges& W = s.input.wedges;
    if (!s.wedge.empty() && W.joints.size() == W.size() && W.weights.size() == W.size()) {
        s.influenceWedge.assign(m.positions.size(), kNone - 1);  // kNone - 1: not seen yet
        auto same = [&](uint32_t a, uint32_t b) {
            const Vec4 &p = W.weights[a], &q = W.weights[b];
            return W.joints[a] == W.joints[b] && p.x == q.x && p.y == q.y && p.z == q.z && p.w == q.w;
        };
        for (size_t f = 0; f < m.triangles.size(); ++f)
            for (size_t k = 0; k < 3; ++k) {
                uint32_t& iw = s.influenceWedge[m.triangles[f][k]];
                const uint32_t w = s.wedge[f][k];
                if (iw == kNone - 1) iw = w;
                else if (iw != kNone && !same(iw, w)) iw = kNone;
            }
    }
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
    s.collapsedInto.assign(s.vertexCount, kNone);
    s.keptFace.assign(s.vertexCount, kNone);
    s.farPoint.assign(s.vertexCount, kNone);
    s.farDist.assign(s.vertexCount, 0.f);
    s.attachHead.assign(s.vertexCount, kNone);
    s.attachTail.assign(s.vertexCount, kNone);
    s.attachNext.assign(s.vertexCount, kNone);
}

static uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

// A vertex is manifold when every edge around it has one or two faces and its faces form one fan
// (connected through shared edges); a pinch (bow-tie) when its edges are manifold but its faces
// form several fans. Orientation is not required: two faces sharing an edge in the same direction
// (inconsistently wound neighbours) are a manifold edge like any other; every geometric test
// compares a face with its own normal. `open`: some edge around v has one face.
static FanKind classifyFan(const CollapseState& s, uint32_t v, FanScratch& scratch, bool& open) {
    const auto& fs = s.vfaces[v];
    size_t n = fs.size();
    std::vector<RingEntry>& ring = scratch.ring;
    std::vector<uint32_t>& faceCount = scratch.count;
    std::vector<uint32_t>& parent = scratch.parent;
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

void classifyVertices(CollapseState& s, int threads) {
    s.locked.assign(s.vertexCount, 0);
    s.pinch.assign(s.vertexCount, 0);
    s.border.assign(s.vertexCount, 0);
    s.removed.assign(s.vertexCount, 0);
    // Faces with a repeated corner: lock their vertices (they never move).
    for (const Tri& t : s.mesh.triangles)
        if (degenerateIndices(t))
            for (uint32_t v : t) s.locked[v] = 1;

    // Each fan is classified on its own (per-vertex results, per-thread scratch).
    std::vector<FanScratch> scratch(size_t(resolveThreads(threads)));
    parallelChunks(s.vertexCount, kClassifyChunk, threads, [&](size_t begin, size_t end, size_t t) {
        for (uint32_t v = uint32_t(begin); v < end; ++v) {
            if (s.vfaces[v].empty() || s.locked[v]) continue;
            bool open = false;
            FanKind k = classifyFan(s, v, scratch[t], open);
            s.locked[v] = k == FanKind::NonManifold;
            s.pinch[v] = k == FanKind::Pinch;
            s.border[v] = open;
        }
    });
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
    Components& c = s.components;
    c.label.assign(s.vertexCount, kNone);
    uint32_t count = 0;
    std::vector<uint32_t> label(s.vertexCount, kNone);
    for (uint32_t u = 0; u < s.vertexCount; ++u) {  // in input order: labels as without renumbering
        uint32_t v = s.newId[u];
        if (s.vfaces[v].empty()) continue;
        uint32_t r = findRoot(parent, v);
        if (label[r] == kNone) label[r] = count++;
        c.label[v] = label[r];
    }
    c.open.assign(count, 0);
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (c.label[v] != kNone && s.isOpen(v)) ++c.open[c.label[v]];
}

void measureComponents(CollapseState& s) {
    Components& c = s.components;
    size_t n = c.count();
    std::vector<Box3> box(n);
    const auto& P = s.mesh.positions;
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (c.label[v] != kNone) box[c.label[v]].extend(P[v]);
    c.size.assign(n, 0);
    c.pruned.assign(n, 0);
    c.faces.assign(n, 0);
    for (const Tri& t : s.mesh.triangles) ++c.faces[c.label[t[0]]];
    c.vertexStart.assign(n + 1, 0);
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (c.label[v] != kNone) ++c.vertexStart[c.label[v] + 1];
    for (size_t k = 0; k < n; ++k) c.vertexStart[k + 1] += c.vertexStart[k];
    c.vertices.resize(c.vertexStart[n]);
    std::vector<uint32_t> at(c.vertexStart.begin(), c.vertexStart.end() - 1);
    for (uint32_t u = 0; u < s.vertexCount; ++u) {  // in input order (pruning records)
        uint32_t v = s.newId[u];
        if (c.label[v] != kNone) c.vertices[at[c.label[v]]++] = v;
    }
    for (size_t k = 0; k < n; ++k) {
        c.size[k] = 0.5 * box[k].diagonal();
        c.order.push_back(uint32_t(k));
    }
    std::stable_sort(c.order.begin(), c.order.end(), [&](uint32_t a, uint32_t b) { return c.size[a] < c.size[b]; });
}

void initQuadrics(CollapseState& s) {
    s.quadric.assign(s.vertexCount, Quadric{});
    const auto& P = s.mesh.positions;
    for (uint32_t f = 0; f < s.faceCount; ++f) {
        const Tri& t = s.tri[f];
        Vec3 n = cross(P[t[1]] - P[t[0]], P[t[2]] - P[t[0]]);
        double l = length(n);
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

void collectRing(const CollapseState& s, uint32_t v, std::vector<RingEntry>& ring) {
    // Each neighbour w shares an edge (v, w) with one or two faces around a manifold vertex,
    // whatever their orientations (a non-manifold fan is locked and never evaluated; a third face
    // of an edge is ignored here).
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

uint32_t labelFans(const CollapseState& s, uint32_t v, const std::vector<RingEntry>& ring, std::vector<uint32_t>& fan) {
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

// The wedge a corner moving from vi to vj takes: the vj wedge of a removed face whose vi corner
// used the same wedge (same material first), else a vj wedge of the same material, else any.
static uint32_t chooseWedge(const CollapseState& s, uint32_t f, int c, uint32_t vi, uint32_t vj,
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

// A border collapse may close a three-vertex hole: re-classify the ring of the removed open vertex
// vi (fan: vi's faces before the collapse). Locks and pinches are sticky: a pinch whose fans got
// joined by later collapses still has fans that are only vertex-connected in the original mesh,
// and merging their regions through it would break region edge-connectivity.
static void reclassifyRing(CollapseState& s, uint32_t vi, const std::vector<uint32_t>& fan) {
    uint32_t comp = s.componentOf(vi);
    uint32_t& open = s.components.open[comp];
    --open;
    s.border[vi] = s.pinch[vi] = 0;
    std::vector<uint32_t>& ring = s.ringScratch;
    ring.clear();
    for (uint32_t f : fan)
        for (uint32_t u : s.tri[f])
            if (u != vi && !s.locked[u]) ring.push_back(u);
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    for (uint32_t u : ring) {
        if (s.vfaces[u].empty()) continue;
        bool wasOpen = s.isOpen(u), isOpen = false;
        FanKind k = classifyFan(s, u, s.classScratch, isOpen);
        s.locked[u] |= k == FanKind::NonManifold;
        s.pinch[u] |= k == FanKind::Pinch;
        s.border[u] = isOpen;
        if (s.isOpen(u) != wasOpen) {
            if (wasOpen) --open; else ++open;
        }
    }
}

void applyCollapse(CollapseState& s, uint32_t vi, uint32_t vj, double deviation, float farDistance) {
    std::vector<uint32_t>& fan = s.fanScratch;  // vi's faces before the collapse
    fan.assign(s.vfaces[vi].begin(), s.vfaces[vi].end());
    std::vector<uint32_t>& kept = s.keptScratch;
    std::vector<uint32_t>& removedFaces = s.removedScratch;
    kept.clear();
    removedFaces.clear();
    for (uint32_t f : fan) (s.corner(f, vj) >= 0 ? removedFaces : kept).push_back(f);

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
    if (s.isOpen(vi)) reclassifyRing(s, vi, fan);
    s.vfaces[vi].release();
    s.removed[vi] = 1;
    s.collapsedInto[vi] = vj;
    s.keptFace[vi] = kept.empty() ? kNone : kept.front();

    s.aliveFaces -= removedFaces.size();
    s.components.faces[s.componentOf(vi)] -= uint32_t(removedFaces.size());
    s.quadric[vj].add(s.quadric[vi]);
    // The farthest attached point of vj: vi itself, vi's farthest point or vj's own.
    // (Ties by input id; kNone ranks last.)
    auto key = [&](uint32_t v) { return v == kNone ? kNone : s.oldId[v]; };
    float farD = s.farDist[vj];
    uint32_t farP = s.farPoint[vj];
    auto offer = [&](float d, uint32_t p) {
        if (d > farD || (d == farD && key(p) > key(farP))) farD = d, farP = p;
    };
    offer(float(deviation), vi);
    if (s.farPoint[vi] != kNone) offer(farDistance, s.farPoint[vi]);
    s.farDist[vj] = farD;
    s.farPoint[vj] = farP;
    // vi and its attached points now hang under vj.
    s.attachNext[vi] = s.attachHead[vi];
    uint32_t tail = s.attachTail[vi] == kNone ? vi : s.attachTail[vi];
    s.attachNext[tail] = s.attachHead[vj];
    if (s.attachHead[vj] == kNone) s.attachTail[vj] = tail;
    s.attachHead[vj] = vi;
    s.attachHead[vi] = s.attachTail[vi] = kNone;
}

}  // namespace lodbake::simplify_detail
