// parameterize: charts, Tutte, Ceres (E = beta E_pixel + (1 - beta) E_poly), checks and
// fallbacks, shelf-packed atlas, per-corner and per-level UVs (thesis 3.3; DESIGN.md).
//
// Pipeline of parameterize, in execution order:
//   (1) buildCharts         charts from the coarsest level's base regions (chart/charts.cpp)
//   (2) localCharts         each chart as a local mesh with its simplification pairs and the level
//                           triangles it carries (all levels)
//   (3) solveCharts         per chart (solveChart): Tutte map, Ceres, injectivity and level-fold
//                           checks; fallback beta = 1, then Tutte
//   (4) measureCharts       stretch (Sander et al. 2001), UV/3D area ratios; alignChart
//   (5)-(7) layoutAtlas     rounds of packCharts (shelfPack at a uniform density), writeCornerUVs,
//                           writeLevelUVs, and addFoldIslands (level triangles that fold or cross a
//                           chart boundary get their own island) until no level folds
//   nudgeRoundedSliverCorners   sliver faces that flip once their UVs are rounded to float
//   foldedAtlasFaces, carveFaces  fallback: an original face still folded in the atlas gets a chart
//                           of its own (so does every face of a chart the solver cannot map,
//                           splitFailedCharts), then (5)-(7) again
#include "lodbake/param/parameterize.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <string>
#include <thread>
#include <unordered_map>

#include "lodbake/atlas/atlas.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/timing.h"
#include "lodbake/core/parallel.h"
#include "param/uv_check_detail.h"

namespace lodbake {
namespace {

struct LocalChart {
    std::vector<uint32_t> faces;            // original faces (non-degenerate)
    std::vector<uint32_t> vertices;         // local -> global, sorted
    std::unordered_map<uint32_t, uint32_t> local;  // global -> local
    ChartMesh mesh;
    std::vector<ChartPair> pairs;
    std::vector<Vec2> uv;                   // final map, model units
};

void extractCharts(const TriMesh& mesh, const ChartResult& cr, std::vector<LocalChart>& charts) {
    charts.assign(cr.chartCount, {});
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f)
        if (cr.faceChart[f] >= 0 && !degenerateIndices(mesh.triangles[f])) charts[size_t(cr.faceChart[f])].faces.push_back(f);
    for (LocalChart& c : charts) {
        for (uint32_t f : c.faces) c.vertices.insert(c.vertices.end(), mesh.triangles[f].begin(), mesh.triangles[f].end());
        std::sort(c.vertices.begin(), c.vertices.end());
        c.vertices.erase(std::unique(c.vertices.begin(), c.vertices.end()), c.vertices.end());
        c.local.reserve(c.vertices.size());
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
}

// The square root of the mean face area: a face's usual size.
double typicalFaceSize(const TriMesh& mesh) {
    double area = 0;
    for (const Tri& t : mesh.triangles)
        area += 0.5 * length(cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]));
    return std::sqrt(area / double(std::max<size_t>(1, mesh.triangleCount())));
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
}

struct Stretch {
    double l2 = 0, linf = 0;
    std::vector<double> ratios;  // per triangle UV area / 3D area (raw), 3D-degenerate skipped
    double sumUV = 0, sum3D = 0;
};

// Sander et al. 2001 stretch of the map UV -> 3D, accumulated (not yet normalised).
void accumulateStretch(const ChartMesh& m, const std::vector<Vec2>& uv, Stretch& s, double& l2sum, double& gmax) {
    for (const Tri& t : m.triangles) {
        Vec3 q1 = m.positions[t[0]], q2 = m.positions[t[1]], q3 = m.positions[t[2]];
        Vec2 p1 = uv[t[0]], p2 = uv[t[1]], p3 = uv[t[2]];
        double a3 = 0.5 * length(cross(q2 - q1, q3 - q1));
        double a2 = 0.5 * cross(p2 - p1, p3 - p1);
        s.sumUV += std::max(a2, 0.0);
        s.sum3D += a3;
        if (a3 <= 0 || a2 <= 0) continue;
        s.ratios.push_back(a2 / a3);
        Vec3 Ss = (q1 * (p2.y - p3.y) + q2 * (p3.y - p1.y) + q3 * (p1.y - p2.y)) / (2 * a2);
        Vec3 St = (q1 * (p3.x - p2.x) + q2 * (p1.x - p3.x) + q3 * (p2.x - p1.x)) / (2 * a2);
        double a = dot(Ss, Ss), b = dot(Ss, St), c = dot(St, St);
        l2sum += (a + c) / 2 * a3;
        gmax = std::max(gmax, std::sqrt(std::max(0.0, ((a + c) + std::sqrt((a - c) * (a - c) + 4 * b * b)) / 2)));
    }
}

void finishStretch(Stretch& s, double l2sum, double gmax) {
    double norm = s.sum3D > 0 ? std::sqrt(s.sumUV / s.sum3D) : 1;
    s.l2 = s.sum3D > 0 ? std::sqrt(l2sum / s.sum3D) * norm : 0;
    s.linf = gmax * norm;
}

