// Regions per selected cell (thesis 2.4): union-find over manifold edges between faces of one
// cell, then each region's faces and its flatness (the cell error threshold's ingredient).
#include "agsphere/regions.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace lodbake::agsphere_detail {
namespace {

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

// Union-find roots: the smallest face of each region (unions always keep the smaller root).
std::vector<uint32_t> joinCellNeighbours(const Topology& t, const Cut& cut) {
    std::vector<uint32_t> parent(t.nf);
    std::iota(parent.begin(), parent.end(), 0u);
    std::vector<uint64_t> key(t.nf);
    for (uint32_t f = 0; f < t.nf; ++f) key[f] = cellKey(faceCell(t, cut, f));
    for (uint32_t f = 0; f < t.nf; ++f) {
        if (t.degenerate[f]) continue;
        for (uint32_t k = 0; k < 3; ++k) {
            uint32_t o = t.twin[3 * f + k];
            if (o >= kNonManifoldEdge) continue;
            uint32_t g = o / 3;
            if (g < f || key[g] != key[f] || t.isPinned(f) || t.isPinned(g)) continue;
            uint32_t a = findRoot(parent, f), b = findRoot(parent, g);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
    }
    return parent;
}

// Dense region ids in order of their smallest face, and each region's faces.
void numberRegions(const Topology& t, const Cut& cut, std::vector<uint32_t>& parent, Regions& r) {
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
}

// Largest distance of a region vertex to the region's plane; 0 for regions without area.
void measureFlatness(const Topology& t, Regions& r) {
    const uint32_t nr = r.count();
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
}

}  // namespace

Regions buildRegions(const Topology& t, const Cut& cut) {
    std::vector<uint32_t> parent = joinCellNeighbours(t, cut);
    Regions r;
    numberRegions(t, cut, parent, r);
    measureFlatness(t, r);
    return r;
}

}  // namespace lodbake::agsphere_detail
