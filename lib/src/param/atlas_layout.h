// Atlas layout rounds (parameterize steps 5-7): charts turned to their principal axis, shelf-packed
// with the fold fallback's islands, corner and level UVs written; repeated while the fold fallback
// (fold_fallback.h) adds islands. AtlasState is what the rounds and the fallback share.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <vector>

#include "lodbake/core/face_grid.h"
#include "lodbake/param/parameterize.h"
#include "param/chart_extraction.h"

namespace lodbake::param_detail {

// A level corner projected onto a chart: the closest point of the chart's faces (face, bary).
struct Projection {
    uint32_t face = 0;
    std::array<double, 3> bary{1, 0, 0};
};

// A level corner that is not a vertex of its triangle's chart (levelCornerLocal).
constexpr uint32_t kNotInChart = UINT32_MAX;

// The chart tables and island state shared by the packing rounds (islands grow between rounds).
struct AtlasState {
    AtlasState(const FaceGrid& g, double r) : grid(g), radius(r) {}
    const FaceGrid& grid;                               // the original faces (islands, projections)
    double radius;                                      // closestFaceIn's first box
    std::vector<uint32_t> faceChart;                    // chart per original face (unassigned -> 0)
    std::vector<std::vector<uint32_t>> levelTriChart;   // per level: chart each triangle takes UVs from
    std::vector<std::vector<uint32_t>> vertexCharts;    // per vertex: the charts holding it
    std::vector<std::array<uint32_t, 3>> faceCornerLocal;  // per face corner: local index in its chart (0 if none)
    std::vector<std::vector<std::array<uint32_t, 3>>> levelCornerLocal;  // per level corner: in its chart, or kNotInChart
    std::map<Tri, uint32_t> islandOf;                   // level vertex triple -> island
    std::vector<std::vector<Vec2>> islandModel;         // island UVs, model units
    std::unordered_map<uint64_t, Projection> projections;  // (chart << 32 | vertex) -> closest chart point
    std::vector<std::vector<uint8_t>> projectedCount;   // per level triangle: corners not in its chart
};

// Rotates a chart so its principal UV axis is horizontal (tighter shelf packing).
void alignChart(std::vector<Vec2>& uv);

// (5)-(7) with the island fallback: pack, write corner and level UVs; a level triangle still
// folded in the packed atlas (or crossing a chart boundary) gets its own island, and as islands
// take atlas space the atlas is packed again and every level re-checked until none folds (at
// most kMaxRounds repacks).
void layoutAtlas(const TriMesh& mesh, const Multires& multires, const std::vector<LocalChart>& charts, double chartUvArea,
                 const FaceGrid& grid, double radius, const ParameterizeOptions& options, ParameterizeResult& res);

}  // namespace lodbake::param_detail
