// Shape-aware page packing of `pack` (packAtlas): the page search. Placing the charts on a page in
// one order is bitmap_pack.cpp; the T0 shelf packer is shelf_pack.cpp; a chart's orientation and
// footprints are chart_footprint.cpp, the page bitmap bitmap_page.h.
//
// References: Freeman & Shapira, "Determining the minimum-area encasing rectangle for an
// arbitrary closed curve" (1975), minimum-area rectangle from a hull edge; bitmap ("tetris")
// chart packing as in Lévy et al., "Least Squares Conformal Maps" (2002), section 5.
//
// Pipeline of packAtlas:
//   1. chartFrames: convex hull of each chart's UV points, minimum-area bounding rectangle;
//      chartOrders: the chart orders tried;
//   2. footprintsAt: chartRuns rasterises each chart (conservatively, as runs of cells per row)
//      at the density and grows it by the gutter radius; the four quarter turns of its
//      block-rounded cells, computed once per density and shared by every page tried;
//   3. page size and density: packFreeSize runs packBitmap at the density limit into twenty strip
//      widths (five for very many charts), three sorted chart orders plus eight shuffled ones (at
//      most 32 charts) and two placement rules (smallest page wins; the trials run on
//      AtlasOptions::threads threads, the winner is picked in trial order), then, for few charts,
//      a local search of pairwise swaps on the winner's order (improveOrder: a swap (a, b) resumes
//      from the winner's packing before position a). Trials share the smallest page finished so
//      far (CostBound): one whose partial page already costs more stops, exact and independent of
//      the thread count since such a trial cannot win; packPowerOfTwo
//      takes the largest power-of-two page not far above the need; densestFit searches the
//      density when the charts do not fit. packBitmap places each chart at the lowest free
//      position of each quarter turn (the lowest top edge, or the lowest centre of gravity, wins);
//      no gutter along the page border (the samplers clamp to the edge); the search skips rows
//      whose longest free run is shorter than the chart's row needs (past every position a page
//      row too full for any of the chart's rows rules out), and jumps over a whole occupied
//      stretch on a collision, testing the footprint as rectangular blocks of up to 16 rows,
//      each against the union of its rows (a set texel there is a collision, and the union's
//      stretches are the longest);
//   4. placeCharts: the affine UV -> texel map of each chart (placementFor); utilisation figures.
#include "lodbake/atlas/atlas.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <numeric>
#include <optional>

#include "atlas/bitmap_pack.h"
#include "atlas/chart_footprint.h"
#include "lodbake/core/parallel.h"

