// Poses sampled from a rig, for measures that must hold when the asset moves: a deterministic set
// of (animation, time) pairs and the mesh's wedges posed at each (lodbake/core/pose.h poses them).
#pragma once

#include <cstdint>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

struct PoseSample {
    int animation = -1;  // index into Rig::animations; -1 = the rest pose of the nodes
    double time = 0;     // seconds
};

struct PoseSampleOptions {
    // Times per animation, evenly spaced from its first to its last key (>= 3: start, middle and
    // end among them when odd). 0 = no sampled poses at all (measures stay in the bind pose).
    int perAnimation = 5;
    // At most this many poses in all (the rest pose included): with many animations each gets
    // fewer times (at least its middle).
    int maxPoses = 16;
};

// The rest pose of the nodes, then each animation's times, in animation order. Empty for an
// asset without a rig or with perAnimation = 0.
std::vector<PoseSample> samplePoses(const Rig& rig, const PoseSampleOptions& options);

// The mesh's wedges at each sampled pose, and which wedges move rigidly together.
struct PosedWedges {
    // positions[k][w]: wedge w's vertex posed by its own influences at sample k (model units).
    std::vector<std::vector<Vec3>> positions;
    // Per wedge: the joint it is bound to with weight 1 when that joint's skinning matrix is a
    // rigid motion at every sample (kNotRigid otherwise). Points of wedges with the same rigid
    // joint keep their distances in every pose, so a measure over them equals its bind-pose value.
    std::vector<uint32_t> rigidJoint;
    static constexpr uint32_t kNotRigid = 0xffffffffu;
    bool empty() const { return positions.empty(); }
};

// \pre mesh is an asset's mesh whose wedges carry the rig's influences (Wedges::joints/weights).
// Empty when `samples` is empty, the rig is empty or the mesh has no influences.
PosedWedges poseWedges(const Rig& rig, const MorphTargets& morph, const TriMesh& mesh, const std::vector<PoseSample>& samples);

}  // namespace lodbake
