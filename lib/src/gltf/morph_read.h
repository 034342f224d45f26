// Private to lib/src/gltf: morph targets of a flattened scene (lodbake/core/morph.h states what
// holds): which targets of the union each mesh node owns, its deltas per wedge in the world frame,
// and the weight animations merged into one channel of the union.
#pragma once

#include <array>
#include <map>
#include <utility>
#include <vector>

#include "gltf/gltf_read_context.h"

namespace tinygltf {
struct Animation;
}

namespace lodbake::gltf_detail {

struct MorphLayout {
    MorphTargets targets;        // the union over the mesh nodes, in scene order
    std::map<int, size_t> first;  // mesh node with targets -> its first target in the union
    std::map<int, size_t> count;  // ... and how many targets its mesh has
    size_t size() const { return targets.size(); }
};

// The union of the targets of the mesh nodes `nodes` (glTF node, world matrix), with the names of
// mesh.extras.targetNames and the default weights of node.weights, else mesh.weights, else 0.
// \throw InvalidInput when primitives of one mesh have different target counts or weights do not
// match them.
MorphLayout morphLayout(const ReadContext& c, const std::vector<std::pair<int, Mat4>>& nodes);

// How a mesh node's local vectors reach the world frame.
struct NodeFrame {
    Mat4 world = identity4();
    std::array<double, 9> cofactor{};  // (world^-1)^T up to det: normals
    double sign = 1;                   // sign of det(world): mirrored nodes flip normals
};
NodeFrame nodeFrame(const Mat4& world);

// Stores the deltas of vertex i of `p` (a primitive of mesh node `node`) as wedge w's, for every
// target of the union (zeros for targets the node does not own). \pre W.targets has layout.size()
// entries whose position arrays hold wedge w; normal/tangent arrays are started (zeros) on first use.
void storeWedgeDeltas(const MorphLayout& layout, int node, const PrimData& p, size_t i, const NodeFrame& frame, Wedges& W, size_t w);

// Appends wedge slots (zero deltas) up to W.vertex.size(), then stores vertex i's deltas in the last.
void appendWedgeDeltas(const MorphLayout& layout, int node, const PrimData& p, size_t i, const NodeFrame& frame, Wedges& W);

// The weights channels (glTF node, sampler) of animation `ai` merged into one sampler over the
// union and appended to `out` as its Weights channel: kept as is when one channel drives the whole
// union, else resampled at the union of key times (exact for LINEAR and STEP); channels of nodes
// without targets are ignored; a mix of interpolations or CUBICSPLINE over several meshes is
// dropped with a warning in `asset`.
void mergeWeightChannels(const ReadContext& c, const MorphLayout& layout, size_t ai, const tinygltf::Animation& a,
                         const std::vector<std::pair<int, int>>& channels, Animation& out, Asset& asset);

}  // namespace lodbake::gltf_detail