namespace lodbake {
namespace {

using namespace atlas_detail;

// Strip widths tried, relative to the side of the charts' padded area.
constexpr double kStripWidths[] = {0.6, 0.65, 0.7, 0.75, 0.8, 0.85, 0.9, 0.95, 1.0, 1.05,
                                   1.1, 1.15, 1.2, 1.25, 1.3, 1.4, 1.5, 1.6, 1.8, 2.0};
constexpr size_t kManyCharts = 32;            // more charts: no local search of the chart order
constexpr size_t kManyChartsForOrders = 32;   // more charts: only the first sorted order
constexpr size_t kManyChartsForRules = 256;
constexpr size_t kManyChartsWidthStride = 4;
constexpr int kShuffledOrders = 8;
constexpr int kOrderSweeps = 8;
// Trials on large pages (search grids of 2 x 2 texel blocks or coarser, or a padded side of at
// least kRankFromSide texels, where a one-texel search of every trial and swap costs seconds for
// a fraction of a percent of page area), when there are more than kRankFromTrials of them, and
// the swaps of the order search there, are ranked on a grid twice as coarse first: those within
// kRankSlack of the coarse minimum (at most kFineTrials of them, the cheapest) are packed on the
// search grid. Fewer trials are all packed there: each one counts. Shuffled orders pay off for
// up to kManyChartsForOrders charts; above, the first sorted order alone packs pages as small
// (within 1%) in a quarter of the time.
constexpr int kRankFromScale = 2;
constexpr double kRankFromSide = 512;
constexpr size_t kRankFromTrials = 64;
constexpr double kRankSlack = 1.03;
constexpr size_t kFineTrials = 16;
constexpr double kCoverageSlack = 4;  // mayFit: chart coverage may exceed the page this many times

// The trials worth packing on the search grid after a coarse ranking: those whose coarse cost is
// within `limit` (a CostBound's with slack), at most kFineTrials of the cheapest (earlier trials
// first on equal costs), in trial order. It depends on the costs alone, not on the thread count.
std::vector<size_t> nearBest(const std::vector<double>& cost, double limit) {
    std::vector<size_t> out;
    for (size_t i = 0; i < cost.size(); ++i)
        if (cost[i] <= limit) out.push_back(i);
    std::stable_sort(out.begin(), out.end(), [&](size_t x, size_t y) { return cost[x] < cost[y]; });
    if (out.size() > kFineTrials) out.resize(kFineTrials);
    std::sort(out.begin(), out.end());
    return out;
}

// `order` with charts a and b swapped, packed from `prefix` (the states of `order` before each
// chart: both orders place the same charts before position a).
std::optional<Packing> packSwapped(const Footprints& fp, const std::vector<size_t>& order, std::pair<size_t, size_t> swap,
                                   const std::vector<PackState>& prefix, int width, int maxSize, Placement rule, CostBound& bound) {
    std::vector<size_t> o = order;
    std::swap(o[swap.first], o[swap.second]);
    const size_t a = swap.first;
    return a < prefix.size() ? packBitmap(fp, o, width, maxSize, rule, &bound, nullptr, &prefix[a], a)
                             : packBitmap(fp, o, width, maxSize, rule, &bound);
}

// Local search on the winning chart order (few charts): every swap of two charts is packed at the
// winner's strip width and rule (on `threads` threads); the swap giving the smallest page, if it
// beats the best so far, is kept and the search goes on from it, for at most kOrderSweeps rounds.
// With `coarse` footprints (large pages), each round ranks the swaps on that grid first and packs
// only the near-best ones (nearBest) on the search grid.
// `keep(packing)` takes a packing when it is the smallest page yet and says whether it did.
// It finds tighter pages than many more random orders would.
template <class Keep>
void improveOrder(const Footprints& fp, const Footprints* coarse, std::vector<size_t> order, int width, int maxSize, Placement rule,
                  int threads, double best, Keep&& keep) {
    std::vector<std::pair<size_t, size_t>> swaps;
    for (size_t a = 0; a < order.size(); ++a)
        for (size_t b = a + 1; b < order.size(); ++b) swaps.push_back({a, b});
    auto prefixOf = [&](const Footprints& f) {
        std::vector<PackState> prefix;
        prefix.reserve(order.size());
        packBitmap(f, order, width, maxSize, rule, nullptr, &prefix);
        return prefix;
    };
    for (int round = 0; round < kOrderSweeps; ++round) {
        std::vector<size_t> tried(swaps.size());
        std::iota(tried.begin(), tried.end(), size_t(0));
        if (coarse) {
            const std::vector<PackState> prefix = prefixOf(*coarse);
            const std::optional<Packing> now = packBitmap(*coarse, order, width, maxSize, rule);
            CostBound rank(maxSize, now ? pageCost(now->width, now->height, maxSize) : 1e300, kRankSlack);
            std::vector<double> cost(swaps.size(), 1e300);
            parallelFor(swaps.size(), threads, [&](size_t i) {
                if (auto p = packSwapped(*coarse, order, swaps[i], prefix, width, maxSize, rule, rank))
                    cost[i] = pageCost(p->width, p->height, maxSize);
            });
            tried = nearBest(cost, rank.limit());
        }
        std::vector<std::optional<Packing>> packed(swaps.size());
        CostBound bound(maxSize, best);
        // A swap (a, b) places the same charts as the order before position a: it resumes there.
        const std::vector<PackState> prefix = prefixOf(fp);
        parallelFor(tried.size(), threads, [&](size_t k) {
            packed[tried[k]] = packSwapped(fp, order, swaps[tried[k]], prefix, width, maxSize, rule, bound);
        });
        size_t kept = swaps.size();
        for (size_t i = 0; i < swaps.size(); ++i)
            if (keep(packed[i])) kept = i;
        if (kept == swaps.size()) return;
        std::swap(order[swaps[kept].first], order[swaps[kept].second]);
        best = bound.best();
    }
}

double paddedArea(const std::vector<Oriented>& charts, double t, int gutter) {
    double a = 0;
    for (const Oriented& c : charts) a += double(texels(c.w, t) + gutter) * double(texels(c.h, t) + gutter);
    return a;
}

// The gutter the search starts from: halved while the gutters take more than half of the padded
// area (many small charts), where they cost more than the mips they protect.
int narrowedGutter(const std::vector<Oriented>& charts, double t, int gutter) {
    while (gutter > 2 && paddedArea(charts, t, gutter) > 2 * paddedArea(charts, t, 0)) gutter /= 2;
    return gutter;
}

// False when the charts cannot fit a binW x binH page at density t: a chart's rectangle is
// longer than the page in either quarter turn, or their coverage exceeds the page many times
// over (the slack allows for charts whose triangles overlap in UV). Footprints are rasterised
// at t only when this holds, so their memory stays within a few pages whatever the density
// limit: a level that switches at a huge coverage (a near-exact simplification) asks for one.
bool mayFit(const std::vector<Oriented>& charts, double t, int binW, int binH) {
    const int shortSide = std::min(binW, binH), longSide = std::max(binW, binH);
    double area = 0;
    for (const Oriented& c : charts) {
        const int a = texels(c.w, t), b = texels(c.h, t);
        if (std::min(a, b) > shortSide || std::max(a, b) > longSide) return false;
        area += c.uvArea * t * t;
    }
    return area <= kCoverageSlack * double(binW) * binH;
}

// A chart's orientation without its triangles: what the size, order and fit rules read (a
// million-triangle chart set's triangles are some 100 MB a copy).
Oriented rectangleOf(const Oriented& o) {
    Oriented r;
    r.c = o.c;
    r.s = o.s;
    r.minX = o.minX;
    r.minY = o.minY;
    r.w = o.w;
    r.h = o.h;
    r.aligned = o.aligned;
    r.turns = o.turns;
    r.uvArea = o.uvArea;
    return r;
}

std::vector<Oriented> firstRectangles(const Orientations& charts) {
    std::vector<Oriented> first;
    first.reserve(charts.size());
    for (const auto& c : charts) first.push_back(rectangleOf(c.front()));
    return first;
}

// The charts packed in binW x binH at density t, when they fit.
std::optional<std::pair<double, Packing>> fitAt(const Orientations& charts, const std::vector<size_t>& order, int threads,
                                                double t, int gutter, int binW, int binH) {
    if (!mayFit(firstRectangles(charts), t, binW, binH)) return std::nullopt;
    if (auto p = packBitmap(charts, order, t, gutter, binW, binH, searchScale(std::max(binW, binH), charts), threads))
        return std::make_pair(t, *p);
    return std::nullopt;
}

// The bisection of densestFit: [lo, hi] narrowed to 0.5% of hi, `loPack` the packing at lo (lo
// fits, hi does not). Each step packs at the middle (fit(t, threads)). On two threads or more the
// step after it is packed at once, on the branch the packing at lo predicts (a packing's area grows
// as t^2): the points packed and what they give are the serial bisection's, so only the time
// depends on the thread count (the packing's own threads, mostly idle while it places charts, are
// shared by both).
// Every density the bisection packs from a bracket [lo, hi] lies below 0.9975 hi (a middle, while
// hi - lo > 0.005 hi): with lo below `wanted` (> 1e-12, densestFit's least) and 0.998 hi at most `wanted`, the densest fit
// is known to lie below `wanted` and the search stops, where the serial bisection would (the
// speculative step is not applied past that point).
template <class Fit>
void bisectFit(const std::vector<Oriented>& first, double& lo, double& hi, Packing& loPack, int binW, int binH, int threads,
               double wanted, Fit&& fit) {
    const int n = resolveThreads(threads);
    // The packing at mid (or none) narrows the bracket as the serial step does.
    auto apply = [&](double mid, std::optional<Packing>& p) {
        if (p) lo = mid, loPack = std::move(*p);
        else hi = mid;
    };
    auto below = [&] { return wanted > 1e-12 && lo < wanted && 0.998 * hi <= wanted; };
    while (hi - lo > 0.005 * hi && !below()) {
        const double mid = 0.5 * (lo + hi);
        if (!mayFit(first, mid, binW, binH)) {
            hi = mid;
            continue;
        }
        const double filled = double(loPack.width) * loPack.height / (double(binW) * binH);
        const bool guessFits = filled * (mid / lo) * (mid / lo) <= 1;
        const double nextLo = guessFits ? mid : lo, nextHi = guessFits ? hi : mid, next = 0.5 * (nextLo + nextHi);
        std::optional<Packing> now, then;
        if (n < 2 || !(nextHi - nextLo > 0.005 * nextHi) || !mayFit(first, next, binW, binH)) {
            now = fit(mid, threads);
            apply(mid, now);
            continue;
        }
        parallelFor(2, 2, [&](size_t k) { (k == 0 ? now : then) = fit(k == 0 ? mid : next, std::max(1, n / 2)); });
        apply(mid, now);
        if (bool(now) == guessFits && !below()) apply(next, then);
    }
}

// The densest t in (0, hi] at which the charts fit in binW x binH, to 0.5%: a bracket around the
// density whose padded area fills 3/4 of the page (area grows as t^2), narrowed by bisection.
// With `wanted` > 0 (AtlasOptions::minTexelsPerUnit) the bisection stops once the densest fit is
// known to lie below it: the fit returned is then a looser one, at a density below `wanted`. A fit
// exists then as it does without: the search for one is the same.
std::optional<std::pair<double, Packing>> densestFit(const Orientations& charts, const std::vector<size_t>& order, int threads,
                                                     double hi, int gutter, int binW, int binH, double wanted = 0) {
    if (auto p = fitAt(charts, order, threads, hi, gutter, binW, binH)) return p;
    const int scale = searchScale(std::max(binW, binH), charts);
    auto fit = [&](double t, int th) { return packBitmap(charts, order, t, gutter, binW, binH, scale, th); };
    const std::vector<Oriented> first = firstRectangles(charts);
    double t = std::min(hi, hi * std::sqrt(0.75 * double(binW) * binH / std::max(1e-300, paddedArea(first, hi, gutter))));
    // The charts' coverage bounds the start too (it binds only when texels() saturates at a huge hi).
    double uvArea = 0;
    for (const Oriented& c : first) uvArea += c.uvArea;
    if (uvArea > 0) t = std::min(t, std::sqrt(double(binW) * binH / uvArea));
    double lo = 0;
    std::optional<Packing> loPack;
    for (int k = 0; k < 64 && !loPack; ++k, t *= 0.8) {
        if (!mayFit(first, t, binW, binH)) hi = t;
        else if (auto p = fit(t, threads)) { lo = t; loPack = p; }
        else hi = t;
    }
    if (!loPack) {
        loPack = fit(1e-12, threads);
        if (!loPack) return std::nullopt;
        lo = 1e-12;
    }
    bisectFit(first, lo, hi, *loPack, binW, binH, threads, wanted, fit);
    return std::make_pair(std::max(lo, 1e-12), *loPack);
}

// The chart orders tried: largest rectangle first (ties: longest side), longest side first and
// largest coverage first. With many charts the order matters less than the time it costs (the
// hundreds of charts of coarse levels and CAD assemblies): only the first. With fewer,
// kShuffledOrders shuffles of the first from a fixed seed (deterministic), which find nestings
// the sorted orders miss.
std::vector<std::vector<size_t>> chartOrders(const std::vector<Oriented>& charts) {
    std::vector<size_t> order(charts.size());
    std::iota(order.begin(), order.end(), size_t(0));
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
        double aa = charts[a].w * charts[a].h, ab = charts[b].w * charts[b].h;
        if (aa != ab) return aa > ab;
        return std::max(charts[a].w, charts[a].h) > std::max(charts[b].w, charts[b].h);
    });
    std::vector<std::vector<size_t>> orders{order, order, order};
    std::stable_sort(orders[1].begin(), orders[1].end(), [&](size_t a, size_t b) {
        return std::max(charts[a].w, charts[a].h) > std::max(charts[b].w, charts[b].h);
    });
    std::stable_sort(orders[2].begin(), orders[2].end(), [&](size_t a, size_t b) { return charts[a].uvArea > charts[b].uvArea; });
    if (charts.size() > kManyChartsForOrders) orders.resize(1);
    else {
        uint64_t seed = 0x9e3779b97f4a7c15ull;
        for (int k = 0; k < kShuffledOrders; ++k) {
            std::vector<size_t> o = order;
            for (size_t i = o.size(); i > 1; --i) {
                seed = seed * 6364136223846793005ull + 1442695040888963407ull;
                std::swap(o[i - 1], o[size_t((seed >> 33) % i)]);
            }
            orders.push_back(o);
        }
    }
    // An order equal to an earlier one packs the same pages and cannot win (the first tried wins
    // ties): only the first is kept (few charts have few distinct orders).
    std::vector<std::vector<size_t>> distinct;
    for (std::vector<size_t>& o : orders)
        if (std::find(distinct.begin(), distinct.end(), o) == distinct.end()) distinct.push_back(std::move(o));
    return distinct;
}

