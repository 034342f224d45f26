// texture-refine: the multiresolution texture hierarchy (thesis chapter 4, DESIGN.md "Texture
// hierarchy"). Two hierarchies over a parameterized multiresolution asset:
//   - MIP-style: every layout baked at several resolutions with the same UVs (lowers the pixel
//     resolution error only);
//   - rank refinement: each chart of the rank-(j-1) layout is split into about 4 charts from the
//     regions of a finer geometry level l_j (merged by E_region, each a disk), re-parameterised
//     with the energy of parameterize over the simplification pairs of the levels it serves
//     (0..l_j) and re-baked from the original appearance. Rank j is valid for levels 0..l_j.
//     l_0 = n (the coarsest level, T0); l_j is the coarsest level finer than l_{j-1} whose
//     regions split the rank-(j-1) charts into a layout that lowers both E and the UV-area /
//     3D-area std-dev of T0 over levels 0..v for some v <= l_j (levels whose regions equal the
//     coarser level's add nothing; level 0 = every original face its own region). Pieces that
//     solve worse than their parent are split again (finer, at last the parent whole). A rank is
//     valid for the levels 0..v: the longest run on which it adds no flipped or overlapping
//     level triangle to T0's, its chart boundaries cut at most maxExtraCutFraction of the level's
//     triangles more than T0's do (a split of a non-disk region makes boundaries that are not
//     p-boundaries), and it lowers E and the std-dev of T0 over 0..v.
// Geometry levels are numbered as in `pack`: 0 = the original mesh, k = Multires::levels[k-1].
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"
#include "lodbake/param/chart_uv.h"
#include "lodbake/param/parameterize.h"

