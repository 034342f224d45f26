// The charts of a coarse level whose page is baked by projection from its own surface.
//
// A level triangle takes its UVs from the chart layout (T0 or a hierarchy rank): from the chart
// holding its corners, or, when its corners lie in different charts or it would fold there, from
// an island of its own (parameterize's fallback). A projection bake reads every texel from the
// original surface near the level's own triangle, so a triangle's UVs need not come from the
// layout at all: any placement that neither folds nor overlaps the rest of its chart is valid.
// Islands are therefore unfolded onto a neighbouring chart across a shared edge (the triangle's
// 3D shape at the scale of that edge), and islands with no room there are grown into charts of
// their own the same way. Fewer, larger charts waste less of the page on gutters.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake::lod_detail {

struct LevelChartSet {
    std::vector<uint32_t> chart;             // per level triangle, dense chart id in [0, uvArea.size())
    std::vector<std::array<Vec2, 3>> uv;     // per level triangle, its corners' UVs (layout units)
    std::vector<double> uvArea;              // per chart, the UV area of its level triangles
    std::vector<uint32_t> source;            // per chart, the input chart id it grew from (>= firstIsland: an island)
    size_t absorbed = 0;                     // islands unfolded onto a layout chart
    size_t grouped = 0;                      // islands unfolded onto a chart grown from another island
};

struct AbsorbOptions {
    // A triangle unfolded across an edge takes that edge's UV scale; it is refused when the scale
    // differs from the layout's average (uvPerUnit) by more than this factor either way, which
    // would show as a visibly denser or coarser patch.
    double maxScaleRatio = 4;
};

// Level triangles `triangles` (welded vertex ids into `positions`) with their layout charts
// (`chart`, islands have ids >= firstIsland) and corner UVs: every island triangle is unfolded
// onto an adjacent chart where it neither folds nor overlaps that chart's triangles; the rest are
// seeds of new charts that grow over neighbouring islands. Layout charts keep their triangles and
// UVs. The result is the same for the same input (triangles are visited in index order).
LevelChartSet absorbIslands(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles,
                            const std::vector<uint32_t>& chart, const std::vector<std::array<Vec2, 3>>& uv,
                            uint32_t firstIsland, double uvPerUnit, const AbsorbOptions& options = {});

}  // namespace lodbake::lod_detail