// The chosen packing: density, packing and page size.
struct PagePick {
    std::optional<std::pair<double, Packing>> best;  // density (texels per UV unit) and packing
    int width = 0, height = 0;                       // page, texels
};

// A page of free size: every (placement rule, chart order, strip width) packed at the density
// limit tMax, on options.threads threads, each into its own slot; the smallest page (rounded to 4
// texels; on equal areas the squarer one, then the first tried) wins, in that fixed order, so the
// result does not depend on the thread count. Strip widths lie around the side of the charts'
// padded area (their coverage plus a gutter ring). For few charts a local search of pairwise
// swaps on the winner's order follows. Very many charts try one rule and every
// kManyChartsWidthStride-th width only (the page area varies little across widths there). When
// the padded area exceeds the page, or nothing fits, the densest fit of maxSize x maxSize (a
// looser one when that lies below `wanted`: densestFit); with `exact` (texel-aligned charts, which only the density limit serves) a fit at tMax or none.
PagePick packFreeSize(const Orientations& turned, const std::vector<Oriented>& charts, const std::vector<std::vector<size_t>>& orders,
                      double tMax, int gutter, int maxSize, int threads, bool exact, double wanted) {
    PagePick pick;
    double a = 0;
    for (const Oriented& c : charts) a += std::pow(std::sqrt(c.uvArea) * tMax + gutter, 2);
    const int scale = searchScale(std::sqrt(a), turned);
    double bestArea = 1e300;
    const bool manyCharts = charts.size() > kManyChartsForRules;
    const std::vector<Placement> rules = manyCharts ? std::vector<Placement>{Placement::TopEdge}
                                                    : std::vector<Placement>{Placement::TopEdge, Placement::Gravity};
    const size_t widthStride = manyCharts ? kManyChartsWidthStride : 1;
    auto stripWidth = [&](size_t k) { return std::clamp(int(std::ceil(std::sqrt(a) * kStripWidths[k])), 1, maxSize); };
    struct Trial {
        Placement rule;
        size_t order;
        int width;
    };
    std::vector<Trial> trials;
    if (a <= double(maxSize) * maxSize)
        for (Placement rule : rules)
            for (size_t o = 0; o < orders.size(); ++o)
                for (size_t k = 0; k < std::size(kStripWidths); k += widthStride)
                    if (k == 0 || stripWidth(k) != stripWidth(k - widthStride)) trials.push_back({rule, o, stripWidth(k)});
    // Rasterised only for the trials: at a density whose padded area exceeds the page they would
    // take memory in proportion to tMax^2 for nothing.
    // Large pages with many trials: ranked on a twice coarser grid first (see kRankFromScale).
    const bool ranked = (scale >= kRankFromScale || std::sqrt(a) >= kRankFromSide) && trials.size() > kRankFromTrials;
    // A trial whose strip some chart cannot lie in fails: it is not packed, and when every trial
    // fails the footprints are not rasterised (the ranking picks among failures alone).
    auto sidesFit = [&](const Trial& tr, int s) { return footprintsFit(turned, tMax, gutter, s, tr.width, maxSize); };
    const bool anyFits = std::any_of(trials.begin(), trials.end(), [&](const Trial& tr) { return sidesFit(tr, scale); });
    Footprints coarse;
    const Footprints fp = !anyFits ? Footprints{} : footprintsAt(turned, tMax, gutter, scale, threads, ranked ? &coarse : nullptr);
    std::vector<std::optional<Packing>> packed(trials.size());
    std::vector<size_t> fine(trials.size());
    std::iota(fine.begin(), fine.end(), size_t(0));
    if (!anyFits) fine.clear();
    if (ranked && anyFits) {
        std::vector<double> cost(trials.size(), 1e300);
        CostBound rank(maxSize, 1e300, kRankSlack);
        parallelFor(trials.size(), threads, [&](size_t i) {
            if (!sidesFit(trials[i], coarse.scale)) return;
            if (auto p = packBitmap(coarse, orders[trials[i].order], trials[i].width, maxSize, trials[i].rule, &rank))
                cost[i] = pageCost(p->width, p->height, maxSize);
        });
        fine = nearBest(cost, rank.limit());
    }
    // Run (not picked) strip widths nearest the padded side first: their pages are usually the
    // smallest, and a small bound found early stops the other trials sooner. The winner is the
    // same in any run order (CostBound).
    std::vector<size_t> run = fine;
    std::stable_sort(run.begin(), run.end(), [&](size_t x, size_t y) {
        return std::abs(trials[x].width - std::sqrt(a)) < std::abs(trials[y].width - std::sqrt(a));
    });
    CostBound bound(maxSize);
    parallelFor(run.size(), threads, [&](size_t k) {
        const Trial& tr = trials[run[k]];
        if (sidesFit(tr, scale)) packed[run[k]] = packBitmap(fp, orders[tr.order], tr.width, maxSize, tr.rule, &bound);
    });
    auto keepIfSmaller = [&](std::optional<Packing>& p) {
        if (!p) return false;
        const double area = pageCost(p->width, p->height, maxSize);
        if (area >= bestArea) return false;
        bestArea = area;
        pick.best = std::make_pair(tMax, std::move(*p));
        pick.width = roundToFour(pick.best->second.width, maxSize);
        pick.height = roundToFour(pick.best->second.height, maxSize);
        return true;
    };
    size_t winner = trials.size();
    for (size_t i = 0; i < packed.size(); ++i)
        if (keepIfSmaller(packed[i])) winner = i;
    if (winner < trials.size() && charts.size() > 2 && charts.size() <= kManyCharts)
        improveOrder(fp, ranked ? &coarse : nullptr, orders[trials[winner].order], trials[winner].width, maxSize, trials[winner].rule, threads, bestArea,
                     keepIfSmaller);
    if (!pick.best) {
        // The fit at tMax on the search grid packs the trials' footprints (texel-aligned charts
        // take the same grid on any page): they are not rasterised again.
        const bool sameGrid = anyFits && scale == searchScale(maxSize, turned) && mayFit(charts, tMax, maxSize, maxSize);
        if (exact && sameGrid && footprintsFit(turned, tMax, gutter, scale, maxSize, maxSize)) {
            if (auto p = packBitmap(fp, orders[0], maxSize, maxSize)) pick.best = std::make_pair(tMax, std::move(*p));
        } else {
            pick.best = exact ? fitAt(turned, orders[0], threads, tMax, gutter, maxSize, maxSize)
                              : densestFit(turned, orders[0], threads, tMax, gutter, maxSize, maxSize, wanted);
        }
        if (pick.best) { pick.width = pick.best->second.width; pick.height = pick.best->second.height; }
    }
    return pick;
}

