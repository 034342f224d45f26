// Atlas packing: the one home of chart packing, with two packers.
//   - shelfPack: the T0 atlas of `parameterize`. Point sets (charts and level islands, model units)
//     at one uniform density, their bounding boxes in rows ("shelves") on a square page.
//   - packAtlas: the pages of `pack`. The charts of a texture layout placed by their shapes: each
//     chart is turned to its minimum-area bounding rectangle, rasterised at the page density (the
//     texels its triangles touch, grown by half the gutter) and placed, in a few orders (largest
//     first, longest first, ...), at the lowest free position of a page bitmap over the four
//     quarter turns, so charts nest into each other's concavities; the smallest page wins. Charts
//     keep the gutter between each other but not along the page border (the chain's samplers
//     clamp to the edge).
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "lodbake/core/math.h"

namespace lodbake {

// ---- Shelf packing (T0) ----

struct ShelfPackOptions {
    int size = 1024;  // page side, texels (square)
    int gutter = 4;   // texels between items and along the page border
    // A page that cannot hold the items at any density tried doubles, up to this side (0: the
    // page never grows; such items throw).
    int maxSize = 0;
};

// Where one item went: its bounding-box minimum `min` (model units) sits at texel (x, y).
struct ShelfPlacement {
    double x = 0, y = 0;
    Vec2 min{};
};

struct ShelfPackResult {
    int size = 0;                         // page side, texels
    double texelsPerUnit = 0;             // the uniform density reached (texels per model unit)
    std::vector<ShelfPlacement> items;    // per input point set
    // Atlas UV (glTF: [0,1], v down) of point p (model units) of item i; texel centres at +0.5.
    Vec2 atlasUV(size_t i, Vec2 p) const {
        const ShelfPlacement& s = items[i];
        double X = s.x + (p.x - s.min.x) * texelsPerUnit + 0.5;
        double Y = s.y + (p.y - s.min.y) * texelsPerUnit + 0.5;
        return Vec2{X / size, 1.0 - Y / size};
    }
};

// Packs the bounding boxes of `items` (point sets in model units; an empty set is a 1-texel box)
// tallest first, left to right in shelves, at one density for all: it starts where `area`
// (the items' total area, model units^2; <= 0 counts as 1) fills 70% of the page and shrinks by
// 5% per attempt until every box fits with its gutters. A page whose last attempt would still fail
// first doubles up to options.maxSize (ShelfPackResult::size is the side used).
// \pre options.size >= 16, options.gutter >= 0; the pointers are valid.
// \throw Impossible when nothing fits after 400 attempts.
ShelfPackResult shelfPack(const std::vector<const std::vector<Vec2>*>& items, double area, const ShelfPackOptions& options);

// The most items with UV area shelfPack places on a `size` page at any density: however small
// the density, such an item's box takes 2 x 2 texels and the gutter around it. More charts than
// this never fit that page.
size_t shelfPackCapacity(int size, int gutter);

// ---- Shape-aware page packing (pack) ----

// One chart to place: the UV points it covers and its UV area (T0 units).
struct AtlasChart {
    std::vector<Vec2> points;  // every UV corner the page must show (triangle corners)
    // The chart's UV triangles, rasterised for its shape; empty = its points' convex hull.
    std::vector<std::array<Vec2, 3>> triangles;
    double uvArea = 0;         // sum of |UV triangle areas| (the chart's actual coverage)
    // Texel-aligned pages: the chart's UVs are already page texels (an island of the original's
    // texture, in its texels); kept there when the searched layouts do not fit and the spot is free.
    bool inPlace = false;
};

struct AtlasOptions {
    double maxTexelsPerUnit = 256;  // texels per T0 UV unit at most (the level's screen limit); > 0
    int gutter = 4;                 // texels between two charts (each chart is padded by gutter/2); >= 0.
                                    // Halved while it takes more than half the padded area, or the charts do not fit.
    int maxSize = 2048;             // page width and height cap, texels
    bool powerOfTwo = false;        // page sides powers of two (then texel density may drop below the limit)
    int threads = 1;                // threads of the page search (0 = all cores); the result is the same for any count
    // Charts keep their orientation (quarter turns only) and land on whole texels: with UVs in
    // source texels and maxTexelsPerUnit 1, every page texel centre maps to a source texel centre
    // (check AtlasResult::texelsPerUnit: the density is lowered when the charts do not fit).
    bool texelAligned = false;
    // A page below this density is of no use to the caller (it discards it): the density search
    // may stop once the densest page is known to lie below it, and return a page that fits at a
    // lower density than the densest. A page at this density or above is the same as with 0.
    double minTexelsPerUnit = 0;
};

// Maps T0 UV to page texel coordinates: x = m[0] u + m[1] v + m[2], y = m[3] u + m[4] v + m[5].
struct ChartPlacement {
    std::array<double, 6> m{};
    int rotation = 0;  // quarter turns (counter-clockwise in texel space) of the oriented chart
    Vec2 apply(Vec2 uv) const { return {m[0] * uv.x + m[1] * uv.y + m[2], m[3] * uv.x + m[4] * uv.y + m[5]}; }
};

struct AtlasResult {
    int width = 0, height = 0;           // page size, texels
    double texelsPerUnit = 0;            // the density reached (<= maxTexelsPerUnit)
    std::vector<ChartPlacement> charts;  // per input chart
    // Chart texels / page texels, with chart texels = the charts' actual triangle coverage (UV area).
    double utilisation = 0;
    // The same with chart texels = each chart's (rotated) bounding rectangle, gutters excluded;
    // above 1 when charts nest into each other's rectangles.
    double boxUtilisation = 0;
    // The same with chart texels = the texels the charts' triangles touch (conservative raster,
    // the texels a sampler reads; gutters excluded), and with the charts' gutter rings included
    // (rings may reach past the page border, where no gutter is needed: samplers clamp).
    double rasterUtilisation = 0;
    double footprintUtilisation = 0;
    int gutter = 0;                      // the gutter used (may be narrower than asked)
};

// A chart's frame on a page: turned by the angle (c, s) = (cos, sin), its rectangle is
// [minX, minX + w] x [minY, minY + h] (texel-aligned: unturned, the corner on a block of texels).
struct ChartFrame {
    double c = 1, s = 0;
    double minX = 0, minY = 0, w = 0, h = 0;
};

// Each chart's frame, as packAtlas and atlasStartGutter find it first (the minimum-area rectangle
// of its UV hull, a function of the chart and options.texelAligned alone). A caller that packs
// the same charts many times finds the frames once and hands them to both.
std::vector<ChartFrame> chartFrames(const std::vector<AtlasChart>& charts, const AtlasOptions& options);

// \pre every chart has >= 1 point; options.maxTexelsPerUnit > 0; maxSize >= 8; `frames`, when
// given, is chartFrames(charts, options).
// Never fails: when the charts do not fit at the density limit the density is lowered until they
// fit in maxSize x maxSize.
AtlasResult packAtlas(const std::vector<AtlasChart>& charts, const AtlasOptions& options,
                      const std::vector<ChartFrame>* frames = nullptr);

// The gutter packAtlas's search starts from: options.gutter, halved while the gutters take more
// than half of the charts' padded area at the density limit. Unless options.texelAligned (whose
// in-place fallback starts from options.gutter itself), packAtlas returns the same result for two
// options that differ in the gutter alone when this is the same for both.
int atlasStartGutter(const std::vector<AtlasChart>& charts, const AtlasOptions& options, const std::vector<ChartFrame>* frames = nullptr);

}  // namespace lodbake
