// Texel coverage of the original faces at the bake's UVs (texel_raster.h): conservative
// rasterisation, the nearest face winning each texel.
#include "bake/texel_raster.h"

#include "lodbake/core/parallel.h"
#include "lodbake/core/touched_fill.h"

namespace lodbake::bake_detail {
namespace {

// Side of the tiles whose largest bound lets a face skip them (kRasterRows is a multiple).
constexpr int kTile = 8;
// Dilation of the first pass, which only bounds each texel's nearest distance.
constexpr double kBoundDilation = 1;
// Box distances are taken this much nearer (texels) than computed: a computed closest point may
// stray from its face's box by rounding, and a face that ties the bound must still be asked.
constexpr double kBoxMargin = 1e-6;
// Texels added to a walked bound: above the float rounding of a hit's distance and of the walk.
constexpr double kChamferMargin = 1e-4;

// The face's texel centre rasterised: the hit the texel takes from face f at distance d.
TexelHit hitOf(uint32_t f, const Vec2 (&P)[3], int x, int y, double d, const std::array<double, 3>& b) {
    const Vec2 q = P[0] * b[0] + P[1] * b[1] + P[2] * b[2];
    return {int32_t(f), float(d), {float(b[0]), float(b[1]), float(b[2])}, -1, {float(x + 0.5 - q.x), float(y + 0.5 - q.y)}};
}

// Calls fn(f, P) for the faces in order that may reach rows [rowBegin, rowEnd) within `dilation`
// and have UV area; P: the face's corners in texels.
template <class Fn>
void forEachBandFace(const TriMesh& mesh, const std::vector<std::array<Vec2, 3>>& cornerUV, const TexelRegion& g,
                     double dilation, size_t rowBegin, size_t rowEnd, Fn&& fn) {
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f) {
        Vec2 P[3];
        for (int k = 0; k < 3; ++k) P[k] = {cornerUV[f][size_t(k)].x * g.size, cornerUV[f][size_t(k)].y * g.size};
        if (offBand(P, dilation, rowBegin, rowEnd)) continue;
        if (std::fabs(cross(P[1] - P[0], P[2] - P[0])) < 1e-12) continue;
        fn(f, P);
    }
}

// The faces' hits on rows [rowBegin, rowEnd): each texel keeps the first face at the least float
// distance.
void rasterBand(const TriMesh& mesh, const std::vector<std::array<Vec2, 3>>& cornerUV, const TexelRegion& g,
                double dilation, size_t rowBegin, size_t rowEnd, std::vector<TexelHit>& hits) {
    forEachBandFace(mesh, cornerUV, g, dilation, rowBegin, rowEnd, [&](uint32_t f, const Vec2(&P)[3]) {
        const EdgeDistanceBound edges(P);
        forEachTexelNear(
            P, g, dilation,
            [&](int x, int y, double d, const std::array<double, 3>& b) {
                TexelHit& h = hits[g.at(x, y)];
                if (float(d) < h.dist) h = hitOf(f, P, x, y, d, b);
            },
            int(rowBegin), int(rowEnd), [&](int x, int y) { return cannotTake(edges, dilation, hits[g.at(x, y)].dist, x, y); });
    });
}

// Upper bounds of each band texel's least distance to a face, from the hits of a pass with a
// narrow dilation: a texel's own hit, or a neighbour's bound plus the path to it (the neighbour's
// face is at most that far; a chamfer walk, never shorter than the straight line). Bounds off the
// hits carry kChamferMargin above the float roundings of the walk. Row-major over the band.
std::vector<float> distanceBounds(const std::vector<TexelHit>& hits, const TexelRegion& g, size_t rowBegin, int rows) {
    const int w = g.w;
    std::vector<double> walk(size_t(rows) * size_t(w));
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < w; ++x) {
            const float d = hits[g.at(x, int(rowBegin) + y)].dist;
            walk[size_t(y) * size_t(w) + size_t(x)] = d < 1e30f ? double(d) : 1e300;
        }
    const double diagonal = std::sqrt(2.0);
    auto relax = [&](int x, int y, int dx, int dy) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= w || ny >= rows) return;
        double& b = walk[size_t(y) * size_t(w) + size_t(x)];
        b = std::min(b, walk[size_t(ny) * size_t(w) + size_t(nx)] + (dx != 0 && dy != 0 ? diagonal : 1.0));
    };
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < w; ++x) {
            relax(x, y, -1, 0);
            relax(x, y, -1, -1);
            relax(x, y, 0, -1);
            relax(x, y, 1, -1);
        }
    for (int y = rows - 1; y >= 0; --y)
        for (int x = w - 1; x >= 0; --x) {
            relax(x, y, 1, 0);
            relax(x, y, 1, 1);
            relax(x, y, 0, 1);
            relax(x, y, -1, 1);
        }
    std::vector<float> bound(walk.size());
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * size_t(w) + size_t(x);
            const float own = hits[g.at(x, int(rowBegin) + y)].dist;
            bound[i] = std::min(own, walk[i] < 1e30 ? float(walk[i] + kChamferMargin) : 1e30f);
        }
    return bound;
}

