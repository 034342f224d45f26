// Texel coverage of UV triangles: which texels of the baked region a triangle reaches (its texel
// centres within a dilation margin), and for each texel the nearest original face and the
// barycentrics of its closest point. Every later step of the bake reads a texel through this hit.
#pragma once

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdint>
#include <vector>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/math.h"
#include "lodbake/core/mesh.h"

namespace lodbake::bake_detail {

// What a texel shows: the original face and the barycentrics of the point it reads.
struct TexelHit {
    int32_t face = -1;
    float dist = 1e30f;
    std::array<float, 3> bary{};
    int32_t island = -1;  // >= 0: the texel belongs to this island; face/bary = the closest original point
    std::array<float, 2> beyond{};  // texel centre minus the closest point (dilated texels), texels
};

// The baked region: texels [0, w) x [0, h) of the size x size texture cornerUV is scaled to. A
// dense raster of texels, not a bucket grid of items (that is core/grid2d.h).
struct TexelRegion {
    int size, w, h;
    size_t at(int x, int y) const { return size_t(y) * size_t(w) + size_t(x); }
};

// The rasterisers run in bands of kRasterRows page rows on their threads, each band's texels
// written by the triangles in order (the same hits for any thread count).
constexpr size_t kRasterRows = 64;

// Whether triangle P (texel units), dilated by `dilation`, lies off rows [rowBegin, rowEnd) (with
// a texel to spare: forEachTexelNear clips to the band exactly).
inline bool offBand(const Vec2 (&P)[3], double dilation, size_t rowBegin, size_t rowEnd) {
    return std::max({P[0].y, P[1].y, P[2].y}) + dilation < double(rowBegin) - 1 ||
           std::min({P[0].y, P[1].y, P[2].y}) - dilation > double(rowEnd) + 1;
}

// The texels [x0, x1] x [y0, y1] of the region (rows [rowBegin, rowEnd) of it) that hold every
// texel centre within `dilation` texels of triangle P (texel units); empty when x0 > x1 or y0 > y1.
struct TexelBox {
    int x0, x1, y0, y1;
};
inline TexelBox texelBox(const Vec2 (&P)[3], const TexelRegion& g, double dilation, int rowBegin = 0, int rowEnd = INT_MAX) {
    double x0 = std::min({P[0].x, P[1].x, P[2].x}) - dilation, x1 = std::max({P[0].x, P[1].x, P[2].x}) + dilation;
    double y0 = std::min({P[0].y, P[1].y, P[2].y}) - dilation, y1 = std::max({P[0].y, P[1].y, P[2].y}) + dilation;
    return {std::max(0, int(std::floor(x0))), std::min(g.w - 1, int(std::ceil(x1))), std::max(rowBegin, int(std::floor(y0))),
            std::min({g.h - 1, rowEnd - 1, int(std::ceil(y1))})};
}

// Calls fn(x, y, d, bary) for every texel of the region (rows [rowBegin, rowEnd) of it)
// whose centre lies within `dilation` texels of triangle P (texel units) and for which skip(x, y)
// is false (skip: a texel fn would leave as it is, not measured); bary: of the closest point of P
// (core/closest_point.h). Inline: it is the rasterisers' inner loop.
template <class Fn, class Skip>
void forEachTexelNear(const Vec2 (&P)[3], const TexelRegion& g, double dilation, Fn&& fn, int rowBegin, int rowEnd, Skip&& skip) {
    const TexelBox box = texelBox(P, g, dilation, rowBegin, rowEnd);
    const std::array<Vec2, 3> tri{P[0], P[1], P[2]};
    for (int y = box.y0; y <= box.y1; ++y)
        for (int x = box.x0; x <= box.x1; ++x) {
            if (skip(x, y)) continue;
            std::array<double, 3> b{};
            double d = std::sqrt(closestOnTriangle(Vec2{x + 0.5, y + 0.5}, tri, b));
            if (d <= dilation) fn(x, y, d, b);
        }
}

template <class Fn>
void forEachTexelNear(const Vec2 (&P)[3], const TexelRegion& g, double dilation, Fn&& fn, int rowBegin = 0, int rowEnd = INT_MAX) {
    forEachTexelNear(P, g, dilation, fn, rowBegin, rowEnd, [](int, int) { return false; });
}

// A lower bound on the distance from a point to triangle P (texel units, not degenerate): how far
// the point lies outside the farthest of the triangle's edge lines (the triangle lies inside each
// edge's half-plane), less a slack far above the rounding of that distance and of
// closestOnTriangle's (both about 1e-12 texel on pages of a few thousand texels).
class EdgeDistanceBound {
public:
    explicit EdgeDistanceBound(const Vec2 (&P)[3]) {
        const double side = cross(P[1] - P[0], P[2] - P[0]) > 0 ? 1.0 : -1.0;
        for (size_t k = 0; k < 3; ++k) {
            const Vec2 e = P[(k + 1) % 3] - P[k];
            const double l = std::sqrt(dot(e, e));
            a_[k] = P[k];
            n_[k] = l > 0 ? Vec2{e.y, -e.x} * (side / l) : Vec2{0, 0};  // outward unit normal
        }
    }
    double operator()(Vec2 p) const {
        double out = 0;
        for (size_t k = 0; k < 3; ++k) out = std::max(out, dot(p - a_[k], n_[k]));
        return out - kSlack;
    }

private:
    static constexpr double kSlack = 1e-6;
    Vec2 a_[3], n_[3];
};

// Whether a triangle with distance bound `bound` surely cannot take texel (x, y), whose hit lies at
// float distance `current`, from within `dilation` texels (a hit replaced only by a strictly
// nearer float(d)): the hit is at distance 0 (float(d) < 0 never holds), or the triangle is surely
// beyond the dilation or the hit (d >= current gives float(d) >= current).
inline bool cannotTake(const EdgeDistanceBound& bound, double dilation, float current, int x, int y) {
    if (!(current > 0)) return true;
    const double low = bound(Vec2{x + 0.5, y + 0.5});
    return low > dilation || low >= double(current);
}

// The hits of the ORIGINAL faces at `cornerUV` (per face corner, [0,1] scaled by g.size): each
// texel within `dilation` texels of a face takes the nearest face (the earlier face on ties), its
// closest point's barycentrics and the offset from that point to the texel centre. Faces with no
// UV area are skipped. Rows in bands on `threads` threads; the hits do not depend on the count.
void rasterizeTriangles(const TriMesh& mesh, const std::vector<std::array<Vec2, 3>>& cornerUV, const TexelRegion& g,
                        double dilation, int threads, std::vector<TexelHit>& hits);

}  // namespace lodbake::bake_detail
