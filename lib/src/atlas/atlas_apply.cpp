// applyAtlas: puts a parameterize() result into the asset and its levels (point-consistent
// mapping: a level vertex is an original vertex, so it takes its UV in the chart of the face).
//
// The level UVs themselves are computed (and checked) by parameterize (ParameterizeResult::levels):
// corners that are not vertices of their triangle's chart take the UV of the closest point of
// that chart's surface; level triangles that would fold use their island.
#include "lodbake/atlas/atlas_apply.h"

#include <algorithm>
#include <map>
#include <string>
#include <tuple>

#include "lodbake/core/errors.h"

namespace lodbake {

AtlasApplyStats applyAtlas(Asset& asset, Multires& multires, const ParameterizeResult& param, const Image& bakedImage) {
    TriMesh& mesh = asset.mesh;
    const size_t nf = mesh.triangleCount();
    if (param.cornerUV.size() != nf || param.charts.faceChart.size() != nf)
        throw InvalidInput("applyAtlas: parameterization does not match the mesh");
    AtlasApplyStats stats;

    // Original wedges keep their attributes; make uv0 present if it was not.
    Wedges& W = mesh.wedges;
    const size_t originalWedges = W.size();
    if (W.uv0.empty()) W.uv0.assign(originalWedges, Vec2{0, 0});
    std::vector<uint32_t> anyWedge(mesh.vertexCount(), UINT32_MAX);
    for (uint32_t w = 0; w < originalWedges; ++w)
        if (anyWedge[W.vertex[w]] == UINT32_MAX) anyWedge[W.vertex[w]] = w;

    // New wedge per (chart, source wedge, uv): keyed map, created in level order (deterministic).
    std::map<std::tuple<uint32_t, uint32_t, double, double>, uint32_t> made;
    auto wedgeFor = [&](uint32_t chart, uint32_t vertex, uint32_t source, Vec2 uv) {
        auto key = std::make_tuple(chart, source, uv.x, uv.y);
        auto it = made.find(key);
        if (it != made.end()) return it->second;
        uint32_t id = uint32_t(W.vertex.size());
        W.vertex.push_back(vertex);
        if (!W.normal.empty()) W.normal.push_back(W.normal[source]);
        if (!W.tangent.empty()) W.tangent.push_back(W.tangent[source]);
        W.uv0.push_back(uv);
        if (!W.uv1.empty()) W.uv1.push_back(W.uv1[source]);
        if (!W.color.empty()) W.color.push_back(Vec4{1, 1, 1, 1});  // colour is baked into the texture
        if (!W.joints.empty()) W.joints.push_back(W.joints[source]);
        if (!W.weights.empty()) W.weights.push_back(W.weights[source]);
        for (MorphDeltas& D : W.targets) {
            D.position.push_back(D.position[source]);
            if (!D.normal.empty()) D.normal.push_back(D.normal[source]);
            if (!D.tangent.empty()) D.tangent.push_back(D.tangent[source]);
        }
        made.emplace(key, id);
        return id;
    };

    // The baked material: PBR factors of the most used original material.
    std::vector<size_t> use(asset.materials.size() + 1, 0);
    for (int32_t m : mesh.triangleMaterial) ++use[size_t(m + 1)];
    int top = int(std::max_element(use.begin(), use.end()) - use.begin()) - 1;
    Material baked;
    baked.name = "lodbake_atlas";
    if (top >= 0) {
        const Material& src = asset.materials[size_t(top)];
        baked.metallicFactor = src.metallicRoughness.texture >= 0 ? 0 : src.metallicFactor;
        baked.roughnessFactor = src.metallicRoughness.texture >= 0 ? 1 : src.roughnessFactor;
        baked.emissiveFactor = src.emissive.texture >= 0 ? Vec3{} : src.emissiveFactor;
    }
    for (const Material& m : asset.materials) baked.doubleSided = baked.doubleSided || m.doubleSided;
    if (!bakedImage.encoded.empty()) {  // no image (not baked): the material keeps its factors
        asset.images.push_back(bakedImage);
        asset.textures.push_back({int(asset.images.size()) - 1, -1});
        baked.baseColor.texture = int(asset.textures.size()) - 1;
        baked.baseColor.texCoord = 0;
    }
    asset.materials.push_back(baked);
    stats.material = int(asset.materials.size()) - 1;

    std::vector<uint32_t> faceChart(nf);
    for (size_t f = 0; f < nf; ++f) faceChart[f] = uint32_t(std::max(param.charts.faceChart[f], 0));
    if (param.levels.size() != multires.levels.size())
        throw InvalidInput("applyAtlas: the parameterization has UVs for " + std::to_string(param.levels.size()) +
                           " levels, the chain has " + std::to_string(multires.levels.size()));
    for (size_t li = 0; li < multires.levels.size(); ++li) {
        Level& L = multires.levels[li];
        const LevelUV& luv = param.levels[li];
        if (L.faces.size() != L.triangles.size()) throw InvalidInput("level faces and triangles differ in size");
        if (luv.uv.size() != L.triangles.size() || luv.chart.size() != L.triangles.size())
            throw InvalidInput("applyAtlas: level UVs do not match the level's triangles");
        std::vector<Tri> corners(L.triangles.size());
        for (size_t t = 0; t < L.triangles.size(); ++t) {
            // Wedges are split per chart; an island (chart id >= chartCount) gets its own.
            const uint32_t c = luv.chart[t];
            if (c >= param.charts.chartCount) ++stats.islandTriangles;
            for (int k = 0; k < 3; ++k) {
                uint32_t v = L.triangles[t][size_t(k)];
                uint32_t source = t < L.cornerWedges.size() ? L.cornerWedges[t][size_t(k)] : anyWedge[v];
                if (source >= originalWedges) source = anyWedge[v];
                corners[t][size_t(k)] = wedgeFor(c, v, source, luv.uv[t][size_t(k)]);
            }
        }
        stats.projectedCorners += luv.projectedCorners;
        L.cornerWedges = std::move(corners);
        L.triangleMaterial.assign(L.triangles.size(), stats.material);
    }
    stats.newWedges = W.size() - originalWedges;

    // The layout itself travels in the file (LODBAKE_multires.charts) for `pack` and later tools.
    ChartLayout& layout = multires.charts;
    layout.chartCount = param.charts.chartCount;
    layout.faceChart = faceChart;
    layout.cornerUV = param.cornerUV;
    layout.islands.clear();
    for (const LevelIsland& isl : param.islands) layout.islands.push_back({isl.vertices, isl.uv});
    layout.material = stats.material;
    layout.image = int(asset.images.size()) - 1;
    return stats;
}

}  // namespace lodbake
