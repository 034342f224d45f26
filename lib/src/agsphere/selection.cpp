// Level selection on the sphere's quadtree (thesis 2.4.4: view- and light-dependent refinement).
//
//   measureDepth   per uniform depth: regions, simplified runs and the triangles each region's
//                  loops would make -> estimated triangles and error threshold per cell
//   classify       silhouette (orthogonal) cells of a view or light, reference cells facing a
//                  view, cells facing away from every light (or view) that stay coarsest, others
//   selectCut      default depths per class (relaxed when already above the target), then rounds
//                  of splitting leaves by class and error until the estimate reaches the target;
//                  the last split is undone when the count before it was closer
//   balanceCut     neighbouring cells at most two depths apart
#include "agsphere/selection.h"

#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "agsphere/boundary_runs.h"
#include "lodbake/core/math.h"

namespace lodbake::agsphere_detail {
namespace {

// Triangles the ear clipping of region i's kept loops makes (n + 2 h - 2 for n loop vertices and
// h holes); the region's face count when a loop is too short or the boundary walk fails.
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

struct Leaf {
    uint8_t depth;
    uint32_t cell;
    CellClass cls;
};

// The quadtree as the selection walks it.
struct Tree {
    const AgsphereOptions& o;
    const DepthTables& tables;
    int maxDepth;

    uint64_t estimate(const Leaf& l) const { return uint64_t(tables.estimate[l.depth][l.cell]); }
    uint64_t estimate(const std::vector<Leaf>& leaves) const {
        uint64_t sum = 0;
        for (const Leaf& l : leaves) sum += estimate(l);
        return sum;
    }
    std::array<Leaf, 4> children(const Leaf& l) const {
        std::array<Leaf, 4> ch;
        for (uint32_t k = 0; k < 4; ++k) {
            uint32_t c = l.cell * 4 + k;
            ch[k] = {uint8_t(l.depth + 1), c, classify(o, c, l.depth + 1)};
        }
        return ch;
    }
    // Default depths: silhouette cells two depths finer than reference cells, others one; `relax`
    // depths less each.
    int minDepth(CellClass c, int relax) const {
        if (o.views.empty() && o.lights.empty()) return 0;
        int base = c == CellClass::Orthogonal ? 2 : (c == CellClass::Other ? 1 : 0);
        return std::max(0, std::min(base - relax, maxDepth));
    }
};

// The leaves at the default depths. When they are already above the target, the offsets shrink
// (relax 1, then 2) so that the rounds can still trade reference detail for silhouette detail.
std::vector<Leaf> defaultLeaves(const Tree& tree, uint64_t target) {
    std::vector<Leaf> roots;
    for (uint32_t c = 0; c < 8; ++c) roots.push_back({0, c, classify(tree.o, c, 0)});
    std::vector<Leaf> leaves;
    for (int relax = 0; relax <= 2; ++relax) {
        leaves = roots;
        for (bool changed = true; changed;) {
            changed = false;
            std::vector<Leaf> next;
            for (const Leaf& l : leaves) {
                if (l.depth < tree.minDepth(l.cls, relax)) {
                    for (const Leaf& c : tree.children(l)) next.push_back(c);
                    changed = true;
                } else {
                    next.push_back(l);
                }
            }
            leaves = std::move(next);
        }
        if (tree.estimate(leaves) <= target) break;
    }
    return leaves;
}

// The most recent split: the estimate before it, the parent and its children.
struct LastSplit {
    bool any = false;
    uint64_t before = 0;
    Leaf parent{};
    std::array<Leaf, 4> children{};
};

// One pass over one class: splits its leaves (largest threshold first, then by cell) while the
// estimate `total` is below the target. Returns whether any leaf was split.
bool splitClass(const Tree& tree, CellClass cls, uint64_t target, std::vector<Leaf>& leaves, uint64_t& total,
                LastSplit& last) {
    std::vector<uint32_t> order;
    for (uint32_t i = 0; i < leaves.size(); ++i)
        if (leaves[i].cls == cls && leaves[i].depth < tree.maxDepth && tree.estimate(leaves[i]) > 0) order.push_back(i);
    std::stable_sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        float ta = tree.tables.threshold[leaves[a].depth][leaves[a].cell];
        float tb = tree.tables.threshold[leaves[b].depth][leaves[b].cell];
        if (ta != tb) return ta > tb;
        return cellKey({leaves[a].depth, leaves[a].cell}) < cellKey({leaves[b].depth, leaves[b].cell});
    });
    bool expanded = false;
    std::vector<Leaf> added;
    std::vector<char> gone(leaves.size(), 0);
    for (uint32_t i : order) {
        if (total >= target) break;
        last.before = total;
        auto ch = tree.children(leaves[i]);
        total -= tree.estimate(leaves[i]);
        for (const Leaf& c : ch) total += tree.estimate(c), added.push_back(c);
        gone[i] = 1;
        last.parent = leaves[i];
        last.children = ch;
        last.any = true;
        expanded = true;
    }
    std::vector<Leaf> next;
    for (uint32_t i = 0; i < leaves.size(); ++i)
        if (!gone[i]) next.push_back(leaves[i]);
    for (const Leaf& c : added) next.push_back(c);
    leaves = std::move(next);
    return expanded;
}

