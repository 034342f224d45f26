// Snapshot of a level: its faces, corner wedges, regions and simplification pairs (thesis ch. 3.2;
// docs/simplify.md, "Simplification pairs"). Private to lib/src/simplify.
#pragma once

#include <string>

#include "collapse_rules.h"
#include "collapse_state.h"
#include "regions.h"

namespace lodbake::simplify_detail {

// Re-elects surviving representatives (fixDeadRepresentatives), then appends the current mesh as
// a level to rec.out with its simplification pairs (projections on `threads` threads, identical for
// any count). Updates rec.levelMax: maxDeviation never decreases from level to level.
void snapshotLevel(const CollapseState& s, RegionState& r, HierarchyRecorder& rec, const PlannedLevel& plan,
                   const std::string& stopReason, double seconds, int threads, uint32_t pass);

}  // namespace lodbake::simplify_detail
