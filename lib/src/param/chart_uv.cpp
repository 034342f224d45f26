// Chart UV checks and the energy E (DESIGN.md "The energy parameterize minimises"), evaluated
// without Ceres so reports and tests need no solver. The minimiser is in ceres_energy.cpp and
// uses the same terms (chart_energy_terms.h).
#include <algorithm>
#include <cmath>

#include "lodbake/core/adjacency.h"
#include "lodbake/core/key_set.h"
#include "lodbake/param/chart_uv.h"
#include "param/chart_energy_terms.h"

namespace lodbake {
namespace {

double orient(Vec2 a, Vec2 b, Vec2 c) { return cross(b - a, c - a); }

bool segmentsCross(Vec2 p1, Vec2 p2, Vec2 q1, Vec2 q2) {
    double d1 = orient(q1, q2, p1), d2 = orient(q1, q2, p2);
    double d3 = orient(p1, p2, q1), d4 = orient(p1, p2, q2);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
    return false;
}

}  // namespace

namespace param_detail {

EnergyTerms buildEnergyTerms(const ChartMesh& chart, const std::vector<ChartPair>& pairs,
                             const ChartEnergyOptions& o) {
    EnergyTerms t;
    double area = 0, meanA2 = 0, meanL2 = 0;
    KeySet seen(chart.triangles.size() * 3 / 2);
    for (const Tri& tri : chart.triangles) {
        const Vec3 &a = chart.positions[tri[0]], &b = chart.positions[tri[1]], &c = chart.positions[tri[2]];
        double a2 = length(cross(b - a, c - a));
        area += a2 / 2;
        meanA2 += a2;
        for (int k = 0; k < 3; ++k) {
            uint32_t i = tri[k], j = tri[(k + 1) % 3];
            if (!seen.insert(edgeKey(i, j))) continue;
            double l2 = length2(chart.positions[i] - chart.positions[j]);
            t.edges.push_back({i, j, l2});
            meanL2 += l2;
        }
        t.tris.push_back({tri, a2});
    }
    t.area3D = area;
    meanA2 = chart.triangles.empty() ? 1 : meanA2 / double(chart.triangles.size());
    meanL2 = t.edges.empty() ? 1 : meanL2 / double(t.edges.size());
    for (auto& e : t.edges) e.l2 = std::max(e.l2, 1e-3 * meanL2);
    for (auto& tr : t.tris) tr.a2 = std::max(tr.a2, 1e-3 * meanA2);
    // Weights so that E = sum of squared residuals.
    t.edgeWeight = o.resolution * o.beta * o.alpha;
    t.areaWeight = o.resolution * o.beta * (1 - o.alpha);
    t.polyWeight = o.resolution * (1 - o.beta);
    double floor = o.deviationFloor * std::sqrt(std::max(area, 1e-300));
    t.pairs.reserve(pairs.size());
    for (const ChartPair& p : pairs) t.pairs.push_back({p, std::max(p.deviation, floor)});
    return t;
}

}  // namespace param_detail

ChartEnergy chartEnergy(const ChartMesh& chart, const std::vector<ChartPair>& pairs, const std::vector<Vec2>& uv,
                        const ChartEnergyOptions& options) {
    param_detail::EnergyTerms t = param_detail::buildEnergyTerms(chart, pairs, options);
    ChartEnergy e;
    for (const auto& ed : t.edges) {
        Vec2 d = uv[ed.i] - uv[ed.j];
        double r = (dot(d, d) - ed.l2) / ed.l2;
        e.edge += r * r;
    }
    for (const auto& tr : t.tris) {
        double det = cross(uv[tr.v[1]] - uv[tr.v[0]], uv[tr.v[2]] - uv[tr.v[0]]);
        double r = (det - tr.a2) / tr.a2;
        e.area += r * r;
    }
    double poly = 0;
    for (const auto& p : t.pairs) {
        Vec2 q = uv[p.pair.vertex];
        for (int k = 0; k < 3; ++k) q = q - uv[p.pair.coarse[k]] * p.pair.bary[k];
        poly += dot(q, q) / (p.dev * p.dev);
    }
    e.pixel = options.resolution * (options.alpha * e.edge + (1 - options.alpha) * e.area);
    e.poly = options.resolution * poly;
    e.E = options.beta * e.pixel + (1 - options.beta) * e.poly;
    return e;
}

size_t countFlips(const ChartMesh& chart, const std::vector<Vec2>& uv) {
    size_t n = 0;
    for (const Tri& t : chart.triangles)
        if (!(cross(uv[t[1]] - uv[t[0]], uv[t[2]] - uv[t[0]]) > 0)) ++n;
    return n;
}

Vec2 chartPointUV(const ChartPoint& p, const std::vector<Vec2>& uv) {
    return uv[p.vertex[0]] * p.weight[0] + uv[p.vertex[1]] * p.weight[1] + uv[p.vertex[2]] * p.weight[2];
}

size_t countLevelFlips(const ChartMesh& chart, const std::vector<Vec2>& uv) {
    size_t n = 0;
    for (const ChartLevelTriangle& t : chart.levelTriangles) {
        Vec2 a = chartPointUV(t.corner[0], uv), b = chartPointUV(t.corner[1], uv), c = chartPointUV(t.corner[2], uv);
        if (!(cross(b - a, c - a) > 0)) ++n;
    }
    return n;
}

size_t countOverlaps(const ChartMesh& chart, const std::vector<Vec2>& uv) {
    // Boundary half-edges: those whose twin is absent.
    KeySet half(chart.triangles.size() * 3);
    for (const Tri& t : chart.triangles)
        for (int k = 0; k < 3; ++k) half.insert(directedEdgeKey(t[k], t[(k + 1) % 3]));
    struct Seg {
        uint32_t a, b, face;
        double minx, maxx, miny, maxy;
    };
    std::vector<Seg> segs;
    for (uint32_t f = 0; f < chart.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = chart.triangles[f][k], b = chart.triangles[f][(k + 1) % 3];
            if (half.contains(directedEdgeKey(b, a))) continue;
            Vec2 p = uv[a], q = uv[b];
            segs.push_back({a, b, f, std::min(p.x, q.x), std::max(p.x, q.x), std::min(p.y, q.y), std::max(p.y, q.y)});
        }
    std::sort(segs.begin(), segs.end(), [](const Seg& s, const Seg& t) {
        return s.minx != t.minx ? s.minx < t.minx : (s.a != t.a ? s.a < t.a : s.b < t.b);
    });
    std::vector<char> bad(chart.triangles.size(), 0);
    for (size_t i = 0; i < segs.size(); ++i)
        for (size_t j = i + 1; j < segs.size() && segs[j].minx <= segs[i].maxx; ++j) {
            const Seg &s = segs[i], &t = segs[j];
            if (s.a == t.a || s.a == t.b || s.b == t.a || s.b == t.b) continue;
            if (t.maxy < s.miny || t.miny > s.maxy) continue;
            if (segmentsCross(uv[s.a], uv[s.b], uv[t.a], uv[t.b])) bad[s.face] = bad[t.face] = 1;
        }
    return size_t(std::count(bad.begin(), bad.end(), 1));
}

}  // namespace lodbake
