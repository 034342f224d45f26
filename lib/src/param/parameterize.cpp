// parameterize: charts, their maps (LSCM or Tutte start, Ceres: E = beta E_pixel + (1 - beta)
// E_poly), checks and fallbacks, a shelf-packed atlas, per-corner and per-level UVs (thesis 3.3;
// DESIGN.md). This file is the entry point; each step lives in the file named beside it.
//
// Pipeline of parameterize, in execution order:
//   (1) buildCharts         charts from the coarsest level's base regions (chart/charts.cpp)
//   (2) localCharts         each chart as a local mesh with its simplification pairs and the level
//                           triangles it carries, all levels (chart_extraction.cpp)
//   (3) solveCharts         per chart: LSCM or Tutte start, Ceres, injectivity and level-fold
//                           checks, fallback beta = 1; remembered solves from the byte-keyed
//                           ChartSolveCache (chart_solve.cpp)
//   (3b) splitFailedCharts  a chart the solver cannot map becomes single-face charts (fold_fallback.cpp)
//   (4) measureCharts       stretch (Sander et al. 2001), UV/3D area ratios (stretch_metrics.cpp);
//                           alignChart (atlas_layout.cpp)
//   (5)-(7) layoutAtlas     rounds of packCharts (shelfPack at a uniform density), writeCornerUVs,
//                           writeLevelUVs, and addFoldIslands (level triangles that fold or cross a
//                           chart boundary get their own island) until no level folds (atlas_layout.cpp)
//   nudgeRoundedSliverCorners   sliver faces that flip once their UVs are rounded to float
//   foldedAtlasFaces, carveFaces  fallback: an original face still folded in the atlas gets a chart
//                           of its own, then (5)-(7) again (fold_fallback.cpp)
#include "lodbake/param/parameterize.h"

#include <string>

#include "lodbake/core/errors.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/timing.h"
#include "param/atlas_layout.h"
#include "param/chart_extraction.h"
#include "param/chart_solve.h"
#include "param/fold_fallback.h"
#include "param/stretch_metrics.h"

namespace lodbake {

using namespace param_detail;

ParameterizeResult parameterize(const TriMesh& mesh, const Multires& multires, const ParameterizeOptions& options) {
    auto t0 = Clock::now();
    ParameterizeResult res;
    if (mesh.triangleCount() == 0) throw Impossible("the mesh has no triangles");
    if (!(options.textureSize >= 16)) throw InvalidInput("texture size must be >= 16");

    // (1) Charts from the coarsest level's base regions (every face its own region without levels).
    static const std::vector<uint32_t> kNoRegions;
    const std::vector<uint32_t>& regions = multires.levels.empty() ? kNoRegions : multires.levels.back().faceRegion;
    ChartOptions chartOptions = options.charts;
    chartOptions.threads = options.threads;
    res.charts = buildCharts(mesh, regions, chartOptions);

    // The original faces by place, for closest-point and near-face queries (not held while the
    // charts are solved, the run's peak); the typical face size is where those queries' search
    // boxes start.
    const double radius = typicalFaceSize(mesh);
    std::vector<LocalChart> charts = localCharts(mesh, multires, res.charts, FaceGrid(mesh, 1.0, options.threads), radius);  // (2)
    solveCharts(charts, options, res);                                         // (3)
    splitFailedCharts(mesh, options, charts, res);                             // (3b)
    if (!options.layout) {
        res.seconds = secondsSince(t0);
        return res;
    }
    double chartUvArea = measureCharts(charts, res);                           // (4)
    for (LocalChart& c : charts) alignChart(c.uv);
    // (5)-(7), then the LOD0 fallback: original faces still folded in the packed atlas (a chart
    // map that is not injective, corners that fold once rounded to float) leave their charts as
    // single-face charts of at least 2 texels a side, and the atlas is laid out again.
    constexpr int kMaxCarvePasses = 4;
    const FaceGrid grid(mesh);
    for (int pass = 0;; ++pass) {
        layoutAtlas(mesh, multires, charts, chartUvArea, grid, radius, options, res);
        res.floatRepairs = nudgeRoundedSliverCorners(mesh, res.charts.faceChart, res.cornerUV);
        const std::vector<uint32_t> folded = foldedAtlasFaces(mesh, options.threads, res);
        if (folded.empty() || pass == kMaxCarvePasses || res.texelsPerUnit <= 0) break;
        const size_t before = res.carvedFaces;
        chartUvArea += carveFaces(mesh, folded, (pass + 2.0) / res.texelsPerUnit, charts, res);
        if (pass == 0 || res.carvedFaces > before)
            res.warnings.push_back(std::to_string(folded.size()) + " original faces folded in the atlas (" +
                                   std::to_string(res.flips) + " flipped, " + std::to_string(res.overlaps) +
                                   " overlapping); each now has a chart of its own");
    }
    if (res.atlasSize > options.textureSize)
        res.warnings.push_back(std::to_string(res.charts.chartCount) + " charts and " + std::to_string(res.islands.size()) +
                               " level islands do not fit a " + std::to_string(options.textureSize) +
                               " atlas at any density; they are laid out on a " + std::to_string(res.atlasSize) + " atlas");
    if (options.progress) options.progress(1.0);
    res.seconds = secondsSince(t0);
    return res;
}

}  // namespace lodbake
