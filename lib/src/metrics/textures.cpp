// Decoding of an asset's images for the rasteriser (render.h): texture/codec.h decodes the
// encoded bytes; texels are converted from sRGB to linear light (base colour textures are sRGB by
// the glTF spec) and box-filtered into a mip pyramid.
#include <cmath>
#include <set>

#include "lodbake/core/errors.h"
#include "lodbake/metrics/render.h"
#include "lodbake/texture/codec.h"
#include "lodbake/texture/color_space.h"

namespace lodbake {
namespace {

// Decodes `image` (texture/codec.h) to linear RGBA level 0; false when it cannot be decoded.
bool decodeLinear(const Image& image, MipImage::Level& out, std::string& error) {
    DecodedImage decoded;
    if (!decodeImage(image, decoded, error)) return false;
    const int w = decoded.width, h = decoded.height, nc = decoded.channels;
    const std::vector<float>& pixels = decoded.pixels;
    out.width = w;
    out.height = h;
    out.rgba.assign(static_cast<size_t>(w) * h * 4, 1.f);
    for (size_t i = 0, n = static_cast<size_t>(w) * h; i < n; ++i) {
        const float* p = &pixels[i * nc];
        float* q = &out.rgba[i * 4];
        if (nc <= 2) {
            q[0] = q[1] = q[2] = srgbToLinear(p[0]);
            if (nc == 2) q[3] = p[1];
        } else {
            for (int c = 0; c < 3; ++c) q[c] = srgbToLinear(p[c]);
            if (nc >= 4) q[3] = p[3];
        }
    }
    return true;
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
    std::set<int> used;
    for (int32_t m : mesh.triangleMaterial) {
        if (m < 0 || static_cast<size_t>(m) >= asset.materials.size()) continue;
        int t = asset.materials[m].baseColor.texture;
        if (t < 0 || static_cast<size_t>(t) >= asset.textures.size()) continue;
        int i = asset.textures[t].image;
        if (i >= 0 && static_cast<size_t>(i) < asset.images.size()) used.insert(i);
    }
    for (int i : used) {
        MipImage::Level level0;
        std::string error;
        if (!decodeLinear(asset.images[i], level0, error)) {
            scene.warnings.push_back(error + " (rendered white)");
            continue;
        }
        scene.images[i].levels.push_back(std::move(level0));
        buildPyramid(scene.images[i]);
    }
    return scene;
}

}  // namespace lodbake
