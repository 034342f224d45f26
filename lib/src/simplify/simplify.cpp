// Half-edge-collapse simplification with a region hierarchy: the entry point and the pass loop.
//
// References
//   [Hoppe96]    H. Hoppe, "Progressive meshes", SIGGRAPH 1996 (collapse records, vertex hierarchy).
//   [Garland97]  M. Garland, P. Heckbert, "Surface simplification using quadric error metrics",
//                SIGGRAPH 1997 (the quadric part of the cost).
//   [Thesis]     "Multiresolution model generation of texture-geometry for the real-time
//                rendering", ch. 2.3 (edge collapsing with region hierarchy) and ch. 3.2 (modified
//                multiresolution geometry generation: p-boundaries, the three region rules).
//   [meshopt]    A. Kapoulkine, meshoptimizer simplifier.cpp (pass-based collapsing: pick the best
//                collapse per vertex, sort, apply the non-conflicting ones under a per-pass error
//                limit; component pruning).
//
// docs/simplify.md describes the method. The pieces, in pipeline order:
//   collapse_state   the mesh during simplification, quadrics, the collapse, the hierarchy recorder
//   regions          regions, p-boundaries, merges, E_region
//   collapse_rules   cost, link condition, no flip, rules 1-3 and the normal cone, level targets
//   candidates       best collapse per vertex, deferral, a pass's candidate list
//   pruning          removal of small and stuck components
//   gross_stop       the gross-error bound of triangle-count levels
//   pairs            the snapshot of a level and its simplification pairs

#include "lodbake/simplify/simplify.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <string>

#include "candidates.h"
#include "collapse_rules.h"
#include "collapse_state.h"
#include "gross_stop.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/math.h"
#include "pairs.h"
#include "posed_guard.h"
#include "pruning.h"
#include "regions.h"

namespace lodbake {
namespace {

using namespace simplify_detail;

// Everything one run holds: the mesh, its regions, the candidates, the recorder, per-thread scratch.
struct Simplifier {
    CollapseState mesh;
    RegionState regions;
    RuleSettings settings;
    CandidateState candidates;
    HierarchyRecorder recorder;
    GrossStop gross;  // the level's gross-error bound
    std::vector<EvalScratch> work;  // one per evaluation thread; work[0] also serves the collapse walk
    const SimplifyOptions& options;

