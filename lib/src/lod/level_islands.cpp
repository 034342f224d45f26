// A projected level's own charts (level_islands.h): islands unfolded onto neighbouring charts.
#include "lod/level_islands.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <unordered_map>

namespace lodbake::lod_detail {
namespace {

using UvTri = std::array<Vec2, 3>;

double lengthOf(Vec2 v) { return std::sqrt(v.x * v.x + v.y * v.y); }

// True when the interiors of two UV triangles overlap by more than `tol` (separating axis test
// over the six edge normals; triangles that only touch along an edge or at a corner are apart).
bool overlaps(const UvTri& a, const UvTri& b, double tol) {
    for (const UvTri* t : {&a, &b})
        for (size_t i = 0; i < 3; ++i) {
            Vec2 e = (*t)[(i + 1) % 3] - (*t)[i];
            double len = lengthOf(e);
            if (!(len > 0)) continue;
            Vec2 n{-e.y / len, e.x / len};
            double aMin = 1e300, aMax = -1e300, bMin = 1e300, bMax = -1e300;
            for (const Vec2& p : a) { double d = dot(p, n); aMin = std::min(aMin, d); aMax = std::max(aMax, d); }
            for (const Vec2& p : b) { double d = dot(p, n); bMin = std::min(bMin, d); bMax = std::max(bMax, d); }
            if (aMax <= bMin + tol || bMax <= aMin + tol) return false;
        }
    return true;
}

uint64_t pairKey(uint32_t a, uint32_t b) { return a < b ? (uint64_t(a) << 32) | b : (uint64_t(b) << 32) | a; }

// The UV triangles of every chart, bucketed by a uniform grid for the overlap tests. Not
// core/grid2d.h: the triangles arrive while they are unfolded (no box is known in advance), so
// the cells are hashed, unbounded and kept per chart.
class ChartGrid {
public:
    explicit ChartGrid(double cell) : cell_(cell) {}

    void add(uint32_t chart, uint32_t triangle, const UvTri& t) {
        forCells(chart, t, [&](uint64_t key) { cells_[key].push_back(triangle); });
    }

    // True when `t` overlaps a triangle of `chart` (the UVs of triangle i are uv[i]).
    bool overlapsChart(uint32_t chart, const UvTri& t, const std::vector<UvTri>& uv, double tol) const {
        bool hit = false;
        forCells(chart, t, [&](uint64_t key) {
            if (hit) return;
            auto it = cells_.find(key);
            if (it == cells_.end()) return;
            for (uint32_t other : it->second)
                if (overlaps(t, uv[other], tol)) { hit = true; return; }
        });
        return hit;
    }

private:
    template <class F>
    void forCells(uint32_t chart, const UvTri& t, F&& f) const {
        double lox = std::min({t[0].x, t[1].x, t[2].x}), hix = std::max({t[0].x, t[1].x, t[2].x});
        double loy = std::min({t[0].y, t[1].y, t[2].y}), hiy = std::max({t[0].y, t[1].y, t[2].y});
        const int64_t x0 = int64_t(std::floor(lox / cell_)), x1 = int64_t(std::floor(hix / cell_));
        const int64_t y0 = int64_t(std::floor(loy / cell_)), y1 = int64_t(std::floor(hiy / cell_));
        for (int64_t x = x0; x <= x1; ++x)
            for (int64_t y = y0; y <= y1; ++y)
                f((uint64_t(chart) << 40) ^ (uint64_t(x & 0xFFFFF) << 20) ^ uint64_t(y & 0xFFFFF));
    }

