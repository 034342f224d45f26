// Private to lib/src/atlas: charts placed on a bitmap page in a given order (packBitmap), and
// what the page search compares packings by (pageCost, CostBound). The search itself (strip
// widths, chart orders, density) is atlas.cpp; the page bitmap bitmap_page.h.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <optional>
#include <vector>

#include "atlas/bitmap_page.h"
#include "atlas/chart_footprint.h"

namespace lodbake::atlas_detail {

// A packing: each chart's slot and the page they take.
struct Packing {
    std::vector<Slot> slots;  // per chart
    int width = 0, height = 0;
    size_t rasterTexels = 0, footprintTexels = 0;  // charts' conservative raster, and with gutters
};

// Page side rounded up to a multiple of 4 texels (block-compression friendly, aligned rows).
inline int roundToFour(int side, int maxSize) { return std::min(maxSize, (std::max(side, 4) + 3) / 4 * 4); }

// What packFreeSize minimises: the page area (sides rounded to 4 texels), then the longer side.
// It never decreases as a packing's used width and height grow.
inline double pageCost(int width, int height, int maxSize) {
    const int pw = roundToFour(width, maxSize), ph = roundToFour(height, maxSize);
    return double(pw) * ph + 1e-3 * std::max(pw, ph);
}

// Placement search on large pages runs on a grid of scale x scale texel blocks (charts and their
// gutters rounded up to whole blocks), keeping the search near 512 blocks across.
int searchScale(double side);

// The search grid for these charts: texel-aligned ones are placed on whole kAlignedBlock blocks
// (a multiple of every searchScale, so their offsets stay multiples of it).
int searchScale(double side, const Orientations& charts);

// The smallest pageCost of the packings finished so far, shared by trials that run at once. A
// trial whose partial packing already costs more gives up: it could not have won, and every trial
// that can win (cost at most the final minimum, which no finished trial undercuts) runs to the
// end, so the winner does not depend on which trials finished first.
//
// With a slack s > 1 a trial gives up only above s times the smallest page: every trial whose page
// costs at most s times the final minimum runs to the end (a ranking of the near-best trials).
class CostBound {
public:
    CostBound(int maxSize, double best = 1e300, double slack = 1) : maxSize_(maxSize), slack_(slack), best_(best) {}
    int maxSize() const { return maxSize_; }
    double best() const { return best_.load(std::memory_order_relaxed); }
    // The cost above which a partial packing gives up.
    double limit() const { return best() * slack_; }
    void offer(double cost) {
        double b = best_.load(std::memory_order_relaxed);
        while (cost < b && !best_.compare_exchange_weak(b, cost, std::memory_order_relaxed)) {}
    }

private:
    int maxSize_;
    double slack_;
    std::atomic<double> best_;
};

// Where a chart goes: the free position with the lowest top edge (bottom-left fill), or with the
// lowest centre of gravity (nests irregular charts differently: neither wins on every asset).
enum class Placement { TopEdge, Gravity };

// A packing under way: the page and the slots of the charts placed so far.
struct PackState {
    BitmapPage page;
    Packing packing;
};

// Places the charts (in `order`) on a binW x binH page, each at its lowest position over the four
// quarter turns. Returns nothing when one does not fit. The samplers clamp to the page edge, so
// no gutter is kept along the page border: the bitmap extends `radius` texels beyond every side of
// the page and a chart's gutter ring may lie out there.
//
// `prefix`, when given, receives the state before each chart of `order` is placed; `from`, when
// given, is such a state of an order that agrees with `order` on its first `fromIndex` charts:
// the packing resumes there (the same charts placed the same way). `inPlace`, when given, holds
// per chart a cell its first orientation takes, unturned, when it lies on the page ({-1, -1}:
// none); such charts come first in `order` and may overlap each other (AtlasChart::inPlace).
std::optional<Packing> packBitmap(const Footprints& fp, const std::vector<size_t>& order, int binW, int binH,
                                  Placement placement = Placement::TopEdge, CostBound* bound = nullptr,
                                  std::vector<PackState>* prefix = nullptr, const PackState* from = nullptr, size_t fromIndex = 0,
                                  const std::vector<std::array<int, 2>>* inPlace = nullptr);

// The same at density t from the charts: their footprints are rasterised in the packing order, in
// batches that double, so a packing that fails at a chart has not rasterised most of the charts
// after it (on pages the charts overfill, the large ones first fail early).
std::optional<Packing> packBitmap(const Orientations& charts, const std::vector<size_t>& order, double t,
                                  int gutter, int binW, int binH, int scale, int threads);

}  // namespace lodbake::atlas_detail
