// Charts of a level: which chart each level triangle takes its UVs from (shared by parameterize,
// applyAtlas, textureDeviation, texture-refine and pack, so the solver guards exactly the
// triangles that are written).
#pragma once

#include <cstdint>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/simplification_hierarchy.h"

namespace lodbake {

// The chart each triangle of `level` takes its UVs from: the chart of its face when the three
// corners are vertices of that chart; else the lowest chart having all three corners (a collapse
// moved the triangle off its face's chart, but its corners still share a chart); else the face's
// chart, whose surface then supplies projected UVs for the corners outside it.
// \pre faceChart has mesh.triangleCount() entries (ChartLayout::faceChart convention).
std::vector<uint32_t> levelTriangleCharts(const TriMesh& mesh, const std::vector<uint32_t>& faceChart,
                                          uint32_t chartCount, const Level& level);

}  // namespace lodbake
