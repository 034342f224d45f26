// Removal of small and stuck parts: whole connected components leave a level when simplification
// cannot reach its target otherwise, or when removing a part costs less than the collapses a pass
// accepts (docs/simplify.md, "Component pruning"; as meshoptimizer's component pruning). Private
// to lib/src/simplify.
#pragma once

#include <cstdint>
#include <vector>

#include "candidates.h"
#include "collapse_state.h"

namespace lodbake::simplify_detail {

// Reorders s.components.order by visual weight, lightest first: the surface area of each
// component (a convex part's mean silhouette over all view directions is a quarter of its area,
// so area ranks parts by how much of the picture they fill), ties by size, then by id. Called
// once after measureComponents; without it the order is by size.
void orderByVisualWeight(CollapseState& s);

// Per component: 1 when none of its live vertices has a valid or a deferred candidate, i.e. the
// part cannot shrink any further this pass (stuck on its locks, borders or rule 1).
std::vector<uint8_t> stuckComponents(const CollapseState& s, const CandidateState& c);

// Whether pruneComponents(s, .., limit, target, ..) would look at any component: the live face
// count is above `target` and the first unpruned component in s.components.order is below `limit`
// (the walk stops there otherwise). Lets a caller skip what only the pruning reads.
bool anyPrunable(const CollapseState& s, double limit, uint64_t target);

// Prunes components (closed ones only when closedOnly; with `stuck`, open ones only when stuck) whose size (half box diagonal, model units)
// is below `limit`, in s.components.order, while the live face count stays at or above `target`
// and above zero; the walk stops at the first component not below `limit`, so a part is never
// pruned before a lighter one that is still there. Each surviving vertex of a pruned component
// gets a collapse record with kept == removed and deviation = the component's size. Returns
// whether anything was pruned.
bool pruneComponents(CollapseState& s, HierarchyRecorder& rec, double limit, uint64_t target, bool closedOnly,
                     const std::vector<uint8_t>* stuck = nullptr);

// The size of the first component pruneComponents(s, .., inf, target, closedOnly) would prune
// (model units); infinity when none.
double nextPrunableSize(const CollapseState& s, uint64_t target, bool closedOnly);

}  // namespace lodbake::simplify_detail
