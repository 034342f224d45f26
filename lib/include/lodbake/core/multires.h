// The multiresolution model: what `simplify` (and later `agsphere-build`) produce and
// `parameterize`, `texture-refine` and `pack` consume. It travels between tools inside the glTF
// as the LODBAKE_multires vendor extension (docs/LODBAKE_multires.md).
//
// Indices: "face" = triangle index in the original TriMesh (level 0); "vertex" = welded vertex
// index of the original TriMesh. Half-edge collapse keeps vertices at their original positions,
// so every coarse vertex is an original vertex and every coarse triangle is a surviving original
// face whose corners moved to kept vertices.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

// A removed original vertex V (or a sample on a modified edge) and its closest point P on the
// coarse surface of one level: P = sum_k bary[k] * position(coarse[k]). On a p-boundary P lies
// on a coarse edge: then coarse[2] == coarse[1] and bary[2] == 0.
struct SimplificationPair {
    uint32_t vertex = 0;          // original welded vertex V_i
    std::array<uint32_t, 3> coarse{};  // welded vertices of the coarse triangle (or edge)
    std::array<float, 3> bary{};  // barycentric coordinates of P_i
    uint32_t face = 0;            // the coarse triangle (an original face id) P_i lies on
    float deviation = 0;          // |V_i - P_i|, model units
};

struct Level {
    // What was asked and what was reached.
    double targetRatio = 0;         // 0 when the target was a count or an error
    uint64_t targetTriangles = 0;
    double targetError = 0;         // --max-error target (model units), 0 if none
    std::string stopReason;         // "target" or the constraint that stopped simplification

    // Geometry: surviving original faces with their current corners.
    std::vector<uint32_t> faces;    // original face id of each level triangle
    std::vector<Tri> triangles;     // welded vertex ids of each level triangle (CCW)
    std::vector<Tri> cornerWedges;  // original wedge used at each corner (for original materials/UVs)
    std::vector<int32_t> triangleMaterial;  // per level triangle; empty = the original faces' materials

    // Regions at this level: faceRegion[f] = representative face of original face f's region.
    std::vector<uint32_t> faceRegion;
    uint32_t regionCount = 0;

    std::vector<SimplificationPair> pairs;

    uint32_t collapseCount = 0;     // collapses applied to reach this level (prefix of Multires::collapses)
    double maxDeviation = 0;        // model units; non-decreasing along the levels
    double meanDeviation = 0;       // mean of pair deviations
    double seconds = 0;             // time spent producing this level (report only, not written to files)
};

// One half-edge collapse (removed -> kept) and the region updates it made: the entries
// [regionBegin, regionEnd) of Multires::regionUpdates.
struct CollapseRecord {
    uint32_t removed = 0;
    uint32_t kept = 0;
    float deviation = 0;
    uint32_t regionBegin = 0;
    uint32_t regionEnd = 0;
};

// Region oldRep joined region newRep, or (when no face is labelled newRep yet) was renamed to it:
// every face labelled oldRep takes the label newRep (representative face ids). The records of a
// collapse prefix, replayed in order on the identity table, give the faceRegion of its level; they
// are also the edges of the region hierarchy (child region -> parent).
struct RegionUpdate {
    uint32_t oldRep = 0;
    uint32_t newRep = 0;
};

// The texture-space layout `parameterize` made: which chart each original face is in and the
// texture coordinate of each original face corner in the baked texture. Empty (chartCount 0)
// until the asset is parameterized. UVs follow glTF: origin top-left, v down, [0,1].
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

struct ChartLayout {
    uint32_t chartCount = 0;
    std::vector<uint32_t> faceChart;           // per original face
    std::vector<std::array<Vec2, 3>> cornerUV;  // per original face, per corner
    std::vector<LayoutIsland> islands;         // level-triangle islands (chart ids chartCount + i)
    int material = -1;  // Asset::materials index of the baked material the levels use
    int image = -1;     // Asset::images index of the baked base-colour texture (T0)
    bool empty() const { return chartCount == 0; }
};

// The texture hierarchy `texture-refine` builds (thesis chapter 4). Geometry levels are numbered
// as `pack` numbers LODs: 0 = the original mesh, k = Multires::levels[k-1] (coarser as k grows).
// A rank-j layout is made from the regions of a level l_j < l_{j-1} (l_0 = levels.size()): their
// boundaries are p-boundaries for every finer level, so a rank-j texture is valid for levels
// 0..l_j. Rank 0 is Multires::charts (T0, valid for every level).
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

struct Multires {
    std::vector<Level> levels;  // finest first (excluding the original, which is the TriMesh itself)
    std::vector<CollapseRecord> collapses;
    std::vector<RegionUpdate> regionUpdates;
    ChartLayout charts;
    TextureHierarchy textures;  // empty until texture-refine ran
    std::string generator = "simplify";  // "simplify" or "agsphere-build"
};

// The TriMesh of level `level` (0 = the original `mesh` itself, k >= 1 = multires.levels[k-1]):
// same positions and wedges as `mesh`, the level's triangles, corners and materials.
// \pre multires was produced for `mesh`; 0 <= level <= multires.levels.size().
TriMesh levelMesh(const TriMesh& mesh, const Multires& multires, size_t level);

}  // namespace lodbake
