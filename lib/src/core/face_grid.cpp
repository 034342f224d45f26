// Uniform grid of face bounding boxes (see face_grid.h).
#include "lodbake/core/face_grid.h"

#include <algorithm>
#include <cmath>

#include "lodbake/core/cell_lists.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/parallel.h"

namespace lodbake {

std::vector<uint32_t> indexedFaces(const TriMesh& mesh) {
    std::vector<uint32_t> out;
    out.reserve(mesh.triangleCount());
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f)
        if (!degenerateIndices(mesh.triangles[f])) out.push_back(f);
    return out;
}

FaceGrid::FaceGrid(const TriMesh& mesh, double cellsPerFace, int threads)
    : FaceGrid(mesh, indexedFaces(mesh), mesh.triangleCount(), cellsPerFace, threads) {}

FaceGrid::FaceGrid(const TriMesh& mesh, const std::vector<uint32_t>& faces, double cellsPerFace, int threads)
    : FaceGrid(mesh, faces, faces.size(), cellsPerFace, threads) {}

FaceGrid::FaceGrid(const TriMesh& mesh, const std::vector<uint32_t>& held, size_t nf, double cellsPerFace, int threads) {
    const Box3 box = bounds(mesh);
    boxes_.resize(mesh.triangleCount());
    constexpr size_t kChunk = 65536;
    parallelChunks(mesh.triangleCount(), kChunk, threads, [&](size_t begin, size_t end, size_t) {
        for (size_t f = begin; f < end; ++f) boxes_[f] = faceBox(mesh, uint32_t(f));
    });
    if (box.empty() || nf == 0) {
        start_.assign(2, 0);
        return;
    }
    origin_ = box.min;
    const Vec3 ext = box.max - box.min;
    // Cells of side cell_: about nf * cellsPerFace cells, at most 2^21 per axis.
    const double volume = std::max(ext.x, 1e-12) * std::max(ext.y, 1e-12) * std::max(ext.z, 1e-12);
    cell_ = std::cbrt(volume / std::max(1.0, double(nf) * cellsPerFace));
    cell_ = std::max({cell_, box.longestSide() / 2048.0, 1e-12});
    for (int a = 0; a < 3; ++a) n_[a] = std::max(1, int(std::ceil(ext[a] / cell_)));
    const size_t cells = size_t(n_[0]) * size_t(n_[1]) * size_t(n_[2]);
    auto forCells = [&](size_t i, auto&& fn) {
        const auto& b = boxes_[held[i]];
        int lo[3], hi[3];
        cellRange({b[0], b[1], b[2]}, {b[3], b[4], b[5]}, lo, hi);
        for (int z = lo[2]; z <= hi[2]; ++z)
            for (int y = lo[1]; y <= hi[1]; ++y)
                for (int x = lo[0]; x <= hi[0]; ++x) fn((size_t(z) * size_t(n_[1]) + size_t(y)) * size_t(n_[0]) + size_t(x));
    };
    fillCellLists(held.size(), cells, threads, forCells, [&](size_t i) { return held[i]; }, start_, faces_);
}

void FaceGrid::cellRange(Vec3 lo, Vec3 hi, int (&a)[3], int (&b)[3]) const {
    for (int k = 0; k < 3; ++k) {
        a[k] = std::clamp(int(std::floor((lo[k] - origin_[k]) / cell_)), 0, n_[k] - 1);
        b[k] = std::clamp(int(std::floor((hi[k] - origin_[k]) / cell_)), 0, n_[k] - 1);
    }
}

std::vector<uint32_t> FaceGrid::facesIn(Vec3 lo, Vec3 hi) const {
    std::vector<uint32_t> out;
    forEachFaceIn(lo, hi, [&](uint32_t f) { out.push_back(f); });
    std::sort(out.begin(), out.end());
    return out;
}

// The faces facesIn lists, each once; the scan's first strictly closer face in ascending ids is
// the least (distance, id) pair, whatever order they come in.
double FaceGrid::closestIn(const TriMesh& mesh, Vec3 lo, Vec3 hi, Vec3 p, uint32_t& face, std::array<double, 3>& bary,
                           bool& any) const {
    any = false;
    double best = 1e300;
    forEachFaceIn(lo, hi, [&](uint32_t f) {
        any = true;
        std::array<double, 3> w;
        const double d = faceDistance2(mesh, f, p, &w);
        if (d < best || (d == best && best < 1e300 && f < face)) {
            best = d;
            face = f;
            bary = w;
        }
    });
    return best;
}