// Replaces the last split's children by their parent.
void undoSplit(const LastSplit& last, std::vector<Leaf>& leaves) {
    std::vector<Leaf> next;
    for (const Leaf& l : leaves) {
        bool isChild = false;
        for (const Leaf& c : last.children) isChild |= c.depth == l.depth && c.cell == l.cell;
        if (!isChild) next.push_back(l);
    }
    next.push_back(last.parent);
    leaves = std::move(next);
}

Cut cutOfLeaves(int maxDepth, const std::vector<Leaf>& leaves) {
    Cut cut(sphereCellCount(maxDepth), 0);
    for (const Leaf& l : leaves) {
        uint32_t span = finestSpan(maxDepth, l.depth);
        for (uint32_t z = l.cell * span; z < (l.cell + 1) * span; ++z) cut[z] = l.depth;
    }
    return cut;
}

}  // namespace

AgsphereDepthStats measureDepth(const Topology& t, int d, double boundaryTolerance, DepthTables& tables) {
    Cut cut(sphereCellCount(t.maxDepth), uint8_t(d));
    Regions r = buildRegions(t, cut);
    Runs R = buildBoundaryRuns(t, r, boundaryTolerance);
    auto& estimate = tables.estimate[size_t(d)];
    auto& threshold = tables.threshold[size_t(d)];
    estimate.assign(sphereCellCount(d), 0);
    threshold.assign(sphereCellCount(d), 0.f);
    AgsphereDepthStats st;
    st.depth = d;
    st.regions = r.count();
    for (uint32_t i = 0; i < r.count(); ++i) {
        uint64_t e = estimateRegionTriangles(t, r, R, i);
        estimate[r.cell[i].index] += uint32_t(e);
        float& th = threshold[r.cell[i].index];
        th = std::max(th, float(r.flatness[i]));
        st.estimatedTriangles += e;
        st.maxThreshold = std::max(st.maxThreshold, r.flatness[i]);
    }
    for (uint32_t c = 0; c < sphereCellCount(d); ++c) st.cells += estimate[c] > 0;
    return st;
}

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

void balanceCut(const Topology& t, const std::vector<std::array<uint32_t, 3>>& nb, Cut& cut) {
    const int D = t.maxDepth;
    for (bool changed = true; changed;) {
        changed = false;
        for (uint32_t x = 0; x < cut.size(); ++x)
            for (uint32_t y : nb[x]) {
                if (cut[y] <= cut[x] + 2) continue;
                uint8_t d = cut[x];
                uint32_t leaf = ancestorAt(x, D, d);
                uint32_t span = finestSpan(D, d);
                for (uint32_t z = leaf * span; z < (leaf + 1) * span; ++z) cut[z] = uint8_t(d + 1);
                changed = true;
            }
    }
}

Selection selectCut(const Topology& t, const AgsphereOptions& o, const DepthTables& tables, uint64_t target) {
    const Tree tree{o, tables, t.maxDepth};
    std::vector<Leaf> leaves = defaultLeaves(tree, target);
    uint64_t total = tree.estimate(leaves);
    Selection s;
    s.stopReason = "target";
    bool reached = total >= target;
    if (reached && total > target) s.stopReason = "coarsest cut";  // the sphere cannot go lower
    LastSplit last;
    last.before = total;
    while (!reached) {
        bool expanded = false;
        for (CellClass cls : {CellClass::Orthogonal, CellClass::Other, CellClass::Reference}) {
            expanded |= splitClass(tree, cls, target, leaves, total, last);
            if (total >= target) break;
        }
        if (total >= target) reached = true;
        if (!expanded) {
            s.stopReason = "finest depth";
            break;
        }
    }
    // The last split is undone when the count before it was closer to the target.
    if (reached && last.any && last.before < target && target - last.before < total - target) {
        undoSplit(last, leaves);
        total = last.before;
    }
    s.cut = cutOfLeaves(t.maxDepth, leaves);
    s.estimate = total;
    return s;
}

void countCutCells(const Topology& t, const AgsphereOptions& o, const Cut& cut, AgsphereLevelStats& st) {
    const int D = t.maxDepth;
    st.cellsPerDepth.assign(size_t(D) + 1, 0);
    std::unordered_set<uint64_t> seen;
    for (uint32_t z = 0; z < cut.size(); ++z) {
        uint8_t d = cut[z];
        uint32_t c = ancestorAt(z, D, d);
        if (!seen.insert(cellKey({d, c})).second) continue;
        ++st.cellsPerDepth[d];
        switch (classify(o, c, d)) {
            case CellClass::Orthogonal: ++st.orthogonalCells; break;
            case CellClass::Reference: ++st.referenceCells; break;
            case CellClass::Coarsest: ++st.coarsestCells; break;
            default: ++st.otherCells; break;
        }
    }
}

}  // namespace lodbake::agsphere_detail
