// pack: parameterized multiresolution asset -> glTF LOD chain.
//
// Pipeline of packLodChain:
//   1. layoutsOf: T0 (multires.charts) and, with a texture hierarchy, every rank layout;
//   2. measureLevels: two-sided Hausdorff / RMS distance of each level to the original
//      (Metro-style sampling, lodbake/metrics/distance.h);
//   3. screenCoverages: level k is good while its deviation e_k projects to <= p pixels on a
//      viewport H pixels tall; with the bounding sphere radius R that is coverage <= 2 R p / (e_k H)
//      (independent of the field of view: coverage = projected sphere height / viewport height);
//   4. per level: levelCoverage (its coverage range and the texel density it can show);
//      eligibleRanks (T0 and the ranks of the hierarchy valid for the level) and, with several,
//      chooseLayoutByBake (the one whose bake shows the least texture deviation, rank_choice.h);
//      levelUVs (the layout UV of every level corner; a level baked by projection then takes
//      its own charts, ownCharts: islands unfolded onto neighbouring charts); packLevelPage (the charts its triangles
//      use repacked at that density, gutters sized for the mips used down to its smallest
//      coverage); bakePage (the ORIGINAL triangles baked at the repacked UVs); buildLevelMesh
//      (one indexed primitive: position, normal, atlas UV);
//   5. with Lod0::Original, LOD0 is the input asset itself (readSourceScene): its page is packed
//      (LOD1's is held to its texels) but nothing is baked, and its report describes the original.
#include "lodbake/lod/lod_chain.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "lodbake/bake/bake.h"
#include "lodbake/bake/draw_split.h"
#include "lodbake/bake/material_plan.h"
#include "lod/level_islands.h"
#include "lod/level_material.h"
#include "lod/level_parts.h"
#include "lod/level_variants.h"
#include "lod/rank_choice.h"
#include "lod/source_texels.h"
#include "lod/tiled_levels.h"
#include "lod/vertex_placement.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/timing.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/chart/chart_lookup.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/parallel.h"
#include "lodbake/metrics/distance.h"
#include "lodbake/metrics/posed_distance.h"
#include "lodbake/atlas/atlas.h"
#include "lodbake/param/parameterize.h"
#include "lodbake/texture/codec.h"

