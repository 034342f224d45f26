// A chart's shape on a page: orientation, conservative rasterisation, quarter turns and coarser
// grids of its footprint (chart_footprint.h).
#include "atlas/chart_footprint.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "lodbake/core/parallel.h"

namespace lodbake::atlas_detail {
namespace {

std::vector<Vec2> convexHull(std::vector<Vec2> p) {
    std::sort(p.begin(), p.end(), [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    p.erase(std::unique(p.begin(), p.end(), [](Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }), p.end());
    if (p.size() < 3) return p;
    std::vector<Vec2> h(2 * p.size());
    size_t k = 0;
    for (size_t i = 0; i < p.size(); ++i) {
        while (k >= 2 && cross(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0) --k;
        h[k++] = p[i];
    }
    for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
        while (k >= t && cross(h[k - 1] - h[k - 2], p[i - 1] - h[k - 2]) <= 0) --k;
        h[k++] = p[i - 1];
    }
    h.resize(k - 1);
    return h;
}

// The chart in the frame rotated by the angle (c, s) = (cos, sin), moved to [0, w] x [0, h]
// (aligned: by whole units, so that unit cell centres stay cell centres).
Oriented frameAt(const AtlasChart& chart, const std::vector<Vec2>& hull, double c, double s, bool aligned = false) {
    Oriented o;
    o.uvArea = chart.uvArea;
    o.c = c;
    o.s = s;
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const Vec2& q : hull) {
        double x = c * q.x + s * q.y, y = -s * q.x + c * q.y;
        x0 = std::min(x0, x); x1 = std::max(x1, x);
        y0 = std::min(y0, y); y1 = std::max(y1, y);
    }
    if (hull.empty()) { x0 = x1 = y0 = y1 = 0; }
    if (aligned) {
        x0 = std::floor(x0 / kAlignedBlock) * kAlignedBlock;
        y0 = std::floor(y0 / kAlignedBlock) * kAlignedBlock;
        o.aligned = true;
        o.turns = 1;
    }
    o.minX = x0; o.minY = y0; o.w = x1 - x0; o.h = y1 - y0;
    auto turn = [&](Vec2 q) { return Vec2{c * q.x + s * q.y - x0, -s * q.x + c * q.y - y0}; };
    if (!chart.triangles.empty()) {
        for (const auto& tri : chart.triangles) o.triangles.push_back({turn(tri[0]), turn(tri[1]), turn(tri[2])});
    } else {
        for (size_t i = 1; i + 1 < hull.size(); ++i) o.triangles.push_back({turn(hull[0]), turn(hull[i]), turn(hull[i + 1])});
        if (hull.size() < 3) for (const Vec2& q : hull) o.triangles.push_back({turn(q), turn(q), turn(q)});
    }
    return o;
}

// Whether a triangle and a unit cell [x, x+1] x [y, y+1] overlap by more than a hair (separating
// axes: the three edge normals; the caller visits only cells within the triangle's bounding box).
// What depends on the triangle alone is computed once, for every cell it is tested against.
class TriangleCellTest {
public:
    explicit TriangleCellTest(const std::array<Vec2, 3>& q) {
        for (int k = 0; k < 3; ++k) {
            Axis& a = axes_[size_t(k)];
            Vec2 e = q[size_t((k + 1) % 3)] - q[size_t(k)];
            a.n = {-e.y, e.x};
            const double t0 = dot(a.n, q[0]), t1 = dot(a.n, q[1]), t2 = dot(a.n, q[2]);
            a.tMin = std::min({t0, t1, t2});
            a.tMax = std::max({t0, t1, t2});
            const double scale = std::sqrt(dot(a.n, a.n));
            a.skip = scale == 0;
            a.margin = kEps * scale;
            a.lowX = a.n.x < 0 ? 1 : 0;
            a.lowY = a.n.y < 0 ? 1 : 0;
        }
    }
    // The cells of row y in [x0, x1] the triangle overlaps (no axis separates them), as [a, b];
    // false when none. Along a row each separation test moves one way (the cell's extent on an
    // axis is monotone in x, in floating point too), so each one cuts the row at one place, found
    // by bisection: the same cells as testing each one, in a few tests per row.
    bool span(int y, int x0, int x1, int& a, int& b) const {
        for (const Axis& ax : axes_) {
            if (ax.skip) continue;
            if (!narrow(x0, x1, [&](int x) { return !below(ax, x, y); }) || !narrow(x0, x1, [&](int x) { return !above(ax, x, y); }))
                return false;
        }
        a = x0;
        b = x1;
        return true;
    }

private:
    static constexpr double kEps = 1e-6;
    struct Axis {
        Vec2 n;
        double tMin = 0, tMax = 0, margin = 0;
        bool skip = false;  // a degenerate edge separates nothing
        int lowX = 0, lowY = 0;  // the cell corner with the least projection, from (x, y)
    };
    // The cell's extent on the axis: the least and largest projection of its corners. Those are
    // the corners the normal's signs pick (the opposite ones): products and sums round
    // monotonically, so no other corner's rounded projection lies beyond theirs.
    static double lowest(const Axis& a, int x, int y) { return dot(a.n, Vec2{double(x + a.lowX), double(y + a.lowY)}); }
    static double highest(const Axis& a, int x, int y) { return dot(a.n, Vec2{double(x + 1 - a.lowX), double(y + 1 - a.lowY)}); }
    // The axis separates the cell from the triangle: the cell lies below, or above, the triangle's extent.
    static bool below(const Axis& a, int x, int y) { return highest(a, x, y) <= a.tMin + a.margin; }
    static bool above(const Axis& a, int x, int y) { return a.tMax <= lowest(a, x, y) + a.margin; }
    // [x0, x1] narrowed to where `pass` holds, given that it holds on a prefix or a suffix of the
    // row; false when nowhere.
    template <class Pass>
    static bool narrow(int& x0, int& x1, Pass&& pass) {
        if (x0 > x1) return false;
        const bool first = pass(x0), last = pass(x1);
        if (first && last) return true;
        if (!first && !last) return false;
        int lo = x0, hi = x1;  // pass(lo) != pass(hi): bisect to the neighbours where it changes
        while (hi - lo > 1) {
            const int mid = lo + (hi - lo) / 2;
            (pass(mid) == first ? lo : hi) = mid;
        }
        if (first) x1 = lo;
        else x0 = hi;
        return true;
    }
    std::array<Axis, 3> axes_;
};

// Sets every cell within `radius` cells (a square: the max filter along rows, then along columns)
// of a set cell. Each pass tracks the nearest set cell before and after, so it costs the grid's
// cells whatever the radius.
void growByRadius(std::vector<uint8_t>& mask, int gw, int gh, int radius) {
    constexpr int kFar = std::numeric_limits<int>::max() / 4;
    std::vector<uint8_t> rows(mask.size(), 0);
    for (int y = 0; y < gh; ++y) {
        const uint8_t* in = &mask[size_t(y) * size_t(gw)];
        uint8_t* out = &rows[size_t(y) * size_t(gw)];
        for (int x = 0, last = -kFar; x < gw; ++x) {
            if (in[x]) last = x;
            out[x] = x - last <= radius;
        }
        for (int x = gw - 1, next = kFar; x >= 0; --x) {
            if (in[x]) next = x;
            out[x] |= next - x <= radius;
        }
    }
    std::vector<int> near(size_t(gw), -kFar);  // per column: the last set row seen
    for (int y = 0; y < gh; ++y) {
        const uint8_t* in = &rows[size_t(y) * size_t(gw)];
        uint8_t* out = &mask[size_t(y) * size_t(gw)];
        for (int x = 0; x < gw; ++x) {
            if (in[x]) near[size_t(x)] = y;
            out[x] = y - near[size_t(x)] <= radius;
        }
    }
    std::fill(near.begin(), near.end(), kFar);  // per column: the next set row seen
    for (int y = gh - 1; y >= 0; --y) {
        const uint8_t* in = &rows[size_t(y) * size_t(gw)];
        uint8_t* out = &mask[size_t(y) * size_t(gw)];
        for (int x = 0; x < gw; ++x) {
            if (in[x]) near[size_t(x)] = y;
            out[x] |= near[size_t(x)] - y <= radius;
        }
    }
}

using Runs = std::vector<std::pair<int, int>>;

// The cells in both run lists.
Runs intersect(const Runs& p, const Runs& q) {
    Runs out;
    for (size_t i = 0, j = 0; i < p.size() && j < q.size();) {
        const int a = std::max(p[i].first, q[j].first), b = std::min(p[i].second, q[j].second);
        if (a <= b) out.push_back({a, b});
        (p[i].second < q[j].second ? i : j)++;
    }
    return out;
}

// The cells of p not in q.
Runs subtract(const Runs& p, const Runs& q) {
    Runs out;
    size_t j = 0;
    for (auto [a, b] : p) {
        while (j < q.size() && q[j].second < a) ++j;
        for (size_t k = j; k < q.size() && q[k].first <= b && a <= b; ++k) {
            if (q[k].first > a) out.push_back({a, q[k].first - 1});
            a = std::max(a, q[k].second + 1);
        }
        if (a <= b) out.push_back({a, b});
    }
    return out;
}

// The blocks of the band of rows [s, s + n) (clipped to the footprint): the cells every row of
// it occupies, less those of its enclosing band's (`outer`, which its blocks took), then its two
// halves' blocks.
void coverBand(Footprint& f, int s, int n, const Runs& outer) {
    const int m = std::min(n, f.h - s);
    Runs all = f.rows[size_t(s)];
    for (int i = 1; i < m; ++i) all = intersect(all, f.rows[size_t(s + i)]);
    int level = 0;
    while ((2 << level) <= m) ++level;
    for (const auto& [a, b] : subtract(all, outer)) f.blocks.push_back({s, m, a, b, level});
    if (n == 1) return;
    coverBand(f, s, n / 2, all);
    if (s + n / 2 < f.h) coverBand(f, s + n / 2, n / 2, all);
}

// Footprint::blocks, largest first (ties: in the order the bands are visited).
void coverBlocks(Footprint& f) {
    f.blocks.clear();
    for (int s = 0; s < f.h; s += kBlockRows) coverBand(f, s, kBlockRows, {});
    std::stable_sort(f.blocks.begin(), f.blocks.end(), [](const Footprint::Block& p, const Footprint::Block& q) {
        return long(p.rows) * (p.b - p.a + 1) > long(q.rows) * (q.b - q.a + 1);
    });
}

}  // namespace

std::vector<Oriented> chartOrientations(const AtlasChart& chart, bool aligned) {
    std::vector<Vec2> hull = convexHull(chart.points);
    if (aligned) return {frameAt(chart, hull, 1, 0, true)};
    double bestC = 1, bestS = 0, bestArea = 1e300;
    auto tryAngle = [&](double c, double s) {
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        for (const Vec2& q : hull) {
            double x = c * q.x + s * q.y, y = -s * q.x + c * q.y;
            x0 = std::min(x0, x); x1 = std::max(x1, x);
            y0 = std::min(y0, y); y1 = std::max(y1, y);
        }
        double area = (x1 - x0) * (y1 - y0);
        if (area < bestArea * (1 - 1e-9)) { bestArea = area; bestC = c; bestS = s; }
    };
    tryAngle(1, 0);  // the chart as it is first: ties keep it unrotated
    for (size_t i = 0; i < hull.size(); ++i) {
        Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
        double l = std::sqrt(dot(e, e));
        if (l > 0) tryAngle(e.x / l, e.y / l);
    }
    return {frameAt(chart, hull, bestC, bestS)};
}

std::vector<uint8_t> chartMask(const Oriented& c, double t, int radius, int& gw, int& gh, size_t* rasterCells) {
    gw = texels(c.w, t) + 2 * radius;
    gh = texels(c.h, t) + 2 * radius;
    std::vector<uint8_t> mask(size_t(gw) * size_t(gh), 0);
    auto mark = [&](int x, int y) {
        if (x >= 0 && y >= 0 && x < gw && y < gh) mask[size_t(y) * size_t(gw) + size_t(x)] = 1;
    };
    auto toGrid = [&](Vec2 p) { return Vec2{p.x * t + radius, p.y * t + radius}; };
    for (const std::array<Vec2, 3>& tri : c.triangles) {
        std::array<Vec2, 3> q{toGrid(tri[0]), toGrid(tri[1]), toGrid(tri[2])};
        for (const Vec2& v : q) mark(int(std::floor(v.x)), int(std::floor(v.y)));  // corners always show
        if (std::abs(cross(q[1] - q[0], q[2] - q[0])) < 1e-12) continue;
        int x0 = std::max(0, int(std::floor(std::min({q[0].x, q[1].x, q[2].x}))));
        int x1 = std::min(gw - 1, int(std::floor(std::max({q[0].x, q[1].x, q[2].x}))));
        int y0 = std::max(0, int(std::floor(std::min({q[0].y, q[1].y, q[2].y}))));
        int y1 = std::min(gh - 1, int(std::floor(std::max({q[0].y, q[1].y, q[2].y}))));
        const TriangleCellTest test(q);
        for (int y = y0, a = 0, b = 0; y <= y1; ++y)
            if (test.span(y, x0, x1, a, b)) std::fill_n(&mask[size_t(y) * size_t(gw) + size_t(a)], b - a + 1, uint8_t(1));
    }
    if (rasterCells) *rasterCells = size_t(std::count(mask.begin(), mask.end(), uint8_t(1)));
    // Grow by the gutter radius (a square, separable max filter): two footprints that do not
    // overlap keep their charts 2 * radius texels apart.
    if (radius > 0) growByRadius(mask, gw, gh, radius);
    return mask;
}

std::array<double, 6> placementFor(const Oriented& c, const Slot& s, double t, int radius) {
    // Grid coordinates before the turn: q = (A . uv + a, B . uv + b).
    const double A[3] = {t * c.c, t * c.s, radius - t * c.minX};
    const double B[3] = {-t * c.s, t * c.c, radius - t * c.minY};
    std::array<double, 6> m{};
    for (int k = 0; k < 3; ++k) {
        double x = A[k], y = B[k], cx = k == 2 ? 1 : 0;  // constants carry the grid offsets
        double rx = x, ry = y;
        switch (s.rotation) {
            case 1: rx = s.gh * cx - y; ry = x; break;
            case 2: rx = s.gw * cx - x; ry = s.gh * cx - y; break;
            case 3: rx = y; ry = s.gw * cx - x; break;
            default: break;
        }
        m[size_t(k)] = rx + (k == 2 ? s.x : 0);
        m[size_t(3 + k)] = ry + (k == 2 ? s.y : 0);
    }
    return m;
}

Footprint rotatedFootprint(const std::vector<uint8_t>& mask, int gw, int gh, int rotation) {
    Footprint f;
    f.w = rotation % 2 ? gh : gw;
    f.h = rotation % 2 ? gw : gh;
    f.rows.resize(size_t(f.h));
    f.rowCells.assign(size_t(f.h), 0);
    f.rowLongest.assign(size_t(f.h), 0);
    auto at = [&](int x, int y) -> bool {  // (x, y) in the rotated grid -> source cell
        int sx = x, sy = y;
        switch (rotation) {
            case 1: sx = y; sy = gh - 1 - x; break;
            case 2: sx = gw - 1 - x; sy = gh - 1 - y; break;
            case 3: sx = gw - 1 - y; sy = x; break;
            default: break;
        }
        return mask[size_t(sy) * size_t(gw) + size_t(sx)] != 0;
    };
    for (int y = 0; y < f.h; ++y) {
        int start = -1;
        for (int x = 0; x <= f.w; ++x) {
            bool on = x < f.w && at(x, y);
            if (on && start < 0) start = x;
            if (!on && start >= 0) {
                f.rows[size_t(y)].push_back({start, x - 1});
                f.rowCells[size_t(y)] += x - start;
                f.rowLongest[size_t(y)] = std::max(f.rowLongest[size_t(y)], x - start);
                start = -1;
            }
        }
    }
    double cells = 0, moment = 0;
    for (int y = 0; y < f.h; ++y) {
        cells += f.rowCells[size_t(y)];
        moment += f.rowCells[size_t(y)] * (y + 0.5);
    }
    f.centroidRow = cells > 0 ? moment / cells : 0.5 * f.h;
    if (f.h > 0) {
        f.leastCells = *std::min_element(f.rowCells.begin(), f.rowCells.end());
        f.leastLongest = *std::min_element(f.rowLongest.begin(), f.rowLongest.end());
    }
    coverBlocks(f);
    return f;
}

std::vector<uint8_t> coarsen(const std::vector<uint8_t>& mask, int gw, int gh, int scale, int& cw, int& ch) {
    cw = (gw + scale - 1) / scale;
    ch = (gh + scale - 1) / scale;
    if (scale == 1) return mask;
    std::vector<uint8_t> out(size_t(cw) * size_t(ch), 0);
    for (int y = 0; y < gh; ++y)
        for (int x = 0; x < gw; ++x)
            if (mask[size_t(y) * size_t(gw) + size_t(x)]) out[size_t(y / scale) * size_t(cw) + size_t(x / scale)] = 1;
    return out;
}

namespace {

// A chart's footprints in one orientation on the search grid of fp (ChartFootprints), and in
// `twiceCoarser`, when given, on the grid twice as coarse (from the same rasterisation).
ChartFootprints orientedFootprints(const Oriented& o, const Footprints& fp, ChartFootprints* twiceCoarser) {
    ChartFootprints c;
    c.turns = o.turns;
    std::vector<uint8_t> fine = chartMask(o, fp.t, fp.radius, c.gw, c.gh, &c.raster);
    c.footprint = size_t(std::count(fine.begin(), fine.end(), uint8_t(1)));
    auto blocks = [&](ChartFootprints& into, int s) {
        std::vector<uint8_t> mask = coarsen(fine, into.gw, into.gh, s, into.cw, into.ch);
        // Only the quarter turns the placement tries (texel-aligned charts: none).
        for (int rot = 0; rot < into.turns; ++rot) into.rot[size_t(rot)] = rotatedFootprint(mask, into.cw, into.ch, rot);
    };
    if (twiceCoarser) {
        *twiceCoarser = c;
        blocks(*twiceCoarser, 2 * fp.scale);
    }
    blocks(c, fp.scale);
    return c;
}

}  // namespace

Footprints noFootprints(size_t charts, double t, int gutter, int scale) {
    Footprints fp;
    fp.t = t;
    fp.scale = scale;
    fp.radius = (gutter + 1) / 2;
    fp.charts.resize(charts);
    return fp;
}

void addFootprints(const Orientations& charts, const std::vector<size_t>& which, Footprints& fp, int threads) {
    parallelFor(which.size(), threads, [&](size_t k) {  // each chart into its own slot
        for (const Oriented& o : charts[which[k]]) fp.charts[which[k]].push_back(orientedFootprints(o, fp, nullptr));
    });
}

Footprints footprintsAt(const Orientations& charts, double t, int gutter, int scale, int threads, Footprints* twiceCoarser) {
    Footprints fp = noFootprints(charts.size(), t, gutter, scale);
    if (twiceCoarser) *twiceCoarser = noFootprints(charts.size(), t, gutter, 2 * scale);
    parallelFor(charts.size(), threads, [&](size_t i) {  // each chart into its own slot
        for (const Oriented& o : charts[i]) {
            ChartFootprints coarse;
            fp.charts[i].push_back(orientedFootprints(o, fp, twiceCoarser ? &coarse : nullptr));
            if (twiceCoarser) twiceCoarser->charts[i].push_back(std::move(coarse));
        }
    });
    return fp;
}

bool footprintsFit(const Orientations& charts, double t, int gutter, int scale, int binW, int binH) {
    const int radius = (gutter + 1) / 2;
    const int pageW = (binW + 2 * radius) / scale, pageH = (binH + 2 * radius) / scale;  // BitmapPage's sides
    auto blocks = [&](double extent) { return (texels(extent, t) + 2 * radius + scale - 1) / scale; };  // chartMask, coarsen
    for (const std::vector<Oriented>& chart : charts) {
        bool fits = false;
        for (const Oriented& o : chart) {
            const int w = blocks(o.w), h = blocks(o.h);
            fits = fits || (w <= pageW && h <= pageH) || (o.turns > 1 && h <= pageW && w <= pageH);
        }
        if (!fits) return false;
    }
    return true;
}

}  // namespace lodbake::atlas_detail
