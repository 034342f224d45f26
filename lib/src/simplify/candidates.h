// Candidates: the best collapse of each vertex, cached between passes, deferred while a lower
// bound of its cost is far above the pass limit, and the sorted candidate list of one pass
// (docs/simplify.md, "Passes"). Evaluation only reads the state, so it runs in parallel over
// fixed vertex chunks; the result does not depend on the thread count. Private to
// lib/src/simplify.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "collapse_rules.h"

namespace lodbake::simplify_detail {

// A sortable candidate of one pass: (deviation bucket, E_region key, deviation, input id).
struct PassEntry {
    int64_t bucket;
    float shape;
    double dev;
    uint32_t vertex;
    uint32_t key;  // the vertex's input id: ties go to the smaller input id
    bool operator<(const PassEntry& b) const {
        if (bucket != b.bucket) return bucket < b.bucket;
        if (shape != b.shape) return shape < b.shape;
        if (dev != b.dev) return dev < b.dev;
        return key < b.key;
    }
};

// An outgoing half-edge of the vertex being evaluated: its quadric term and ring slot. Equal terms
// go to the smaller input id of the target (read only on a tie: most terms differ).
struct Option {
    double q;
    uint32_t k;
};

// Per-thread scratch of candidate evaluation; each on its own cache lines (the threads write their
// stamps and vector ends all the time).
struct alignas(64) EvalScratch : RuleScratch {
    std::vector<Option> options;  // one per ring entry (ringOptions)
};

struct CandidateState {
    uint32_t pass = 0;                // passes run so far
    std::vector<Candidate> cand;      // per vertex
    // Deferred vertices: not evaluated while a lower bound of their cost (costBound) is above the
    // pass's deferral bound; their cand is empty.
    std::vector<uint8_t> deferred;
    std::vector<double> costBound;
    double lastLimit = std::numeric_limits<double>::infinity();  // the previous pass's error limit
    std::vector<uint32_t> dirtyPass;    // per vertex: pass of the last change of its fan
    std::vector<uint32_t> touchedPass;  // per vertex: pass of its last collapse (as v_i or v_j)
    std::vector<PassEntry> entries;     // this pass's candidates
    std::vector<std::vector<PassEntry>> chunkEntries;  // per evaluation chunk
};

void initCandidates(CandidateState& c, size_t vertexCount);

// The ring of vi (w.ring) and the quadric term of each outgoing half-edge (w.options, unsorted).
// Returns the smallest term: a lower bound of vi's collapse cost.
double ringOptions(const RuleContext& ctx, EvalScratch& w, uint32_t vi);

// Rule 2's primary key: deviations quantised into buckets of relative width similarDeviation.
int64_t deviationBucket(const RuleSettings& settings, double dev);

// a. Evaluates (or defers) every vertex whose candidate may be stale and lists the valid
// candidates within maxCost in c.entries. anyValid: some vertex has a valid candidate. Returns
// the number of deferred vertices.
size_t evaluateCandidates(CandidateState& c, const RuleContext& ctx, std::vector<EvalScratch>& work, double maxCost,
                          bool& anyValid);

// Evaluates the deferred vertices whose bound is at most `upTo`, appending the valid ones within
// `maxCost` to `entries` (when given); returns how many stay deferred.
size_t resolveDeferred(CandidateState& c, const RuleContext& ctx, std::vector<EvalScratch>& work, double upTo,
                       double maxCost, std::vector<PassEntry>* entries, bool* anyValid);

// b. The pass error limit: 1.1 x the cost of the (need / 3)-th cheapest candidate, at most
// maxCost; deferred vertices that may fall under it join c.entries first. need: collapses left
// to the target.
double passLimit(CandidateState& c, const RuleContext& ctx, std::vector<EvalScratch>& work, size_t deferred,
                 size_t need, double maxCost, bool& anyValid);

// d. Keeps the entries under `limit`, in (bucket, E_region, deviation, input id) order (the same
// for any `threads`).
void orderEntries(CandidateState& c, const RuleSettings& settings, double limit, int threads);

// Whether a cached candidate of vi may have changed since it was evaluated: the fans of vi or of
// its target changed, a face of vi's fan was relabelled, rule 1 may apply (closed component) or
// the normal-cone limit reads region stats.
bool candidateStale(const CandidateState& c, const RuleContext& ctx, uint32_t vi, const Candidate& cand);

// The stop reason of a level that cannot reach its target: rule 1 when it blocks anything, else
// the most frequent reason among the remaining vertices.
const char* summariseStop(const CandidateState& c, const CollapseState& s);

}  // namespace lodbake::simplify_detail
