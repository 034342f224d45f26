// parameterize: charts from the coarsest level's base regions, one injective UV map per chart
// minimising E = beta E_pixel + (1 - beta) E_poly, and a shelf-packed square atlas (thesis 3.3;
// the packer is shelfPack of lodbake/atlas/atlas.h).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"
#include "lodbake/chart/charts.h"
#include "lodbake/chart/level_charts.h"  // LevelUV::chart is levelTriangleCharts' choice
#include "lodbake/param/chart_uv.h"

namespace lodbake {

// Chart solves remembered across parameterize calls (texture-refine re-solves layouts in which
// most charts are unchanged): a chart whose local mesh, pairs and level triangles are exactly
// those of a remembered one takes its map and report instead of being solved again, so results
// are the same as without it. Valid for one setting of ParameterizeOptions::solve (the texture
// size is part of the key); one parameterize call at a time may use it.
struct ChartSolveCache;
std::shared_ptr<ChartSolveCache> makeChartSolveCache();

struct ParameterizeOptions {
    ChartOptions charts;
    // The per-chart solve: E's alpha and beta, Ceres iterations (0 = keep the Tutte maps) and the
    // level rounds. solve.energy.resolution is not read: parameterize sets it from textureSize.
    ChartSolveOptions solve;
    int textureSize = 1024;    // atlas side in texels (square)
    int gutter = 4;            // texels between charts and around the border (>= 4 recommended)
    int threads = 1;           // charts solved in parallel (0 = all cores); results are identical for any value
    // Last resort against folded levels: a level triangle that is still flipped or overlapping in
    // the packed atlas gets its own UV island (see LevelIsland). false = leave it folded (reported).
    bool levelIslands = true;
    // A level triangle whose corners are not all vertices of one chart (it crosses a chart
    // boundary; its outside corners would take projected UVs and smear the neighbouring chart's
    // texture over it) gets its own island too, baked from the closest original surface, unless
    // their smallest footprints would take more than a quarter of the atlas (then none does).
    bool crossingIslands = true;
    std::function<bool(double)> progress;  // fraction done; may be empty
    std::shared_ptr<ChartSolveCache> solveCache;  // may be empty (every chart solved)
    // false: stop once the charts are solved and failed charts split (step 3b): the result has the
    // charts, each chart's solve (ChartReport: initial and final E, method, start, iterations) and
    // the solve totals, and no atlas (cornerUV, levels, islands empty; no stretch figures). Those
    // solves are the full run's: the atlas fallbacks after them carve faces into charts of their
    // own and leave every solved chart's report as it is.
    bool layout = true;
};

struct ChartReport {
    uint32_t faces = 0, vertices = 0, pairs = 0;
    ChartEnergy initial, final;             // E of the solve's start map and of the kept map
    double stretchL2 = 0, stretchLinf = 0;  // Sander et al., normalised so 1 = isometric up to scale
    double areaRatioStdDev = 0;             // std-dev of (UV area / 3D area) / (chart mean ratio)
    size_t flips = 0, overlaps = 0;
    size_t levelFlips = 0;                  // flipped level triangles of this chart (all levels)
    int iterations = 0;
    std::string method;                     // "ceres", "ceres-beta1", "lscm", "tutte", "single-face" (a
                                            // face split off by the fold fallback) or "failed" (no map)
    std::string start;                      // the solve's start: "lscm" or "tutte" (empty: not solved)
    std::string failure;                    // why the solver failed ("failed" only)
    double seconds = 0;
};

// A level triangle that could not keep injective UVs inside its chart (still flipped or
// overlapping another triangle of its level once the charts are packed, typically because a
// collapse moved it across a chart cut): it gets its own small UV island in T0, the triangle laid
// out flat with its 3D edge lengths at the atlas texel density (at least ~2 texels high), packed
// like a chart. The bake fills the island by sampling, for each texel, the original surface
// point closest to the corresponding point of the coarse triangle (among `faces`). Every
// occurrence of the same vertex triple in any level uses the island.
struct LevelIsland {
    Tri vertices{};                   // welded vertex ids, the level's corner order (CCW)
    std::array<Vec2, 3> uv{};         // atlas UV per corner (glTF: [0,1], v down)
    std::vector<uint32_t> faces;      // original faces the bake samples (charts of its corners and face)
    uint32_t level = 0;               // first Multires level (1-based) where it folded
};

// Final atlas UVs of one level's triangles, exactly as applyAtlas writes them.
struct LevelUV {
    std::vector<uint32_t> chart;               // chart the triangle takes its UVs from; chartCount + i = island i
    std::vector<std::array<Vec2, 3>> uv;       // atlas UV per corner (glTF convention)
    size_t projectedCorners = 0;               // corners that are not vertices of their chart (projected)
    size_t islands = 0;                        // triangles of this level using an island
};

struct ParameterizeResult {
    ChartResult charts;
    std::vector<std::array<Vec2, 3>> cornerUV;  // per original face corner, atlas UV (glTF: [0,1], v down)
    std::vector<ChartReport> chartReports;
    ChartEnergy initialTotal, finalTotal;      // sums over charts
    double stretchL2 = 0, stretchLinf = 0;     // whole atlas (area-normalised)
    double areaRatioStdDev = 0;                // per triangle (UV area / 3D area), normalised by the mean
    std::array<uint32_t, 10> areaRatioHistogram{};  // bins of normalised ratio over [0, 2]; the last holds >= 1.8
    size_t flips = 0, overlaps = 0;            // original faces still folded in the packed atlas (0 unless
                                               // the fallback below ran out of passes)
    size_t carvedFaces = 0;                    // faces moved to single-face charts (fold fallback)
    size_t failedCharts = 0;                   // charts the solver could not map (their faces carved)
    std::vector<std::string> warnings;         // each fallback taken, one line each
    size_t levelFlips = 0;                     // flipped level triangles, all charts and levels
    std::vector<LevelIsland> islands;          // level-triangle islands (fallback), in creation order
    std::vector<LevelUV> levels;               // per Multires level (empty when there are no levels)
    size_t floatRepairs = 0;                   // sliver faces whose corner UV moved by a float step (they flipped once rounded)
    size_t crossingIslandsSkipped = 0;         // crossing triangles left on projected UVs (too many for the atlas)
    int atlasSize = 0;                         // atlas side, texels: textureSize, or larger when the
                                               // charts need more texels than it has (warnings say so)
    double texelsPerUnit = 0;                  // atlas density (texels per model unit)
    double atlasFill = 0;                      // fraction of the atlas covered by charts (UV area)
    double seconds = 0;
};

// \pre multires was produced for `mesh` (faceRegion of the last level, pairs indices in range).
//      With no levels every face starts as its own region.
// A chart the solver cannot map, and an original face still folded once the atlas is packed, fall
// back to single-face charts (res.warnings says so); level triangles that fold fall back to islands.
// \throw InvalidInput (inconsistent multires), Impossible (no triangles; the charts and islands
//        do not fit a 16384 atlas).
ParameterizeResult parameterize(const TriMesh& mesh, const Multires& multires, const ParameterizeOptions& options = {});

struct UVInjectivity {
    size_t triangles = 0;  // triangles checked (index-degenerate ones are skipped)
    size_t flips = 0;      // signed UV area <= 0 relative to the atlas orientation (CCW in 3D = CCW in UV)
    size_t overlaps = 0;   // triangles whose UV interior intersects another checked triangle's interior
};

// Checks UV triangles given in glTF convention ([0,1], v down; a front-facing triangle is CCW with
// v up). Flipped triangles are not tested for overlap. `tolerance` (UV units) is the overlap depth
// below which two triangles count as touching (shared edges, vertices on an edge). On `threads`
// threads (0 = all cores); the counts do not depend on the number.
UVInjectivity checkUVInjectivity(const std::vector<std::array<Vec2, 3>>& tris, double tolerance = 1e-7, int threads = 1);
// The same, checking `tris` in place instead of a copy (a million-triangle level's UVs are 48 MB).
UVInjectivity checkUVInjectivity(std::vector<std::array<Vec2, 3>>&& tris, double tolerance = 1e-7, int threads = 1);

// The same for a level's triangles with their TEXCOORD_0 taken from mesh.wedges.uv0 via cornerWedges.
UVInjectivity checkLevelUVs(const TriMesh& mesh, const std::vector<Tri>& triangles, const std::vector<Tri>& cornerWedges,
                            double tolerance = 1e-7, int threads = 1);

struct TextureDeviationOptions {
    size_t samples = 200000;  // area-weighted sample points on the level's triangles (deterministic)
    // Level islands (ParameterizeResult::islands): a level triangle with an island's vertex triple
    // is measured against the closest point of the island's faces, which is what its texels show.
    const std::vector<LevelIsland>* islands = nullptr;
    int threads = 1;  // 0 = all cores; the figures are the same for any count
};

struct TextureDeviation {
    size_t samples = 0;
    size_t outside = 0;        // samples whose UV lies outside every original triangle of the chart
    size_t islandSamples = 0;  // samples on island triangles
    double mean = 0, rms = 0, max = 0;          // |p - q|, model units
    double diagonal = 0;                        // bounding-box diagonal of the mesh
    double meanRelative = 0, maxRelative = 0;   // mean and max / diagonal
};

// Texture deviation of `level` under `layout`: for points p on the level's triangles with UV u
// (interpolated from mesh.wedges.uv0 through level.cornerWedges), the distance to the original
// surface point q with atlas UV u in the same chart (layout.cornerUV of the chart's original faces).
// \pre applyAtlas ran (level corners index wedges with atlas UVs); layout matches mesh.
// \throw InvalidInput on size mismatches.
TextureDeviation textureDeviation(const TriMesh& mesh, const Level& level, const ChartLayout& layout,
                                  const TextureDeviationOptions& options = {});

}  // namespace lodbake
