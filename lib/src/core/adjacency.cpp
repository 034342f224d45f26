// Mesh connectivity over welded triangles (adjacency.h): edges, face neighbours, twins, fans.
#include "lodbake/core/adjacency.h"

#include <algorithm>

namespace lodbake {
namespace {

// (key, half-edge) of every half-edge of the non-degenerate triangles, sorted.
template <class KeyFn>
std::vector<std::pair<uint64_t, uint32_t>> sortedHalfEdges(const std::vector<Tri>& triangles, KeyFn key) {
    std::vector<std::pair<uint64_t, uint32_t>> he;
    he.reserve(triangles.size() * 3);
    for (uint32_t f = 0; f < triangles.size(); ++f) {
        const Tri& t = triangles[f];
        if (degenerateIndices(t)) continue;
        for (uint32_t k = 0; k < 3; ++k) he.push_back({key(t[k], t[(k + 1) % 3]), 3 * f + k});
    }
    std::sort(he.begin(), he.end());
    return he;
}

CompressedRows rowsFromLists(std::vector<std::vector<uint32_t>>& lists) {
    CompressedRows rows;
    rows.offsets.assign(lists.size() + 1, 0);
    for (size_t r = 0; r < lists.size(); ++r) rows.offsets[r + 1] = rows.offsets[r] + uint32_t(lists[r].size());
    rows.items.reserve(rows.offsets.back());
    for (auto& l : lists) rows.items.insert(rows.items.end(), l.begin(), l.end());
    return rows;
}

}  // namespace

EdgeGroups groupEdges(const std::vector<Tri>& triangles) {
    auto he = sortedHalfEdges(triangles, edgeKey);
    EdgeGroups g;
    g.halfEdges.offsets.push_back(0);
    g.halfEdges.items.reserve(he.size());
    for (size_t i = 0; i < he.size();) {
        size_t j = i;
        while (j < he.size() && he[j].first == he[i].first) g.halfEdges.items.push_back(he[j++].second);
        g.keys.push_back(he[i].first);
        g.halfEdges.offsets.push_back(uint32_t(g.halfEdges.items.size()));
        i = j;
    }
    return g;
}

CompressedRows faceNeighbours(const std::vector<Tri>& triangles) { return faceNeighbours(groupEdges(triangles), triangles.size()); }

CompressedRows faceNeighbours(const EdgeGroups& g, size_t faceCount) {
    std::vector<std::vector<uint32_t>> nb(faceCount);
    for (size_t e = 0; e < g.keys.size(); ++e)
        for (const uint32_t* a = g.halfEdges.begin(e); a != g.halfEdges.end(e); ++a)
            for (const uint32_t* b = g.halfEdges.begin(e); b != g.halfEdges.end(e); ++b)
                if (*a / 3 != *b / 3) nb[*a / 3].push_back(*b / 3);
    for (auto& l : nb) {
        std::sort(l.begin(), l.end());
        l.erase(std::unique(l.begin(), l.end()), l.end());
    }
    return rowsFromLists(nb);
}

CompressedRows vertexFaces(const std::vector<Tri>& triangles, size_t vertexCount) {
    CompressedRows rows;
    rows.offsets.assign(vertexCount + 1, 0);
    for (const Tri& t : triangles)
        for (uint32_t v : t) ++rows.offsets[v + 1];
    for (size_t v = 0; v < vertexCount; ++v) rows.offsets[v + 1] += rows.offsets[v];
    rows.items.resize(rows.offsets[vertexCount]);
    std::vector<uint32_t> fill(rows.offsets.begin(), rows.offsets.end() - 1);
    for (uint32_t f = 0; f < triangles.size(); ++f)
        for (uint32_t v : triangles[f]) rows.items[fill[v]++] = f;
    return rows;
}

std::vector<uint32_t> halfEdgeTwins(const std::vector<Tri>& triangles) {
    const EdgeGroups g = groupEdges(triangles);
    std::vector<uint32_t> twin(triangles.size() * 3, kNonManifoldEdge);
    for (size_t e = 0; e < g.keys.size(); ++e) {
        const uint32_t* h = g.halfEdges.begin(e);
        if (g.halfEdges.size(e) == 1) {
            twin[h[0]] = kBorderEdge;
        } else if (g.halfEdges.size(e) == 2) {
            uint32_t a = h[0], b = h[1];
            bool opposite = triangles[a / 3][a % 3] != triangles[b / 3][b % 3];
            if (a / 3 != b / 3 && opposite) {
                twin[a] = b;
                twin[b] = a;
            }
        }
    }
    return twin;
}

std::vector<std::pair<uint32_t, uint32_t>> uniqueEdgesInOrder(const std::vector<Tri>& triangles) {
    const EdgeGroups g = groupEdges(triangles);
    std::vector<uint32_t> first;  // the first half-edge of each group
    first.reserve(g.keys.size());
    for (size_t e = 0; e < g.keys.size(); ++e) first.push_back(*g.halfEdges.begin(e));
    std::sort(first.begin(), first.end());
    std::vector<std::pair<uint32_t, uint32_t>> edges;
    edges.reserve(first.size());
    for (uint32_t h : first) {
        const Tri& t = triangles[h / 3];
        edges.push_back({t[h % 3], t[(h % 3 + 1) % 3]});
    }
    return edges;
}

std::vector<char> borderHalfEdges(const std::vector<Tri>& triangles) {
    auto he = sortedHalfEdges(triangles, directedEdgeKey);
    std::vector<uint64_t> keys(he.size());
    for (size_t i = 0; i < he.size(); ++i) keys[i] = he[i].first;
    std::vector<char> border(triangles.size() * 3, 0);
    for (const auto& [key, h] : he) {
        uint64_t reverse = directedEdgeKey(uint32_t(key & 0xffffffffu), uint32_t(key >> 32));
        border[h] = !std::binary_search(keys.begin(), keys.end(), reverse);
    }
    return border;
}

}  // namespace lodbake
