// Private to lib/src/gltf: reading what makes an asset move (lodbake/core/rig.h) from a loaded
// glTF, and the influences of one primitive's vertices in the unified skin.
#pragma once

#include <array>
#include <map>
#include <utility>
#include <vector>

#include "gltf/gltf_read_context.h"

namespace tinygltf {
struct AnimationSampler;
}

namespace lodbake::gltf_detail {

struct MorphLayout;

// How the vertices of one mesh node's primitives bind to the unified skin.
struct NodeInfluence {
    bool skinned = false;         // the node has a skin: vertices read JOINTS_n / WEIGHTS_n
    std::vector<uint16_t> joint;  // the node's skin joint k -> unified joint (skinned)
    uint16_t rigid = 0;           // the unified joint of every vertex (not skinned)
};

struct RigRead {
    Rig rig;                                // empty: the asset is static
    std::map<int, NodeInfluence> meshNodes;  // glTF node -> its binding (every mesh node when the rig is not empty)
    size_t truncated = 0;                   // vertices that had more than 4 influences
    size_t unweighted = 0;                  // vertices of skinned nodes without JOINTS_0 (Draco primitives)
    std::vector<int> nodeSource;            // glTF node of each rig node (rig.nodes order)
    std::vector<int> animationSource;       // glTF animation of each rig animation (rig.animations order)
};

// The rig of the flattened scene `nodes` (glTF node, world matrix): every skin used by a mesh
// node and every unskinned mesh node (a joint of its own) merged into one skin, the hierarchy
// above those joints and the animation targets, and the translation / rotation / scale
// animations, with the morph weight animations merged over the union of `layout` (the rig is then
// animations only when nothing else moves). Animations that move no mesh are dropped with a
// warning in `asset`. \throw InvalidInput on malformed skins or animations.
RigRead readRig(const ReadContext& c, const std::vector<std::pair<int, Mat4>>& nodes, const MorphLayout& layout, Asset& asset);

// Sampler `s` with `comps` values per key (`scalarOutput`: a SCALAR output accessor holding them
// in turn, as morph weights are stored). \throw InvalidInput on a count that does not match the
// key times, or key times that do not increase.
AnimationSampler readSampler(const ReadContext& c, const tinygltf::AnimationSampler& s, int comps, const std::string& what,
                             bool scalarOutput = false);

// Influences of the vertices of `p` (4 largest, merged per unified joint, renormalised; a vertex
// without weight binds to the node's first joint), appended to `joints` / `weights`; counts the
// vertices that had more than 4 in rr.truncated. \throw InvalidInput on a joint index beyond the skin.
void primitiveInfluences(const ReadContext& c, const PrimData& p, const NodeInfluence& binding, RigRead& rr,
                         std::vector<std::array<uint16_t, 4>>& joints, std::vector<Vec4>& weights, const std::string& what);

// The warnings about influences read: truncated to 4, or missing on a skinned node.
std::vector<std::string> influenceWarnings(const RigRead& rr);

}  // namespace lodbake::gltf_detail