double ratioStdDev(const std::vector<double>& ratios, double mean) {
    if (ratios.empty() || !(mean > 0)) return 0;
    double acc = 0;
    for (double r : ratios) acc += (r / mean - 1) * (r / mean - 1);
    return std::sqrt(acc / double(ratios.size()));
}

ChartEnergy addEnergy(ChartEnergy a, const ChartEnergy& b) {
    a.E += b.E;
    a.pixel += b.pixel;
    a.poly += b.poly;
    a.edge += b.edge;
    a.area += b.area;
    return a;
}

// Folded level triangles of a chart map: flipped or overlapping another triangle of the same
// level (checked per level, in the chart's own UV frame scaled to a unit box).
size_t levelFolds(const ChartMesh& chart, const std::vector<Vec2>& uv) {
    if (chart.levelTriangles.empty() || uv.empty()) return 0;
    Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
    for (Vec2 p : uv) {
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
    }
    const double scale = 1 / std::max({hi.x - lo.x, hi.y - lo.y, 1e-30});
    std::map<uint32_t, std::vector<std::array<Vec2, 3>>> byLevel;
    for (const ChartLevelTriangle& t : chart.levelTriangles) {
        std::array<Vec2, 3> tri;
        for (size_t k = 0; k < 3; ++k) {
            Vec2 p = chartPointUV(t.corner[k], uv);
            tri[k] = {(p.x - lo.x) * scale, -(p.y - lo.y) * scale};  // glTF convention: v down
        }
        byLevel[t.level].push_back(tri);
    }
    size_t folds = 0;
    for (const auto& [level, tris] : byLevel) {
        UVInjectivity r = checkUVInjectivity(tris, 1e-6);
        folds += r.flips + r.overlaps;
    }
    return folds;
}

void solveChart(LocalChart& c, const ParameterizeOptions& o, double resolution, ChartReport& rep) {
    auto t0 = Clock::now();
    ChartSolveOptions so = o.solve;
    so.energy.resolution = resolution;
    auto valid = [&](const std::vector<Vec2>& uv) {
        return countFlips(c.mesh, uv) == 0 && countOverlaps(c.mesh, uv) == 0;
    };
    // The start: the least-squares conformal map when it is injective (its free boundary follows
    // the chart, so few iterations remain), else Tutte's, which exists whenever the chart is a
    // disk. With no iterations the Tutte map is kept as it is, and so is an LSCM start of more
    // than kKeepLscmAboveVertices vertices. Tutte's solve is the costliest step on large charts
    // (its LU factor was parameterize's memory peak), so it runs only as that fallback.
    std::vector<Vec2> start;
    if (so.maxIterations > 0) try {
        start = lscmEmbedding(c.mesh);
        if (!valid(start)) start.clear();
    } catch (const Error&) {
        // Singular or degenerate: Tutte's start.
        start.clear();
    }
    rep.start = start.empty() ? "tutte" : "lscm";
    if (start.empty()) try {
        start = tutteEmbedding(c.mesh);
    } catch (const Error& e) {
        // No map of this chart: splitFailedCharts lays its faces out one by one.
        rep.method = "failed";
        rep.failure = e.what();
        c.uv.clear();
        rep.seconds = secondsSince(t0);
        return;
    }
    rep.initial = chartEnergy(c.mesh, c.pairs, start, so.energy);
    // Candidates in order of preference; the first injective one without folded level triangles
    // wins, else the injective one with the fewest (level triangles that stay folded get islands
    // of their own). The start is the fallback: a candidate with as few folds replaces it.
    c.uv = start;
    rep.method = rep.start;
    bool fallback = true;
    size_t bestFolds = levelFolds(c.mesh, start);
    auto consider = [&](const std::vector<Vec2>& uv, const char* method) {
        if (!valid(uv)) return;
        size_t folds = levelFolds(c.mesh, uv);
        if (folds > bestFolds || (!fallback && folds == bestFolds)) return;
        c.uv = uv;
        rep.method = method;
        bestFolds = folds;
        fallback = false;
    };
    const bool solve = so.maxIterations > 0 && (rep.start != "lscm" || c.mesh.positions.size() <= kKeepLscmAboveVertices);
    if (solve) {
        ChartSolveResult r = optimizeChartUV(c.mesh, c.pairs, start, so);
        rep.iterations = r.iterations;
        if (r.improved) consider(r.uv, "ceres");
        // The beta = 1 retry: when the solve kept nothing, or (small charts) to lower the folds.
        const bool large = c.mesh.positions.size() > kLargeChartVertices;
        if (so.energy.beta < 1 && (fallback || (bestFolds > 0 && !large))) {
            ChartSolveOptions s1 = so;
            s1.energy.beta = 1;
            ChartSolveResult r1 = optimizeChartUV(c.mesh, c.pairs, start, s1);
            rep.iterations += r1.iterations;
            if (r1.improved) consider(r1.uv, "ceres-beta1");
        }
    }
    rep.levelFlips = countLevelFlips(c.mesh, c.uv);
    rep.final = chartEnergy(c.mesh, c.pairs, c.uv, so.energy);
    rep.flips = countFlips(c.mesh, c.uv);
    rep.overlaps = countOverlaps(c.mesh, c.uv);
    rep.seconds = secondsSince(t0);
}