    Simplifier(const TriMesh& local, const TriMesh& input, const SimplifyOptions& o) : mesh(local, input), options(o) {}
    RuleContext context() const { return {mesh, regions, settings}; }
};

void validateInput(const TriMesh& mesh) {
    if (mesh.triangles.empty()) throw Impossible("simplify: the mesh has no triangles");
    for (const Tri& t : mesh.triangles)
        for (uint32_t v : t)
            if (v >= mesh.positions.size()) throw InvalidInput("simplify: triangle index out of range");
}

RuleSettings resolveSettings(const SimplifyOptions& options, double diagonal, double longestSide) {
    RuleSettings r;
    r.cosMaxNormalChange = std::cos(std::clamp(options.maxNormalChangeDeg, 0.0, 180.0) * kPi / 180.0);
    // A spherical cap of half-angle t has |sum of area-weighted normals| / area = (1 + cos t) / 2.
    r.minRegionCoherence = 0.5 * (1 + std::cos(std::clamp(options.maxRegionConeDeg, 0.0, 180.0) * kPi / 180.0));
    r.epsilonDeviationFactor = options.epsilonDeviationFactor;
    r.epsilonBox = options.epsilonBoxFactor * longestSide;
    r.similarDeviation = options.similarDeviation;
    r.diagonal = diagonal;
    r.maxInfluenceChange = options.maxInfluenceChange >= 0         ? options.maxInfluenceChange
                           : options.posed.positions.size() >= 2 ? 1
                                                                 : SimplifyOptions::kBindPoseInfluenceChange;
    if (!options.posed.empty()) r.posed = &options.posed;
    r.twoSidedCost = options.twoSidedCost;
    return r;
}

// Applies the collapse of vi described by its current candidate c: regions first (they read the
// pre-collapse fan), then the mesh, then the record; marks the changed fans. planned: c's merge
// groups when the caller just planned them (planRegions), else null.
void applyCandidate(Simplifier& s, uint32_t vi, const Candidate& c, const MergeGroups* planned = nullptr) {
    CandidateState& cs = s.candidates;
    for (uint32_t f : s.mesh.vfaces[vi])
        for (uint32_t u : s.mesh.tri[f]) cs.dirtyPass[u] = cs.pass;
    cs.touchedPass[vi] = cs.touchedPass[c.target] = cs.pass;
    uint32_t begin = s.recorder.regionMark();
    updateRegions(s.regions, s.mesh, s.recorder, vi, c.target, c.rule3, cs.pass, planned);
    uint32_t end = s.recorder.regionMark();
    applyCollapse(s.mesh, vi, c.target, c.dev, c.farDist);
    s.recorder.collapsed({vi, c.target, float(c.dev), begin, end});
    s.recorder.accepted(double(float(c.dev)));
    cs.cand[vi] = Candidate{};
}

// d. Walks the sorted candidates, applying each whose v_i and v_j did not take part in a collapse
// of this pass; stops at the target. A candidate whose fans changed in this pass is checked and
// costed again, and its region plan is re-done unless nothing it reads changed. Returns the number
// of collapses applied (or dropped from the level by the error target).
size_t walkCandidates(Simplifier& s, const PlannedLevel& plan, double limit) {
    CollapseState& m = s.mesh;
    CandidateState& cs = s.candidates;
    EvalScratch& w = s.work[0];
    const RuleContext ctx = s.context();
    size_t applied = 0;
    const size_t entryCount = cs.entries.size();
    for (size_t k = 0; k < entryCount; ++k) {
        const PassEntry& e = cs.entries[k];
        if (plan.reached(m.aliveFaces)) break;
        // The walk visits vertices in cost order, i.e. at random: fetch ahead what it reads first
        // (the vertex's candidate and face list, then the faces of a nearer entry).
        if (k + 16 < entryCount) {
            uint32_t a = cs.entries[k + 16].vertex;
            __builtin_prefetch(&cs.cand[a]);
            __builtin_prefetch(&m.vfaces[a]);
            __builtin_prefetch(&cs.touchedPass[a]);
            __builtin_prefetch(&cs.dirtyPass[a]);
            __builtin_prefetch(&m.removed[a]);
            __builtin_prefetch(&m.components.label[a]);
        }
        if (k + 8 < entryCount) {
            uint32_t a = cs.entries[k + 8].vertex;
            for (uint32_t f : m.vfaces[a]) {
                __builtin_prefetch(&m.tri.rec[f]);
                __builtin_prefetch(&s.regions.faceRegion[f]);
                __builtin_prefetch(&s.regions.faceRelabelPass[f]);
                if (!m.wedge.empty()) __builtin_prefetch(&m.wedge[f]);
            }
            __builtin_prefetch(&cs.touchedPass[cs.cand[a].target]);
            __builtin_prefetch(&cs.dirtyPass[cs.cand[a].target]);
            __builtin_prefetch(&m.farPoint[a]);
            __builtin_prefetch(&m.quadric[a]);
            __builtin_prefetch(reinterpret_cast<const char*>(&m.quadric[a]) + sizeof(Quadric) - 1);
        }
        if (k + 4 < entryCount) {
            uint32_t a = cs.entries[k + 4].vertex;
            for (uint32_t f : m.vfaces[a]) {
                // (The region's record and representative face: a merge reads them.)
                const uint32_t rep = s.regions.faceRegion[f];
                __builtin_prefetch(&s.regions.stats[rep]);
                __builtin_prefetch(&s.regions.lists[rep]);
                __builtin_prefetch(&m.tri.rec[rep]);
                __builtin_prefetch(&m.faceAlive[rep]);
                for (uint32_t u : m.tri[f]) {
                    __builtin_prefetch(&m.mesh.positions[u]);
                    __builtin_prefetch(&m.vfaces[u]);
                }
            }
            __builtin_prefetch(&m.quadric[cs.cand[a].target]);
            __builtin_prefetch(&m.vfaces[cs.cand[a].target]);
        }
        uint32_t vi = e.vertex;
        if (m.removed[vi] || cs.touchedPass[vi] == cs.pass) continue;
        Candidate c = cs.cand[vi];
        uint32_t vj = c.target;
        if (cs.touchedPass[vj] == cs.pass) continue;
        if (!plan.hasErrorTarget() && !candidateStale(cs, ctx, vi, c)) {
            // Nothing the candidate depends on changed since it was evaluated: apply it as is.
            if (!s.gross.allows(m, w, vi, vj, c.dev, cs.pass)) continue;
            applyCandidate(s, vi, c);
            ++applied;
            continue;
        }
        collectRing(m, vi, w.ring);
        const RingEntry* edge = nullptr;
        for (const RingEntry& r : w.ring)
            if (r.w == vj) edge = &r;
        if (!edge || (m.pinch[vi] && labelFans(m, vi, w.ring, w.fan) < 2)) {
            cs.dirtyPass[vi] = cs.pass;  // re-evaluate next pass
            continue;
        }
        const CollapseProfile profile(ctx, vi, *edge, w.ring, w.fan);
        if (cs.dirtyPass[vi] == cs.pass || cs.dirtyPass[vj] == cs.pass) {
            // The fan of vi or of vj changed in this pass: check and cost the collapse again.
            ++w.stampI;
            for (const RingEntry& r : w.ring) w.markI[r.w] = w.stampI;
            double q = m.quadric[vi].distance(m.mesh.positions[vj]);
            if (checkCollapse(profile, w, q, c.dev, c.farDist) != Reject::None || c.dev > limit) {
                cs.dirtyPass[vi] = cs.pass;
                continue;
            }
        }
        // The region plan is re-done (labels may have merged).
        if (planRegions(profile, w, c) != Reject::None || c.dev > limit) {
            cs.dirtyPass[vi] = cs.pass;  // re-evaluate next pass
            continue;
        }
        if (plan.hasErrorTarget()) {
            // Error target: measure every attached point exactly (see measureAttached).
            double d = measureAttached(m, w, vi, c.target);
            if (d > plan.error) {
                cs.cand[vi].dev = std::max(cs.cand[vi].dev, d);  // out of this level until re-evaluated
                ++applied;  // not idle: the candidate set shrank
                continue;
            }
            c.dev = std::max(c.dev, d);
        } else if (!s.gross.allows(m, w, vi, vj, c.dev, cs.pass)) {
            continue;  // past the gross-error bound: the level keeps what it has
        }
        // planRegions left the merge groups of this collapse in w.groups (unless it keeps the boundary).
        applyCandidate(s, vi, c, &w.groups);
        ++applied;
    }
    return applied;
}

enum class PassResult { Progress, Idle, NoCandidate, ErrorReached };

// One pass toward `plan` (docs/simplify.md, "Passes").
PassResult runPass(Simplifier& s, const PlannedLevel& plan) {
    CandidateState& cs = s.candidates;
    const RuleContext ctx = s.context();
    ++cs.pass;
    // a. Candidates of the vertices whose candidate may have changed, in parallel.
    bool anyValid = false;
    size_t deferred = evaluateCandidates(cs, ctx, s.work, plan.error, anyValid);
    // b. The pass error limit: each pass takes about a third of the remaining reduction.
    const size_t need = size_t((s.mesh.aliveFaces - plan.triangles + 1) / 2);
    double limit = passLimit(cs, ctx, s.work, deferred, need, plan.error, anyValid);
    // c. Components smaller than the limit are pruned, lightest first: closed ones, and by visual
    // weight also open or locked ones that cannot shrink any further (without it those wait until
    // the level is stuck).
    // (Which components are stuck is only asked when some component is small enough to prune.)
    const bool weighted = s.options.visualWeight;
    bool pruned = false;
    const double partLimit = s.gross.cap(limit);
    if (anyPrunable(s.mesh, partLimit, plan.triangles)) {
        const std::vector<uint8_t> stuck = weighted ? stuckComponents(s.mesh, cs) : std::vector<uint8_t>{};
        pruned = pruneComponents(s.mesh, s.recorder, partLimit, plan.triangles, !weighted, weighted ? &stuck : nullptr);
    }
    if (pruned) {
        cs.entries.erase(std::remove_if(cs.entries.begin(), cs.entries.end(),
                                        [&](const PassEntry& e) { return s.mesh.removed[e.vertex] != 0; }),
                         cs.entries.end());
        if (plan.reached(s.mesh.aliveFaces)) return PassResult::Progress;
    }
    if (cs.entries.empty()) return anyValid ? PassResult::ErrorReached : PassResult::NoCandidate;
    // d. Candidates under the limit in (bucket, E_region, deviation, vertex) order, applied.
    orderEntries(cs, s.settings, limit, int(s.work.size()));
    return walkCandidates(s, plan, limit) ? PassResult::Progress : PassResult::Idle;
}

// Simplification is stuck before the level's target: prune closed components up to the level's
// error target; then any component (open or non-manifold ones too, which are stuck on locks) no
// larger than the error already accepted, so pruning never raises maxDeviation; last, for a
// triangle target, small parts (options.pruneStuckSize of the diagonal), smallest first, whose
// size enters maxDeviation. No part larger than the gross-error bound leaves; one it keeps is
// recorded as refused. Returns whether anything was pruned.
bool pruneStuck(Simplifier& s, const PlannedLevel& level) {
    CollapseState& m = s.mesh;
    GrossStop& g = s.gross;
    const double stuckSize = level.hasErrorTarget() ? 0 : s.options.pruneStuckSize * m.diagonal;
    if (pruneComponents(m, s.recorder, g.cap(level.error), level.triangles, true) ||
        pruneComponents(m, s.recorder, g.cap(std::min(level.error, s.recorder.runningMax * (1 + 1e-9))),
                        level.triangles, false) ||
        pruneComponents(m, s.recorder, g.cap(stuckSize), level.triangles, false))
        return true;
    for (bool closedOnly : {true, false}) {
        const double size = nextPrunableSize(m, level.triangles, closedOnly);
        if (size < (closedOnly ? level.error : stuckSize) && size >= g.bound) g.refusePart(size, s.candidates.pass);
    }
    return false;
}

// Passes until the level's target; returns the stop reason (grossStop: the gross-error bound).
std::string runLevel(Simplifier& s, const PlannedLevel& level, double start, double span, bool& grossStop) {
    grossStop = false;
    s.gross.startLevel(level, s.options.grossError, s.mesh.diagonal);
    int idle = 0;
    while (!level.reached(s.mesh.aliveFaces)) {
        PassResult r = runPass(s, level);
        if (r == PassResult::ErrorReached) break;  // error target reached
        idle = r == PassResult::Idle ? idle + 1 : 0;
        if (r == PassResult::NoCandidate || idle > 2) {
            if (pruneStuck(s, level)) {
                idle = 0;
                continue;
            }
            resolveDeferred(s.candidates, s.context(), s.work, std::numeric_limits<double>::infinity(), level.error,
                            nullptr, nullptr);
            // The last pass refused collapses or parts: the bound stopped the level.
            grossStop = s.gross.refusedIn(s.candidates.pass);
            return grossStop ? s.gross.reason(s.mesh.diagonal) : summariseStop(s.candidates, s.mesh);
        }
        const SimplifyOptions& o = s.options;
        if (o.progress && !o.progress(std::clamp((start - double(s.mesh.aliveFaces)) / span, 0.0, 1.0)))
            throw Cancelled("simplify: cancelled");
    }
    return kRejectReason[0];
}

}  // namespace

SimplifyResult simplify(const TriMesh& mesh, const SimplifyOptions& options) {
    using Clock = std::chrono::steady_clock;
    // 1. Input: internal vertex ids in order of first use; outputs use the input ids.
    validateInput(mesh);
    std::vector<uint32_t> oldId, newId;
    TriMesh local = renumberVertices(mesh, oldId, newId);
    Simplifier s(local, mesh, options);
    CollapseState& m = s.mesh;
    m.oldId = std::move(oldId);
    m.newId = std::move(newId);
    Box3 box = bounds(mesh);
    m.diagonal = box.diagonal();
    m.longestSide = box.longestSide();
    s.settings = resolveSettings(options, m.diagonal, m.longestSide);

    // 2. Adjacency: the live faces around each vertex.
    buildAdjacency(m);
    s.work.resize(size_t(std::max(1, options.threads)));
    for (EvalScratch& w : s.work) {
        w.markI.assign(m.vertexCount, 0);
        w.markJ.assign(m.vertexCount, 0);
    }
    // 3. Locked, pinch and border vertices; components and their sizes.
    classifyVertices(m, int(s.work.size()));
    measureComponents(m);
    if (options.visualWeight) orderByVisualWeight(m);
    // 4. Quadrics. 5. Every face its own region.
    initQuadrics(m);
    initRegions(s.regions, m, int(s.work.size()));
    // 6. Targets, finest first.
    std::vector<PlannedLevel> plan = planLevels(options.levels, m.faceCount, m.diagonal);
    initCandidates(s.candidates, m.vertexCount);

    // 7. Passes until each level's target; a snapshot at each.
    uint64_t finalTarget = plan.empty() ? m.faceCount : plan.back().triangles;
    double start = double(m.faceCount), span = std::max(1.0, start - double(std::min<uint64_t>(finalTarget, m.faceCount)));
    auto levelStart = Clock::now();
    for (const PlannedLevel& level : plan) {
        bool grossStop = false;
        std::string stop = runLevel(s, level, start, span, grossStop);
        auto now = Clock::now();
        snapshotLevel(m, s.regions, s.recorder, level, stop, std::chrono::duration<double>(now - levelStart).count(),
                      int(s.work.size()), s.candidates.pass);
        if (grossStop) {
            s.recorder.out.levels.back().grossErrorBound = s.gross.bound;
            s.recorder.out.levels.back().grossErrorRefused = s.gross.cheapestRefused;
        }
        if (s.settings.posed) raisePosedLevelDeviation(m, *s.settings.posed, int(s.work.size()), s.recorder);
        levelStart = Clock::now();
    }
    if (options.progress && !options.progress(1.0)) throw Cancelled("simplify: cancelled");

    // 8. Outputs in the input's vertex ids.
    restoreInputIds(m.oldId, s.recorder.out);
    SimplifyResult result;
    result.multires = std::move(s.recorder.out);
    result.diagonal = m.diagonal;
    return result;
}

}  // namespace lodbake
