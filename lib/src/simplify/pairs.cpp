// Simplification pairs and the snapshot of a level (pairs.h, docs/simplify.md).

#include "pairs.h"

#include <algorithm>
#include <limits>

#include "lodbake/core/parallel.h"

namespace lodbake::simplify_detail {

constexpr size_t kChunk = 4096;  // vertices per projection chunk (fixed: thread-independent)

// Root of the collapse chain of removed vertex v (kNone when it ends in a pruned vertex), memoised
// for one snapshot in root[] (kNone - 1: not known yet).
static uint32_t chainRoot(const CollapseState& s, uint32_t v, std::vector<uint32_t>& root) {
    uint32_t u = v;
    while (s.removed[u] && root[u] == kNone - 1) {
        uint32_t next = s.collapsedInto[u];
        if (next == kNone) break;
        u = next;
    }
    uint32_t r = !s.removed[u] ? u : (root[u] != kNone - 1 ? root[u] : kNone);
    for (uint32_t w = v; w != u && s.removed[w];) {  // path compression
        uint32_t next = s.collapsedInto[w];
        root[w] = r;
        if (next == kNone) break;
        w = next;
    }
    if (s.removed[u]) root[u] = r;
    return r;
}

// The pair of removed vertex v whose chain ends in surviving vertex `root`: V_v projected onto
// the faces around root (one ring further when that is farther than any collapse cost), preferring
// the faces of v's region; edge form when the projection lies on a p-boundary edge.
static SimplificationPair projectVertex(const CollapseState& s, const RegionState& r, uint32_t v, uint32_t root,
                                        double runningMax2, std::vector<uint32_t>& faceMark, uint32_t& faceStamp) {
    const auto& P = s.mesh.positions;
    uint32_t region = s.keptFace[v] == kNone ? kNone : r.faceRegion[s.keptFace[v]];
    double bestAny = std::numeric_limits<double>::infinity(), bestRegion = bestAny;
    uint32_t fAny = kNone, fRegion = kNone;
    Closest cAny{}, cRegion{};
    auto consider = [&](uint32_t f) {
        const Tri& t = s.tri[f];
        Closest cp = closestWithDistance(P[v], P[t[0]], P[t[1]], P[t[2]]);
        if (cp.dist2 < bestAny) bestAny = cp.dist2, fAny = f, cAny = cp;
        if (r.faceRegion[f] == region && cp.dist2 < bestRegion) bestRegion = cp.dist2, fRegion = f, cRegion = cp;
    };
    for (uint32_t f : s.vfaces[root]) consider(f);
    // Farther than any collapse cost: the closest point may lie one ring out.
    double found = fRegion != kNone ? bestRegion : bestAny;
    if (found > runningMax2) {
        uint32_t stamp = ++faceStamp;
        for (uint32_t f : s.vfaces[root]) faceMark[f] = stamp;
        for (uint32_t f : s.vfaces[root])
            for (uint32_t u : s.tri[f])
                for (uint32_t g : s.vfaces[u])
                    if (faceMark[g] != stamp) {
                        faceMark[g] = stamp;
                        consider(g);
                    }
    }
    uint32_t f = fRegion != kNone ? fRegion : fAny;
    const Closest& cp = fRegion != kNone ? cRegion : cAny;
    const Tri& t = s.tri[f];
    SimplificationPair pair;
    pair.vertex = v;
    pair.face = f;
    pair.coarse = t;
    for (int k = 0; k < 3; ++k) pair.bary[k] = float(cp.bary[k]);
    // Edge form when P lies on an edge of the face that is a p-boundary at this level.
    for (int k = 0; k < 3; ++k) {
        if (cp.bary[k] != 0) continue;
        uint32_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
        bool pb = false;
        for (uint32_t g : s.vfaces[a])
            if (g != f && s.corner(g, b) >= 0 && r.faceRegion[g] != r.faceRegion[f]) pb = true;
        if (!pb) continue;
        pair.coarse = {a, b, b};
        pair.bary = {float(cp.bary[(k + 1) % 3]), float(cp.bary[(k + 2) % 3]), 0.f};
        break;
    }
    float sumB = pair.bary[0] + pair.bary[1] + pair.bary[2];
    for (float& b : pair.bary) b /= sumB;
    Vec3 q = P[pair.coarse[0]] * pair.bary[0] + P[pair.coarse[1]] * pair.bary[1] + P[pair.coarse[2]] * pair.bary[2];
    pair.deviation = float(length(P[v] - q));
    return pair;
}

// The pairs of every removed vertex whose chain ends in a surviving vertex, in input vertex order.
// Returns the largest pair deviation.
static double computePairs(const CollapseState& s, const RegionState& r, double runningMax, int threads,
                           Level& level) {
    // Chain roots first (sequential, memoised), then the projections in parallel chunks whose
    // pairs are concatenated in vertex order.
    std::vector<uint32_t> root(s.vertexCount, kNone - 1), rootOf(s.vertexCount, kNone);
    for (uint32_t v = 0; v < s.vertexCount; ++v)
        if (s.removed[v] && s.collapsedInto[v] != kNone) rootOf[v] = chainRoot(s, v, root);
    root.clear();
    root.shrink_to_fit();
    const double runningMax2 = runningMax * runningMax;
    std::vector<std::vector<SimplificationPair>> chunkPairs(chunkCount(s.vertexCount, kChunk));
    std::vector<std::vector<uint32_t>> faceMark(size_t(resolveThreads(threads)));  // per thread
    std::vector<uint32_t> faceStamp(faceMark.size(), 0);
    parallelChunks(s.vertexCount, kChunk, threads, [&](size_t begin, size_t end, size_t t) {
        if (faceMark[t].size() != s.faceCount) faceMark[t].assign(s.faceCount, 0);
        // The stamp and the pairs stay local until the chunk ends: the per-thread stamps and the
        // chunks' vectors share cache lines with the other threads' ones.
        uint32_t stamp = faceStamp[t];
        std::vector<SimplificationPair> out;
        for (uint32_t u = uint32_t(begin); u < end; ++u) {  // in input order
            uint32_t v = s.newId[u];
            uint32_t rv = rootOf[v];
            if (rv == kNone || s.vfaces[rv].empty()) continue;
            out.push_back(projectVertex(s, r, v, rv, runningMax2, faceMark[t], stamp));
        }
        faceStamp[t] = stamp;
        chunkPairs[begin / kChunk] = std::move(out);
    });
    double sum = 0, maxPair = 0;
    size_t total = 0;
    for (const auto& c : chunkPairs) total += c.size();
    level.pairs.reserve(total);
    for (auto& c : chunkPairs) {
        for (const SimplificationPair& pair : c) {
            sum += pair.deviation;
            maxPair = std::max(maxPair, double(pair.deviation));
        }
        level.pairs.insert(level.pairs.end(), c.begin(), c.end());
        std::vector<SimplificationPair>().swap(c);
    }
    level.meanDeviation = level.pairs.empty() ? 0 : sum / double(level.pairs.size());
    return maxPair;
}

void snapshotLevel(const CollapseState& s, RegionState& r, HierarchyRecorder& rec, const PlannedLevel& plan,
                   const std::string& stopReason, double seconds, int threads, uint32_t pass) {
    fixDeadRepresentatives(r, s, rec, pass);
    Level level;
    level.targetRatio = plan.target.ratio;
    level.targetTriangles = plan.triangles;
    level.targetError = plan.hasErrorTarget() ? plan.error : 0;
    level.stopReason = stopReason;
    level.faces.reserve(s.aliveFaces);
    level.triangles.reserve(s.aliveFaces);
    for (uint32_t f = 0; f < s.faceCount; ++f) {
        if (!s.faceAlive[f]) continue;
        level.faces.push_back(f);
        level.triangles.push_back(s.tri[f]);
        if (!s.wedge.empty()) level.cornerWedges.push_back(s.wedge[f]);
    }
    level.faceRegion = r.faceRegion;
    level.regionCount = r.regionCount;
    level.collapseCount = uint32_t(rec.out.collapses.size());
    double maxPair = computePairs(s, r, rec.runningMax, threads, level);
    rec.levelMax = std::max({rec.levelMax, rec.runningMax, maxPair});
    level.maxDeviation = rec.levelMax;
    level.seconds = seconds;
    rec.out.levels.push_back(std::move(level));
}

}  // namespace lodbake::simplify_detail
