// One level of the chain in terms of the original (level_view.h), and repeated levels.
#include "lod/level_view.h"

#include <algorithm>

namespace lodbake::lod_detail {

std::vector<LevelView> levelViews(const Asset& asset, const Multires& mr, std::vector<std::string>& warnings) {
    std::vector<LevelView> v;
    LevelView l0;
    l0.triangles = asset.mesh.triangles;
    l0.cornerWedges = asset.mesh.cornerWedges;
    l0.faces.resize(asset.mesh.triangleCount());
    for (size_t f = 0; f < l0.faces.size(); ++f) l0.faces[f] = uint32_t(f);
    l0.source = "original";
    v.push_back(std::move(l0));
    for (size_t k = 0; k < mr.levels.size(); ++k) {
        const Level& L = mr.levels[k];
        if (L.triangles.empty()) continue;
        if (L.triangles == v.back().triangles)
            warnings.push_back("LOD" + std::to_string(v.size()) + " (level " + std::to_string(k + 1) + ") repeats LOD" +
                               std::to_string(v.size() - 1) + ": the same " + std::to_string(L.triangles.size()) +
                               " triangles (simplify could not make it coarser)");
        LevelView lv;
        lv.triangles = L.triangles;
        lv.cornerWedges = L.cornerWedges;
        lv.faces = L.faces;
        lv.source = "level " + std::to_string(k + 1);
        lv.maxDeviation = L.maxDeviation;
        lv.level = k + 1;
        lv.data = &L;
        v.push_back(std::move(lv));
    }
    return v;
}

TriMesh asTriMesh(const TriMesh& original, const LevelView& lv) {
    TriMesh m;
    m.positions = lv.positionsOr(original);
    m.triangles = lv.triangles;
    return m;
}

bool sameSurface(const LevelView& a, const LevelView& b) {
    auto same = [](Vec3 p, Vec3 q) { return p.x == q.x && p.y == q.y && p.z == q.z; };
    return a.triangles == b.triangles && a.cornerWedges == b.cornerWedges && a.faces == b.faces &&
           std::equal(a.positions.begin(), a.positions.end(), b.positions.begin(), b.positions.end(), same);
}

bool showsOriginalSurface(const TriMesh& original, const LevelView& lv) {
    if (!lv.positions.empty() || lv.triangles != original.triangles || lv.faces.size() != original.triangleCount()) return false;
    for (size_t t = 0; t < lv.faces.size(); ++t)
        if (lv.faces[t] != t) return false;
    // An original without normals is drawn flat by viewers, while a level carries normals of its
    // own: its normal map carries that faceting.
    const std::vector<Vec3>& normal = original.wedges.normal;
    if (normal.empty()) return false;
    auto same = [](Vec3 p, Vec3 q) { return p.x == q.x && p.y == q.y && p.z == q.z; };
    for (size_t t = 0; t < lv.triangles.size(); ++t)
        for (size_t j = 0; j < 3; ++j)
            if (!same(normal[lv.cornerWedges[t][j]], normal[original.cornerWedges[t][j]])) return false;
    return true;
}

}  // namespace lodbake::lod_detail
