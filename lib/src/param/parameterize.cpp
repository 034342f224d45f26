// parameterize: charts -> Tutte -> Ceres (E = beta E_pixel + (1 - beta) E_poly) -> checks and
// fallbacks -> shelf-packed atlas -> per-corner UVs (thesis 3.3; DESIGN.md).
//
// Pipeline, in execution order:
//   gatherCharts        charts from the coarsest level's base regions (charts.cpp)
//   extractChart        each chart as a local mesh, its simplification pairs (all levels)
//   solveChart          Tutte map, Ceres, injectivity check; fallback beta = 1, then Tutte
//   measureChart        stretch (Sander et al. 2001), UV/3D area ratios
//   packCharts          uniform texel density, shelf packing with gutters, density shrunk until it fits
//   writeCornerUVs      atlas UV per original face corner (glTF convention)
#include "lodbake/param/parameterize.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <thread>
#include <unordered_map>

#include "lodbake/core/errors.h"
#include "lodbake/core/closest_point.h"
#include "lodbake/core/parallel.h"

namespace lodbake {
namespace {

bool degenerateIndices(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

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

// Level triangles of every level, per chart of their face (deduplicated across levels), with
// corners that are not chart vertices projected onto the chart's surface (as applyAtlas does).
void gatherLevelTriangles(const TriMesh& mesh, const ChartResult& cr, const Multires& mr, std::vector<LocalChart>& charts) {
    std::vector<std::set<std::array<uint32_t, 3>>> seen(charts.size());
    std::vector<std::map<uint32_t, ChartPoint>> projected(charts.size());
    auto project = [&](LocalChart& ch, size_t c, uint32_t v) {
        auto it = projected[c].find(v);
        if (it != projected[c].end()) return it->second;
        const Vec3 p = mesh.positions[v];
        double best = 1e300;
        ChartPoint cp;
        for (size_t i = 0; i < ch.faces.size(); ++i) {
            const Tri& t = mesh.triangles[ch.faces[i]];
            auto b = closestOnTriangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
            Vec3 q = mesh.positions[t[0]] * b[0] + mesh.positions[t[1]] * b[1] + mesh.positions[t[2]] * b[2];
            double d = length2(q - p);
            if (d < best) {
                best = d;
                cp.vertex = ch.mesh.triangles[i];
                cp.weight = b;
            }
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
            if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2] || L.faces[t] >= cr.faceChart.size()) continue;
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
    auto t0 = std::chrono::steady_clock::now();
    std::vector<Vec2> tutte = tutteEmbedding(c.mesh);
    ChartSolveOptions so;
    so.energy.alpha = o.alpha;
    so.energy.beta = o.beta;
    so.energy.resolution = resolution;
    so.maxIterations = o.maxIterations;
    rep.tutte = chartEnergy(c.mesh, c.pairs, tutte, so.energy);
    auto valid = [&](const std::vector<Vec2>& uv) {
        return countFlips(c.mesh, uv) == 0 && countOverlaps(c.mesh, uv) == 0;
    };
    // Candidates in order of preference; the first injective one without folded level triangles
    // wins, else the injective one with the fewest (the tool reports and refuses those). Tutte's
    // convex boundary keeps every level's boundary simple, so it is the fallback when the
    // optimised maps fold a level.
    c.uv = tutte;
    rep.method = "tutte";
    size_t bestFolds = levelFolds(c.mesh, tutte);
    auto consider = [&](const ChartSolveResult& r, const char* method) {
        if (!r.improved || !valid(r.uv)) return;
        size_t folds = levelFolds(c.mesh, r.uv);
        if (rep.method != "tutte" && folds >= bestFolds) return;
        if (rep.method == "tutte" && folds > bestFolds) return;
        c.uv = r.uv;
        rep.method = method;
        bestFolds = folds;
    };
    if (o.maxIterations > 0) {
        ChartSolveResult r = optimizeChartUV(c.mesh, c.pairs, tutte, so);
        rep.iterations = r.iterations;
        consider(r, "ceres");
        if (o.beta < 1 && (rep.method == "tutte" || bestFolds > 0)) {
            ChartSolveOptions s1 = so;
            s1.energy.beta = 1;
            ChartSolveResult r1 = optimizeChartUV(c.mesh, c.pairs, tutte, s1);
            rep.iterations += r1.iterations;
            consider(r1, "ceres-beta1");
        }
    }
    rep.levelFlips = countLevelFlips(c.mesh, c.uv);
    rep.final = chartEnergy(c.mesh, c.pairs, c.uv, so.energy);
    rep.flips = countFlips(c.mesh, c.uv);
    rep.overlaps = countOverlaps(c.mesh, c.uv);
    rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
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

struct Placement {
    double x = 0, y = 0;  // texel offset of the chart's bbox min
    Vec2 min{};           // chart bbox min in model units
};

// Shelf packing at density d; returns false when the charts do not fit.
bool shelfPack(const std::vector<LocalChart>& charts, double d, int size, int gutter, std::vector<Placement>& out) {
    struct Item {
        uint32_t id;
        int w, h;
        Vec2 min;
    };
    std::vector<Item> items;
    for (uint32_t i = 0; i < charts.size(); ++i) {
        Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
        for (Vec2 p : charts[i].uv) {
            lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
            hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
        }
        if (charts[i].uv.empty()) lo = hi = {0, 0};
        items.push_back({i, int(std::ceil((hi.x - lo.x) * d)) + 1, int(std::ceil((hi.y - lo.y) * d)) + 1, lo});
    }
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.h != b.h ? a.h > b.h : a.id < b.id; });
    out.assign(charts.size(), {});
    int x = gutter, y = gutter, shelf = 0;
    for (const Item& it : items) {
        if (it.w + 2 * gutter > size) return false;
        if (x + it.w + gutter > size) {
            x = gutter;
            y += shelf + gutter;
            shelf = 0;
        }
        if (y + it.h + gutter > size) return false;
        out[it.id] = {double(x), double(y), it.min};
        x += it.w + gutter;
        shelf = std::max(shelf, it.h);
    }
    return true;
}

}  // namespace

ParameterizeResult parameterize(const TriMesh& mesh, const Multires& multires, const ParameterizeOptions& options) {
    auto t0 = std::chrono::steady_clock::now();
    ParameterizeResult res;
    const size_t nf = mesh.triangleCount();
    if (nf == 0) throw Impossible("the mesh has no triangles");
    if (!(options.textureSize >= 16)) throw InvalidInput("texture size must be >= 16");

    // (1) Charts from the coarsest level's base regions.
    static const std::vector<uint32_t> kNoRegions;
    const std::vector<uint32_t>& regions = multires.levels.empty() ? kNoRegions : multires.levels.back().faceRegion;
    res.charts = buildCharts(mesh, regions, options.charts);

    // (2) Local chart meshes and their pairs.
    std::vector<LocalChart> charts;
    extractCharts(mesh, res.charts, charts);
    gatherPairs(mesh, multires, charts);
    gatherLevelTriangles(mesh, res.charts, multires, charts);

    // (3) Per chart: Tutte, Ceres, checks (fixed order, deterministic).
    const double resolution = (512.0 * 512.0) / (double(options.textureSize) * options.textureSize);
    // Charts are independent: solved on up to options.threads threads, largest first, results
    // kept per chart and summed in chart order (identical for any thread count).
    res.chartReports.resize(charts.size());
    std::vector<size_t> bySize(charts.size());
    std::iota(bySize.begin(), bySize.end(), size_t(0));
    std::stable_sort(bySize.begin(), bySize.end(), [&](size_t a, size_t b) { return charts[a].faces.size() > charts[b].faces.size(); });
    std::atomic<size_t> solved{0};
    const std::thread::id caller = std::this_thread::get_id();
    parallelFor(charts.size(), options.threads, [&](size_t i) {
        size_t c = bySize[i];
        ChartReport& rep = res.chartReports[c];
        rep.faces = uint32_t(charts[c].faces.size());
        rep.vertices = uint32_t(charts[c].vertices.size());
        rep.pairs = uint32_t(charts[c].pairs.size());
        if (!charts[c].faces.empty()) solveChart(charts[c], options, resolution, rep);
        size_t done = ++solved;
        if (options.progress && std::this_thread::get_id() == caller) options.progress(0.9 * double(done) / double(charts.size()));
    });
    for (size_t c = 0; c < charts.size(); ++c) {
        const ChartReport& rep = res.chartReports[c];
        res.tutteTotal = addEnergy(res.tutteTotal, rep.tutte);
        res.finalTotal = addEnergy(res.finalTotal, rep.final);
        res.flips += rep.flips;
        res.overlaps += rep.overlaps;
        res.levelFlips += rep.levelFlips;
    }

    // (4) Measures: per chart and whole atlas (uniform density, so model-unit UVs compare).
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

    // (5) Packing: uniform density, shrunk until everything fits.
    for (LocalChart& c : charts) alignChart(c.uv);
    const int size = options.textureSize;
    double uvArea = all.sumUV > 0 ? all.sumUV : 1;
    double d = std::sqrt(0.7 * double(size) * size / uvArea);
    std::vector<Placement> place;
    int attempts = 0;
    while (!shelfPack(charts, d, size, options.gutter, place)) {
        d *= 0.95;
        if (++attempts > 400) throw Impossible("charts do not fit into a " + std::to_string(size) + " texture");
    }
    res.texelsPerUnit = d;
    res.atlasFill = uvArea * d * d / (double(size) * size);

    // (6) Corner UVs: chart-local map -> texels -> glTF [0,1] with v down (image rows from the top).
    res.cornerUV.assign(nf, {});
    auto atlas = [&](size_t c, uint32_t local) {
        Vec2 p = charts[c].uv[local];
        double X = place[c].x + (p.x - place[c].min.x) * d + 0.5;
        double Y = place[c].y + (p.y - place[c].min.y) * d + 0.5;
        return Vec2{X / size, 1.0 - Y / size};
    };
    for (uint32_t f = 0; f < nf; ++f) {
        int32_t c = res.charts.faceChart[f];
        if (c < 0 || charts[size_t(c)].uv.empty()) continue;
        for (int k = 0; k < 3; ++k) {
            auto it = charts[size_t(c)].local.find(mesh.triangles[f][k]);
            res.cornerUV[f][size_t(k)] = atlas(size_t(c), it != charts[size_t(c)].local.end() ? it->second : 0);
        }
    }
    if (options.progress) options.progress(1.0);
    res.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return res;
}

}  // namespace lodbake
