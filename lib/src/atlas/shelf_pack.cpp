// Shelf packing of the T0 atlas: bounding boxes sorted by height, placed left to right in rows
// whose height is their tallest box, at one uniform density shrunk until everything fits.
#include <algorithm>
#include <cmath>
#include <string>

#include "lodbake/atlas/atlas.h"
#include "lodbake/core/errors.h"

namespace lodbake {
namespace {

// Places the items at density d (texels per model unit); false when they do not fit the page.
bool shelvesAt(const std::vector<const std::vector<Vec2>*>& sets, double d, int size, int gutter,
               std::vector<ShelfPlacement>& out) {
    struct Item {
        uint32_t id;
        int w, h;  // texels
        Vec2 min;
    };
    std::vector<Item> items;
    for (uint32_t i = 0; i < sets.size(); ++i) {
        Vec2 lo{1e300, 1e300}, hi{-1e300, -1e300};
        for (Vec2 p : *sets[i]) {
            lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
            hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
        }
        if (sets[i]->empty()) lo = hi = {0, 0};
        items.push_back({i, int(std::ceil((hi.x - lo.x) * d)) + 1, int(std::ceil((hi.y - lo.y) * d)) + 1, lo});
    }
    std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) { return a.h != b.h ? a.h > b.h : a.id < b.id; });
    out.assign(sets.size(), {});
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

size_t shelfPackCapacity(int size, int gutter) {
    // shelvesAt's rows and shelves of 2 x 2 boxes: a box at x needs x + 2 + gutter <= size.
    const int step = 2 + gutter, room = size - gutter - step;
    const size_t perRow = room < 0 ? 0 : size_t(room / step + 1);
    return perRow * perRow;
}

ShelfPackResult shelfPack(const std::vector<const std::vector<Vec2>*>& items, double area, const ShelfPackOptions& options) {
    constexpr double kStartFill = 0.7;  // fraction of the page the items' area fills at the start density
    constexpr double kShrink = 0.95;    // density factor per failed attempt
    constexpr int kMaxAttempts = 400;
    // A page whose last attempt (the smallest density tried) still fails holds the items at no
    // density: it doubles before any density is tried.
    auto startDensity = [&](int side) { return std::sqrt(kStartFill * double(side) * side / (area > 0 ? area : 1)); };
    const double lastFactor = std::pow(kShrink, kMaxAttempts);
    int size = options.size;
    ShelfPackResult res;
    while (size < options.maxSize && !shelvesAt(items, startDensity(size) * lastFactor, size, options.gutter, res.items)) size *= 2;
    res.size = size;
    double d = startDensity(size);
    int attempts = 0;
    while (!shelvesAt(items, d, size, options.gutter, res.items)) {
        d *= kShrink;
        if (++attempts > kMaxAttempts) throw Impossible("charts do not fit into a " + std::to_string(size) + " texture");
    }
    res.texelsPerUnit = d;
    return res;
}

}  // namespace lodbake
