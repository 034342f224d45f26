// A uniform grid over a mesh's triangles by their bounding boxes, for "which faces lie near this
// box" queries (pack's projection bake asks it once per level triangle), and the closest face of a
// subset of the faces (parameterize's level-corner projections).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

// Every face of the mesh that is not index-degenerate (the faces a FaceGrid can list), ascending.
std::vector<uint32_t> indexedFaces(const TriMesh& mesh);

class FaceGrid {
public:
    // About `cellsPerFace` cells per face over the mesh's bounding box (degenerate faces skipped),
    // built on `threads` threads (0 = all cores; the same grid for any count).
    explicit FaceGrid(const TriMesh& mesh, double cellsPerFace = 1.0, int threads = 1);
    // Only `faces` (ascending ids, none index-degenerate), about `cellsPerFace` cells per listed
    // face; the boxes span the whole mesh's bounding box.
    FaceGrid(const TriMesh& mesh, const std::vector<uint32_t>& faces, double cellsPerFace = 1.0, int threads = 1);
    // Ids of every face whose bounding box overlaps box [lo, hi], ascending.
    std::vector<uint32_t> facesIn(Vec3 lo, Vec3 hi) const;
    // visit(f) once for every face facesIn(lo, hi) lists, in cell order (not ascending): for
    // callers whose answer does not depend on the order, without the list's allocation and sort.
    template <class Visit>
    void forEachFaceIn(Vec3 lo, Vec3 hi, Visit&& visit) const;
    // closestSurfacePoint(mesh, facesIn(lo, hi), p, face, bary) without the list (mesh: the one the
    // grid was built over): the squared distance to the first closest face by id, 1e300 when none
    // is at a finite distance; `any` tells whether the box holds a face at all.
    double closestIn(const TriMesh& mesh, Vec3 lo, Vec3 hi, Vec3 p, uint32_t& face, std::array<double, 3>& bary, bool& any) const;
    // The cell entries facesIn(lo, hi) scans (a face counts once per cell it is listed in): its
    // cost, found in time proportional to the cells of the box.
    size_t entriesIn(Vec3 lo, Vec3 hi) const;
    // The cells' side: about a face's size.
    double cellSide() const { return cell_; }

private:
    Vec3 origin_{};
    double cell_ = 1;
    int n_[3] = {1, 1, 1};
    std::vector<uint32_t> start_;  // CSR: cell c holds faces_[start_[c] .. start_[c + 1])
    std::vector<uint32_t> faces_;
    std::vector<std::array<double, 6>> boxes_;
    // The faces `held` listed, with cells sized for `nf` faces.
    FaceGrid(const TriMesh& mesh, const std::vector<uint32_t>& held, size_t nf, double cellsPerFace, int threads);
    void cellRange(Vec3 lo, Vec3 hi, int (&a)[3], int (&b)[3]) const;
};

// A face listed in several cells of the range is visited in one of them only: the first cell of
// the range it is listed in (its own first cell on each axis, or the range's when that lies below),
// so no deduplication is needed. The face's first cell is found as the build found it (cellRange
// of its box), and only off the range's first row, column or layer.
template <class Visit>
void FaceGrid::forEachFaceIn(Vec3 lo, Vec3 hi, Visit&& visit) const {
    if (faces_.empty()) return;
    int a[3], b[3];
    cellRange(lo, hi, a, b);
    auto firstCell = [&](const std::array<double, 6>& bx, int axis) {
        return std::clamp(int(std::floor((bx[size_t(axis)] - origin_[axis]) / cell_)), 0, n_[axis] - 1);
    };
    for (int z = a[2]; z <= b[2]; ++z)
        for (int y = a[1]; y <= b[1]; ++y)
            for (int x = a[0]; x <= b[0]; ++x) {
                const size_t c = (size_t(z) * size_t(n_[1]) + size_t(y)) * size_t(n_[0]) + size_t(x);
                for (uint32_t i = start_[c]; i < start_[c + 1]; ++i) {
                    const uint32_t f = faces_[i];
                    const auto& bx = boxes_[f];
                    if (!(bx[0] <= hi.x && bx[3] >= lo.x && bx[1] <= hi.y && bx[4] >= lo.y && bx[2] <= hi.z && bx[5] >= lo.z)) continue;
                    if ((x != a[0] && firstCell(bx, 0) != x) || (y != a[1] && firstCell(bx, 1) != y) ||
                        (z != a[2] && firstCell(bx, 2) != z))
                        continue;
                    visit(f);
                }
            }
}

// The point of `faces` (ascending ids, none index-degenerate) closest to p, exactly as
// closestSurfacePoint's scan of `faces` in order finds it (the first of equally close faces): its
// position in `faces` and its barycentrics; false when `faces` is empty. Only the faces of the
// set in a box around p are measured, looked up in `grid` (built over `mesh`, whose faces these
// are): the box grows from half-side `radius` (a face's usual size is a good start) until it holds
// a face of the set no farther than the box reaches. Cost: the faces near p, not the set's size.
bool closestFaceIn(const TriMesh& mesh, const FaceGrid& grid, const std::vector<uint32_t>& faces, Vec3 p, double radius,
                   size_t& index, std::array<double, 3>& bary);

// closestSurfacePoint's scan of fixed face sets (ascending ids, index-degenerate faces allowed)
// for many points, each point measuring only the faces near it: closestFaceIn over the faces the
// grid lists, and a set's index-degenerate faces (the grid lists none) measured beside them, ties
// to the lower id as the scan breaks them. The grid is built over the mesh on the first query.
// Threads may query one search at once.
class FaceSetSearch {
public:
    // `threads` build the grid.
    explicit FaceSetSearch(const TriMesh& mesh, int threads = 1) : mesh_(mesh), threads_(threads) {}
    // The squared distance to the closest point of `faces` (1e300 when none); `face` and `bary`
    // receive it. A set is known by its address: it stays in place while the search lives.
    double closest(const std::vector<uint32_t>& faces, Vec3 p, uint32_t& face, std::array<double, 3>& bary);
    // The texture coordinate of the closest point of `faces`, interpolated from the faces'
    // per-corner UVs (cornerUV[f][k]); {0, 0} when faces is empty.
    Vec2 closestUV(const std::vector<std::array<Vec2, 3>>& cornerUV, const std::vector<uint32_t>& faces, Vec3 p) {
        uint32_t f = 0;
        std::array<double, 3> b{};
        if (closest(faces, p, f, b) >= 1e300) return {};
        return cornerUV[f][0] * b[0] + cornerUV[f][1] * b[1] + cornerUV[f][2] * b[2];
    }

private:
    const TriMesh& mesh_;
    int threads_ = 1;
    std::once_flag gridBuilt_;
    std::unique_ptr<FaceGrid> grid_;
    std::mutex degenerateMutex_;
    std::map<const std::vector<uint32_t>*, std::vector<uint32_t>> degenerate_;  // per set asked for
};

}  // namespace lodbake
