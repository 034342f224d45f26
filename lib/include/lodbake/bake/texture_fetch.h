// The bake's texture sampling: a decoded image as MIP levels (8-bit RGBA, box-filtered) and a
// footprint-filtered fetch (trilinear, a few taps along the footprint's major axis), and the
// pull-push gap fill of a baked page. Plain loops over memory: OpenImageIO only decodes the image.
#pragma once

#include <cstdint>
#include <vector>

#include "lodbake/core/math.h"
#include "lodbake/texture/codec.h"

namespace lodbake {

// MIP levels of one image: level 0 is the image, each next level half the size (rounded up) down
// to 1 x 1. Texels RGBA as stored (grey fills RGB, no alpha gives 1), 0..255, in 4 x 4 tiles of
// 64 bytes (a cache line: a bilinear tap mostly reads one, whatever direction the fetches walk).
struct MipTexture {
    struct Level {
        int width = 0, height = 0;
        size_t tilesX = 0;          // tiles per tile row: ceil(width / 4)
        std::vector<uint8_t> rgba;  // tile (x / 4, y / 4), then row y % 4, column x % 4
        size_t at(int x, int y) const {
            return ((size_t(y >> 2) * tilesX + size_t(x >> 2)) * 16 + size_t(y & 3) * 4 + size_t(x & 3)) * 4;
        }
    };
    std::vector<Level> levels;
};

// \throw InvalidInput (no pixels, or fewer than width x height x channels).
MipTexture buildMipTexture(const DecodedImage& image);

enum class TextureWrap { Repeat, Clamp, Mirror };

struct FetchOptions {
    TextureWrap wrapS = TextureWrap::Repeat, wrapT = TextureWrap::Repeat;
    int maxAnisotropy = 8;  // taps along the major axis at most; beyond, the footprint is blurred
};

// The filtered texel at texture coordinates `st` (glTF convention: [0,1], v down) for a footprint
// with derivatives dx, dy (texture coordinates per output texel): RGBA in [0,1].
void fetchFiltered(const MipTexture& texture, const FetchOptions& options, Vec2 st, Vec2 dx, Vec2 dy, float out[4]);

// A glTF sampler wrap constant (sampler.wrapS/T) -> TextureWrap (repeat for anything unknown).
TextureWrap textureWrapFromGl(int gl);

// Pull-push fill of a w x h image of `channels` interleaved floats: texels with covered[i] == 0
// take values spread from the covered ones (coarser levels of a coverage-weighted pyramid);
// covered texels keep theirs. Rows on `threads` threads; the result does not depend on the count.
// Nothing changes when no texel is covered.
void pullPushFill(std::vector<float>& values, int channels, const std::vector<uint8_t>& covered, int w, int h, int threads);

// One image of a joint fill: w x h texels of `channels` interleaved floats.
struct FillImage {
    std::vector<float>* values = nullptr;
    int channels = 0;
};
// pullPushFill of every image of `images` over the same coverage, in one pass (each image's result
// is that of its own call).
void pullPushFill(const std::vector<FillImage>& images, const std::vector<uint8_t>& covered, int w, int h, int threads);

}  // namespace lodbake
