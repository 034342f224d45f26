// Image encoding and checking with OpenImageIO, the only module that links it besides the texture
// samplers (bake, metrics). The glTF reader keeps images encoded, so tools that only pass images
// through (simplify, agsphere-build) never load OpenImageIO and its ~250 shared libraries, whose
// symbol binding alone takes 0.2-0.4 s per process.
#pragma once

#include <string>
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

enum class ImageCheck {
    Header,  // open each image and read its size (cheap)
    Decode,  // also decode every pixel (finds truncated or corrupt data)
};

// Fills width, height and channels of every image of `asset`.
// \throw InvalidInput "<asset.sourcePath>: image N 'name': cannot decode ..." (one line).
void checkImages(Asset& asset, ImageCheck check = ImageCheck::Decode);

}  // namespace lodbake
