// Injectivity check of UV triangles in one atlas (used for every level of a parameterized chain):
// flipped triangles (signed UV area <= 0 relative to the atlas orientation) and triangles whose
// UV interior overlaps another triangle's interior (uniform-grid broad phase, separating-axis
// narrow phase with a tolerance so that triangles sharing an edge or a vertex do not count).
#include <algorithm>
#include <cmath>
#include <utility>

#include "lodbake/core/grid2d.h"
#include "lodbake/core/parallel.h"
#include "lodbake/param/parameterize.h"
#include "param/uv_check_detail.h"

namespace lodbake {
namespace {

// Signed area in math orientation (u right, v up) of a triangle given in glTF UVs (v down).
double signedAreaGltf(const std::array<Vec2, 3>& t) {
    return signedArea({t[0].x, -t[0].y}, {t[1].x, -t[1].y}, {t[2].x, -t[2].y});
}

// A triangle's three edge axes as the overlap test takes them: the edge's normal scaled to unit
// length, a zero-length edge giving no axis (bit k of the mask). Computed once per triangle with
// the same operations in the same order as a test of any pair would, so every pair test sees the
// same bits; the projections are cheap next to the square root and stay per pair.
using EdgeAxes = std::array<Vec2, 3>;

uint8_t edgeAxes(const std::array<Vec2, 3>& t, EdgeAxes& axes) {
    uint8_t mask = 0;
    for (int k = 0; k < 3; ++k) {
        Vec2 e = t[size_t((k + 1) % 3)] - t[size_t(k)];
        Vec2 n{-e.y, e.x};
        double len = std::sqrt(dot(n, n));
        if (!(len > 0)) continue;
        axes[size_t(k)] = n * (1.0 / len);
        mask = uint8_t(mask | (1u << k));
    }
    return mask;
}

// True when the projections of a and b on the axes of both triangles' edges all overlap by more
// than a tolerance (interiors intersect). Both triangles are non-degenerate.
bool interiorsOverlap(const std::array<Vec2, 3>& a, const EdgeAxes& axA, uint8_t maskA, const std::array<Vec2, 3>& b,
                      const EdgeAxes& axB, uint8_t maskB, double eps) {
    for (int side = 0; side < 2; ++side)
        for (int k = 0; k < 3; ++k) {
            if (!((side == 0 ? maskA : maskB) >> k & 1u)) continue;
            const Vec2 n = (side == 0 ? axA : axB)[size_t(k)];
            double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
            for (const Vec2& p : a) { double d = dot(n, p); amin = std::min(amin, d); amax = std::max(amax, d); }
            for (const Vec2& p : b) { double d = dot(n, p); bmin = std::min(bmin, d); bmax = std::max(bmax, d); }
            if (amax <= bmin + eps || bmax <= amin + eps) return false;
        }
    return true;
}

}  // namespace

namespace param_detail {

// Cells with more items than this are swept instead of testing every pair.
constexpr size_t kSweepFrom = 32;
// Grid rows per parallel task.
constexpr size_t kRowsPerChunk = 16;
// Triangles per parallel task of the per-triangle tables.
constexpr size_t kTrianglesPerChunk = 1 << 14;

UVFolds findUVFolds(std::vector<std::array<Vec2, 3>> tris, double tolerance, int threads) {
    // Checked as written: glTF stores float UVs, and rounding can flip a sliver triangle.
    for (auto& t : tris)
        for (Vec2& p : t) p = {double(float(p.x)), double(float(p.y))};
    UVFolds r;
    const size_t n = tris.size();
    r.flipped.assign(n, 0);
    if (n == 0) return r;
    Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
    for (size_t i = 0; i < n; ++i) {
        if (!(signedAreaGltf(tris[i]) > 0)) r.flipped[i] = 1;
        for (const Vec2& p : tris[i]) {
            lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
            hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
        }
    }
    // Boxes of the unflipped triangles in a grid of about one cell per triangle: triangles whose
    // boxes meet share a cell.
    std::vector<GridItem2> items;
    for (size_t i = 0; i < n; ++i) {
        if (r.flipped[i]) continue;
        const auto& t = tris[i];
        items.push_back({uint32_t(i), {std::min({t[0].x, t[1].x, t[2].x}), std::min({t[0].y, t[1].y, t[2].y})},
                         {std::max({t[0].x, t[1].x, t[2].x}), std::max({t[0].y, t[1].y, t[2].y})}});
    }
    const int g = std::clamp(int(std::sqrt(double(n))), 1, 2048);
    const Grid2 grid(lo, hi, g, g, items);
    // Boxes with a gap between them hold disjoint triangles, which one of the six edge axes
    // separates by that gap (more than the tolerance asks): the same pairs pass as without it.
    std::vector<std::array<double, 4>> box(n);
    for (size_t i = 0; i < n; ++i) {
        const auto& t = tris[i];
        box[i] = {std::min({t[0].x, t[1].x, t[2].x}), std::min({t[0].y, t[1].y, t[2].y}), std::max({t[0].x, t[1].x, t[2].x}),
                  std::max({t[0].y, t[1].y, t[2].y})};
    }
    std::vector<GridItem2>().swap(items);  // the grid holds its own lists
    std::vector<EdgeAxes> axes(n);
    std::vector<uint8_t> axisMask(n, 0);
    parallelChunks(n, kTrianglesPerChunk, threads, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i)
            if (!r.flipped[i]) axisMask[i] = edgeAxes(tris[i], axes[i]);
    });
    auto apart = [&](uint32_t i, uint32_t j) {
        const auto &a = box[i], &b = box[j];
        return a[2] < b[0] || b[2] < a[0] || a[3] < b[1] || b[3] < a[1];
    };
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> found(chunkCount(size_t(g), kRowsPerChunk));
    parallelChunks(size_t(g), kRowsPerChunk, threads, [&](size_t rowBegin, size_t rowEnd, size_t) {
        auto& out = found[rowBegin / kRowsPerChunk];
        // Two meeting boxes share every cell from the one holding their overlap's lowest corner;
        // the pair is tested in that cell only.
        auto test = [&](uint32_t a, uint32_t b, int x, int y) {
            const uint32_t i = std::min(a, b), j = std::max(a, b);
            if (apart(i, j) || grid.cellX(std::max(box[i][0], box[j][0])) != x || grid.cellY(std::max(box[i][1], box[j][1])) != y)
                return;
            if (interiorsOverlap(tris[i], axes[i], axisMask[i], tris[j], axes[j], axisMask[j], tolerance)) out.push_back({i, j});
        };
        std::vector<uint32_t> byX;
        for (int y = int(rowBegin); y < int(rowEnd); ++y)
            for (int x = 0; x < g; ++x) {
                const Grid2::Cell cell = grid.cell(x, y);
                if (cell.size() <= kSweepFrom) {
                    for (const uint32_t* a = cell.begin(); a != cell.end(); ++a)
                        for (const uint32_t* b = a + 1; b != cell.end(); ++b) test(*a, *b, x, y);
                    continue;
                }
                // A crowded cell (a chart laid out far denser than the grid assumes): swept along
                // x, each box meets only the boxes that start before it ends.
                byX.assign(cell.begin(), cell.end());
                std::sort(byX.begin(), byX.end(),
                          [&](uint32_t a, uint32_t b) { return box[a][0] < box[b][0] || (box[a][0] == box[b][0] && a < b); });
                for (size_t a = 0; a < byX.size(); ++a)
                    for (size_t b = a + 1; b < byX.size() && box[byX[b]][0] <= box[byX[a]][2]; ++b) test(byX[a], byX[b], x, y);
            }
    });
    for (const auto& f : found) r.overlapping.insert(r.overlapping.end(), f.begin(), f.end());
    std::sort(r.overlapping.begin(), r.overlapping.end());
    r.overlapping.erase(std::unique(r.overlapping.begin(), r.overlapping.end()), r.overlapping.end());
    return r;
}

}  // namespace param_detail

