// A uniform grid of items bucketed by their boxes in the plane, for "which items lie near this
// box" queries: UV triangles (texture deviation's point location, the UV overlap check) and
// polygon nodes and segments (agsphere's ear clipping and simplicity test). Every item is listed
// in each cell its box overlaps, clamped to the grid, in the order it was given. The plane's
// counterpart of core/face_grid.h (3D, over a mesh's faces).
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "lodbake/core/math.h"

namespace lodbake {

// An item of the grid: its id and its box [lo, hi].
struct GridItem2 {
    uint32_t id = 0;
    Vec2 lo, hi;
};

class Grid2 {
public:
    // The ids listed in one cell, in the order the items were given.
    struct Cell {
        const uint32_t* first = nullptr;
        const uint32_t* last = nullptr;
        const uint32_t* begin() const { return first; }
        const uint32_t* end() const { return last; }
        size_t size() const { return size_t(last - first); }
    };

    // nx x ny cells (each >= 1) over the box [lo, hi] (a side of no extent counts as 1e-300),
    // filled on `threads` threads (the same lists for any count).
    Grid2(Vec2 lo, Vec2 hi, int nx, int ny, const std::vector<GridItem2>& items, int threads = 1);

    // Cells for about `items` cells over [lo, hi], of about square shape, at most 1024 a side.
    static std::array<int, 2> squareCells(Vec2 lo, Vec2 hi, size_t items);

    int nx() const { return nx_; }
    int ny() const { return ny_; }
    // The column and row of a coordinate, clamped to the grid (neither decreases with its argument).
    int cellX(double x) const { return std::clamp(int((x - lo_.x) * sx_), 0, nx_ - 1); }
    int cellY(double y) const { return std::clamp(int((y - lo_.y) * sy_), 0, ny_ - 1); }
    Cell cell(int x, int y) const {
        const size_t c = size_t(y) * size_t(nx_) + size_t(x);
        return {items_.data() + start_[c], items_.data() + start_[c + 1]};
    }

    // Calls f(cell) for every cell the box [lo, hi] overlaps, row by row.
    template <class F>
    void visit(Vec2 lo, Vec2 hi, F&& f) const {
        for (int y = cellY(lo.y); y <= cellY(hi.y); ++y)
            for (int x = cellX(lo.x); x <= cellX(hi.x); ++x) f(cell(x, y));
    }

private:
    Vec2 lo_;
    int nx_ = 1, ny_ = 1;
    double sx_ = 1, sy_ = 1;       // cells per unit along x and y
    std::vector<uint32_t> start_;  // CSR: cell c lists items_[start_[c] .. start_[c + 1])
    std::vector<uint32_t> items_;
};

}  // namespace lodbake
