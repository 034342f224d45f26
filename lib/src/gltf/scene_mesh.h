// The welded mesh of a glTF scene (step 3 of readGltf): every triangle primitive of the mesh nodes
// decoded, moved to world space and welded by position (lodbake/core/weld.h) into asset.mesh, with
// its wedge attributes, skin influences and morph deltas.
#pragma once

#include <utility>
#include <vector>

#include "gltf/gltf_read_context.h"
#include "gltf/morph_read.h"
#include "gltf/rig_read.h"
#include "lodbake/core/mesh.h"

namespace lodbake::gltf_detail {

// Every triangle primitive of every mesh node (glTF node, world matrix), decoded, transformed to
// world space and welded by position into asset.mesh. Triangles whose corners weld together are
// dropped (counted in a warning). \throw InvalidInput on a missing mesh or material, or a
// non-finite world position.
void weldScene(const ReadContext& c, const std::vector<std::pair<int, Mat4>>& nodes, RigRead& rr, const MorphLayout& layout,
               Asset& asset);

}  // namespace lodbake::gltf_detail
