// Uniform grid of item boxes in the plane (see grid2d.h).
#include "lodbake/core/grid2d.h"

#include <algorithm>
#include <cmath>

#include "lodbake/core/cell_lists.h"

namespace lodbake {

Grid2::Grid2(Vec2 lo, Vec2 hi, int nx, int ny, const std::vector<GridItem2>& items, int threads) : lo_(lo), nx_(nx), ny_(ny) {
    sx_ = nx_ / std::max(hi.x - lo.x, 1e-300);
    sy_ = ny_ / std::max(hi.y - lo.y, 1e-300);
    auto forCells = [&](size_t i, auto&& fn) {
        const GridItem2& item = items[i];
        for (int y = cellY(item.lo.y); y <= cellY(item.hi.y); ++y)
            for (int x = cellX(item.lo.x); x <= cellX(item.hi.x); ++x) fn(size_t(y) * size_t(nx_) + size_t(x));
    };
    fillCellLists(items.size(), size_t(nx_) * size_t(ny_), threads, forCells, [&](size_t i) { return items[i].id; }, start_, items_);
}

std::array<int, 2> Grid2::squareCells(Vec2 lo, Vec2 hi, size_t items) {
    const double w = std::max(hi.x - lo.x, 1e-300), h = std::max(hi.y - lo.y, 1e-300);
    const double n = std::max(1.0, std::sqrt(double(items)));
    const double aspect = w / h;
    return {std::clamp(int(std::ceil(n * std::sqrt(aspect))), 1, 1024), std::clamp(int(std::ceil(n / std::sqrt(aspect))), 1, 1024)};
}


}  // namespace lodbake
