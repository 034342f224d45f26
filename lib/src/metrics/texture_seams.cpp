// textureSeamEdges (render.h): the edges where a texture's UVs jump, found over the welded
// positions so a seam counts whether or not the file splits its vertices there.
#include <cmath>

#include "lodbake/core/adjacency.h"
#include "lodbake/metrics/render.h"

namespace lodbake {

std::vector<uint8_t> textureSeamEdges(const TriMesh& mesh) {
    std::vector<uint8_t> seams(mesh.triangles.size(), 0);
    const std::vector<Vec2>& uv = mesh.wedges.uv0;
    if (uv.empty() || uv.size() != mesh.wedges.size() || mesh.cornerWedges.size() != mesh.triangles.size()) return seams;
    constexpr double kSameUv = 1e-6;
    // The UV triangle f gives position v (one of its corners).
    auto uvAt = [&](uint32_t f, uint32_t v) {
        const Tri& t = mesh.triangles[f];
        const int k = t[0] == v ? 0 : (t[1] == v ? 1 : 2);
        return uv[mesh.cornerWedges[f][size_t(k)]];
    };
    const EdgeGroups groups = groupEdges(mesh.triangles);
    for (size_t g = 0; g < groups.keys.size(); ++g) {
        if (groups.halfEdges.size(g) < 2) continue;
        const uint32_t a = uint32_t(groups.keys[g] >> 32), b = uint32_t(groups.keys[g] & 0xffffffffu);
        const uint32_t* first = groups.halfEdges.begin(g);
        const uint32_t f0 = *first / 3;
        bool split = false;
        for (const uint32_t* h = first + 1; h != groups.halfEdges.end(g) && !split; ++h)
            for (uint32_t v : {a, b}) {
                const Vec2 d = uvAt(*h / 3, v) - uvAt(f0, v);
                split = split || std::fabs(d.x) > kSameUv || std::fabs(d.y) > kSameUv;
            }
        if (!split) continue;
        for (const uint32_t* h = first; h != groups.halfEdges.end(g); ++h) seams[*h / 3] |= uint8_t(1u << (*h % 3));
    }
    return seams;
}

}  // namespace lodbake
