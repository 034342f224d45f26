// Mesh connectivity over welded triangles: the one place every module builds its edges, face
// neighbours, half-edge twins and vertex fans from. All results are deterministic (sorted by
// index), independent of hashing and thread count.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

// Key of the undirected edge {a, b}: edgeKey(a, b) == edgeKey(b, a).
inline uint64_t edgeKey(uint32_t a, uint32_t b) {
    if (a > b) std::swap(a, b);
    return (uint64_t(a) << 32) | b;
}
// Key of the directed edge a -> b.
inline uint64_t directedEdgeKey(uint32_t a, uint32_t b) { return (uint64_t(a) << 32) | b; }

// Compressed rows: row r is items[offsets[r] .. offsets[r + 1]).
struct CompressedRows {
    std::vector<uint32_t> offsets;  // rows + 1 entries
    std::vector<uint32_t> items;
    size_t rows() const { return offsets.empty() ? 0 : offsets.size() - 1; }
    const uint32_t* begin(size_t r) const { return items.data() + offsets[r]; }
    const uint32_t* end(size_t r) const { return items.data() + offsets[r + 1]; }
    size_t size(size_t r) const { return offsets[r + 1] - offsets[r]; }
};

// Half-edge h = 3 f + k runs from triangles[f][k] to triangles[f][(k + 1) % 3].
// Every non-degenerate triangle's half-edges grouped by undirected edge, groups ordered by
// edgeKey and half-edges within a group by index. Degenerate triangles contribute none.
struct EdgeGroups {
    std::vector<uint64_t> keys;  // one edgeKey per group
    CompressedRows halfEdges;    // row g: the half-edges of group g
};
EdgeGroups groupEdges(const std::vector<Tri>& triangles);

// Faces sharing an undirected edge with each face (every face of a non-manifold edge counts),
// sorted and without repeats; degenerate faces have none.
CompressedRows faceNeighbours(const std::vector<Tri>& triangles);
// The same from groupEdges(triangles) of `faceCount` triangles.
CompressedRows faceNeighbours(const EdgeGroups& groups, size_t faceCount);

// The faces using each vertex, in face order (a face that repeats a vertex is listed once per
// corner).
CompressedRows vertexFaces(const std::vector<Tri>& triangles, size_t vertexCount);

// The opposite half-edge of each half-edge on a manifold, consistently oriented edge (exactly two
// half-edges, of different faces, running in opposite directions); kBorderEdge where the edge has
// one half-edge, kNonManifoldEdge otherwise (more than two, or two running the same way).
constexpr uint32_t kBorderEdge = UINT32_MAX;
constexpr uint32_t kNonManifoldEdge = UINT32_MAX - 1;
std::vector<uint32_t> halfEdgeTwins(const std::vector<Tri>& triangles);

// Every undirected edge once, in the order its first half-edge appears, as that half-edge runs
// (a, b). Degenerate triangles' repeated-vertex edges are left out.
std::vector<std::pair<uint32_t, uint32_t>> uniqueEdgesInOrder(const std::vector<Tri>& triangles);

// For each half-edge a -> b: true when no half-edge b -> a exists (it lies on the boundary of the
// triangle set as an oriented surface).
std::vector<char> borderHalfEdges(const std::vector<Tri>& triangles);

}  // namespace lodbake