// Rotates a chart so its principal UV axis is horizontal (tighter shelf packing).
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

// Model-unit UVs of a level triangle's island: the 3D triangle laid flat (A at the origin, B on
// +u, C above), each side and the height at least `minSize` so the island keeps texels and a
// positive float area. Counter-clockwise.
std::vector<Vec2> islandLayout(Vec3 a, Vec3 b, Vec3 c, double minSize) {
    Vec3 ab = b - a, ac = c - a;
    double lab = length(ab);
    double x = lab > 0 ? dot(ac, ab) / lab : 0;
    double y = lab > 0 ? length(cross(ab, ac)) / lab : length(ac);
    lab = std::max(lab, minSize);
    y = std::max(y, minSize);
    return {Vec2{0, 0}, Vec2{lab, 0}, Vec2{x, y}};
}

// glTF stores UVs as floats: an original face that is a sliver in 3D (hence in UV) can come out
// flat or flipped once its corner UVs are rounded to float, whatever their double values. Such a
// face's corner opposite its longest (rounded) edge is moved on a grid of 2^-24 steps (one float
// step for UVs in [0.5, 1), below the overlap tolerance of the checks) in the first of eight
// directions, up to eight steps out, that makes the rounded triangle face the right way. Only this
// face's corner UVs change (cornerUV holds UVs per face corner, nothing is shared); returns the
// faces nudged. `pack` has its own repair for its indexed float meshes (lod_chain.cpp).
size_t nudgeRoundedSliverCorners(const TriMesh& mesh, const std::vector<int32_t>& faceChart, std::vector<std::array<Vec2, 3>>& cornerUV) {
    auto rounded = [](Vec2 p) { return Vec2{double(float(p.x)), double(float(p.y))}; };
    auto area = [&](const std::array<Vec2, 3>& t) {  // math orientation (v up) of glTF UVs
        Vec2 a = rounded(t[0]), b = rounded(t[1]), c = rounded(t[2]);
        a.y = -a.y;
        b.y = -b.y;
        c.y = -c.y;
        return cross(b - a, c - a);
    };
    constexpr double kStep = 1.0 / 16777216.0;  // 2^-24: one float step for UVs in [0.5, 1)
    const Vec2 dirs[8] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, 1}, {1, -1}, {-1, -1}};
    size_t repaired = 0;
    for (size_t f = 0; f < cornerUV.size(); ++f) {
        if (faceChart[f] < 0 || degenerateIndices(mesh.triangles[f]) || area(cornerUV[f]) > 0) continue;
        std::array<Vec2, 3>& t = cornerUV[f];
        const size_t apex = cornerOppositeLongestEdge({rounded(t[0]), rounded(t[1]), rounded(t[2])});
        bool done = false;
        for (int step = 1; step <= 8 && !done; ++step)
            for (const Vec2& dir : dirs) {
                std::array<Vec2, 3> c = t;
                c[apex] = rounded(t[apex]) + dir * (step * kStep);
                if (area(c) > 0) {
                    t = c;
                    done = true;
                    break;
                }
            }
        if (done) ++repaired;
    }
    return repaired;
}

// A chart of one original face, laid flat by islandLayout (injective by construction).
LocalChart singleFaceChart(const TriMesh& mesh, uint32_t f, double minSize) {
    LocalChart c;
    const Tri& t = mesh.triangles[f];
    c.faces = {f};
    c.vertices = {t[0], t[1], t[2]};
    std::sort(c.vertices.begin(), c.vertices.end());
    for (uint32_t i = 0; i < 3; ++i) {
        c.local.emplace(c.vertices[i], i);
        c.mesh.positions.push_back(mesh.positions[c.vertices[i]]);
    }
    c.mesh.triangles.push_back({c.local[t[0]], c.local[t[1]], c.local[t[2]]});
    std::vector<Vec2> flat = islandLayout(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]], minSize);
    c.uv.assign(3, {});
    for (size_t k = 0; k < 3; ++k) c.uv[c.local[t[k]]] = flat[k];
    return c;
}

