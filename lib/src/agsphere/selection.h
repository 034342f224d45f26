// Private to lib/src/agsphere: the per-depth estimates and the cut each level selects.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "agsphere/regions.h"
#include "agsphere/topology.h"
#include "lodbake/agsphere/agsphere.h"

namespace lodbake::agsphere_detail {

// Per depth and cell: what the selection trades.
struct DepthTables {
    std::vector<std::vector<uint32_t>> estimate;  // [depth][cell] estimated triangles
    std::vector<std::vector<float>> threshold;    // [depth][cell] error threshold, model units
};

// Fills tables.estimate[depth] and tables.threshold[depth] from the uniform cut at `depth`
// (regions, simplified runs, triangles an ear clipping of their loops would make) and returns
// that depth's statistics. \pre tables sized to t.maxDepth + 1.
AgsphereDepthStats measureDepth(const Topology& t, int depth, double boundaryTolerance, DepthTables& tables);

// How a cell is refined relative to the views and lights.
enum class CellClass : uint8_t {
    Orthogonal = 0,  // within the silhouette band of a view or light: refined first
    Other = 1,
    Reference = 2,   // facing a view (or lit, without views): refined last
    Coarsest = 3     // facing away from every light (or view, backCellsCoarsest): never refined
};

// \pre options' views and lights in the sphere's frame, unit.
CellClass classify(const AgsphereOptions& options, uint32_t cell, int depth);

struct Selection {
    Cut cut;
    uint64_t estimate = 0;  // estimated triangles of the cut
    std::string stopReason; // see AgsphereLevelStats::stopReason
};

// The cut whose estimated triangle count comes closest to `target`: leaves of the quadtree refined
// round by round (silhouette cells, then the others, then reference cells; within a class the
// largest error threshold first). \pre options in the sphere's frame (see classify).
Selection selectCut(const Topology& t, const AgsphereOptions& options, const DepthTables& tables, uint64_t target);

// Refines the cut until the selected cells of every two neighbouring finest cells are at most two
// depths apart. neighbours = sphereNeighbourTable(t.maxDepth).
void balanceCut(const Topology& t, const std::vector<std::array<uint32_t, 3>>& neighbours, Cut& cut);

// Selected cells per depth and per class.
void countCutCells(const Topology& t, const AgsphereOptions& options, const Cut& cut, AgsphereLevelStats& stats);

}  // namespace lodbake::agsphere_detail
