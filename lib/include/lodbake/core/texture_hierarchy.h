// The texture hierarchy `texture-refine` builds (thesis chapter 4): textures of several ranks
// and sizes, each valid for a range of geometry levels.
#pragma once

#include <cstdint>
#include <vector>

#include "lodbake/core/chart_layout.h"

namespace lodbake {

// One texture of the hierarchy. Geometry levels are numbered as `pack` numbers LODs: 0 = the
// original mesh, k = Multires::levels[k-1] (coarser as k grows). A rank-j layout is made from
// the regions of a level l_j < l_{j-1} (l_0 = levels.size()): their boundaries are p-boundaries
// for every finer level, so a rank-j texture is valid for levels 0..l_j. Rank 0 is
// Multires::charts (T0, valid for every level).
struct HierarchyTexture {
    uint32_t rank = 0;        // 0 = T0's layout (Multires::charts); j >= 1 = TextureHierarchy::ranks[j-1]
    uint32_t firstLevel = 0;  // valid for geometry levels firstLevel..lastLevel (inclusive)
    uint32_t lastLevel = 0;
    int image = -1;           // Asset::images index of this texture (base colour baked from the original)
    int size = 0;             // image side, texels (square)
};

struct TextureHierarchy {
    std::vector<ChartLayout> ranks;          // ranks[j-1] = the rank-j layout (material -1, image = its largest texture)
    std::vector<HierarchyTexture> textures;  // MIP-style T0 variants and the refined textures, rank then size ascending
    bool empty() const { return textures.empty(); }
    // The layout of `rank` (0 = base).
    const ChartLayout& layout(uint32_t rank, const ChartLayout& base) const { return rank == 0 ? base : ranks.at(rank - 1); }
};

}  // namespace lodbake