    double cell_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

// A cell about twice the median longest UV edge: most triangles touch a few cells.
double gridCell(const std::vector<UvTri>& uv) {
    std::vector<double> edges;
    edges.reserve(uv.size());
    for (const UvTri& t : uv) {
        double e = std::max({lengthOf(t[1] - t[0]), lengthOf(t[2] - t[1]), lengthOf(t[0] - t[2])});
        if (e > 0 && std::isfinite(e)) edges.push_back(e);
    }
    if (edges.empty()) return 1;
    std::nth_element(edges.begin(), edges.begin() + edges.size() / 2, edges.end());
    return 2 * edges[edges.size() / 2];
}

class Absorber {
public:
    Absorber(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles, const std::vector<uint32_t>& chart,
             const std::vector<UvTri>& uv, uint32_t firstIsland, double uvPerUnit, const AbsorbOptions& options)
        : positions_(positions), triangles_(triangles), firstIsland_(firstIsland), uvPerUnit_(uvPerUnit), options_(options),
          chart_(chart), uv_(uv), assigned_(triangles.size(), 0), grid_(gridCell(uv)) {
        // Each edge's triangles in triangle order (corner order within one): the half-edges sorted
        // by (edge, half-edge id), each half-edge pointing at its edge's run.
        const size_t halfEdges = 3 * triangles_.size();
        std::vector<std::pair<uint64_t, uint32_t>> byEdge(halfEdges);
        for (uint32_t t = 0; t < triangles_.size(); ++t)
            for (size_t j = 0; j < 3; ++j) byEdge[3 * t + j] = {pairKey(triangles_[t][j], triangles_[t][(j + 1) % 3]), uint32_t(3 * t + j)};
        std::sort(byEdge.begin(), byEdge.end());
        edgeTriangles_.resize(halfEdges);
        edgeRun_.resize(halfEdges);
        for (size_t i = 0, j = 0; i < halfEdges; i = j) {
            while (j < halfEdges && byEdge[j].first == byEdge[i].first) ++j;
            for (size_t k = i; k < j; ++k) {
                edgeTriangles_[k] = byEdge[k].second / 3;
                edgeRun_[byEdge[k].second] = {uint32_t(i), uint32_t(j)};
            }
        }
        vertexUv_.reserve(halfEdges);
        nextChart_ = firstIsland_;
        for (uint32_t c : chart_) nextChart_ = std::max(nextChart_, c + 1);
        for (uint32_t t = 0; t < triangles_.size(); ++t)
            if (chart_[t] < firstIsland_) assign(t);
    }

    void run(LevelChartSet& out) {
        std::deque<uint32_t> queue;
        for (uint32_t t = 0; t < triangles_.size(); ++t)
            if (!assigned_[t]) queue.push_back(t);
        drain(queue, out.absorbed);
        for (uint32_t seed = 0; seed < triangles_.size(); ++seed) {
            if (assigned_[seed]) continue;
            chart_[seed] = nextChart_++;
            assign(seed);
            pushNeighbours(seed, queue);
            drain(queue, out.grouped);
        }
        out.chart = std::move(chart_);
        out.uv = std::move(uv_);
    }

private:
    void assign(uint32_t t) {
        assigned_[t] = 1;
        grid_.add(chart_[t], t, uv_[t]);
        for (size_t j = 0; j < 3; ++j) vertexUv_.emplace((uint64_t(chart_[t]) << 32) | triangles_[t][j], uv_[t][j]);
    }

    void pushNeighbours(uint32_t t, std::deque<uint32_t>& queue) const {
        for (size_t j = 0; j < 3; ++j) {
            const auto [begin, end] = edgeRun_[3 * size_t(t) + j];
            for (uint32_t k = begin; k < end; ++k)
                if (!assigned_[edgeTriangles_[k]]) queue.push_back(edgeTriangles_[k]);
        }
    }

    // Unfolds every queued triangle onto the first adjacent chart that has room for it; each one
    // placed queues its unplaced neighbours.
    void drain(std::deque<uint32_t>& queue, size_t& placed) {
        while (!queue.empty()) {
            const uint32_t t = queue.front();
            queue.pop_front();
            if (assigned_[t] || !unfold(t)) continue;
            ++placed;
            assign(t);
            pushNeighbours(t, queue);
        }
    }

    // Places triangle t on the chart of an assigned neighbour across one of its edges.
    bool unfold(uint32_t t) {
        for (size_t j = 0; j < 3; ++j) {
            const size_t ia = j, ib = (j + 1) % 3, ic = (j + 2) % 3;
            const auto [begin, end] = edgeRun_[3 * size_t(t) + j];
            for (uint32_t k = begin; k < end; ++k) {
                const uint32_t s = edgeTriangles_[k];
                if (s == t || !assigned_[s]) continue;
                UvTri placed;
                if (place(t, s, ia, ib, ic, placed)) {
                    chart_[t] = chart_[s];
                    uv_[t] = placed;
                    return true;
                }
            }
        }
        return false;
    }

