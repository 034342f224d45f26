// Regions during simplification: face labels, p-boundaries, merges and their records, and the
// E_region shape measure of rule 2 (thesis ch. 2.3 and 3.2; docs/simplify.md).
//
// faceRegion[f] is the representative face of f's region. Region face lists are intrusive linked
// lists merged by union by size, so relabelling is O(F log F) in total. Every merge and every
// re-elected representative is recorded through the HierarchyRecorder. Private to lib/src/simplify.
#pragma once

#include <cstdint>
#include <vector>

#include "collapse_state.h"

namespace lodbake::simplify_detail {

// Groups of regions that one collapse merges, each into one region: group g is
// regions[start[g] .. start[g + 1]), sorted and distinct.
struct MergeGroups {
    std::vector<uint32_t> regions;
    std::vector<uint32_t> start;
    size_t count() const { return start.size() - 1; }
    const uint32_t* begin(size_t g) const { return regions.data() + start[g]; }
    size_t size(size_t g) const { return start[g + 1] - start[g]; }
};

// Accumulated shape of one region.
struct RegionStats {
    double area = 0;  // model units squared
    Vec3 normalSum;   // sum of area-weighted unit normals
    float bmin[3], bmax[3];
};

// The face list of one region: first and last face of its intrusive list, and its length.
struct RegionList {
    uint32_t head, tail, size;
};

struct RegionState {
    std::vector<uint32_t> faceRegion;       // representative face of each face's region
    std::vector<uint32_t> faceRelabelPass;  // pass of each face's last relabel
    std::vector<uint32_t> regionNext;       // next face of the same region (intrusive list)
    std::vector<RegionList> lists;          // per representative (one record: a merge reads all three)
    std::vector<RegionStats> stats;         // per representative
    uint32_t regionCount = 0;
    std::vector<uint32_t> componentRegions;  // regions per component (rule 1)
    double totalArea = 0;                    // of the input, model units squared

    // Scratch of updateRegions.
    std::vector<RingEntry> ringScratch;
    std::vector<uint32_t> fanScratch;
    MergeGroups groupScratch;
};

// Every face is its own region (stats on up to `threads` threads).
void initRegions(RegionState& r, const CollapseState& s, int threads);

void mergeStats(RegionStats& a, const RegionStats& b);
// E_region approximation of a region (docs/simplify.md, rule 2); 0 for an empty region.
float regionShape(const RegionStats& r, double totalArea);

// Whether the spoke e of a ring is a p-boundary: its two faces lie in different regions.
inline bool isPBoundarySpoke(const RegionState& r, const RingEntry& e) {
    return e.f1 != kNone && r.faceRegion[e.f0] != r.faceRegion[e.f1];
}

// The regions a collapse of vi merges when it does not keep a boundary (rule 3): all regions of
// vi's fan as one group, or for a pinch the regions of each fan separately (fans that only meet
// at vi must not join; fans sharing a region form one group). fan: labelFans of vi (pinch only).
void collectMergeGroups(const CollapseState& s, const RegionState& r, uint32_t vi, const std::vector<uint32_t>& fan,
                        MergeGroups& out);

// Merges the regions of the collapse (vi -> vj) before it is applied; nothing when it keeps a
// boundary (rule 3). Relabelled faces get `pass`. planned: the collapse's merge groups when the
// caller has them for the current state (collectMergeGroups of vi), else null.
void updateRegions(RegionState& r, const CollapseState& s, HierarchyRecorder& rec, uint32_t vi, uint32_t vj,
                   bool keepsBoundary, uint32_t pass, const MergeGroups* planned = nullptr);

// Every region whose representative is a removed face moves to its smallest surviving face; the
// updates are recorded with the last collapse (so a replay up to any level sees surviving reps).
void fixDeadRepresentatives(RegionState& r, const CollapseState& s, HierarchyRecorder& rec, uint32_t pass);

}  // namespace lodbake::simplify_detail