// A power-of-two page: the largest one (square or 2:1) whose area is at most 1.1x the padded
// area needed at the density limit, then the densest packing that fits it (larger pages when
// none does).
PagePick packPowerOfTwo(const Orientations& turned, const std::vector<Oriented>& charts, const std::vector<size_t>& order,
                        double tMax, int gutter, int maxSize, int threads) {
    PagePick pick;
    double need = paddedArea(charts, tMax, gutter);
    std::vector<std::pair<int, int>> pages;
    for (int w = 8; w <= maxSize; w *= 2) {
        pages.push_back({w, w});
        if (w / 2 >= 8) pages.push_back({w, w / 2});
    }
    std::sort(pages.begin(), pages.end(), [](auto a, auto b) { return double(a.first) * a.second < double(b.first) * b.second; });
    size_t first = 0;
    for (size_t i = 0; i < pages.size(); ++i)
        if (double(pages[i].first) * pages[i].second <= 1.1 * need) first = i;
    for (size_t i = first; i < pages.size() && !pick.best; ++i) {
        pick.best = densestFit(turned, order, threads, tMax, gutter, pages[i].first, pages[i].second);
        if (pick.best) { pick.width = pages[i].first; pick.height = pages[i].second; }
    }
    return pick;
}

// Charts marked inPlace kept where their UVs are, on a maxSize x maxSize page (texel-aligned, one
// texel per UV unit); the others placed around them, largest first, on whole texels. The marked
// charts are one texture's islands in its texels: they fit in place where no search packs them
// into the same page (the texture itself holds them), and need no gutter between each other, as
// the texels around each are the texture's own.
PagePick packInPlace(const std::vector<AtlasChart>& input, const Orientations& turned, const std::vector<size_t>& order, int gutter,
                     int maxSize, int threads) {
    PagePick pick;
    // Kept charts need no block grid (their offset is 0, which every mip divides): whole texels
    // let islands a few texels apart keep their places.
    if (!footprintsFit(turned, 1.0, gutter, 1, maxSize, maxSize)) return pick;
    const Footprints fp = footprintsAt(turned, 1.0, gutter, 1, threads);
    std::vector<std::array<int, 2>> cells(turned.size(), {-1, -1});
    std::vector<size_t> inPlaceFirst;
    for (size_t i = 0; i < turned.size(); ++i) {
        const Oriented& c = turned[i][0];
        if (input[i].inPlace && c.minX >= 0 && c.minY >= 0) {
            cells[i] = {int(c.minX), int(c.minY)};
            inPlaceFirst.push_back(i);
        }
    }
    for (size_t i : order)
        if (cells[i][0] < 0) inPlaceFirst.push_back(i);
    if (auto p = packBitmap(fp, inPlaceFirst, maxSize, maxSize, Placement::TopEdge, nullptr, nullptr, nullptr, 0, &cells)) {
        // Power-of-two sides (within maxSize) whatever the option: the kept charts' texels then
        // fall on the same mip texels as in the original's (power-of-two) texture.
        auto side = [&](int texels) {
            int pot = 8;
            while (pot < texels && pot < maxSize) pot *= 2;
            return pot <= maxSize ? pot : roundToFour(texels, maxSize);
        };
        pick.width = side(p->width);
        pick.height = side(p->height);
        pick.best = std::make_pair(1.0, std::move(*p));
    }
    return pick;
}

