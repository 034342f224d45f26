// One level of the chain in terms of the original: its triangles, corner wedges and original
// faces, and the positions vertex placement gave it.
#pragma once

#include <string>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"

namespace lodbake::lod_detail {

// One level's geometry in terms of original faces: triangles, corner wedges and face ids.
struct LevelView {
    std::vector<Tri> triangles, cornerWedges;
    std::vector<uint32_t> faces;
    std::string source;
    double maxDeviation = 0;
    size_t level = 0;            // multires level number (0 = the original)
    const Level* data = nullptr;  // multires.levels[level - 1]; null for the original
    std::vector<Vec3> positions;  // welded positions after vertex placement; empty = the original's
    const std::vector<Vec3>& positionsOr(const TriMesh& original) const { return positions.empty() ? original.positions : positions; }
};

// The original, then every level that has triangles. A level simplify could not make coarser
// repeats the one before it: it stays in the chain (the chain's level count and files do not
// depend on how far simplify got), with a warning appended to `warnings` that says so.
std::vector<LevelView> levelViews(const Asset& asset, const Multires& mr, std::vector<std::string>& warnings);

// The level's triangles at its positions (no attributes).
TriMesh asTriMesh(const TriMesh& original, const LevelView& lv);

// The same surface: the same triangles of the same original faces through the same wedges at the
// same positions (a level simplify could not make coarser, unmoved by vertex placement).
bool sameSurface(const LevelView& a, const LevelView& b);

// The level shades as the original does: it is the original's triangles, each of the same face,
// unmoved, whose corners carry the original corners' normals (their wedges may be the level's own
// copies). A normal map baked for it would be flat. Not a level of an original without normals,
// which viewers draw flat-shaded.
bool showsOriginalSurface(const TriMesh& original, const LevelView& lv);

}  // namespace lodbake::lod_detail