// The fallback for faces no chart map keeps injective: each face in `faces` (ascending) leaves its
// chart and becomes a single-face chart appended after the existing ones (a face that already is
// one is laid out again with `minSize`). The chart it leaves keeps its map for its other faces.
// Returns the UV area (model units^2) the new charts add.
double carveFaces(const TriMesh& mesh, const std::vector<uint32_t>& faces, double minSize, std::vector<LocalChart>& charts,
                  ParameterizeResult& res) {
    double addedArea = 0;
    for (uint32_t f : faces) {
        const int32_t old = res.charts.faceChart[f];
        if (old < 0) continue;
        LocalChart& from = charts[size_t(old)];
        if (from.faces.size() == 1) {
            from = singleFaceChart(mesh, f, minSize);
            continue;
        }
        auto it = std::find(from.faces.begin(), from.faces.end(), f);
        if (it == from.faces.end()) continue;
        const size_t i = size_t(it - from.faces.begin());
        from.faces.erase(it);
        from.mesh.triangles.erase(from.mesh.triangles.begin() + long(i));
        if (from.faces.empty()) from.uv.clear();
        LocalChart c = singleFaceChart(mesh, f, minSize);
        addedArea += 0.5 * std::abs(cross(c.uv[1] - c.uv[0], c.uv[2] - c.uv[0]));
        res.charts.faceChart[f] = int32_t(charts.size());
        ChartReport rep;
        rep.faces = 1;
        rep.vertices = 3;
        rep.method = "single-face";
        res.chartReports.push_back(rep);
        charts.push_back(std::move(c));
        ++res.carvedFaces;
    }
    res.charts.chartCount = uint32_t(charts.size());
    return addedArea;
}

// Charts emptied by carveFaces are dropped and the rest renumbered in order (chart ids stay dense).
void dropEmptyCharts(std::vector<LocalChart>& charts, ParameterizeResult& res) {
    std::vector<int32_t> newId(charts.size(), -1);
    size_t n = 0;
    for (size_t c = 0; c < charts.size(); ++c)
        if (!charts[c].faces.empty() || res.chartReports[c].method != "failed") newId[c] = int32_t(n++);
    if (n == charts.size()) return;
    for (int32_t& c : res.charts.faceChart)
        if (c >= 0) c = newId[size_t(c)];
    for (size_t c = 0; c < charts.size(); ++c)
        if (newId[c] >= 0 && size_t(newId[c]) != c) {
            charts[size_t(newId[c])] = std::move(charts[c]);
            res.chartReports[size_t(newId[c])] = std::move(res.chartReports[c]);
        }
    charts.resize(n);
    res.chartReports.resize(n);
    res.charts.chartCount = uint32_t(n);
}

// (3b) A chart the solver could not map at all (not a disk after all, a singular Tutte system):
// its faces become single-face charts, laid out at about 2 texels a side of the expected density.
void splitFailedCharts(const TriMesh& mesh, const ParameterizeOptions& options, std::vector<LocalChart>& charts,
                       ParameterizeResult& res) {
    std::vector<uint32_t> faces;
    for (size_t c = 0; c < charts.size(); ++c) {
        if (res.chartReports[c].method != "failed") continue;
        ++res.failedCharts;
        res.warnings.push_back("chart " + std::to_string(c) + " (" + std::to_string(charts[c].faces.size()) +
                               " faces) could not be flattened (" + res.chartReports[c].failure +
                               "); its faces are laid out one by one");
        faces.insert(faces.end(), charts[c].faces.begin(), charts[c].faces.end());
    }
    if (faces.empty()) return;
    std::sort(faces.begin(), faces.end());
    double area = 0;
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f) {
        const Tri& t = mesh.triangles[f];
        area += 0.5 * length(cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]));
    }
    const double expectedDensity = 0.7 * options.textureSize / std::sqrt(std::max(area, 1e-30));
    carveFaces(mesh, faces, 2.0 / expectedDensity, charts, res);
    dropEmptyCharts(charts, res);
}

// Original faces folded in the packed atlas, checked as the tool checks them (float UVs, overlap
// tolerance 1e-7): every flipped face and, of each overlapping pair, the one with the smaller 3D
// area (ascending face ids). Sets res.flips and res.overlaps to the counts.
std::vector<uint32_t> foldedAtlasFaces(const TriMesh& mesh, ParameterizeResult& res) {
    std::vector<std::array<Vec2, 3>> tris;
    std::vector<uint32_t> which;
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f)
        if (!degenerateIndices(mesh.triangles[f])) {
            tris.push_back(res.cornerUV[f]);
            which.push_back(f);
        }
    param_detail::UVFolds folds = param_detail::findUVFolds(tris, 1e-7);
    std::vector<char> pick(tris.size(), 0);
    res.flips = 0;
    for (size_t i = 0; i < tris.size(); ++i) {
        pick[i] = folds.flipped[i];
        res.flips += size_t(folds.flipped[i]);
    }
    auto area3 = [&](uint32_t f) {
        const Tri& v = mesh.triangles[f];
        return length(cross(mesh.positions[v[1]] - mesh.positions[v[0]], mesh.positions[v[2]] - mesh.positions[v[0]]));
    };
    std::set<uint32_t> overlapping;
    for (const auto& [i, j] : folds.overlapping) {
        overlapping.insert(i);
        overlapping.insert(j);
        if (pick[i] || pick[j]) continue;
        pick[area3(which[i]) <= area3(which[j]) ? i : j] = 1;
    }
    res.overlaps = overlapping.size();
    std::vector<uint32_t> faces;
    for (size_t i = 0; i < tris.size(); ++i)
        if (pick[i]) faces.push_back(which[i]);
    return faces;
}

