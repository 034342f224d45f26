// The chart layout `parameterize` makes (thesis 3.3): which chart each original face is in, the
// texture coordinate of each original face corner in the baked texture (T0), and the level
// triangles that got an island of their own. Indices as in simplification_hierarchy.h.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

// A level triangle with its own UV island in the layout (parameterize's fallback for a level
// triangle that would fold inside its chart): every level triangle with this vertex triple takes
// these UVs, per vertex; the island is packed like a chart of one triangle.
struct LayoutIsland {
    Tri vertices{};              // welded vertex ids
    std::array<Vec2, 3> uv{};    // UV of vertices[k] in the layout
    // The UV of vertex v, one of `vertices`.
    Vec2 uvOf(uint32_t v) const { return uv[v == vertices[0] ? 0 : v == vertices[1] ? 1 : 2]; }
};

// The key a level triangle finds its island by (any corner order): the vertex triple, ascending.
inline std::array<uint32_t, 3> islandKey(const Tri& t) {
    std::array<uint32_t, 3> k{t[0], t[1], t[2]};
    std::sort(k.begin(), k.end());
    return k;
}

// The texture-space layout `parameterize` made: which chart each original face is in and the
// texture coordinate of each original face corner in the baked texture. Empty (chartCount 0)
// until the asset is parameterized. UVs follow glTF: origin top-left, v down, [0,1].
struct ChartLayout {
    uint32_t chartCount = 0;
    std::vector<uint32_t> faceChart;           // per original face
    std::vector<std::array<Vec2, 3>> cornerUV;  // per original face, per corner
    std::vector<LayoutIsland> islands;         // level-triangle islands (chart ids chartCount + i)
    int material = -1;  // Asset::materials index of the baked material the levels use
    int image = -1;     // Asset::images index of the baked base-colour texture (T0)
    bool empty() const { return chartCount == 0; }
};

}  // namespace lodbake