namespace lodbake {

// Quality of one chart layout over the geometry levels firstLevel..lastLevel it serves.
struct LayoutMeasure {
    uint32_t lastLevel = 0;             // levels 0..lastLevel measured
    uint32_t charts = 0;
    size_t pairs = 0;                   // simplification pairs of levels 1..lastLevel inside a chart
    ChartEnergy energy;                 // sum over charts at resolution modifier r = 1 (512^2 texels)
    std::vector<ChartEnergy> chartEnergies;  // per chart, r = 1
    double areaRatioStdDev = 0;         // std-dev of (UV area / 3D area) / mean over the levels' triangles
    std::array<uint32_t, 10> areaRatioHistogram{};  // normalised ratio bins over [0, 2]; the last holds >= 1.8
    size_t triangles = 0;               // level triangles measured (all levels, 3D-degenerate skipped)
    std::vector<UVInjectivity> levels;  // per level 0..lastLevel, UVs as `pack` assigns them
    std::vector<size_t> crossing;       // per level: triangles whose corners are not all vertices of their chart
                                        // (projected corners; island triangles do not count)
    size_t flips = 0, overlaps = 0;     // summed over levels
};

// Measures `layout` (ChartLayout convention: per original face corner, [0,1], v down) over levels
// 0..lastLevel. Energies use model-unit UVs (the layout scaled so its UV area equals the 3D area)
// and the simplification pairs of levels 1..lastLevel. Level triangles get the UVs `pack` gives
// them: an island's when the layout has one for their vertex triple, else those of the chart
// levelTriangleCharts picks, a corner outside it the UV of the closest point of the chart's surface.
// Charts and the levels' injectivity checks on `threads` threads (0 = all cores), the same
// measure for any count.
// \pre layout matches mesh; lastLevel <= multires.levels.size().
LayoutMeasure measureLayout(const TriMesh& mesh, const Multires& multires, const ChartLayout& layout,
                            uint32_t lastLevel, const ChartEnergyOptions& energy = {}, int threads = 1);
// measureLayout over levels 0..v for every v <= lastLevel (index v), each equal to measureLayout's
// for v, from one pass over the levels: each level's UVs, injectivity and crossings are made once.
std::vector<LayoutMeasure> measureLayoutLevels(const TriMesh& mesh, const Multires& multires, const ChartLayout& layout,
                                               uint32_t lastLevel, const ChartEnergyOptions& energy = {}, int threads = 1);

// Splits every chart of `parentChart` (chart id per original face, < parentCount) into about
// `perChart` charts: the parts of the regions `faceRegion` (representative face per face) inside
// it are merged by E_region (buildCharts), each result a disk. Returns the new charts as a
// faceRegion table (representative = the smallest face of each new chart) and their count.
std::vector<uint32_t> splitCharts(const TriMesh& mesh, const std::vector<uint32_t>& parentChart, uint32_t parentCount,
                                  const std::vector<uint32_t>& faceRegion, uint32_t perChart, uint32_t& count);
// The same with a target per parent chart.
std::vector<uint32_t> splitCharts(const TriMesh& mesh, const std::vector<uint32_t>& parentChart, uint32_t parentCount,
                                  const std::vector<uint32_t>& faceRegion, const std::vector<uint32_t>& perChart,
                                  uint32_t& count);

// Pieces made by splitCharts per (parent chart, target pieces): per face of the parent chart in
// ascending order its new chart's representative, and the number of pieces. Valid for one
// parentChart and faceRegion table.
using SplitMemo = std::map<std::pair<uint32_t, uint32_t>, std::pair<std::vector<uint32_t>, uint32_t>>;
// The same, taking the pieces of a (parent chart, target) `memo` holds and adding the ones it makes.
std::vector<uint32_t> splitCharts(const TriMesh& mesh, const std::vector<uint32_t>& parentChart, uint32_t parentCount,
                                  const std::vector<uint32_t>& faceRegion, const std::vector<uint32_t>& perChart,
                                  uint32_t& count, SplitMemo* memo, int threads = 1);

// How refineTextures parameterises rank layouts by default: parameterize's defaults on a
// 512-texel atlas.
inline ParameterizeOptions rankParameterizeDefaults() {
    ParameterizeOptions p;
    p.textureSize = 512;
    return p;
}

struct RefineOptions {
    // The parameterisation of the rank layouts: E's alpha and beta, Ceres iterations and level
    // rounds (param.solve); the atlas side they are packed for, texels, which is also the
    // resolution E is measured at (param.textureSize); the gutter between their charts, texels
    // (param.gutter); and the threads charts are solved and textures baked on (param.threads,
    // 0 = all cores; output identical for any value). refineTextures sets param.charts (no
    // merging: the split charts are final), param.levelIslands and param.progress itself.
    ParameterizeOptions param = rankParameterizeDefaults();
    std::vector<int> sizes{128, 256, 512, 1024};  // MIP-style: every layout baked at each of these sides
    // false: the hierarchy's textures (rank, levels, size) are recorded without baking their
    // images. `pack` reads only those (it re-bakes every page from the original), so the chain
    // skips the bakes of an intermediate nobody else sees.
    bool bakeImages = true;
    // Rank layouts (j >= 1) are baked only at sizes >= this (the largest size when none is): their
    // extra chart seams and gutters cost more than they give on small pages. `pack` uses a rank
    // only for levels whose page is at least its smallest size.
    int minRefinedSize = 128;
    // A rank serves a level only when its chart boundaries cut at most this fraction of the
    // level's triangles more than T0's do (cut triangles that have an island do not count), and
    // it has no flipped or overlapping triangle there.
    double maxExtraCutFraction = 0.005;
    // Merge pieces back while their boundaries cut more level triangles than the parent chart did.
    bool keepLevelTrianglesWhole = false;
    // A candidate rank is not made when T0's UV-area / 3D-area std-dev over the levels it would
    // serve is below this: T0 is then already near-isometric there and refinement only adds seams.
    double minAreaRatioStdDev = 0.05;
    int ranks = 2;                         // refine up to this rank (fewer when no finer level splits the charts)
    uint32_t splitPerChart = 4;            // charts per parent chart
    // Budget: a mesh with more triangles than this keeps T0 for every level (no rank >= 1; a
    // warning says so). Each rank re-solves every chart of the mesh several times, which takes
    // minutes of CPU at a million triangles. 0 = no limit.
    size_t maxTriangles = 500000;
    std::function<bool(double)> progress;  // fraction done; may be empty
};

struct RankResult {
    uint32_t rank = 0;
    uint32_t firstLevel = 0, lastLevel = 0;  // geometry levels served (lastLevel <= the level of its regions)
    ChartLayout layout;                      // rank 0: a copy of Multires::charts
    LayoutMeasure measure;                   // this layout over levels 0..lastLevel
    LayoutMeasure base;                      // T0 over the same levels (the comparison)
    // False for T0 over the triangle budget (RefineOptions::maxTriangles): no rank is compared with
    // it, so `measure` and `base` are not taken (on a million triangles they cost seconds for
    // figures only the report shows).
    bool measured = true;
    uint32_t regions = 0;                    // regions of level lastLevel (rank >= 1)
    size_t chartFlips = 0, chartOverlaps = 0, levelFlipsInSolve = 0;  // from parameterize (rank >= 1)
    // Rounds (<= 3) in which parent charts whose pieces came out worse than the parent itself (higher
    // E over the served levels, or a piece left at its Tutte map) were split again: finer, and in
    // the last round not at all.
    uint32_t resplits = 0;
    uint32_t unsplit = 0;                    // parent charts kept whole
    std::map<std::string, uint32_t> methods;  // charts per solve method of parameterize ("ceres", "tutte", ...)
    double parameterizeSeconds = 0;
};

struct RefinedImage {
    uint32_t rank = 0;
    int size = 0;
    Image image;  // empty (no encoded bytes) when RefineOptions::bakeImages is false
    size_t coveredTexels = 0;
    double seconds = 0;
};

// A candidate rank that was not kept (its level's regions were tried, the next finer level follows).
struct RejectedRank {
    uint32_t level = 0;   // the level whose regions were tried
    uint32_t charts = 0;
    std::string reason;
};

struct RefineResult {
    std::vector<RankResult> ranks;   // rank 0 first
    std::vector<RejectedRank> rejected;
    std::vector<RefinedImage> images;  // rank then size ascending
    std::vector<std::string> warnings;  // fallbacks taken (e.g. the triangle budget)
    double seconds = 0;
};

// \pre multires.charts is set (parameterize ran) and matches asset.mesh.
// \throw Impossible (no chart layout, no levels to refine from), InvalidInput (inconsistent
//        multires), SolverError (a rank layout folds), IOError (bake).
RefineResult refineTextures(const Asset& asset, const Multires& multires, const RefineOptions& options = {});

// Appends the images to the asset and records the hierarchy in multires.textures (replacing any).
void applyTextureHierarchy(Asset& asset, Multires& multires, const RefineResult& result);

}  // namespace lodbake
