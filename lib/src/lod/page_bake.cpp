// A level's page baked from the original (page_bake.h): at the page UVs, or by projection.
#include "lod/page_bake.h"

#include <algorithm>
#include <vector>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/parallel.h"

namespace lodbake::lod_detail {
namespace {

// Charts copied texel for texel (source texels) extend over their gutter ring up to this many
// texels: the first mips that average across a border read the original's neighbours; beyond, the
// pull-push fill (a wider margin costs a closest-point test per texel of every triangle's box).
constexpr int kMaxChartExtension = 16;

}  // namespace

BakeOptions pageBakeOptions(int width, int height, const BakeChannels& channels, int threads) {
    BakeOptions bo;
    bo.size = std::max(width, height);
    bo.width = width;
    bo.height = height;
    bo.encodePng = false;
    bo.threads = threads;
    bo.channels = channels;
    return bo;
}

BakeResult bakePage(const BakeSources& sources, LayoutData& L, const LevelAtlas& la, const BakeChannels& channels,
                    const BakeTarget* target, int threads, bool sourceTexels) {
    const Asset& asset = sources.asset();
    const ChartLayout& ch = *L.ch;
    const AtlasResult& a = la.atlas;
    int size = std::max(a.width, a.height);
    std::vector<std::array<Vec2, 3>> uv(asset.mesh.triangleCount());
    for (size_t f = 0; f < uv.size(); ++f) {
        int slot = la.chartSlot[ch.faceChart[f]];
        for (size_t j = 0; j < 3; ++j) {
            if (slot < 0) { uv[f][j] = {-10, -10}; continue; }  // chart unused at this level: off the page
            Vec2 p = a.charts[size_t(slot)].apply(ch.cornerUV[f][j]);
            uv[f][j] = {p.x / size, p.y / size};
        }
    }
    std::vector<BakeIsland> islands;
    for (size_t i = 0; i < ch.islands.size(); ++i) {
        int slot = la.chartSlot[ch.chartCount + i];
        if (slot < 0) continue;
        const std::vector<std::vector<uint32_t>>& islandFaces = islandFacesOf(asset.mesh, L);
        BakeIsland b;
        for (size_t k = 0; k < 3; ++k) {
            b.position[k] = asset.mesh.positions[ch.islands[i].vertices[k]];
            Vec2 p = a.charts[size_t(slot)].apply(ch.islands[i].uv[k]);
            b.uv[k] = {p.x / size, p.y / size};
        }
        b.faces = islandFaces[i];
        islands.push_back(std::move(b));
    }
    // UVs are scaled by the longer side; only the width x height page is baked (the chain
    // encodes it itself).
    BakeOptions bo = pageBakeOptions(a.width, a.height, channels, threads);
    if (sourceTexels) {
        bo.extendCharts = true;
        bo.dilation = std::clamp((a.gutter + 1) / 2, 1, kMaxChartExtension);
    }
    return bakeMaterial(sources, uv, bo, islands, target);
}

FaceGrid projectionGrid(const TriMesh& mesh, int threads) {
    return FaceGrid(mesh, withoutCopies(mesh, indexedFaces(mesh)), 1.0, threads);
}

BakeResult bakeProjected(const BakeSources& sources, const FaceGrid& grid, const LodLevelData& L, size_t front, int width,
                         int height, double reach, double diagonal, const BakeChannels& channels, const BakeTarget* target,
                         int threads) {
    const Asset& asset = sources.asset();
    const int size = std::max(width, height);
    std::vector<BakeIsland> islands(front);
    parallelFor(front, threads, [&](size_t t) {
        BakeIsland& b = islands[t];
        Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t v = L.indices[3 * t + k];
            b.position[k] = {L.positions[3 * v], L.positions[3 * v + 1], L.positions[3 * v + 2]};
            b.uv[k] = {double(L.uvs[2 * v]) * width / size, double(L.uvs[2 * v + 1]) * height / size};
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], b.position[k][a] - reach);
                hi[a] = std::max(hi[a], b.position[k][a] + reach);
            }
        }
        // A sampled deviation can fall short of the true one: widen the search until it finds faces.
        for (double grow = reach; ; grow *= 4) {
            const Vec3 g{grow - reach, grow - reach, grow - reach};
            if (projectedIslandFaces(asset.mesh, grid, lo - g, hi + g, b) || grow > 4 * diagonal) break;
        }
    });
    const std::vector<std::array<Vec2, 3>> offPage(asset.mesh.triangleCount(), {Vec2{-10, -10}, Vec2{-10, -10}, Vec2{-10, -10}});
    return bakeMaterial(sources, offPage, pageBakeOptions(width, height, channels, threads), islands, target);
}

}  // namespace lodbake::lod_detail
