// A bounding-box tree over a fixed set of mesh faces, for many closest-point queries against the
// same set (an island's samples or texels): each query measures the faces near the point, not the
// whole set. The answer is exactly closestSurfacePoint's over the set in its order (the first of
// equally close faces), so swapping a linear scan for the tree changes no output.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

class FaceTree {
public:
    // `faces`: ids of faces of `mesh` (any order; ties go to the earlier one). The mesh must
    // outlive the tree.
    FaceTree(const TriMesh& mesh, std::vector<uint32_t> faces);
    // Squared distance from p to the closest point of the faces (1e300 when there are none);
    // `face` and `bary` receive that point, as closestSurfacePoint gives it.
    double closest(Vec3 p, uint32_t& face, std::array<double, 3>& bary) const {
        uint32_t hint = UINT32_MAX;
        return closest(p, face, bary, hint);
    }
    // The same, starting from the face at position `hint` in the set (a nearby query's answer;
    // any value past the set for none), which only speeds the search; `hint` receives the
    // answer's position for the next query.
    double closest(Vec3 p, uint32_t& face, std::array<double, 3>& bary, uint32_t& hint) const;
    size_t size() const { return faces_.size(); }

private:
    struct Node {
        std::array<double, 6> box;  // min x y z, max x y z of its faces' boxes
        uint32_t begin = 0, end = 0;  // leaf: positions order_[begin, end); inner: end == begin
        uint32_t child = 0;           // inner: children child and child + 1
    };
    const TriMesh& mesh_;
    std::vector<uint32_t> faces_;
    std::vector<std::array<double, 6>> box_;  // per position in faces_
    std::vector<uint32_t> order_;             // positions in faces_, grouped by leaf
    std::vector<Node> nodes_;
    double extent_ = 0;  // largest |coordinate| of the faces
    void build(uint32_t id, uint32_t begin, uint32_t end);
};

}  // namespace lodbake