size_t FaceGrid::entriesIn(Vec3 lo, Vec3 hi) const {
    if (faces_.empty()) return 0;
    int a[3], b[3];
    cellRange(lo, hi, a, b);
    size_t n = 0;
    for (int z = a[2]; z <= b[2]; ++z)
        for (int y = a[1]; y <= b[1]; ++y) {
            const size_t row = (size_t(z) * size_t(n_[1]) + size_t(y)) * size_t(n_[0]);
            n += start_[row + size_t(b[0]) + 1] - start_[row + size_t(a[0])];
        }
    return n;
}

// A box's grid entries beyond this many times the set's faces: the set is scanned instead (a
// face's distance costs several box tests).
constexpr size_t kScanRatio = 4;

// Every face at least as close as the best one found has its box within that distance of p, so
// inside the query box once the box reaches past it: the first closest by id among the box's
// faces is the first closest of the whole set.
bool closestFaceIn(const TriMesh& mesh, const FaceGrid& grid, const std::vector<uint32_t>& faces, Vec3 p, double radius,
                   size_t& index, std::array<double, 3>& bary) {
    auto distance2 = [&](uint32_t f, std::array<double, 3>& b) { return faceDistance2(mesh, f, p, &b); };
    if (faces.empty()) return false;
    const double scale = 1e-9 * (1 + std::abs(p.x) + std::abs(p.y) + std::abs(p.z));
    // Small sets, and a box still empty of them after 24 doublings, are scanned whole.
    double r = std::max(radius, scale);
    // The box's faces come in cell order: the least (distance, position) pair is the first closest
    // of an ascending scan.
    for (int grow = 0; grow < 24 && faces.size() > 64; ++grow, r *= 2) {
        // A box listing many more of the mesh's faces than the set holds (a point far from the
        // set, or a set of few faces) costs more than the scan of the set, which finds the same.
        if (grid.entriesIn(p - Vec3{r, r, r}, p + Vec3{r, r, r}) > kScanRatio * faces.size()) break;
        double best = 1e300;
        bool found = false;
        grid.forEachFaceIn(p - Vec3{r, r, r}, p + Vec3{r, r, r}, [&](uint32_t f) {
            auto it = std::lower_bound(faces.begin(), faces.end(), f);
            if (it == faces.end() || *it != f) return;
            const size_t i = size_t(it - faces.begin());
            std::array<double, 3> b;
            const double d = distance2(f, b);
            if (d < best || (found && d == best && i < index)) {
                best = d;
                index = i;
                bary = b;
                found = true;
            }
        });
        // Faces as close as the best have boxes within its distance of p: inside the box.
        if (found && std::sqrt(best) * (1 + 1e-6) + scale <= r) return true;
    }
    double best = 1e300;
    bool found = false;
    for (size_t i = 0; i < faces.size(); ++i) {
        std::array<double, 3> b;
        const double d = distance2(faces[i], b);
        if (d < best) {
            best = d;
            index = i;
            bary = b;
            found = true;
        }
    }
    return found;
}

double FaceSetSearch::closest(const std::vector<uint32_t>& faces, Vec3 p, uint32_t& face, std::array<double, 3>& bary) {
    double best = 1e300;
    if (faces.empty()) return best;
    std::call_once(gridBuilt_, [this] { grid_ = std::make_unique<FaceGrid>(mesh_, 1.0, threads_); });
    const std::vector<uint32_t>* degenerate = nullptr;  // a map's elements stay in place
    {
        const std::lock_guard<std::mutex> lock(degenerateMutex_);
        auto [it, added] = degenerate_.try_emplace(&faces);
        if (added)
            for (uint32_t f : faces)
                if (degenerateIndices(mesh_.triangles[f])) it->second.push_back(f);
        degenerate = &it->second;
    }
    size_t index = 0;
    std::array<double, 3> b{};
    const bool found = closestFaceIn(mesh_, *grid_, faces, p, grid_->cellSide(), index, b);
    if (found) {
        face = faces[index];
        bary = b;
        best = faceDistance2(mesh_, face, p, nullptr);
    }
    for (uint32_t f : *degenerate) {
        const double d = faceDistance2(mesh_, f, p, &b);
        if (d < best || (found && d == best && f < face)) {
            best = d;
            face = f;
            bary = b;
        }
    }
    return best;
}

}  // namespace lodbake
