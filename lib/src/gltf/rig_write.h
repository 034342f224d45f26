// Private to lib/src/gltf: writing a Rig (lodbake/core/rig.h) and per-vertex influences, shared by
// the intermediate writer (gltf_write.cpp) and the LOD chain writer (msft_lod_write.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf/gltf_buffer.h"
#include "lodbake/core/morph.h"
#include "lodbake/core/rig.h"

namespace lodbake::gltf_detail {

// Appends the rig's nodes to `nodes` (rig node k becomes node nodes.size() + k), sets
// root["skins"] = [the one skin] and root["animations"]; returns the node indices of the rig's
// roots, which the caller puts in the scene. Mesh nodes that use the skin get "skin": 0. A rig
// without joints writes its animations only (morph weights). Weights channels target every node
// of `morphNodes` (the mesh nodes whose primitives have the targets).
std::vector<int> writeRig(BufferBuilder& b, nlohmann::json& root, nlohmann::json& nodes, const Rig& rig, const std::vector<int>& morphNodes);

// root["animations"] of `rig` (rig node k is glTF node first + k; first < 0 writes the weights
// channels only); animations left without a channel are not written.
void writeAnimations(BufferBuilder& b, nlohmann::json& root, const Rig& rig, int first, const std::vector<int>& morphNodes);

// The weights channels of `a`, its samplers written again, appended to the glTF animation object
// `animation`: one channel per node of `morphNodes` (its samplers and channels indices follow
// those already there). Nothing when `a` has no weights channel.
void appendWeightChannels(BufferBuilder& b, nlohmann::json& animation, const Animation& a, const std::vector<int>& morphNodes);

// primitive["targets"]: per target, POSITION (with min/max) and, when given, NORMAL / TANGENT
// deltas (3 floats per vertex each). Nothing without targets.
void addMorphTargets(BufferBuilder& b, nlohmann::json& primitive, const std::vector<std::vector<float>>& position,
                     const std::vector<std::vector<float>>& normal, const std::vector<std::vector<float>>& tangent);

// mesh["weights"] (the default weights) and mesh.extras.targetNames when any target is named.
void addMorphDefaults(nlohmann::json& mesh, const MorphTargets& morph);

// JOINTS_0 (UNSIGNED_SHORT VEC4) and WEIGHTS_0 (FLOAT VEC4) of a primitive, 4 per vertex, into `attributes`.
void addInfluences(BufferBuilder& b, nlohmann::json& attributes, const std::vector<uint16_t>& joints, const std::vector<float>& weights);

}  // namespace lodbake::gltf_detail