// A level corner projected onto a chart: the closest point of the chart's faces (face, bary).
struct Projection {
    uint32_t face = 0;
    std::array<double, 3> bary{1, 0, 0};
};

// The chart tables and island state shared by the packing rounds (islands grow between rounds).
struct AtlasState {
    AtlasState(const FaceGrid& g, double r) : grid(g), radius(r) {}
    const FaceGrid& grid;                               // the original faces (islands, projections)
    double radius;                                      // closestFaceIn's first box
    std::vector<uint32_t> faceChart;                    // chart per original face (unassigned -> 0)
    std::vector<std::vector<uint32_t>> levelTriChart;   // per level: chart each triangle takes UVs from
    std::vector<std::vector<uint32_t>> vertexCharts;    // per vertex: the charts holding it
    std::map<Tri, uint32_t> islandOf;                   // level vertex triple -> island
    std::vector<std::vector<Vec2>> islandModel;         // island UVs, model units
    std::unordered_map<uint64_t, Projection> projections;  // (chart << 32 | vertex) -> closest chart point
    std::vector<std::vector<uint8_t>> projectedCount;   // per level triangle: corners not in its chart
};

// (2) The charts as local meshes with their simplification pairs and level triangles.
std::vector<LocalChart> localCharts(const TriMesh& mesh, const Multires& multires, const ChartResult& cr, const FaceGrid& grid,
                                    double radius) {
    std::vector<LocalChart> charts;
    extractCharts(mesh, cr, charts);
    gatherPairs(mesh, multires, charts);
    gatherLevelTriangles(mesh, cr, multires, grid, radius, charts);
    return charts;
}

template <class T>
void appendBytes(std::string& key, const T& x) {
    key.append(reinterpret_cast<const char*>(&x), sizeof(T));
}

// Everything solveChart reads of a chart, as bytes (field by field: no padding).
std::string solveKey(const LocalChart& c, double resolution) {
    std::string key;
    appendBytes(key, resolution);
    appendBytes(key, c.mesh.positions.size());
    for (const Vec3& p : c.mesh.positions) { appendBytes(key, p.x); appendBytes(key, p.y); appendBytes(key, p.z); }
    appendBytes(key, c.mesh.triangles.size());
    for (const Tri& t : c.mesh.triangles) for (uint32_t v : t) appendBytes(key, v);
    appendBytes(key, c.pairs.size());
    for (const ChartPair& p : c.pairs) {
        appendBytes(key, p.vertex);
        for (size_t k = 0; k < 3; ++k) { appendBytes(key, p.coarse[k]); appendBytes(key, p.bary[k]); }
        appendBytes(key, p.deviation);
    }
    appendBytes(key, c.mesh.levelTriangles.size());
    for (const ChartLevelTriangle& t : c.mesh.levelTriangles) {
        for (const ChartPoint& q : t.corner)
            for (size_t k = 0; k < 3; ++k) { appendBytes(key, q.vertex[k]); appendBytes(key, q.weight[k]); }
        appendBytes(key, t.area2);
        appendBytes(key, t.level);
    }
    return key;
}

}  // namespace

struct ChartSolveCache {
    struct Entry {
        std::vector<Vec2> uv;
        ChartReport report;
    };
    std::unordered_map<std::string, Entry> entries;  // by solveKey
};

std::shared_ptr<ChartSolveCache> makeChartSolveCache() { return std::make_shared<ChartSolveCache>(); }

