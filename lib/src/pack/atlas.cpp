// Atlas packing (pack, DESIGN.md "Tools").
//
// References: J. Jylänki, "A Thousand Ways to Pack the Bin" (2010), skyline bottom-left with
// best-fit (waste map omitted); Freeman & Shapira, "Determining the minimum-area encasing
// rectangle for an arbitrary closed curve" (1975), minimum-area rectangle from a hull edge.
//
// Pipeline of packAtlas:
//   1. orientChart: convex hull of each chart's UV points, minimum-area bounding rectangle;
//   2. choosePage: page size and density (strip packing at the density limit for free sizes,
//      the largest power-of-two page not far above the need for --pot, binary search on the
//      density when the charts do not fit);
//   3. packSkyline: charts sorted by area, each placed where its top edge is lowest (ties: least
//      waste), trying both 90-degree orientations;
//   4. placementsFor: the affine UV -> texel map of each chart; utilisation figures.
#include "lodbake/pack/atlas.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <numeric>
#include <optional>

namespace lodbake {
namespace {

// A chart turned to its minimum-area rectangle: rotate by -angle, then [minX, minX+w] x [minY, minY+h].
struct Oriented {
    double c = 1, s = 0;  // cos, sin of the angle
    double minX = 0, minY = 0, w = 0, h = 0;
    double uvArea = 0;
};

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

Oriented orientChart(const AtlasChart& chart) {
    std::vector<Vec2> hull = convexHull(chart.points);
    Oriented best;
    best.uvArea = chart.uvArea;
    double bestArea = 1e300;
    auto tryAngle = [&](double c, double s) {
        double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
        for (const Vec2& q : hull) {
            double x = c * q.x + s * q.y, y = -s * q.x + c * q.y;
            x0 = std::min(x0, x); x1 = std::max(x1, x);
            y0 = std::min(y0, y); y1 = std::max(y1, y);
        }
        double area = (x1 - x0) * (y1 - y0);
        if (area < bestArea * (1 - 1e-9)) {
            bestArea = area;
            best.c = c; best.s = s; best.minX = x0; best.minY = y0; best.w = x1 - x0; best.h = y1 - y0;
        }
    };
    tryAngle(1, 0);  // the chart as it is first: ties keep it unrotated
    for (size_t i = 0; i < hull.size(); ++i) {
        Vec2 e = hull[(i + 1) % hull.size()] - hull[i];
        double l = std::sqrt(dot(e, e));
        if (l > 0) tryAngle(e.x / l, e.y / l);
    }
    if (hull.empty()) { best.w = best.h = 0; }
    return best;
}

struct Rect {
    int x = 0, y = 0, w = 0, h = 0;
    bool rotated = false;
};

// Skyline bottom-left packer with best fit (lowest top edge, then least wasted area beneath).
class Skyline {
public:
    Skyline(int width, int height) : W_(width), H_(height) { segs_.push_back({0, 0, width}); }

    bool insert(int w, int h, Rect& out) {
        int bestTop = INT32_MAX;
        long long bestWaste = LLONG_MAX;
        size_t bestI = 0;
        int bestY = 0;
        bool bestRot = false, found = false;
        for (int rot = 0; rot < 2; ++rot) {
            int rw = rot ? h : w, rh = rot ? w : h;
            if (rot && w == h) break;
            for (size_t i = 0; i < segs_.size(); ++i) {
                int y;
                long long waste;
                if (!fits(i, rw, rh, y, waste)) continue;
                int top = y + rh;
                if (top < bestTop || (top == bestTop && waste < bestWaste)) {
                    bestTop = top; bestWaste = waste; bestI = i; bestY = y; bestRot = rot; found = true;
                }
            }
        }
        if (!found) return false;
        out.rotated = bestRot;
        out.w = bestRot ? h : w;
        out.h = bestRot ? w : h;
        out.x = segs_[bestI].x;
        out.y = bestY;
        place(bestI, out);
        usedW_ = std::max(usedW_, out.x + out.w);
        usedH_ = std::max(usedH_, out.y + out.h);
        return true;
    }
    int usedWidth() const { return usedW_; }
    int usedHeight() const { return usedH_; }

private:
    struct Seg { int x, y, w; };
    int W_, H_, usedW_ = 0, usedH_ = 0;
    std::vector<Seg> segs_;

