// prepareRenderScene (render.h): decodes an asset's images for the rasteriser (texture/codec.h
// decodes the encoded bytes) and box-filters them into mip pyramids. Colour textures (base colour,
// emissive) are sRGB by the glTF spec and are converted to linear light; data textures
// (metallicRoughness, occlusion, normal, the clearcoat's three) are kept as stored. An image used
// both ways is decoded once and kept in both forms. Also computes the wedge tangents of normal maps
// (the base's and the clearcoat's) when the mesh has none.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

#include "lodbake/core/tangents.h"
#include "lodbake/core/errors.h"
#include "lodbake/metrics/render.h"
#include "lodbake/texture/codec.h"
#include "lodbake/texture/color_space.h"
#include "lodbake/texture/texture_transform.h"

namespace lodbake {
namespace {

// Level 0 of `decoded` as RGBA (grey and grey-alpha images expanded, alpha 1 when absent), colour
// channels converted from sRGB to linear when `srgb`.
MipImage::Level toRgba(const DecodedImage& decoded, bool srgb) {
    MipImage::Level out;
    const int w = decoded.width, h = decoded.height, nc = decoded.channels;
    const std::vector<float>& pixels = decoded.pixels;
    out.width = w;
    out.height = h;
    out.rgba.assign(static_cast<size_t>(w) * h * 4, 1.f);
    for (size_t i = 0, n = static_cast<size_t>(w) * h; i < n; ++i) {
        const float* p = &pixels[i * nc];
        float* q = &out.rgba[i * 4];
        if (nc <= 2) {
            q[0] = q[1] = q[2] = srgb ? srgbToLinear(p[0]) : p[0];
            if (nc == 2) q[3] = p[1];
        } else {
            for (int c = 0; c < 3; ++c) q[c] = srgb ? srgbToLinear(p[c]) : p[c];
            if (nc >= 4) q[3] = p[3];
        }
    }
    return out;
}

// The source texels under each texel of a level `dst` texels wide made from one `src` wide, and
// their weights: the overlap of the source texel with the footprint [x src/dst, (x + 1) src/dst).
// An odd side keeps every texel in place (a GPU's generateMipmap blits the whole extent); dropping
// the last one would stretch the rest by up to half a texel of the smaller level.
std::vector<std::vector<std::pair<int, float>>> footprints(int src, int dst) {
    std::vector<std::vector<std::pair<int, float>>> taps(static_cast<size_t>(dst));
    const double scale = static_cast<double>(src) / dst;
    for (int x = 0; x < dst; ++x) {
        const double lo = x * scale, hi = (x + 1) * scale;
        for (int i = static_cast<int>(std::floor(lo)); i < src && i < hi; ++i) {
            const double overlap = std::min(hi, i + 1.0) - std::max(lo, static_cast<double>(i));
            if (overlap > 0) taps[static_cast<size_t>(x)].push_back({i, static_cast<float>(overlap / scale)});
        }
    }
    return taps;
}

// The next level of `src` with an odd side: each texel the weighted mean of its footprint.
MipImage::Level halveOdd(const MipImage::Level& src, int width, int height) {
    MipImage::Level dst;
    dst.width = width;
    dst.height = height;
    dst.rgba.assign(static_cast<size_t>(width) * height * 4, 0.f);
    const auto tx = footprints(src.width, width), ty = footprints(src.height, height);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            float* out = &dst.rgba[(static_cast<size_t>(y) * width + x) * 4];
            for (const auto& [j, wy] : ty[static_cast<size_t>(y)])
                for (const auto& [i, wx] : tx[static_cast<size_t>(x)]) {
                    const float* in = &src.rgba[(static_cast<size_t>(j) * src.width + i) * 4];
                    for (int c = 0; c < 4; ++c) out[c] += wx * wy * in[c];
                }
        }
    return dst;
}

void buildPyramid(MipImage& mip) {
    while (mip.levels.back().width > 1 || mip.levels.back().height > 1) {
        const MipImage::Level& src = mip.levels.back();
        const int width = std::max(1, src.width / 2), height = std::max(1, src.height / 2);
        if ((src.width > 1 && src.width % 2) || (src.height > 1 && src.height % 2)) {
            mip.levels.push_back(halveOdd(src, width, height));
            continue;
        }
        MipImage::Level dst;
        dst.width = width;
        dst.height = height;
        dst.rgba.resize(static_cast<size_t>(dst.width) * dst.height * 4);
        for (int y = 0; y < dst.height; ++y)
            for (int x = 0; x < dst.width; ++x) {
                int x0 = std::min(2 * x, src.width - 1), x1 = std::min(2 * x + 1, src.width - 1);
                int y0 = std::min(2 * y, src.height - 1), y1 = std::min(2 * y + 1, src.height - 1);
                for (int c = 0; c < 4; ++c) {
                    auto at = [&](int xx, int yy) { return src.rgba[(static_cast<size_t>(yy) * src.width + xx) * 4 + c]; };
                    dst.rgba[(static_cast<size_t>(y) * dst.width + x) * 4 + c] =
                        0.25f * (at(x0, y0) + at(x1, y0) + at(x0, y1) + at(x1, y1));
                }
            }
        mip.levels.push_back(std::move(dst));
    }
}

}  // namespace

