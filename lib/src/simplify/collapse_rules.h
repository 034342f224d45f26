// The rules of a half-edge collapse (v_i -> v_j): the cost (vertex deviation), the mesh filters
// (link condition, no flip) and the region rules of thesis ch. 3.2 (rule 1: last p-boundary,
// rule 3: keep a straight p-boundary; rule 2 is the E_region key) plus the normal-cone limit.
// Every rule sees one read-only CollapseProfile (or, for merges, one MergeProfile); the region
// rules that forbid a merge are a table (kMergeRules in collapse_rules.cpp). docs/simplify.md
// states the rules. Private to lib/src/simplify.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "collapse_state.h"
#include "lodbake/core/pose_samples.h"
#include "lodbake/simplify/simplify.h"
#include "regions.h"

namespace lodbake::simplify_detail {

// Why a vertex could not collapse. The stop reason of a level that cannot reach its target is the
// most frequent reason among the remaining vertices.
enum class Reject : uint8_t { None, Locked, Border, Link, Flip, Degenerate, Ear, Rule1, Cone, Isolated, Skin, Count };

inline constexpr const char* kRejectReason[] = {
    "target",                                        // None
    "locked: non-manifold edge or pinch vertex",     // Locked
    "border: no collapse along the open boundary",   // Border
    "topology: link condition",                      // Link
    "no valid collapse: face flip",                  // Flip
    "no valid collapse: degenerate face",            // Degenerate
    "no valid collapse: corner",                     // Ear: the whole fan would vanish
    "rule1: last p-boundary",                        // Rule1
    "region: normal cone",                           // Cone: the merged region would turn too far to be a chart
    "no valid collapse",                             // Isolated
    "skin: joint influences differ",                 // Skin
};
static_assert(sizeof(kRejectReason) / sizeof(kRejectReason[0]) == size_t(Reject::Count), "rule table");

// A level's targets as the stop predicate of its passes.
struct PlannedLevel {
    LevelTarget target;
    uint64_t triangles;  // stop when the live face count is <= this
    double error;        // stop before a collapse costs more than this (model units); inf = none
    bool reached(size_t aliveFaces) const { return aliveFaces <= triangles; }
    bool hasErrorTarget() const { return std::isfinite(error); }
};

// The levels of `targets`, finest first (most triangles, then smallest error).
std::vector<PlannedLevel> planLevels(const std::vector<LevelTarget>& targets, size_t faceCount, double diagonal);

// The options the rules read, resolved once (model units, cosines).
struct RuleSettings {
    double cosMaxNormalChange = 0;      // a face of the new fan must turn by less than this (cosine)
    double minRegionCoherence = 0;      // |sum a_f n_f| / area a merged region keeps; 0 = no cone limit
    double epsilonDeviationFactor = 0;  // rule 3: eps = max(epsilonDeviationFactor * cost, epsilonBox)
    double epsilonBox = 0;              // model units
    double similarDeviation = 0;        // rule 2: relative width of a deviation bucket; 0 = off
    double diagonal = 0;                // of the input's bounding box, model units
    double maxInfluenceChange = 1;      // largest total variation between the joint weights of v_i and v_j
    const PosedWedges* posed = nullptr; // rigged meshes: wedges at sampled poses; null = bind pose only
};

// The best collapse found for a vertex, with its region plan.
struct Candidate {
    Reject reason = Reject::Isolated;
    uint32_t target = kNone;
    double dev = 0;     // cost, model units
    float farDist = 0;  // distance of v_i's farthest attached point to the new fan
    float shape = 0;    // E_region of the resulting region (rule 2 key)
    bool rule3 = false; // keeps the p-boundary: no region merges
    uint32_t evalPass = 0;  // pass whose start evaluated this candidate
};

// Per-thread scratch of the rules.
struct RuleScratch {
    std::vector<RingEntry> ring;         // ring of the vertex being evaluated
    std::vector<uint32_t> markI, markJ;  // per-vertex stamps: one-ring of vi, neighbours of vj
    uint32_t stampI = 0, stampJ = 0;
    std::vector<uint32_t> fan;           // fan id of each face of vfaces[vi] (pinch vertices only)
    MergeGroups groups;
};

// What the rules read: the state of the walk, never written while candidates are evaluated.
struct RuleContext {
    const CollapseState& mesh;
    const RegionState& regions;
    const RuleSettings& settings;
};

// The read-only profile of one candidate collapse (vi -> edge.w) that every rule sees.
struct CollapseProfile {
    const CollapseState& mesh;
    const RegionState& regions;
    const RuleSettings& settings;
    uint32_t vi;
    const RingEntry& edge;               // the spoke (v_i, v_j)
    const std::vector<RingEntry>& ring;  // ring of v_i
    const std::vector<uint32_t>& fan;    // labelFans of v_i (pinch only)
    CollapseProfile(const RuleContext& c, uint32_t v, const RingEntry& e, const std::vector<RingEntry>& r,
                    const std::vector<uint32_t>& f)
        : mesh(c.mesh), regions(c.regions), settings(c.settings), vi(v), edge(e), ring(r), fan(f) {}
    uint32_t vj() const { return edge.w; }
    bool borderEdge() const { return edge.f1 == kNone; }
};

// One merge of regions into one, as the region rules see it.
struct MergeProfile {
    const RegionStats& merged;  // the merged region
    size_t regions;             // regions merged (1: nothing merges)
    uint32_t regionsAfter;      // regions left on the component after the merge
    bool closedComponent;       // no live border, pinch or locked vertex on the component
};

// Validity and cost of (vi -> vj): the mesh filters (target not locked, a border vertex moves
// along the border, no vanishing fan, link condition, no duplicate, degenerate or flipped face),
// then the vertex deviation. markI must mark the ring of vi with stampI. On success fills dev
// (model units) and farDist. quadricTerm: Q_i(V_j) as RMS distance.
Reject checkCollapse(const CollapseProfile& p, RuleScratch& w, double quadricTerm, double& dev, float& farDist);

// Region plan of a valid collapse: rule 3 (keep the boundary) or merge under kMergeRules; fills
// c.rule3, c.shape and may raise c.dev to the kept boundary's displacement.
Reject planRegions(const CollapseProfile& p, RuleScratch& w, Candidate& c);

// Under an error target: the largest distance, after collapse (vi -> vj), of every removed point
// attached to a vertex whose fan changes (and of V_i) to the new fan of the vertex it then hangs
// under. Pairs are projected onto (at least) that fan, so a collapse measured here within the
// target keeps every pair within it. Model units.
double measureAttached(const CollapseState& s, RuleScratch& w, uint32_t vi, uint32_t vj);

}  // namespace lodbake::simplify_detail
