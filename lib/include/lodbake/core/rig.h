// What makes a flattened asset move: the node hierarchy its joints hang from, ONE skin (joints and
// inverse bind matrices) and the animations of those nodes, as data. No format-library types.
//
// What holds: positions in TriMesh are world space in bind/rest pose. A vertex with influences
// (Wedges::joints/weights) is posed as sum_i w_i * G(joint_i) * inverseBind[joint_i] * p, where G
// is the joint node's global matrix at the pose's time. The reader folds each primitive's own
// world matrix M into the inverse bind matrices (IBM * M^-1), so that posing reproduces the input;
// a mesh node that is not skinned in the input is a joint of its own (inverse bind = M^-1) with
// weight 1, so rigid node animation survives the flattening.
#pragma once

#include <string>
#include <vector>

#include "lodbake/core/math.h"

namespace lodbake {

struct RigNode {
    std::string name;
    int parent = -1;           // index into Rig::nodes; -1 = a root of the scene
    bool hasMatrix = false;    // the node's local transform is `matrix` (never animated) ...
    Mat4 matrix = identity4();
    Vec3 translation{0, 0, 0};  // ... else T * R * S
    Vec4 rotation{0, 0, 0, 1};  // unit quaternion x, y, z, w
    Vec3 scale{1, 1, 1};
};

enum class Interpolation { Linear, Step, CubicSpline };
// Weights: the morph target weights of the flattened mesh (Asset::morph); the channel's node is
// -1 and its sampler has one component per target.
enum class AnimationPath { Translation, Rotation, Scale, Weights };

struct AnimationSampler {
    std::vector<double> times;   // seconds, increasing
    std::vector<double> values;  // comps per key (x3 for CubicSpline: in-tangent, value, out-tangent)
    int comps = 3;               // 3 (translation, scale), 4 (rotation) or the morph target count (weights)
    Interpolation interpolation = Interpolation::Linear;
};

struct AnimationChannel {
    int sampler = 0;  // index into Animation::samplers
    int node = 0;     // index into Rig::nodes; -1 for Weights (the mesh)
    AnimationPath path = AnimationPath::Translation;
};

struct Animation {
    std::string name;
    std::vector<AnimationSampler> samplers;
    std::vector<AnimationChannel> channels;
};

// Rig::animations may exist without a skin (joints empty) when they only drive morph weights.
struct Rig {
    std::vector<RigNode> nodes;     // parents before children
    std::vector<int> joints;        // the one skin: joint k is node joints[k]
    std::vector<Mat4> inverseBind;  // per joint, in the flattened (world, bind pose) frame
    std::vector<Animation> animations;
    bool empty() const { return joints.empty(); }
};

}  // namespace lodbake
