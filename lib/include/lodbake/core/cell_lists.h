// The per-cell id lists of a uniform grid (FaceGrid, Grid2), filled side by side.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "lodbake/core/parallel.h"

namespace lodbake {

// Lists, for `cells` cells, the ids of `count` items in every cell forCells(i, fn) names (fn(cell)
// once per cell of item i): cell c's ids are ids[start[c]] .. ids[start[c + 1] - 1], in item
// order. The items are taken in up to four consecutive parts, counted and filled on `threads`
// threads; each cell lists part 0's items first, then part 1's, ..., so the lists are those of
// one pass whatever the thread count.
template <class ForCells, class IdOf>
void fillCellLists(size_t count, size_t cells, int threads, ForCells&& forCells, IdOf&& idOf, std::vector<uint32_t>& start,
                   std::vector<uint32_t>& ids) {
    constexpr size_t kPartItems = 65536;
    const size_t parts = std::clamp<size_t>(count / kPartItems, 1, 4);
    auto partRange = [&](size_t p) { return std::pair<size_t, size_t>{count * p / parts, count * (p + 1) / parts}; };
    std::vector<std::vector<uint32_t>> slot(parts, std::vector<uint32_t>(cells, 0));  // counts, then where the part's next id goes
    parallelFor(parts, threads, [&](size_t p) {
        const auto [begin, end] = partRange(p);
        for (size_t i = begin; i < end; ++i) forCells(i, [&](size_t c) { ++slot[p][c]; });
    });
    start.assign(cells + 1, 0);
    for (size_t c = 0; c < cells; ++c) {
        uint32_t at = start[c];
        for (size_t p = 0; p < parts; ++p) std::swap(slot[p][c], at), at += slot[p][c];
        start[c + 1] = at;
    }
    ids.resize(start[cells]);
    parallelFor(parts, threads, [&](size_t p) {
        const auto [begin, end] = partRange(p);
        for (size_t i = begin; i < end; ++i) {
            const uint32_t id = idOf(i);
            forCells(i, [&](size_t c) { ids[slot[p][c]++] = id; });
        }
    });
}

}  // namespace lodbake
