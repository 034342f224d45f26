// The largest distance over the bind pose and sampled poses (lodbake/metrics/posed_distance.h).

#include "lodbake/metrics/posed_distance.h"

#include <algorithm>
#include <utility>

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

PosedDistanceReference::PosedDistanceReference(const Rig& rig, const MorphTargets& morph, const TriMesh& a,
                                               std::vector<PoseSample> poses)
    : rig_(rig), morph_(morph), a_(a), poses_(std::move(poses)), posed_(poses_.size()), posedTried_(poses_.size(), 0) {}

const DistanceReference& PosedDistanceReference::bind() {
    if (!bind_) bind_.emplace(a_);
    return *bind_;
}

GeometricDistance PosedDistanceReference::distance(const TriMesh& b, const DistanceOptions& options) {
    GeometricDistance out = surfaceDistance(bind(), b, options);
    if (rig_.empty()) return out;
    for (size_t k = 0; k < poses_.size(); ++k) {
        const PoseSample& s = poses_[k];
        if (!posedTried_[k]) {
            posedTried_[k] = 1;
            try {
                posed_[k].emplace(poseMesh(rig_, morph_, a_, s.animation, s.time));
            } catch (const Impossible&) {
                // the pose scales the original to no area: nothing to see there
            }
        }
        if (!posed_[k]) continue;
        GeometricDistance d;
        DistanceOptions posedOptions = options;  // a pose's runs below the maximum so far need no refining
        posedOptions.refineFloor = std::max(options.refineFloor, out.hausdorff);
        try {
            d = surfaceDistance(*posed_[k], poseMesh(rig_, morph_, b, s.animation, s.time), posedOptions);
        } catch (const Impossible&) {
            continue;  // the pose scales the level to no area
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

GeometricDistance posedSurfaceDistance(const Rig& rig, const MorphTargets& morph, const TriMesh& a, const TriMesh& b,
                                       const std::vector<PoseSample>& poses, const DistanceOptions& options) {
    return PosedDistanceReference(rig, morph, a, poses).distance(b, options);
}

}  // namespace lodbake
