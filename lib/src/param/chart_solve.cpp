// Chart solves (parameterize step 3) and the solve cache keyed by a chart's bytes (chart_solve.h).
#include "param/chart_solve.h"

#include <algorithm>
#include <atomic>
#include <map>
#include <numeric>
#include <string>
#include <thread>
#include <unordered_map>

#include "lodbake/core/errors.h"
#include "lodbake/core/free_pages.h"
#include "lodbake/core/parallel.h"
#include "lodbake/core/timing.h"
#include "param/solve_schedule.h"

namespace lodbake {
namespace {

using param_detail::LocalChart;

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

namespace param_detail {

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
    // What a chart's solve holds at its peak: an LSCM-only chart its factorisation, about in
    // proportion to its vertices; a chart the Ceres solve refines (or a remembered one) little.
    std::vector<size_t> lscmWeight(charts.size(), 0);
    for (size_t c = 0; c < charts.size(); ++c)
        if (!known[c] && charts[c].vertices.size() > kKeepLscmAboveVertices) lscmWeight[c] = charts[c].vertices.size();
    std::atomic<size_t> solved{0};
    const std::thread::id caller = std::this_thread::get_id();
    runWithinBudget(bySize, lscmWeight, kLscmVerticesTogether, options.threads, [&](size_t c) {
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
        if (lscmWeight[c] > 0) returnFreedPages();
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

}  // namespace param_detail
}  // namespace lodbake
