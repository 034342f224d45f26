// Morph targets of a flattened asset, as data. No format-library types.
//
// What holds: a target's deltas are stored per wedge (Wedges::targets[t] is wedgeCount long when
// present), in the same world frame as TriMesh positions and wedge normals. Welding is by position
// only, so one welded vertex may carry wedges whose deltas differ; every consumer that moves
// vertices (posing, the level writers) splits a welded vertex per distinct deltas, as it does per
// distinct skin influences. Several source meshes with targets are flattened into the union of
// their targets: a wedge of a mesh that lacks target t has zero deltas for it.
#pragma once

#include <string>
#include <vector>

#include "lodbake/core/math.h"

namespace lodbake {

// One target's deltas, per wedge.
struct MorphDeltas {
    std::vector<Vec3> position;  // always wedgeCount long
    std::vector<Vec3> normal;    // empty, or wedgeCount long
    std::vector<Vec3> tangent;   // empty, or wedgeCount long (xyz: the handedness does not morph)
};

// What names the targets and how much of each applies at rest.
struct MorphTargets {
    std::vector<std::string> names;  // one per target ("" when the input gave none)
    std::vector<double> weights;     // default weight per target (mesh.weights / node.weights)
    size_t size() const { return weights.size(); }
    bool empty() const { return weights.empty(); }
};

}  // namespace lodbake
