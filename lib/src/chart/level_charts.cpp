// Which chart each level triangle takes its UVs from (shared by parameterize, applyAtlas and
// textureDeviation so the solver guards exactly the triangles that are written).
#include "lodbake/chart/level_charts.h"

#include <algorithm>

#include "lodbake/core/errors.h"

namespace lodbake {

std::vector<uint32_t> levelTriangleCharts(const TriMesh& mesh, const std::vector<uint32_t>& faceChart,
                                          uint32_t chartCount, const Level& level) {
    const size_t nf = mesh.triangleCount();
    if (faceChart.size() != nf) throw InvalidInput("levelTriangleCharts: faceChart does not match the mesh");
    // Charts of each vertex (from index-non-degenerate faces, like the chart meshes), sorted.
    std::vector<std::vector<uint32_t>> vertexCharts(mesh.vertexCount());
    for (size_t f = 0; f < nf; ++f) {
        const Tri& t = mesh.triangles[f];
        if (degenerateIndices(t) || faceChart[f] >= chartCount) continue;
        for (uint32_t v : t) {
            auto& list = vertexCharts[v];
            auto it = std::lower_bound(list.begin(), list.end(), faceChart[f]);
            if (it == list.end() || *it != faceChart[f]) list.insert(it, faceChart[f]);
        }
    }
    auto has = [&](uint32_t v, uint32_t c) {
        return v < vertexCharts.size() && std::binary_search(vertexCharts[v].begin(), vertexCharts[v].end(), c);
    };
    std::vector<uint32_t> out(level.triangles.size(), 0);
    for (size_t t = 0; t < level.triangles.size(); ++t) {
        const Tri& v = level.triangles[t];
        uint32_t own = t < level.faces.size() && level.faces[t] < nf ? faceChart[level.faces[t]] : 0;
        out[t] = own;
        if (has(v[0], own) && has(v[1], own) && has(v[2], own)) continue;
        if (v[0] >= vertexCharts.size()) continue;
        for (uint32_t c : vertexCharts[v[0]])
            if (has(v[1], c) && has(v[2], c)) {
                out[t] = c;
                break;
            }
    }
    return out;
}

}  // namespace lodbake
