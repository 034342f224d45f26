// Removal of small and stuck parts: whole connected components leave a level when simplification
// cannot reach its target otherwise (docs/simplify.md, "Component pruning"; as meshoptimizer's
// component pruning). Private to lib/src/simplify.
#pragma once

#include <cstdint>

#include "collapse_state.h"

namespace lodbake::simplify_detail {

// Prunes components (closed ones only when closedOnly) whose size (half box diagonal, model units)
// is below `limit`, smallest first, while the live face count stays at or above `target` and above
// zero. Each surviving vertex of a pruned component gets a collapse record with kept == removed and
// deviation = the component's size. Returns whether anything was pruned.
bool pruneComponents(CollapseState& s, HierarchyRecorder& rec, double limit, uint64_t target, bool closedOnly);

}  // namespace lodbake::simplify_detail
