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
                                               std::vector<PoseSample> poses, int threads)
    : rig_(rig),
      morph_(morph),
      a_(a),
      poses_(std::move(poses)),
      threads_(threads),
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
        posed_[k].emplace(m, threads_);
    } catch (const Impossible&) {
        // the pose scales the original to no area: nothing to see there
    }
}

const DistanceReference& PosedDistanceReference::bind() {
    if (!bind_) bind_.emplace(a_, threads_);
    return *bind_;
}

GeometricDistance PosedDistanceReference::distance(const TriMesh& b, const DistanceOptions& options) {
    Measure m(*this, b);
    while (!m.done()) m.step(options);
    return m.figures();
}

PosedDistanceReference::Measure PosedDistanceReference::measure(const TriMesh& b) { return Measure(*this, b); }

bool PosedDistanceReference::Measure::done() const {
    return !ref_ || out_.stopped || next_ > (ref_->rig_.empty() ? 0 : ref_->poses_.size());
}

void PosedDistanceReference::Measure::raiseBy(const GeometricDistance& d) {
    raise(out_.aToB, d.aToB);
    raise(out_.bToA, d.bToA);
    out_.hausdorff = std::max(out_.hausdorff, d.hausdorff);
    out_.mean = std::max(out_.mean, d.mean);
    out_.rms = std::max(out_.rms, d.rms);
    out_.stopped = d.stopped;
    const double diag = out_.diagonal;
    out_.relHausdorff = diag > 0 ? out_.hausdorff / diag : 0;
    out_.relMean = diag > 0 ? out_.mean / diag : 0;
    out_.relRms = diag > 0 ? out_.rms / diag : 0;
}

void PosedDistanceReference::Measure::step(const DistanceOptions& options) {
    PosedDistanceReference& r = *ref_;
    if (next_++ == 0) {
        out_ = surfaceDistance(r.bind(), *b_, options);
        if (!r.rig_.empty()) posedB_.resize(r.poses_.size());
        return;
    }
    // A pose that puts `a` and `b` where the bind pose or an earlier pose does measures the same
    // surfaces again: its figures would raise nothing (a higher refineFloor only refines fewer runs).
    const size_t k = next_ - 2;
    const PoseSample& s = r.poses_[k];
    r.prepare(k);
    const int same = r.sameAs_[k];
    if (same != int(k) && (same == kBindPose || r.posed_[size_t(same)])) {
        try {
            const TriMesh p = poseMesh(r.rig_, r.morph_, *b_, s.animation, s.time);
            if (sameSurface(p, same == kBindPose ? *b_ : posedB_[size_t(same)])) return;
            posedB_[k] = p;
        } catch (const Impossible&) {
            return;  // the pose scales the level to no area
        }
    }
    const std::optional<DistanceReference>& reference = same == kBindPose ? r.bind_ : r.posed_[size_t(same)];
    if (!reference) return;
    GeometricDistance d;
    DistanceOptions posedOptions = options;  // a pose's runs below the maximum so far need no refining
    posedOptions.refineFloor = std::max(options.refineFloor, out_.hausdorff);
    try {
        if (posedB_[k].triangles.empty()) posedB_[k] = poseMesh(r.rig_, r.morph_, *b_, s.animation, s.time);
        d = surfaceDistance(*reference, posedB_[k], posedOptions);
    } catch (const Impossible&) {
        return;  // the pose scales the level to no area
    }
    raiseBy(d);
}

GeometricDistance posedSurfaceDistance(const Rig& rig, const MorphTargets& morph, const TriMesh& a, const TriMesh& b,
                                       const std::vector<PoseSample>& poses, const DistanceOptions& options) {
    return PosedDistanceReference(rig, morph, a, poses, options.threads).distance(b, options);
}

}  // namespace lodbake
