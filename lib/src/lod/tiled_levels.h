// Levels that keep a repeating material tiling. When every triangle wears one material whose
// textures repeat (cloth weaves, bricks, wood: a KHR_texture_transform scale above 1, or UVs
// spanning several tiles), an atlas of the whole surface either magnifies the pattern or spends
// large pages on it. Such a chain instead bakes one period of the material (a tile per channel,
// the same channel packing as a level's page), gives every level the original's texture
// coordinates through the transform, and lets the sampler repeat the tile.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "lodbake/bake/bake.h"
#include "lodbake/core/mesh.h"
#include "lodbake/lod/lod_chain.h"

namespace lodbake::lod_detail {

struct TilingOptions {
    // Transformed UVs spanning more than this many tiles (in u or v) make textures count as
    // repeating even without a transform scale above 1.
    double minSpan = 1.5;
};

// Whether an asset's chain can keep its material's tiling, and the tile it would use.
struct TilingEligibility {
    bool eligible = false;
    std::string reason;          // why (or why not), for the report
    int material = -1;           // the one material every triangle wears
    int uvSet = 0;               // the TEXCOORD_n all its textures read
    TextureTransform transform;  // the transform all its textures share (present = false: none)
    double span = 0;             // largest extent of the transformed UVs over the mesh, tiles
    int width = 0, height = 0;   // the tile, texels: the largest sides of the material's images
};

// The rule: one material on every triangle, with at least one texture; all its textures read the
// same UV set through the same transform and repeat (sampler wrap REPEAT both ways); the texture
// coordinates repeat (|scale| > 1 on an axis, or a span above minSpan); no vertex colour that
// varies (a tile cannot hold it); no material variants. `imageSizes` = the asset's images' sides.
TilingEligibility tilingEligibility(const Asset& asset, const std::vector<std::pair<int, int>>& imageSizes,
                                    const TilingOptions& options = {});

// The same with the sides of the asset's images (read from their headers).
TilingEligibility tilingEligibility(const Asset& asset, const TilingOptions& options = {});

// A level's corners on the tile: texture coordinates (the source UV through the shared transform;
// the tile spans [0,1]^2 and repeats).
struct TiledLevelUVs {
    std::vector<std::array<Vec2, 3>> uv;  // per level triangle
    // Triangles whose corners gave a stretched or flipped map (corners across a UV seam) and that
    // took other wedges of their corners' vertices, and those still stretched
    // after that, with their share of the level's area.
    size_t rechosen = 0, stretched = 0;
    double stretchedArea = 0;
};

// Corner UVs of a level (triangles over `positions`, each descending from original face
// `faces[t]`): the original's UVs at its corners (a level's vertices are original vertices), each
// taken from the UV island of its face. A triangle counts as stretched when its UV-to-3D area
// ratio differs from its face's by more than `maxStretch` times either way, or its UVs face the
// other way.
TiledLevelUVs tiledLevelUVs(const TriMesh& original, const std::vector<Vec3>& positions, const std::vector<Tri>& triangles,
                            const std::vector<uint32_t>& faces, const TilingEligibility& tiling, double maxStretch = 3);

// A level of a tiling chain on the tile: its UVs, or none when its stretched triangles cover more
// than `maxStretchedArea` of its area (it takes an atlas page); the report says which and why.
std::optional<TiledLevelUVs> tiledLevel(const TriMesh& original, const std::vector<Vec3>& positions, const std::vector<Tri>& triangles,
                                        const std::vector<uint32_t>& faces, const TilingEligibility& tiling,
                                        PackLevelReport::Tiling& report, double maxStretchedArea = 0.01);

// One period of the material: the source material evaluated at every texel of the tile (a flat
// quad whose UVs span one tile, baked by bakeMaterial with `channels`, normal maps in the frames
// a level's tangents take from tile UVs). width x height = tiling's.
// \throw IOError (an image cannot be decoded).
BakeResult bakeTile(const Asset& asset, const TilingEligibility& tiling, const BakeChannels& channels, int threads);

}  // namespace lodbake::lod_detail
