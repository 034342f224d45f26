// Bake: original appearance -> new atlas (DESIGN.md "Bake and gap fill"). This file is the bake
// as a script; each step lives in its own file:
//
//   BakeSources (bake_sources.cpp: once per asset, each image a bake reads decoded once to MIP
//   levels, texture_fetch.h, and kept for every later bake)
//   -> rasterizeTriangles (texel_raster.cpp: original faces in atlas texel space, 1-texel
//   conservative dilation, the nearest face wins a texel)
//   -> rasterizeIslands (island_bake.cpp: level triangles parameterize could not keep injective
//   in their chart; their texels sample the original surface at the closest point)
//   -> rasterizeTarget (bake_target.cpp: the level triangle under each texel, whose tangent frame
//   the normal channels are expressed in)
//   -> shade (texel_shading.cpp: base colour factor x filtered texture fetch at the original UV
//   with the footprint from the UV Jacobian x COLOR_0, in linear space, and the other channels;
//   rows on BakeOptions::threads threads)
//   -> fill gaps (pullPushFill with coverage, every channel image in one pass) -> encode and
//   quantise each channel as it is stored -> encode PNG (unless the caller encodes).
//
// Only the width x height region of the size x size grid is baked.
#include "lodbake/bake/bake.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <vector>

#include "bake/bake_sources.h"
#include "bake/bake_target.h"
#include "bake/island_bake.h"
#include "bake/srgb_bytes.h"
#include "bake/texel_raster.h"
#include "bake/texel_shading.h"
#include "lodbake/bake/texture_fetch.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/parallel.h"
#include "lodbake/core/touched_fill.h"
#include "lodbake/texture/codec.h"
#include "lodbake/texture/color_space.h"

