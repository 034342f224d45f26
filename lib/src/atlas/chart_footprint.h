// A chart's shape on a page (packAtlas): its minimum-area orientation (Oriented), and its
// footprint, the texels its triangles touch at a density grown by the gutter radius, in each
// quarter turn and on the coarser grids of the page search.
//
// Reference: Freeman & Shapira, "Determining the minimum-area encasing rectangle for an arbitrary
// closed curve" (1975), minimum-area rectangle from a hull edge.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "lodbake/atlas/atlas.h"

namespace lodbake::atlas_detail {

// Texel-aligned charts start on blocks of this many texels and are not turned: the page's first
// log2(kAlignedBlock) mip levels then average the same source texels as the original's mips.
constexpr int kAlignedBlock = 16;

// A chart turned to its minimum-area rectangle: rotate by -angle, then [minX, minX+w] x [minY, minY+h].
struct Oriented {
    double c = 1, s = 0;  // cos, sin of the angle
    double minX = 0, minY = 0, w = 0, h = 0;
    bool aligned = false; // texel-aligned (AtlasOptions::texelAligned)
    int turns = 4;        // quarter turns tried in placement (texel-aligned: 1)
    double uvArea = 0;
    std::vector<std::array<Vec2, 3>> triangles;  // in the rotated frame, [0, w] x [0, h]
};

// The frame a chart is tried in (with the placement's four quarter turns): as it is when
// texel-aligned, else its minimum-area rectangle only (further angles cost time in proportion and
// pack no tighter; see docs/benchmarks.md).
ChartFrame chartFrame(const AtlasChart& chart, bool aligned);

// The chart in its frame: the rectangle and the UV triangles turned into [0, w] x [0, h] (a chart
// without triangles: its hull's fan).
Oriented orientedIn(const AtlasChart& chart, const ChartFrame& frame, bool aligned);

// The orientations a chart is tried in: its one frame.
inline std::vector<Oriented> chartOrientations(const AtlasChart& chart, bool aligned) {
    return {orientedIn(chart, chartFrame(chart, aligned), aligned)};
}

// Texels an extent takes at density t; held below 2^30 so that sums and gutters stay in int range
// at any density asked for.
inline int texels(double extent, double t) { return int(std::clamp(std::ceil(extent * t - 1e-9), 1.0, double(1 << 30))); }

// A chart's footprint on the page at one density and rotation: the texels its triangles touch
// (conservative rasterisation), grown by the gutter radius, as runs [a, b] per row.
struct Footprint {
    int w = 0, h = 0;                                  // grid size, texels
    std::vector<std::vector<std::pair<int, int>>> rows;  // occupied runs per row, inclusive
    std::vector<int> rowCells;                         // occupied texels per row
    std::vector<int> rowLongest;                       // longest run per row
    double centroidRow = 0;                            // mean row of the occupied texels
    int leastCells = 0, leastLongest = 0;              // smallest rowCells and rowLongest
    // Rectangles of occupied cells that cover the occupied cells exactly once, largest first:
    // rows [top, top + rows), columns [a, b]; `level` = floor(log2 rows) picks BitmapPage's row
    // unions. Each lies within a band of kBlockRows rows, 2^k-aligned from row 0, halved down to
    // single rows: a band's block holds the columns all its rows occupy that the enclosing band's
    // blocks do not.
    struct Block {
        int top = 0, rows = 1, a = 0, b = 0, level = 0;
    };
    std::vector<Block> blocks;
};

// The most rows a footprint's block spans (BitmapPage keeps the union of up to this many
// consecutive rows).
constexpr int kBlockRows = 16;

// The occupied cells of a w x h grid, row by row: runs [a, b] sorted, disjoint and not touching.
struct RowRuns {
    int w = 0, h = 0;
    std::vector<size_t> first;                 // row y's runs are runs[first[y], first[y + 1])
    std::vector<std::pair<int, int>> runs;
    size_t cells() const;
};

// Every cell within `radius` cells (a square) of an occupied one; radius >= 0.
RowRuns growByRadius(const RowRuns& cells, int radius);

// The chart rasterised in its oriented frame at density t: cells [pad, pad + ceil(w t)) hold the
// chart, pad = radius cells on each side hold its half of the gutter (the raster grown by a
// square of that radius). `rasterCells`, when given, receives the raster's cells before growing.
RowRuns chartRuns(const Oriented& c, double t, int radius, size_t* rasterCells = nullptr);

// The same as one byte per cell (row-major, 1 = occupied).
std::vector<uint8_t> chartMask(const Oriented& c, double t, int radius, int& gw, int& gh, size_t* rasterCells = nullptr);

// Where a chart lies on the page: its orientation, quarter turn and grid, the turned grid's offset.
struct Slot {
    int x = 0, y = 0, rotation = 0;
    size_t orientation = 0;  // index into the chart's orientations
    int gw = 0, gh = 0;  // the unrotated grid
};

// The affine UV -> page map of a chart: oriented frame, grid (density t, gutter radius), quarter
// turn, page offset.
std::array<double, 6> placementFor(const Oriented& c, const Slot& s, double t, int radius);

// Quarter turns of the grid (counter-clockwise in texel space, determinant +1): cell (x, y) of
// the turned grid is cell (y, gh-1-x) of the gw x gh grid at one turn, (gw-1-x, gh-1-y) at two,
// (gw-1-y, x) at three; continuous points use placementFor's matching formulas.
Footprint rotatedFootprint(const RowRuns& cells, int rotation);
Footprint rotatedFootprint(const std::vector<uint8_t>& mask, int gw, int gh, int rotation);

// The cells on a grid `scale` times coarser: a coarse cell is occupied when any of its cells is.
RowRuns coarsen(const RowRuns& cells, int scale);

// Every chart's footprints at one density, gutter and search scale (the four quarter turns of its
// block-rounded mask), computed once and shared by every page width and order tried.
struct ChartFootprints {
    int turns = 4;       // the quarter turns tried (Oriented::turns)
    int gw = 0, gh = 0;  // the unrotated texel grid
    int cw = 0, ch = 0;  // ... in blocks
    std::array<Footprint, 4> rot;  // the first `turns` quarter turns (the rest stay empty)
    size_t raster = 0, footprint = 0;  // texels: conservative raster, and grown by the gutter radius
};

struct Footprints {
    double t = 0;
    int scale = 1;
    int radius = 0;  // the gutter radius each footprint is grown by
    std::vector<std::vector<ChartFootprints>> charts;  // per chart, per orientation
};

using Orientations = std::vector<std::vector<Oriented>>;  // per chart: the orientations tried

// Every chart's footprints at density t with the gutter and search scale given, on `threads` threads.
// `twiceCoarser`, when given, receives the same at scale 2 * scale (from the same rasterisation).
Footprints footprintsAt(const Orientations& charts, double t, int gutter, int scale, int threads, Footprints* twiceCoarser = nullptr);

// Footprints at density t with the gutter and search scale given, with no chart's yet.
Footprints noFootprints(size_t charts, double t, int gutter, int scale);

// Adds the footprints of charts `which` (indices into `charts`) to fp (made by noFootprints or
// footprintsAt for the same charts), on `threads` threads: the same as footprintsAt's.
void addFootprints(const Orientations& charts, const std::vector<size_t>& which, Footprints& fp, int threads);

// Whether every chart has an orientation and quarter turn whose footprint (density t, grown by the
// gutter radius, in blocks of `scale` texels, as footprintsAt makes it) lies within the bitmap of a
// binW x binH page. When not, packing there fails wherever the other charts go: this tells so from
// the charts' extents, before any rasterisation.
bool footprintsFit(const Orientations& charts, double t, int gutter, int scale, int binW, int binH);

}  // namespace lodbake::atlas_detail
