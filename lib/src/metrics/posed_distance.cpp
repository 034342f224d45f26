// The largest distance over the bind pose and sampled poses (lodbake/metrics/posed_distance.h).

#include "lodbake/metrics/posed_distance.h"

#include <algorithm>

#include "lodbake/core/errors.h"
#include "lodbake/core/pose.h"

namespace lodbake {

namespace {

void raise(OneSidedDistance& to, const OneSidedDistance& d) {
    to.max = std::max(to.max, d.max);
    to.mean = std::max(to.mean, d.mean);
    to.rms = std::max(to.rms, d.rms);
}

}  // namespace

GeometricDistance posedSurfaceDistance(const Rig& rig, const MorphTargets& morph, const TriMesh& a, const TriMesh& b,
                                       const std::vector<PoseSample>& poses, const DistanceOptions& options) {
    GeometricDistance out = surfaceDistance(a, b, options);
    if (rig.empty()) return out;
    for (const PoseSample& s : poses) {
        GeometricDistance d;
        try {
            d = surfaceDistance(poseMesh(rig, morph, a, s.animation, s.time),
                                poseMesh(rig, morph, b, s.animation, s.time), options);
        } catch (const Impossible&) {
            continue;  // the pose scales a mesh to no area: nothing to see there
        }
        raise(out.aToB, d.aToB);
        raise(out.bToA, d.bToA);
        out.hausdorff = std::max(out.hausdorff, d.hausdorff);
        out.mean = std::max(out.mean, d.mean);
        out.rms = std::max(out.rms, d.rms);
    }
    const double diag = out.diagonal;
    out.relHausdorff = diag > 0 ? out.hausdorff / diag : 0;
    out.relMean = diag > 0 ? out.mean / diag : 0;
    out.relRms = diag > 0 ? out.rms / diag : 0;
    return out;
}

}  // namespace lodbake