namespace lodbake {

using namespace bake_detail;

namespace {

// One extension image of a bake: whether it is asked for, where it goes, its values per texel,
// how a texel is shaded, and whether its RGB is a colour (stored sRGB).
struct ExtensionImage {
    bool on;
    std::vector<float>* out;
    size_t comps;
    void (*shade)(const ShadeContext&, const BakeChannels&, const TexelHit&, double*);
    bool srgb;
};

// Chunks of the per-texel loops after the shading (each texel alone: any thread count).
constexpr size_t kTexelChunk = size_t(1) << 16;

// Rounds values in [0,1] to 8-bit steps, as they will be stored: lround of y = v x 255, taken as
// floor(y + 0.5) where y >= 0 (y holds at most 32 significant bits below 256, so y + 0.5 is exact
// from y >= 0.25 on, and below it both give 0; a NaN keeps lround).
void quantize(std::vector<float>& v, int threads) {
    parallelChunks(v.size(), kTexelChunk, threads, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i) {
            const double y = std::clamp(double(v[i]), 0.0, 1.0) * 255;
            v[i] = float(y >= 0 ? long(y + 0.5) : std::lround(y)) / 255.0f;
        }
    });
}

}  // namespace

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
    const TexelRegion g{o.size, o.width > 0 ? o.width : o.size, o.height > 0 ? o.height : o.size};
    const BakeChannels& ch = o.channels;
    BakeResult res;

    std::vector<TexelHit> hits;
    rasterizeTriangles(mesh, cornerUV, g, o.dilation, o.threads, hits);
    rasterizeIslands(mesh, islands, g, o.dilation, o.threads, hits);
    std::vector<TargetHit> targetHits;
    const bool directions = ch.normal || ch.clearcoatNormal || ch.anisotropy;
    if (directions && target) targetHits = rasterizeTarget(*target, g, o.threads);

    decodeSources(asset, sources, ch, o.threads);
    // Shade: linear RGB + coverage, rows in parallel (each texel depends only on its hit).
    const size_t texels = size_t(g.w) * size_t(g.h);
    std::vector<float> px;
    assignTouched(px, texels * 3, 0.0f, o.threads);
    if (ch.alpha) assignTouched(res.alpha, texels, 0.0f, o.threads);
    if (ch.orm) assignTouched(res.orm, texels * 3, 0.0f, o.threads);
    if (ch.emissive) assignTouched(res.emissive, texels * 3, 0.0f, o.threads);
    if (ch.normal) assignTouched(res.normal, texels * 3, 0.0f, o.threads);
    const ExtensionImage extensionImages[] = {
        {ch.clearcoat, &res.clearcoat, 3, shadeClearcoat, false},
        {ch.sheen, &res.sheen, 4, shadeSheen, true},
        {ch.specular, &res.specular, 4, shadeSpecular, true},
        {ch.transmission, &res.transmission, 3, shadeTransmission, false},
        {ch.iridescence, &res.iridescence, 3, shadeIridescence, false},
        {ch.diffuseTransmission, &res.diffuseTransmission, 4, shadeDiffuseTransmission, true},
    };
    for (const ExtensionImage& e : extensionImages)
        if (e.on) assignTouched(*e.out, texels * e.comps, 0.0f, o.threads);
    if (ch.clearcoatNormal) assignTouched(res.clearcoatNormal, texels * 3, 0.0f, o.threads);
    if (ch.anisotropy) assignTouched(res.anisotropy, texels * 3, 0.0f, o.threads);
    std::vector<uint8_t> covered;
    assignTouched(covered, texels, uint8_t(0), o.threads);
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
            // The target's frame at the texel, once for every direction channel.
            TangentFrame frame;
            const TangentFrame* frameOrNull =
                directions && targetFrame(target, target ? targetHits[i] : TargetHit{}, frame) ? &frame : nullptr;
            const Vec3 interpolated = directions ? interpolatedNormal(ctx, h) : Vec3{};
            if (ch.orm) {
                shadeOrm(ctx, h, v);
                for (size_t c = 0; c < 3; ++c) res.orm[i * 3 + c] = float(v[c]);
            }
            if (ch.emissive) {
                shadeEmissive(ctx, h, v);
                for (size_t c = 0; c < 3; ++c) res.emissive[i * 3 + c] = float(v[c]);
            }
            if (ch.normal) {
                const Vec3 N = shadingNormal(ctx, h, interpolated);
                encodeInFrame(frameOrNull, N, v);
                for (size_t c = 0; c < 3; ++c) res.normal[i * 3 + c] = float(v[c]);
            }
            for (const ExtensionImage& e : extensionImages) {
                if (!e.on) continue;
                double x[4];
                e.shade(ctx, ch, h, x);
                for (size_t c = 0; c < e.comps; ++c) (*e.out)[i * e.comps + c] = float(x[c]);
            }
            if (ch.clearcoatNormal) {
                encodeInFrame(frameOrNull, clearcoatNormal(ctx, h, interpolated), v);
                for (size_t c = 0; c < 3; ++c) res.clearcoatNormal[i * 3 + c] = float(v[c]);
            }
            if (ch.anisotropy) {
                Vec3 D;
                const double strength = anisotropyAt(ctx, h, interpolated, D);
                encodeAnisotropyInFrame(frameOrNull, D, strength, v);
                for (size_t c = 0; c < 3; ++c) res.anisotropy[i * 3 + c] = float(v[c]);
            }
        }
    });
    for (size_t y = 0; y < size_t(g.h); ++y) {
        res.coveredTexels += rowCovered[y];
        res.islandTexels += rowIsland[y];
        res.texturedLookups += rowLookups[y];
    }
    // Gap fill: pull-push with coverage, every channel image in one pass (each as if alone).
    if (o.fillGaps && res.coveredTexels > 0) {
        hits = {};  // shaded: freed before the fill allocates its pyramids
        targetHits = {};
        std::vector<FillImage> fill{{&px, 3}};
        for (std::vector<float>* c : {&res.alpha, &res.orm, &res.emissive, &res.normal, &res.clearcoatNormal, &res.anisotropy})
            if (!c->empty()) fill.push_back({c, c == &res.alpha ? 1 : 3});
        for (const ExtensionImage& e : extensionImages)
            if (e.on) fill.push_back({e.out, int(e.comps)});
        pullPushFill(fill, covered, g.w, g.h, o.threads);
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

    // Encode: sRGB 8-bit RGB (srgb_bytes.h: the formula's bytes by table).
    assignTouched(res.pixels, texels * 3, 0.0f, o.threads);
    std::vector<uint8_t> rgb8;
    assignTouched(rgb8, res.pixels.size(), uint8_t(0), o.threads);
    const SrgbBytes& srgb = srgbBytes();
    parallelChunks(texels * 3, kTexelChunk, o.threads, [&](size_t begin, size_t end, size_t) {
        for (size_t i = begin; i < end; ++i) {
            const uint8_t b = srgb(px[i]);
            rgb8[i] = b;
            res.pixels[i] = float(b) / 255.0f;
        }
    });
    if (o.encodePng) res.image = encodePng(rgb8, g.w, g.h, "lodbake_baseColor");
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

}  // namespace lodbake
