// M-AGSphere levels (thesis 2.4; DESIGN.md "M-AGSphere"). See agsphere.h for the model and
// docs/architecture.md for the files of the pipeline, read in this order:
//
//   topology.cpp        face normals and their finest cells on the (rotated) sphere, half-edge
//                       twins, vertex -> faces
//   contour.cpp         with views/lights: the faces of the contour edges on each view's projected
//                       outline, pinned (kept unchanged as one-face regions whose runs keep every
//                       vertex)
//   regions.cpp         the regions of a cut: edge-connected faces whose normals share a cell
//   boundary_runs.cpp   region boundaries split into runs, simplified by Douglas-Peucker within
//                       their cells' error thresholds
//   selection.cpp       per uniform depth: estimated triangles and error per cell; per level: the
//                       cut refined by class and error until the estimate reaches the target,
//                       balanced (neighbouring cells at most two depths apart)
//   retriangulate.cpp   ear clipping per region (polygon.cpp) with fallbacks (restore runs, keep
//                       original faces) until the level is manifold where the input is and no new
//                       triangle pokes out of a view's outline
//   assemble_level.cpp  faces, wedges and simplification pairs of a level
//
// This file runs them: levels are built coarsest first so that each cut contains the next coarser
// level's final cut (regions nest across levels: a region hierarchy).
#include "lodbake/agsphere/agsphere.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "agsphere/assemble_level.h"
#include "agsphere/contour.h"
#include "agsphere/regions.h"
#include "agsphere/retriangulate.h"
#include "agsphere/selection.h"
#include "agsphere/sphere_table.h"
#include "agsphere/topology.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/timing.h"

