// Private to lib/src/agsphere: the regions of a cut retriangulated from their simplified
// boundaries, with the fallbacks that keep the level valid.
#pragma once

#include <cstdint>
#include <vector>

#include "agsphere/boundary_runs.h"
#include "agsphere/regions.h"
#include "agsphere/topology.h"

namespace lodbake::agsphere_detail {

enum class RegionState : uint8_t {
    Pending,         // not built yet
    Retriangulated,  // new triangles from its simplified boundary
    Kept,            // its original faces (outline faces, and regions that could not be rebuilt)
    Empty            // a degenerate face: no triangles
};

struct RegionOut {
    RegionState state = RegionState::Pending;
    std::vector<Tri> tris;  // vertex ids of the input mesh
    Vec3 axis;              // projection direction used for the ear clipping
};

// The geometry of one level: regions, their runs and each region's triangles.
struct LevelBuild {
    Regions regions;
    Runs runs;
    std::vector<RegionOut> out;  // per region
    uint32_t restoredRuns = 0;   // runs whose simplification was undone
};

// Regions of `cut` -> simplified runs -> ear clipping per region -> fallbacks (restore the runs of
// a failed region, then keep its original faces) until every region is built, no directed edge
// appears twice and no undirected edge more than twice (except where the input already does), and
// no new triangle covers, seen from a view of t.outline, what the original leaves uncovered.
// boundaryTolerance: see buildBoundaryRuns.
LevelBuild buildLevelGeometry(const Topology& t, const Cut& cut, double boundaryTolerance);

// Triangles of a built level.
uint64_t levelTriangleCount(const LevelBuild& level);

}  // namespace lodbake::agsphere_detail