namespace {

// (3) Tutte, Ceres and checks per chart. Charts are independent: solved on up to options.threads
// threads, largest first, results kept per chart and summed in chart order (identical for any
// thread count). A chart options.solveCache remembers takes the remembered result (looked up and
// stored outside the parallel loop). Progress runs to 0.9.
void solveCharts(std::vector<LocalChart>& charts, const ParameterizeOptions& options, ParameterizeResult& res) {
    const double resolution = (512.0 * 512.0) / (double(options.textureSize) * options.textureSize);
    res.chartReports.resize(charts.size());
    std::vector<size_t> bySize(charts.size());
    std::iota(bySize.begin(), bySize.end(), size_t(0));
    std::stable_sort(bySize.begin(), bySize.end(), [&](size_t a, size_t b) { return charts[a].faces.size() > charts[b].faces.size(); });
    ChartSolveCache* cache = options.solveCache.get();
    std::vector<std::string> keys(cache ? charts.size() : 0);
    std::vector<const ChartSolveCache::Entry*> known(charts.size(), nullptr);
    if (cache)
        for (size_t c = 0; c < charts.size(); ++c) {
            if (charts[c].faces.empty()) continue;
            keys[c] = solveKey(charts[c], resolution);
            auto it = cache->entries.find(keys[c]);
            if (it != cache->entries.end()) known[c] = &it->second;
        }
    std::atomic<size_t> solved{0};
    const std::thread::id caller = std::this_thread::get_id();
    parallelFor(charts.size(), options.threads, [&](size_t i) {
        size_t c = bySize[i];
        ChartReport& rep = res.chartReports[c];
        if (known[c]) {
            charts[c].uv = known[c]->uv;
            rep = known[c]->report;
        } else {
            rep.faces = uint32_t(charts[c].faces.size());
            rep.vertices = uint32_t(charts[c].vertices.size());
            rep.pairs = uint32_t(charts[c].pairs.size());
            if (!charts[c].faces.empty()) solveChart(charts[c], options, resolution, rep);
        }
        size_t done = ++solved;
        if (options.progress && std::this_thread::get_id() == caller) options.progress(0.9 * double(done) / double(charts.size()));
    });
    if (cache)
        for (size_t c = 0; c < charts.size(); ++c)
            if (!known[c] && !charts[c].faces.empty())
                cache->entries.emplace(std::move(keys[c]), ChartSolveCache::Entry{charts[c].uv, res.chartReports[c]});
    for (size_t c = 0; c < charts.size(); ++c) {
        const ChartReport& rep = res.chartReports[c];
        res.initialTotal = addEnergy(res.initialTotal, rep.initial);
        res.finalTotal = addEnergy(res.finalTotal, rep.final);
        res.flips += rep.flips;
        res.overlaps += rep.overlaps;
        res.levelFlips += rep.levelFlips;
    }
}

// (4) Stretch and area-ratio measures per chart and for the whole atlas (uniform density, so
// model-unit UVs compare). Returns the charts' total UV area (model units^2).
double measureCharts(const std::vector<LocalChart>& charts, ParameterizeResult& res) {
    Stretch all;
    double allL2 = 0, allG = 0;
    for (size_t c = 0; c < charts.size(); ++c) {
        Stretch s;
        double l2 = 0, g = 0;
        accumulateStretch(charts[c].mesh, charts[c].uv, s, l2, g);
        finishStretch(s, l2, g);
        ChartReport& rep = res.chartReports[c];
        rep.stretchL2 = s.l2;
        rep.stretchLinf = s.linf;
        rep.areaRatioStdDev = ratioStdDev(s.ratios, s.sum3D > 0 ? s.sumUV / s.sum3D : 0);
        accumulateStretch(charts[c].mesh, charts[c].uv, all, allL2, allG);
    }
    finishStretch(all, allL2, allG);
    res.stretchL2 = all.l2;
    res.stretchLinf = all.linf;
    double meanRatio = all.sum3D > 0 ? all.sumUV / all.sum3D : 0;
    res.areaRatioStdDev = ratioStdDev(all.ratios, meanRatio);
    for (double r : all.ratios) {
        int bin = std::clamp(int(r / meanRatio / 0.2), 0, 9);
        ++res.areaRatioHistogram[size_t(bin)];
    }
    return all.sumUV;
}

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
    return st;
}

