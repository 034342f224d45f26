// The HTML report's pictures (review_images.h): view strips from compareAssets' kept renders, and
// box-filtered thumbnails of the texture pages a mesh's materials use.
#include "lodbake/metrics/review_images.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <string>

#include "lodbake/texture/codec.h"

namespace lodbake {
namespace {

uint8_t toByte(double v) { return static_cast<uint8_t>(std::lround(std::clamp(v, 0.0, 1.0) * 255)); }

// Copies an RGB float image into column `col` of a strip `stripWidth` pixels wide.
void putTile(std::vector<uint8_t>& strip, int stripWidth, int col, const Rendering& tile, const std::vector<float>& rgb) {
    for (int y = 0; y < tile.height; ++y)
        for (int x = 0; x < tile.width; ++x)
            for (int c = 0; c < 3; ++c)
                strip[(size_t(y) * stripWidth + size_t(col) * tile.width + x) * 3 + c] = toByte(rgb[(size_t(y) * tile.width + x) * 3 + c]);
}

// The index of `mode` in kCompareModes (the order of the kept renders).
size_t modeIndex(RenderMode mode) {
    for (size_t m = 0; m < std::size(kCompareModes); ++m)
        if (kCompareModes[m] == mode) return m;
    return 0;
}

// Each distinct image the used materials reference, with the name of its first use.
std::map<int, std::string> usedImages(const Asset& asset, const TriMesh& mesh) {
    std::map<int, std::string> out;
    std::vector<int32_t> materials(mesh.triangleMaterial.begin(), mesh.triangleMaterial.end());
    std::sort(materials.begin(), materials.end());
    materials.erase(std::unique(materials.begin(), materials.end()), materials.end());
    auto use = [&](const TextureRef& r, const std::string& name) {
        if (r.texture < 0 || size_t(r.texture) >= asset.textures.size()) return;
        const int i = asset.textures[size_t(r.texture)].image;
        if (i >= 0 && size_t(i) < asset.images.size()) out.emplace(i, name);
    };
    for (int32_t m : materials) {
        if (m < 0 || size_t(m) >= asset.materials.size()) continue;
        const Material& mat = asset.materials[size_t(m)];
        use(mat.baseColor, "baseColor");
        use(mat.metallicRoughness, "metallicRoughness");
        use(mat.occlusion, "occlusion");
        use(mat.normal, "normal");
        use(mat.emissive, "emissive");
        use(mat.specularGlossiness, "specularGlossiness");
        for (const TextureRef* r : textureRefs(mat.ext)) use(*r, "extension");
    }
    return out;
}

// A box-filtered copy of `d` whose longest side is at most `side`, as 8-bit RGB or RGBA.
Image thumbnail(const DecodedImage& d, int side, const std::string& name) {
    const int step = std::max(1, (std::max(d.width, d.height) + side - 1) / side);
    const int w = std::max(1, d.width / step), h = std::max(1, d.height / step);
    const int in = d.channels, out = (in == 2 || in == 4) ? 4 : 3;
    auto value = [&](size_t i) { return d.bytes.empty() ? double(d.pixels[i]) : d.bytes[i] / 255.0; };
    std::vector<uint8_t> px(size_t(w) * h * out);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double sum[4] = {0, 0, 0, 0};
            for (int dy = 0; dy < step; ++dy)
                for (int dx = 0; dx < step; ++dx) {
                    const int sy = std::min(y * step + dy, d.height - 1), sx = std::min(x * step + dx, d.width - 1);
                    const size_t p = (size_t(sy) * d.width + size_t(sx)) * in;
                    for (int c = 0; c < in; ++c) sum[c] += value(p + c);
                }
            const double n = double(step) * step;
            double rgba[4];
            if (in <= 2) rgba[0] = rgba[1] = rgba[2] = sum[0] / n;
            else for (int c = 0; c < 3; ++c) rgba[c] = sum[c] / n;
            rgba[3] = in == 2 ? sum[1] / n : in == 4 ? sum[3] / n : 1;
            for (int c = 0; c < out; ++c) px[(size_t(y) * w + x) * out + c] = toByte(rgba[c]);
        }
    return encodePng(px, w, h, name + " " + std::to_string(d.width) + "x" + std::to_string(d.height), out);
}

}  // namespace

std::vector<size_t> shownViews(int views, int maxViews) {
    std::vector<size_t> out;
    const int n = std::min(std::max(views, 0), std::max(maxViews, 0));
    for (int k = 0; k < n; ++k) out.push_back(size_t(k) * size_t(views) / size_t(n));
    return out;
}

std::vector<Image> viewStrips(const CompareResult& result, const ReviewImageOptions& options) {
    std::vector<Image> out;
    if (result.rendersA.empty() || result.rendersA.size() != result.rendersB.size()) return out;
    const size_t mode = modeIndex(options.mode);
    for (size_t v : shownViews(int(result.rendersA.size()), options.maxViews)) {
        const Rendering& a = result.rendersA[v][mode];
        const Rendering& b = result.rendersB[v][mode];
        std::vector<float> diff(a.rgb.size());
        for (size_t i = 0; i < diff.size() && i < b.rgb.size(); ++i)
            diff[i] = float(std::fabs(a.rgb[i] - b.rgb[i]) * options.diffGain);
        const int W = 3 * a.width;
        std::vector<uint8_t> strip(size_t(W) * a.height * 3, 0);
        putTile(strip, W, 0, a, a.rgb);
        putTile(strip, W, 1, a, b.rgb);
        putTile(strip, W, 2, a, diff);
        out.push_back(encodePng(strip, W, a.height, "view " + std::to_string(v)));
    }
    return out;
}

std::vector<Image> pageThumbnails(const Asset& asset, const TriMesh& mesh, const ReviewImageOptions& options) {
    std::vector<Image> out;
    for (const auto& [index, use] : usedImages(asset, mesh)) {
        DecodedImage d;
        std::string error;
        if (!decodeImage(asset.images[size_t(index)], d, error, DecodeDepth::KeepEightBit) || d.width <= 0 || d.height <= 0 ||
            d.channels <= 0 || d.channels > 4)
            continue;
        out.push_back(thumbnail(d, std::max(1, options.thumbnailSide), use));
    }
    return out;
}

}  // namespace lodbake
