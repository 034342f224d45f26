// Each level's measured deviation from the original (level_measure.h), after vertex placement.
#include "lod/level_measure.h"

#include "lodbake/core/parallel.h"
#include "lodbake/core/pose_samples.h"
#include "lodbake/core/timing.h"
#include "lodbake/metrics/distance.h"
#include "lodbake/metrics/posed_distance.h"
#include "lod/vertex_placement.h"

#include <algorithm>
#include <mutex>
#include <optional>
#include <utility>

namespace lodbake::lod_detail {
namespace {

constexpr size_t kMeasureStride = 8;  // coarse pass of pack's measure: every 8th sample (DistanceOptions)
// A level within this fraction of the original's bounding-box diagonal is left where simplify put
// it: that is some eight float steps of a coordinate the diagonal's size, the precision its
// positions are written with, so vertex placement could not bring it measurably closer.
constexpr double kOnOriginal = 0x1p-20;

// A level view as the measure reads it: for a rigged asset posed through the wedges its corners keep.
TriMesh measuredMesh(const Asset& asset, const LevelView& lv, bool posed) {
    TriMesh level = asTriMesh(asset.mesh, lv);
    if (posed) {
        level.wedges = asset.mesh.wedges;
        level.cornerWedges = lv.cornerWedges;
    }
    return level;
}

// Whether the level measured by `after` deviates no more than measured by `before` (full
// Hausdorff distances, the largest over the bind pose and the sampled poses), measuring only what
// decides it: the side behind is measured a pose further, and a side's last poses stop once it
// passes the other's full figure. When it returns true `after` is done, otherwise `before`.
bool noWorse(PosedDistanceReference::Measure& after, PosedDistanceReference::Measure& before, const DistanceOptions& dopt) {
    for (;;) {
        const double a = after.figures().hausdorff, b = before.figures().hausdorff;
        if (after.done() && a <= b) return true;
        if (before.done() && a > b) return false;
        DistanceOptions bounded = dopt;
        if (before.done() || (!after.done() && a < b)) {
            if (before.done()) bounded.stopAbove = b;
            after.step(bounded);
        } else {
            if (after.done()) bounded.stopAbove = a;
            before.step(bounded);
        }
    }
}

// Vertex placement of level view `lv`, kept when the measured Hausdorff distance does not grow.
// `before` is the level's measure as simplify left it (of `level`; done when the level was measured
// already). Returns the level's figures: after placement when kept, else before's (then done).
// `time` receives the placement's seconds.
GeometricDistance placeVertices(const Asset& asset, LevelView& lv, bool posed, PosedDistanceReference& original,
                                const DistanceOptions& dopt, const TriMesh& level, double diagonal,
                                PosedDistanceReference::Measure& before, PackLevelReport::Placement& report,
                                PackLevelProfile& time) {
    auto t0 = Clock::now();
    // A level on the original to its positions' precision is not moved. It is measured first up
    // to that bound: one within it is then measured in full, one beyond it stops at its first
    // sample past the bound and is measured afresh (an unstopped measure's figures are the full ones).
    const double onOriginal = kOnOriginal * diagonal;
    if (!before.done()) {
        DistanceOptions bounded = dopt;
        bounded.stopAbove = onOriginal;
        while (!before.done()) before.step(bounded);
        if (before.figures().stopped) before = original.measure(level);
    }
    if (before.done() && before.figures().hausdorff <= onOriginal) {
        const GeometricDistance& b = before.figures();
        report = {true, false, b.hausdorff, b.relHausdorff, b.rms, b.relRms, 0, 0, 0, 0,
                  "the level lies on the original to its positions' precision"};
        time.placementSeconds = secondsSince(t0);
        return b;
    }
    PlacementOptions po;
    po.threads = dopt.threads;
    PlacementResult placed = placeLevelVertices(asset.mesh, original.bind(), *lv.data, po);
    time.placeSeconds = secondsSince(t0);
    bool applied = false;
    GeometricDistance d;
    if (placed.moved > 0) {
        lv.positions = std::move(placed.positions);
        const TriMesh moved = measuredMesh(asset, lv, posed);
        PosedDistanceReference::Measure after = original.measure(moved);
        applied = noWorse(after, before, dopt);
        if (applied) d = after.figures();
        else lv.positions.clear();
    }
    while (!applied && !before.done()) before.step(dopt);
    if (!applied) d = before.figures();
    // Kept: the figures before it measured only until they reached those after it (a lower bound).
    const GeometricDistance& b = before.figures();
    report = {true, applied, b.hausdorff, b.relHausdorff, b.rms, b.relRms, placed.moved, placed.fixed, placed.shortened, placed.rounds, {}};
    time.placementSeconds = secondsSince(t0);
    return d;
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
    PosedDistanceReference original(asset.rig, asset.morph, asset.mesh, poses, options.threads);
    const bool posed = !poses.empty();
    const double diagonal = bounds(asset.mesh).diagonal();  // the measures' (their relative figures')
    for (size_t k = 0; k < n; ++k) {
        res.reports[k].source = views[k].source;
        res.reports[k].maxDeviation = views[k].maxDeviation;
    }
    // Levels k-1 and k of the same triangles may show the same surface: level k then takes k-1's
    // figures, so they are measured in one run, in order. Runs are independent of each other: an
    // unposed original is read only (its bind pose's trees built first), and the runs take the
    // threads, largest first (each level's placement still splits its own queries). A posed
    // original builds its poses' trees as measures first reach them: one run after another.
    std::vector<std::pair<size_t, size_t>> runs;  // [first, last) level
    for (size_t k = 1; k < n; ++k) {
        const LevelView& a = views[k - 1];
        const bool sameTriangles = k > 1 && a.triangles == views[k].triangles && a.cornerWedges == views[k].cornerWedges && a.faces == views[k].faces;
        if (sameTriangles) runs.back().second = k + 1;
        else runs.push_back({k, k + 1});
    }
    const bool place = options.vertexPlacement && options.projectLevels;
    if (!posed) {
        // Built here, not by the first query of whichever run comes first: the closest-point
        // ranks the placements read are set on the tree the measures search.
        const DistanceReference& bind = original.bind();
        if (place) bind.closestPoints({}, 1);
    }
    std::stable_sort(runs.begin(), runs.end(), [&](const auto& x, const auto& y) {
        return views[x.first].triangles.size() > views[y.first].triangles.size();
    });
    // Progress is reported one level at a time; once it throws (the caller cancels), no run
    // reports or starts another level.
    std::mutex progressMutex;
    size_t measured = 0;
    bool stopped = false;
    auto measureRun = [&](std::pair<size_t, size_t> run) {
        // Level k - 1's figures before vertex placement, when measured in full.
        std::optional<GeometricDistance> previous;
        for (size_t k = run.first; k < run.second; ++k) {
            {
                std::lock_guard<std::mutex> lock(progressMutex);
                if (stopped) return;
            }
            PackLevelReport& r = res.reports[k];
            const TriMesh level = measuredMesh(asset, views[k], posed);
            PosedDistanceReference::Measure before =
                k > run.first && previous && sameSurface(views[k], views[k - 1]) ? PosedDistanceReference::Measure(*previous)
                                                                                  : original.measure(level);
            GeometricDistance d;
            if (place && views[k].data) {
                d = placeVertices(asset, views[k], posed, original, dopt, level, diagonal, before, r.placement, time[k]);
            } else {
                while (!before.done()) before.step(dopt);
                d = before.figures();
            }
            previous.reset();
            if (before.done() && !before.figures().stopped) previous = before.figures();
            r.hausdorff = d.hausdorff;
            r.relHausdorff = d.relHausdorff;
            r.rms = d.rms;
            r.relRms = d.relRms;
            std::lock_guard<std::mutex> lock(progressMutex);
            if (stopped) return;
            try {
                progress(0.3 * double(++measured) / double(n));
            } catch (...) {
                stopped = true;
                throw;
            }
        }
    };
    parallelFor(runs.size(), posed ? 1 : options.threads, [&](size_t i) { measureRun(runs[i]); });
}

}  // namespace lodbake::lod_detail
