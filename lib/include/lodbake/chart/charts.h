// Chart building for texture parameterization (thesis 3.3.1): the base regions of the coarsest
// level (sets of original faces bounded by p-boundaries) are merged into a few planar, compact,
// disk-shaped charts. Chart boundaries therefore lie on p-boundaries only, so one atlas (T_0)
// is valid for every level of the chain.
#pragma once

#include <cstdint>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

struct ChartOptions {
    // Stop merging once this many charts remain; 0 = no bound (merge while the limits below allow).
    // When > 0 and the limits leave more charts, merging continues ignoring maxNormalConeDegrees and
    // maxRegionEnergy (the disk rule is never relaxed).
    uint32_t maxCharts = 0;
    // A merge is refused when the merged chart's face normals deviate from its mean normal by more
    // than this (degrees, half-angle of the normal cone). 0 = no limit.
    double maxNormalConeDegrees = 80;
    // A base region whose normal cone exceeds this (degrees) is split before merging, although
    // its pieces' new boundaries are not p-boundaries (level corners there get projected UVs).
    // Catches "closed surface minus one face" regions, which no flattening handles. 0 = never.
    double splitNormalConeDegrees = 150;
    // A merge is refused when the merged chart's E_region, with lengths relative to the mesh's
    // bounding-box diagonal, exceeds this. 0 = no limit.
    double maxRegionEnergy = 0;
    // Threads measuring the first list of candidate merges (every pair of neighbouring charts);
    // 0 = all cores. Never changes the result.
    int threads = 1;
};

struct ChartResult {
    std::vector<int32_t> faceChart;  // chart id per original face, 0..chartCount-1 (dense, deterministic)
    uint32_t chartCount = 0;
    uint32_t baseRegions = 0;        // regions in the input faceRegion
    uint32_t splitRegions = 0;       // base regions split (not a disk, or normal cone over the limit)
    uint32_t merges = 0;             // merges applied
};

// Merges the regions of `faceRegion` (faceRegion[f] = representative face of face f's region, e.g.
// the coarsest Level::faceRegion; empty = every face its own region) into charts, lowest E_region
// first (E_region = area(R)/area(M) x (max dist to fitted plane + max_B |x-c| - min_B |y-c|)).
// Every chart is a topological disk (connected, edge- and vertex-manifold, one boundary loop,
// Euler characteristic 1): regions that are not disks, or whose normal cone exceeds
// splitNormalConeDegrees, are first split by growing halves from two far-apart faces; a merge that would not give a disk is refused (this covers "two regions sharing
// more than one boundary run"). A closed surface therefore always gets >= 2 charts.
// \pre faceRegion is empty or has mesh.triangleCount() entries, each < triangleCount().
// \throw InvalidInput when faceRegion has the wrong size or out-of-range entries.
ChartResult buildCharts(const TriMesh& mesh, const std::vector<uint32_t>& faceRegion, const ChartOptions& options = {});

// True when the faces `faces` of `mesh` form a topological disk (see buildCharts).
bool isDisk(const TriMesh& mesh, const std::vector<uint32_t>& faces);

}  // namespace lodbake