namespace lodbake {
namespace {

using namespace agsphere_detail;

// A region of at least this many faces that has to keep its original faces gets its cell split.
constexpr uint32_t kRefineKeptFaces = 16;
// Rounds of such splits per build of a level.
constexpr int kRefineRounds = 8;
// Levels are rebuilt until their triangle count is within this fraction of the target (or after
// kCalibrationRounds extra builds).
constexpr int kCalibrationRounds = 3;
constexpr double kCalibrationTolerance = 0.05;

void checkOptions(const TriMesh& mesh, const AgsphereOptions& options) {
    if (mesh.triangleCount() == 0) throw Impossible("the mesh has no triangles");
    if (options.maxDepth < 0 || options.maxDepth > kAgsphereMaxDepth)
        throw Impossible("sphere depth must be in [0, " + std::to_string(kAgsphereMaxDepth) + "]");
    if (options.levels.empty()) throw Impossible("no level targets given");
}

// The options with views and lights as unit directions in the sphere's frame (cells are
// classified there).
AgsphereOptions inSphereFrame(const AgsphereOptions& options, const Frame& frame) {
    AgsphereOptions sphereOptions = options;
    for (Vec3& v : sphereOptions.views) v = frame.toSphere(normalize(v));
    for (Vec3& v : sphereOptions.lights) v = frame.toSphere(normalize(v));
    return sphereOptions;
}

// keepOutline: pins the outline faces of every view (at its eye distance) and every light (at
// infinity: the outline seen from a light is the light silhouette, the shadow's outline), and
// keeps their rasters for the protrusion test.
void pinOutlineFaces(const TriMesh& mesh, const AgsphereOptions& options, Topology& t, AgsphereResult& res) {
    if (!options.keepOutline || (options.views.empty() && options.lights.empty())) return;
    OutlineOptions oo;
    oo.viewDistance = options.viewDistance;
    oo.rings = options.outlineRings;
    OutlineFaces of = outlineFaces(mesh, options.views, oo);
    oo.viewDistance = 0;
    OutlineFaces lit = outlineFaces(mesh, options.lights, oo);
    for (uint32_t f = 0; f < t.nf; ++f) of.keep[f] = !t.degenerate[f] && (of.keep[f] || lit.keep[f]);
    for (OutlineView& v : lit.views) of.views.push_back(std::move(v));
    res.contourEdges = of.contourEdges + lit.contourEdges;
    res.outlineEdges = of.outlineEdges + lit.outlineEdges;
    t.pinned = std::move(of.keep);
    t.outline = std::move(of);
    for (char k : t.pinned) res.outlineFaces += k != 0;
}

struct PlannedLevel {
    AgsphereTarget target;
    uint64_t triangles;  // target triangle count, >= 1
    Selection sel;
};

// The targets as triangle counts, finest first (stable for equal counts).
std::vector<PlannedLevel> planLevels(const AgsphereOptions& options, uint32_t faceCount) {
    std::vector<PlannedLevel> plan;
    for (const AgsphereTarget& g : options.levels) {
        uint64_t n = g.triangles;
        if (g.ratio > 0) n = uint64_t(std::llround(g.ratio * double(faceCount)));
        if (n == 0) n = 1;
        plan.push_back({g, n, {}});
    }
    std::stable_sort(plan.begin(), plan.end(),
                     [](const PlannedLevel& a, const PlannedLevel& b) { return a.triangles > b.triangles; });
    return plan;
}

// What every level build shares.
struct LevelContext {
    const Topology& t;
    const AgsphereOptions& sphereOptions;  // views and lights in the sphere's frame
    const DepthTables& tables;
    const std::vector<std::array<uint32_t, 3>>& neighbours;
    double boundaryTolerance;
};

// Builds the level of `cut` (first made to contain `coarser` and balanced). A region of at least
// kRefineKeptFaces faces that keeps its original faces (its boundary is not a simple polygon in
// its plane) has its cell split and the level rebuilt, up to kRefineRounds times; `cut` is updated.
LevelBuild buildOnCut(const LevelContext& c, const Cut& coarser, Cut& cut) {
    const int D = c.t.maxDepth;
    if (!coarser.empty())
        for (size_t z = 0; z < cut.size(); ++z) cut[z] = std::max(cut[z], coarser[z]);
    balanceCut(c.t, c.neighbours, cut);
    LevelBuild B = buildLevelGeometry(c.t, cut, c.boundaryTolerance);
    for (int round = 0; round < kRefineRounds; ++round) {
        bool refined = false;
        for (uint32_t i = 0; i < B.regions.count(); ++i) {
            if (B.out[i].state != RegionState::Kept) continue;
            CellId cell = B.regions.cell[i];
            if (B.regions.faceOffset[i + 1] - B.regions.faceOffset[i] < kRefineKeptFaces || cell.depth >= D) continue;
            uint32_t span = finestSpan(D, cell.depth);
            for (uint32_t z = cell.index * span; z < (cell.index + 1) * span; ++z)
                cut[z] = std::max<uint8_t>(cut[z], uint8_t(cell.depth + 1));
            refined = true;
        }
        if (!refined) break;
        balanceCut(c.t, c.neighbours, cut);
        B = buildLevelGeometry(c.t, cut, c.boundaryTolerance);
    }
    return B;
}

// The estimates behind the selection ignore restored runs and split cells, so a level whose
// selection stopped at its target is rebuilt (up to kCalibrationRounds times) with the estimate
// target scaled by target / reached, keeping the build closest to the target; p.sel becomes the
// kept build's selection.
LevelBuild buildCalibratedLevel(const LevelContext& c, const Cut& coarser, PlannedLevel& p) {
    const double goal = double(p.triangles);
    LevelBuild L = buildOnCut(c, coarser, p.sel.cut);
    uint64_t reached = levelTriangleCount(L);
    double estimateTarget = goal;
    for (int round = 0; round < kCalibrationRounds && p.sel.stopReason == "target"; ++round) {
        if (std::fabs(double(reached) - goal) <= kCalibrationTolerance * goal) break;
        estimateTarget = std::max(1.0, estimateTarget * goal / double(std::max<uint64_t>(reached, 1)));
        Selection sel = selectCut(c.t, c.sphereOptions, c.tables, uint64_t(std::llround(estimateTarget)));
        balanceCut(c.t, c.neighbours, sel.cut);
        LevelBuild B = buildOnCut(c, coarser, sel.cut);
        uint64_t n = levelTriangleCount(B);
        if (std::fabs(double(n) - goal) < std::fabs(double(reached) - goal)) {
            L = std::move(B);
            reached = n;
            p.sel = std::move(sel);
        }
    }
    return L;
}

AgsphereLevelStats levelStats(const LevelContext& c, const Selection& sel, const LevelBuild& L) {
    AgsphereLevelStats st;
    st.stopReason = sel.stopReason;
    st.estimatedTriangles = sel.estimate;
    countCutCells(c.t, c.sphereOptions, sel.cut, st);
    for (uint32_t i = 0; i < L.regions.count(); ++i) {
        const RegionOut& o = L.out[i];
        bool pinned = c.t.isPinned(L.regions.rep[i]);
        st.retriangulatedRegions += o.state == RegionState::Retriangulated;
        st.keptRegions += o.state == RegionState::Kept && !pinned;
        st.outlineFaces += pinned;
    }
    st.restoredRuns = L.restoredRuns;
    st.runs = uint32_t(L.runs.runs.size());
    for (const Run& run : L.runs.runs) {
        if (run.restored || run.nonManifold) continue;
        for (size_t i = 1; i + 1 < run.vertices.size(); ++i)
            if (!L.runs.kept[run.vertices[i]]) {
                ++st.simplifiedRuns;
                break;
            }
    }
    return st;
}

}  // namespace

uint32_t agsphereRegions(const TriMesh& mesh, int depth, std::vector<uint32_t>& faceRegion) {
    if (depth < 0 || depth > kAgsphereMaxDepth) throw InvalidInput("agsphere depth out of range");
    Topology t = buildTopology(mesh, depth);
    Cut cut(sphereCellCount(depth), uint8_t(depth));
    Regions r = buildRegions(t, cut);
    faceRegion.resize(t.nf);
    for (uint32_t f = 0; f < t.nf; ++f) faceRegion[f] = r.rep[r.of[f]];
    return r.count();
}

AgsphereResult buildAgsphere(const TriMesh& mesh, const AgsphereOptions& options) {
    checkOptions(mesh, options);
    auto progress = [&](double f) {
        if (options.progress && !options.progress(f)) throw Cancelled("agsphere-build: cancelled");
    };
    AgsphereResult res;
    res.multires.generator = "agsphere-build";
    const int D = options.maxDepth;

    // 1. Cells: the sphere turned so that the first view (or light) is octant 0's centre, every
    //    face's finest cell, and the pinned outline faces.
    auto t0 = Clock::now();
    const Frame frame = alignedFrame(options);
    const AgsphereOptions sphereOptions = inSphereFrame(options, frame);
    Topology t = buildTopology(mesh, D, frame);
    res.diagonal = t.diagonal;
    pinOutlineFaces(mesh, options, t, res);
    const auto neighbours = sphereNeighbourTable(D);
    res.secondsCells = secondsSince(t0);
    progress(0.05);

    // 2. Depth statistics: estimated triangles and error threshold of every cell at every depth.
    auto t1 = Clock::now();
    DepthTables tables;
    tables.estimate.resize(size_t(D) + 1);
    tables.threshold.resize(size_t(D) + 1);
    for (int d = 0; d <= D; ++d) {
        res.depths.push_back(measureDepth(t, d, options.boundaryTolerance, tables));
        progress(0.05 + 0.35 * double(d + 1) / double(D + 1));
    }
    res.secondsDepths = secondsSince(t1);

    // 3. Selection: one balanced cut per target, finest level first.
    auto t2 = Clock::now();
    std::vector<PlannedLevel> plan = planLevels(options, t.nf);
    for (PlannedLevel& p : plan) {
        p.sel = selectCut(t, sphereOptions, tables, p.triangles);
        balanceCut(t, neighbours, p.sel.cut);
    }
    res.secondsSelect = secondsSince(t2);

    // 4. Levels, coarsest first: each cut is made to contain the coarser level's final cut, built,
    //    calibrated towards its target and assembled.
    auto t3 = Clock::now();
    const LevelContext context{t, sphereOptions, tables, neighbours, options.boundaryTolerance};
    std::vector<Level> built(plan.size());
    std::vector<AgsphereLevelStats> builtStats(plan.size());
    Cut coarser;
    for (size_t k = plan.size(); k-- > 0;) {
        auto tl = Clock::now();
        PlannedLevel& p = plan[k];
        LevelBuild L = buildCalibratedLevel(context, coarser, p);
        coarser = p.sel.cut;
        Level level = assembleLevel(t, L);
        level.targetRatio = p.target.ratio;
        level.targetTriangles = p.triangles;
        level.stopReason = p.sel.stopReason;
        level.seconds = secondsSince(tl);
        built[k] = std::move(level);
        builtStats[k] = levelStats(context, p.sel, L);
        progress(0.4 + 0.6 * double(plan.size() - k) / double(plan.size()));
    }
    res.multires.levels = std::move(built);
    res.levelStats = std::move(builtStats);
    res.secondsLevels = secondsSince(t3);
    return res;
}

}  // namespace lodbake
