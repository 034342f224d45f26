// parameterize: charts from the coarsest level's base regions, one injective UV map per chart
// minimising E = beta E_pixel + (1 - beta) E_poly, and a shelf-packed square atlas (thesis 3.3).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"
#include "lodbake/param/charts.h"
#include "lodbake/param/chart_uv.h"

namespace lodbake {

struct ParameterizeOptions {
    ChartOptions charts;
    double alpha = 0.8;        // edge vs area weight inside E_pixel
    double beta = 0.7;         // pixel vs polygon resolution error
    int maxIterations = 50;    // Ceres iterations per chart; 0 = keep the Tutte maps
    int textureSize = 1024;    // atlas side in texels (square)
    int gutter = 4;            // texels between charts and around the border (>= 4 recommended)
    std::function<bool(double)> progress;  // fraction done; may be empty
};

struct ChartReport {
    uint32_t faces = 0, vertices = 0, pairs = 0;
    ChartEnergy tutte, final;
    double stretchL2 = 0, stretchLinf = 0;  // Sander et al., normalised so 1 = isometric up to scale
    double areaRatioStdDev = 0;             // std-dev of (UV area / 3D area) / (chart mean ratio)
    size_t flips = 0, overlaps = 0;
    int iterations = 0;
    std::string method;                     // "ceres", "ceres-beta1" or "tutte"
    double seconds = 0;
};

struct ParameterizeResult {
    ChartResult charts;
    std::vector<std::array<Vec2, 3>> cornerUV;  // per original face corner, atlas UV (glTF: [0,1], v down)
    std::vector<ChartReport> chartReports;
    ChartEnergy tutteTotal, finalTotal;        // sums over charts
    double stretchL2 = 0, stretchLinf = 0;     // whole atlas (area-normalised)
    double areaRatioStdDev = 0;                // per triangle (UV area / 3D area), normalised by the mean
    std::array<uint32_t, 10> areaRatioHistogram{};  // bins of normalised ratio over [0, 2]; the last holds >= 1.8
    size_t flips = 0, overlaps = 0;
    double texelsPerUnit = 0;                  // atlas density (texels per model unit)
    double atlasFill = 0;                      // fraction of the atlas covered by charts (UV area)
    double seconds = 0;
};

// \pre multires was produced for `mesh` (faceRegion of the last level, pairs indices in range).
//      With no levels every face starts as its own region.
// \throw InvalidInput (inconsistent multires), Impossible (a chart cannot be embedded),
//        SolverError (no injective map could be produced).
ParameterizeResult parameterize(const TriMesh& mesh, const Multires& multires, const ParameterizeOptions& options = {});

struct AtlasApplyStats {
    size_t newWedges = 0;
    size_t projectedCorners = 0;  // level corners whose vertex is not in the chart of the face
    int material = -1;            // index of the added material
};

// Adds the atlas to the asset: appends chart-split wedges (uv0 = atlas UV, normal/tangent/uv1
// copied, colour white: it is baked) to asset.mesh.wedges, appends a Material using `bakedImage`
// (plus its Texture and Image), and gives every level new cornerWedges and a triangleMaterial
// override pointing at that material. Level 0 (the original triangles) keeps its wedges and
// materials; original wedges get uv0 = (0,0) when the asset had no TEXCOORD_0.
// A level corner whose vertex is not a vertex of its face's chart (a collapse moved it across a
// chart boundary) takes the UV of the closest point of that chart's surface (counted).
AtlasApplyStats applyAtlas(Asset& asset, Multires& multires, const ParameterizeResult& param, const Image& bakedImage);

}  // namespace lodbake