    bool fits(size_t i, int w, int h, int& y, long long& waste) const {
        int x = segs_[i].x;
        if (x + w > W_) return false;
        y = 0;
        int left = w;
        for (size_t j = i; left > 0 && j < segs_.size(); ++j) {
            y = std::max(y, segs_[j].y);
            left -= segs_[j].w;
        }
        if (y + h > H_) return false;
        waste = 0;
        left = w;
        for (size_t j = i; left > 0 && j < segs_.size(); ++j) {
            int span = std::min(left, segs_[j].w);
            waste += (long long)(y - segs_[j].y) * span;
            left -= span;
        }
        return true;
    }

    void place(size_t i, const Rect& r) {
        Seg ns{r.x, r.y + r.h, r.w};
        int end = r.x + r.w;
        std::vector<Seg> out;
        out.reserve(segs_.size() + 2);
        for (size_t j = 0; j < i; ++j) out.push_back(segs_[j]);
        out.push_back(ns);
        for (size_t j = i; j < segs_.size(); ++j) {
            const Seg& s = segs_[j];
            int sEnd = s.x + s.w;
            if (sEnd <= end) continue;  // fully covered
            if (s.x < end) out.push_back({end, s.y, sEnd - end});
            else out.push_back(s);
        }
        segs_.clear();
        for (const Seg& s : out) {  // merge neighbours of equal height
            if (!segs_.empty() && segs_.back().y == s.y) segs_.back().w += s.w;
            else segs_.push_back(s);
        }
    }
};

struct Packing {
    std::vector<Rect> rects;  // per chart
    int width = 0, height = 0;
};

int texels(double extent, double t) { return std::max(1, int(std::ceil(extent * t - 1e-9))); }

std::optional<Packing> packSkyline(const std::vector<Oriented>& charts, const std::vector<size_t>& order, double t,
                                   int gutter, int binW, int binH) {
    Skyline sky(binW, binH);
    Packing p;
    p.rects.resize(charts.size());
    for (size_t i : order) {
        const Oriented& c = charts[i];
        Rect r;
        if (!sky.insert(texels(c.w, t) + gutter, texels(c.h, t) + gutter, r)) return std::nullopt;
        p.rects[i] = r;
    }
    p.width = sky.usedWidth();
    p.height = sky.usedHeight();
    return p;
}

double paddedArea(const std::vector<Oriented>& charts, double t, int gutter) {
    double a = 0;
    for (const Oriented& c : charts) a += double(texels(c.w, t) + gutter) * double(texels(c.h, t) + gutter);
    return a;
}

// The densest t in (lo, hi] at which the charts fit in binW x binH (lo fits or is 0).
std::optional<std::pair<double, Packing>> densestFit(const std::vector<Oriented>& charts, const std::vector<size_t>& order,
                                                     double hi, int gutter, int binW, int binH) {
    if (auto p = packSkyline(charts, order, hi, gutter, binW, binH)) return std::make_pair(hi, *p);
    double lo = 0;
    std::optional<Packing> loPack = packSkyline(charts, order, 1e-12, gutter, binW, binH);
    if (!loPack) return std::nullopt;
    for (int it = 0; it < 24; ++it) {
        double mid = 0.5 * (lo + hi);
        if (auto p = packSkyline(charts, order, mid, gutter, binW, binH)) { lo = mid; loPack = p; }
        else hi = mid;
    }
    return std::make_pair(std::max(lo, 1e-12), *loPack);
}

}  // namespace

AtlasResult packAtlas(const std::vector<AtlasChart>& input, const AtlasOptions& options) {
    // 1. Orientation.
    std::vector<Oriented> charts;
    charts.reserve(input.size());
    for (const AtlasChart& c : input) charts.push_back(orientChart(c));
    std::vector<size_t> order(charts.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        double aa = charts[a].w * charts[a].h, ab = charts[b].w * charts[b].h;
        if (aa != ab) return aa > ab;
        return std::max(charts[a].w, charts[a].h) > std::max(charts[b].w, charts[b].h);
    });
    const int maxSize = std::max(8, options.maxSize);
    int gutter = std::max(0, options.gutter);
    double tMax = options.maxTexelsPerUnit;