    bool place(uint32_t t, uint32_t s, size_t ia, size_t ib, size_t ic, UvTri& placed) const {
        const Tri& tri = triangles_[t];
        const Tri& st = triangles_[s];
        auto cornerOf = [&](uint32_t v) { return st[0] == v ? 0 : st[1] == v ? 1 : 2; };
        const Vec2 ua = uv_[s][size_t(cornerOf(tri[ia]))], ub = uv_[s][size_t(cornerOf(tri[ib]))];
        const Vec3 A = positions_[tri[ia]], B = positions_[tri[ib]], C = positions_[tri[ic]];
        const Vec3 e = B - A;
        const double l2 = dot(e, e);
        const Vec2 d = ub - ua;
        const double dl = lengthOf(d);
        if (!(l2 > 0) || !(dl > 0)) return false;
        const double scale = dl / std::sqrt(l2);
        if (scale > options_.maxScaleRatio * uvPerUnit_ || scale * options_.maxScaleRatio < uvPerUnit_) return false;
        const double x = dot(C - A, e) / l2, h = length(cross(e, C - A)) / l2;
        if (!(h > 0)) return false;
        // The neighbour's orientation is the chart's: the unfolded triangle must turn the same way.
        const double want = signedArea(uv_[s][0], uv_[s][1], uv_[s][2]);
        if (!(std::abs(want) > 0)) return false;
        const Vec2 perp{-d.y, d.x};
        Vec2 p = ua + d * x + perp * h;
        placed[ia] = ua;
        placed[ib] = ub;
        placed[ic] = p;
        if (signedArea(placed[0], placed[1], placed[2]) * want < 0) placed[ic] = p = ua + d * x - perp * h;
        // Share the chart's UV of the third corner when it is about where the unfolding puts it:
        // the texture then stays continuous across both of its other edges.
        auto known = vertexUv_.find((uint64_t(chart_[s]) << 32) | tri[ic]);
        if (known != vertexUv_.end() && lengthOf(known->second - p) <= 0.25 * dl) {
            UvTri shared = placed;
            shared[ic] = known->second;
            if (signedArea(shared[0], shared[1], shared[2]) * want > 0) placed = shared;
        }
        if (!(signedArea(placed[0], placed[1], placed[2]) * want > 0)) return false;
        return !grid_.overlapsChart(chart_[s], placed, uv_, 1e-7 * dl);
    }

    const std::vector<Vec3>& positions_;
    const std::vector<Tri>& triangles_;
    const uint32_t firstIsland_;
    const double uvPerUnit_;
    const AbsorbOptions options_;
    std::vector<uint32_t> chart_;
    std::vector<UvTri> uv_;
    std::vector<char> assigned_;
    ChartGrid grid_;
    std::vector<uint32_t> edgeTriangles_;                   // every edge's triangles, edge by edge
    std::vector<std::pair<uint32_t, uint32_t>> edgeRun_;    // per half-edge (3 t + j), its edge's run there
    std::unordered_map<uint64_t, Vec2> vertexUv_;  // (chart << 32 | vertex) -> its first UV there
    uint32_t nextChart_ = 0;
};

}  // namespace

LevelChartSet absorbIslands(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles,
                            const std::vector<uint32_t>& chart, const std::vector<UvTri>& uv, uint32_t firstIsland,
                            double uvPerUnit, const AbsorbOptions& options) {
    LevelChartSet out;
    Absorber(positions, triangles, chart, uv, firstIsland, uvPerUnit, options).run(out);
    // Dense chart ids in order of first use.
    std::unordered_map<uint32_t, uint32_t> dense;
    for (size_t t = 0; t < out.chart.size(); ++t) {
        auto [it, inserted] = dense.emplace(out.chart[t], uint32_t(out.uvArea.size()));
        if (inserted) {
            out.uvArea.push_back(0);
            out.source.push_back(out.chart[t]);
        }
        out.chart[t] = it->second;
        out.uvArea[it->second] += triangleArea(out.uv[t][0], out.uv[t][1], out.uv[t][2]);
    }
    return out;
}

}  // namespace lodbake::lod_detail
