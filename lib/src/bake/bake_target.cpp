// The bake target (bake_target.h): its triangles rasterised at the page's UVs, and world
// directions expressed in their tangent frames (lodbake/core/tangents.h).
#include "bake/bake_target.h"

#include <cmath>

#include "lodbake/core/parallel.h"
#include "lodbake/core/touched_fill.h"
#include "lodbake/core/tangents.h"

namespace lodbake::bake_detail {

bool targetFrame(const BakeTarget* targetOrNull, const TargetHit& th, TangentFrame& frame) {
    if (!targetOrNull || th.tri < 0) return false;
    const BakeTarget& target = *targetOrNull;
    Vec3 N{};
    for (size_t k = 0; k < 3; ++k) N += target.normal[size_t(th.tri)][k] * th.bary[k];
    N = normalize(N);
    if (!(length(N) > 0.5)) return false;
    return tangentFrameAt(N, target.tangent[size_t(th.tri)], {th.bary[0], th.bary[1], th.bary[2]}, frame);
}

std::vector<TargetHit> rasterizeTarget(const BakeTarget& target, const TexelRegion& g, int threads) {
    std::vector<TargetHit> hits;
    assignTouched(hits, size_t(g.w) * size_t(g.h), TargetHit{}, threads);
    parallelChunks(size_t(g.h), kRasterRows, threads, [&](size_t rowBegin, size_t rowEnd, size_t) {
        for (size_t t = 0; t < target.uv.size(); ++t) {
            Vec2 P[3];
            for (int k = 0; k < 3; ++k) P[k] = {target.uv[t][size_t(k)].x * g.size, target.uv[t][size_t(k)].y * g.size};
            if (offBand(P, target.reach, rowBegin, rowEnd)) continue;
            if (std::fabs(cross(P[1] - P[0], P[2] - P[0])) < 1e-12) continue;
            // Texels this triangle cannot take are not measured (as rasterizeTriangles).
            const EdgeDistanceBound bound(P);
            forEachTexelNear(
                P, g, target.reach,
                [&](int x, int y, double d, const std::array<double, 3>& b) {
                    TargetHit& h = hits[g.at(x, y)];
                    if (float(d) < h.dist) h = {int32_t(t), float(d), {float(b[0]), float(b[1]), float(b[2])}};
                },
                int(rowBegin), int(rowEnd), [&](int x, int y) { return cannotTake(bound, target.reach, hits[g.at(x, y)].dist, x, y); });
        }
    });
    return hits;
}

void encodeInFrame(const TangentFrame* frameOrNull, Vec3 N, double rgb[3]) {
    Vec3 n{0, 0, 1};
    if (frameOrNull) {
        n = normalize(frameOrNull->toTangent(N));
        if (!(length(n) > 0.5)) n = {0, 0, 1};
    }
    rgb[0] = n.x * 0.5 + 0.5;
    rgb[1] = n.y * 0.5 + 0.5;
    rgb[2] = n.z * 0.5 + 0.5;
}

void encodeAnisotropyInFrame(const TangentFrame* frameOrNull, Vec3 D, double strength, double rgb[3]) {
    double x = 1, y = 0;
    if (frameOrNull) {
        const Vec3 d = frameOrNull->toTangent(D);
        const double l = std::hypot(d.x, d.y);
        if (l > 1e-12) {
            x = d.x / l;
            y = d.y / l;
        }
    }
    rgb[0] = x * 0.5 + 0.5;
    rgb[1] = y * 0.5 + 0.5;
    rgb[2] = strength;
}

}  // namespace lodbake::bake_detail
