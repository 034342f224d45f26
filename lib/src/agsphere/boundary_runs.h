// Private to lib/src/agsphere: region boundaries split into runs, and their simplification.
#pragma once

#include <cstdint>
#include <vector>

#include "agsphere/regions.h"
#include "agsphere/topology.h"

namespace lodbake::agsphere_detail {

// True when half-edge h separates two regions or lies on a mesh border or non-manifold edge.
inline bool isBoundary(const Topology& t, const Regions& r, uint32_t h) {
    uint32_t o = t.twin[h];
    return o >= kNonManifoldEdge || r.of[o / 3] != r.of[h / 3];
}

// A maximal chain of boundary edges between junction vertices, shared by exactly the same two
// regions (or by one region and the mesh border / a non-manifold edge).
struct Run {
    std::vector<uint32_t> vertices;  // v0 .. vm (closed when v0 == vm)
    uint32_t regionA = kNone, regionB = kNone;  // regionA < regionB; regionB = kNone: border or non-manifold
    bool nonManifold = false;
    bool restored = false;  // keeps every vertex
    double tolerance = 0;   // Douglas-Peucker distance, model units
};

struct Runs {
    std::vector<Run> runs;
    std::vector<char> junction;     // per vertex
    std::vector<uint32_t> runOf;    // per vertex: the run of a non-junction boundary vertex, else kNone
    std::vector<uint32_t> posInRun; // per vertex: its index in that run
    std::vector<char> kept;         // per vertex: on a boundary and kept after simplification
};

// The runs of r, simplified: each run's tolerance is toleranceScale times the smaller error
// threshold (largest region flatness) of its two cells, at least 1e-9 of the bounding diagonal
// (toleranceScale <= 0: that floor, so only exactly straight runs lose vertices); runs next to a
// pinned face keep every vertex. Where two simplified runs would share an edge, one keeps more.
// \pre finite positions.
Runs buildBoundaryRuns(const Topology& t, const Regions& r, double toleranceScale);

// Douglas-Peucker on one run: sets `kept` of its interior vertices. Closed runs keep at least 3
// vertices, runs whose two ends are the same vertex at least 2 interior ones; restored and
// non-manifold runs keep all.
void simplifyRun(const Topology& t, Run& run, std::vector<char>& kept);

// The runs adjacent to each region, in run order.
std::vector<std::vector<uint32_t>> regionRuns(const Runs& runs, uint32_t regionCount);

// Boundary loops of region i (kept vertices only), walking boundary half-edges with the region
// on the left; empty when the walk does not close.
std::vector<std::vector<uint32_t>> regionLoops(const Topology& t, const Regions& r, const Runs& runs, uint32_t i);

// Distance from p to segment ab; *param (when given) = the closest point's parameter in [0, 1].
double pointSegmentDistance(Vec3 p, Vec3 a, Vec3 b, double* param = nullptr);

}  // namespace lodbake::agsphere_detail
