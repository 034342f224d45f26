// The measured deviation of each level from the original: two-sided Hausdorff / RMS distance
// (Metro-style sampling, lodbake/metrics/distance.h), after vertex placement where it applies.
#pragma once

#include <functional>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/lod/lod_chain.h"
#include "lod/level_view.h"

namespace lodbake::lod_detail {

// Fills res.reports (one per view: source, simplify's deviation, the measured distance and the
// vertex placement) and moves the vertices of `views` that placement kept. LOD0 measures none; a
// rigged asset's distance is the largest over the bind pose and the sampled poses. `time` (one
// per view) receives the placements' seconds; `progress` fractions up to 0.3.
void measureLevels(const Asset& asset, std::vector<LevelView>& views, const PackOptions& options, PackResult& res,
                   std::vector<PackLevelProfile>& time, const std::function<void(double)>& progress);

}  // namespace lodbake::lod_detail
