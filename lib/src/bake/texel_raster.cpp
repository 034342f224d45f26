// Texel coverage of the original faces at the bake's UVs (texel_raster.h): conservative
// rasterisation, the nearest face winning each texel.
#include "bake/texel_raster.h"

#include "lodbake/core/parallel.h"

namespace lodbake::bake_detail {

void rasterizeTriangles(const TriMesh& mesh, const std::vector<std::array<Vec2, 3>>& cornerUV, const TexelRegion& g,
                        double dilation, int threads, std::vector<TexelHit>& hits) {
    hits.assign(size_t(g.w) * size_t(g.h), {});
    parallelChunks(size_t(g.h), kRasterRows, threads, [&](size_t rowBegin, size_t rowEnd, size_t) {
        for (uint32_t f = 0; f < mesh.triangleCount(); ++f) {
            Vec2 P[3];
            for (int k = 0; k < 3; ++k) P[k] = {cornerUV[f][size_t(k)].x * g.size, cornerUV[f][size_t(k)].y * g.size};
            if (offBand(P, dilation, rowBegin, rowEnd)) continue;
            if (std::fabs(cross(P[1] - P[0], P[2] - P[0])) < 1e-12) continue;
            const EdgeDistanceBound bound(P);
            forEachTexelNear(
                P, g, dilation,
                [&](int x, int y, double d, const std::array<double, 3>& b) {
                    TexelHit& h = hits[g.at(x, y)];
                    if (!(float(d) < h.dist)) return;
                    const Vec2 q = P[0] * b[0] + P[1] * b[1] + P[2] * b[2];
                    h = {int32_t(f), float(d), {float(b[0]), float(b[1]), float(b[2])}, -1,
                         {float(x + 0.5 - q.x), float(y + 0.5 - q.y)}};
                },
                int(rowBegin), int(rowEnd), [&](int x, int y) { return cannotTake(bound, dilation, hits[g.at(x, y)].dist, x, y); });
        }
    });
}

}  // namespace lodbake::bake_detail
