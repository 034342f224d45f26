// Bake: original appearance -> new atlas (DESIGN.md "Bake and gap fill").
//
// Pipeline: BakeSources (once per asset: each image a bake reads decoded once to MIP levels,
// texture_fetch.h, and kept for every later bake) -> rasterizeTriangles (original faces in atlas texel space, 1-texel
// conservative dilation, exact coverage wins over dilated) -> rasterizeIslands (level triangles
// parameterize could not keep injective in their chart: their texels sample the original surface
// at the closest point) -> shadeTexel (base colour factor x filtered texture fetch at the original
// UV with the footprint from the UV Jacobian x COLOR_0, in linear space; rows on
// BakeOptions::threads threads) -> fill gaps (pullPushFill with coverage, per channel image) ->
// encode PNG (unless the caller encodes). Only the width x height region of the
// size x size grid is baked.
#include "lodbake/bake/bake.h"

#include <algorithm>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <iterator>
#include <memory>
#include <mutex>

#include "lodbake/bake/texture_fetch.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/face_tree.h"
#include "lodbake/core/parallel.h"
#include "lodbake/core/tangents.h"
#include "lodbake/texture/codec.h"
#include "lodbake/texture/color_space.h"
#include "lodbake/texture/texture_transform.h"

namespace lodbake {
namespace {

// An image a material channel reads, decoded on the first bake that reads it.
struct SourceTexture {
    bool used = false;  // some material channel references it
    std::once_flag decoded;
    MipTexture mip;
};

struct TexelHit {
    int32_t face = -1;
    float dist = 1e30f;
    std::array<float, 3> bary{};
    int32_t island = -1;  // >= 0: the texel belongs to this island; face/bary = the closest original point
    std::array<float, 2> beyond{};  // texel centre minus the closest point (dilated texels), texels
};

// Closest point of triangle abc to p as barycentrics; returns the distance.
double closestBary(Vec2 p, Vec2 a, Vec2 b, Vec2 c, std::array<double, 3>& out) {
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

// The baked region: texels [0, w) x [0, h) of the size x size grid cornerUV is scaled to.
struct Grid {
    int size, w, h;
    size_t at(int x, int y) const { return size_t(y) * size_t(w) + size_t(x); }
};

// Calls fn(x, y, d, bary) for every texel of the grid's region (rows [rowBegin, rowEnd) of it)
// whose centre lies within `dilation` texels of triangle P (texel units); bary: of the closest
// point of P.
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

// Bands of kRasterRows page rows on `threads` threads, each band's texels written by the faces in
// order (the same hits for any thread count).
constexpr size_t kRasterRows = 64;

void rasterizeTriangles(const TriMesh& mesh, const std::vector<std::array<Vec2, 3>>& cornerUV, const Grid& g,
                        double dilation, int threads, std::vector<TexelHit>& hits) {
    hits.assign(size_t(g.w) * size_t(g.h), {});
    parallelChunks(size_t(g.h), kRasterRows, threads, [&](size_t rowBegin, size_t rowEnd, size_t) {
        for (uint32_t f = 0; f < mesh.triangleCount(); ++f) {
            Vec2 P[3];
            for (int k = 0; k < 3; ++k) P[k] = {cornerUV[f][size_t(k)].x * g.size, cornerUV[f][size_t(k)].y * g.size};
            if (std::max({P[0].y, P[1].y, P[2].y}) + dilation < double(rowBegin) - 1 ||
                std::min({P[0].y, P[1].y, P[2].y}) - dilation > double(rowEnd) + 1)
                continue;  // off the band (with a texel to spare: the band clips exactly)
            if (std::fabs(cross(P[1] - P[0], P[2] - P[0])) < 1e-12) continue;
            forEachTexelNear(
                P, g, dilation,
                [&](int x, int y, double d, const std::array<double, 3>& b) {
                    TexelHit& h = hits[g.at(x, y)];
                    if (!(float(d) < h.dist)) return;
                    const Vec2 q = P[0] * b[0] + P[1] * b[1] + P[2] * b[2];
                    h = {int32_t(f), float(d), {float(b[0]), float(b[1]), float(b[2])}, -1,
                         {float(x + 0.5 - q.x), float(y + 0.5 - q.y)}};
                },
                int(rowBegin), int(rowEnd));
        }
    });
}

// Islands: texel -> point X of the island's 3D triangle -> closest point of its faces (over
// facesNearTriangle, which holds the closest point of every X). Islands are measured on
// `threads` threads against the faces' hits, then merged in island order (a texel takes the
// nearest hit, the earlier island on ties), so the result does not depend on the thread count.
constexpr size_t kIslandTreeFrom = 64;  // island texels from which a FaceTree answers them

void rasterizeIslands(const TriMesh& mesh, const std::vector<BakeIsland>& islands, const Grid& g, double dilation,
                      int threads, std::vector<TexelHit>& hits) {
    for (size_t i = 0; i < islands.size(); ++i)
        if (islands[i].faces.empty()) throw InvalidInput("bake: island " + std::to_string(i) + " has no faces to sample");
    std::vector<std::vector<std::pair<size_t, TexelHit>>> found(islands.size());
    parallelFor(islands.size(), threads, [&](size_t i) {
        const BakeIsland& isl = islands[i];
        Vec2 P[3];
        for (int k = 0; k < 3; ++k) P[k] = {isl.uv[size_t(k)].x * g.size, isl.uv[size_t(k)].y * g.size};
        if (std::fabs(cross(P[1] - P[0], P[2] - P[0])) < 1e-12) return;
        // The texels first: a few of them are answered faster by BoxedFaces' scan than by
        // building a FaceTree (both give the scan's answer).
        struct Query {
            size_t texel;
            float d;
            Vec3 X;
        };
        std::vector<Query> queries;
        forEachTexelNear(P, g, dilation, [&](int x, int y, double d, const std::array<double, 3>& b) {
            if (!(float(d) < hits[g.at(x, y)].dist)) return;  // a face's hit is nearer
            queries.push_back({g.at(x, y), float(d), isl.position[0] * b[0] + isl.position[1] * b[1] + isl.position[2] * b[2]});
        });
        if (queries.empty()) return;
        auto answer = [&](const auto& near, auto&& closest) {
            for (const Query& q : queries) {
                std::array<double, 3> fb{};
                uint32_t f = closest(near, q.X, fb);
                found[i].push_back({q.texel, {int32_t(f), q.d, {float(fb[0]), float(fb[1]), float(fb[2])}, int32_t(i)}});
            }
        };
        std::vector<uint32_t> faces = facesNearTriangle(mesh, isl.faces, isl.position);
        if (queries.size() < kIslandTreeFrom) {
            uint32_t f = 0xffffffffu;  // the previous texel's face: the next texel's search bound
            answer(BoxedFaces(mesh, std::move(faces)), [&](const BoxedFaces& near, Vec3 X, std::array<double, 3>& fb) {
                near.closest(X, f, f, fb);
                return f;
            });
        } else {
            uint32_t hint = UINT32_MAX;  // the previous texel's answer: the next texel's start
            answer(FaceTree(mesh, std::move(faces)), [&](const FaceTree& near, Vec3 X, std::array<double, 3>& fb) {
                uint32_t f = 0;
                near.closest(X, f, fb, hint);
                return f;
            });
        }
    });
    for (const auto& list : found)
        for (const auto& [texel, hit] : list)
            if (hit.dist < hits[texel].dist) hits[texel] = hit;
}

// d(original UV)/d(texel x) and /d(texel y) at an island texel: texel -> 3D on the island's
// triangle (affine), then 3D -> original UV on face f (its tangent plane, affine).
void islandDerivatives(const TriMesh& mesh, const BakeIsland& isl, int size, uint32_t f, const Vec2 T[3], Vec2& dx, Vec2& dy) {
    dx = dy = Vec2{0, 0};
    Vec2 P[3];
    for (int k = 0; k < 3; ++k) P[k] = {isl.uv[size_t(k)].x * size, isl.uv[size_t(k)].y * size};
    Vec2 e1 = P[1] - P[0], e2 = P[2] - P[0];
    double det = cross(e1, e2);
    if (!(std::fabs(det) > 0)) return;
    Vec3 E1 = isl.position[1] - isl.position[0], E2 = isl.position[2] - isl.position[0];
    Vec3 dXdx = (E1 * e2.y - E2 * e1.y) * (1 / det), dXdy = (E2 * e1.x - E1 * e2.x) * (1 / det);
    const Tri& t = mesh.triangles[f];
    Vec3 a1 = mesh.positions[t[1]] - mesh.positions[t[0]], a2 = mesh.positions[t[2]] - mesh.positions[t[0]];
    double g11 = dot(a1, a1), g12 = dot(a1, a2), g22 = dot(a2, a2), gd = g11 * g22 - g12 * g12;
    if (!(gd > 0)) return;
    auto map = [&](Vec3 v) {
        double r1 = dot(a1, v), r2 = dot(a2, v);
        double al = (g22 * r1 - g12 * r2) / gd, be = (g11 * r2 - g12 * r1) / gd;
        return (T[1] - T[0]) * al + (T[2] - T[0]) * be;
    };
    dx = map(dXdx);
    dy = map(dXdy);
}

// What shading a texel reads: the asset, its decoded sources, the original's tangent frames
// (per UV set, for its normal maps) and the bake's UVs and islands.
struct ShadeContext {
    const Asset& asset;
    const std::vector<std::array<Vec2, 3>>& cornerUV;
    const std::vector<BakeIsland>& islands;
    std::vector<SourceTexture>& sources;
    const std::array<std::vector<Vec4>, 2>& tangents;
    int size;
    bool extendCharts;  // BakeOptions::extendCharts
};

const Material& materialOf(const ShadeContext& c, uint32_t f) {
    static const Material kDefault;
    const TriMesh& mesh = c.asset.mesh;
    int mi = f < mesh.triangleMaterial.size() ? mesh.triangleMaterial[f] : -1;
    return (mi >= 0 && mi < int(c.asset.materials.size())) ? c.asset.materials[size_t(mi)] : kDefault;
}

// True when two texture references read the same texels at the same UVs (the usual
// occlusion-in-red of a metallic-roughness texture): one lookup serves both.
bool sameLookup(const TextureRef& a, const TextureRef& b) {
    const TextureTransform &s = a.transform, &t = b.transform;
    const int setA = s.texCoord >= 0 ? s.texCoord : a.texCoord, setB = t.texCoord >= 0 ? t.texCoord : b.texCoord;
    return a.texture == b.texture && setA == setB && s.present == t.present && s.offset.x == t.offset.x &&
           s.offset.y == t.offset.y && s.rotation == t.rotation && s.scale.x == t.scale.x && s.scale.y == t.scale.y;
}

// The decoded MIP levels of image i, decoded by the first caller (others wait for it).
// \throw IOError (the image cannot be decoded).
const MipTexture& decodedSource(const Asset& asset, SourceTexture& src, size_t i) {
    std::call_once(src.decoded, [&] {
        DecodedImage img;
        std::string error;
        if (!decodeImage(asset.images[i], img, error, DecodeDepth::KeepEightBit))
            throw IOError("cannot decode for baking: " + error);
        src.mip = buildMipTexture(img);
    });
    return src.mip;
}

// The image a texture reference samples; -1 when it names no texture or image of the asset.
int imageOf(const Asset& asset, const TextureRef& ref) {
    if (ref.texture < 0 || ref.texture >= int(asset.textures.size())) return -1;
    const int i = asset.textures[size_t(ref.texture)].image;
    return i >= 0 && i < int(asset.images.size()) ? i : -1;
}

// The extension texture references that baking `ch` reads.
std::vector<const TextureRef*> extensionRefs(const MaterialExtensions& e, const BakeChannels& ch) {
    std::vector<const TextureRef*> refs;
    auto add = [&](bool on, std::initializer_list<const TextureRef*> list) {
        if (on) refs.insert(refs.end(), list);
    };
    add(ch.clearcoat, {&e.clearcoat.texture, &e.clearcoat.roughnessTexture});
    add(ch.clearcoatNormal, {&e.clearcoat.normalTexture});
    add(ch.sheen, {&e.sheen.colorTexture, &e.sheen.roughnessTexture});
    add(ch.specular, {&e.specular.texture, &e.specular.colorTexture});
    add(ch.transmission, {&e.transmission.texture, &e.volume.thicknessTexture});
    add(ch.iridescence, {&e.iridescence.texture, &e.iridescence.thicknessTexture});
    add(ch.diffuseTransmission, {&e.diffuseTransmission.texture, &e.diffuseTransmission.colorTexture});
    add(ch.anisotropy, {&e.anisotropy.texture});
    return refs;
}

// Decodes, on `threads` threads, every image that baking `ch` reads (each once, in any order:
// each is decoded on its own), so the shading threads do not wait on one another's decodes.
void decodeSources(const Asset& asset, std::vector<SourceTexture>& sources, const BakeChannels& ch, int threads) {
    std::vector<size_t> images;
    for (const Material& m : asset.materials) {
        const TextureRef* refs[] = {&m.baseColor, ch.orm ? &m.metallicRoughness : nullptr, ch.orm ? &m.occlusion : nullptr,
                                    ch.orm ? &m.specularGlossiness : nullptr, ch.emissive ? &m.emissive : nullptr,
                                    ch.normal ? &m.normal : nullptr};
        for (const TextureRef* ref : refs) {
            const int i = ref ? imageOf(asset, *ref) : -1;
            if (i >= 0 && sources[size_t(i)].used) images.push_back(size_t(i));
        }
        for (const TextureRef* ref : extensionRefs(m.ext, ch)) {
            const int i = imageOf(asset, *ref);
            if (i >= 0 && sources[size_t(i)].used) images.push_back(size_t(i));
        }
    }
    std::sort(images.begin(), images.end());
    images.erase(std::unique(images.begin(), images.end()), images.end());
    parallelFor(images.size(), threads, [&](size_t k) { decodedSource(asset, sources[images[k]], images[k]); });
}

// The filtered texel of texture reference `ref` at hit h (bilinear / trilinear over the texel's
// footprint, as a renderer samples it): RGBA as stored (no colour conversion; grey images fill
// RGB, images without alpha give alpha 1). False when the material has no such texture (or no UVs
// of its set): `out` is then untouched.
bool lookup(const ShadeContext& c, const TextureRef& ref, const TexelHit& h, float out[4]) {
    const TriMesh& mesh = c.asset.mesh;
    const uint32_t f = uint32_t(h.face);
    int ti = ref.texture;
    if (ti < 0 || ti >= int(c.asset.textures.size())) return false;
    const Texture& tex = c.asset.textures[size_t(ti)];
    int set = ref.transform.texCoord >= 0 ? ref.transform.texCoord : ref.texCoord;
    const std::vector<Vec2>& uvs = set == 1 ? mesh.wedges.uv1 : mesh.wedges.uv0;
    if (tex.image < 0 || size_t(tex.image) >= c.sources.size() || !c.sources[size_t(tex.image)].used || uvs.empty())
        return false;
    const Tri& cw = mesh.cornerWedges[f];
    Vec2 T[3];
    for (int k = 0; k < 3; ++k) T[k] = uvs[cw[size_t(k)]];
    Vec2 uv = T[0] * h.bary[0] + T[1] * h.bary[1] + T[2] * h.bary[2];
    // Jacobian d(uv)/d(texel) of the affine map atlas texel -> original UV.
    Vec2 dx, dy;
    if (h.island >= 0) {
        islandDerivatives(mesh, c.islands[size_t(h.island)], c.size, f, T, dx, dy);
    } else {
        Vec2 P[3];
        for (int k = 0; k < 3; ++k) P[k] = {c.cornerUV[f][size_t(k)].x * c.size, c.cornerUV[f][size_t(k)].y * c.size};
        Vec2 e1 = P[1] - P[0], e2 = P[2] - P[0], g1 = T[1] - T[0], g2 = T[2] - T[0];
        double det = cross(e1, e2);
        // inverse of [e1 e2] = 1/det [e2.y -e2.x; -e1.y e1.x]
        dx = (g1 * e2.y - g2 * e1.y) * (1 / det);   // d uv / d x
        dy = (g2 * e1.x - g1 * e2.x) * (1 / det);   // d uv / d y
        if (c.extendCharts) uv = uv + dx * double(h.beyond[0]) + dy * double(h.beyond[1]);
    }
    const std::array<double, 4> lm = textureTransformLinear(ref.transform);
    Vec2 st = applyTextureTransform(ref.transform, uv);
    Vec2 tdx = applyLinear(lm, dx);
    Vec2 tdy = applyLinear(lm, dy);
    Sampler smp;
    if (tex.sampler >= 0 && tex.sampler < int(c.asset.samplers.size())) smp = c.asset.samplers[size_t(tex.sampler)];
    FetchOptions opt;
    opt.wrapS = textureWrapFromGl(smp.wrapS);
    opt.wrapT = textureWrapFromGl(smp.wrapT);
    float r[4];
    fetchFiltered(decodedSource(c.asset, c.sources[size_t(tex.image)], size_t(tex.image)), opt, st, tdx, tdy, r);
    for (int i = 0; i < 4; ++i) out[i] = r[i];
    return true;
}

// The linear RGB of one covered texel: base colour factor x COLOR_0 x the filtered texture
// lookup at the original UV (derivatives from the texel -> original UV Jacobian). Returns
// whether a texture was sampled; `alpha` gets the same product's alpha.
bool shadeTexel(const ShadeContext& c, const TexelHit& h, double rgb[3], double* alpha = nullptr) {
    const TriMesh& mesh = c.asset.mesh;
    const uint32_t f = uint32_t(h.face);
    const Material& m = materialOf(c, f);
    rgb[0] = m.baseColorFactor.x;
    rgb[1] = m.baseColorFactor.y;
    rgb[2] = m.baseColorFactor.z;
    double a = m.baseColorFactor.w;
    const Tri& cw = mesh.cornerWedges[f];
    if (!mesh.wedges.color.empty()) {
        double col[4] = {0, 0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            const Vec4& vc = mesh.wedges.color[cw[size_t(k)]];
            col[0] += h.bary[size_t(k)] * vc.x;
            col[1] += h.bary[size_t(k)] * vc.y;
            col[2] += h.bary[size_t(k)] * vc.z;
            col[3] += h.bary[size_t(k)] * vc.w;
        }
        for (int i = 0; i < 3; ++i) rgb[i] *= col[i];
        a *= col[3];
    }
    float r[4];
    const bool textured = lookup(c, m.baseColor, h, r);
    if (textured) {
        for (int i = 0; i < 3; ++i) rgb[i] *= srgbToLinear(std::clamp(double(r[i]), 0.0, 1.0));
        a *= std::clamp(double(r[3]), 0.0, 1.0);
    }
    if (alpha) *alpha = m.alphaMode == AlphaMode::Opaque ? 1.0 : a;
    return textured;
}

// Occlusion, roughness and metallic of the original material at hit h (linear, [0,1]).
void shadeOrm(const ShadeContext& c, const TexelHit& h, double orm[3]) {
    const Material& m = materialOf(c, uint32_t(h.face));
    orm[0] = 1;
    orm[1] = m.roughnessFactor;
    orm[2] = m.metallicFactor;
    float r[4];
    const bool mr = lookup(c, m.metallicRoughness, h, r);
    if (mr) {
        orm[1] *= std::clamp(double(r[1]), 0.0, 1.0);
        orm[2] *= std::clamp(double(r[2]), 0.0, 1.0);
    }
    float sg[4];
    if (lookup(c, m.specularGlossiness, h, sg)) orm[1] = 1 - m.glossinessFactor * std::clamp(double(sg[3]), 0.0, 1.0);
    if ((mr && sameLookup(m.occlusion, m.metallicRoughness)) || lookup(c, m.occlusion, h, r))
        orm[0] = 1 + m.occlusion.scale * (std::clamp(double(r[0]), 0.0, 1.0) - 1);
    for (int i = 0; i < 3; ++i) orm[i] = std::clamp(orm[i], 0.0, 1.0);
}

// Linear emissive radiance of the original material at hit h (may exceed 1 with emissive strength).
void shadeEmissive(const ShadeContext& c, const TexelHit& h, double e[3]) {
    const Material& m = materialOf(c, uint32_t(h.face));
    const Vec3 f = m.emissiveFactor * m.emissiveStrength;
    e[0] = f.x;
    e[1] = f.y;
    e[2] = f.z;
    float r[4];
    if ((e[0] > 0 || e[1] > 0 || e[2] > 0) && lookup(c, m.emissive, h, r))
        for (int i = 0; i < 3; ++i) e[i] *= srgbToLinear(std::clamp(double(r[i]), 0.0, 1.0));
}

// The original's normal at hit h, world space: interpolated normal (the face's when the file has
// none) perturbed by normal map `map` of its material in the original tangent frame.
Vec3 interpolatedNormal(const ShadeContext& c, const TexelHit& h) {
    const TriMesh& mesh = c.asset.mesh;
    const uint32_t f = uint32_t(h.face);
    const Tri& t = mesh.triangles[f];
    const Tri& cw = mesh.cornerWedges[f];
    const Vec3 face = normalize(cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]));
    Vec3 N = face;
    if (!mesh.wedges.normal.empty()) {
        Vec3 n{};
        for (int k = 0; k < 3; ++k) n += mesh.wedges.normal[cw[size_t(k)]] * h.bary[size_t(k)];
        if (length(n) > 1e-12) N = normalize(n);
    }
    return N;
}

// The original's tangent T and bitangent B at hit h around normal N, for UV set `set` (the file's
// TANGENT, else the frames BakeSources computed). False when there is none.
bool originalTangentFrame(const ShadeContext& c, const TexelHit& h, int set, Vec3 N, TangentFrame& frame) {
    const TriMesh& mesh = c.asset.mesh;
    const Tri& cw = mesh.cornerWedges[uint32_t(h.face)];
    const std::vector<Vec4>& tangents = mesh.wedges.tangent.empty() ? c.tangents[set == 1 ? 1 : 0] : mesh.wedges.tangent;
    if (tangents.empty()) return false;
    return tangentFrameAt(N, {tangents[cw[0]], tangents[cw[1]], tangents[cw[2]]}, {h.bary[0], h.bary[1], h.bary[2]}, frame);
}

Vec3 perturbedNormal(const ShadeContext& c, const TexelHit& h, const TextureRef& map) {
    const Vec3 N = interpolatedNormal(c, h);
    float r[4];
    if (!lookup(c, map, h, r)) return N;
    const int set = map.transform.texCoord >= 0 ? map.transform.texCoord : map.texCoord;
    TangentFrame frame;
    if (!originalTangentFrame(c, h, set, N, frame)) return N;
    const double s = map.scale;
    const Vec3 out = normalize(frame.toWorld({(2.0 * r[0] - 1) * s, (2.0 * r[1] - 1) * s, 2.0 * r[2] - 1}));
    return length(out) > 0.5 ? out : N;
}

// The original's shading normal at hit h (its material's normal map).
Vec3 shadingNormal(const ShadeContext& c, const TexelHit& h) { return perturbedNormal(c, h, materialOf(c, uint32_t(h.face)).normal); }

// The original's clearcoat normal at hit h (the coat's own normal map; without one the
// interpolated normal, as glTF defines it).
Vec3 clearcoatNormal(const ShadeContext& c, const TexelHit& h) {
    return perturbedNormal(c, h, materialOf(c, uint32_t(h.face)).ext.clearcoat.normalTexture);
}

// The original's anisotropy at hit h: its strength (0 where the material has none) and its
// direction in world space (the tangent rotated by anisotropyRotation, then by the texture's RG
// direction, in the original tangent frame of the texture's UV set).
double anisotropyAt(const ShadeContext& c, const TexelHit& h, Vec3& direction) {
    const AnisotropyExtension& e = materialOf(c, uint32_t(h.face)).ext.anisotropy;
    direction = {};
    if (!e.present) return 0;
    double strength = e.strength, dx = 1, dy = 0;
    float r[4];
    if (lookup(c, e.texture, h, r)) {
        dx = 2.0 * r[0] - 1;
        dy = 2.0 * r[1] - 1;
        strength *= std::clamp(double(r[2]), 0.0, 1.0);
    }
    const double cr = std::cos(e.rotation), sr = std::sin(e.rotation);
    const double x = cr * dx - sr * dy, y = sr * dx + cr * dy;
    const int set = e.texture.transform.texCoord >= 0 ? e.texture.transform.texCoord : e.texture.texCoord;
    const Vec3 N = interpolatedNormal(c, h);
    TangentFrame frame;
    if (!originalTangentFrame(c, h, set, N, frame)) return 0;
    direction = frame.toWorld({x, y, 0});
    return std::clamp(strength, 0.0, 1.0);
}

// Extension channels: each fills v (3 or 4 values, BakeChannels' packing) with the original
// material at hit h; colours linear here (bakeMaterial encodes them as sRGB after the fill).
// An extension the material lacks reads as its neutral value (the struct's defaults).

// Channel `k` of texture `ref` at h, clamped to [0,1]; 1 without a texture.
double texel(const ShadeContext& c, const TextureRef& ref, const TexelHit& h, int k) {
    float r[4];
    return lookup(c, ref, h, r) ? std::clamp(double(r[k]), 0.0, 1.0) : 1.0;
}

// A colour factor x the linear RGB of an sRGB texture `ref` at h.
void texelColor(const ShadeContext& c, const TextureRef& ref, const TexelHit& h, Vec3 factor, double* rgb) {
    float r[4];
    const bool t = lookup(c, ref, h, r);
    const double f[3] = {factor.x, factor.y, factor.z};
    for (int i = 0; i < 3; ++i) rgb[i] = f[i] * (t ? srgbToLinear(std::clamp(double(r[i]), 0.0, 1.0)) : 1.0);
}

void shadeClearcoat(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const ClearcoatExtension& e = materialOf(c, uint32_t(h.face)).ext.clearcoat;
    v[0] = e.factor * texel(c, e.texture, h, 0);
    v[1] = e.present ? e.roughnessFactor * texel(c, e.roughnessTexture, h, 1) : ch.clearcoatRoughnessFill;
    v[2] = 0;
}

void shadeSheen(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const SheenExtension& e = materialOf(c, uint32_t(h.face)).ext.sheen;
    texelColor(c, e.colorTexture, h, e.colorFactor, v);
    v[3] = e.present ? e.roughnessFactor * texel(c, e.roughnessTexture, h, 3) : ch.sheenRoughnessFill;
}

void shadeSpecular(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const SpecularExtension& e = materialOf(c, uint32_t(h.face)).ext.specular;
    texelColor(c, e.colorTexture, h, e.colorFactor * (1 / ch.specularColorScale), v);
    v[3] = e.factor * texel(c, e.texture, h, 3);
}

void shadeTransmission(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const MaterialExtensions& e = materialOf(c, uint32_t(h.face)).ext;
    v[0] = e.transmission.factor * texel(c, e.transmission.texture, h, 0);
    v[1] = e.volume.thicknessFactor * texel(c, e.volume.thicknessTexture, h, 1) / ch.thicknessScale;
    v[2] = 0;
}

void shadeIridescence(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const IridescenceExtension& e = materialOf(c, uint32_t(h.face)).ext.iridescence;
    v[0] = e.factor * texel(c, e.texture, h, 0);
    float r[4];
    // The thickness in nm (glTF: the maximum without a thickness texture), then its place in the
    // chain's range. A part without iridescence takes the range's minimum.
    const double nm = !e.present ? ch.iridescenceThicknessMin
                      : lookup(c, e.thicknessTexture, h, r)
                          ? e.thicknessMinimum + (e.thicknessMaximum - e.thicknessMinimum) * std::clamp(double(r[1]), 0.0, 1.0)
                          : e.thicknessMaximum;
    const double span = ch.iridescenceThicknessMax - ch.iridescenceThicknessMin;
    v[1] = span > 0 ? (nm - ch.iridescenceThicknessMin) / span : 0;
    v[2] = 0;
}

void shadeDiffuseTransmission(const ShadeContext& c, const BakeChannels&, const TexelHit& h, double* v) {
    const DiffuseTransmissionExtension& e = materialOf(c, uint32_t(h.face)).ext.diffuseTransmission;
    texelColor(c, e.colorTexture, h, e.colorFactor, v);
    v[3] = e.factor * texel(c, e.texture, h, 3);
}

// One extension image of a bake: whether it is asked for, where it goes, its values per texel,
// how a texel is shaded, and whether its RGB is a colour (stored sRGB).
struct ExtensionImage {
    bool on;
    std::vector<float>* out;
    size_t comps;
    void (*shade)(const ShadeContext&, const BakeChannels&, const TexelHit&, double*);
    bool srgb;
};

// A texel's place on the target surface: the target triangle and barycentrics (-1 = none).
struct TargetHit {
    int32_t tri = -1;
    float dist = 1e30f;
    std::array<float, 3> bary{};
};

std::vector<TargetHit> rasterizeTarget(const BakeTarget& target, const Grid& g) {
    std::vector<TargetHit> hits(size_t(g.w) * size_t(g.h));
    for (size_t t = 0; t < target.uv.size(); ++t) {
        Vec2 P[3];
        for (int k = 0; k < 3; ++k) P[k] = {target.uv[t][size_t(k)].x * g.size, target.uv[t][size_t(k)].y * g.size};
        if (std::fabs(cross(P[1] - P[0], P[2] - P[0])) < 1e-12) continue;
        forEachTexelNear(P, g, target.reach, [&](int x, int y, double d, const std::array<double, 3>& b) {
            TargetHit& h = hits[g.at(x, y)];
            if (float(d) < h.dist) h = {int32_t(t), float(d), {float(b[0]), float(b[1]), float(b[2])}};
        });
    }
    return hits;
}

// The target's tangent frame at hit th (tangents.h); false without a target, a hit or a usable
// frame.
bool targetFrame(const BakeTarget* targetOrNull, const TargetHit& th, TangentFrame& frame) {
    if (!targetOrNull || th.tri < 0) return false;
    const BakeTarget& target = *targetOrNull;
    Vec3 N{};
    for (size_t k = 0; k < 3; ++k) N += target.normal[size_t(th.tri)][k] * th.bary[k];
    N = normalize(N);
    if (!(length(N) > 0.5)) return false;
    return tangentFrameAt(N, target.tangent[size_t(th.tri)], {th.bary[0], th.bary[1], th.bary[2]}, frame);
}

// World normal N expressed in the target's tangent frame at hit th, as an encoded colour; the
// unperturbed (0, 0, 1) without a target or a hit.
void encodeInTarget(const BakeTarget* targetOrNull, const TargetHit& th, Vec3 N, double rgb[3]) {
    Vec3 n{0, 0, 1};
    TangentFrame frame;
    if (targetFrame(targetOrNull, th, frame)) {
        n = normalize(frame.toTangent(N));
        if (!(length(n) > 0.5)) n = {0, 0, 1};
    }
    rgb[0] = n.x * 0.5 + 0.5;
    rgb[1] = n.y * 0.5 + 0.5;
    rgb[2] = n.z * 0.5 + 0.5;
}

// An anisotropy texel for the target: RG = world direction D in the target's tangent plane at
// th (unit, encoded x 0.5 + 0.5; the tangent without a target, a hit or a direction), B = strength.
void encodeAnisotropyInTarget(const BakeTarget* targetOrNull, const TargetHit& th, Vec3 D, double strength, double rgb[3]) {
    double x = 1, y = 0;
    TangentFrame frame;
    if (targetFrame(targetOrNull, th, frame)) {
        const Vec3 d = frame.toTangent(D);
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

// Rounds values in [0,1] to 8-bit steps, as they will be stored.
// Chunks of the per-texel loops after the shading (each texel alone: any thread count).
constexpr size_t kTexelChunk = size_t(1) << 16;

void quantize(std::vector<float>& v, int threads) {
    parallelChunks(v.size(), kTexelChunk, threads, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i) v[i] = float(std::lround(std::clamp(double(v[i]), 0.0, 1.0) * 255)) / 255.0f;
    });
}

}  // namespace