// The affine UV -> page map of every chart, and the utilisation figures of the page.
void placeCharts(const Orientations& turned, const std::vector<Oriented>& charts, const Packing& pk, double t, int gutter,
                 AtlasResult& res) {
    double chartTexels = 0, boxTexels = 0;
    res.charts.resize(charts.size());
    for (size_t i = 0; i < charts.size(); ++i) {
        const Oriented& c = turned[i][pk.slots[i].orientation];
        ChartPlacement& P = res.charts[i];
        P.rotation = pk.slots[i].rotation;
        P.m = placementFor(c, pk.slots[i], t, (gutter + 1) / 2);
        chartTexels += c.uvArea * t * t;
        boxTexels += charts[i].w * charts[i].h * t * t;  // the minimum-area rectangle
    }
    double page = double(res.width) * res.height;
    res.utilisation = chartTexels / page;
    res.boxUtilisation = boxTexels / page;
    res.rasterUtilisation = double(pk.rasterTexels) / page;
    res.footprintUtilisation = double(pk.footprintTexels) / page;
}

}  // namespace

std::vector<ChartFrame> chartFrames(const std::vector<AtlasChart>& charts, const AtlasOptions& options) {
    std::vector<ChartFrame> frames(charts.size());
    parallelFor(charts.size(), options.threads, [&](size_t i) { frames[i] = chartFrame(charts[i], options.texelAligned); });
    return frames;
}

