// LOD0 on the original's own texels: a chart layout whose charts are the original's texture
// islands, in the texels of their material's textures.
//
// LOD0 keeps the original triangles, so its page can hold the original texels one to one: each
// island (a connected piece of one material's TEXCOORD_0, cut where the UVs jump) is placed whole,
// unrotated, at one atlas texel per source texel and an integer texel offset (packAtlas with
// AtlasOptions::texelAligned). Every atlas texel centre then maps to a source texel centre, the
// bake reads that texel exactly, and the page renders as the original did: resampling the
// original's textures at another density or orientation blurs every sharp edge they have (on
// pbrscene's checker textures, resampled at 2.7x with the original UVs, three.js renders 33.5 dB
// against the original; an aligned copy is exact).
// Faces of untextured materials keep their layout (T0) charts at the level's screen density;
// textures read through another UV set or a texture transform are resampled, as on any level.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "lodbake/core/chart_layout.h"
#include "lodbake/core/mesh.h"

namespace lodbake::lod_detail {

struct SourceTexelLayout {
    ChartLayout layout;  // empty when the original cannot be copied texel for texel (see reason)
    std::string reason;  // why not
    size_t islands = 0;  // charts from texture islands (the first ones); the rest are T0 pieces
    size_t inPlace = 0;  // the first islands: the texture with the most texels (AtlasChart::inPlace)
    // The same charts with every line piece held to the size of one that does not repeat (empty
    // when no line piece repeats): the texels LOD0 holds for its surface at its density, which the coarser levels'
    // texel cap counts. A repeating line's copy of every period serves LOD0 alone: coarser levels
    // resample the sides at their own density whatever their cap.
    ChartLayout capLayout;
};

// `imageSizes`: width and height of each Asset::images entry. `t0` is the layout the untextured
// faces keep, scaled by `t0Texels` (page texels per layout unit). A material's islands are in the
// texels of the largest texture it reads through TEXCOORD_0 without KHR_texture_transform; the
// layout is empty when no face has such a texture.
SourceTexelLayout sourceTexelLayout(const Asset& asset, const std::vector<std::pair<int, int>>& imageSizes,
                                    const ChartLayout& t0, double t0Texels);

// The GL min and mag filters every texture of the asset's materials samples with ({0, 0} when
// they differ or none is set): a page of the original's texels keeps them.
std::pair<int, int> sourceFilters(const Asset& asset);

}  // namespace lodbake::lod_detail
