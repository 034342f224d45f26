// A level drawn as several primitives (lodbake/bake/draw_split.h): its triangles ordered by draw
// group, one LodPart per group it has triangles of, and the report's draw calls.
#pragma once

#include <cstdint>
#include <vector>

#include "lodbake/bake/draw_split.h"
#include "lodbake/gltf/msft_lod.h"
#include "lodbake/lod/lod_chain.h"

namespace lodbake::lod_detail {

// With one group: L and the report stay as they are (one primitive). Else L's triangles are
// reordered by group (stable: within a group the chain's order stays), L.parts gets one part per
// group present, with the group's default values and, per variant, the values of the selection it
// uses (`selectionOfVariant`: index into the split's selections, 0 = the default); the report gets
// the draw calls, materials and the properties the parts differ in.
// \pre triangleGroup has one group index per triangle of L.
void splitLevel(const DrawSplit& split, const std::vector<uint32_t>& triangleGroup, const std::vector<size_t>& selectionOfVariant,
                LodLevelData& L, PackLevelReport& report);

}  // namespace lodbake::lod_detail
