// The UV of each (welded vertex, chart) pair of a chart layout, used wherever level corners get
// their UVs (pack, texture-refine): every coarse vertex is an original vertex, so it takes the
// UV it has in that chart (point-consistent mapping). A vertex that is not in the chart (a
// collapse moved it across a chart boundary) takes the UV of the chart's vertex nearest in 3D.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"

namespace lodbake {

class ChartVertexUV {
public:
    // \pre layout matches mesh (faceChart and cornerUV per original face); mesh outlives this.
    ChartVertexUV(const TriMesh& mesh, const ChartLayout& layout);
    bool has(uint32_t vertex, uint32_t chart) const;
    // \pre chart < layout.chartCount and the chart has at least one face.
    Vec2 operator()(uint32_t vertex, uint32_t chart) const;

private:
    const TriMesh& mesh_;
    std::unordered_map<uint64_t, Vec2> uv_;
    std::vector<std::vector<uint32_t>> chartVertices_;
};

}  // namespace lodbake
