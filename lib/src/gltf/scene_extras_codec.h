// Private to lib/src/gltf: lodbake/core/scene_extras.h read from a glTF's JSON and written into
// one (the intermediates and the MSFT_lod chain share the writer, so a light written by one stage
// reads back the same in the next).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf/gltf_read_context.h"
#include "lodbake/core/scene_extras.h"

namespace lodbake::gltf_detail {

// The lights (KHR_lights_punctual), cameras and extras of c.root, and a placement for every node
// of the flattened scene `nodes` (glTF node, world matrix) that names a light or a camera.
// Warnings into `warnings`: a placement below an animated node (it keeps its rest transform), a
// root extension that is not carried to the output (any but KHR_lights_punctual and
// LODBAKE_multires), a node extension the reader does not use (any but KHR_lights_punctual,
// EXT_mesh_gpu_instancing and MSFT_lod). \throw InvalidInput on a light or camera index out of range, an unknown light
// or camera type.
SceneExtras readSceneExtras(const ReadContext& c, const std::vector<std::pair<int, Mat4>>& nodes,
                            std::vector<std::string>& warnings);

// Writes `s` into a glTF being built: lights into root.extensions.KHR_lights_punctual, cameras into
// root.cameras, one root node per placement appended to `nodes` (TRS of its world matrix, its name,
// light and camera) and to scene.nodes, extras into root.extras, root.asset.extras (root.asset
// must be set) and scene.extras. Adds nothing when `s` is empty. Returns true when it wrote lights
// (the caller lists KHR_lights_punctual in extensionsUsed).
bool writeSceneExtras(const SceneExtras& s, nlohmann::json& root, nlohmann::json& nodes, nlohmann::json& scene);

// Translation, rotation (unit quaternion x, y, z, w; w >= 0) and scale with T * R * S = `m` for a
// matrix without shear; a sheared matrix gets the rotation of its Gram-Schmidt frame (a light or
// camera only uses the frame). A negative determinant goes into scale x.
void decomposeTrs(const Mat4& m, Vec3& translation, Vec4& rotation, Vec3& scale);

}  // namespace lodbake::gltf_detail
