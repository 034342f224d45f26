// Posing on the CPU: node transforms at a time of an animation, then linear blend skinning of a
// mesh by its wedges' influences (lodbake/core/rig.h states what the rig means).
#pragma once

#include "lodbake/core/mesh.h"

namespace lodbake {

// The matrix T * R * S of a glTF node (rotation: quaternion x, y, z, w; normalised here).
Mat4 trsMatrix(Vec3 translation, Vec4 rotation, Vec3 scale);

// The inverse of an affine matrix (last row 0 0 0 1). Returns false, leaving `out` untouched, when
// its 3x3 part is singular.
bool invertAffine(const Mat4& m, Mat4& out);

// A node's local matrix (its matrix, or TRS).
Mat4 localMatrix(const RigNode& node);

// First and last key time over every sampler of `animation` (0, 0 without keys).
struct TimeRange {
    double start = 0, end = 0;
};
TimeRange animationTimes(const Animation& animation);

// The value of sampler `s` at `time` (seconds; clamped to its keys) into out[0 .. s.comps); a
// rotation is slerped (linear) or renormalised (cubic).
void sampleAnimation(const AnimationSampler& s, double time, bool rotation, double* out);

// Global matrix of every rig node with animation `animation` sampled at `time` (seconds; clamped
// to the keys); animation < 0 or out of range = the rest pose.
std::vector<Mat4> poseNodes(const Rig& rig, int animation, double time);

// The morph target weights at `time` of `animation`: the animation's weights channel sampled
// (clamped to its keys), else the default weights (animation < 0 or without such a channel).
std::vector<double> morphWeights(const Rig& rig, const MorphTargets& morph, int animation, double time);

// `mesh` (asset.mesh or one of its levels; wedges index asset.mesh's wedge arrays) posed with
// animation `animation` at `time`: the morph targets first (weights from morphWeights), then linear
// blend skinning. Every welded vertex becomes one vertex per distinct (influence set, morphed
// position) among its wedges, so parts that move apart stay apart. Normals and tangents follow the
// targets' deltas and the blended matrices. Without influences and without a target of non-zero
// weight the mesh is returned as it is.
TriMesh poseMesh(const Rig& rig, const MorphTargets& morph, const TriMesh& mesh, int animation, double time);

}  // namespace lodbake
