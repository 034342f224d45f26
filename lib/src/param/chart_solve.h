// Chart solves (parameterize step 3): each chart's map (LSCM or Tutte start, Ceres with the
// beta = 1 retry, injectivity and level-fold checks) on threads, and the byte-keyed cache of solves
// across parameterize calls (ChartSolveCache).
#pragma once

#include <vector>

#include "lodbake/param/parameterize.h"
#include "param/chart_extraction.h"

namespace lodbake::param_detail {

// (3) Tutte, Ceres and checks per chart. Charts are independent: solved on up to options.threads
// threads, largest first except that the largest LSCM-only charts do not run side by side past
// kLscmVerticesTogether vertices (solve_schedule.h), results kept per chart and summed in chart order (identical for any
// thread count). A chart options.solveCache remembers takes the remembered result (looked up and
// stored outside the parallel loop). Progress runs to 0.9.
void solveCharts(std::vector<LocalChart>& charts, const ParameterizeOptions& options, ParameterizeResult& res);

}  // namespace lodbake::param_detail
