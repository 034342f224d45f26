// Chart extraction (parameterize step 2): the charts of a ChartResult as local meshes, their
// simplification pairs and their level triangles (chart_extraction.h).
#include "param/chart_extraction.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "lodbake/chart/level_charts.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/math.h"

namespace lodbake::param_detail {
namespace {

void extractCharts(const TriMesh& mesh, const ChartResult& cr, std::vector<LocalChart>& charts) {
    charts.assign(cr.chartCount, {});
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f)
        if (cr.faceChart[f] >= 0 && !degenerateIndices(mesh.triangles[f])) charts[size_t(cr.faceChart[f])].faces.push_back(f);
    for (LocalChart& c : charts) {
        for (uint32_t f : c.faces) c.vertices.insert(c.vertices.end(), mesh.triangles[f].begin(), mesh.triangles[f].end());
        std::sort(c.vertices.begin(), c.vertices.end());
        c.vertices.erase(std::unique(c.vertices.begin(), c.vertices.end()), c.vertices.end());
        c.local.reserve(c.vertices.size());
        c.mesh.positions.reserve(c.vertices.size());
        c.mesh.triangles.reserve(c.faces.size());
        for (uint32_t i = 0; i < c.vertices.size(); ++i) {
            c.local.emplace(c.vertices[i], i);
            c.mesh.positions.push_back(mesh.positions[c.vertices[i]]);
        }
        for (uint32_t f : c.faces) {
            const Tri& t = mesh.triangles[f];
            c.mesh.triangles.push_back({c.local[t[0]], c.local[t[1]], c.local[t[2]]});
        }
    }
}

// Pairs of every level whose removed vertex and coarse vertices all lie in one chart.
void gatherPairs(const TriMesh& mesh, const Multires& mr, std::vector<LocalChart>& charts) {
    std::vector<std::vector<uint32_t>> vertexCharts(mesh.vertexCount());
    for (uint32_t c = 0; c < charts.size(); ++c)
        for (uint32_t v : charts[c].vertices) vertexCharts[v].push_back(c);
    for (const Level& L : mr.levels)
        for (const SimplificationPair& p : L.pairs) {
            if (p.vertex >= mesh.vertexCount()) throw InvalidInput("simplification pair vertex out of range");
            for (uint32_t c : vertexCharts[p.vertex]) {
                LocalChart& ch = charts[c];
                ChartPair cp;
                cp.vertex = ch.local.at(p.vertex);
                cp.deviation = p.deviation;
                bool ok = true;
                for (int k = 0; k < 3 && ok; ++k) {
                    cp.bary[k] = p.bary[k];
                    auto it = ch.local.find(p.coarse[k]);
                    if (it == ch.local.end()) {
                        if (p.bary[k] != 0) ok = false;
                        cp.coarse[k] = cp.vertex;
                        cp.bary[k] = 0;
                    } else {
                        cp.coarse[k] = it->second;
                    }
                }
                if (ok) ch.pairs.push_back(cp);
            }
        }
    // Without the slack of growing: a million-triangle asset's pairs are some 50 MB.
    for (LocalChart& c : charts) c.pairs.shrink_to_fit();
}

// Level triangles of every level, per chart of their face (deduplicated across levels), with
// corners that are not chart vertices projected onto the chart's surface (as applyAtlas does).
void gatherLevelTriangles(const TriMesh& mesh, const ChartResult& cr, const Multires& mr, const FaceGrid& grid, double radius,
                          std::vector<LocalChart>& charts) {
    std::vector<std::set<std::array<uint32_t, 3>>> seen(charts.size());
    std::vector<std::map<uint32_t, ChartPoint>> projected(charts.size());
    auto project = [&](LocalChart& ch, size_t c, uint32_t v) {
        auto it = projected[c].find(v);
        if (it != projected[c].end()) return it->second;
        ChartPoint cp;
        size_t i = 0;
        std::array<double, 3> b{};
        if (closestFaceIn(mesh, grid, ch.faces, mesh.positions[v], radius, i, b)) {
            cp.vertex = ch.mesh.triangles[i];
            cp.weight = b;
        }
        projected[c].emplace(v, cp);
        return cp;
    };
    std::vector<uint32_t> faceChart(cr.faceChart.size());
    for (size_t f = 0; f < faceChart.size(); ++f) faceChart[f] = uint32_t(std::max(cr.faceChart[f], 0));
    for (size_t li = 0; li < mr.levels.size(); ++li) {
        const Level& L = mr.levels[li];
        const std::vector<uint32_t> triChart = levelTriangleCharts(mesh, faceChart, cr.chartCount, L);
        for (size_t t = 0; t < L.triangles.size() && t < L.faces.size(); ++t) {
            const Tri& v = L.triangles[t];
            if (degenerateIndices(v) || L.faces[t] >= cr.faceChart.size()) continue;
            int32_t c = int32_t(triChart[t]);
            if (c < 0 || size_t(c) >= charts.size() || charts[size_t(c)].faces.empty()) continue;
            LocalChart& ch = charts[size_t(c)];
            if (!seen[size_t(c)].insert({v[0], v[1], v[2]}).second) continue;
            ChartLevelTriangle lt;
            for (size_t k = 0; k < 3; ++k) {
                auto it = ch.local.find(v[k]);
                if (it != ch.local.end()) lt.corner[k].vertex = {it->second, it->second, it->second};
                else lt.corner[k] = project(ch, size_t(c), v[k]);
            }
            lt.area2 = length(cross(mesh.positions[v[1]] - mesh.positions[v[0]], mesh.positions[v[2]] - mesh.positions[v[0]]));
            lt.level = uint32_t(li + 1);
            ch.mesh.levelTriangles.push_back(lt);
        }
    }
    for (LocalChart& c : charts) c.mesh.levelTriangles.shrink_to_fit();
}

}  // namespace

double surfaceArea(const TriMesh& mesh) {
    double area = 0;
    for (const Tri& t : mesh.triangles) area += triangleArea(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    return area;
}

double typicalFaceSize(const TriMesh& mesh) {
    return std::sqrt(surfaceArea(mesh) / double(std::max<size_t>(1, mesh.triangleCount())));
}

std::vector<LocalChart> localCharts(const TriMesh& mesh, const Multires& multires, const ChartResult& cr, const FaceGrid& grid,
                                    double radius) {
    std::vector<LocalChart> charts;
    extractCharts(mesh, cr, charts);
    gatherPairs(mesh, multires, charts);
    gatherLevelTriangles(mesh, cr, multires, grid, radius, charts);
    return charts;
}

}  // namespace lodbake::param_detail
