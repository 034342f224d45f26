// sourceTexelLayout (source_texels.h): the original's texture islands as LOD0's charts.
#include "lod/source_texels.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "lodbake/core/adjacency.h"
#include "lod/material_equality.h"

namespace lodbake::lod_detail {
namespace {

// Every texture reference of a material (core channels, then its extensions').
std::vector<const TextureRef*> materialTextureRefs(const Material& m) {
    std::vector<const TextureRef*> refs = {&m.baseColor, &m.metallicRoughness, &m.normal, &m.occlusion, &m.emissive,
                                           &m.specularGlossiness};
    for (const TextureRef* r : textureRefs(m.ext)) refs.push_back(r);
    return refs;
}

// The texels of one material: the size of the largest texture it reads through plain TEXCOORD_0 (0 x 0:
// none; its faces keep T0 pieces). Textures on another UV set or transformed are resampled by
// the bake as on any level.
struct MaterialTexels {
    int width = 0, height = 0;
    int image = -1;  // the texture whose texels these are
};

MaterialTexels materialTexels(const Asset& asset, const Material& m, const std::vector<std::pair<int, int>>& imageSizes) {
    MaterialTexels g;
    for (const TextureRef* r : materialTextureRefs(m)) {
        if (r->texture < 0 || size_t(r->texture) >= asset.textures.size()) continue;
        const int image = asset.textures[size_t(r->texture)].image;
        if (image < 0 || size_t(image) >= imageSizes.size()) continue;
        const int set = r->transform.texCoord >= 0 ? r->transform.texCoord : r->texCoord;
        const TextureTransform& t = r->transform;
        if (set != 0 || (t.present && (t.offset.x != 0 || t.offset.y != 0 || t.rotation != 0 || t.scale.x != 1 || t.scale.y != 1)))
            continue;
        const auto [w, h] = imageSizes[size_t(image)];
        if (w < 1 || h < 1 || double(w) * h <= double(g.width) * g.height) continue;
        g = {w, h, image};
    }
    return g;
}

constexpr double kMinTexelArea = 2e-6;  // twice a UV triangle's area in texels: below it, no area
constexpr double kConstantPieceTexels = 8;  // the longer side of a one-colour T0 piece, texels
constexpr double kLinePieceTexels = 64;     // at most, of a piece whose UVs cover no area

uint32_t findRoot(std::vector<uint32_t>& parent, uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

// Calls fn(texel index) for every texel of g whose centre lies in face f's UV triangle, wrapped
// into the texture; nothing for a face whose UVs span more than four textures (it tiles the
// texture: no one region of it).
template <class Fn>
void forCoveredTexels(const TriMesh& mesh, size_t f, const MaterialTexels& g, Fn&& fn) {
    Vec2 P[3];
    for (size_t k = 0; k < 3; ++k) {
        const Vec2 p = mesh.wedges.uv0[mesh.cornerWedges[f][k]];
        P[k] = {p.x * g.width, p.y * g.height};
    }
    const double x0 = std::min({P[0].x, P[1].x, P[2].x}), x1 = std::max({P[0].x, P[1].x, P[2].x});
    const double y0 = std::min({P[0].y, P[1].y, P[2].y}), y1 = std::max({P[0].y, P[1].y, P[2].y});
    if ((x1 - x0) * (y1 - y0) > 4.0 * double(g.width) * double(g.height)) return;
    const double area = cross(P[1] - P[0], P[2] - P[0]);
    for (long long ty = (long long)std::ceil(y0 - 0.5); ty + 0.5 <= y1; ++ty)
        for (long long tx = (long long)std::ceil(x0 - 0.5); tx + 0.5 <= x1; ++tx) {
            const Vec2 c{double(tx) + 0.5, double(ty) + 0.5};
            const double w0 = cross(P[1] - c, P[2] - c), w1 = cross(P[2] - c, P[0] - c), w2 = cross(P[0] - c, P[1] - c);
            if (area > 0 ? (w0 < 0 || w1 < 0 || w2 < 0) : (w0 > 0 || w1 > 0 || w2 > 0)) continue;
            const long long wx = ((tx % g.width) + g.width) % g.width, wy = ((ty % g.height) + g.height) % g.height;
            fn(size_t(wy) * size_t(g.width) + size_t(wx));
        }
}

// Per material: the first material that shades texels as it does (sameTexelShading).
std::vector<int32_t> shadingClasses(const Asset& asset) {
    const std::vector<Material>& materials = asset.materials;
    const std::vector<int> canonical = canonicalTextures(asset.textures);
    std::vector<int32_t> cls(materials.size());
    for (size_t m = 0; m < materials.size(); ++m) {
        cls[m] = int32_t(m);
        for (size_t j = 0; j < m; ++j)
            if (cls[j] == int32_t(j) && sameTexelShading(materials[j], materials[m], canonical)) { cls[m] = int32_t(j); break; }
    }
    return cls;
}

// Per island root: whether the island keeps its place on the page (the main texture's islands
// whose texels no island of another shading class kept in place before it covers; islands in the
// order of their first face). Kept islands may share texels only when they shade them alike,
// which the island joining has made one island.
template <class TexelsOf, class ClassOf>
std::vector<char> inPlaceIslands(const TriMesh& mesh, const std::vector<char>& textured, TexelsOf&& texelsOf, ClassOf&& classOf,
                                 int mainImage, std::vector<uint32_t>& parent) {
    const size_t n = textured.size();
    std::vector<std::vector<uint32_t>> faces(n);  // per root, its faces on the main texture
    std::vector<uint32_t> roots;
    for (size_t f = 0; f < n; ++f)
        if (textured[f] && texelsOf(f)->image == mainImage) {
            const uint32_t r = findRoot(parent, uint32_t(f));
            if (faces[r].empty()) roots.push_back(r);
            faces[r].push_back(uint32_t(f));
        }
    std::vector<char> kept(n, 0);
    if (roots.empty()) return kept;
    const MaterialTexels& g = *texelsOf(faces[roots[0]][0]);
    std::vector<int32_t> material(size_t(g.width) * size_t(g.height), -1);  // per texel: the kept island's class
    for (uint32_t r : roots) {
        const int32_t m = classOf(faces[r][0]);
        bool free = true;
        for (uint32_t f : faces[r])
            forCoveredTexels(mesh, f, g, [&](size_t t) { free = free && (material[t] < 0 || material[t] == m); });
        if (!free) continue;
        kept[r] = 1;
        for (uint32_t f : faces[r]) forCoveredTexels(mesh, f, g, [&](size_t t) { material[t] = m; });
    }
    return kept;
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
    std::vector<MaterialTexels> grids;
    for (const Material& m : asset.materials) grids.push_back(materialTexels(asset, m, imageSizes));
    auto texelsOf = [&](size_t f) -> const MaterialTexels* {
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
        if (const MaterialTexels* g = texelsOf(f)) {
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
    // Islands that cover the same texels of a texture (a texture region shared by repeated parts,
    // mirrored halves, or materials that differ only per primitive) become one chart when their
    // materials shade those texels alike: the shared texels are stored once. Materials that read
    // the same texels differently (one as base colour, one as emission) keep islands apart, each
    // with texels of its own.
    const std::vector<int32_t> shading = shadingClasses(asset);
    auto classOf = [&](uint32_t f) { return shading[size_t(mesh.triangleMaterial[f])]; };
    std::vector<uint32_t> byImage;
    for (size_t f = 0; f < n; ++f)
        if (textured[f]) byImage.push_back(uint32_t(f));
    auto gridKey = [&](uint32_t f) { return std::make_pair(texelsOf(f)->image, classOf(f)); };
    std::stable_sort(byImage.begin(), byImage.end(), [&](uint32_t x, uint32_t y) { return gridKey(x) < gridKey(y); });
    std::vector<uint32_t> owner;  // per texel of the current texture and material: a face covering it
    for (size_t i = 0; i < byImage.size(); ++i) {
        const uint32_t f = byImage[i];
        const MaterialTexels& g = *texelsOf(f);
        if (i == 0 || gridKey(f) != gridKey(byImage[i - 1])) owner.assign(size_t(g.width) * size_t(g.height), UINT32_MAX);
        forCoveredTexels(mesh, f, g, [&](size_t texel) {
            uint32_t& o = owner[texel];
            if (o == UINT32_MAX) o = f;
            else parent[findRoot(parent, o)] = findRoot(parent, f);
        });
    }
    // The texture whose islands cover the most texels: they can keep their places on the page.
    std::map<int, double> imageTexels;
    for (size_t f = 0; f < n; ++f)
        if (textured[f]) {
            const MaterialTexels& g = *texelsOf(f);
            const Vec2 a = uv[mesh.cornerWedges[f][0]], b = uv[mesh.cornerWedges[f][1]], c = uv[mesh.cornerWedges[f][2]];
            imageTexels[g.image] += std::abs(cross(b - a, c - a)) * g.width * g.height;
        }
    const int mainImage = std::max_element(imageTexels.begin(), imageTexels.end(), [](auto& x, auto& y) { return x.second < y.second; })->first;
    const std::vector<char> inPlace = inPlaceIslands(mesh, textured, texelsOf, classOf, mainImage, parent);
    // Chart ids: the islands kept in place, the other islands (each in the order of its first
    // face), then T0's charts of the untextured faces.
    ChartLayout& L = out.layout;
    L.faceChart.assign(n, 0);
    L.cornerUV.resize(n);
    std::vector<uint32_t> islandOf(n, UINT32_MAX);
    uint32_t charts = 0;
    for (int pass = 0; pass < 2; ++pass) {
        for (size_t f = 0; f < n; ++f)
            if (textured[f] && (inPlace[findRoot(parent, uint32_t(f))] != 0) == (pass == 0)) {
                uint32_t& id = islandOf[findRoot(parent, uint32_t(f))];
                if (id == UINT32_MAX) id = charts++;
            }
        if (pass == 0) out.inPlace = charts;
    }
    for (size_t f = 0; f < n; ++f) {
        if (!textured[f]) continue;
        const uint32_t id = islandOf[findRoot(parent, uint32_t(f))];
        L.faceChart[f] = id;
        const MaterialTexels& g = *texelsOf(f);
        for (size_t k = 0; k < 3; ++k) {
            const Vec2 p = uv[mesh.cornerWedges[f][k]];
            L.cornerUV[f][k] = {p.x * g.width, p.y * g.height};
        }
    }
    out.islands = charts;
    // T0 pieces: the untextured faces of one T0 chart, split by material where a material is
    // constant (no texture, no vertex colours). A constant piece shows one colour and needs no
    // resolution: it is shrunk to kConstantPieceTexels across, so the original's texels keep the
    // page. A piece of a texture's faces whose UVs cover no area (palette texels, strips along a
    // line) needs no more texels than its UVs cross in the texture: it takes that density, at
    // most kLinePieceTexels along its longer side while its lines stay within one period of the
    // texture. A line longer than a period reads a repeating texture (a grid along a ledge): every
    // repeat shows the period's detail, so such a piece takes the density its UVs cross up to the
    // level's own.
    const bool colours = !mesh.wedges.color.empty();
    auto pieceMaterial = [&](size_t f) -> int32_t {  // the material of a constant face, else -1
        const int32_t m = mesh.triangleMaterial.empty() ? -1 : mesh.triangleMaterial[f];
        if (colours || m < 0 || size_t(m) >= asset.materials.size()) return -1;
        for (const TextureRef* r : materialTextureRefs(asset.materials[size_t(m)]))
            if (r->texture >= 0) return -1;
        return m;
    };
    struct Piece {
        uint32_t chart = 0;
        double side = 0;     // the longer side of its T0 box, layout units
        bool lines = true;     // every face reads a texture through UVs that cover no area
        double density = 0;    // then: the page texels per layout unit its faces' UVs cross
        bool repeats = false;  // and some face's UVs span more than one period of its texture
        double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    };
    // The texture's texels face f's UV edges cross per layout unit of the same edge.
    auto lineDensity = [&](size_t f, const MaterialTexels& g) {
        double d = 0;
        for (size_t k = 0; k < 3; ++k) {
            const Vec2 e = uv[mesh.cornerWedges[f][(k + 1) % 3]] - uv[mesh.cornerWedges[f][k]];
            const Vec2 l = t0.cornerUV[f][(k + 1) % 3] - t0.cornerUV[f][k];
            const double texels = std::hypot(e.x * g.width, e.y * g.height), units = std::hypot(l.x, l.y);
            if (units > 0) d = std::max(d, texels / units);
        }
        return d;
    };
    // Whether face f's UVs span more than one texture period in u or v (the texture repeats along them).
    auto spansPeriod = [&](size_t f) {
        const Vec2 a = uv[mesh.cornerWedges[f][0]], b = uv[mesh.cornerWedges[f][1]], c = uv[mesh.cornerWedges[f][2]];
        return std::max({a.x, b.x, c.x}) - std::min({a.x, b.x, c.x}) > 1 || std::max({a.y, b.y, c.y}) - std::min({a.y, b.y, c.y}) > 1;
    };
    std::map<std::pair<uint32_t, int32_t>, Piece> pieces;  // by (T0 chart, constant material or -1)
    for (size_t f = 0; f < n; ++f) {
        if (textured[f]) continue;
        const int32_t m = pieceMaterial(f);
        Piece& p = pieces[{t0.faceChart[f], m}];
        if (m < 0) {
            const MaterialTexels* g = texelsOf(f);
            p.lines = p.lines && g && !colours && uvs;
            if (p.lines) {
                p.density = std::max(p.density, lineDensity(f, *g));
                p.repeats = p.repeats || spansPeriod(f);
            }
        }
        for (const Vec2& q : t0.cornerUV[f]) {
            p.x0 = std::min(p.x0, q.x); p.x1 = std::max(p.x1, q.x);
            p.y0 = std::min(p.y0, q.y); p.y1 = std::max(p.y1, q.y);
        }
    }
    for (auto& [key, p] : pieces) {
        p.chart = charts++;
        p.side = std::max(p.x1 - p.x0, p.y1 - p.y0);
    }
    // The scale of face f's piece; `repeating`: whether a repeating line piece may exceed kLinePieceTexels.
    auto pieceScale = [&](size_t f, bool repeating) {
        const int32_t m = pieceMaterial(f);
        const Piece& p = pieces[{t0.faceChart[f], m}];
        double scale = t0Texels;
        if (m >= 0 && p.side > 0) scale = std::min(t0Texels, kConstantPieceTexels / p.side);
        if (m < 0 && p.lines && p.side > 0)
            scale = std::min({t0Texels, repeating && p.repeats ? t0Texels : kLinePieceTexels / p.side,
                              std::max(kConstantPieceTexels / p.side, p.density)});
        return scale;
    };
    bool repeatingLines = false;
    for (size_t f = 0; f < n; ++f) {
        if (textured[f]) continue;
        L.faceChart[f] = pieces[{t0.faceChart[f], pieceMaterial(f)}].chart;
        const double scale = pieceScale(f, true);
        repeatingLines = repeatingLines || scale != pieceScale(f, false);
        for (size_t k = 0; k < 3; ++k) L.cornerUV[f][k] = t0.cornerUV[f][k] * scale;
    }
    L.chartCount = charts;
    L.material = t0.material;
    L.image = t0.image;
    if (repeatingLines) {
        out.capLayout = L;
        for (size_t f = 0; f < n; ++f)
            if (!textured[f])
                for (size_t k = 0; k < 3; ++k) out.capLayout.cornerUV[f][k] = t0.cornerUV[f][k] * pieceScale(f, false);
    }
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
