// Geometric distance of a rigged asset's level from its original in the bind pose and in sampled
// poses (lodbake/core/pose_samples.h): what a level deviates by while the asset moves.
#pragma once

#include <optional>
#include <vector>

#include "lodbake/core/pose_samples.h"
#include "lodbake/metrics/distance.h"

namespace lodbake {

// surfaceDistance(a, b) in the bind pose and with both meshes posed at each of `poses` (poseMesh:
// a and b are asset.mesh or its levels, their corner wedges index the same wedge arrays); returns
// the bind-pose figures with hausdorff, mean and rms (and their one-sided parts) raised to the
// largest over the poses. The relative figures stay relative to a's bind-pose diagonal. A pose
// that flattens either mesh to no area is skipped. With DistanceOptions::stopAbove, measuring stops
// at the first pose (the bind pose first) whose distance exceeds it (GeometricDistance::stopped).
GeometricDistance posedSurfaceDistance(const Rig& rig, const MorphTargets& morph, const TriMesh& a, const TriMesh& b,
                                       const std::vector<PoseSample>& poses, const DistanceOptions& options = {});

// The original `a` of posedSurfaceDistance prepared once for all levels measured against it: its
// bind pose and each pose's posed mesh with their nearest-point trees (built on first use, held
// until the reference is destroyed). Figures are posedSurfaceDistance's exactly. A pose that leaves
// both meshes where the bind pose or an earlier pose put them (a looping animation's last key, a
// pose of joints that influence nothing) measures what that pose measured: it is not measured again.
class PosedDistanceReference {
public:
    class Measure;
    // `rig`, `morph` and `a` must outlive the reference; `threads` build its trees (0 = all cores).
    PosedDistanceReference(const Rig& rig, const MorphTargets& morph, const TriMesh& a, std::vector<PoseSample> poses,
                           int threads = 1);

    GeometricDistance distance(const TriMesh& b, const DistanceOptions& options = {});
    // distance(b) taken one pose at a time (Measure::step); `b` must outlive the measure.
    Measure measure(const TriMesh& b);
    // The bind pose's reference.
    const DistanceReference& bind();

private:
    const Rig& rig_;
    const MorphTargets& morph_;
    const TriMesh& a_;
    std::vector<PoseSample> poses_;
    int threads_ = 1;
    std::optional<DistanceReference> bind_;
    std::vector<std::optional<DistanceReference>> posed_;  // per pose; empty when the pose leaves `a` no area
    std::vector<char> posedTried_;
    std::vector<TriMesh> posedMeshes_;  // per pose tried, `a` posed (positions and triangles only)
    // Per pose tried, the bind pose (kBindPose) or the earliest pose that puts `a` exactly where it
    // does (itself when none does).
    std::vector<int> sameAs_;
    static constexpr int kBindPose = -1;

    void prepare(size_t k);
};

// A posed measure of one mesh taken one pose at a time, the bind pose first: its running figures
// are the largest over the poses measured so far (each no more than the full figures), and
// distance()'s exactly once done() with every step given the same options but for stopAbove.
class PosedDistanceReference::Measure {
public:
    Measure(PosedDistanceReference& reference, const TriMesh& b) : ref_(&reference), b_(&b) {}
    // A measure taken already: done, with these figures.
    explicit Measure(const GeometricDistance& figures) : out_(figures) {}
    bool done() const;
    // Measures the next pose. A step stopped by options.stopAbove ends the measure (figures().stopped).
    void step(const DistanceOptions& options);
    const GeometricDistance& figures() const { return out_; }

private:
    PosedDistanceReference* ref_ = nullptr;  // null: taken already
    const TriMesh* b_ = nullptr;
    size_t next_ = 0;  // 0: the bind pose; k + 1: pose k
    std::vector<TriMesh> posedB_;
    GeometricDistance out_;
    void raiseBy(const GeometricDistance& d);
};

}  // namespace lodbake
