// The UV of each (welded vertex, chart) pair of a chart layout (chart_lookup.h).
#include "lodbake/chart/chart_lookup.h"

namespace lodbake {
namespace {

uint64_t key(uint32_t vertex, uint32_t chart) { return (uint64_t(vertex) << 32) | chart; }

}  // namespace

ChartVertexUV::ChartVertexUV(const TriMesh& mesh, const ChartLayout& layout)
    : mesh_(mesh), chartVertices_(layout.chartCount) {
    for (size_t f = 0; f < mesh.triangleCount(); ++f)
        for (size_t j = 0; j < 3; ++j) {
            uint32_t v = mesh.triangles[f][j], c = layout.faceChart[f];
            if (uv_.emplace(key(v, c), layout.cornerUV[f][j]).second) chartVertices_[c].push_back(v);
        }
}

bool ChartVertexUV::has(uint32_t vertex, uint32_t chart) const { return uv_.count(key(vertex, chart)) > 0; }

Vec2 ChartVertexUV::operator()(uint32_t vertex, uint32_t chart) const {
    auto it = uv_.find(key(vertex, chart));
    if (it != uv_.end()) return it->second;
    uint32_t best = chartVertices_[chart].front();
    double bd = 1e300;
    for (uint32_t v : chartVertices_[chart]) {
        double d = length2(mesh_.positions[v] - mesh_.positions[vertex]);
        if (d < bd) {
            bd = d;
            best = v;
        }
    }
    return uv_.at(key(best, chart));
}

}  // namespace lodbake
