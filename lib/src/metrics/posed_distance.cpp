// The largest distance over the bind pose and sampled poses (lodbake/metrics/posed_distance.h).

#include "lodbake/metrics/posed_distance.h"

#include <algorithm>
#include <cstring>
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

// Whether x and y have the same triangles at bit-identical positions: the distance reads nothing else.
bool sameSurface(const TriMesh& x, const TriMesh& y) {
    return x.positions.size() == y.positions.size() && x.triangles.size() == y.triangles.size() &&
           std::memcmp(x.positions.data(), y.positions.data(), x.positions.size() * sizeof(Vec3)) == 0 &&
           std::memcmp(x.triangles.data(), y.triangles.data(), x.triangles.size() * sizeof(Tri)) == 0;
}

}  // namespace

PosedDistanceReference::PosedDistanceReference(const Rig& rig, const MorphTargets& morph, const TriMesh& a,
                                               std::vector<PoseSample> poses)
    : rig_(rig),
      morph_(morph),
      a_(a),
      poses_(std::move(poses)),
      posed_(poses_.size()),
      posedTried_(poses_.size(), 0),
      posedMeshes_(poses_.size()),
      sameAs_(poses_.size(), kBindPose) {}

void PosedDistanceReference::prepare(size_t k) {
    if (posedTried_[k]) return;
    posedTried_[k] = 1;
    const PoseSample& s = poses_[k];
    TriMesh& m = posedMeshes_[k];
    const TriMesh posed = poseMesh(rig_, morph_, a_, s.animation, s.time);
    m.positions = posed.positions;
    m.triangles = posed.triangles;
    sameAs_[k] = int(k);
    if (sameSurface(m, a_)) sameAs_[k] = kBindPose;
    for (size_t j = 0; j < k && sameAs_[k] == int(k); ++j)
        if (sameAs_[j] == int(j) && sameSurface(m, posedMeshes_[j])) sameAs_[k] = int(j);
    if (sameAs_[k] != int(k)) return;  // measured through the bind pose or pose sameAs_[k]
    try {
        posed_[k].emplace(m);
    } catch (const Impossible&) {
        // the pose scales the original to no area: nothing to see there
    }
}

const DistanceReference& PosedDistanceReference::bind() {
    if (!bind_) bind_.emplace(a_);
    return *bind_;
}

GeometricDistance PosedDistanceReference::distance(const TriMesh& b, const DistanceOptions& options) {
    GeometricDistance out = surfaceDistance(bind(), b, options);
    if (rig_.empty() || out.stopped) return out;
    // A pose that puts `a` and `b` where the bind pose or an earlier pose does measures the same
    // surfaces again: its figures would raise nothing (a higher refineFloor only refines fewer runs).
    std::vector<TriMesh> posedB(poses_.size());
    for (size_t k = 0; k < poses_.size(); ++k) {
        const PoseSample& s = poses_[k];
        prepare(k);
        const int same = sameAs_[k];
        if (same != int(k) && (same == kBindPose || posed_[size_t(same)])) {
            try {
                const TriMesh p = poseMesh(rig_, morph_, b, s.animation, s.time);
                if (sameSurface(p, same == kBindPose ? b : posedB[size_t(same)])) continue;
                posedB[k] = p;
            } catch (const Impossible&) {
                continue;  // the pose scales the level to no area
            }
        }
        const std::optional<DistanceReference>& reference = same == kBindPose ? bind_ : posed_[size_t(same)];
        if (!reference) continue;
        GeometricDistance d;
        DistanceOptions posedOptions = options;  // a pose's runs below the maximum so far need no refining
        posedOptions.refineFloor = std::max(options.refineFloor, out.hausdorff);
        try {
            if (posedB[k].triangles.empty()) posedB[k] = poseMesh(rig_, morph_, b, s.animation, s.time);
            d = surfaceDistance(*reference, posedB[k], posedOptions);
        } catch (const Impossible&) {
            continue;  // the pose scales the level to no area
        }
        raise(out.aToB, d.aToB);
        raise(out.bToA, d.bToA);
        out.hausdorff = std::max(out.hausdorff, d.hausdorff);
        out.mean = std::max(out.mean, d.mean);
        out.rms = std::max(out.rms, d.rms);
        if (d.stopped) {  // the poses after it could only raise the figures
            out.stopped = true;
            break;
        }
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
