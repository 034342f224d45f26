// Uniform grid of item boxes in the plane (see grid2d.h).
#include "lodbake/core/grid2d.h"

#include <algorithm>
#include <cmath>

namespace lodbake {

Grid2::Grid2(Vec2 lo, Vec2 hi, int nx, int ny, const std::vector<GridItem2>& items) : lo_(lo), nx_(nx), ny_(ny) {
    sx_ = nx_ / std::max(hi.x - lo.x, 1e-300);
    sy_ = ny_ / std::max(hi.y - lo.y, 1e-300);
    const size_t cells = size_t(nx_) * size_t(ny_);
    auto forCells = [&](const GridItem2& item, auto&& fn) {
        for (int y = cellY(item.lo.y); y <= cellY(item.hi.y); ++y)
            for (int x = cellX(item.lo.x); x <= cellX(item.hi.x); ++x) fn(size_t(y) * size_t(nx_) + size_t(x));
    };
    start_.assign(cells + 1, 0);
    for (const GridItem2& item : items) forCells(item, [&](size_t c) { ++start_[c + 1]; });
    for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
    items_.resize(start_[cells]);
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (const GridItem2& item : items) forCells(item, [&](size_t c) { items_[fill[c]++] = item.id; });
}

std::array<int, 2> Grid2::squareCells(Vec2 lo, Vec2 hi, size_t items) {
    const double w = std::max(hi.x - lo.x, 1e-300), h = std::max(hi.y - lo.y, 1e-300);
    const double n = std::max(1.0, std::sqrt(double(items)));
    const double aspect = w / h;
    return {std::clamp(int(std::ceil(n * std::sqrt(aspect))), 1, 1024), std::clamp(int(std::ceil(n / std::sqrt(aspect))), 1, 1024)};
}


}  // namespace lodbake
