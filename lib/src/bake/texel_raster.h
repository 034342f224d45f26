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

// The baked region: texels [0, w) x [0, h) of the size x size grid cornerUV is scaled to.
struct Grid {
    int size, w, h;
    size_t at(int x, int y) const { return size_t(y) * size_t(w) + size_t(x); }
};

// Closest point of triangle abc to p as barycentrics; returns the distance.
inline double closestBary(Vec2 p, Vec2 a, Vec2 b, Vec2 c, std::array<double, 3>& out) {
    double den = cross(b - a, c - a);
    double l1 = cross(p - a, c - a) / den, l2 = cross(b - a, p - a) / den, l0 = 1 - l1 - l2;
    if (l0 >= 0 && l1 >= 0 && l2 >= 0) {
        out = {l0, l1, l2};
        return 0;
    }
    double best = 1e300;
    const Vec2 v[3] = {a, b, c};
    for (int e = 0; e < 3; ++e) {
        Vec2 s = v[e], t = v[(e + 1) % 3];
        Vec2 d = t - s;
        double len2 = dot(d, d);
        double u = len2 > 0 ? std::clamp(dot(p - s, d) / len2, 0.0, 1.0) : 0;
        Vec2 q = s + d * u;
        double dist = std::sqrt(dot(p - q, p - q));
        if (dist < best) {
            best = dist;
            std::array<double, 3> bb{};
            bb[size_t(e)] = 1 - u;
            bb[size_t((e + 1) % 3)] = u;
            out = bb;
        }
    }
    return best;
}

// Calls fn(x, y, d, bary) for every texel of the grid's region (rows [rowBegin, rowEnd) of it)
// whose centre lies within `dilation` texels of triangle P (texel units); bary: of the closest
// point of P. Inline: it is the rasterisers' inner loop.
template <class Fn>
void forEachTexelNear(const Vec2 (&P)[3], const Grid& g, double dilation, Fn&& fn, int rowBegin = 0, int rowEnd = INT_MAX) {
    double x0 = std::min({P[0].x, P[1].x, P[2].x}) - dilation, x1 = std::max({P[0].x, P[1].x, P[2].x}) + dilation;
    double y0 = std::min({P[0].y, P[1].y, P[2].y}) - dilation, y1 = std::max({P[0].y, P[1].y, P[2].y}) + dilation;
    int ix0 = std::max(0, int(std::floor(x0))), ix1 = std::min(g.w - 1, int(std::ceil(x1)));
    int iy0 = std::max(rowBegin, int(std::floor(y0))), iy1 = std::min({g.h - 1, rowEnd - 1, int(std::ceil(y1))});
    for (int y = iy0; y <= iy1; ++y)
        for (int x = ix0; x <= ix1; ++x) {
            std::array<double, 3> b{};
            double d = closestBary({x + 0.5, y + 0.5}, P[0], P[1], P[2], b);
            if (d <= dilation) fn(x, y, d, b);
        }
}

// The hits of the ORIGINAL faces at `cornerUV` (per face corner, [0,1] scaled by g.size): each
// texel within `dilation` texels of a face takes the nearest face (the earlier face on ties), its
// closest point's barycentrics and the offset from that point to the texel centre. Faces with no
// UV area are skipped. Rows in bands on `threads` threads; the hits do not depend on the count.
void rasterizeTriangles(const TriMesh& mesh, const std::vector<std::array<Vec2, 3>>& cornerUV, const Grid& g,
                        double dilation, int threads, std::vector<TexelHit>& hits);

}  // namespace lodbake::bake_detail