// (5) Shelf-packs the charts and the islands made so far; sets the density and fill figures.
ShelfPackResult packCharts(const std::vector<LocalChart>& charts, const AtlasState& st, double uvArea,
                           const ParameterizeOptions& options, ParameterizeResult& res) {
    std::vector<const std::vector<Vec2>*> sets;
    double islandArea = 0;
    for (const LocalChart& c : charts) sets.push_back(&c.uv);
    for (const auto& m : st.islandModel) {
        sets.push_back(&m);
        islandArea += 0.5 * cross(m[1] - m[0], m[2] - m[0]);
    }
    ShelfPackOptions so;
    so.size = options.textureSize;
    so.gutter = options.gutter;
    ShelfPackResult atlas = shelfPack(sets, uvArea + islandArea, so);
    const double d = atlas.texelsPerUnit;
    const int size = options.textureSize;
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
        for (int k = 0; k < 3; ++k) {
            auto it = charts[size_t(c)].local.find(mesh.triangles[f][k]);
            uint32_t local = it != charts[size_t(c)].local.end() ? it->second : 0;
            res.cornerUV[f][size_t(k)] = atlas.atlasUV(size_t(c), charts[size_t(c)].uv[local]);
        }
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
                auto it = ch.local.find(v);
                if (it != ch.local.end()) {
                    out.uv[t][k] = atlas.atlasUV(c, ch.uv[it->second]);
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

// Crossing islands only while their smallest footprint (2 texels plus the gutter a side) fits in
// a quarter of the atlas; beyond that (thousands of tiny crossing triangles) they would crush the
// charts' density and float precision. Records the skipped count; returns whether they are made.
bool crossingIslandsFit(const Multires& multires, const AtlasState& st, const ParameterizeOptions& options, ParameterizeResult& res) {
    std::set<Tri> crossingTriples;
    for (size_t li = 0; li < multires.levels.size(); ++li)
        for (size_t t = 0; t < multires.levels[li].triangles.size(); ++t)
            if (st.projectedCount[li][t] > 0) crossingTriples.insert(multires.levels[li].triangles[t]);
    const double footprint = std::pow(2.0 + options.gutter, 2.0);
    const int size = options.textureSize;
    const bool fits = double(crossingTriples.size()) * footprint <= 0.25 * double(size) * double(size);
    res.crossingIslandsSkipped = fits ? 0 : crossingTriples.size();
    return fits;
}

// The faces an island's bake and deviation sample: exactly facesNearTriangle(candidates, triangle)
// with `candidates` the faces of charts `cs` (ascending ids, each chart's faces as charts[c].faces
// holds them), found without listing the charts' faces or scanning them all. The triangle's own
// face, when a candidate, bounds the centroid's distance to the candidates from above, so only
// candidates whose boxes lie within that bound's reach (a superset of facesNearTriangle's, which
// holds the closest face) are kept, looked up in the face grid; the ones within the true reach are
// the same faces in the same order. Later calls of facesNearTriangle on the result return it
// unchanged.
std::vector<uint32_t> islandFaces(const TriMesh& mesh, const std::vector<LocalChart>& charts, const std::vector<int32_t>& faceChart,
                                  const FaceGrid& grid, const std::vector<uint32_t>& cs, const Tri& v, uint32_t ownFace) {
    const std::array<Vec3, 3> tri{mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]]};
    // A candidate: a face with a chart among cs that is not index-degenerate (charts hold no such
    // face, and the grid leaves them out).
    auto candidate = [&](uint32_t f) {
        return faceChart[f] >= 0 && std::binary_search(cs.begin(), cs.end(), uint32_t(faceChart[f])) &&
               !degenerateIndices(mesh.triangles[f]);
    };
    if (!candidate(ownFace)) {
        std::vector<uint32_t> candidates;
        for (uint32_t c : cs) candidates.insert(candidates.end(), charts[c].faces.begin(), charts[c].faces.end());
        std::sort(candidates.begin(), candidates.end());
        return facesNearTriangle(mesh, candidates, tri);
    }
    const Vec3 c = (tri[0] + tri[1] + tri[2]) * (1.0 / 3);
    const Tri& o = mesh.triangles[ownFace];
    const auto b = closestOnTriangle(c, mesh.positions[o[0]], mesh.positions[o[1]], mesh.positions[o[2]]);
    const Vec3 q = mesh.positions[o[0]] * b[0] + mesh.positions[o[1]] * b[1] + mesh.positions[o[2]] * b[2];
    double r = 0;
    for (const Vec3& p : tri) r = std::max(r, length(p - c));
    // Twice facesNearTriangle's margin: the bound's reach is never below the true one.
    const double reach = (length(q - c) + 2 * r) * (1 + 2e-9) + 2e-12;
    // The grid box is padded past the reach so rounding of its corners never drops a face the
    // exact box-distance test keeps.
    const double pad = reach * (1 + 1e-6) + 1e-9 * (1 + std::abs(c.x) + std::abs(c.y) + std::abs(c.z));
    std::vector<uint32_t> near;
    auto keep = [&](uint32_t f) {
        if (candidate(f) && boxDistance2(faceBox(mesh, f), c) <= reach * reach) near.push_back(f);
    };
    // A face within the reach has its box inside the padded box: the grid's faces there, or the
    // charts' own faces when they are fewer than the grid cells' entries (a coarse level's large
    // triangle over small charts), give the same faces.
    const Vec3 lo = c - Vec3{pad, pad, pad}, hi = c + Vec3{pad, pad, pad};
    size_t chartFaces = 0;
    for (uint32_t k : cs) chartFaces += charts[k].faces.size();
    if (chartFaces < grid.entriesIn(lo, hi)) {
        for (uint32_t k : cs)
            for (uint32_t f : charts[k].faces) keep(f);
        std::sort(near.begin(), near.end());
    } else {
        for (uint32_t f : grid.facesIn(lo, hi)) keep(f);
    }
    return facesNearTriangle(mesh, near, tri);
}