RenderScene prepareRenderScene(const Asset& asset, const TriMesh& mesh) {
    RenderScene scene;
    scene.asset = &asset;
    scene.mesh = &mesh;
    scene.images.resize(asset.images.size());
    scene.dataImages.resize(asset.images.size());
    // Per image: used as colour (sRGB) and/or as data; per UV set: used by a normal map.
    std::map<int, std::pair<bool, bool>> used;
    bool normalMapSet[2] = {false, false};
    const std::set<int32_t> materials(mesh.triangleMaterial.begin(), mesh.triangleMaterial.end());
    for (int32_t m : materials) {
        if (m < 0 || static_cast<size_t>(m) >= asset.materials.size()) continue;
        const Material& mat = asset.materials[m];
        const ClearcoatExtension& cc = mat.ext.clearcoat;
        const bool coat = cc.present && cc.factor > 0;
        for (const TextureRef* r : {&mat.baseColor, &mat.emissive, &mat.metallicRoughness, &mat.occlusion, &mat.normal,
                                    &cc.texture, &cc.roughnessTexture, &cc.normalTexture}) {
            if (r->texture < 0 || static_cast<size_t>(r->texture) >= asset.textures.size()) continue;
            if (!coat && (r == &cc.texture || r == &cc.roughnessTexture || r == &cc.normalTexture)) continue;
            int i = asset.textures[r->texture].image;
            if (i < 0 || static_cast<size_t>(i) >= asset.images.size()) continue;
            const bool colour = r == &mat.baseColor || r == &mat.emissive;
            (colour ? used[i].first : used[i].second) = true;
            if (r == &mat.normal || r == &cc.normalTexture) normalMapSet[textureCoordSet(*r) == 1 ? 1 : 0] = true;
        }
    }
    for (const auto& [i, use] : used) {
        DecodedImage decoded;
        std::string error;
        if (!decodeImage(asset.images[i], decoded, error)) {
            scene.warnings.push_back(error + " (rendered white)");
            continue;
        }
        if (use.first) {
            scene.images[i].levels.push_back(toRgba(decoded, true));
            buildPyramid(scene.images[i]);
        }
        if (use.second) {
            scene.dataImages[i].levels.push_back(toRgba(decoded, false));
            buildPyramid(scene.dataImages[i]);
        }
    }
    if (mesh.wedges.tangent.size() != mesh.wedges.size())
        for (int set = 0; set < 2; ++set)
            if (normalMapSet[set]) scene.tangents[set] = computeWedgeTangents(mesh, normalMapUVs(mesh, asset.materials, set));
    scene.seamEdges = textureSeamEdges(mesh);
    return scene;
}

}  // namespace lodbake