// rasterBand with a wide dilation over many small faces, where each face would ask hundreds of
// texels that nearer faces take. A first pass with kBoundDilation bounds each texel's least
// distance from above (distanceBounds); the full pass then skips a tile, or a texel, whose
// distance to a face's box is above that bound: the face can neither win nor tie it (or lies
// beyond the dilation), so every texel keeps the same face, distance and barycentrics.
void rasterBandBounded(const TriMesh& mesh, const std::vector<std::array<Vec2, 3>>& cornerUV, const TexelRegion& g,
                       double dilation, size_t rowBegin, size_t rowEnd, std::vector<TexelHit>& hits) {
    rasterBand(mesh, cornerUV, g, kBoundDilation, rowBegin, rowEnd, hits);
    const int rows = int(rowEnd - rowBegin), tilesX = (g.w + kTile - 1) / kTile;
    const std::vector<float> bound = distanceBounds(hits, g, rowBegin, rows);
    std::vector<float> tileBound(size_t((rows + kTile - 1) / kTile) * size_t(tilesX), 0.f);
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < g.w; ++x) {
            float& t = tileBound[size_t(y / kTile) * size_t(tilesX) + size_t(x / kTile)];
            t = std::max(t, bound[size_t(y) * size_t(g.w) + size_t(x)]);
            hits[g.at(x, int(rowBegin) + y)] = {};
        }
    // How far a texel centre range [c0, c1] lies from [b0, b1] along one axis.
    auto gap = [](double c0, double c1, double b0, double b1) { return std::max({0.0, c0 - b1, b0 - c1}); };
    auto beyond = [](double dx, double dy, float bound) { return float(std::sqrt(dx * dx + dy * dy) - kBoxMargin) > bound; };
    forEachBandFace(mesh, cornerUV, g, dilation, rowBegin, rowEnd, [&](uint32_t f, const Vec2(&P)[3]) {
        const TexelBox box = texelBox(P, g, dilation, int(rowBegin), int(rowEnd));
        const double bx0 = std::min({P[0].x, P[1].x, P[2].x}), bx1 = std::max({P[0].x, P[1].x, P[2].x});
        const double by0 = std::min({P[0].y, P[1].y, P[2].y}), by1 = std::max({P[0].y, P[1].y, P[2].y});
        const std::array<Vec2, 3> tri{P[0], P[1], P[2]};
        const EdgeDistanceBound edges(P);
        for (int ty = (box.y0 - int(rowBegin)) / kTile; box.y0 <= box.y1 && ty <= (box.y1 - int(rowBegin)) / kTile; ++ty) {
            const int ya = std::max(box.y0, int(rowBegin) + ty * kTile), yb = std::min(box.y1, int(rowBegin) + ty * kTile + kTile - 1);
            const double dy = gap(ya + 0.5, yb + 0.5, by0, by1);
            for (int tx = box.x0 / kTile; box.x0 <= box.x1 && tx <= box.x1 / kTile; ++tx) {
                const int xa = std::max(box.x0, tx * kTile), xb = std::min(box.x1, tx * kTile + kTile - 1);
                if (beyond(gap(xa + 0.5, xb + 0.5, bx0, bx1), dy, tileBound[size_t(ty) * size_t(tilesX) + size_t(tx)])) continue;
                for (int y = ya; y <= yb; ++y)
                    for (int x = xa; x <= xb; ++x) {
                        const float b = bound[size_t(y - int(rowBegin)) * size_t(g.w) + size_t(x)];
                        if (beyond(gap(x + 0.5, x + 0.5, bx0, bx1), gap(y + 0.5, y + 0.5, by0, by1), b)) continue;
                        TexelHit& h = hits[g.at(x, y)];
                        if (cannotTake(edges, dilation, h.dist, x, y)) continue;
                        std::array<double, 3> w{};
                        const double d = std::sqrt(closestOnTriangle(Vec2{x + 0.5, y + 0.5}, tri, w));
                        if (!(d <= dilation)) continue;
                        if (float(d) < h.dist) h = hitOf(f, P, x, y, d, w);
                    }
            }
        }
    });
}

}  // namespace

void rasterizeTriangles(const TriMesh& mesh, const std::vector<std::array<Vec2, 3>>& cornerUV, const TexelRegion& g,
                        double dilation, int threads, std::vector<TexelHit>& hits) {
    assignTouched(hits, size_t(g.w) * size_t(g.h), TexelHit{}, threads);
    parallelChunks(size_t(g.h), kRasterRows, threads, [&](size_t rowBegin, size_t rowEnd, size_t) {
        if (dilation > 2 * kBoundDilation)
            rasterBandBounded(mesh, cornerUV, g, dilation, rowBegin, rowEnd, hits);
        else
            rasterBand(mesh, cornerUV, g, dilation, rowBegin, rowEnd, hits);
    });
}

}  // namespace lodbake::bake_detail
