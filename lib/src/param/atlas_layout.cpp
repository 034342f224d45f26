// Atlas layout rounds of parameterize (atlas_layout.h): (5) shelf packing of the charts and
// islands (lodbake/atlas/atlas.h), (6) atlas UVs of the original face corners and islands, (7)
// level UVs exactly as applyAtlas writes them, then the fold fallback's islands and another round.
#include "param/atlas_layout.h"

#include <algorithm>
#include <cmath>

#include "lodbake/atlas/atlas.h"
#include "lodbake/chart/level_charts.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/math.h"
#include "param/fold_fallback.h"

namespace lodbake::param_detail {
namespace {

// The per-face, per-level and per-vertex chart tables the packing rounds read.
// \throw InvalidInput when a level's faces and triangles disagree or a face id is out of range.
AtlasState atlasState(const TriMesh& mesh, const Multires& multires, const ChartResult& cr, const std::vector<LocalChart>& charts,
                      const FaceGrid& grid, double radius) {
    const size_t nf = mesh.triangleCount();
    AtlasState st(grid, radius);
    st.faceChart.resize(nf);
    for (size_t f = 0; f < nf; ++f) st.faceChart[f] = uint32_t(std::max(cr.faceChart[f], 0));
    st.levelTriChart.resize(multires.levels.size());
    for (size_t li = 0; li < multires.levels.size(); ++li) {
        const Level& L = multires.levels[li];
        if (L.faces.size() != L.triangles.size()) throw InvalidInput("level faces and triangles differ in size");
        for (uint32_t f : L.faces)
            if (f >= nf) throw InvalidInput("level face id out of range");
        st.levelTriChart[li] = levelTriangleCharts(mesh, st.faceChart, cr.chartCount, L);
    }
    st.vertexCharts.resize(mesh.vertexCount());
    for (uint32_t c = 0; c < charts.size(); ++c)
        for (uint32_t v : charts[c].vertices) st.vertexCharts[v].push_back(c);
    // The charts' local indices do not change between rounds (only islands and the packing do):
    // looked up once here instead of once per round.
    auto localIn = [&](const LocalChart& ch, uint32_t v, uint32_t missing) {
        auto it = ch.local.find(v);
        return it != ch.local.end() ? it->second : missing;
    };
    st.faceCornerLocal.assign(nf, {});
    for (uint32_t f = 0; f < nf; ++f) {
        const int32_t c = cr.faceChart[f];
        if (c < 0 || charts[size_t(c)].uv.empty()) continue;
        for (size_t k = 0; k < 3; ++k) st.faceCornerLocal[f][k] = localIn(charts[size_t(c)], mesh.triangles[f][k], 0);
    }
    st.levelCornerLocal.resize(multires.levels.size());
    for (size_t li = 0; li < multires.levels.size(); ++li) {
        const Level& L = multires.levels[li];
        st.levelCornerLocal[li].resize(L.triangles.size());
        for (size_t t = 0; t < L.triangles.size(); ++t) {
            const uint32_t c = st.levelTriChart[li][t];
            for (size_t k = 0; k < 3; ++k)
                st.levelCornerLocal[li][t][k] = c < charts.size() ? localIn(charts[c], L.triangles[t][k], kNotInChart) : kNotInChart;
        }
    }
    return st;
}

// The largest atlas side parameterize lays charts out on: a textureSize page too small for the
// charts and level islands at any density (tens of thousands of islands, as a multi-million-
// triangle scan has) grows up to it rather than failing.
constexpr int kMaxAtlasSize = 16384;

// (5) Shelf-packs the charts and the islands made so far; sets the density and fill figures.
ShelfPackResult packCharts(const std::vector<LocalChart>& charts, const AtlasState& st, double uvArea,
                           const ParameterizeOptions& options, ParameterizeResult& res) {
    std::vector<const std::vector<Vec2>*> sets;
    double islandArea = 0;
    for (const LocalChart& c : charts) sets.push_back(&c.uv);
    for (const auto& m : st.islandModel) {
        sets.push_back(&m);
        islandArea += signedArea(m[0], m[1], m[2]);
    }
    ShelfPackOptions so;
    so.size = options.textureSize;
    so.gutter = options.gutter;
    so.maxSize = std::max(options.textureSize, kMaxAtlasSize);
    ShelfPackResult atlas = shelfPack(sets, uvArea + islandArea, so);
    const double d = atlas.texelsPerUnit;
    const int size = atlas.size;
    res.atlasSize = size;
    res.texelsPerUnit = d;
    res.atlasFill = (uvArea + islandArea) * d * d / (double(size) * size);
    return atlas;
}

// (6) Atlas UV of every original face corner and of every island corner.
void writeCornerUVs(const TriMesh& mesh, const std::vector<LocalChart>& charts, const AtlasState& st,
                    const ShelfPackResult& atlas, ParameterizeResult& res) {
    const size_t nf = mesh.triangleCount();
    res.cornerUV.assign(nf, {});
    for (uint32_t f = 0; f < nf; ++f) {
        int32_t c = res.charts.faceChart[f];
        if (c < 0 || charts[size_t(c)].uv.empty()) continue;
        for (size_t k = 0; k < 3; ++k) res.cornerUV[f][k] = atlas.atlasUV(size_t(c), charts[size_t(c)].uv[st.faceCornerLocal[f][k]]);
    }
    res.islands.resize(st.islandModel.size());
    for (size_t i = 0; i < st.islandModel.size(); ++i)
        for (size_t k = 0; k < 3; ++k) res.islands[i].uv[k] = atlas.atlasUV(charts.size() + i, st.islandModel[i][k]);
}

// The closest point of chart c's faces to vertex v (cached per chart and vertex).
const Projection& projectOntoChart(const TriMesh& mesh, const LocalChart& chart, uint32_t c, uint32_t v, AtlasState& st) {
    uint64_t key = (uint64_t(c) << 32) | v;
    auto pj = st.projections.find(key);
    if (pj == st.projections.end()) {
        Projection pr;
        size_t i = 0;
        if (closestFaceIn(mesh, st.grid, chart.faces, mesh.positions[v], st.radius, i, pr.bary)) pr.face = chart.faces[i];
        pj = st.projections.emplace(key, pr).first;
    }
    return pj->second;
}

// (7) Level UVs exactly as applyAtlas writes them: an island's UVs for an island's vertex triple,
// else each corner's UV in the triangle's chart, a corner outside the chart the UV of its closest
// point on the chart's surface (counted in st.projectedCount).
void writeLevelUVs(const TriMesh& mesh, const Multires& multires, const std::vector<LocalChart>& charts, const ShelfPackResult& atlas,
                   AtlasState& st, ParameterizeResult& res) {
    const uint32_t chartCount = res.charts.chartCount;
    res.levels.assign(multires.levels.size(), {});
    st.projectedCount.assign(multires.levels.size(), {});
    for (size_t li = 0; li < multires.levels.size(); ++li) {
        const Level& L = multires.levels[li];
        LevelUV& out = res.levels[li];
        out.chart = st.levelTriChart[li];
        out.uv.resize(L.triangles.size());
        st.projectedCount[li].assign(L.triangles.size(), 0);
        for (size_t t = 0; t < L.triangles.size(); ++t) {
            auto isl = st.islandOf.find(L.triangles[t]);
            if (isl != st.islandOf.end()) {
                out.chart[t] = chartCount + isl->second;
                out.uv[t] = res.islands[isl->second].uv;
                ++out.islands;
                continue;
            }
            const uint32_t c = out.chart[t];
            const LocalChart& ch = charts[c];
            for (size_t k = 0; k < 3; ++k) {
                const uint32_t v = L.triangles[t][k];
                const uint32_t local = st.levelCornerLocal[li][t][k];
                if (local != kNotInChart) {
                    out.uv[t][k] = atlas.atlasUV(c, ch.uv[local]);
                    continue;
                }
                ++st.projectedCount[li][t];
                ++out.projectedCorners;
                const Projection& pj = projectOntoChart(mesh, ch, c, v, st);
                const auto& cu = res.cornerUV[pj.face];
                const auto& bb = pj.bary;
                out.uv[t][k] = cu[0] * bb[0] + cu[1] * bb[1] + cu[2] * bb[2];
            }
        }
    }
}

}  // namespace

void alignChart(std::vector<Vec2>& uv) {
    if (uv.empty()) return;
    Vec2 mean{};
    for (Vec2 p : uv) mean = mean + p;
    mean = mean * (1.0 / double(uv.size()));
    double sxx = 0, sxy = 0, syy = 0;
    for (Vec2 p : uv) {
        Vec2 d = p - mean;
        sxx += d.x * d.x;
        sxy += d.x * d.y;
        syy += d.y * d.y;
    }
    double angle = 0.5 * std::atan2(2 * sxy, sxx - syy);
    double c = std::cos(-angle), s = std::sin(-angle);
    for (Vec2& p : uv) {
        Vec2 d = p - mean;
        p = {c * d.x - s * d.y, s * d.x + c * d.y};
    }
}

void layoutAtlas(const TriMesh& mesh, const Multires& multires, const std::vector<LocalChart>& charts, double chartUvArea,
                 const FaceGrid& grid, double radius, const ParameterizeOptions& options, ParameterizeResult& res) {
    constexpr int kMaxRounds = 8;
    AtlasState st = atlasState(mesh, multires, res.charts, charts, grid, radius);
    res.islands.clear();
    res.crossingIslandsSkipped = 0;
    const double uvArea = chartUvArea > 0 ? chartUvArea : 1;
    bool crossing = options.crossingIslands;
    for (int round = 0;; ++round) {
        const ShelfPackResult atlas = packCharts(charts, st, uvArea, options, res);
        writeCornerUVs(mesh, charts, st, atlas, res);
        writeLevelUVs(mesh, multires, charts, atlas, st, res);
        if (!options.levelIslands || res.charts.chartCount == 0 || round >= kMaxRounds) break;
        if (round == 0 && crossing) crossing = crossingIslandsFit(multires, st, options, res);
        if (addFoldIslands(mesh, multires, charts, crossing, atlas.texelsPerUnit, options.threads, st, res) == 0) break;
    }
}

}  // namespace lodbake::param_detail
