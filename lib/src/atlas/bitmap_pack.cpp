// Charts placed on a bitmap page in a given order (bitmap_pack.h).
#include "atlas/bitmap_pack.h"

#include <algorithm>
#include <utility>

#include "lodbake/core/parallel.h"

namespace lodbake::atlas_detail {
namespace {

// A packing's start: the empty page.
PackState emptyPack(const Footprints& fp, int binW, int binH) {
    PackState state{BitmapPage((binW + 2 * fp.radius) / fp.scale, (binH + 2 * fp.radius) / fp.scale), Packing{}};
    state.packing.slots.resize(fp.charts.size());
    return state;
}

// Places the charts order[first, last) into `state`; false when one finds no place (or, with a
// bound, costs too much). See packBitmap for `prefix` and `inPlace`.
bool packSteps(const Footprints& fp, const std::vector<size_t>& order, size_t first, size_t last, PackState& state, Placement placement,
               CostBound* bound, std::vector<PackState>* prefix, const std::vector<std::array<int, 2>>* inPlace) {
    const int scale = fp.scale, r = fp.radius;
    BitmapPage& page = state.page;
    Packing& p = state.packing;
    // The page's cost when the bitmap's used part is w x h blocks.
    auto costOf = [&](int w, int h) { return pageCost(std::max(1, w * scale - 2 * r), std::max(1, h * scale - 2 * r), bound->maxSize()); };
    for (size_t step = first; step < last; ++step) {
        if (prefix) prefix->push_back(state);
        const size_t i = order[step];
        Slot& s = p.slots[i];
        // With the top-edge rule a chart's key is its top edge: positions whose top edge costs more
        // than the bound are not searched (the lowest one that remains is the rule's choice).
        double firstLimit = 1e300;
        if (bound && placement == Placement::TopEdge) {
            const double b = bound->limit();
            int lo = page.usedHeight(), hi = page.height();  // the highest top edge within the bound
            if (costOf(page.usedWidth(), lo) > b) return false;
            while (lo < hi) {
                const int mid = lo + (hi - lo + 1) / 2;
                if (costOf(page.usedWidth(), mid) > b) hi = mid - 1;
                else lo = mid;
            }
            firstLimit = lo + 1;
        }
        double bestKey = firstLimit;
        const bool kept = inPlace && page.onPage(fp.charts[i][0].rot[0], (*inPlace)[i][0], (*inPlace)[i][1]);
        if (kept) {
            s.x = (*inPlace)[i][0]; s.y = (*inPlace)[i][1]; s.rotation = 0; s.orientation = 0;
            bestKey = -1;
        }
        for (size_t v = 0; v < fp.charts[i].size() && !kept; ++v)
            for (int rot = 0; rot < fp.charts[i][v].turns; ++rot) {
                const Footprint& f = fp.charts[i][v].rot[size_t(rot)];
                const double key = placement == Placement::Gravity ? f.centroidRow : f.h;
                int x, y;
                if (page.find(f, key, bestKey, x, y)) {
                    bestKey = y + key;
                    s.x = x; s.y = y; s.rotation = rot; s.orientation = v;
                }
            }
        if (bestKey == firstLimit) return false;
        const ChartFootprints& c = fp.charts[i][s.orientation];
        s.gw = c.gw;
        s.gh = c.gh;
        p.rasterTexels += c.raster;
        p.footprintTexels += c.footprint;
        page.place(c.rot[size_t(s.rotation)], s.x, s.y);
        if (bound && costOf(page.usedWidth(), page.usedHeight()) > bound->limit()) return false;
        // Back to texels: the chart's grid turns inside its block-rounded footprint.
        int fw = c.cw * scale, fh = c.ch * scale;
        s.x *= scale;
        s.y *= scale;
        if (s.rotation == 1) s.x += fh - s.gh;
        if (s.rotation == 2) { s.x += fw - s.gw; s.y += fh - s.gh; }
        if (s.rotation == 3) s.y += fw - s.gw;
        s.x -= r;  // page coordinates: the bitmap starts `radius` texels before the page
        s.y -= r;
    }
    return true;
}

// The packing of every chart placed in `state`: its page size (offered to the bound).
Packing packed(const Footprints& fp, PackState& state, CostBound* bound) {
    Packing& p = state.packing;
    p.width = std::max(1, state.page.usedWidth() * fp.scale - 2 * fp.radius);
    p.height = std::max(1, state.page.usedHeight() * fp.scale - 2 * fp.radius);
    if (bound) bound->offer(pageCost(p.width, p.height, bound->maxSize()));
    return std::move(p);
}

}  // namespace

// Placement search on large pages runs on a grid of scale x scale texel blocks (charts and their
// gutters rounded up to whole blocks), keeping the search near 512 blocks across.
int searchScale(double side) { return std::clamp(int(side / 512), 1, 8); }

// The search grid for these charts: texel-aligned ones are placed on whole kAlignedBlock blocks
// (a multiple of every searchScale, so their offsets stay multiples of it).
int searchScale(double side, const Orientations& charts) {
    for (const auto& c : charts)
        if (!c.empty() && c.front().aligned) return kAlignedBlock;
    return searchScale(side);
}

// `prefix`, when given, receives the state before each chart of `order` is placed; `from`, when
// given, is such a state of an order that agrees with `order` on its first `fromIndex` charts:
// the packing resumes there (the same charts placed the same way). `inPlace`, when given, holds
// per chart a cell its first orientation takes, unturned, when it lies on the page ({-1, -1}:
// none); such charts come first in `order` and may overlap each other (AtlasChart::inPlace).
std::optional<Packing> packBitmap(const Footprints& fp, const std::vector<size_t>& order, int binW, int binH,
                                  Placement placement, CostBound* bound,
                                  std::vector<PackState>* prefix, const PackState* from, size_t fromIndex,
                                  const std::vector<std::array<int, 2>>* inPlace) {
    PackState state = from ? *from : emptyPack(fp, binW, binH);
    if (!packSteps(fp, order, from ? fromIndex : 0, order.size(), state, placement, bound, prefix, inPlace)) return std::nullopt;
    return packed(fp, state, bound);
}

// The same at density t from the charts: their footprints are rasterised in the packing order, in
// batches that double, so a packing that fails at a chart has not rasterised most of the charts
// after it (on pages the charts overfill, the large ones first fail early).
std::optional<Packing> packBitmap(const Orientations& charts, const std::vector<size_t>& order, double t,
                                  int gutter, int binW, int binH, int scale, int threads) {
    if (!footprintsFit(charts, t, gutter, scale, binW, binH)) return std::nullopt;
    Footprints fp = noFootprints(charts.size(), t, gutter, scale);
    PackState state = emptyPack(fp, binW, binH);
    for (size_t first = 0, batch = size_t(8 * std::max(1, threads)); first < order.size(); first += batch, batch *= 2) {
        const size_t last = std::min(order.size(), first + batch);
        addFootprints(charts, std::vector<size_t>(order.begin() + long(first), order.begin() + long(last)), fp, threads);
        if (!packSteps(fp, order, first, last, state, Placement::TopEdge, nullptr, nullptr, nullptr)) return std::nullopt;
    }
    return packed(fp, state, nullptr);
}

}  // namespace lodbake::atlas_detail
