// Levels that keep a repeating material tiling (see tiled_levels.h).
//
//   tilingEligibility: one material, every texture on one UV set through one transform, sampled
//   with REPEAT, coordinates that repeat;
//   tiledLevelUVs: each level corner's kept wedge UV through the transform, a stretched triangle
//   (corners from different UV islands) re-picking its corners' wedges;
//   bakeTile: the material over one period, by the page bake on a flat quad.
#include "lod/tiled_levels.h"

#include <algorithm>
#include <cmath>

#include "lod/level_material.h"
#include "lodbake/core/math.h"
#include "lodbake/texture/codec.h"
#include "lodbake/texture/texture_transform.h"

namespace lodbake::lod_detail {
namespace {

constexpr int kRepeat = 10497;  // GL_REPEAT

// Every texture reference of a material, extensions included.
std::vector<const TextureRef*> materialTextures(const Material& m) {
    std::vector<const TextureRef*> refs{&m.baseColor, &m.metallicRoughness, &m.normal, &m.occlusion, &m.emissive, &m.specularGlossiness};
    for (const TextureRef* r : textureRefs(m.ext)) refs.push_back(r);
    refs.erase(std::remove_if(refs.begin(), refs.end(), [](const TextureRef* r) { return r->texture < 0; }), refs.end());
    return refs;
}

bool sameTransform(const TextureTransform& a, const TextureTransform& b) {
    if (a.present != b.present) return false;
    return !a.present || (a.offset.x == b.offset.x && a.offset.y == b.offset.y && a.rotation == b.rotation && a.scale.x == b.scale.x &&
                          a.scale.y == b.scale.y);
}

const std::vector<Vec2>& uvSetOf(const Wedges& w, int set) { return set == 0 ? w.uv0 : w.uv1; }

// Vertex colours that vary over the mesh (a tile cannot carry them).
bool varyingColors(const Wedges& w) {
    for (const Vec4& c : w.color)
        if (c.x != w.color[0].x || c.y != w.color[0].y || c.z != w.color[0].z || c.w != w.color[0].w) return true;
    return false;
}

// The one material of every triangle; -1 when they differ or one has none.
int singleMaterial(const TriMesh& m) {
    if (m.triangleMaterial.empty()) return -1;
    const int32_t first = m.triangleMaterial[0];
    for (int32_t x : m.triangleMaterial)
        if (x != first) return -1;
    return first;
}

// The signed UV area in the glTF convention (v down): > 0 for a front-facing map.
double uvArea(const std::array<Vec2, 3>& t) { return -signedArea(t[0], t[1], t[2]); }

double area3(const std::vector<Vec3>& p, const Tri& t) { return triangleArea(p[t[0]], p[t[1]], p[t[2]]); }

// How far a triangle's map departs from the original's: |log(ratio / reference)| of its UV-to-3D
// area ratio, infinite when it faces the other way or has no area.
double stretchOf(const std::array<Vec2, 3>& uv, double area, double reference, double orientation) {
    const double a = uvArea(uv) * orientation;
    if (!(a > 0) || !(area > 0)) return INFINITY;
    return std::abs(std::log(a / area / reference));
}

}  // namespace

TilingEligibility tilingEligibility(const Asset& asset, const std::vector<std::pair<int, int>>& imageSizes,
                                    const TilingOptions& options) {
    TilingEligibility e;
    const TriMesh& mesh = asset.mesh;
    auto no = [&](std::string why) {
        e.eligible = false;
        e.reason = std::move(why);
        return e;
    };
    e.material = singleMaterial(mesh);
    if (e.material < 0 || size_t(e.material) >= asset.materials.size()) return no("the triangles do not all wear one material");
    if (!asset.variants.empty()) return no("material variants");
    const std::vector<const TextureRef*> refs = materialTextures(asset.materials[size_t(e.material)]);
    if (refs.empty()) return no("the material has no texture");
    e.uvSet = textureCoordSet(*refs[0]);
    e.transform = refs[0]->transform;
    for (const TextureRef* r : refs) {
        if (textureCoordSet(*r) != e.uvSet) return no("the material's textures read different UV sets");
        if (!sameTransform(r->transform, e.transform)) return no("the material's textures have different texture transforms");
        if (size_t(r->texture) >= asset.textures.size()) return no("a texture index is out of range");
        const Texture& t = asset.textures[size_t(r->texture)];
        const Sampler s = t.sampler >= 0 && size_t(t.sampler) < asset.samplers.size() ? asset.samplers[size_t(t.sampler)] : Sampler{};
        if (s.wrapS != kRepeat || s.wrapT != kRepeat) return no("a texture's sampler does not repeat");
        if (t.image < 0 || size_t(t.image) >= imageSizes.size()) return no("a texture has no image");
        e.width = std::max(e.width, imageSizes[size_t(t.image)].first);
        e.height = std::max(e.height, imageSizes[size_t(t.image)].second);
    }
    if (e.uvSet > 1 || uvSetOf(mesh.wedges, e.uvSet).size() != mesh.wedges.size()) return no("the mesh lacks the textures' UV set");
    if (varyingColors(mesh.wedges)) return no("vertex colours vary");
    if (!(e.width > 0 && e.height > 0)) return no("the textures have no size");
    // The extent of the texture coordinates the triangles use.
    Vec2 lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
    const std::vector<Vec2>& uv = uvSetOf(mesh.wedges, e.uvSet);
    for (const Tri& w : mesh.cornerWedges)
        for (uint32_t x : w) {
            const Vec2 t = applyTextureTransform(e.transform, uv[x]);
            lo = {std::min(lo.x, t.x), std::min(lo.y, t.y)};
            hi = {std::max(hi.x, t.x), std::max(hi.y, t.y)};
        }
    e.span = std::max(hi.x - lo.x, hi.y - lo.y);
    const bool scaled = e.transform.present && (std::abs(e.transform.scale.x) > 1 || std::abs(e.transform.scale.y) > 1);
    if (!scaled && !(e.span > options.minSpan)) return no("the textures do not repeat");
    e.eligible = true;
    e.reason = scaled ? "texture transform scale above 1" : "texture coordinates span several tiles";
    return e;
}

TilingEligibility tilingEligibility(const Asset& asset, const TilingOptions& options) {
    std::vector<std::pair<int, int>> sizes;
    for (const Image& image : asset.images) sizes.push_back(imageSize(image));
    return tilingEligibility(asset, sizes, options);
}

TiledLevelUVs tiledLevelUVs(const TriMesh& original, const std::vector<Vec3>& positions, const std::vector<Tri>& triangles,
                            const std::vector<uint32_t>& faces, const TilingEligibility& tiling, double maxStretch) {
    const std::vector<Vec2>& uv = uvSetOf(original.wedges, tiling.uvSet);
    auto tileUV = [&](uint32_t w) { return applyTextureTransform(tiling.transform, uv[w]); };
    // The original's UV-to-3D area ratio and orientation (area-weighted over its triangles: the
    // reference where a level triangle's own face has no area), and each vertex's wedges among
    // the original faces' corners (one per UV island around it).
    double uvSum = 0, areaSum = 0;
    std::vector<std::vector<uint32_t>> wedgesOf(original.vertexCount());
    for (size_t f = 0; f < original.triangleCount(); ++f) {
        const Tri& w = original.cornerWedges[f];
        uvSum += uvArea({tileUV(w[0]), tileUV(w[1]), tileUV(w[2])});
        areaSum += area3(original.positions, original.triangles[f]);
        for (size_t j = 0; j < 3; ++j) {
            std::vector<uint32_t>& of = wedgesOf[original.triangles[f][j]];
            if (std::find(of.begin(), of.end(), w[j]) == of.end()) of.push_back(w[j]);
        }
    }
    const double meanOrientation = uvSum < 0 ? -1 : 1;
    const double meanRatio = areaSum > 0 ? std::abs(uvSum) / areaSum : 1;
    const double limit = std::log(maxStretch);

    TiledLevelUVs out;
    out.uv.resize(triangles.size());
    double levelArea = 0;
    for (size_t t = 0; t < triangles.size(); ++t) {
        // Each corner in the UV island of the original face the triangle descends from: that
        // face's own wedge at a corner it shares, else the vertex's wedge nearest to the face's UVs.
        const uint32_t f = faces[t];
        const std::array<Vec2, 3> face{tileUV(original.cornerWedges[f][0]), tileUV(original.cornerWedges[f][1]),
                                       tileUV(original.cornerWedges[f][2])};
        const Vec2 centre = (face[0] + face[1] + face[2]) * (1.0 / 3);
        // The face's own map is the reference (UV density may vary over the original).
        const double faceUV = uvArea(face), faceArea = area3(original.positions, original.triangles[f]);
        const bool own = faceUV != 0 && faceArea > 0;
        const double reference = own ? std::abs(faceUV) / faceArea : meanRatio;
        const double orientation = own ? (faceUV < 0 ? -1 : 1) : meanOrientation;
        for (size_t j = 0; j < 3; ++j) {
            const uint32_t v = triangles[t][j];
            const size_t at = size_t(std::find(original.triangles[f].begin(), original.triangles[f].end(), v) - original.triangles[f].begin());
            if (at < 3) {
                out.uv[t][j] = face[at];
                continue;
            }
            double nearest = INFINITY;
            for (uint32_t w : wedgesOf[v]) {
                const Vec2 e = tileUV(w) - centre;
                const double d = e.x * e.x + e.y * e.y;
                if (d < nearest) {
                    nearest = d;
                    out.uv[t][j] = tileUV(w);
                }
            }
        }
        const double area = area3(positions, triangles[t]);
        levelArea += area;
        double best = stretchOf(out.uv[t], area, reference, orientation);
        if (best <= limit) continue;
        // Every combination of its corners' wedges, each of the last two corners also moved by
        // whole tiles towards the first (the same texels: a seam where the UVs wrap, such as a
        // sphere's u = 0 / 1, is a whole number of tiles): the least stretched (first on ties).
        const std::vector<uint32_t>&a = wedgesOf[triangles[t][0]], &b = wedgesOf[triangles[t][1]], &c = wedgesOf[triangles[t][2]];
        std::array<Vec2, 3> chosen = out.uv[t];
        bool changed = false;
        auto wrapped = [](Vec2 p, Vec2 to, int k) {  // k bit 0: u moved, bit 1: v moved
            return Vec2{k & 1 ? p.x - std::round(p.x - to.x) : p.x, k & 2 ? p.y - std::round(p.y - to.y) : p.y};
        };
        for (uint32_t x : a)
            for (uint32_t y : b)
                for (uint32_t z : c)
                    for (int k = 0; k < 16; ++k) {
                        const Vec2 p = tileUV(x);
                        const std::array<Vec2, 3> trial{p, wrapped(tileUV(y), p, k & 3), wrapped(tileUV(z), p, k >> 2)};
                        const double s = stretchOf(trial, area, reference, orientation);
                        if (s < best) {
                            best = s;
                            chosen = trial;
                            changed = true;
                        }
                    }
        if (changed) ++out.rechosen;
        out.uv[t] = chosen;
        if (best > limit) {
            ++out.stretched;
            out.stretchedArea += area;
        }
    }
    if (levelArea > 0) out.stretchedArea /= levelArea;
    return out;
}

std::optional<TiledLevelUVs> tiledLevel(const TriMesh& original, const std::vector<Vec3>& positions, const std::vector<Tri>& triangles,
                                        const std::vector<uint32_t>& faces, const TilingEligibility& tiling,
                                        PackLevelReport::Tiling& report, double maxStretchedArea) {
    TiledLevelUVs uvs = tiledLevelUVs(original, positions, triangles, faces, tiling);
    report.span = tiling.span;
    report.rechosen = uvs.rechosen;
    report.stretched = uvs.stretched;
    report.stretchedArea = uvs.stretchedArea;
    report.tiled = uvs.stretchedArea <= maxStretchedArea;
    report.note = report.tiled ? tiling.reason
                               : "stretched UVs over " + std::to_string(int(std::lround(100 * uvs.stretchedArea))) +
                                     "% of the level's area (corners across UV seams): an atlas page";
    if (!report.tiled) return std::nullopt;
    return uvs;
}

BakeResult bakeTile(const Asset& asset, const TilingEligibility& tiling, const BakeChannels& channels, int threads) {
    // A flat quad over one tile: position (u, 1 - v, 0) for tile UV (u, v), facing +z, so its
    // tangent frames are those a level's tangents take from tile UVs. Its wedges' source UVs are
    // the tile corners through the inverse transform: the material's own texture space.
    Asset quad;
    quad.sourcePath = asset.sourcePath;
    quad.materials = {asset.materials[size_t(tiling.material)]};
    quad.textures = asset.textures;
    quad.samplers = asset.samplers;
    quad.images = asset.images;
    const std::array<Vec2, 4> corners{Vec2{0, 0}, Vec2{1, 0}, Vec2{1, 1}, Vec2{0, 1}};
    const std::array<double, 4> L = textureTransformLinear(tiling.transform);
    const double det = L[0] * L[3] - L[2] * L[1];
    const Vec2 offset = tiling.transform.present ? tiling.transform.offset : Vec2{0, 0};
    TriMesh& m = quad.mesh;
    LodLevelData target;  // the quad as a level on the tile, for its frames
    for (uint32_t i = 0; i < 4; ++i) {
        const Vec2 t = corners[i];
        const Vec2 d = t - offset;
        const Vec2 source{(L[3] * d.x - L[2] * d.y) / det, (-L[1] * d.x + L[0] * d.y) / det};
        m.positions.push_back({t.x, 1 - t.y, 0});
        m.wedges.vertex.push_back(i);
        m.wedges.normal.push_back({0, 0, 1});
        (tiling.uvSet == 0 ? m.wedges.uv0 : m.wedges.uv1).push_back(source);
        target.positions.insert(target.positions.end(), {float(t.x), float(1 - t.y), 0.f});
        target.normals.insert(target.normals.end(), {0.f, 0.f, 1.f});
        target.uvs.insert(target.uvs.end(), {float(t.x), float(t.y)});
    }
    if (tiling.uvSet == 1) m.wedges.uv0 = m.wedges.uv1;  // a UV set 1 needs a set 0 beside it
    if (!asset.mesh.wedges.color.empty()) m.wedges.color.assign(4, asset.mesh.wedges.color[0]);  // constant (eligibility)
    m.triangles = {Tri{3, 2, 1}, Tri{3, 1, 0}};  // counter-clockwise seen from +z
    m.cornerWedges = m.triangles;
    m.triangleMaterial = {0, 0};
    target.indices = {3, 2, 1, 3, 1, 0};
    target.tangents = levelTangents(target);
    // Without TANGENT in the file, the bake takes the original's frames from the UVs as its normal
    // map reads them (normalMapUVs): the quad's are the tile's, as viewers show the original.

    const int size = std::max(tiling.width, tiling.height);
    std::vector<std::array<Vec2, 3>> cornerUV(2);
    for (size_t f = 0; f < 2; ++f)
        for (size_t k = 0; k < 3; ++k) {
            const Vec2 t = corners[m.triangles[f][k]];
            cornerUV[f][k] = {t.x * tiling.width / size, t.y * tiling.height / size};
        }
    BakeOptions bo;
    bo.size = size;
    bo.width = tiling.width;
    bo.height = tiling.height;
    bo.encodePng = false;
    bo.threads = threads;
    bo.channels = channels;
    const bool frames = channels.normal || channels.clearcoatNormal || channels.anisotropy;
    const BakeTarget frame = levelBakeTarget(target, tiling.width, tiling.height);
    BakeSources sources(quad);
    return bakeMaterial(sources, cornerUV, bo, {}, frames ? &frame : nullptr);
}

}  // namespace lodbake::lod_detail
