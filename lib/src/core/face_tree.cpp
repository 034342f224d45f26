// Bounding-box tree over a face set (see face_tree.h).
//
// Why the answer is closestSurfacePoint's: a subtree is skipped only when its box is farther
// from p than the best distance found so far (plus a margin far above rounding, relative and at
// the faces' scale, as BoxedFaces uses); a box holds its faces, so every face as close as the
// true closest one is measured, with the same arithmetic as the scan. Among equal distances the
// earliest position in the set wins, which is the scan's "first strictly smaller" rule.
#include "lodbake/core/face_tree.h"

#include <algorithm>
#include <cmath>

#include "lodbake/core/closest_point.h"

namespace lodbake {
namespace {

constexpr uint32_t kLeafSize = 8;

std::array<double, 6> emptyBox() { return {1e300, 1e300, 1e300, -1e300, -1e300, -1e300}; }

void grow(std::array<double, 6>& b, const std::array<double, 6>& o) {
    for (size_t a = 0; a < 3; ++a) {
        b[a] = std::min(b[a], o[a]);
        b[a + 3] = std::max(b[a + 3], o[a + 3]);
    }
}

}  // namespace

FaceTree::FaceTree(const TriMesh& mesh, std::vector<uint32_t> faces) : mesh_(mesh), faces_(std::move(faces)) {
    box_.reserve(faces_.size());
    for (uint32_t f : faces_) {
        box_.push_back(faceBox(mesh, f));
        for (double v : box_.back()) extent_ = std::max(extent_, std::abs(v));
    }
    order_.resize(faces_.size());
    for (uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
    if (!faces_.empty()) {
        nodes_.reserve(2 * (faces_.size() / kLeafSize + 1));
        nodes_.push_back({});
        build(0, 0, uint32_t(faces_.size()));
    }
}

// Median split of the box centres along the longest axis of their spread; ties by position, so
// the tree is the same on every run (the answers do not depend on its shape anyway).
void FaceTree::build(uint32_t id, uint32_t begin, uint32_t end) {
    std::array<double, 6> box = emptyBox(), centres = emptyBox();
    for (uint32_t i = begin; i < end; ++i) {
        const auto& b = box_[order_[i]];
        grow(box, b);
        for (size_t a = 0; a < 3; ++a) {
            const double c = 0.5 * (b[a] + b[a + 3]);
            centres[a] = std::min(centres[a], c);
            centres[a + 3] = std::max(centres[a + 3], c);
        }
    }
    nodes_[id].box = box;
    if (end - begin <= kLeafSize) {
        nodes_[id].begin = begin;
        nodes_[id].end = end;
        return;
    }
    size_t axis = 0;
    for (size_t a = 1; a < 3; ++a)
        if (centres[a + 3] - centres[a] > centres[axis + 3] - centres[axis]) axis = a;
    const uint32_t mid = begin + (end - begin) / 2;
    std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](uint32_t x, uint32_t y) {
        const double cx = box_[x][axis] + box_[x][axis + 3], cy = box_[y][axis] + box_[y][axis + 3];
        return cx < cy || (cx == cy && x < y);
    });
    const uint32_t child = uint32_t(nodes_.size());
    nodes_[id].begin = nodes_[id].end = begin;
    nodes_[id].child = child;
    nodes_.resize(nodes_.size() + 2);  // the children sit side by side
    build(child, begin, mid);
    build(child + 1, mid, end);
}

double FaceTree::closest(Vec3 p, uint32_t& face, std::array<double, 3>& bary, uint32_t& hint) const {
    double best = 1e300;
    uint32_t bestPos = UINT32_MAX;
    // Boxes farther than this are skipped: the best distance with the margin.
    double bound = 1e300;
    auto tighten = [&] {
        const double r = std::sqrt(best) * (1 + 1e-9) + 1e-9 * extent_;
        bound = r * r;
    };
    auto measure = [&](uint32_t i) {
        const Tri& t = mesh_.triangles[faces_[i]];
        const auto b = closestOnTriangle(p, mesh_.positions[t[0]], mesh_.positions[t[1]], mesh_.positions[t[2]]);
        const Vec3 q = mesh_.positions[t[0]] * b[0] + mesh_.positions[t[1]] * b[1] + mesh_.positions[t[2]] * b[2];
        const double d = length2(q - p);
        if (d < best || (d == best && i < bestPos)) {
            best = d;
            bestPos = i;
            bary = b;
            tighten();
        }
    };
    if (nodes_.empty()) return best;
    // The hint is one candidate measured first: it only makes the bound tight from the start.
    if (hint < faces_.size()) measure(hint);
    struct Entry {
        uint32_t node;
        double d2;
    };
    Entry stack[128];
    size_t top = 0;
    stack[top++] = {0, boxDistance2(nodes_[0].box, p)};
    while (top > 0) {
        const Entry e = stack[--top];
        if (e.d2 > bound) continue;
        const Node& n = nodes_[e.node];
        if (n.end > n.begin) {
            for (uint32_t k = n.begin; k < n.end; ++k) {
                const uint32_t i = order_[k];
                if (i != bestPos && boxDistance2(box_[i], p) <= bound) measure(i);
            }
            continue;
        }
        // Nearer child on top of the stack: it is searched first and tightens the bound.
        const uint32_t a = n.child, c = n.child + 1;
        const double da = boxDistance2(nodes_[a].box, p), dc = boxDistance2(nodes_[c].box, p);
        if (da <= dc) {
            stack[top++] = {c, dc};
            stack[top++] = {a, da};
        } else {
            stack[top++] = {a, da};
            stack[top++] = {c, dc};
        }
    }
    if (bestPos == UINT32_MAX) return best;  // no face with a finite distance
    face = faces_[bestPos];
    hint = bestPos;
    return best;
}

}  // namespace lodbake
