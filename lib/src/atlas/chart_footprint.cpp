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

// The points strictly inside the polygon of the extreme points in eight directions, by a margin
// far above rounding: they cannot be hull vertices, and the monotone chain below would push and
// pop them, so dropping them first leaves the sort only a thin ring of a dense chart's points.
std::vector<Vec2> withoutInterior(std::vector<Vec2> p) {
    if (p.size() < 64) return p;
    // Directions in counter-clockwise order; the extremes follow the hull in the same order.
    const Vec2 dirs[8] = {{0, -1}, {1, -1}, {1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}};
    Vec2 ext[8];
    double best[8];
    for (int k = 0; k < 8; ++k) best[k] = -1e300;
    double lo = 1e300, hi = -1e300;
    for (const Vec2& q : p) {
        for (int k = 0; k < 8; ++k)
            if (dot(q, dirs[k]) > best[k]) { best[k] = dot(q, dirs[k]); ext[k] = q; }
        lo = std::min({lo, q.x, q.y});
        hi = std::max({hi, q.x, q.y});
    }
    std::vector<Vec2> poly;
    for (const Vec2& q : ext)
        if (poly.empty() || q.x != poly.back().x || q.y != poly.back().y) poly.push_back(q);
    while (poly.size() > 1 && poly.back().x == poly.front().x && poly.back().y == poly.front().y) poly.pop_back();
    if (poly.size() < 3) return p;
    const double margin = 1e-9 * std::max(hi - lo, 1e-300);
    auto inside = [&](Vec2 q) {
        for (size_t i = 0; i < poly.size(); ++i) {
            const Vec2 a = poly[i], e = poly[(i + 1) % poly.size()] - a;
            if (!(cross(e, q - a) > margin * std::sqrt(dot(e, e)))) return false;
        }
        return true;
    };
    p.erase(std::remove_if(p.begin(), p.end(), inside), p.end());
    return p;
}

