// prepareRenderScene (render.h): decodes an asset's images for the rasteriser (texture/codec.h
// decodes the encoded bytes) and box-filters them into mip pyramids. Colour textures (base colour,
// emissive) are sRGB by the glTF spec and are converted to linear light; data textures
// (metallicRoughness, occlusion, normal) are kept as stored. An image used both ways is decoded
// once and kept in both forms. Also computes the wedge tangents of normal maps when the mesh has none.
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

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

void buildPyramid(MipImage& mip) {
    while (mip.levels.back().width > 1 || mip.levels.back().height > 1) {
        const MipImage::Level& src = mip.levels.back();
        MipImage::Level dst;
        dst.width = std::max(1, src.width / 2);
        dst.height = std::max(1, src.height / 2);
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
        for (const TextureRef* r : {&mat.baseColor, &mat.emissive, &mat.metallicRoughness, &mat.occlusion, &mat.normal}) {
            if (r->texture < 0 || static_cast<size_t>(r->texture) >= asset.textures.size()) continue;
            int i = asset.textures[r->texture].image;
            if (i < 0 || static_cast<size_t>(i) >= asset.images.size()) continue;
            const bool colour = r == &mat.baseColor || r == &mat.emissive;
            (colour ? used[i].first : used[i].second) = true;
            if (r == &mat.normal) normalMapSet[textureCoordSet(*r) == 1 ? 1 : 0] = true;
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