AtlasResult packAtlas(const std::vector<AtlasChart>& input, const AtlasOptions& options, const std::vector<ChartFrame>* frames) {
    // 1. Orientation: each chart turned to its minimum-area rectangle.
    std::vector<ChartFrame> found;
    if (!frames) frames = &(found = chartFrames(input, options));
    Orientations turned(input.size());
    std::vector<Oriented> charts(input.size());  // each chart's first orientation, its rectangle (sizes and orders)
    parallelFor(input.size(), options.threads, [&](size_t i) {
        turned[i] = {orientedIn(input[i], (*frames)[i], options.texelAligned)};
        charts[i] = rectangleOf(turned[i][0]);
    });
    const std::vector<std::vector<size_t>> orders = chartOrders(charts);
    const int maxSize = std::max(8, options.maxSize);
    const double tMax = options.maxTexelsPerUnit;
    int gutter = narrowedGutter(charts, tMax, std::max(0, options.gutter));

    // 2-3. Page and density; narrower gutters while the charts do not fit even at minimal size
    // (texel-aligned: while they do not fit at the density limit, which they must keep, down to
    // 2 texels: copied texels touching another chart's would bleed into each other at every mip).
    PagePick pick;
    const int narrowest = options.texelAligned ? std::min(gutter, 2) : 0;
    for (;;) {
        pick = options.powerOfTwo ? packPowerOfTwo(turned, charts, orders[0], tMax, gutter, maxSize, options.threads)
                                  : packFreeSize(turned, charts, orders, tMax, gutter, maxSize, options.threads, options.texelAligned,
                                                 options.minTexelsPerUnit);
        if ((pick.best && (!options.texelAligned || pick.best->first >= tMax)) || gutter <= narrowest) break;
        gutter = std::max(narrowest, gutter / 2);
    }
    // Texel-aligned charts that no search fits at their density: kept in place where they can be.
    for (int g = std::max(0, options.gutter); options.texelAligned && tMax == 1.0 && (!pick.best || pick.best->first < tMax);) {
        if (PagePick kept = packInPlace(input, turned, orders[0], g, maxSize, options.threads); kept.best) {
            pick = std::move(kept);
            gutter = g;
        }
        if (g <= narrowest) break;
        g = std::max(narrowest, g / 2);
    }

    AtlasResult res;
    res.gutter = gutter;
    if (!pick.best) {  // cannot happen for sane inputs (every chart at least 1 texel); keep a valid result
        res.width = res.height = 1;
        res.charts.resize(input.size());
        return res;
    }
    // Non-power-of-two pages are a multiple of 4 texels.
    res.width = options.powerOfTwo ? pick.width : roundToFour(pick.width, maxSize);
    res.height = options.powerOfTwo ? pick.height : roundToFour(pick.height, maxSize);
    res.texelsPerUnit = pick.best->first;

    // 4. Placements and utilisation.
    placeCharts(turned, charts, pick.best->second, res.texelsPerUnit, gutter, res);
    return res;
}

int atlasStartGutter(const std::vector<AtlasChart>& input, const AtlasOptions& options, const std::vector<ChartFrame>* frames) {
    std::vector<ChartFrame> found;
    if (!frames) frames = &(found = chartFrames(input, options));
    std::vector<Oriented> charts(input.size());
    for (size_t i = 0; i < input.size(); ++i) {
        const ChartFrame& f = (*frames)[i];
        charts[i].w = f.w;
        charts[i].h = f.h;
    }
    return narrowedGutter(charts, options.maxTexelsPerUnit, std::max(0, options.gutter));
}

}  // namespace lodbake