std::vector<Vec2> convexHull(std::vector<Vec2> p) {
    p = withoutInterior(std::move(p));
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

// The frame rotated by the angle (c, s) = (cos, sin) around the hull, moved to [0, w] x [0, h]
// (aligned: by whole blocks, so that unit cell centres stay cell centres).
ChartFrame frameAt(const std::vector<Vec2>& hull, double c, double s, bool aligned = false) {
    ChartFrame f;
    f.c = c;
    f.s = s;
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
    }
    f.minX = x0; f.minY = y0; f.w = x1 - x0; f.h = y1 - y0;
    return f;
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
    // The bisection starts at the cells where the cell's extent reaches the triangle's on the
    // axis in exact arithmetic (next to where the rounded test changes).
    bool span(int y, int x0, int x1, int& a, int& b) const {
        for (const Axis& ax : axes_) {
            if (ax.skip) continue;
            const double belowEnds = (ax.tMin + ax.margin - ax.n.y * (y + 1 - ax.lowY)) / ax.n.x - (1 - ax.lowX);
            const double aboveEnds = (ax.tMax - ax.margin - ax.n.y * (y + ax.lowY)) / ax.n.x - ax.lowX;
            if (!narrow(x0, x1, belowEnds, [&](int x) { return !below(ax, x, y); }) ||
                !narrow(x0, x1, aboveEnds, [&](int x) { return !above(ax, x, y); }))
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
    // row; false when nowhere. `guess`: a cell near where it changes (any value, NaN included):
    // it and its neighbour towards the change are tested first, then the bisection goes on
    // between the nearest cells on either side.
    template <class Pass>
    static bool narrow(int& x0, int& x1, double guess, Pass&& pass) {
        if (x0 > x1) return false;
        const bool first = pass(x0), last = pass(x1);
        if (first && last) return true;
        if (!first && !last) return false;
        int lo = x0, hi = x1;  // pass(lo) != pass(hi): bisect to the neighbours where it changes
        auto probe = [&](int x) {
            if (x > lo && x < hi) (pass(x) == first ? lo : hi) = x;
        };
        if (!std::isnan(guess)) {
            const int g = int(std::clamp(std::floor(guess), double(x0), double(x1)));
            probe(g);
            probe(lo == g ? g + 1 : g - 1);
        }
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

// Sorts the runs [begin, end) and appends their union to `out` (touching runs join).
void appendUnion(std::vector<std::pair<int, int>>& out, std::pair<int, int>* begin, std::pair<int, int>* end) {
    std::sort(begin, end);
    const size_t start = out.size();
    for (auto* r = begin; r != end; ++r) {
        if (out.size() > start && r->first <= out.back().second + 1) out.back().second = std::max(out.back().second, r->second);
        else out.push_back(*r);
    }
}

// Appends the union of the runs [p, pe) and [q, qe), each sorted by start, to `out` (touching
// runs join).
void appendUnited(std::vector<std::pair<int, int>>& out, const std::pair<int, int>* p, const std::pair<int, int>* pe,
                  const std::pair<int, int>* q, const std::pair<int, int>* qe) {
    const size_t start = out.size();
    while (p != pe || q != qe) {
        const std::pair<int, int> r = q == qe || (p != pe && p->first <= q->first) ? *p++ : *q++;
        if (out.size() > start && r.first <= out.back().second + 1) out.back().second = std::max(out.back().second, r.second);
        else out.push_back(r);
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

ChartFrame chartFrame(const AtlasChart& chart, bool aligned) {
    std::vector<Vec2> hull = convexHull(chart.points);
    if (aligned) return frameAt(hull, 1, 0, true);
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
    return frameAt(hull, bestC, bestS);
}

Oriented orientedIn(const AtlasChart& chart, const ChartFrame& f, bool aligned) {
    Oriented o;
    o.uvArea = chart.uvArea;
    o.c = f.c; o.s = f.s;
    o.minX = f.minX; o.minY = f.minY; o.w = f.w; o.h = f.h;
    if (aligned) {
        o.aligned = true;
        o.turns = 1;
    }
    auto turn = [&](Vec2 q) { return Vec2{f.c * q.x + f.s * q.y - f.minX, -f.s * q.x + f.c * q.y - f.minY}; };
    if (!chart.triangles.empty()) {
        o.triangles.reserve(chart.triangles.size());
        for (const auto& tri : chart.triangles) o.triangles.push_back({turn(tri[0]), turn(tri[1]), turn(tri[2])});
    } else {
        const std::vector<Vec2> hull = convexHull(chart.points);
        for (size_t i = 1; i + 1 < hull.size(); ++i) o.triangles.push_back({turn(hull[0]), turn(hull[i]), turn(hull[i + 1])});
        if (hull.size() < 3) for (const Vec2& q : hull) o.triangles.push_back({turn(q), turn(q), turn(q)});
    }
    return o;
}

// Each row's runs widened by the radius, then per row the union of the widened rows within the
// radius, from the unions of 1, 2, 4... rows (the window is the union of two overlapping
// power-of-two stretches).
RowRuns growByRadius(const RowRuns& in, int radius) {
    const int window = 2 * radius + 1, padded = in.h + 2 * radius;  // padded row i is row i - radius
    RowRuns rows;  // per padded row i: the union of widened rows [i - radius, i - radius + span), clipped
    rows.first.assign(1, 0);
    for (int i = 0; i < padded; ++i) {
        const int y = i - radius;
        if (y >= 0 && y < in.h)
            for (size_t k = in.first[size_t(y)]; k < in.first[size_t(y) + 1]; ++k)
                rows.runs.push_back({std::max(0, in.runs[k].first - radius), std::min(in.w - 1, in.runs[k].second + radius)});
        rows.first.push_back(rows.runs.size());
    }
    auto row = [](const RowRuns& r, int i) { return std::make_pair(r.runs.data() + r.first[size_t(i)], r.runs.data() + r.first[size_t(i) + 1]); };
    int span = 1;
    for (; 2 * span <= window; span *= 2) {
        RowRuns twice;
        twice.first.assign(1, 0);
        for (int i = 0; i < padded; ++i) {
            const auto [p, pe] = row(rows, i);
            const auto [q, qe] = i + span < padded ? row(rows, i + span) : std::make_pair(pe, pe);
            appendUnited(twice.runs, p, pe, q, qe);
            twice.first.push_back(twice.runs.size());
        }
        rows = std::move(twice);
    }
    RowRuns out;
    out.w = in.w;
    out.h = in.h;
    out.first.assign(1, 0);
    for (int y = 0; y < in.h; ++y) {  // padded rows [y, y + window)
        const auto [p, pe] = row(rows, y);
        const auto [q, qe] = row(rows, y + window - span);
        appendUnited(out.runs, p, pe, q, qe);
        out.first.push_back(out.runs.size());
    }
    return out;
}

size_t RowRuns::cells() const {
    size_t n = 0;
    for (const auto& [a, b] : runs) n += size_t(b - a + 1);
    return n;
}

RowRuns chartRuns(const Oriented& c, double t, int radius, size_t* rasterCells) {
    const int gw = texels(c.w, t) + 2 * radius, gh = texels(c.h, t) + 2 * radius;
    // One bit per cell: each triangle sets its span per row it touches, and its corners' cells
    // (many small triangles set few cells each, over and over).
    const size_t words = (size_t(gw) + 63) / 64;
    std::vector<uint64_t> bits(words * size_t(gh), 0);
    auto setSpan = [&](int y, int a, int b) {
        uint64_t* row = &bits[size_t(y) * words];
        const size_t wa = size_t(a) / 64, wb = size_t(b) / 64;
        const uint64_t from = ~uint64_t(0) << (a % 64), to = ~uint64_t(0) >> (63 - b % 64);
        if (wa == wb) {
            row[wa] |= from & to;
            return;
        }
        row[wa] |= from;
        for (size_t w = wa + 1; w < wb; ++w) row[w] = ~uint64_t(0);
        row[wb] |= to;
    };
    // Whether cells [a, b] of row y are all set already.
    auto allSet = [&](int y, int a, int b) {
        const uint64_t* row = &bits[size_t(y) * words];
        for (int x = a; x <= b;) {
            const int w = x / 64, n = std::min(64 - x % 64, b - x + 1);
            const uint64_t m = n == 64 ? ~uint64_t(0) : ((uint64_t(1) << n) - 1) << (x % 64);
            if ((row[w] & m) != m) return false;
            x += n;
        }
        return true;
    };
    auto mark = [&](int x, int y) {
        if (x >= 0 && y >= 0 && x < gw && y < gh) bits[size_t(y) * words + size_t(x) / 64] |= uint64_t(1) << (x % 64);
    };
    auto toGrid = [&](Vec2 p) { return Vec2{p.x * t + radius, p.y * t + radius}; };
    for (const std::array<Vec2, 3>& tri : c.triangles)
        for (const Vec2& p : tri) {
            const Vec2 v = toGrid(p);
            mark(int(std::floor(v.x)), int(std::floor(v.y)));
        }
    // The cells a triangle may add lie in its bounding box: a row of it that is set already (the
    // corners of a dense mesh's triangles fill most cells) needs no test.
    for (const std::array<Vec2, 3>& tri : c.triangles) {
        std::array<Vec2, 3> q{toGrid(tri[0]), toGrid(tri[1]), toGrid(tri[2])};
        if (std::abs(cross(q[1] - q[0], q[2] - q[0])) < 1e-12) continue;
        int x0 = std::max(0, int(std::floor(std::min({q[0].x, q[1].x, q[2].x}))));
        int x1 = std::min(gw - 1, int(std::floor(std::max({q[0].x, q[1].x, q[2].x}))));
        int y0 = std::max(0, int(std::floor(std::min({q[0].y, q[1].y, q[2].y}))));
        int y1 = std::min(gh - 1, int(std::floor(std::max({q[0].y, q[1].y, q[2].y}))));
        if (x0 > x1) continue;
        int open = y0;  // the first row with a cell to test
        while (open <= y1 && allSet(open, x0, x1)) ++open;
        if (open > y1) continue;
        const TriangleCellTest test(q);
        for (int y = open, a = 0, b = 0; y <= y1; ++y)
            if (!allSet(y, x0, x1) && test.span(y, x0, x1, a, b)) setSpan(y, a, b);
    }
    // The set bits' runs, row by row.
    RowRuns raster;
    raster.w = gw;
    raster.h = gh;
    raster.first.assign(1, 0);
    for (size_t y = 0; y < size_t(gh); ++y) {
        const uint64_t* row = &bits[y * words];
        int start = -1;
        for (size_t w = 0; w < words; ++w) {
            // Alternate: the next set bit (a run starts), the next clear bit (it ends).
            for (int pos = 0; pos < 64;) {
                const uint64_t m = start < 0 ? row[w] : ~row[w];
                const uint64_t rest = pos == 0 ? m : m & (~uint64_t(0) << pos);
                if (!rest) break;
                pos = __builtin_ctzll(rest);
                if (start < 0) start = int(w * 64) + pos;
                else {
                    raster.runs.push_back({start, int(w * 64) + pos - 1});
                    start = -1;
                }
            }
        }
        if (start >= 0) raster.runs.push_back({start, gw - 1});  // bits past gw are never set
        raster.first.push_back(raster.runs.size());
    }
    if (rasterCells) *rasterCells = raster.cells();
    // Grown by the gutter radius: two footprints that do not overlap keep their charts 2 * radius
    // texels apart.
    return radius > 0 ? growByRadius(raster, radius) : raster;
}

std::vector<uint8_t> chartMask(const Oriented& c, double t, int radius, int& gw, int& gh, size_t* rasterCells) {
    const RowRuns cells = chartRuns(c, t, radius, rasterCells);
    gw = cells.w;
    gh = cells.h;
    std::vector<uint8_t> mask(size_t(gw) * size_t(gh), 0);
    for (size_t y = 0; y < size_t(gh); ++y)
        for (size_t k = cells.first[y]; k < cells.first[y + 1]; ++k)
            std::fill_n(&mask[y * size_t(gw) + size_t(cells.runs[k].first)], cells.runs[k].second - cells.runs[k].first + 1, uint8_t(1));
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

namespace {

// The runs of a line of cells, `on(i)` for i in [0, n).
template <class On>
void lineRuns(int n, On&& on, std::vector<std::pair<int, int>>& out) {
    for (int i = 0, start = -1; i <= n; ++i) {
        const bool set = i < n && on(i);
        if (set && start < 0) start = i;
        if (!set && start >= 0) {
            out.push_back({start, i - 1});
            start = -1;
        }
    }
}

// The per-row figures, order and blocks of a footprint whose rows are set.
void finishFootprint(Footprint& f) {
    f.rowCells.assign(size_t(f.h), 0);
    f.rowLongest.assign(size_t(f.h), 0);
    double cells = 0, moment = 0;
    for (int y = 0; y < f.h; ++y) {
        for (const auto& [a, b] : f.rows[size_t(y)]) {
            f.rowCells[size_t(y)] += b - a + 1;
            f.rowLongest[size_t(y)] = std::max(f.rowLongest[size_t(y)], b - a + 1);
        }
        cells += f.rowCells[size_t(y)];
        moment += f.rowCells[size_t(y)] * (y + 0.5);
    }
    f.centroidRow = cells > 0 ? moment / cells : 0.5 * f.h;
    if (f.h > 0) {
        f.leastCells = *std::min_element(f.rowCells.begin(), f.rowCells.end());
        f.leastLongest = *std::min_element(f.rowLongest.begin(), f.rowLongest.end());
    }
    coverBlocks(f);
}

}  // namespace

Footprint rotatedFootprint(const RowRuns& cells, int rotation) {
    const int gw = cells.w, gh = cells.h;
    Footprint f;
    f.w = rotation % 2 ? gh : gw;
    f.h = rotation % 2 ? gw : gh;
    f.rows.resize(size_t(f.h));
    auto runsOf = [&](int y) { return std::make_pair(cells.runs.begin() + long(cells.first[size_t(y)]), cells.runs.begin() + long(cells.first[size_t(y) + 1])); };
    if (rotation == 0 || rotation == 2) {
        for (int y = 0; y < f.h; ++y) {
            auto& row = f.rows[size_t(y)];
            if (rotation == 0) {
                const auto [b, e] = runsOf(y);
                row.assign(b, e);
            } else {  // row gh-1-y mirrored
                const auto [b, e] = runsOf(gh - 1 - y);
                for (auto r = e; r != b;) {
                    --r;
                    row.push_back({gw - 1 - r->second, gw - 1 - r->first});
                }
            }
        }
    } else {
        // The grid's columns as rows: column sx, cell sy at [sx * gh + sy].
        std::vector<uint8_t> columns(size_t(gw) * size_t(gh), 0);
        for (int y = 0; y < gh; ++y) {
            const auto [b, e] = runsOf(y);
            for (auto r = b; r != e; ++r)
                for (int x = r->first; x <= r->second; ++x) columns[size_t(x) * size_t(gh) + size_t(y)] = 1;
        }
        for (int y = 0; y < f.h; ++y) {
            // One turn: row y is column y from its last cell; three: column gw-1-y from its first.
            const uint8_t* col = &columns[size_t(rotation == 1 ? y : gw - 1 - y) * size_t(gh)];
            if (rotation == 1) lineRuns(f.w, [&](int x) { return col[gh - 1 - x] != 0; }, f.rows[size_t(y)]);
            else lineRuns(f.w, [&](int x) { return col[x] != 0; }, f.rows[size_t(y)]);
        }
    }
    finishFootprint(f);
    return f;
}

Footprint rotatedFootprint(const std::vector<uint8_t>& mask, int gw, int gh, int rotation) {
    RowRuns cells;
    cells.w = gw;
    cells.h = gh;
    cells.first.assign(1, 0);
    for (int y = 0; y < gh; ++y) {
        lineRuns(gw, [&](int x) { return mask[size_t(y) * size_t(gw) + size_t(x)] != 0; }, cells.runs);
        cells.first.push_back(cells.runs.size());
    }
    return rotatedFootprint(cells, rotation);
}

RowRuns coarsen(const RowRuns& cells, int scale) {
    if (scale == 1) return cells;
    RowRuns out;
    out.w = (cells.w + scale - 1) / scale;
    out.h = (cells.h + scale - 1) / scale;
    out.first.assign(1, 0);
    std::vector<std::pair<int, int>> block;
    for (int cy = 0; cy < out.h; ++cy) {
        block.clear();
        for (size_t k = cells.first[size_t(cy * scale)]; k < cells.first[size_t(std::min(cells.h, cy * scale + scale))]; ++k)
            block.push_back({cells.runs[k].first / scale, cells.runs[k].second / scale});
        appendUnion(out.runs, block.data(), block.data() + block.size());
        out.first.push_back(out.runs.size());
    }
    return out;
}

namespace {

// A chart's footprints in one orientation on the search grid of fp (ChartFootprints), and in
// `twiceCoarser`, when given, on the grid twice as coarse (from the same rasterisation).
ChartFootprints orientedFootprints(const Oriented& o, const Footprints& fp, ChartFootprints* twiceCoarser) {
    ChartFootprints c;
    c.turns = o.turns;
    const RowRuns fine = chartRuns(o, fp.t, fp.radius, &c.raster);
    c.gw = fine.w;
    c.gh = fine.h;
    c.footprint = fine.cells();
    auto blocks = [&](ChartFootprints& into, int s) {
        const RowRuns cells = coarsen(fine, s);
        into.cw = cells.w;
        into.ch = cells.h;
        // Only the quarter turns the placement tries (texel-aligned charts: none).
        for (int rot = 0; rot < into.turns; ++rot) into.rot[size_t(rot)] = rotatedFootprint(cells, rot);
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