// Checks every level in the atlas as the tool does (float UVs, overlap tolerance 1e-7) and gives
// an island to each level triangle that is flipped, crossing (with `crossing`), or the one of an
// overlapping pair with more projected corners (it straddles a chart cut), else the smaller.
// Islands are laid out at density d (at least 2 texels a side). Returns the islands added.
size_t addFoldIslands(const TriMesh& mesh, const Multires& multires, const std::vector<LocalChart>& charts, bool crossing,
                      double d, AtlasState& st, ParameterizeResult& res) {
    size_t added = 0;
    for (size_t li = 0; li < multires.levels.size(); ++li) {
        const Level& L = multires.levels[li];
        std::vector<std::array<Vec2, 3>> tris;
        std::vector<uint32_t> which;
        for (size_t t = 0; t < L.triangles.size(); ++t) {
            const Tri& v = L.triangles[t];
            if (degenerateIndices(v) || st.islandOf.count(v)) continue;  // islands never overlap a chart
            tris.push_back(res.levels[li].uv[t]);
            which.push_back(uint32_t(t));
        }
        param_detail::UVFolds folds = param_detail::findUVFolds(tris, 1e-7);
        std::vector<char> pick(tris.size(), 0);
        for (size_t i = 0; i < tris.size(); ++i)
            pick[i] = folds.flipped[i] || (crossing && st.projectedCount[li][which[i]] > 0);
        auto area3 = [&](uint32_t t) {
            const Tri& v = L.triangles[t];
            return length(cross(mesh.positions[v[1]] - mesh.positions[v[0]], mesh.positions[v[2]] - mesh.positions[v[0]]));
        };
        for (const auto& [i, j] : folds.overlapping) {
            if (pick[i] || pick[j]) continue;
            uint8_t pi = st.projectedCount[li][which[i]], pjc = st.projectedCount[li][which[j]];
            bool takeI = pi != pjc ? pi > pjc : area3(which[i]) < area3(which[j]);
            pick[takeI ? i : j] = 1;
        }
        for (size_t i = 0; i < tris.size(); ++i) {
            if (!pick[i]) continue;
            const uint32_t t = which[i];
            const Tri& v = L.triangles[t];
            if (st.islandOf.count(v)) continue;
            st.islandOf.emplace(v, uint32_t(st.islandModel.size()));
            st.islandModel.push_back(islandLayout(mesh.positions[v[0]], mesh.positions[v[1]], mesh.positions[v[2]], 2.0 / d));
            // The island's bake samples the charts of its face and of its corners.
            LevelIsland isl;
            isl.vertices = v;
            isl.level = uint32_t(li + 1);
            std::vector<uint32_t> cs{st.faceChart[L.faces[t]]};
            for (uint32_t vv : v) cs.insert(cs.end(), st.vertexCharts[vv].begin(), st.vertexCharts[vv].end());
            std::sort(cs.begin(), cs.end());
            cs.erase(std::unique(cs.begin(), cs.end()), cs.end());
            isl.faces = islandFaces(mesh, charts, res.charts.faceChart, st.grid, cs, v, L.faces[t]);
            res.islands.push_back(std::move(isl));
            ++added;
        }
    }
    return added;
}

// (5)-(7) with the island fallback: pack, write corner and level UVs; a level triangle still
// folded in the packed atlas (or crossing a chart boundary) gets its own island, and as islands
// take atlas space the atlas is packed again and every level re-checked until none folds (at
// most kMaxRounds repacks).
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
        if (addFoldIslands(mesh, multires, charts, crossing, atlas.texelsPerUnit, st, res) == 0) break;
    }
}

}  // namespace

ParameterizeResult parameterize(const TriMesh& mesh, const Multires& multires, const ParameterizeOptions& options) {
    auto t0 = Clock::now();
    ParameterizeResult res;
    if (mesh.triangleCount() == 0) throw Impossible("the mesh has no triangles");
    if (!(options.textureSize >= 16)) throw InvalidInput("texture size must be >= 16");

    // (1) Charts from the coarsest level's base regions (every face its own region without levels).
    static const std::vector<uint32_t> kNoRegions;
    const std::vector<uint32_t>& regions = multires.levels.empty() ? kNoRegions : multires.levels.back().faceRegion;
    res.charts = buildCharts(mesh, regions, options.charts);

    // The original faces by place, for closest-point and near-face queries (not held while the
    // charts are solved, the run's peak); the typical face size is where those queries' search
    // boxes start.
    const double radius = typicalFaceSize(mesh);
    std::vector<LocalChart> charts = localCharts(mesh, multires, res.charts, FaceGrid(mesh), radius);  // (2)
    solveCharts(charts, options, res);                                         // (3)
    splitFailedCharts(mesh, options, charts, res);                             // (3b)
    double chartUvArea = measureCharts(charts, res);                           // (4)
    for (LocalChart& c : charts) alignChart(c.uv);
    // (5)-(7), then the LOD0 fallback: original faces still folded in the packed atlas (a chart
    // map that is not injective, corners that fold once rounded to float) leave their charts as
    // single-face charts of at least 2 texels a side, and the atlas is laid out again.
    constexpr int kMaxCarvePasses = 4;
    const FaceGrid grid(mesh);
    for (int pass = 0;; ++pass) {
        layoutAtlas(mesh, multires, charts, chartUvArea, grid, radius, options, res);
        res.floatRepairs = nudgeRoundedSliverCorners(mesh, res.charts.faceChart, res.cornerUV);
        const std::vector<uint32_t> folded = foldedAtlasFaces(mesh, res);
        if (folded.empty() || pass == kMaxCarvePasses || res.texelsPerUnit <= 0) break;
        const size_t before = res.carvedFaces;
        chartUvArea += carveFaces(mesh, folded, (pass + 2.0) / res.texelsPerUnit, charts, res);
        if (pass == 0 || res.carvedFaces > before)
            res.warnings.push_back(std::to_string(folded.size()) + " original faces folded in the atlas (" +
                                   std::to_string(res.flips) + " flipped, " + std::to_string(res.overlaps) +
                                   " overlapping); each now has a chart of its own");
    }
    if (options.progress) options.progress(1.0);
    res.seconds = secondsSince(t0);
    return res;
}

}  // namespace lodbake
