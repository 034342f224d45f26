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

// A UV coordinate as glTF stores it (float), back in double. Not inlined: GCC 12's vectoriser
// (-O3) drops or misplaces some of these conversions when it merges them across corners.
[[gnu::noinline]] double asFloat(double x) { return double(float(x)); }

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
    UVFolds r;
    const size_t n = tris.size();
    r.flipped.assign(n, 0);
    if (n == 0) return r;
    // Per triangle, on the threads: the UVs rounded to float (checked as written: glTF stores float
    // UVs, and rounding can flip a sliver triangle), except the last corner of the last triangle of
    // an odd count, which the serial loop this replaces left as it was when built by GCC 12 at -O3
    // (its vectorised remainder rounds two corners of three): outputs stay byte-identical. Then the
    // flip and the box; the extent per chunk, reduced in chunk order (min and max keep the first of
    // equal values, as one pass over all the points does).
    std::vector<std::array<double, 4>> box(n);
    std::vector<std::array<Vec2, 2>> extent(chunkCount(n, kTrianglesPerChunk), {Vec2{1e300, 1e300}, Vec2{-1e300, -1e300}});
    parallelChunks(n, kTrianglesPerChunk, threads, [&](size_t begin, size_t end, size_t) {
        Vec2 lo = extent[begin / kTrianglesPerChunk][0], hi = extent[begin / kTrianglesPerChunk][1];
        for (size_t i = begin; i < end; ++i) {
            auto& t = tris[i];
            const size_t corners = i + 1 == n && n % 2 == 1 ? 2 : 3;
            for (size_t k = 0; k < corners; ++k) t[k] = {asFloat(t[k].x), asFloat(t[k].y)};
        }
        for (size_t i = begin; i < end; ++i) {
            const auto& t = tris[i];
            if (!(signedAreaGltf(t) > 0)) r.flipped[i] = 1;
            for (const Vec2& p : t) {
                lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
                hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
            }
            box[i] = {std::min({t[0].x, t[1].x, t[2].x}), std::min({t[0].y, t[1].y, t[2].y}), std::max({t[0].x, t[1].x, t[2].x}),
                      std::max({t[0].y, t[1].y, t[2].y})};
        }
        extent[begin / kTrianglesPerChunk] = {lo, hi};
    });
    Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
    for (const auto& e : extent) {
        lo = {std::min(lo.x, e[0].x), std::min(lo.y, e[0].y)};
        hi = {std::max(hi.x, e[1].x), std::max(hi.y, e[1].y)};
    }
    // Boxes of the unflipped triangles in a grid of about one cell per triangle: triangles whose
    // boxes meet share a cell.
    const int g = std::clamp(int(std::sqrt(double(n))), 1, 2048);
    std::vector<GridItem2> items;
    items.reserve(n);
    for (size_t i = 0; i < n; ++i)
        if (!r.flipped[i]) items.push_back({uint32_t(i), {box[i][0], box[i][1]}, {box[i][2], box[i][3]}});
    const Grid2 grid(lo, hi, g, g, items, threads);
    std::vector<GridItem2>().swap(items);  // the grid holds its own lists (freed before the axes: the peak)
    std::vector<EdgeAxes> axes(n);
    std::vector<uint8_t> axisMask(n, 0);
    parallelChunks(n, kTrianglesPerChunk, threads, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i)
            if (!r.flipped[i]) axisMask[i] = edgeAxes(tris[i], axes[i]);
    });
    // Boxes with a gap between them hold disjoint triangles, which one of the six edge axes
    // separates by that gap (more than the tolerance asks): the same pairs pass as without it.
    // A cell's boxes are gathered once (its pairs read them k - 1 times each), with the cell of
    // their lowest corner: cellX and cellY do not decrease with their argument, so the cell of the
    // lowest corner of two boxes' overlap (the larger of their lows) is the larger of their cells,
    // and a pair is tested in that cell only.
    struct Entry {
        std::array<double, 4> box;
        std::array<int32_t, 2> low;
        uint32_t id;
    };
    auto apart = [](const Entry& a, const Entry& b) {
        return a.box[2] < b.box[0] || b.box[2] < a.box[0] || a.box[3] < b.box[1] || b.box[3] < a.box[1];
    };
    std::vector<std::vector<std::pair<uint32_t, uint32_t>>> found(chunkCount(size_t(g), kRowsPerChunk));
    parallelChunks(size_t(g), kRowsPerChunk, threads, [&](size_t rowBegin, size_t rowEnd, size_t) {
        auto& out = found[rowBegin / kRowsPerChunk];
        auto test = [&](const Entry& a, const Entry& b, int x, int y) {
            if (std::max(a.low[0], b.low[0]) != x || std::max(a.low[1], b.low[1]) != y || apart(a, b)) return;
            const uint32_t i = std::min(a.id, b.id), j = std::max(a.id, b.id);
            if (interiorsOverlap(tris[i], axes[i], axisMask[i], tris[j], axes[j], axisMask[j], tolerance)) out.push_back({i, j});
        };
        std::vector<Entry> local;
        for (int y = int(rowBegin); y < int(rowEnd); ++y)
            for (int x = 0; x < g; ++x) {
                const Grid2::Cell cell = grid.cell(x, y);
                if (cell.size() < 2) continue;
                local.clear();
                for (uint32_t i : cell) local.push_back({box[i], {grid.cellX(box[i][0]), grid.cellY(box[i][1])}, i});
                if (cell.size() <= kSweepFrom) {
                    for (size_t a = 0; a < local.size(); ++a)
                        for (size_t b = a + 1; b < local.size(); ++b) test(local[a], local[b], x, y);
                    continue;
                }
                // A crowded cell (a chart laid out far denser than the grid assumes): swept along
                // x, each box meets only the boxes that start before it ends.
                std::sort(local.begin(), local.end(), [](const Entry& a, const Entry& b) {
                    return a.box[0] < b.box[0] || (a.box[0] == b.box[0] && a.id < b.id);
                });
                for (size_t a = 0; a < local.size(); ++a)
                    for (size_t b = a + 1; b < local.size() && local[b].box[0] <= local[a].box[2]; ++b) test(local[a], local[b], x, y);
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
