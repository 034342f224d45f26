// Injectivity check of UV triangles in one atlas (used for every level of a parameterized chain):
// flipped triangles (signed UV area <= 0 relative to the atlas orientation) and triangles whose
// UV interior overlaps another triangle's interior (uniform-grid broad phase, separating-axis
// narrow phase with a tolerance so that triangles sharing an edge or a vertex do not count).
#include <algorithm>
#include <cmath>

#include "lodbake/core/grid2d.h"
#include "lodbake/param/parameterize.h"
#include "param/uv_check_detail.h"

namespace lodbake {
namespace {

// Signed area in math orientation (u right, v up) of a triangle given in glTF UVs (v down).
double signedAreaGltf(const std::array<Vec2, 3>& t) {
    return signedArea({t[0].x, -t[0].y}, {t[1].x, -t[1].y}, {t[2].x, -t[2].y});
}

// True when the projections of a and b on the axes of both triangles' edges all overlap by more
// than a tolerance (interiors intersect). Both triangles are non-degenerate.
bool interiorsOverlap(const std::array<Vec2, 3>& a, const std::array<Vec2, 3>& b, double eps) {
    for (const auto* t : {&a, &b})
        for (int k = 0; k < 3; ++k) {
            Vec2 e = (*t)[size_t((k + 1) % 3)] - (*t)[size_t(k)];
            Vec2 n{-e.y, e.x};
            double len = std::sqrt(dot(n, n));
            if (!(len > 0)) continue;
            n = n * (1.0 / len);
            double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
            for (const Vec2& p : a) { double d = dot(n, p); amin = std::min(amin, d); amax = std::max(amax, d); }
            for (const Vec2& p : b) { double d = dot(n, p); bmin = std::min(bmin, d); bmax = std::max(bmax, d); }
            if (amax <= bmin + eps || bmax <= amin + eps) return false;
        }
    return true;
}

}  // namespace

namespace param_detail {

UVFolds findUVFolds(const std::vector<std::array<Vec2, 3>>& input, double tolerance) {
    // Checked as written: glTF stores float UVs, and rounding can flip a sliver triangle.
    std::vector<std::array<Vec2, 3>> tris(input);
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
    auto apart = [&](uint32_t i, uint32_t j) {
        const auto &a = box[i], &b = box[j];
        return a[2] < b[0] || b[2] < a[0] || a[3] < b[1] || b[3] < a[1];
    };
    // A pair is listed in every cell both its triangles are listed in, a block of cells starting at
    // the larger of their first columns and rows; it is tested in that first cell only. Within a
    // cell the boxes are swept by their low x: a box starting past another's high x, and every
    // box after it, is apart from that one. Each pair meeting in a cell is found whatever the
    // order, and the list is sorted below.
    auto ownCell = [&](uint32_t i, uint32_t j, int x, int y) {
        const auto &a = box[i], &b = box[j];
        return std::max(grid.cellX(a[0]), grid.cellX(b[0])) == x && std::max(grid.cellY(a[1]), grid.cellY(b[1])) == y;
    };
    std::vector<uint32_t> sweep;
    for (int y = 0; y < g; ++y)
        for (int x = 0; x < g; ++x) {
            const Grid2::Cell cell = grid.cell(x, y);
            sweep.assign(cell.begin(), cell.end());
            std::sort(sweep.begin(), sweep.end(), [&](uint32_t a, uint32_t b) { return box[a][0] < box[b][0] || (box[a][0] == box[b][0] && a < b); });
            for (size_t ia = 0; ia < sweep.size(); ++ia)
                for (size_t ib = ia + 1; ib < sweep.size() && !(box[sweep[ia]][2] < box[sweep[ib]][0]); ++ib) {
                    uint32_t i = std::min(sweep[ia], sweep[ib]), j = std::max(sweep[ia], sweep[ib]);
                    if (!apart(i, j) && ownCell(i, j, x, y) && interiorsOverlap(tris[i], tris[j], tolerance))
                        r.overlapping.push_back({i, j});
                }
        }
    std::sort(r.overlapping.begin(), r.overlapping.end());
    r.overlapping.erase(std::unique(r.overlapping.begin(), r.overlapping.end()), r.overlapping.end());
    return r;
}

}  // namespace param_detail

UVInjectivity checkUVInjectivity(const std::vector<std::array<Vec2, 3>>& tris, double tolerance) {
    param_detail::UVFolds f = param_detail::findUVFolds(tris, tolerance);
    UVInjectivity r;
    r.triangles = tris.size();
    r.flips = size_t(std::count(f.flipped.begin(), f.flipped.end(), 1));
    std::vector<char> bad(tris.size(), 0);
    for (const auto& [i, j] : f.overlapping) bad[i] = bad[j] = 1;
    r.overlaps = size_t(std::count(bad.begin(), bad.end(), 1));
    return r;
}

UVInjectivity checkLevelUVs(const TriMesh& mesh, const std::vector<Tri>& triangles, const std::vector<Tri>& cornerWedges,
                            double tolerance) {
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
    return checkUVInjectivity(tris, tolerance);
}

}  // namespace lodbake