UVInjectivity checkUVInjectivity(const std::vector<std::array<Vec2, 3>>& tris, double tolerance, int threads) {
    return checkUVInjectivity(std::vector<std::array<Vec2, 3>>(tris), tolerance, threads);
}

UVInjectivity checkUVInjectivity(std::vector<std::array<Vec2, 3>>&& tris, double tolerance, int threads) {
    const size_t n = tris.size();
    param_detail::UVFolds f = param_detail::findUVFolds(std::move(tris), tolerance, threads);
    UVInjectivity r;
    r.triangles = n;
    r.flips = size_t(std::count(f.flipped.begin(), f.flipped.end(), 1));
    std::vector<char> bad(n, 0);
    for (const auto& [i, j] : f.overlapping) bad[i] = bad[j] = 1;
    r.overlaps = size_t(std::count(bad.begin(), bad.end(), 1));
    return r;
}

UVInjectivity checkLevelUVs(const TriMesh& mesh, const std::vector<Tri>& triangles, const std::vector<Tri>& cornerWedges,
                            double tolerance, int threads) {
    std::vector<std::array<Vec2, 3>> tris;
    tris.reserve(triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t) {
        const Tri& v = triangles[t];
        if (degenerateIndices(v)) continue;
        std::array<Vec2, 3> uv{};
        for (size_t k = 0; k < 3; ++k) {
            uint32_t w = t < cornerWedges.size() ? cornerWedges[t][k] : UINT32_MAX;
            uv[k] = w < mesh.wedges.uv0.size() ? mesh.wedges.uv0[w] : Vec2{};
        }
        tris.push_back(uv);
    }
    return checkUVInjectivity(std::move(tris), tolerance, threads);
}

}  // namespace lodbake