struct BakeSources::Impl {
    const Asset& asset;
    std::vector<SourceTexture> sources;  // per image
    std::array<std::vector<Vec4>, 2> tangents;  // per UV set a normal map uses, when the file has no TANGENT
    explicit Impl(const Asset& a) : asset(a), sources(a.images.size()) {
        for (const Material& m : asset.materials) {
            std::vector<const TextureRef*> refs = textureRefs(m.ext);
            refs.insert(refs.end(), {&m.baseColor, &m.metallicRoughness, &m.occlusion, &m.emissive, &m.normal, &m.specularGlossiness});
            for (const TextureRef* ref : refs) {
                const int i = imageOf(asset, *ref);
                if (i >= 0) sources[size_t(i)].used = true;
            }
        }
        if (asset.mesh.wedges.tangent.empty())
            for (const Material& m : asset.materials)
                for (const TextureRef* map : {&m.normal, &m.ext.clearcoat.normalTexture, &m.ext.anisotropy.texture}) {
                    // Anisotropy needs the frame even without a texture (its rotation is relative to it).
                    if (map->texture < 0 && !(map == &m.ext.anisotropy.texture && m.ext.anisotropy.present)) continue;
                    const int set = (map->transform.texCoord >= 0 ? map->transform.texCoord : map->texCoord) == 1 ? 1 : 0;
                    if (tangents[size_t(set)].empty()) tangents[size_t(set)] = computeWedgeTangents(asset.mesh, set);
                }
    }
};

