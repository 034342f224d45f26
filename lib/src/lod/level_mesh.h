// A level's mesh: one indexed primitive (position, normal, page UV, and the wedges' joints,
// weights and morph deltas) from its triangles, layout UVs and page.
#pragma once

#include <cstddef>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/gltf/msft_lod.h"
#include "lod/level_page.h"
#include "lod/level_view.h"

namespace lodbake::lod_detail {

// Fills `out` (empty) with level `lv` on page `la`: a vertex per welded vertex, chart, normal,
// chart UV and influence set. Normals are the wedges' (unit) when the asset has them, else
// area-weighted over the level. Slivers whose page UVs would turn flat or flipped once rounded to
// float get their own copy of a corner, moved by float ulps until they face the right way.
void buildLevelMesh(const Asset& asset, const LevelView& lv, const LevelUVs& luv, const LevelAtlas& la, LodLevelData& out);

// Appends a reversed copy (negated normals) of every triangle whose original material is
// double-sided: a chain whose one material is single-sided still shows those parts from behind.
// Returns, per back copy, the level triangle it copies.
std::vector<size_t> addBackFaces(const Asset& asset, const LevelView& lv, LodLevelData& out);

// The same level mesh: every attribute and index.
bool sameLevelMesh(const LodLevelData& a, const LodLevelData& b);

}  // namespace lodbake::lod_detail
