// Image decoding, encoding and checking with OpenImageIO: every encoded image lodbake reads or
// writes goes through this file (the bake decodes its source images here, then samples them
// itself: bake/texture_fetch.h). The glTF reader keeps images encoded, so tools that only pass images
// through (simplify, agsphere-build) never load OpenImageIO and its ~250 shared libraries, whose
// symbol binding alone takes 0.2-0.4 s per process.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

enum class ImageFormat { Png, Jpeg };

// Encodes an 8-bit RGB image from floats in [0,1] (already sRGB-encoded), RGB interleaved, top row
// first. jpegQuality in [1,100] (JPEG only).
// \throw InvalidInput (size mismatch), IOError (encoder failure).
Image encodeImage(const std::vector<float>& rgb, int width, int height, ImageFormat format, int jpegQuality = 90,
                  const std::string& name = "");
// The same with 1 to 4 interleaved channels (4: RGBA, alpha straight). JPEG has no alpha: callers
// encode RGBA as PNG.
Image encodeImage(const std::vector<float>& values, int width, int height, int channels, ImageFormat format,
                  int jpegQuality = 90, const std::string& name = "");

struct EncodeOptions {
    ImageFormat format = ImageFormat::Png;
    int jpegQuality = 90;  // [1,100], JPEG only
    int channels = 3;      // 1..4 interleaved (4 = RGBA, straight alpha; PNG only)
    bool srgb = true;      // tag the file as sRGB colour (false for data: normals, roughness, occlusion)
};

// Encodes an 8-bit image from floats in [0,1] as they are to be stored, top row first.
// \throw InvalidInput (size mismatch, RGBA as JPEG), IOError (encoder failure).
Image encodeImage(const std::vector<float>& values, int width, int height, const EncodeOptions& options,
                  const std::string& name = "");

// Encodes an 8-bit image (`channels` interleaved, top row first) as PNG, without a colour-space chunk.
// \throw InvalidInput (size mismatch), IOError (encoder failure).
Image encodePng(const std::vector<uint8_t>& pixels, int width, int height, const std::string& name = "", int channels = 3);

// Pixels of a decoded image: floats in [0,1] as stored (sRGB-encoded for colour), `channels`
// interleaved per texel, top row first; or, when decoded with DecodeDepth::KeepEightBit from an
// image stored with 8 bits per channel, those bytes (value = byte / 255) with `pixels` empty.
struct DecodedImage {
    int width = 0, height = 0, channels = 0;
    std::vector<float> pixels;  // width * height * channels
    std::vector<uint8_t> bytes;  // width * height * channels, instead of `pixels` (see above)
};

enum class DecodeDepth {
    Float,         // always `pixels`
    KeepEightBit,  // `bytes` for 8-bit images (no float image of 4 bytes a value), `pixels` otherwise
};

// Decodes `image` into `out`; false, with a one-line `error` naming the image, when it has no data
// or cannot be decoded.
bool decodeImage(const Image& image, DecodedImage& out, std::string& error, DecodeDepth depth = DecodeDepth::Float);

// Width and height of an encoded image (its own fields when set, else read from its header);
// {0, 0} when it cannot be read.
std::pair<int, int> imageSize(const Image& image);

enum class ImageCheck {
    Header,  // open each image and read its size (cheap)
    Decode,  // also decode every pixel (finds truncated or corrupt data)
};

// Fills width, height and channels of every image of `asset`.
// \throw InvalidInput "<asset.sourcePath>: image N 'name': cannot decode ..." (one line).
void checkImages(Asset& asset, ImageCheck check = ImageCheck::Decode);

}  // namespace lodbake
