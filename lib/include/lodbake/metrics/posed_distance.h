// Geometric distance of a rigged asset's level from its original in the bind pose and in sampled
// poses (lodbake/core/pose_samples.h): what a level deviates by while the asset moves.
#pragma once

#include <vector>

#include "lodbake/core/pose_samples.h"
#include "lodbake/metrics/distance.h"

namespace lodbake {

// surfaceDistance(a, b) in the bind pose and with both meshes posed at each of `poses` (poseMesh:
// a and b are asset.mesh or its levels, their corner wedges index the same wedge arrays); returns
// the bind-pose figures with hausdorff, mean and rms (and their one-sided parts) raised to the
// largest over the poses. The relative figures stay relative to a's bind-pose diagonal. A pose
// that flattens either mesh to no area is skipped.
GeometricDistance posedSurfaceDistance(const Rig& rig, const MorphTargets& morph, const TriMesh& a, const TriMesh& b,
                                       const std::vector<PoseSample>& poses, const DistanceOptions& options = {});

}  // namespace lodbake