    // Gutters wider than the charts they separate (many small charts) cost more than the mips
    // they protect: narrow them until they take at most half of the padded area.
    while (gutter > 2 && paddedArea(charts, tMax, gutter) > 2 * paddedArea(charts, tMax, 0)) gutter /= 2;

    // 2-3. Page and density.
    std::optional<std::pair<double, Packing>> best;
    int pageW = 0, pageH = 0;
    for (;;) {
        if (!options.powerOfTwo) {
            // Strip packing at the density limit, a few strip widths; the smallest page wins.
            double a = paddedArea(charts, tMax, gutter);
            double bestArea = 1e300;
            for (double f : {0.85, 0.95, 1.0, 1.05, 1.15, 1.3, 1.5}) {
                int w = std::clamp(int(std::ceil(std::sqrt(a) * f)), 1, maxSize);
                auto p = packSkyline(charts, order, tMax, gutter, w, maxSize);
                if (!p) continue;
                double area = double(p->width) * p->height;
                if (area < bestArea) { bestArea = area; best = std::make_pair(tMax, *p); pageW = p->width; pageH = p->height; }
            }
            if (!best) {
                best = densestFit(charts, order, tMax, gutter, maxSize, maxSize);
                if (best) { pageW = best->second.width; pageH = best->second.height; }
            }
        } else {
            // The largest power-of-two page (square or 2:1) whose area is at most ~1.1x the need
            // at the density limit; then the densest packing that fits it.
            double need = paddedArea(charts, tMax, gutter);
            std::vector<std::pair<int, int>> pages;
            for (int w = 8; w <= maxSize; w *= 2) {
                pages.push_back({w, w});
                if (w / 2 >= 8) pages.push_back({w, w / 2});
            }
            std::sort(pages.begin(), pages.end(), [](auto a, auto b) { return double(a.first) * a.second < double(b.first) * b.second; });
            size_t pick = 0;
            for (size_t i = 0; i < pages.size(); ++i)
                if (double(pages[i].first) * pages[i].second <= 1.1 * need) pick = i;
            for (size_t i = pick; i < pages.size() && !best; ++i) {
                best = densestFit(charts, order, tMax, gutter, pages[i].first, pages[i].second);
                if (best) { pageW = pages[i].first; pageH = pages[i].second; }
            }
        }
        if (best || gutter == 0) break;
        gutter /= 2;  // too many charts for the page even at minimal size: narrower gutters
    }

    AtlasResult res;
    res.gutter = gutter;
    if (!best) {  // cannot happen for sane inputs (every chart at least 1 texel); keep a valid result
        res.width = res.height = 1;
        res.charts.resize(input.size());
        return res;
    }
    double t = best->first;
    const Packing& pk = best->second;
    // Non-power-of-two pages are a multiple of 4 texels (block-compression friendly, aligned rows).
    if (!options.powerOfTwo) {
        pageW = std::min(maxSize, (std::max(pageW, 4) + 3) / 4 * 4);
        pageH = std::min(maxSize, (std::max(pageH, 4) + 3) / 4 * 4);
    }
    res.width = pageW;
    res.height = pageH;
    res.texelsPerUnit = t;

    // 4. Placements and utilisation.
    double chartTexels = 0, boxTexels = 0;
    res.charts.resize(charts.size());
    for (size_t i = 0; i < charts.size(); ++i) {
        const Oriented& c = charts[i];
        const Rect& r = pk.rects[i];
        double ox = r.x + 0.5 * gutter, oy = r.y + 0.5 * gutter;
        ChartPlacement& P = res.charts[i];
        P.rotated90 = r.rotated;
        if (!r.rotated) P.m = {t * c.c, t * c.s, ox - t * c.minX, -t * c.s, t * c.c, oy - t * c.minY};
        else P.m = {-t * c.s, t * c.c, ox - t * c.minY, -t * c.c, -t * c.s, oy + t * c.w + t * c.minX};
        chartTexels += c.uvArea * t * t;
        boxTexels += c.w * c.h * t * t;
    }
    double page = double(res.width) * res.height;
    res.utilisation = chartTexels / page;
    res.boxUtilisation = boxTexels / page;
    return res;
}

}  // namespace lodbake