namespace lodbake {
namespace {

using namespace lod_detail;

// One level's geometry in terms of original faces: triangles, corner wedges and face ids.
struct LevelView {
    std::vector<Tri> triangles, cornerWedges;
    std::vector<uint32_t> faces;
    std::string source;
    double maxDeviation = 0;
    size_t level = 0;            // multires level number (0 = the original)
    const Level* data = nullptr;  // multires.levels[level - 1]; null for the original
    std::vector<Vec3> positions;  // welded positions after vertex placement; empty = the original's
    const std::vector<Vec3>& positionsOr(const TriMesh& original) const { return positions.empty() ? original.positions : positions; }
};

// The original, then every level that has triangles. A level simplify could not make coarser
// repeats the one before it: it stays in the chain (the chain's level count and files do not
// depend on how far simplify got), with a warning that says so.
std::vector<LevelView> levelViews(const Asset& asset, const Multires& mr, std::vector<std::string>& warnings) {
    std::vector<LevelView> v;
    LevelView l0;
    l0.triangles = asset.mesh.triangles;
    l0.cornerWedges = asset.mesh.cornerWedges;
    l0.faces.resize(asset.mesh.triangleCount());
    for (size_t f = 0; f < l0.faces.size(); ++f) l0.faces[f] = uint32_t(f);
    l0.source = "original";
    v.push_back(std::move(l0));
    for (size_t k = 0; k < mr.levels.size(); ++k) {
        const Level& L = mr.levels[k];
        if (L.triangles.empty()) continue;
        if (L.triangles == v.back().triangles)
            warnings.push_back("LOD" + std::to_string(v.size()) + " (level " + std::to_string(k + 1) + ") repeats LOD" +
                               std::to_string(v.size() - 1) + ": the same " + std::to_string(L.triangles.size()) +
                               " triangles (simplify could not make it coarser)");
        LevelView lv;
        lv.triangles = L.triangles;
        lv.cornerWedges = L.cornerWedges;
        lv.faces = L.faces;
        lv.source = "level " + std::to_string(k + 1);
        lv.maxDeviation = L.maxDeviation;
        lv.level = k + 1;
        lv.data = &L;
        v.push_back(std::move(lv));
    }
    return v;
}

void checkInput(const Asset& asset, const Multires& mr) {
    const TriMesh& m = asset.mesh;
    const ChartLayout& ch = mr.charts;
    if (m.triangleCount() == 0) throw Impossible(asset.sourcePath + ": no triangles");
    if (ch.empty()) throw Impossible(asset.sourcePath + ": no chart layout (LODBAKE_multires charts); run parameterize first");
    if (ch.faceChart.size() != m.triangleCount() || ch.cornerUV.size() != m.triangleCount())
        throw InvalidInput(asset.sourcePath + ": chart layout does not match the original mesh");
    for (const Level& L : mr.levels) {
        if (L.faces.size() != L.triangles.size() || L.cornerWedges.size() != L.triangles.size())
            throw InvalidInput(asset.sourcePath + ": inconsistent multires level");
        for (uint32_t f : L.faces)
            if (f >= m.triangleCount()) throw InvalidInput(asset.sourcePath + ": level face out of range");
        for (const Tri& t : L.triangles)
            for (uint32_t x : t)
                if (x >= m.vertexCount()) throw InvalidInput(asset.sourcePath + ": level vertex out of range");
        for (const Tri& t : L.cornerWedges)
            for (uint32_t x : t)
                if (x >= m.wedges.size()) throw InvalidInput(asset.sourcePath + ": level wedge out of range");
    }
}

// A chart layout (T0 or a rank layout of the texture hierarchy) with what packing needs of it.
struct LayoutData {
    const ChartLayout* ch = nullptr;
    uint32_t rank = 0;
    std::vector<std::vector<uint32_t>> chartFaces;
    std::vector<double> chartUvArea;  // charts, then islands (chart id chartCount + i)
    double uvPerUnit = 0;  // layout UV units per model unit (area-averaged)
    std::unique_ptr<ChartVertexUV> lookup;
    // Level-triangle islands (parameterize's fallback): sorted vertex triple -> island.
    std::map<std::array<uint32_t, 3>, uint32_t> island;
    // The original faces each island's bake samples (the charts of its corners): found on the
    // first page bake that places an island (islandFacesOf), as the original triangles' page
    // places none and the projected levels' pages take their own.
    std::vector<std::vector<uint32_t>> islandFaces;
    bool islandFacesFound = false;
    uint32_t inPlaceCharts = 0;  // charts [0, n) are the original's texture islands (AtlasChart::inPlace)
};

void addIslands(const ChartLayout& ch, LayoutData& d) {
    for (uint32_t i = 0; i < ch.islands.size(); ++i) {
        const LayoutIsland& isl = ch.islands[i];
        d.island.emplace(islandKey(isl.vertices), i);
        d.chartUvArea.push_back(triangleArea(isl.uv[0], isl.uv[1], isl.uv[2]));
    }
}

const std::vector<std::vector<uint32_t>>& islandFacesOf(const TriMesh& mesh, LayoutData& d) {
    if (!d.islandFacesFound) {
        std::vector<BakeIsland> bake = layoutBakeIslands(mesh, *d.ch);
        d.islandFaces.reserve(bake.size());
        for (BakeIsland& b : bake) d.islandFaces.push_back(std::move(b.faces));
        d.islandFacesFound = true;
    }
    return d.islandFaces;
}

LayoutData layoutData(const Asset& asset, const ChartLayout& ch, uint32_t rank) {
    const TriMesh& mesh = asset.mesh;
    if (ch.faceChart.size() != mesh.triangleCount() || ch.cornerUV.size() != mesh.triangleCount())
        throw InvalidInput(asset.sourcePath + ": chart layout does not match the original mesh");
    for (uint32_t c : ch.faceChart)
        if (c >= ch.chartCount) throw InvalidInput(asset.sourcePath + ": chart id out of range");
    LayoutData d;
    d.ch = &ch;
    d.rank = rank;
    d.chartFaces.resize(ch.chartCount);
    d.chartUvArea.assign(ch.chartCount, 0);
    double uvTotal = 0, areaTotal = 0;
    for (size_t f = 0; f < mesh.triangleCount(); ++f) {
        uint32_t c = ch.faceChart[f];
        d.chartFaces[c].push_back(uint32_t(f));
        double a = triangleArea(ch.cornerUV[f][0], ch.cornerUV[f][1], ch.cornerUV[f][2]);
        d.chartUvArea[c] += a;
        uvTotal += a;
        const Tri& t = mesh.triangles[f];
        areaTotal += triangleArea(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    }
    if (!(uvTotal > 0) || !(areaTotal > 0)) throw Impossible(asset.sourcePath + ": the chart layout has no area");
    d.uvPerUnit = std::sqrt(uvTotal / areaTotal);
    d.lookup = std::make_unique<ChartVertexUV>(mesh, ch);
    addIslands(ch, d);
    return d;
}

// The chart and layout UVs of every triangle of a level.
struct LevelUVs {
    std::vector<uint32_t> chart;
    std::vector<std::array<Vec2, 3>> uv;
    // Non-empty: the charts are the level's own (ownCharts), this is each one's level-triangle UV
    // area and ownChartSource the layout chart each grew from (>= the layout's chartCount: from an
    // island). Empty: the ids are the layout's charts and islands.
    std::vector<double> ownChartArea;
    std::vector<uint32_t> ownChartSource;
    size_t absorbedIslands = 0;  // own charts: islands unfolded onto a chart
};

// A level baked by projection: islands unfolded onto neighbouring charts (level_islands.h).
LevelUVs ownCharts(const TriMesh& mesh, const LayoutData& L, const LevelView& lv, LevelUVs luv) {
    LevelChartSet set = absorbIslands(lv.positionsOr(mesh), lv.triangles, luv.chart, luv.uv, L.ch->chartCount, L.uvPerUnit);
    LevelUVs out;
    out.chart = std::move(set.chart);
    out.uv = std::move(set.uv);
    out.ownChartArea = std::move(set.uvArea);
    out.ownChartSource = std::move(set.source);
    out.absorbedIslands = set.absorbed + set.grouped;
    return out;
}

// Every layout (T0 and the hierarchy's ranks): the chart levelTriangleCharts picks (the face's, or
// one holding all three corners), a corner outside it the UV of the closest point of the chart's
// surface: the level UVs parameterize writes and guards against folds for that layout. A level
// triangle with an island's vertex triple takes the island (parameterize's fallback for a level
// triangle that would fold in its chart).
LevelUVs levelUVs(const TriMesh& mesh, const LayoutData& L, const LevelView& lv, const Level* level) {
    const ChartLayout& ch = *L.ch;
    LevelUVs out;
    const size_t n = lv.triangles.size();
    out.chart.resize(n);
    out.uv.resize(n);
    if (!level) {  // the original triangles
        for (size_t t = 0; t < n; ++t) {
            out.chart[t] = ch.faceChart[lv.faces[t]];
            out.uv[t] = ch.cornerUV[lv.faces[t]];
        }
        return out;
    }
    out.chart = levelTriangleCharts(mesh, ch.faceChart, ch.chartCount, *level);
    std::map<std::pair<uint32_t, uint32_t>, Vec2> projected;
    for (size_t t = 0; t < n; ++t) {
        if (!L.island.empty()) {
            auto isl = L.island.find(islandKey(lv.triangles[t]));
            if (isl != L.island.end()) {
                const LayoutIsland& island = ch.islands[isl->second];
                out.chart[t] = ch.chartCount + isl->second;
                for (size_t j = 0; j < 3; ++j) out.uv[t][j] = island.uvOf(lv.triangles[t][j]);
                continue;
            }
        }
        uint32_t c = out.chart[t];
        for (size_t j = 0; j < 3; ++j) {
            uint32_t v = lv.triangles[t][j];
            if (L.lookup->has(v, c)) {
                out.uv[t][j] = (*L.lookup)(v, c);
                continue;
            }
            auto it = projected.find({c, v});
            if (it == projected.end()) {
                Vec2 uv = closestSurfaceUV(mesh, ch.cornerUV, L.chartFaces[c], mesh.positions[v]);
                it = projected.emplace(std::make_pair(c, v), uv).first;
            }
            out.uv[t][j] = it->second;
        }
    }
    return out;
}

TriMesh asTriMesh(const TriMesh& original, const LevelView& lv) {
    TriMesh m;
    m.positions = lv.positionsOr(original);
    m.triangles = lv.triangles;
    return m;
}

// The same surface: the same triangles of the same original faces through the same wedges at the
// same positions (a level simplify could not make coarser, unmoved by vertex placement).
bool sameSurface(const LevelView& a, const LevelView& b) {
    auto same = [](Vec3 p, Vec3 q) { return p.x == q.x && p.y == q.y && p.z == q.z; };
    return a.triangles == b.triangles && a.cornerWedges == b.cornerWedges && a.faces == b.faces &&
           std::equal(a.positions.begin(), a.positions.end(), b.positions.begin(), b.positions.end(), same);
}

// The same level mesh: every attribute and index.
bool sameLevelMesh(const LodLevelData& a, const LodLevelData& b) {
    return a.positions == b.positions && a.normals == b.normals && a.uvs == b.uvs && a.tangents == b.tangents && a.joints == b.joints &&
           a.weights == b.weights && a.targetPositions == b.targetPositions && a.targetNormals == b.targetNormals &&
           a.targetTangents == b.targetTangents && a.indices == b.indices;
}

struct LevelAtlas {
    AtlasResult atlas;
    std::vector<int> chartSlot;  // original chart id -> index in atlas.charts, -1 if unused
    size_t charts = 0;
};

// The layout chart (or island) whose original faces chart c of a level's UVs covers; >= the
// layout's chartCount + islands for a level's own chart grown from islands (no original faces).
uint32_t layoutChartOf(const LevelUVs& luv, uint32_t c) { return luv.ownChartArea.empty() ? c : luv.ownChartSource[c]; }

// The UV area chart c of a level's UVs takes: its footprint's, at least.
double levelChartArea(const LayoutData& L, const LevelUVs& luv, uint32_t c) {
    const uint32_t source = layoutChartOf(luv, c);
    const double layout = source < L.ch->chartCount || luv.ownChartArea.empty() ? L.chartUvArea[source] : 0;
    return luv.ownChartArea.empty() ? layout : std::max(layout, luv.ownChartArea[c]);
}

LevelAtlas packLevelAtlas(const LayoutData& L, const LevelUVs& luv, bool original, const AtlasOptions& ao) {
    const ChartLayout& ch = *L.ch;
    LevelAtlas la;
    const bool own = !luv.ownChartArea.empty();
    la.chartSlot.assign(own ? luv.ownChartArea.size() : L.chartUvArea.size(), -1);
    std::vector<AtlasChart> charts;
    for (size_t t = 0; t < luv.chart.size(); ++t) {
        uint32_t c = luv.chart[t];
        if (la.chartSlot[c] < 0) {
            la.chartSlot[c] = int(charts.size());
            AtlasChart a;
            a.uvArea = levelChartArea(L, luv, c);
            a.inPlace = !own && c < L.inPlaceCharts;
            // A layout chart's footprint includes its original faces: the layout bake reads them,
            // and around a projected level's triangles they keep the chart's own texels between it
            // and its neighbours, which mips far below the page's gutter blend. A chart grown
            // from islands is just its level triangles, added below.
            const uint32_t source = layoutChartOf(luv, c);
            if (!own && c >= ch.chartCount) {  // an island: its one triangle
                const LayoutIsland& isl = ch.islands[c - ch.chartCount];
                a.points.assign(isl.uv.begin(), isl.uv.end());
                a.triangles.push_back(isl.uv);
            } else if (source < ch.chartCount) {
                for (uint32_t f : L.chartFaces[source]) {
                    for (const Vec2& p : ch.cornerUV[f]) a.points.push_back(p);
                    a.triangles.push_back(ch.cornerUV[f]);
                }
            }
            charts.push_back(std::move(a));
        }
        if (!original) {
            AtlasChart& a = charts[size_t(la.chartSlot[c])];
            std::array<Vec2, 3> tri;
            for (size_t j = 0; j < 3; ++j) tri[j] = luv.uv[t][j];
            a.points.insert(a.points.end(), tri.begin(), tri.end());
            a.triangles.push_back(tri);
        }
    }
    la.charts = charts.size();
    la.atlas = packAtlas(charts, ao);
    return la;
}

// A width x height page's bake: UVs scaled by the longer side, only the page baked, pixels left
// for the chain to encode.
BakeOptions pageBakeOptions(int width, int height, const BakeChannels& channels, int threads) {
    BakeOptions bo;
    bo.size = std::max(width, height);
    bo.width = width;
    bo.height = height;
    bo.encodePng = false;
    bo.threads = threads;
    bo.channels = channels;
    return bo;
}

// Charts copied texel for texel (source texels) extend over their gutter ring up to this many
// texels: the first mips that average across a border read the original's neighbours; beyond, the
// pull-push fill (a wider margin costs a closest-point test per texel of every triangle's box).
constexpr int kMaxChartExtension = 8;

// Bakes the original triangles at the page UVs: every channel of `channels`, the normal map in
// the frames of `target` (the level's own mesh on this page; null without a normal map).
// `sourceTexels`: the page copies the original's texels (its gutters continue each chart's copy).
BakeResult bakePage(const BakeSources& sources, LayoutData& L, const LevelAtlas& la, const BakeChannels& channels,
                    const BakeTarget* target, int threads, bool sourceTexels) {
    const Asset& asset = sources.asset();
    const ChartLayout& ch = *L.ch;
    const AtlasResult& a = la.atlas;
    int size = std::max(a.width, a.height);
    std::vector<std::array<Vec2, 3>> uv(asset.mesh.triangleCount());
    for (size_t f = 0; f < uv.size(); ++f) {
        int slot = la.chartSlot[ch.faceChart[f]];
        for (size_t j = 0; j < 3; ++j) {
            if (slot < 0) { uv[f][j] = {-10, -10}; continue; }  // chart unused at this level: off the page
            Vec2 p = a.charts[size_t(slot)].apply(ch.cornerUV[f][j]);
            uv[f][j] = {p.x / size, p.y / size};
        }
    }
    std::vector<BakeIsland> islands;
    for (size_t i = 0; i < ch.islands.size(); ++i) {
        int slot = la.chartSlot[ch.chartCount + i];
        if (slot < 0) continue;
        const std::vector<std::vector<uint32_t>>& islandFaces = islandFacesOf(asset.mesh, L);
        BakeIsland b;
        for (size_t k = 0; k < 3; ++k) {
            b.position[k] = asset.mesh.positions[ch.islands[i].vertices[k]];
            Vec2 p = a.charts[size_t(slot)].apply(ch.islands[i].uv[k]);
            b.uv[k] = {p.x / size, p.y / size};
        }
        b.faces = islandFaces[i];
        islands.push_back(std::move(b));
    }
    // UVs are scaled by the longer side; only the width x height page is baked (the chain
    // encodes it itself).
    BakeOptions bo = pageBakeOptions(a.width, a.height, channels, threads);
    if (sourceTexels) {
        bo.extendCharts = true;
        bo.dilation = std::clamp((a.gutter + 1) / 2, 1, kMaxChartExtension);
    }
    return bakeMaterial(sources, uv, bo, islands, target);
}

// The projection bake of a coarse level: every level triangle is an island of the page (its own
// 3D triangle at its page UVs) whose texels show the original surface at the closest point, found
// among the original faces whose boxes lie within `reach` of the triangle's box (the level's
// measured deviation bounds how far that point can be). `front` = the level triangles before
// back-face copies (those share their UVs).
BakeResult bakeProjected(const BakeSources& sources, const FaceGrid& grid, const LodLevelData& L, size_t front, int width,
                         int height, double reach, double diagonal, const BakeChannels& channels, const BakeTarget* target,
                         int threads) {
    const Asset& asset = sources.asset();
    const int size = std::max(width, height);
    std::vector<BakeIsland> islands(front);
    parallelFor(front, threads, [&](size_t t) {
        BakeIsland& b = islands[t];
        Vec3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t v = L.indices[3 * t + k];
            b.position[k] = {L.positions[3 * v], L.positions[3 * v + 1], L.positions[3 * v + 2]};
            b.uv[k] = {double(L.uvs[2 * v]) * width / size, double(L.uvs[2 * v + 1]) * height / size};
            for (int a = 0; a < 3; ++a) {
                lo[a] = std::min(lo[a], b.position[k][a] - reach);
                hi[a] = std::max(hi[a], b.position[k][a] + reach);
            }
        }
        // A sampled deviation can fall short of the true one: widen the search until it finds faces.
        for (double grow = reach; ; grow *= 4) {
            b.faces = grid.facesIn(lo - Vec3{grow - reach, grow - reach, grow - reach}, hi + Vec3{grow - reach, grow - reach, grow - reach});
            if (!b.faces.empty() || grow > 4 * diagonal) break;
        }
    });
    const std::vector<std::array<Vec2, 3>> offPage(asset.mesh.triangleCount(), {Vec2{-10, -10}, Vec2{-10, -10}, Vec2{-10, -10}});
    return bakeMaterial(sources, offPage, pageBakeOptions(width, height, channels, threads), islands, target);
}

// Twice the signed UV area in the glTF convention (v down): > 0 for a front-facing triangle.
template <class P>
double uvArea2(const P& a, const P& b, const P& c) {
    return double(b.x - a.x) * double(a.y - c.y) - double(a.y - b.y) * double(c.x - a.x);
}

// A sliver whose page UVs face the right way in double precision may turn flat or flipped once
// they are rounded to float. The level mesh is indexed (a vertex is shared by the triangles
// around it), so the sliver gets its own copy of the corner opposite its longest edge, moved one
// float ulp at a time along the gradient of its area (at most 64 ulps, far below a texel) until
// the rounded triangle faces the right way. parameterize has its own repair for per-face-corner
// UVs that are rounded later (nudgeRoundedSliverCorners); this one works on the float buffers.
// Appends a copy of vertex v's joints, weights and morph deltas (a vertex being duplicated);
// `flipNormal` negates the normal deltas of a back-face copy.
void copyInfluences(LodLevelData& out, uint32_t v, bool flipNormal = false) {
    for (auto* targets : {&out.targetPositions, &out.targetNormals, &out.targetTangents})
        for (std::vector<float>& d : *targets) {
            if (d.empty()) continue;
            const double sign = flipNormal && targets == &out.targetNormals ? -1 : 1;
            for (size_t k = 0; k < 3; ++k) d.push_back(float(sign * d[3 * v + k]));
        }
    if (out.joints.empty()) return;
    for (size_t d = 0; d < 4; ++d) out.joints.push_back(out.joints[4 * v + d]);
    for (size_t d = 0; d < 4; ++d) out.weights.push_back(out.weights[4 * v + d]);
}

void splitRoundedSliverCorners(const std::vector<std::array<Vec2, 3>>& placed, LodLevelData& out) {
    struct F2 { float x, y; };
    for (size_t t = 0; t < placed.size(); ++t) {
        const auto& e = placed[t];
        if (!(uvArea2(e[0], e[1], e[2]) > 0)) continue;  // folded for real: not a rounding artefact
        uint32_t* idx = &out.indices[3 * t];
        auto uvOf = [&](uint32_t v) { return F2{out.uvs[2 * v], out.uvs[2 * v + 1]}; };
        if (uvArea2(uvOf(idx[0]), uvOf(idx[1]), uvOf(idx[2])) > 0) continue;
        const size_t k = cornerOppositeLongestEdge(e);
        // The area is invariant under cyclic turns: with c the moved corner, a and b the others,
        // dA/dc = (-(a.y - b.y), -(b.x - a.x)).
        F2 a = uvOf(idx[(k + 1) % 3]), b = uvOf(idx[(k + 2) % 3]), c = uvOf(idx[k]);
        const float gx = -(a.y - b.y), gy = -(b.x - a.x);
        for (int step = 0; step < 64 && !(uvArea2(a, b, c) > 0); ++step) {
            if (gx != 0) c.x = std::nextafter(c.x, gx > 0 ? 2.f : -2.f);
            if (gy != 0) c.y = std::nextafter(c.y, gy > 0 ? 2.f : -2.f);
        }
        uint32_t v = idx[k], copy = uint32_t(out.uvs.size() / 2);
        for (int d = 0; d < 3; ++d) out.positions.push_back(out.positions[3 * v + uint32_t(d)]);
        for (int d = 0; d < 3; ++d) out.normals.push_back(out.normals[3 * v + uint32_t(d)]);
        copyInfluences(out, v);
        out.uvs.insert(out.uvs.end(), {c.x, c.y});
        idx[k] = copy;
    }
}

// Appends a reversed copy (negated normals) of every triangle whose original material is
// double-sided: a chain whose one material is single-sided still shows those parts from behind.
// Returns, per back copy, the level triangle it copies.
std::vector<size_t> addBackFaces(const Asset& asset, const LevelView& lv, LodLevelData& out) {
    std::vector<size_t> source;
    const TriMesh& m = asset.mesh;
    std::unordered_map<uint32_t, uint32_t> back;  // vertex -> its back-facing copy
    auto copyOf = [&](uint32_t v) {
        auto [it, inserted] = back.emplace(v, uint32_t(out.positions.size() / 3));
        if (inserted) {
            for (size_t d = 0; d < 3; ++d) out.positions.push_back(out.positions[3 * v + d]);
            for (size_t d = 0; d < 3; ++d) out.normals.push_back(-out.normals[3 * v + d]);
            for (size_t d = 0; d < 2; ++d) out.uvs.push_back(out.uvs[2 * v + d]);
            copyInfluences(out, v, true);
        }
        return it->second;
    };
    const size_t triangles = out.indices.size() / 3;
    for (size_t t = 0; t < triangles; ++t) {
        const int32_t mi = m.triangleMaterial.empty() ? -1 : m.triangleMaterial[lv.faces[t]];
        if (mi < 0 || size_t(mi) >= asset.materials.size() || !asset.materials[size_t(mi)].doubleSided) continue;
        const uint32_t a = copyOf(out.indices[3 * t]), b = copyOf(out.indices[3 * t + 1]), c = copyOf(out.indices[3 * t + 2]);
        out.indices.insert(out.indices.end(), {a, c, b});
        source.push_back(t);
    }
    return source;
}

void buildLevelMesh(const Asset& asset, const LevelView& lv, const LevelUVs& luv, const LevelAtlas& la, LodLevelData& out) {
    std::vector<std::array<Vec2, 3>> placed(lv.triangles.size());
    const TriMesh& m = asset.mesh;
    const std::vector<Vec3>& positions = lv.positionsOr(m);
    const AtlasResult& a = la.atlas;
    // Normals: the wedges' (unit) when the asset has them, else area-weighted over this level.
    std::vector<Vec3> vertexNormal;
    bool wedgeNormals = !m.wedges.normal.empty();
    if (!wedgeNormals) {
        vertexNormal.assign(m.vertexCount(), Vec3{});
        for (const Tri& t : lv.triangles) {
            Vec3 n = cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
            for (uint32_t v : t) vertexNormal[v] += n;
        }
    }
    // Welded vertices whose wedges move differently (other influences, other morph deltas) stay
    // apart: the key holds the id of the wedge's influence set and deltas (0 when static).
    const bool skinned = !asset.rig.empty() && m.wedges.joints.size() == m.wedges.size();
    const std::vector<MorphDeltas>& targets = m.wedges.targets;
    const bool morphed = !asset.morph.empty() && targets.size() == asset.morph.size();
    if (morphed) {
        out.targetPositions.assign(targets.size(), {});
        out.targetNormals.assign(targets.size(), {});
    }
    std::map<std::vector<double>, uint32_t> motionIds;
    std::vector<double> motion;
    auto motionOf = [&](uint32_t w) -> uint32_t {
        if (!skinned && !morphed) return 0;
        motion.clear();
        if (skinned) {
            const Vec4& q = m.wedges.weights[w];
            for (uint16_t j : m.wedges.joints[w]) motion.push_back(j);
            motion.insert(motion.end(), {q.x, q.y, q.z, q.w});
        }
        if (morphed)
            for (const MorphDeltas& D : targets) {
                for (const std::vector<Vec3>* d : {&D.position, &D.normal, &D.tangent})
                    if (!d->empty()) motion.insert(motion.end(), {(*d)[w].x, (*d)[w].y, (*d)[w].z});
            }
        return motionIds.emplace(motion, uint32_t(motionIds.size())).first->second;
    };
    auto pushDeltas = [&](const std::vector<Vec3>& d, std::vector<float>& to, uint32_t w) {
        if (!d.empty()) to.insert(to.end(), {float(d[w].x), float(d[w].y), float(d[w].z)});
    };
    // vertex, chart, normal, chart UV (a level's own charts may give a vertex two UVs in one
    // chart), influences
    using Key = std::tuple<uint32_t, uint32_t, float, float, float, double, double, uint32_t>;
    std::map<Key, uint32_t> index;
    for (size_t t = 0; t < lv.triangles.size(); ++t) {
        uint32_t c = luv.chart[t];
        const ChartPlacement& P = a.charts[size_t(la.chartSlot[c])];
        for (size_t j = 0; j < 3; ++j) {
            uint32_t v = lv.triangles[t][j];
            Vec3 n = wedgeNormals ? m.wedges.normal[lv.cornerWedges[t][j]] : vertexNormal[v];
            n = normalize(n);
            if (!(length(n) > 0.5)) {
                Vec3 fn = normalize(cross(positions[lv.triangles[t][1]] - positions[lv.triangles[t][0]],
                                          positions[lv.triangles[t][2]] - positions[lv.triangles[t][0]]));
                n = length(fn) > 0.5 ? fn : Vec3{0, 0, 1};
            }
            const uint32_t w = lv.cornerWedges[t][j];
            Key key{v, c, float(n.x), float(n.y), float(n.z), luv.uv[t][j].x, luv.uv[t][j].y, motionOf(w)};
            auto [it, inserted] = index.emplace(key, uint32_t(out.positions.size() / 3));
            if (inserted) {
                const Vec3& p = positions[v];
                out.positions.insert(out.positions.end(), {float(p.x), float(p.y), float(p.z)});
                out.normals.insert(out.normals.end(), {float(n.x), float(n.y), float(n.z)});
                Vec2 q = P.apply(luv.uv[t][j]);
                out.uvs.insert(out.uvs.end(), {float(q.x / a.width), float(q.y / a.height)});
                if (skinned) {
                    const Vec4& wt = m.wedges.weights[w];
                    for (uint16_t jo : m.wedges.joints[w]) out.joints.push_back(jo);
                    out.weights.insert(out.weights.end(), {float(wt.x), float(wt.y), float(wt.z), float(wt.w)});
                }
                if (morphed) {
                    // Normal deltas only over wedge normals (a level of area-weighted normals has
                    // none); no tangent deltas: the level's tangents are recomputed from its atlas.
                    for (size_t t = 0; t < targets.size(); ++t) {
                        pushDeltas(targets[t].position, out.targetPositions[t], w);
                        if (wedgeNormals) pushDeltas(targets[t].normal, out.targetNormals[t], w);
                    }
                }
            }
            out.indices.push_back(it->second);
            Vec2 q = P.apply(luv.uv[t][j]);
            placed[t][j] = {q.x / a.width, q.y / a.height};
        }
    }
    splitRoundedSliverCorners(placed, out);
}

// A tiled level's page (tiled_levels.h): one chart, the tile, its UVs kept as they are.
LevelAtlas tiledPage(const TilingEligibility& tiling, PackLevelReport& r) {
    LevelAtlas la;
    la.atlas.width = r.width = tiling.width;
    la.atlas.height = r.height = tiling.height;
    la.atlas.charts = {ChartPlacement{{double(tiling.width), 0, 0, 0, double(tiling.height), 0}}};
    la.chartSlot = {0};
    la.charts = r.charts = 1;
    return la;
}

// 1. T0 and, with a texture hierarchy, every rank (faces, UV area, UV-to-model scale).
std::vector<LayoutData> layoutsOf(const Asset& asset, const Multires& mr, bool hierarchy) {
    std::vector<LayoutData> layouts;
    layouts.push_back(layoutData(asset, mr.charts, 0));
    if (hierarchy)
        for (size_t j = 0; j < mr.textures.ranks.size(); ++j) layouts.push_back(layoutData(asset, mr.textures.ranks[j], uint32_t(j + 1)));
    return layouts;
}

// The measured deviation of a level view from the original; for a rigged asset the largest over
// the bind pose and the sampled poses (posed through the wedges its corners keep).
GeometricDistance measureLevel(const Asset& asset, const LevelView& lv, bool posed, PosedDistanceReference& original,
                               const DistanceOptions& dopt) {
    TriMesh level = asTriMesh(asset.mesh, lv);
    if (posed) {
        level.wedges = asset.mesh.wedges;
        level.cornerWedges = lv.cornerWedges;
    }
    return original.distance(level, dopt);
}

// Vertex placement of level view `lv` (measured as `d`): kept when the measured Hausdorff
// distance does not grow, which `d` then holds.
void placeVertices(const Asset& asset, LevelView& lv, bool posed, PosedDistanceReference& original,
                   const DistanceOptions& dopt, GeometricDistance& d, PackLevelReport::Placement& report) {
    auto t0 = Clock::now();
    PlacementOptions po;
    po.threads = dopt.threads;
    PlacementResult placed = placeLevelVertices(asset.mesh, original.bind(), *lv.data, po);
    report = {true, false, d.hausdorff, d.relHausdorff, d.rms, d.relRms, placed.moved, placed.fixed, placed.shortened,
              placed.rounds, 0, secondsSince(t0)};
    if (placed.moved > 0) {
        lv.positions = std::move(placed.positions);
        GeometricDistance after = measureLevel(asset, lv, posed, original, dopt);
        report.applied = after.hausdorff <= d.hausdorff;
        if (report.applied) d = after;
        else lv.positions.clear();
    }
    report.seconds = secondsSince(t0);
}

constexpr size_t kMeasureStride = 8;  // coarse pass of pack's measure: every 8th sample (DistanceOptions)

// 2. The measured deviation of each level from the original (LOD0: none), after vertex placement
// where it applies; for a rigged asset the largest over the bind pose and the sampled poses.
// Progress to 0.3.
template <class Progress>
void measureLevels(const Asset& asset, std::vector<LevelView>& views, const PackOptions& options,
                   PackResult& res, Progress&& progress) {
    const std::vector<PoseSample> poses = samplePoses(asset.rig, options.poses);
    const size_t n = views.size();
    res.reports.resize(n);
    DistanceOptions dopt;
    dopt.samplesPerSide = options.distanceSamples;
    dopt.threads = options.threads;
    // The deviation that picks switch distances is a maximum: a coarse pass finds the worst runs of
    // samples, which alone are sampled densely.
    dopt.refineStride = kMeasureStride;
    // The original's trees, built once for every level and placement and freed before the bakes.
    PosedDistanceReference original(asset.rig, asset.morph, asset.mesh, poses);
    const bool posed = !poses.empty();
    GeometricDistance previous;  // level k - 1's, before vertex placement
    for (size_t k = 0; k < n; ++k) {
        PackLevelReport& r = res.reports[k];
        r.source = views[k].source;
        r.maxDeviation = views[k].maxDeviation;
        if (k == 0) continue;
        // A level that repeats the one before it (unmoved) measures the same.
        GeometricDistance d = k > 1 && sameSurface(views[k], views[k - 1]) ? previous : measureLevel(asset, views[k], posed, original, dopt);
        previous = d;
        if (options.vertexPlacement && options.projectLevels && views[k].data)
            placeVertices(asset, views[k], posed, original, dopt, d, r.placement);
        r.hausdorff = d.hausdorff;
        r.relHausdorff = d.relHausdorff;
        r.rms = d.rms;
        r.relRms = d.relRms;
        progress(0.3 * double(k) / double(n));
    }
}

// 3. Screen coverage: value k = the smallest coverage at which LOD k is drawn (decreasing); the
// last one culls the coarsest level below cutoffPixels (and at half the previous value at most).
constexpr double kExactDeviation = 1e-7;  // relative to the diagonal
constexpr double kProjectionSlack = 1e-4;  // projection search reach beyond the measured deviation, x the diagonal

std::vector<double> screenCoverages(const PackResult& res, const PackOptions& options) {
    const size_t n = res.reports.size();
    const double H = options.viewportHeight, p = options.pixelError;
    std::vector<double> coverage(n, 0);
    for (size_t k = 0; k + 1 < n; ++k) {
        // A deviation below float precision of the positions is no deviation: the coarser level is
        // as good as this one at any size.
        const double e = res.reports[k + 1].hausdorff;
        double c = e > kExactDeviation * res.diagonal ? 2 * res.radius * p / (e * H) : options.lod0Coverage;
        if (k > 0) c = std::min(c, coverage[k - 1]);
        coverage[k] = c;
    }
    double cutoff = options.cutoffPixels / H;
    if (n >= 2) cutoff = std::min(cutoff, 0.5 * coverage[n - 2]);
    coverage[n - 1] = cutoff;
    return coverage;
}

// Level k's coverage range, switch distance and the texel density it can show: one texel per
// pixel at its largest coverage (texels per model unit).
void levelCoverage(const PackResult& res, size_t k, const PackOptions& options, PackLevelReport& r) {
    const double H = options.viewportHeight;
    const double tanHalf = std::tan(options.fovY * kPi / 360);
    r.coverage = res.screenCoverage[k];
    r.maxCoverage = k == 0 ? std::max(options.lod0Coverage, r.coverage) : res.screenCoverage[k - 1];
    r.switchDistance = res.radius / (r.coverage * tanHalf);
    r.texelLimit = (options.lod0Density ? res.reports[0].maxCoverage : r.maxCoverage) * H / (2 * res.radius);
}

// The layouts eligible for level `level`: T0 and every rank valid for it that the hierarchy offers
// at the page side the level needs (a rank whose smallest texture is larger than that page is not
// used: its extra chart seams and gutters only pay at the resolutions it was made for), ascending.
// The energy rule takes the highest (lowest E); chooseLayoutByBake measures them. The page side
// estimate does not depend on the layout: sqrt(3D area) x texel limit / 0.8. Sets r.sideNeeded,
// r.rank (the highest) and r.rankChoice.byEnergy.
std::vector<uint32_t> eligibleRanks(const Multires& mr, const std::vector<LayoutData>& layouts, size_t level, bool hierarchy,
                                    double area3D, const PackOptions& options, PackLevelReport& r) {
    const double sideNeeded = std::min(double(options.maxSize), std::sqrt(area3D) * r.texelLimit / 0.8);
    r.sideNeeded = sideNeeded;
    std::vector<char> eligible(layouts.size(), 0);
    eligible[0] = 1;
    if (hierarchy) {
        std::vector<int> smallest(layouts.size(), 0);
        for (const HierarchyTexture& h : mr.textures.textures)
            if (h.rank < layouts.size() && (smallest[h.rank] == 0 || h.size < smallest[h.rank])) smallest[h.rank] = h.size;
        for (const HierarchyTexture& h : mr.textures.textures)
            if (h.firstLevel <= level && level <= h.lastLevel && h.rank < layouts.size() && smallest[h.rank] <= sideNeeded)
                eligible[h.rank] = 1;
    }
    std::vector<uint32_t> ranks;
    for (uint32_t j = 0; j < eligible.size(); ++j)
        if (eligible[j]) ranks.push_back(j);
    r.rank = r.rankChoice.byEnergy = ranks.back();
    return ranks;
}

// Of rank r.rank's hierarchy textures the smallest that gives the density the level can show (the
// largest when none does). Sets r.textureSize (0 without a hierarchy).
void setTextureSize(const Multires& mr, const std::vector<LayoutData>& layouts, bool hierarchy, PackLevelReport& r) {
    const double tMax = r.texelLimit / layouts[r.rank].uvPerUnit;
    r.textureSize = 0;
    if (hierarchy)
        for (const HierarchyTexture& h : mr.textures.textures)
            if (h.rank == r.rank && (r.textureSize == 0 || (r.textureSize < tMax && h.size > r.textureSize) ||
                                     (h.size >= tMax && h.size < r.textureSize)))
                r.textureSize = h.size;
}

// The page of level k: the charts its triangles use, packed at the density limit tMax (layout
// units) with gutters for the mips used between its largest and smallest coverage (at most
// maxMips, none for pages below minMipSide). A page held below the density limit (maxSize) is
// magnified at the largest coverage and uses fewer mips: the gutter is narrowed to the fewest mips
// that the denser packing it allows still covers. A coarser level never carries more texels than
// the finer one (packing fewer, larger gutters can come out bigger at the same density): its
// density is lowered until it does not (at most 8 tries). `reports` holds levels 0..k-1.
LevelAtlas packLevelPage(const LayoutData& lay, const LevelUVs& luv, size_t k, const PackLevelReport& r,
                         const std::vector<PackLevelReport>& reports, const PackOptions& options, bool sourceTexels = false) {
    // Source texels (LOD0): one page texel per layout unit = per source texel, on whole texels.
    const double tMax = sourceTexels ? 1.0 : r.texelLimit / lay.uvPerUnit;
    // At density d (layout units) the smallest coverage samples mip log2(d / (tMax x cov / maxCov)).
    const double minCoverageRatio = std::max(r.coverage, 1e-12) / r.maxCoverage;
    auto mipsAt = [&](double d) { return int(std::ceil(std::log2(std::max(1.0, d / (tMax * minCoverageRatio)) - 1e-9))); };
    int mips = mipsAt(tMax);
    double usedUv = 0;
    {
        std::vector<char> seen(luv.ownChartArea.empty() ? lay.chartUvArea.size() : luv.ownChartArea.size(), 0);
        for (uint32_t c : luv.chart)
            if (!seen[c]) { seen[c] = 1; usedUv += levelChartArea(lay, luv, c); }
    }
    double side = std::min(double(options.maxSize), std::sqrt(usedUv) * tMax / 0.8);
    int mipLimit = side > options.minMipSide ? int(std::floor(std::log2(side / options.minMipSide))) : 0;
    mips = std::clamp(mips, 0, std::min(options.maxMips, mipLimit));
    AtlasOptions ao;
    ao.maxTexelsPerUnit = tMax;
    ao.gutter = 2 << mips;
    ao.maxSize = options.maxSize;
    ao.powerOfTwo = options.powerOfTwo;
    ao.threads = options.threads;
    ao.texelAligned = sourceTexels;
    LevelAtlas la = packLevelAtlas(lay, luv, k == 0, ao);
    for (int m = std::clamp(mipsAt(la.atlas.texelsPerUnit), 0, mips); m < mips; ++m) {
        AtlasOptions narrow = ao;
        narrow.gutter = 2 << m;
        LevelAtlas denser = packLevelAtlas(lay, luv, k == 0, narrow);
        if (mipsAt(denser.atlas.texelsPerUnit) > m) continue;
        mips = m;
        ao = narrow;
        la = std::move(denser);
        break;
    }
    for (int tries = 0; k > 0 && tries < 8; ++tries) {
        double previous = double(reports[k - 1].width) * reports[k - 1].height;
        double now = double(la.atlas.width) * la.atlas.height;
        if (now <= previous) break;
        ao.maxTexelsPerUnit = std::min(ao.maxTexelsPerUnit, la.atlas.texelsPerUnit) * std::sqrt(previous / now) * 0.98;
        la = packLevelAtlas(lay, luv, false, ao);
    }
    return la;
}

// The page figures of the report.
void recordPage(const LevelAtlas& la, const LayoutData& lay, PackLevelReport& r) {
    r.gutter = la.atlas.gutter;
    r.mips = std::max(0, int(std::log2(std::max(2, r.gutter) / 2)));  // the packer may narrow the gutter
    r.width = la.atlas.width;
    r.height = la.atlas.height;
    r.charts = la.charts;
    r.utilisation = la.atlas.utilisation;
    r.boxUtilisation = la.atlas.boxUtilisation;
    r.rasterUtilisation = la.atlas.rasterUtilisation;
    r.footprintUtilisation = la.atlas.footprintUtilisation;
    r.texelsPerUnit = la.atlas.texelsPerUnit * lay.uvPerUnit;
}

// Scored pages are packed at half the level's page side, and below this side when that is larger
// (texels): a 2048 page (LOD0 when the source texels do not fit) is scored at 512 a side.
constexpr double kScoredMaxSide = 512;

// Level k's layout by the bake (lod/rank_choice.h) among `ranks` (T0 first): each candidate's page
// packed at half the texel limit and page cap (a quarter of the texels; less above
// kScoredMaxSide), its level mesh built and
// its base colour (and, when the level gets one, its normal map in object space) baked the way
// the level's own bake runs (by projection, or the original triangles at the layout), then read
// back at the probe's sample points of the level's surface. The reduced page costs a fraction of
// a full-size one; where it ranks candidates differently than full size would, their scores lie
// within chooseCandidate's margin. The probe and the projected bakes
// search the original through `grid` (built here when missing). Sets r.rank, r.textureSize and
// r.rankChoice. The same for any thread count: each bake is, and the read-back runs in order.
void chooseLayoutByBake(const BakeSources& sources, const Multires& mr, std::vector<LayoutData>& layouts,
                        const std::vector<uint32_t>& ranks, const LevelView& view, size_t k, bool projected, bool normal,
                        std::optional<FaceGrid>& grid, const PackResult& res, const PackOptions& options, PackLevelReport& r) {
    const auto t0 = Clock::now();
    const double cpu0 = processCpuSeconds();
    const Asset& asset = sources.asset();
    const TriMesh& mesh = asset.mesh;
    if (!grid) grid.emplace(mesh);
    BakeChannels channels;  // base colour, and the normal map
    channels.normal = normal;
    const double reach = 1.5 * r.hausdorff + kProjectionSlack * res.diagonal;  // the level bake's
    // The probe: every level triangle in a cell of its own, baked by projection like a coarse level.
    const std::vector<Vec3>& positions = view.positionsOr(mesh);
    std::vector<std::array<Vec3, 3>> triangles(view.triangles.size());
    for (size_t t = 0; t < triangles.size(); ++t)
        for (size_t j = 0; j < 3; ++j) triangles[t][j] = positions[view.triangles[t][j]];
    const ProbeLayout probe = probeLayout(triangles);
    LodLevelData cells;
    for (size_t i = 0; i < probe.triangles.size(); ++i)
        for (size_t j = 0; j < 3; ++j) {
            const Vec3& p = triangles[probe.triangles[i]][j];
            cells.positions.insert(cells.positions.end(), {float(p.x), float(p.y), float(p.z)});
            cells.uvs.insert(cells.uvs.end(), {float(probe.uv[i][j].x), float(probe.uv[i][j].y)});
            cells.indices.push_back(uint32_t(cells.indices.size()));
        }
    const BakeTarget probeFrames = objectSpaceTarget(probe.uv);
    const BakeResult probeBake = bakeProjected(sources, *grid, cells, probe.triangles.size(), probe.side, probe.side, reach,
                                               res.diagonal, channels, normal ? &probeFrames : nullptr, options.threads);
    const PageChannels probePage{probe.side, probe.side, &probeBake.pixels, &probeBake.normal};

    // Half the side, or less for a page that needs more than 2 x kScoredMaxSide a side (LOD0 when
    // the source texels do not fit): scale s of the texel limit, page cap and mip sides, log2(1/s)
    // mips fewer (the same share of gutters).
    const double scale = std::min(0.5, kScoredMaxSide / std::max(1.0, r.sideNeeded));
    const int fewerMips = int(std::lround(std::log2(1 / scale)));
    PackOptions half = options;
    half.maxSize = std::max(16, int(options.maxSize * scale));
    half.minMipSide = std::max(1, int(options.minMipSide * scale));
    half.maxMips = std::max(0, options.maxMips - fewerMips);
    PackLevelReport halfReport = r;
    halfReport.texelLimit = scale * r.texelLimit;
    // The finer levels' pages at the same scale: a level's page holds no more texels than the
    // finer one's, a cap that decides many coarse pages' density.
    std::vector<PackLevelReport> halfReports(res.reports.begin(), res.reports.begin() + std::ptrdiff_t(k));
    for (PackLevelReport& f : halfReports) {
        f.width = int(std::ceil(f.width * scale));
        f.height = int(std::ceil(f.height * scale));
    }
    std::vector<RankCandidate> candidates;
    for (uint32_t rank : ranks) {
        LayoutData& lay = layouts[rank];
        const LevelUVs luv = projected ? ownCharts(mesh, lay, view, levelUVs(mesh, lay, view, view.data))
                                       : levelUVs(mesh, lay, view, view.data);
        const LevelAtlas la = packLevelPage(lay, luv, k, halfReport, halfReports, half);
        const int w = la.atlas.width, h = la.atlas.height, size = std::max(w, h);
        LodLevelData L;
        buildLevelMesh(asset, view, luv, la, L);
        std::vector<std::array<Vec2, 3>> pageUV(view.triangles.size()), bakeUV(view.triangles.size());
        for (size_t t = 0; t < pageUV.size(); ++t)
            for (size_t j = 0; j < 3; ++j) {
                const uint32_t v = L.indices[3 * t + j];
                pageUV[t][j] = {L.uvs[2 * v], L.uvs[2 * v + 1]};
                bakeUV[t][j] = {pageUV[t][j].x * w / size, pageUV[t][j].y * h / size};
            }
        const BakeTarget frames = objectSpaceTarget(std::move(bakeUV));
        const BakeTarget* framesOrNull = normal ? &frames : nullptr;
        const BakeResult baked = projected ? bakeProjected(sources, *grid, L, view.triangles.size(), w, h, reach, res.diagonal,
                                                           channels, framesOrNull, options.threads)
                                           : bakePage(sources, lay, la, channels, framesOrNull, options.threads, false);
        RankCandidate c;
        c.rank = rank;
        c.deviation = textureDeviation(probe, probePage, PageChannels{w, h, &baked.pixels, &baked.normal}, pageUV);
        c.width = w;
        c.height = h;
        c.charts = la.charts;
        candidates.push_back(c);
    }
    const size_t best = chooseCandidate(candidates, r.rankChoice.byEnergy);
    r.rank = candidates[best].rank;
    setTextureSize(mr, layouts, true, r);
    PackLevelReport::RankChoice& rc = r.rankChoice;
    rc.candidates.clear();
    for (const RankCandidate& c : candidates)
        rc.candidates.push_back({c.rank, c.deviation.score, c.deviation.color, c.deviation.normal, c.width, c.height, c.charts});
    rc.reason = choiceReason(candidates, best, rc.byEnergy);
    rc.seconds = secondsSince(t0);
    rc.cpuSeconds = processCpuSeconds() - cpu0;
}

// 5. The original as LOD0: it must be the chain's input (same flattened triangles).
SourceScene readOriginal(const Asset& asset, const PackOptions& options) {
    if (options.original.empty()) throw InvalidInput(asset.sourcePath + ": LOD0 'original' needs the original asset's path");
    SourceScene s = readSourceScene(options.original);
    if (s.triangles != asset.mesh.triangleCount())
        throw InvalidInput(options.original + ": not the original of " + asset.sourcePath + " (" + std::to_string(s.triangles) +
                           " triangles; the chain's original has " + std::to_string(asset.mesh.triangleCount()) + ")");
    return s;
}

// The report of LOD0 when it is the original: no page, bake or channels; deviation 0.
void describeOriginal(const SourceScene& s, PackLevelReport& r) {
    PackLevelReport o;
    o.source = "original asset";
    o.triangles = s.triangles;
    o.vertices = s.vertices;
    o.drawCalls = s.drawCalls;
    o.materials = s.materials;
    o.coverage = r.coverage;
    o.maxCoverage = r.maxCoverage;
    o.switchDistance = r.switchDistance;
    o.texelLimit = r.texelLimit;
    o.sideNeeded = r.sideNeeded;
    r = o;
}

}  // namespace

PackResult packLodChain(const Asset& asset, const Multires& mr, const PackOptions& options) {
    auto t0 = Clock::now();
    checkInput(asset, mr);
    const TriMesh& mesh = asset.mesh;
    PackResult res;
    const bool original = options.lod0 == Lod0::Original;
    if (original) res.original = readOriginal(asset, options);
    res.diagonal = bounds(mesh).diagonal();
    res.radius = 0.5 * res.diagonal;
    if (!(res.radius > 0)) throw Impossible(asset.sourcePath + ": the mesh has no extent");
    std::vector<std::string> repeated;
    std::vector<LevelView> views = levelViews(asset, mr, repeated);
    const BakeSources sources(asset);  // the original images, decoded once for every level's bake
    const size_t n = views.size();
    auto progress = [&](double f) { if (options.progress) options.progress(f); };

    const bool hierarchy = options.useTextureHierarchy && !mr.textures.empty();
    std::vector<LayoutData> layouts = layoutsOf(asset, mr, hierarchy);  // 1
    double area3D = 0;
    for (const Tri& t : mesh.triangles) area3D += triangleArea(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    const auto tMeasure = Clock::now();
    const double cpuMeasure = processCpuSeconds();
    measureLevels(asset, views, options, res, progress);  // 2
    res.measureSeconds = secondsSince(tMeasure);
    res.measureCpuSeconds = processCpuSeconds() - cpuMeasure;
    res.screenCoverage = screenCoverages(res, options);  // 3
    // The projection bakes' grid over the original, built for the first projected level: the
    // original triangles' page (the largest bake) runs without it.
    std::optional<FaceGrid> grid;
    double previousReach = -1;  // the previous level's projection reach (-1: not projected)

    // LOD0's layout on the original's texels (source_texels.h), made at LOD0.
    std::optional<SourceTexelLayout> sourceLayout;
    std::optional<LayoutData> sourceData;

    // 4. Per level: texture, page, mesh, bake.
    const MaterialPlan plan = options.baseColorOnly ? baseColorPlan(planMaterial(asset)) : planMaterial(asset);
    res.warnings = plan.warnings;
    const ChainVariants variants = chainVariants(asset, options.baseColorOnly);  // KHR_materials_variants (level_variants.h)
    res.warnings.insert(res.warnings.end(), variants.warnings.begin(), variants.warnings.end());
    res.variants = variants.names;
    // What glTF cannot vary per texel, kept exact by primitives on the same pages (draw_split.h):
    // the default selection, then each variant bake's.
    const std::vector<int32_t> noMaterials(mesh.triangleMaterial.empty() ? mesh.triangleCount() : 0, -1);
    std::vector<const std::vector<int32_t>*> selections{mesh.triangleMaterial.empty() ? &noMaterials : &mesh.triangleMaterial};
    for (const auto& b : variants.bakes) selections.push_back(&b->asset.mesh.triangleMaterial);
    DrawSplitOptions splitOptions;
    splitOptions.maxDraws = options.maxDraws;
    splitOptions.extensionProperties = plan.ext.any();  // else no material of the chain carries them
    for (const auto& b : variants.bakes) splitOptions.extensionProperties |= b->plan.ext.any();
    const DrawSplit split = splitDraws(asset, selections, splitOptions);
    res.warnings.insert(res.warnings.end(), split.warnings[0].begin(), split.warnings[0].end());
    std::vector<size_t> selectionOfVariant;  // per variant: its selection (0 = the default's)
    for (size_t v = 0; v < variants.names.size(); ++v) {
        const int b = variants.bakeOf[v];
        selectionOfVariant.push_back(b < 0 ? 0 : size_t(b) + 1);
        const bool first = b >= 0 && std::find(variants.bakeOf.begin(), variants.bakeOf.end(), b) - variants.bakeOf.begin() == std::ptrdiff_t(v);
        if (first)
            for (const std::string& w : split.warnings[size_t(b) + 1]) res.warnings.push_back("variant '" + variants.names[v] + "': " + w);
    }
    std::vector<std::vector<uint32_t>> triangleGroups(n);  // per level, per triangle: its draw group
    res.warnings.insert(res.warnings.end(), repeated.begin(), repeated.end());
    res.rig = asset.rig;
    res.morph = asset.morph;
    res.scene = asset.scene;
    LevelImageOptions io;
    io.format = options.ktx2Encoder.empty() ? options.imageFormat : ImageFormat::Png;
    io.jpegQuality = options.jpegQuality;
    io.ktx2Encoder = options.ktx2Encoder;
    io.threads = options.threads;
    // A repeating material keeps its tiling: levels on one baked period of it (tiled_levels.h).
    const TilingEligibility tiling = options.keepTiling ? tilingEligibility(asset) : TilingEligibility{};
    const bool tileNormalMap = !options.baseColorOnly && (options.normalMaps == NormalMaps::Always ||
                                                          (options.normalMaps == NormalMaps::Auto && plan.normalTexture));
    std::optional<LodMaterial> tile;  // baked at the first tiled level
    res.levels.resize(original ? n - 1 : n);
    for (size_t k = 0; k < n; ++k) {
        PackLevelReport& r = res.reports[k];
        levelCoverage(res, k, options, r);
        const std::vector<uint32_t> eligible = eligibleRanks(mr, layouts, views[k].level, hierarchy, area3D, options, r);
        setTextureSize(mr, layouts, hierarchy, r);
        r.tiling.note = tiling.reason;
        std::optional<TiledLevelUVs> tiled;
        if (tiling.eligible)
            tiled = tiledLevel(mesh, views[k].positionsOr(mesh), views[k].triangles, views[k].faces, tiling, r.tiling);
        const bool projected = k > 0 && options.projectLevels;
        // Several layouts eligible: the one whose bake shows the least texture deviation (LOD0 on
        // the source texels needs none, unless they do not fit; the original as LOD0 bakes none).
        const bool levelNormalMap = !options.baseColorOnly && (options.normalMaps == NormalMaps::Always ||
                                                               (options.normalMaps == NormalMaps::Auto && (plan.normalTexture || k > 0)));
        auto chooseRank = [&] {
            if (options.rankByBake && eligible.size() > 1 && !(original && k == 0))
                chooseLayoutByBake(sources, mr, layouts, eligible, views[k], k, projected, levelNormalMap, grid, res, options, r);
        };
        if (k == 0 && options.sourceTexels && !tiled) {
            std::vector<std::pair<int, int>> sizes;
            for (const Image& image : asset.images) sizes.push_back(imageSize(image));
            sourceLayout = sourceTexelLayout(asset, sizes, *layouts[0].ch, r.texelLimit / layouts[0].uvPerUnit);
            if (!sourceLayout->layout.empty()) {
                sourceData.emplace(layoutData(asset, sourceLayout->layout, r.rank));
                sourceData->inPlaceCharts = uint32_t(sourceLayout->inPlace);
            }
            r.sourceTexelsNote = sourceLayout->reason;
        }
        if (!(k == 0 && sourceData) && !tiled) chooseRank();
        auto tStep = Clock::now();
        double cpuStep = processCpuSeconds();
        auto lap = [&](double& wall, double& cpu) {
            const double c = processCpuSeconds();
            wall = secondsSince(tStep);
            cpu = c - cpuStep;
            tStep = Clock::now();
            cpuStep = c;
        };
        LodLevelData scratch;  // LOD0's mesh when the original is LOD0: never built
        LodLevelData& L = original ? (k > 0 ? res.levels[k - 1] : scratch) : res.levels[k];
        L.name = "LOD" + std::to_string(k);
        LevelAtlas la;
        // LOD0 on the source texels when they fit the page whole, else on the rank's layout.
        bool sourceTexels = k == 0 && sourceData;
        LayoutData* layout = sourceTexels ? &*sourceData : &layouts[r.rank];
        if (tiled) {  // the original's texture coordinates on the tile
            la = tiledPage(tiling, r);
            if (original && k == 0) continue;
            LevelUVs luv;
            luv.uv = std::move(tiled->uv);
            luv.chart.assign(luv.uv.size(), 0);
            buildLevelMesh(asset, views[k], luv, la, L);
        } else {  // the level's layout UVs end with its mesh, before the bake
            LevelUVs luv = projected ? ownCharts(mesh, *layout, views[k], levelUVs(mesh, *layout, views[k], views[k].data))
                                     : levelUVs(mesh, *layout, views[k], views[k].data);
            lap(r.wall.uvs, r.cpu.uvs);
            la = packLevelPage(*layout, luv, k, r, res.reports, options, sourceTexels);
            if (sourceTexels && la.atlas.texelsPerUnit < 1) {
                r.sourceTexelsNote = "the original's texture islands do not fit a " + std::to_string(options.maxSize) + " page";
                sourceTexels = false;
                chooseRank();
                layout = &layouts[r.rank];
                luv = levelUVs(mesh, *layout, views[k], views[k].data);
                la = packLevelPage(*layout, luv, k, r, res.reports, options);
            }
            r.sourceTexels = sourceTexels;
            lap(r.wall.page, r.cpu.page);
            recordPage(la, *layout, r);
            r.absorbedIslands = luv.absorbedIslands;
            if (original && k == 0) continue;  // 5: the page only, for LOD1's texel cap
            buildLevelMesh(asset, views[k], luv, la, L);
        }
        const size_t front = L.indices.size() / 3;
        const std::vector<size_t> backSource = plan.backFaces ? addBackFaces(asset, views[k], L) : std::vector<size_t>{};
        if (split.groups.size() > 1) {
            std::vector<uint32_t>& groups = triangleGroups[k];
            for (size_t t = 0; t < front; ++t) groups.push_back(split.groupOf[views[k].faces[t]]);
            for (size_t t : backSource) groups.push_back(groups[t]);
        }
        // The level's channels for a material plan: the default's, or a variant's.
        auto channelsOf = [&](const MaterialPlan& p) {
            return levelChannels(p, !options.baseColorOnly && (options.normalMaps == NormalMaps::Always ||
                                                               (options.normalMaps == NormalMaps::Auto && (p.normalTexture || k > 0))));
        };
        const BakeChannels channels = tiled ? levelChannels(plan, tileNormalMap) : channelsOf(plan);
        const bool normalMaps = channels.normal || channels.clearcoatNormal || channels.anisotropy || variantsNeedTangents(variants, channelsOf);
        if (normalMaps) L.tangents = levelTangents(L);
        // The normal maps' target frames; none without one.
        std::optional<BakeTarget> target;
        if (normalMaps && !tiled) target = levelBakeTarget(L, la.atlas.width, la.atlas.height);
        const BakeTarget* targetOrNull = target ? &*target : nullptr;
        lap(r.wall.mesh, r.cpu.mesh);
        const double reach = 1.5 * r.hausdorff + kProjectionSlack * res.diagonal;
        // A projected level with the previous projected level's mesh, page and reach (and so its
        // channels: every coarser level has the same) bakes the same: its material is copied.
        const LodLevelData* previous = k > 1 ? &res.levels[k - 1 - (original ? 1 : 0)] : nullptr;
        const bool repeat = projected && previous && reach == previousReach && la.atlas.width == res.reports[k - 1].width &&
                            la.atlas.height == res.reports[k - 1].height && sameLevelMesh(L, *previous);
        if (projected && !grid && !repeat && !tiled) grid.emplace(mesh);
        BakeResult baked;
        if (tiled && !tile) {
            baked = bakeTile(asset, tiling, channels, options.threads);
            tile = levelMaterial(plan, baked, tiling.width, tiling.height, io, "tile");
            tile->repeat = true;
            std::tie(tile->minFilter, tile->magFilter) = sourceFilters(asset);  // its texels are the source's
        } else if (!repeat && !tiled)
            baked = projected ? bakeProjected(sources, *grid, L, front, la.atlas.width, la.atlas.height, reach, res.diagonal, channels,
                                              targetOrNull, options.threads)
                              : bakePage(sources, *layout, la, channels, targetOrNull, options.threads, sourceTexels);
        previousReach = projected && !tiled ? reach : -1;
        r.bakeSeconds = baked.seconds;
        lap(r.wall.bake, r.cpu.bake);
        L.material = tiled ? *tile : repeat ? previous->material : levelMaterial(plan, baked, la.atlas.width, la.atlas.height, io, L.name);
        if (sourceTexels) std::tie(L.material.minFilter, L.material.magFilter) = sourceFilters(asset);
        if (repeat && !variants.empty()) copyLevelVariants(*previous, variants, L, r);
        if (!repeat && !variants.empty())  // the same bake with each variant's sources and channels
            bakeLevelVariants(
                variants, channelsOf,
                [&](const BakeSources& s, const BakeChannels& c) {
                    return projected ? bakeProjected(s, *grid, L, front, la.atlas.width, la.atlas.height, reach, res.diagonal, c,
                                                     targetOrNull, options.threads)
                                     : bakePage(s, *layout, la, c, targetOrNull, options.threads, sourceTexels);
                },
                [&](const MaterialPlan& p, const BakeResult& b, const std::string& name) {
                    return levelMaterial(p, b, la.atlas.width, la.atlas.height, io, name);
                },
                L, r);
        lap(r.wall.material, r.cpu.material);
        r.channels = channelNames(L.material);
        r.triangles = L.indices.size() / 3;
        r.vertices = L.positions.size() / 3;
        progress(0.3 + 0.7 * double(k + 1) / double(n));
    }
    // 6. Levels whose triangles span several draw groups: ordered by group, one primitive each
    // (after every bake: a repeated level compares its mesh with the previous one as baked).
    for (size_t k = original ? 1 : 0; k < n && split.groups.size() > 1; ++k)
        splitLevel(split, triangleGroups[k], selectionOfVariant, res.levels[original ? k - 1 : k], res.reports[k]);
    if (original) describeOriginal(*res.original, res.reports[0]);
    res.seconds = secondsSince(t0);
    return res;
}

namespace {

// Level k of one written file's stats (and the file's warnings, once: k == 0) into the pack's.
void appendLevelStats(PackWriteStats& st, const LodChainWriteStats& w, size_t k) {
    st.levelBytes.push_back(w.levelGeometryBytes[k] + w.levelImageBytes[k]);
    st.levelGeometryBytes.push_back(w.levelGeometryBytes[k]);
    st.levelImageBytes.push_back(w.levelImageBytes[k]);
    st.cacheBefore.push_back(w.levelCacheBefore[k]);
    st.cacheAfter.push_back(w.levelCacheAfter[k]);
    if (k == 0) st.warnings.insert(st.warnings.end(), w.warnings.begin(), w.warnings.end());
}

}  // namespace

PackWriteStats writePackResult(const std::string& path, const PackResult& result, const PackWriteOptions& options) {
    PackWriteStats st;
    LodChainWriteOptions chain = options.chain;
    chain.variants = result.variants;
    if (!options.split) {
        LodChainWriteStats w = writeLodChain(path, result.levels, result.screenCoverage, chain, &result.rig, &result.morph,
                                             &result.scene, result.original ? &*result.original : nullptr);
        st.files.push_back(path);
        for (size_t k = 0; k < result.reports.size(); ++k) appendLevelStats(st, w, k);
        st.totalBytes = w.fileBytes;
        return st;
    }
    namespace fs = std::filesystem;
    fs::path p(path);
    std::string stem = (p.parent_path() / p.stem()).string(), ext = p.extension().string();
    nlohmann::json manifest;
    manifest["levels"] = nlohmann::json::array();
    const size_t first = result.original ? 1 : 0;  // index in result.levels of LOD0 - first
    for (size_t k = 0; k < result.reports.size(); ++k) {
        std::string file = stem + ".lod" + std::to_string(k) + ext;
        const bool hero = result.original && k == 0;
        LodChainWriteStats w = hero ? writeLodChain(file, {}, {}, chain, &result.rig, &result.morph, &result.scene, &*result.original)
                                    : writeLodChain(file, {result.levels[k - first]}, {}, chain, &result.rig, &result.morph, &result.scene);
        st.files.push_back(file);
        appendLevelStats(st, w, 0);
        st.totalBytes += w.fileBytes;
        manifest["levels"].push_back({{"file", fs::path(file).filename().string()},
                                      {"screenCoverage", result.screenCoverage[k]},
                                      {"triangles", hero ? result.original->triangles : result.levels[k - first].indices.size() / 3}});
    }
    manifest["cutoff"] = result.screenCoverage.back();
    manifest["screenCoverage"] = result.screenCoverage;
    manifest["note"] = "level k is drawn while the bounding sphere's projected height / viewport height >= screenCoverage[k]; "
                       "below the last value nothing is drawn (MSFT_screencoverage semantics)";
    std::string mpath = stem + ".lods.json";
    std::string text = manifest.dump(2) + "\n";
    writeFileAtomic(mpath, text);
    st.files.push_back(mpath);
    st.totalBytes += text.size();
    return st;
}

}  // namespace lodbake