struct BakeSourcesAccess {
    static std::vector<SourceTexture>& sources(const BakeSources& s) { return s.impl_->sources; }
    static const std::array<std::vector<Vec4>, 2>& tangents(const BakeSources& s) { return s.impl_->tangents; }
};

BakeSources::BakeSources(const Asset& asset) : impl_(std::make_unique<Impl>(asset)) {}
BakeSources::~BakeSources() = default;
const Asset& BakeSources::asset() const { return impl_->asset; }

BakeResult bakeBaseColor(const Asset& asset, const std::vector<std::array<Vec2, 3>>& cornerUV, const BakeOptions& o,
                         const std::vector<BakeIsland>& islands) {
    auto t0 = std::chrono::steady_clock::now();
    BakeSources sources(asset);
    BakeResult res = bakeBaseColor(sources, cornerUV, o, islands);
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

BakeResult bakeBaseColor(const BakeSources& bs, const std::vector<std::array<Vec2, 3>>& cornerUV, const BakeOptions& o,
                         const std::vector<BakeIsland>& islands) {
    BakeOptions base = o;
    base.channels = BakeChannels{};
    return bakeMaterial(bs, cornerUV, base, islands, nullptr);
}

BakeResult bakeMaterial(const BakeSources& bs, const std::vector<std::array<Vec2, 3>>& cornerUV, const BakeOptions& o,
                        const std::vector<BakeIsland>& islands, const BakeTarget* target) {
    auto t0 = std::chrono::steady_clock::now();
    const Asset& asset = bs.asset();
    std::vector<SourceTexture>& sources = BakeSourcesAccess::sources(bs);
    const TriMesh& mesh = asset.mesh;
    if (cornerUV.size() != mesh.triangleCount()) throw InvalidInput("bake: cornerUV size differs from the face count");
    if (o.size < 1) throw InvalidInput("bake: size must be >= 1");
    if (o.width < 0 || o.width > o.size || o.height < 0 || o.height > o.size)
        throw InvalidInput("bake: width and height must be in [0, size]");
    if (target && (target->normal.size() != target->uv.size() || target->tangent.size() != target->uv.size()))
        throw InvalidInput("bake: target UVs, normals and tangents differ in size");
    const Grid g{o.size, o.width > 0 ? o.width : o.size, o.height > 0 ? o.height : o.size};
    const BakeChannels& ch = o.channels;
    BakeResult res;

    std::vector<TexelHit> hits;
    rasterizeTriangles(mesh, cornerUV, g, o.dilation, o.threads, hits);
    rasterizeIslands(mesh, islands, g, o.dilation, o.threads, hits);
    std::vector<TargetHit> targetHits;
    if ((ch.normal || ch.clearcoatNormal || ch.anisotropy) && target) targetHits = rasterizeTarget(*target, g);

    decodeSources(asset, sources, ch, o.threads);
    // Shade: linear RGB + coverage, rows in parallel (each texel depends only on its hit).
    const size_t texels = size_t(g.w) * size_t(g.h);
    std::vector<float> px(texels * 3, 0.0f);
    if (ch.alpha) res.alpha.assign(texels, 0.0f);
    if (ch.orm) res.orm.assign(texels * 3, 0.0f);
    if (ch.emissive) res.emissive.assign(texels * 3, 0.0f);
    if (ch.normal) res.normal.assign(texels * 3, 0.0f);
    const ExtensionImage extensionImages[] = {
        {ch.clearcoat, &res.clearcoat, 3, shadeClearcoat, false},
        {ch.sheen, &res.sheen, 4, shadeSheen, true},
        {ch.specular, &res.specular, 4, shadeSpecular, true},
        {ch.transmission, &res.transmission, 3, shadeTransmission, false},
        {ch.iridescence, &res.iridescence, 3, shadeIridescence, false},
        {ch.diffuseTransmission, &res.diffuseTransmission, 4, shadeDiffuseTransmission, true},
    };
    for (const ExtensionImage& e : extensionImages)
        if (e.on) e.out->assign(texels * e.comps, 0.0f);
    if (ch.clearcoatNormal) res.clearcoatNormal.assign(texels * 3, 0.0f);
    if (ch.anisotropy) res.anisotropy.assign(texels * 3, 0.0f);
    std::vector<uint8_t> covered(texels, 0);
    std::vector<size_t> rowCovered(size_t(g.h), 0), rowIsland(size_t(g.h), 0), rowLookups(size_t(g.h), 0);
    const ShadeContext ctx{asset, cornerUV, islands, sources, BakeSourcesAccess::tangents(bs), g.size, o.extendCharts};
    parallelFor(size_t(g.h), o.threads, [&](size_t y) {
        for (int x = 0; x < g.w; ++x) {
            const size_t i = g.at(x, int(y));
            const TexelHit& h = hits[i];
            if (h.face < 0) continue;
            covered[i] = 1;
            ++rowCovered[y];
            if (h.island >= 0) ++rowIsland[y];
            double rgb[3], a = 1;
            if (shadeTexel(ctx, h, rgb, &a)) ++rowLookups[y];
            for (size_t c = 0; c < 3; ++c) px[i * 3 + c] = float(rgb[c]);
            if (ch.alpha) res.alpha[i] = float(a);
            double v[3];
            if (ch.orm) {
                shadeOrm(ctx, h, v);
                for (size_t c = 0; c < 3; ++c) res.orm[i * 3 + c] = float(v[c]);
            }
            if (ch.emissive) {
                shadeEmissive(ctx, h, v);
                for (size_t c = 0; c < 3; ++c) res.emissive[i * 3 + c] = float(v[c]);
            }
            if (ch.normal) {
                const Vec3 N = shadingNormal(ctx, h);
                encodeInTarget(target, target ? targetHits[i] : TargetHit{}, N, v);
                for (size_t c = 0; c < 3; ++c) res.normal[i * 3 + c] = float(v[c]);
            }
            for (const ExtensionImage& e : extensionImages) {
                if (!e.on) continue;
                double x[4];
                e.shade(ctx, ch, h, x);
                for (size_t c = 0; c < e.comps; ++c) (*e.out)[i * e.comps + c] = float(x[c]);
            }
            if (ch.clearcoatNormal) {
                encodeInTarget(target, target ? targetHits[i] : TargetHit{}, clearcoatNormal(ctx, h), v);
                for (size_t c = 0; c < 3; ++c) res.clearcoatNormal[i * 3 + c] = float(v[c]);
            }
            if (ch.anisotropy) {
                Vec3 D;
                const double strength = anisotropyAt(ctx, h, D);
                encodeAnisotropyInTarget(target, target ? targetHits[i] : TargetHit{}, D, strength, v);
                for (size_t c = 0; c < 3; ++c) res.anisotropy[i * 3 + c] = float(v[c]);
            }
        }
    });
    for (size_t y = 0; y < size_t(g.h); ++y) {
        res.coveredTexels += rowCovered[y];
        res.islandTexels += rowIsland[y];
        res.texturedLookups += rowLookups[y];
    }
    // Gap fill: pull-push with coverage, each channel image alone.
    if (o.fillGaps && res.coveredTexels > 0) {
        hits = {};  // shaded: freed before the fill allocates its pyramids
        targetHits = {};
        pullPushFill(px, 3, covered, g.w, g.h, o.threads);
        for (std::vector<float>* c : {&res.alpha, &res.orm, &res.emissive, &res.normal, &res.clearcoatNormal, &res.anisotropy})
            if (!c->empty()) pullPushFill(*c, c == &res.alpha ? 1 : 3, covered, g.w, g.h, o.threads);
        for (const ExtensionImage& e : extensionImages)
            if (e.on) pullPushFill(*e.out, int(e.comps), covered, g.w, g.h, o.threads);
    }
    for (const ExtensionImage& e : extensionImages) {
        if (!e.on) continue;
        if (e.srgb)
            parallelChunks(texels, kTexelChunk, o.threads, [&](size_t begin, size_t end, size_t) {
                for (size_t i = begin; i < end; ++i)
                    for (size_t c = 0; c < 3; ++c) {
                        float& x = (*e.out)[i * e.comps + c];
                        x = float(linearToSrgb(std::clamp(double(x), 0.0, 1.0)));
                    }
            });
        quantize(*e.out, o.threads);
    }
    if (ch.alpha) quantize(res.alpha, o.threads);
    if (ch.orm) quantize(res.orm, o.threads);
    if (ch.emissive) {
        double peak = 0;
        for (float v : res.emissive) peak = std::max(peak, double(v));
        res.emissiveScale = peak > 1 ? peak : 1;
        parallelChunks(res.emissive.size(), kTexelChunk, o.threads, [&](size_t begin, size_t end, size_t) {
            for (size_t i = begin; i < end; ++i) res.emissive[i] = float(linearToSrgb(res.emissive[i] / res.emissiveScale));
        });
        quantize(res.emissive, o.threads);
    }
    if (ch.anisotropy) quantize(res.anisotropy, o.threads);
    for (std::vector<float>* normals : {&res.normal, &res.clearcoatNormal}) {
        if (normals->empty()) continue;
        parallelChunks(texels, kTexelChunk, o.threads, [&](size_t begin, size_t end, size_t) {
            for (size_t i = begin; i < end; ++i) {
                float* n = &(*normals)[i * 3];
                Vec3 d = normalize(Vec3{2.0 * n[0] - 1, 2.0 * n[1] - 1, 2.0 * n[2] - 1});
                if (!(length(d) > 0.5)) d = {0, 0, 1};
                n[0] = float(d.x * 0.5 + 0.5);
                n[1] = float(d.y * 0.5 + 0.5);
                n[2] = float(d.z * 0.5 + 0.5);
            }
        });
        quantize(*normals, o.threads);
    }

    // Encode: sRGB 8-bit RGB.
    res.pixels.resize(texels * 3);
    std::vector<uint8_t> rgb8(res.pixels.size());
    parallelChunks(texels, kTexelChunk, o.threads, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i)
            for (int c = 0; c < 3; ++c) {
                double v = linearToSrgb(double(px[i * 3 + size_t(c)]));
                uint8_t b = uint8_t(std::lround(v * 255));
                rgb8[i * 3 + size_t(c)] = b;
                res.pixels[i * 3 + size_t(c)] = float(b) / 255.0f;
            }
    });
    if (o.encodePng) res.image = encodePng(rgb8, g.w, g.h, "lodbake_baseColor");
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

