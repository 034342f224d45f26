// Each level's measured deviation from the original (level_measure.h), after vertex placement.
#include "lod/level_measure.h"

#include "lodbake/core/pose_samples.h"
#include "lodbake/core/timing.h"
#include "lodbake/metrics/distance.h"
#include "lodbake/metrics/posed_distance.h"
#include "lod/vertex_placement.h"

namespace lodbake::lod_detail {
namespace {

constexpr size_t kMeasureStride = 8;  // coarse pass of pack's measure: every 8th sample (DistanceOptions)

// The measured deviation of a level view from the original; for a rigged asset the largest over
// the bind pose and the sampled poses (posed through the wedges its corners keep).
GeometricDistance measureLevel(const Asset& asset, const LevelView& lv, bool posed, PosedDistanceReference& original,
                               const DistanceOptions& dopt) {
    TriMesh level = asTriMesh(asset.mesh, lv);
    if (posed) {
        level.wedges = asset.mesh.wedges;
        level.cornerWedges = lv.cornerWedges;
    }
    return original.distance(level, dopt);
}

// Vertex placement of level view `lv` (measured as `d`): kept when the measured Hausdorff
// distance does not grow, which `d` then holds. `time` receives the placement's seconds.
void placeVertices(const Asset& asset, LevelView& lv, bool posed, PosedDistanceReference& original,
                   const DistanceOptions& dopt, GeometricDistance& d, PackLevelReport::Placement& report, PackLevelProfile& time) {
    auto t0 = Clock::now();
    PlacementOptions po;
    po.threads = dopt.threads;
    PlacementResult placed = placeLevelVertices(asset.mesh, original.bind(), *lv.data, po);
    report = {true, false, d.hausdorff, d.relHausdorff, d.rms, d.relRms, placed.moved, placed.fixed, placed.shortened, placed.rounds};
    time.placeSeconds = secondsSince(t0);
    if (placed.moved > 0) {
        lv.positions = std::move(placed.positions);
        // Only a kept placement needs its figures: the measure stops once it exceeds d's Hausdorff.
        DistanceOptions bounded = dopt;
        bounded.stopAbove = d.hausdorff;
        GeometricDistance after = measureLevel(asset, lv, posed, original, bounded);
        report.applied = !after.stopped && after.hausdorff <= d.hausdorff;
        if (report.applied) d = after;
        else lv.positions.clear();
    }
    time.placementSeconds = secondsSince(t0);
}

}  // namespace

void measureLevels(const Asset& asset, std::vector<LevelView>& views, const PackOptions& options, PackResult& res,
                   std::vector<PackLevelProfile>& time, const std::function<void(double)>& progress) {
    const std::vector<PoseSample> poses = samplePoses(asset.rig, options.poses);
    const size_t n = views.size();
    res.reports.resize(n);
    time.resize(n);
    DistanceOptions dopt;
    dopt.samplesPerSide = options.distanceSamples;
    dopt.threads = options.threads;
    // The deviation that picks switch distances is a maximum: a coarse pass finds the worst runs of
    // samples, which alone are sampled densely.
    dopt.refineStride = kMeasureStride;
    // The original's trees, built once for every level and placement and freed before the bakes.
    PosedDistanceReference original(asset.rig, asset.morph, asset.mesh, poses);
    const bool posed = !poses.empty();
    GeometricDistance previous;  // level k - 1's, before vertex placement
    for (size_t k = 0; k < n; ++k) {
        PackLevelReport& r = res.reports[k];
        r.source = views[k].source;
        r.maxDeviation = views[k].maxDeviation;
        if (k == 0) continue;
        // A level that repeats the one before it (unmoved) measures the same.
        GeometricDistance d = k > 1 && sameSurface(views[k], views[k - 1]) ? previous : measureLevel(asset, views[k], posed, original, dopt);
        previous = d;
        if (options.vertexPlacement && options.projectLevels && views[k].data)
            placeVertices(asset, views[k], posed, original, dopt, d, r.placement, time[k]);
        r.hausdorff = d.hausdorff;
        r.relHausdorff = d.relHausdorff;
        r.rms = d.rms;
        r.relRms = d.relRms;
        progress(0.3 * double(k) / double(n));
    }
}

}  // namespace lodbake::lod_detail
