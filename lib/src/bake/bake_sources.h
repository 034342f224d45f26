// The source-image cache behind BakeSources (lodbake/bake/bake.h): each image a material channel
// reads, decoded to MIP levels once, on the first bake that reads it, and kept for every later
// bake of the same asset (pack bakes a page per level, texture-refine one per layout and size);
// and the original's tangent frames for its normal maps when the file has no TANGENT.
#pragma once

#include <array>
#include <cstddef>
#include <mutex>
#include <vector>

#include "lodbake/bake/bake.h"
#include "lodbake/bake/texture_fetch.h"

namespace lodbake {
namespace bake_detail {

// An image a material channel reads, decoded on the first bake that reads it.
struct SourceTexture {
    bool used = false;  // some material channel references it
    std::once_flag decoded;
    MipTexture mip;
};

// The decoded MIP levels of image i, decoded by the first caller (others wait for it).
// \throw IOError (the image cannot be decoded).
const MipTexture& decodedSource(const Asset& asset, SourceTexture& src, size_t i);

// Decodes, on `threads` threads, every image that baking `ch` reads (each once, in any order:
// each is decoded on its own), so the shading threads do not wait on one another's decodes.
// \throw IOError (an image cannot be decoded).
void decodeSources(const Asset& asset, std::vector<SourceTexture>& sources, const BakeChannels& ch, int threads);

}  // namespace bake_detail

// The bake's view of a BakeSources: its images (per image of the asset) and the tangents it
// computed per UV set (empty where the file has TANGENT or no map needs them).
struct BakeSourcesAccess {
    static std::vector<bake_detail::SourceTexture>& sources(const BakeSources& s);
    static const std::array<std::vector<Vec4>, 2>& tangents(const BakeSources& s);
};

}  // namespace lodbake
