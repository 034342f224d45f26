// Grid2 (lib/include/lodbake/core/grid2d.h): every item is listed, in the order given, in exactly
// the cells its box overlaps (clamped to the grid); visit reaches every item whose box meets the
// query box.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "lodbake/core/grid2d.h"

using namespace lodbake;

// A 4 x 2 grid over [0, 4] x [0, 2]: cells are unit squares.
//
//   y=1 | 4 | 5 | 6 | 7 |
//   y=0 | 0 | 1 | 2 | 3 |
//        x=0 x=1 x=2 x=3
TEST(Grid2, ItemsAreListedInTheCellsTheirBoxesOverlapInOrder) {
    const std::vector<GridItem2> items = {
        {7, {0.5, 0.5}, {0.5, 0.5}},    // a point in cell (0, 0)
        {3, {0.5, 0.5}, {2.5, 0.5}},    // a segment over cells (0..2, 0)
        {9, {-5, -5}, {-1, -1}},        // outside: clamped to cell (0, 0)
        {1, {3.5, 1.5}, {10, 10}},      // beyond the top right: cell (3, 1)
    };
    const Grid2 grid({0, 0}, {4, 2}, 4, 2, items);
    ASSERT_EQ(grid.nx(), 4);
    ASSERT_EQ(grid.ny(), 2);
    auto ids = [&](int x, int y) {
        const Grid2::Cell c = grid.cell(x, y);
        return std::vector<uint32_t>(c.begin(), c.end());
    };
    EXPECT_EQ(ids(0, 0), (std::vector<uint32_t>{7, 3, 9}));
    EXPECT_EQ(ids(1, 0), (std::vector<uint32_t>{3}));
    EXPECT_EQ(ids(2, 0), (std::vector<uint32_t>{3}));
    EXPECT_TRUE(ids(3, 0).empty());
    EXPECT_EQ(ids(3, 1), (std::vector<uint32_t>{1}));
    EXPECT_EQ(grid.cellX(-1), 0);
    EXPECT_EQ(grid.cellX(3.999), 3);
    EXPECT_EQ(grid.cellX(4), 3);
    EXPECT_EQ(grid.cellY(1), 1);
}

TEST(Grid2, SquareCellsFollowTheBoxShape) {
    EXPECT_EQ(Grid2::squareCells({0, 0}, {1, 1}, 100), (std::array<int, 2>{10, 10}));
    EXPECT_EQ(Grid2::squareCells({0, 0}, {4, 1}, 100), (std::array<int, 2>{20, 5}));
    EXPECT_EQ(Grid2::squareCells({0, 0}, {1, 1}, 0), (std::array<int, 2>{1, 1}));
    EXPECT_EQ(Grid2::squareCells({0, 0}, {1, 1}, 100000000)[0], 1024);
}

TEST(Grid2, VisitFindsEveryItemWhoseBoxMeetsTheQuery) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> at(-0.1, 1.1), size(0, 0.08);
    std::vector<GridItem2> items;
    for (uint32_t i = 0; i < 500; ++i) {
        const Vec2 lo{at(rng), at(rng)};
        items.push_back({i, lo, {lo.x + size(rng), lo.y + size(rng)}});
    }
    const std::array<int, 2> n = Grid2::squareCells({0, 0}, {1, 1}, items.size());
    const Grid2 grid({0, 0}, {1, 1}, n[0], n[1], items);
    for (int q = 0; q < 200; ++q) {
        const Vec2 lo{at(rng), at(rng)}, hi{lo.x + size(rng), lo.y + size(rng)};
        std::set<uint32_t> found;
        grid.visit(lo, hi, [&](const Grid2::Cell& cell) { found.insert(cell.begin(), cell.end()); });
        for (const GridItem2& it : items)
            if (it.lo.x <= hi.x && it.hi.x >= lo.x && it.lo.y <= hi.y && it.hi.y >= lo.y) {
                EXPECT_TRUE(found.count(it.id)) << it.id;
            }
    }
}
