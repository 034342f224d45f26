// Stretch metrics (parameterize step 4): Sander et al. 2001 L2 and Linf stretch and the spread of
// UV / 3D area ratios, per chart and for the whole atlas.
#pragma once

#include <vector>

#include "lodbake/param/parameterize.h"
#include "param/chart_extraction.h"

namespace lodbake::param_detail {

// (4) Stretch and area-ratio measures per chart and for the whole atlas (uniform density, so
// model-unit UVs compare). Returns the charts' total UV area (model units^2).
double measureCharts(const std::vector<LocalChart>& charts, ParameterizeResult& res);

}  // namespace lodbake::param_detail
