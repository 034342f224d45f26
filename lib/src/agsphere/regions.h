// Private to lib/src/agsphere: cuts of the sphere's quadtree and the regions they make.
#pragma once

#include <cstdint>
#include <vector>

#include "agsphere/topology.h"

namespace lodbake::agsphere_detail {

// A cut of the quadtree: for every finest cell (at Topology::maxDepth), the depth of its selected
// ancestor.
using Cut = std::vector<uint8_t>;

struct CellId {
    uint8_t depth = 0;
    uint32_t index = 0;
};

// Key ordering cells by depth, then index.
inline uint64_t cellKey(CellId c) { return (uint64_t(c.depth) << 32) | c.index; }

// Finest cells (at maxDepth) under one cell at `depth`: cell c covers [c * span, (c + 1) * span).
inline uint32_t finestSpan(int maxDepth, int depth) { return 1u << (2 * (maxDepth - depth)); }

// The ancestor at `depth` of finest cell `finest`.
inline uint32_t ancestorAt(uint32_t finest, int maxDepth, int depth) { return finest >> (2 * (maxDepth - depth)); }

// The selected cell holding face f's normal.
inline CellId faceCell(const Topology& t, const Cut& cut, uint32_t f) {
    uint32_t fc = t.finestCell[f];
    uint8_t d = cut[fc];
    return {d, ancestorAt(fc, t.maxDepth, d)};
}

// Regions of a cut: maximal sets of faces connected across manifold edges whose normals fall in
// one selected cell. Pinned (outline) and degenerate faces are regions of their own.
struct Regions {
    std::vector<uint32_t> of;     // face -> dense region id (numbered by smallest face)
    std::vector<uint32_t> rep;    // region -> smallest face id
    std::vector<CellId> cell;     // region -> its cell
    std::vector<uint32_t> faceOffset, faces;  // region -> faces (ascending)
    // Region -> cell error threshold contribution: the largest distance (model units) of a region
    // vertex to the region's plane (area-weighted normal through the area-weighted centroid).
    std::vector<double> flatness;
    uint32_t count() const { return uint32_t(rep.size()); }
};

// \pre cut.size() == sphereCellCount(t.maxDepth), every entry <= t.maxDepth.
Regions buildRegions(const Topology& t, const Cut& cut);

}  // namespace lodbake::agsphere_detail