std::vector<BakeIsland> layoutBakeIslands(const TriMesh& mesh, const ChartLayout& layout) {
    std::vector<BakeIsland> out;
    if (layout.islands.empty()) return out;
    std::vector<std::vector<uint32_t>> vertexCharts(mesh.vertexCount());
    std::vector<uint32_t> unindexed;  // faces with a repeated corner index: FaceGrid leaves them out
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f) {
        const uint32_t c = layout.faceChart.at(f);
        if (c >= layout.chartCount) throw InvalidInput("layout: chart id out of range");
        for (uint32_t v : mesh.triangles[f]) vertexCharts[v].push_back(c);
        if (degenerateIndices(mesh.triangles[f])) unindexed.push_back(f);
    }
    // An island samples the faces of every chart that holds one of its corners, but the bake
    // (facesNearTriangle) keeps only those whose box lies within d0 + 2r of the island's centroid
    // c (d0: c's distance to them, r: the largest |corner - c|). A corner lies on such a face, so
    // d0 <= r: the faces within 4r of c hold all it keeps, in the same order (by chart, then id),
    // and the island's face list stays proportional to its own size, not its charts'.
    const FaceGrid grid(mesh);
    for (size_t i = 0; i < layout.islands.size(); ++i) {
        const LayoutIsland& isl = layout.islands[i];
        BakeIsland b;
        b.uv = isl.uv;
        std::vector<uint32_t> charts;
        for (size_t k = 0; k < 3; ++k) {
            if (isl.vertices[k] >= mesh.vertexCount()) throw InvalidInput("layout island " + std::to_string(i) + ": vertex out of range");
            b.position[k] = mesh.positions[isl.vertices[k]];
            charts.insert(charts.end(), vertexCharts[isl.vertices[k]].begin(), vertexCharts[isl.vertices[k]].end());
        }
        std::sort(charts.begin(), charts.end());
        charts.erase(std::unique(charts.begin(), charts.end()), charts.end());
        if (charts.empty()) throw InvalidInput("layout island " + std::to_string(i) + " touches no chart");
        const Vec3 c = (b.position[0] + b.position[1] + b.position[2]) * (1.0 / 3);
        double r = 0;
        for (const Vec3& q : b.position) r = std::max(r, length(q - c));
        const double reach = 4 * r * (1 + 1e-6) + 1e-9 * (1 + length(c));
        std::vector<uint32_t> near = grid.facesIn(c - Vec3{reach, reach, reach}, c + Vec3{reach, reach, reach});
        near.insert(near.end(), unindexed.begin(), unindexed.end());
        for (uint32_t f : near)
            if (std::binary_search(charts.begin(), charts.end(), layout.faceChart[f]) && boxDistance2(faceBox(mesh, f), c) <= reach * reach)
                b.faces.push_back(f);
        std::sort(b.faces.begin(), b.faces.end(), [&](uint32_t x, uint32_t y) {
            return std::make_pair(layout.faceChart[x], x) < std::make_pair(layout.faceChart[y], y);
        });
        b.faces.erase(std::unique(b.faces.begin(), b.faces.end()), b.faces.end());
        if (b.faces.empty()) throw InvalidInput("layout island " + std::to_string(i) + " touches no chart");
        out.push_back(std::move(b));
    }
    return out;
}

}  // namespace lodbake
