// The chain's plan: each level's screen coverage range, the texel density it can show there, the
// texture layouts eligible for it and the page side it needs. A plain function of the measured
// deviations, the layouts' scales and the options, made before any page is packed.
//
// Level k is good while its deviation e_k projects to <= p pixels on a viewport H pixels tall;
// with the bounding sphere radius R that is coverage <= 2 R p / (e_k H) (independent of the field
// of view: coverage = projected sphere height / viewport height). A level shows one texel per
// pixel at its largest coverage, the next finer level's threshold.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "lodbake/core/texture_hierarchy.h"

namespace lodbake::lod_detail {

// Page side estimates assume the charts fill this share of the page side: side = the charts'
// square side (sqrt of their area at the density) / kPageSideFill.
constexpr double kPageSideFill = 0.8;

// A deviation below this (relative to the diagonal) is below float precision of the positions:
// no deviation, the coarser level is as good as the finer one at any size.
constexpr double kExactDeviation = 1e-7;

struct LevelPlanOptions {
    double pixelError = 1;      // a level is used while its deviation projects to <= this many pixels
    int viewportHeight = 1080;  // pixels
    double fovY = 60;           // vertical field of view, degrees (switch distances only)
    double lod0Coverage = 1;    // the largest screen coverage LOD0 is sized for
    double cutoffPixels = 2;    // the chain is culled below this many pixels tall
    int maxSize = 2048;         // page side cap, texels
    bool lod0Density = false;   // every level at LOD0's texel limit
};

// What the plan reads of the chain as measured.
struct LevelPlanInput {
    std::vector<double> hausdorff;       // per level (LOD0 first): measured distance to the original, model units (LOD0's unused)
    std::vector<size_t> multiresLevel;   // per level: its multires level number (0 = the original)
    double radius = 0, diagonal = 0;     // bounding sphere radius and bounding box diagonal, model units; radius > 0
    double area3D = 0;                   // the original's surface area, square model units
    std::vector<double> layoutUvPerUnit; // per layout (T0, then the hierarchy's ranks): layout UV units per model unit
    std::vector<HierarchyTexture> textures;  // the texture hierarchy's textures; empty = none (T0 only)
};

struct PlannedLevel {
    double coverage = 0;        // MSFT_screencoverage value: the level is used at coverage >= this
    double maxCoverage = 0;     // ... and below this (the next finer level's value; LOD0: at least lod0Coverage)
    double switchDistance = 0;  // camera distance (model units, fovY) at which the next coarser level takes over
    double texelLimit = 0;      // texels per model unit the level can show at its largest coverage
    double sideNeeded = 0;      // page side estimate: sqrt(area3D) x texelLimit / kPageSideFill, capped by maxSize
    // The layouts eligible for the level, ascending (T0 first): T0 and every rank valid for the
    // level whose smallest hierarchy texture is no larger than sideNeeded (a rank's extra chart
    // seams and gutters only pay at the resolutions it was made for).
    std::vector<uint32_t> eligibleRanks;
    uint32_t rank = 0;          // the energy rule's pick: the highest eligible rank (lowest mapping energy)
    int textureSize = 0;        // hierarchyTextureSize of `rank` at texelLimit; 0 without a hierarchy
};

struct LevelPlan {
    // Per level: the smallest coverage at which it is drawn, decreasing; the last one culls the
    // coarsest level below cutoffPixels (and at half the previous value at most).
    std::vector<double> screenCoverage;
    std::vector<PlannedLevel> levels;
};

// \pre input.hausdorff and input.multiresLevel hold one entry per level (at least one);
//      layoutUvPerUnit holds T0's, and one per rank the textures name.
LevelPlan planLevels(const LevelPlanInput& input, const LevelPlanOptions& options);

// Of rank `rank`'s hierarchy textures the smallest whose side gives `layoutTexels` (texels per
// layout UV unit), the largest when none does; 0 when `textures` holds none of that rank.
int hierarchyTextureSize(const std::vector<HierarchyTexture>& textures, uint32_t rank, double layoutTexels);

}  // namespace lodbake::lod_detail
