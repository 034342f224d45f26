// sourceTexelLayout (source_texels.h): the original's texture islands as LOD0's charts.
#include "lod/source_texels.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "lodbake/core/adjacency.h"

namespace lodbake::lod_detail {
namespace {

// Every texture reference of a material (core channels, then its extensions').
std::vector<const TextureRef*> materialTextureRefs(const Material& m) {
    std::vector<const TextureRef*> refs = {&m.baseColor, &m.metallicRoughness, &m.normal, &m.occlusion, &m.emissive,
                                           &m.specularGlossiness};
    for (const TextureRef* r : textureRefs(m.ext)) refs.push_back(r);
    return refs;
}

// The texel grid of one material: the largest texture it reads through plain TEXCOORD_0 (0 x 0:
// none; its faces keep T0 pieces). Textures on another UV set or transformed are resampled by
// the bake as on any level.
struct MaterialGrid {
    int width = 0, height = 0;
};

MaterialGrid materialGrid(const Asset& asset, const Material& m, const std::vector<std::pair<int, int>>& imageSizes) {
    MaterialGrid g;
    for (const TextureRef* r : materialTextureRefs(m)) {
        if (r->texture < 0 || size_t(r->texture) >= asset.textures.size()) continue;
        const int image = asset.textures[size_t(r->texture)].image;
        if (image < 0 || size_t(image) >= imageSizes.size()) continue;
        const int set = r->transform.texCoord >= 0 ? r->transform.texCoord : r->texCoord;
        const TextureTransform& t = r->transform;
        if (set != 0 || (t.present && (t.offset.x != 0 || t.offset.y != 0 || t.rotation != 0 || t.scale.x != 1 || t.scale.y != 1)))
            continue;
        const auto [w, h] = imageSizes[size_t(image)];
        if (w < 1 || h < 1) continue;
        g.width = std::max(g.width, w);
        g.height = std::max(g.height, h);
    }
    return g;
}

constexpr double kMinTexelArea = 2e-6;  // twice a UV triangle's area in texels: below it, no area

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

}  // namespace

SourceTexelLayout sourceTexelLayout(const Asset& asset, const std::vector<std::pair<int, int>>& imageSizes,
                                    const ChartLayout& t0, double t0Texels) {
    SourceTexelLayout out;
    const TriMesh& mesh = asset.mesh;
    const size_t n = mesh.triangleCount();
    if (t0.faceChart.size() != n || t0.cornerUV.size() != n) {
        out.reason = "no chart layout for the untextured faces";
        return out;
    }
    std::vector<MaterialGrid> grids;
    for (const Material& m : asset.materials) grids.push_back(materialGrid(asset, m, imageSizes));
    auto gridOf = [&](size_t f) -> const MaterialGrid* {
        const int32_t m = mesh.triangleMaterial.empty() ? -1 : mesh.triangleMaterial[f];
        if (m < 0 || size_t(m) >= grids.size() || grids[size_t(m)].width == 0) return nullptr;
        return &grids[size_t(m)];
    };
    // Textured: a face with a texture grid whose UVs cover some area of it. A face whose UVs have
    // none (a palette texture reads one texel per face) covers no texel centre of its own: it
    // shows one colour, which its T0 piece reads at its UV exactly as well.
    const std::vector<Vec2>& uv = mesh.wedges.uv0;
    const bool uvs = uv.size() == mesh.wedges.size() && mesh.cornerWedges.size() == n;
    std::vector<char> textured(n, 0);
    for (size_t f = 0; f < n && uvs; ++f)
        if (const MaterialGrid* g = gridOf(f)) {
            const Vec2 a = uv[mesh.cornerWedges[f][0]], b = uv[mesh.cornerWedges[f][1]], c = uv[mesh.cornerWedges[f][2]];
            textured[f] = std::abs(cross(b - a, c - a)) * g->width * g->height > kMinTexelArea;
        }
    if (std::none_of(textured.begin(), textured.end(), [](char t) { return t != 0; })) {
        out.reason = "no face has a texture (with UVs that cover some of it) on TEXCOORD_0 without a transform";
        return out;
    }
    // Islands: textured faces of one material joined across every edge whose UVs agree at both ends.
    auto uvAt = [&](uint32_t f, uint32_t v) {
        const Tri& t = mesh.triangles[f];
        return uv[mesh.cornerWedges[f][t[0] == v ? 0 : (t[1] == v ? 1 : 2)]];
    };
    std::vector<uint32_t> parent(n);
    std::iota(parent.begin(), parent.end(), 0u);
    const EdgeGroups groups = groupEdges(mesh.triangles);
    for (size_t g = 0; g < groups.keys.size(); ++g) {
        const uint32_t a = uint32_t(groups.keys[g] >> 32), b = uint32_t(groups.keys[g] & 0xffffffffu);
        const uint32_t* first = groups.halfEdges.begin(g);
        for (const uint32_t* h = first; h != groups.halfEdges.end(g); ++h)
            for (const uint32_t* k = h + 1; k != groups.halfEdges.end(g); ++k) {
                const uint32_t f0 = *h / 3, f1 = *k / 3;
                if (!textured[f0] || !textured[f1] || mesh.triangleMaterial[f0] != mesh.triangleMaterial[f1]) continue;
                const Vec2 da = uvAt(f0, a) - uvAt(f1, a), db = uvAt(f0, b) - uvAt(f1, b);
                if (da.x == 0 && da.y == 0 && db.x == 0 && db.y == 0)
                    parent[findRoot(parent, f0)] = findRoot(parent, f1);
            }
    }
    // Islands of one material whose texel boxes (grown by a texel) overlap share texels or their
    // filter footprints (shared texture regions: repeated parts, mirrored halves): they become one
    // chart that keeps the source's arrangement, so shared texels are stored once and bilinear
    // filtering at an island's border reads the neighbours the source has.
    struct Box {
        int32_t material;
        double x0, y0, x1, y1;
        uint32_t root;
    };
    std::map<uint32_t, Box> boxOf;  // island root -> its box
    for (size_t f = 0; f < n; ++f) {
        if (!textured[f]) continue;
        const MaterialGrid& g = *gridOf(f);
        const uint32_t root = findRoot(parent, uint32_t(f));
        auto [it, fresh] = boxOf.emplace(root, Box{mesh.triangleMaterial[f], 1e300, 1e300, -1e300, -1e300, root});
        for (size_t k = 0; k < 3; ++k) {
            const Vec2 p = uv[mesh.cornerWedges[f][k]];
            Box& b = it->second;
            b.x0 = std::min(b.x0, p.x * g.width - 1);
            b.y0 = std::min(b.y0, p.y * g.height - 1);
            b.x1 = std::max(b.x1, p.x * g.width + 1);
            b.y1 = std::max(b.y1, p.y * g.height + 1);
        }
    }
    std::vector<Box> boxes;
    for (const auto& [root, b] : boxOf) boxes.push_back(b);
    std::sort(boxes.begin(), boxes.end(), [](const Box& a, const Box& b) {
        return a.material != b.material ? a.material < b.material : (a.x0 != b.x0 ? a.x0 < b.x0 : a.root < b.root);
    });
    std::vector<size_t> active;  // sweep over x within one material
    for (size_t i = 0; i < boxes.size(); ++i) {
        if (i > 0 && boxes[i].material != boxes[i - 1].material) active.clear();
        const Box& b = boxes[i];
        active.erase(std::remove_if(active.begin(), active.end(), [&](size_t j) { return boxes[j].x1 < b.x0; }), active.end());
        for (size_t j : active)
            if (boxes[j].y0 <= b.y1 && b.y0 <= boxes[j].y1) parent[findRoot(parent, boxes[j].root)] = findRoot(parent, b.root);
        active.push_back(i);
    }
    // Chart ids: islands in the order of their first face, then T0's charts of the untextured faces.
    ChartLayout& L = out.layout;
    L.faceChart.assign(n, 0);
    L.cornerUV.resize(n);
    std::vector<uint32_t> islandOf(n, UINT32_MAX);
    uint32_t charts = 0;
    for (size_t f = 0; f < n; ++f) {
        if (!textured[f]) continue;
        uint32_t& id = islandOf[findRoot(parent, uint32_t(f))];
        if (id == UINT32_MAX) id = charts++;
        L.faceChart[f] = id;
        const MaterialGrid& g = *gridOf(f);
        for (size_t k = 0; k < 3; ++k) {
            const Vec2 p = uv[mesh.cornerWedges[f][k]];
            L.cornerUV[f][k] = {p.x * g.width, p.y * g.height};
        }
    }
    out.islands = charts;
    std::map<uint32_t, uint32_t> t0Chart;
    for (size_t f = 0; f < n; ++f) {
        if (textured[f]) continue;
        auto it = t0Chart.emplace(t0.faceChart[f], charts).first;
        if (it->second == charts) ++charts;
        L.faceChart[f] = it->second;
        for (size_t k = 0; k < 3; ++k) L.cornerUV[f][k] = t0.cornerUV[f][k] * t0Texels;
    }
    L.chartCount = charts;
    L.material = t0.material;
    L.image = t0.image;
    return out;
}

std::pair<int, int> sourceFilters(const Asset& asset) {
    std::pair<int, int> filters{0, 0};
    bool first = true;
    for (const Material& m : asset.materials) {
        for (const TextureRef* r : materialTextureRefs(m)) {
            if (r->texture < 0 || size_t(r->texture) >= asset.textures.size()) continue;
            const int s = asset.textures[size_t(r->texture)].sampler;
            const Sampler smp = s >= 0 && size_t(s) < asset.samplers.size() ? asset.samplers[size_t(s)] : Sampler{};
            const std::pair<int, int> f{smp.minFilter, smp.magFilter};
            if (!first && f != filters) return {0, 0};
            filters = f;
            first = false;
        }
    }
    return filters;
}

}  // namespace lodbake::lod_detail
