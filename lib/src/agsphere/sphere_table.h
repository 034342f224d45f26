// Private to lib/src/agsphere: the edge-neighbour table of all cells at one depth.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace lodbake {

// table[c][k] = the cell across edge k of cell c at `depth` (every cell has three).
std::vector<std::array<uint32_t, 3>> sphereNeighbourTable(int depth);

}  // namespace lodbake
