// measureLayout: E (the energy of parameterize) and the UV-area / 3D-area ratio spread of a chart
// layout over the geometry levels it serves, plus the UV injectivity of those levels.
#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>
#include <utility>

#include "lodbake/chart/chart_lookup.h"
#include "lodbake/chart/level_charts.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/parallel.h"
#include "lodbake/texture_hierarchy/refine.h"

namespace lodbake {

namespace {

// The measures over 0..v for v in [firstLevel, lastLevel] (index v; those below firstLevel stay
// empty). Every figure of the measure over 0..v is built from per-level parts in level order (the
// pairs of levels 1..v are a prefix of each chart's pairs, the ratios of levels 0..v a prefix of
// the ratios, the area sums running sums): the measure over 0..v takes the same operations on the
// same values as measuring 0..v alone.
std::vector<LayoutMeasure> measureLevels(const TriMesh& mesh, const Multires& mr, const ChartLayout& lay, uint32_t firstLevel,
                                         uint32_t lastLevel, const ChartEnergyOptions& eo, int threads) {
    const size_t nf = mesh.triangleCount();
    if (lay.faceChart.size() != nf || lay.cornerUV.size() != nf) throw InvalidInput("measureLayout: layout does not match the mesh");
    if (lastLevel > mr.levels.size()) throw InvalidInput("measureLayout: level out of range");
    for (uint32_t c : lay.faceChart)
        if (c >= lay.chartCount) throw InvalidInput("measureLayout: chart id out of range");

    // Model-unit scale of the layout: UV area = 3D area over the original faces.
    double uvArea = 0, area3 = 0;
    for (size_t f = 0; f < nf; ++f) {
        if (degenerateIndices(mesh.triangles[f])) continue;
        const auto& u = lay.cornerUV[f];
        const Tri& t = mesh.triangles[f];
        uvArea += triangleArea(u[0], u[1], u[2]);
        area3 += triangleArea(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    }
    const double scale = uvArea > 0 ? std::sqrt(area3 / uvArea) : 1;

    // Energy per chart: local chart meshes, math-orientation UVs (v up), the served levels' pairs.
    std::vector<ChartMesh> charts(lay.chartCount);
    std::vector<std::vector<Vec2>> uvs(lay.chartCount);
    std::vector<std::unordered_map<uint32_t, uint32_t>> local(lay.chartCount);
    std::vector<std::vector<uint32_t>> vertexCharts(mesh.vertexCount());
    for (uint32_t f = 0; f < nf; ++f) {
        const Tri& t = mesh.triangles[f];
        if (degenerateIndices(t)) continue;
        uint32_t c = lay.faceChart[f];
        Tri lt{};
        for (size_t k = 0; k < 3; ++k) {
            auto [it, inserted] = local[c].emplace(t[k], uint32_t(charts[c].positions.size()));
            if (inserted) {
                charts[c].positions.push_back(mesh.positions[t[k]]);
                Vec2 u = lay.cornerUV[f][k];
                uvs[c].push_back(Vec2{u.x, 1.0 - u.y} * scale);
                vertexCharts[t[k]].push_back(c);
            }
            lt[k] = it->second;
        }
        charts[c].triangles.push_back(lt);
    }
    std::vector<std::vector<ChartPair>> pairs(lay.chartCount);
    // pairEnd[v][c]: chart c's pairs of levels 1..v (a prefix of pairs[c]).
    std::vector<std::vector<size_t>> pairEnd(lastLevel + 1, std::vector<size_t>(lay.chartCount, 0));
    for (uint32_t l = 1; l <= lastLevel; ++l) {
        for (const SimplificationPair& p : mr.levels[l - 1].pairs) {
            if (p.vertex >= mesh.vertexCount()) throw InvalidInput("measureLayout: pair vertex out of range");
            for (uint32_t c : vertexCharts[p.vertex]) {
                ChartPair cp;
                cp.vertex = local[c].at(p.vertex);
                cp.deviation = p.deviation;
                bool ok = true;
                for (size_t k = 0; k < 3 && ok; ++k) {
                    cp.bary[k] = p.bary[k];
                    auto it = local[c].find(p.coarse[k]);
                    if (it == local[c].end()) {
                        if (p.bary[k] != 0) ok = false;
                        cp.coarse[k] = cp.vertex;
                        cp.bary[k] = 0;
                    } else {
                        cp.coarse[k] = it->second;
                    }
                }
                if (ok) pairs[c].push_back(cp);
            }
        }
        for (uint32_t c = 0; c < lay.chartCount; ++c) pairEnd[l][c] = pairs[c].size();
    }
    std::vector<LayoutMeasure> out(lastLevel + 1);
    ChartEnergyOptions unit = eo;
    unit.resolution = 1;
    // Coarsest first: a chart without pairs on level v + 1 keeps the energy of 0..v + 1.
    for (uint32_t v = lastLevel + 1; v-- > firstLevel;) {
        LayoutMeasure& m = out[v];
        m.lastLevel = v;
        m.charts = lay.chartCount;
        m.chartEnergies.assign(lay.chartCount, ChartEnergy{});
        parallelFor(lay.chartCount, threads, [&](size_t c) {
            if (charts[c].triangles.empty()) return;
            const size_t k = pairEnd[v][c];
            if (v < lastLevel && pairEnd[v + 1][c] == k) m.chartEnergies[c] = out[v + 1].chartEnergies[c];
            else if (k == pairs[c].size()) m.chartEnergies[c] = chartEnergy(charts[c], pairs[c], uvs[c], unit);
            else m.chartEnergies[c] = chartEnergy(charts[c], std::vector<ChartPair>(pairs[c].begin(), pairs[c].begin() + k), uvs[c], unit);
        });
        for (uint32_t c = 0; c < lay.chartCount; ++c) {  // summed in chart order, as for one thread
            if (charts[c].triangles.empty()) continue;
            const ChartEnergy& e = m.chartEnergies[c];
            m.energy.E += e.E;
            m.energy.pixel += e.pixel;
            m.energy.poly += e.poly;
            m.energy.edge += e.edge;
            m.energy.area += e.area;
            m.pairs += pairEnd[v][c];
        }
    }

    // Area ratios and injectivity of every served level, UVs as pack assigns them.
    ChartVertexUV lookup(mesh, lay);
    std::map<std::array<uint32_t, 3>, uint32_t> island;  // a level triangle with an island's triple takes its UVs
    for (uint32_t i = 0; i < lay.islands.size(); ++i) island.emplace(islandKey(lay.islands[i].vertices), i);
    std::vector<std::vector<uint32_t>> chartFaces(lay.chartCount);
    for (uint32_t f = 0; f < nf; ++f) chartFaces[lay.faceChart[f]].push_back(f);
    FaceSetSearch search(mesh);
    std::vector<double> ratios;
    double sumUV = 0, sum3 = 0;
    std::vector<size_t> ratioEnd(lastLevel + 1);   // ratios of levels 0..l
    std::vector<double> sumUVTo(lastLevel + 1), sum3To(lastLevel + 1);
    std::vector<UVInjectivity> levels;
    std::vector<size_t> crossings;
    for (uint32_t l = 0; l <= lastLevel; ++l) {
        std::vector<std::array<Vec2, 3>> tris;
        size_t crossing = 0;
        const std::vector<Tri>& T = l == 0 ? mesh.triangles : mr.levels[l - 1].triangles;
        std::vector<uint32_t> triChart;
        if (l > 0) triChart = levelTriangleCharts(mesh, lay.faceChart, lay.chartCount, mr.levels[l - 1]);
        for (size_t t = 0; t < T.size(); ++t) {
            if (degenerateIndices(T[t])) continue;
            uint32_t f = l == 0 ? uint32_t(t) : mr.levels[l - 1].faces.at(t);
            if (f >= nf) throw InvalidInput("measureLayout: level face out of range");
            std::array<Vec2, 3> u;
            auto isl = l > 0 && !island.empty() ? island.find(islandKey(T[t])) : island.end();
            if (l > 0 && isl == island.end()) {  // an island shows its own bake: it smears nothing
                uint32_t c = triChart[t];
                if (!lookup.has(T[t][0], c) || !lookup.has(T[t][1], c) || !lookup.has(T[t][2], c)) ++crossing;
            }
            for (size_t k = 0; k < 3; ++k) {
                if (l == 0) u[k] = lay.cornerUV[f][k];
                else if (isl != island.end()) u[k] = lay.islands[isl->second].uvOf(T[t][k]);
                else u[k] = lookup.has(T[t][k], triChart[t]) ? lookup(T[t][k], triChart[t])
                                                             : search.closestUV(lay.cornerUV, chartFaces[triChart[t]], mesh.positions[T[t][k]]);
            }
            tris.push_back(u);
            double a3 = triangleArea(mesh.positions[T[t][0]], mesh.positions[T[t][1]], mesh.positions[T[t][2]]);
            if (!(a3 > 0)) continue;
            double a2 = triangleArea(u[0], u[1], u[2]);
            ratios.push_back(a2 / a3);
            sumUV += a2;
            sum3 += a3;
        }
        levels.push_back(checkUVInjectivity(tris, 1e-7, threads));
        crossings.push_back(crossing);
        ratioEnd[l] = ratios.size();
        sumUVTo[l] = sumUV;
        sum3To[l] = sum3;
    }
    for (uint32_t v = firstLevel; v <= lastLevel; ++v) {
        LayoutMeasure& m = out[v];
        for (uint32_t l = 0; l <= v; ++l) {
            m.flips += levels[l].flips;
            m.overlaps += levels[l].overlaps;
        }
        m.levels.assign(levels.begin(), levels.begin() + v + 1);
        m.crossing.assign(crossings.begin(), crossings.begin() + v + 1);
        m.triangles = ratioEnd[v];
        double mean = sum3To[v] > 0 ? sumUVTo[v] / sum3To[v] : 0;
        if (mean > 0 && ratioEnd[v] > 0) {
            double acc = 0;
            for (size_t i = 0; i < ratioEnd[v]; ++i) {
                double x = ratios[i] / mean;
                acc += (x - 1) * (x - 1);
                ++m.areaRatioHistogram[size_t(std::clamp(int(x / 0.2), 0, 9))];
            }
            m.areaRatioStdDev = std::sqrt(acc / double(ratioEnd[v]));
        }
    }
    return out;
}

}  // namespace

LayoutMeasure measureLayout(const TriMesh& mesh, const Multires& mr, const ChartLayout& lay, uint32_t lastLevel,
                            const ChartEnergyOptions& eo, int threads) {
    return std::move(measureLevels(mesh, mr, lay, lastLevel, lastLevel, eo, threads).back());
}

std::vector<LayoutMeasure> measureLayoutLevels(const TriMesh& mesh, const Multires& mr, const ChartLayout& lay,
                                               uint32_t lastLevel, const ChartEnergyOptions& eo, int threads) {
    return measureLevels(mesh, mr, lay, 0, lastLevel, eo, threads);
}

}  // namespace lodbake
