// Best collapse per vertex, deferral, the candidate list of a pass (candidates.h, docs/simplify.md).

#include "candidates.h"

#include <algorithm>
#include <cmath>

#include "lodbake/core/parallel.h"

namespace lodbake::simplify_detail {

constexpr size_t kChunk = 4096;        // vertices per evaluation chunk (fixed: thread-independent)
constexpr double kDeferFactor = 1.5;   // deferral bound of a pass: this times the previous pass's limit
constexpr size_t kMinSortPart = 32768;  // smallest part of a pass's entries sorted on its own thread

void initCandidates(CandidateState& c, size_t vertexCount) {
    c.cand.assign(vertexCount, Candidate{});
    c.deferred.assign(vertexCount, 0);
    c.costBound.assign(vertexCount, 0);
    c.dirtyPass.assign(vertexCount, 0);
    c.touchedPass.assign(vertexCount, 0);
}

// Quadric distances below rounding noise (relative to the model size) tie at 0, so equal costs
// fall back to the smaller target id deterministically.
double ringOptions(const RuleContext& ctx, EvalScratch& w, uint32_t vi) {
    const CollapseState& s = ctx.mesh;
    collectRing(s, vi, w.ring);
    const Quadric& Q = s.quadric[vi];
    const double noise = 1e-9 * s.diagonal;
    const size_t n = w.ring.size();
    w.options.resize(n);
    double bound = n ? std::numeric_limits<double>::infinity() : 0.0;
    for (size_t k = 0; k < n; ++k) {
        const uint32_t t = w.ring[k].w;
        double q = Q.distance(s.mesh.positions[t]);
        w.options[k] = {q > noise ? q : 0.0, uint32_t(k)};
        bound = std::min(bound, w.options[k].q);
    }
    return bound;
}

int64_t deviationBucket(const RuleSettings& settings, double dev) {
    double sim = settings.similarDeviation;
    if (!(sim > 0)) return 0;
    if (!(dev > 1e-12 * settings.diagonal)) return std::numeric_limits<int64_t>::min();
    return int64_t(std::floor(std::log(dev / settings.diagonal) / std::log1p(sim)));
}

// Moves the option that comes first in (quadric term, target input id) order among o[k .. n) to
// slot k. Keys are distinct (one option per target), so taking options this way visits them in the
// order a sort gives; the walk below usually stops after one or two, which a sort would order all.
static void selectNext(const CollapseState& s, const std::vector<RingEntry>& ring, Option* o, size_t k, size_t n) {
    size_t m = k;
    for (size_t j = k + 1; j < n; ++j)
        if (o[j].q < o[m].q || (o[j].q == o[m].q && s.oldId[ring[o[j].k].w] < s.oldId[ring[o[m].k].w])) m = j;
    if (m != k) std::swap(o[k], o[m]);
}

// The best collapse of vi: its outgoing half-edges in quadric order, the first valid one whose
// cost no later option (bounded below by its quadric term) can beat. `prepared`: ringOptions(vi)
// already filled the scratch.
static Candidate evaluateVertex(const RuleContext& ctx, EvalScratch& w, uint32_t vi, uint32_t pass,
                                bool prepared = false) {
    const CollapseState& s = ctx.mesh;
    Candidate best;
    if (s.removed[vi] || s.vfaces[vi].empty()) return best;
    if (s.locked[vi]) {
        best.reason = Reject::Locked;
        return best;
    }
    if (!prepared) ringOptions(ctx, w, vi);
    // A pinch moves with all its fans, which must still be apart: a sticky pinch whose fans were
    // joined by later collapses stays (its faces are only vertex-connected in the original mesh).
    if (s.pinch[vi] && labelFans(s, vi, w.ring, w.fan) < 2) {
        best.reason = Reject::Locked;
        return best;
    }
    ++w.stampI;
    for (const RingEntry& e : w.ring) w.markI[e.w] = w.stampI;
    Option* o = w.options.data();
    const size_t n = w.options.size();
    const double noise = 1e-9 * s.diagonal;
    Reject last = Reject::Isolated;
    best.reason = Reject::Isolated;
    bool found = false;
    for (size_t k = 0; k < n; ++k) {
        selectNext(s, w.ring, o, k, n);
        if (found && o[k].q >= best.dev) break;  // the cost is at least the quadric term
        const CollapseProfile profile(ctx, vi, w.ring[o[k].k], w.ring, w.fan);
        double dev = 0;
        float farDist = 0;
        Reject r = checkCollapse(profile, w, o[k].q, dev, farDist);
        if (dev <= noise) dev = 0;  // rounding noise: ties go to the smaller target id
        if (r != Reject::None) {
            if (last == Reject::Isolated || r == Reject::Rule1 || r == Reject::Cone) last = r;
            continue;
        }
        // The region plan only raises the cost, and `last` no longer matters once a candidate is
        // found: an option not cheaper than the best cannot replace it.
        if (found && dev >= best.dev) continue;
        Candidate c;
        c.target = profile.vj();
        c.dev = dev;
        c.farDist = farDist;
        r = planRegions(profile, w, c);
        if (r != Reject::None) {
            last = r;
            continue;
        }
        c.reason = Reject::None;
        if (!found || c.dev < best.dev) best = c;
        found = true;
    }
    if (!found) best.reason = last;
    best.evalPass = pass;
    return best;
}

// Whether v's cached candidate may be stale after the previous pass: v's fan changed, its
// target's fan changed, or (rejected vertices) a neighbour's fan changed.
static bool needsEvaluation(const CandidateState& c, const CollapseState& s, uint32_t v) {
    uint32_t prev = c.pass - 1;
    if (c.pass == 1 || c.dirtyPass[v] == prev) return true;
    const Candidate& cand = c.cand[v];
    if (cand.reason == Reject::None) return c.dirtyPass[cand.target] == prev;
    if (cand.reason == Reject::Locked && (s.locked[v] || s.pinch[v])) return false;
    for (uint32_t f : s.vfaces[v])
        for (uint32_t u : s.tri[f])
            if (c.dirtyPass[u] == prev) return true;
    return false;
}

// Whether v has a current candidate after this pass's evaluation: v is evaluated when its cached
// candidate may be stale (needsEvaluation), unless a lower bound of its cost is above `bound`
// (deferred: its candidate cannot be under this pass's limit; the bound is kept, and refreshed
// when v's fan changes).
static bool evaluateOrDefer(CandidateState& c, const RuleContext& ctx, EvalScratch& w, uint32_t v, double bound) {
    const CollapseState& s = ctx.mesh;
    bool prepared = false;
    if (c.deferred[v]) {
        if (c.dirtyPass[v] == c.pass - 1) {
            c.costBound[v] = ringOptions(ctx, w, v);
            prepared = true;
        }
        if (c.costBound[v] > bound) return false;
        c.deferred[v] = 0;
    } else if (!needsEvaluation(c, s, v)) {
        return true;
    } else if (bound < std::numeric_limits<double>::infinity() && !s.locked[v] && !s.pinch[v]) {
        double lb = ringOptions(ctx, w, v);
        prepared = true;
        if (lb > bound) {
            c.deferred[v] = 1;
            c.costBound[v] = lb;
            c.cand[v] = Candidate{};
            return false;
        }
    }
    c.cand[v] = evaluateVertex(ctx, w, v, c.pass, prepared);
    return true;
}

// Whether v's fan changed in the previous pass (every vertex in the first): most evaluations.
static bool likelyEvaluated(const CandidateState& c, uint32_t v) { return c.pass == 1 || c.dirtyPass[v] == c.pass - 1; }

// The pass entry of v's valid candidate (bucket filled in once the pass limit is known).
static PassEntry passEntry(const RuleContext& ctx, uint32_t v, const Candidate& cand) {
    return {0, ctx.settings.similarDeviation > 0 ? cand.shape : 0.f, cand.dev, v, ctx.mesh.oldId[v]};
}

size_t evaluateCandidates(CandidateState& c, const RuleContext& ctx, std::vector<EvalScratch>& work, double maxCost,
                          bool& anyValid) {
    const CollapseState& s = ctx.mesh;
    // Vertices whose cost is bounded from below by more than kDeferFactor x the previous pass's
    // limit are deferred (the limit mostly grows slowly from pass to pass): when this pass's limit
    // stays below every deferred bound, the pass is what evaluating them now would give; otherwise
    // passLimit evaluates them before the limit is taken.
    const double bound = kDeferFactor * c.lastLimit;
    const size_t chunks = chunkCount(s.vertexCount, kChunk);
    c.entries.clear();
    c.chunkEntries.resize(chunks);
    std::vector<uint8_t> chunkValid(chunks, 0);
    std::vector<size_t> chunkDeferred(chunks, 0);
    parallelChunks(s.vertexCount, kChunk, int(work.size()), [&](size_t begin, size_t end, size_t t) {
        // Counters and entries stay local until the chunk ends: the slots of neighbouring chunks
        // share cache lines, and the other thread writes them.
        const size_t k = begin / kChunk;
        std::vector<PassEntry> out = std::move(c.chunkEntries[k]);
        out.clear();
        bool valid = false;
        size_t deferredHere = 0;
        for (uint32_t v = uint32_t(begin); v < end; ++v) {
            // Evaluation stalls on the fan's faces and the ring's positions, scattered in memory:
            // fetch them a few vertices ahead for the vertices likely to be evaluated.
            // (Then the rules' reads: the fan's regions and their stats, the farthest point, the
            // component.)
            if (v + 6 < end && likelyEvaluated(c, v + 6)) {
                for (uint32_t f : s.vfaces[v + 6]) {
                    __builtin_prefetch(&s.tri.rec[f]);
                    __builtin_prefetch(&ctx.regions.faceRegion[f]);
                }
                __builtin_prefetch(&s.farPoint[v + 6]);
                __builtin_prefetch(&s.components.label[v + 6]);
            }
            if (v + 3 < end && likelyEvaluated(c, v + 3)) {
                __builtin_prefetch(&s.quadric[v + 3]);
                __builtin_prefetch(reinterpret_cast<const char*>(&s.quadric[v + 3]) + sizeof(Quadric) - 1);
                for (uint32_t f : s.vfaces[v + 3]) {
                    for (uint32_t u : s.tri[f]) {
                        __builtin_prefetch(&s.mesh.positions[u]);
                        __builtin_prefetch(&s.vfaces[u]);
                    }
                    const RegionStats* st = &ctx.regions.stats[ctx.regions.faceRegion[f]];
                    __builtin_prefetch(st);
                    __builtin_prefetch(reinterpret_cast<const char*>(st) + sizeof(RegionStats) - 1);
                }
                if (s.farPoint[v + 3] != kNone) __builtin_prefetch(&s.mesh.positions[s.farPoint[v + 3]]);
            }
            if (s.removed[v] || s.vfaces[v].empty()) continue;
            if (!evaluateOrDefer(c, ctx, work[t], v, bound)) {
                ++deferredHere;
                continue;
            }
            const Candidate& cand = c.cand[v];
            if (cand.reason != Reject::None) continue;
            valid = true;
            if (cand.dev > maxCost) continue;
            out.push_back(passEntry(ctx, v, cand));
        }
        c.chunkEntries[k] = std::move(out);
        chunkValid[k] = valid;
        chunkDeferred[k] = deferredHere;
    });
    size_t deferred = 0;
    for (size_t k = 0; k < chunks; ++k) {
        anyValid |= chunkValid[k] != 0;
        deferred += chunkDeferred[k];
        c.entries.insert(c.entries.end(), c.chunkEntries[k].begin(), c.chunkEntries[k].end());
    }
    return deferred;
}

size_t resolveDeferred(CandidateState& c, const RuleContext& ctx, std::vector<EvalScratch>& work, double upTo,
                       double maxCost, std::vector<PassEntry>* entries, bool* anyValid) {
    const CollapseState& s = ctx.mesh;
    const size_t chunks = chunkCount(s.vertexCount, kChunk);
    std::vector<size_t> left(chunks, 0);
    std::vector<std::vector<PassEntry>> found(chunks);
    std::vector<uint8_t> valid(chunks, 0);
    parallelChunks(s.vertexCount, kChunk, int(work.size()), [&](size_t begin, size_t end, size_t t) {
        const size_t k = begin / kChunk;
        std::vector<PassEntry> out;
        bool anyHere = false;
        size_t leftHere = 0;
        for (uint32_t v = uint32_t(begin); v < end; ++v) {
            if (!c.deferred[v] || s.removed[v] || s.vfaces[v].empty()) continue;
            if (c.costBound[v] > upTo) {
                ++leftHere;
                continue;
            }
            c.deferred[v] = 0;
            c.cand[v] = evaluateVertex(ctx, work[t], v, c.pass);
            const Candidate& cand = c.cand[v];
            if (cand.reason != Reject::None) continue;
            anyHere = true;
            if (cand.dev <= maxCost) out.push_back(passEntry(ctx, v, cand));
        }
        found[k] = std::move(out);
        valid[k] = anyHere;
        left[k] = leftHere;
    });
    size_t stay = 0;
    for (size_t k = 0; k < chunks; ++k) {
        stay += left[k];
        if (anyValid) *anyValid |= valid[k] != 0;
        if (entries) entries->insert(entries->end(), found[k].begin(), found[k].end());
    }
    return stay;
}

double passLimit(CandidateState& c, const RuleContext& ctx, std::vector<EvalScratch>& work, size_t deferred,
                 size_t need, double maxCost, bool& anyValid) {
    const double bound = kDeferFactor * c.lastLimit;
    auto byDev = [](const PassEntry& a, const PassEntry& b) { return a.dev < b.dev; };
    if (deferred) {
        // The deferred candidates cost more than `bound`: they do not move a goal-th cheapest
        // below it. Otherwise (or when there are too few candidates) evaluate them all.
        bool exact = need / 3 < c.entries.size();
        if (exact) {
            std::nth_element(c.entries.begin(), c.entries.begin() + need / 3, c.entries.end(), byDev);
            exact = c.entries[need / 3].dev < bound;
        }
        if (!exact)
            deferred = resolveDeferred(c, ctx, work, std::numeric_limits<double>::infinity(), maxCost, &c.entries,
                                       &anyValid);
    }
    double limit = maxCost;
    if (!c.entries.empty()) {
        size_t goal = std::min(c.entries.size() - 1, need / 3);
        std::nth_element(c.entries.begin(), c.entries.begin() + goal, c.entries.end(), byDev);
        limit = std::min(maxCost, c.entries[goal].dev * 1.1);
    }
    // Deferred candidates that may be under the limit join the pass.
    if (deferred && limit >= bound) resolveDeferred(c, ctx, work, limit, maxCost, &c.entries, &anyValid);
    c.lastLimit = limit;
    return limit;
}

void orderEntries(CandidateState& c, const RuleSettings& settings, double limit, int threads) {
    size_t o = 0;
    for (const PassEntry& e : c.entries)
        if (e.dev <= limit) c.entries[o++] = {deviationBucket(settings, e.dev), e.shape, e.dev, e.vertex, e.key};
    c.entries.resize(o);
    // Entries differ in their input id, so the order is total and any sort gives the same list:
    // large lists are sorted in parts on the threads, then merged.
    const size_t parts = std::min<size_t>(size_t(resolveThreads(threads)), o / kMinSortPart);
    if (parts < 2) {
        std::sort(c.entries.begin(), c.entries.end());
        return;
    }
    std::vector<size_t> cut(parts + 1);
    for (size_t k = 0; k <= parts; ++k) cut[k] = o * k / parts;
    auto at = [&](size_t k) { return c.entries.begin() + ptrdiff_t(cut[k]); };
    parallelFor(parts, threads, [&](size_t k) { std::sort(at(k), at(k + 1)); });
    for (size_t k = 1; k < parts; ++k) std::inplace_merge(at(0), at(k), at(k + 1));
}

bool candidateStale(const CandidateState& c, const RuleContext& ctx, uint32_t vi, const Candidate& cand) {
    if (cand.evalPass == 0 || c.dirtyPass[vi] >= cand.evalPass || c.dirtyPass[cand.target] >= cand.evalPass) return true;
    const CollapseState& s = ctx.mesh;
    if (s.components.open[s.componentOf(vi)] == 0 || ctx.settings.minRegionCoherence > 0) return true;
    for (uint32_t f : s.vfaces[vi])
        if (ctx.regions.faceRelabelPass[f] >= cand.evalPass) return true;
    return false;
}

const char* summariseStop(const CandidateState& c, const CollapseState& s) {
    size_t counts[size_t(Reject::Count)] = {};
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (!s.removed[v] && !s.vfaces[v].empty()) ++counts[size_t(c.cand[v].reason)];
    // Rule 1 and locks are what the user can act on: name them when they block anything.
    if (counts[size_t(Reject::Rule1)]) return kRejectReason[size_t(Reject::Rule1)];
    size_t best = size_t(Reject::Isolated);
    for (size_t k = 1; k < size_t(Reject::Count); ++k)
        if (counts[k] > counts[best]) best = k;
    return kRejectReason[best];
}

}  // namespace lodbake::simplify_detail
