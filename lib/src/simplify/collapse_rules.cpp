// The collapse rules as policies over one read-only profile (collapse_rules.h, docs/simplify.md).

#include "collapse_rules.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "posed_guard.h"

namespace lodbake::simplify_detail {

// ---------------------------------------------------------------------------------------------
// Targets.

std::vector<PlannedLevel> planLevels(const std::vector<LevelTarget>& targets, size_t faceCount, double diagonal) {
    std::vector<PlannedLevel> plan;
    for (const LevelTarget& t : targets) {
        PlannedLevel p{t, 0, std::numeric_limits<double>::infinity()};
        if (t.ratio > 0) p.triangles = uint64_t(std::llround(std::min(1.0, t.ratio) * double(faceCount)));
        if (t.triangles > 0) p.triangles = std::max(p.triangles, t.triangles);
        if (t.maxError > 0) p.error = t.maxError * diagonal;
        plan.push_back(p);
    }
    std::stable_sort(plan.begin(), plan.end(), [](const PlannedLevel& a, const PlannedLevel& b) {
        if (a.triangles != b.triangles) return a.triangles > b.triangles;
        return a.error < b.error;
    });
    return plan;
}

// ---------------------------------------------------------------------------------------------
// Mesh filters.

// Target not locked, a border vertex only moves along a border edge, the fan of the edge does not
// vanish, and the link condition: the common neighbours of v_i and v_j are exactly the opposite
// vertices of the edge's faces, except that a border collapse may close a three-vertex hole
// (v_i, v_j, b). Leaves markJ marking the neighbours of v_j with stampJ.
static Reject linkCondition(const CollapseProfile& p, RuleScratch& w) {
    const CollapseState& s = p.mesh;
    const uint32_t vi = p.vi, vj = p.vj();
    if (s.locked[vj]) return Reject::Locked;
    const bool borderEdge = p.borderEdge();
    if (s.border[vi] && !borderEdge) return Reject::Border;
    size_t fanFaces = s.vfaces[vi].size();
    if (s.pinch[vi]) {  // the fan of the edge must not vanish (p.fan labels vfaces[vi])
        const auto& fs = s.vfaces[vi];
        uint32_t f0 = p.fan[size_t(std::find(fs.begin(), fs.end(), p.edge.f0) - fs.begin())];
        fanFaces = size_t(std::count(p.fan.begin(), p.fan.end(), f0));
    }
    if (fanFaces <= (borderEdge ? 1u : 2u)) return Reject::Ear;
    size_t common = 0;
    uint32_t stampJ = ++w.stampJ;
    uint32_t commonV[3] = {kNone, kNone, kNone};
    for (uint32_t f : s.vfaces[vj])
        for (uint32_t u : s.tri[f]) {
            if (u == vj || w.markJ[u] == stampJ) continue;
            w.markJ[u] = stampJ;
            if (w.markI[u] == w.stampI) {
                if (common < 3) commonV[common] = u;
                ++common;
            }
        }
    // (Not for a pinch: its "hole" may be a crack between sheets that only share vertices, and
    // closing it would join faces whose regions were kept apart.)
    if (borderEdge && common == 2 && !s.pinch[vi]) {
        // Closing a three-vertex hole (vi, vj, b): allowed, the edge (vj, b) gets its second face.
        const Tri& t0 = s.tri[p.edge.f0];
        uint32_t opposite = t0[0] != vi && t0[0] != vj ? t0[0] : (t0[1] != vi && t0[1] != vj ? t0[1] : t0[2]);
        uint32_t b = commonV[0] == opposite ? commonV[1] : commonV[0];
        bool holeI = false;
        for (const RingEntry& e : p.ring)
            if (e.w == b) holeI = e.f1 == kNone;
        size_t facesJB = 0;
        for (uint32_t f : s.vfaces[vj]) facesJB += s.corner(f, b) >= 0;
        if (!holeI || facesJB != 1 || s.locked[b]) return Reject::Link;
    } else if (common != (borderEdge ? 1u : 2u)) {
        return Reject::Link;
    }
    return Reject::None;
}

// The cost, checking each moved face on the way (in fan order, so the first failing face names
// the reason): no duplicate face (the link condition on vertices misses the tetrahedron), no
// degenerate face, no face turning by more than maxNormalChangeDeg or away from its own original
// normal. The cost is max(d(V_i, new fan), d(V_far, new fan), quadricTerm).
static Reject vertexDeviation(const CollapseProfile& p, const RuleScratch& w, double quadricTerm, double& dev,
                              float& farDist) {
    const CollapseState& s = p.mesh;
    const uint32_t vi = p.vi, vj = p.vj();
    const uint32_t stampJ = w.stampJ;
    const auto& P = s.mesh.positions;
    Vec3 pi = P[vi], pj = P[vj];
    uint32_t far = s.farPoint[vi];
    Vec3 pf = far != kNone ? P[far] : pi;
    double best2 = std::numeric_limits<double>::infinity(), far2 = best2;
    for (uint32_t f : s.vfaces[vi]) {
        if (f == p.edge.f0 || f == p.edge.f1) continue;
        const Tri& t = s.tri[f];
        int c = s.corner(f, vi);
        // A moved face (vj, x, y) must not already exist around vj (only possible when x and y are
        // both neighbours of vj, marked by the link condition).
        uint32_t x = t[(c + 1) % 3], y = t[(c + 2) % 3];
        if (w.markJ[x] == stampJ && w.markJ[y] == stampJ)
            for (uint32_t g : s.vfaces[vj])
                if (g != p.edge.f0 && g != p.edge.f1 && s.corner(g, x) >= 0 && s.corner(g, y) >= 0) return Reject::Link;
        Vec3 qv[3] = {P[t[0]], P[t[1]], P[t[2]]};
        Vec3 n0 = cross(qv[1] - qv[0], qv[2] - qv[0]);
        qv[c] = pj;
        Vec3 e1 = qv[1] - qv[0], e2 = qv[2] - qv[0];
        Vec3 n1 = cross(e1, e2);
        double l1 = length(n1);
        double scale = std::max({length2(e1), length2(e2), length2(qv[2] - qv[1])});
        if (!(l1 > 1e-12 * scale)) return Reject::Degenerate;
        double l0 = length(n0);
        if (l0 > 0 && dot(n0, n1) <= p.settings.cosMaxNormalChange * l0 * l1) return Reject::Flip;
        const auto& on = s.tri.rec[f].n;
        if (n1.x * on[0] + n1.y * on[1] + n1.z * on[2] <= 0 && (on[0] != 0 || on[1] != 0 || on[2] != 0))
            return Reject::Flip;
        // The distance to the face's plane bounds the distance to the face from below: skip the
        // exact query when the plane is already farther than the best face (with a margin far
        // above rounding, so the minimum is the same as without the test).
        double inv = 1.0 / (l1 * l1);
        double dp = dot(pi - qv[0], n1);
        if (dp * dp * inv <= best2 * (1 + 1e-6))
            best2 = std::min(best2, closestWithDistance(pi, qv[0], qv[1], qv[2]).dist2);
        if (far != kNone) {
            double df = dot(pf - qv[0], n1);
            if (df * df * inv <= far2 * (1 + 1e-6))
                far2 = std::min(far2, closestWithDistance(pf, qv[0], qv[1], qv[2]).dist2);
        }
    }
    farDist = far != kNone ? float(std::sqrt(far2)) : 0.f;
    dev = std::max({std::sqrt(best2), double(farDist), quadricTerm});
    if (p.settings.posed) dev = std::max(dev, posedDeviation(p, *p.settings.posed));
    return Reject::None;
}

// Skinned meshes: v_i moves only onto a vertex bound (almost) like itself.
static Reject influenceRule(const CollapseProfile& p) {
    const std::vector<uint32_t>& iw = p.mesh.influenceWedge;
    if (iw.empty()) return Reject::None;
    const uint32_t a = iw[p.vi], b = iw[p.vj()];
    if (a == kNone || b == kNone) return Reject::Skin;
    if (a == b) return Reject::None;
    const Wedges& W = p.mesh.input.wedges;
    auto weight = [&](uint32_t wedge, int k) {
        const Vec4& q = W.weights[wedge];
        return k == 0 ? q.x : k == 1 ? q.y : k == 2 ? q.z : q.w;
    };
    // Total variation: half the L1 distance between the two weight vectors over all joints
    // (weights of a joint listed twice add up; zero-weight slots do not count).
    std::array<std::pair<uint16_t, double>, 8> diff{};
    size_t n = 0;
    auto add = [&](uint32_t wedge, double sign) {
        for (int k = 0; k < 4; ++k) {
            const double x = weight(wedge, k);
            if (x == 0) continue;
            const uint16_t j = W.joints[wedge][size_t(k)];
            size_t i = 0;
            while (i < n && diff[i].first != j) ++i;
            if (i == n) diff[n++] = {j, 0.0};
            diff[i].second += sign * x;
        }
    };
    add(a, 1);
    add(b, -1);
    double l1 = 0;
    for (size_t i = 0; i < n; ++i) l1 += std::fabs(diff[i].second);
    return 0.5 * l1 > p.settings.maxInfluenceChange ? Reject::Skin : Reject::None;
}

Reject checkCollapse(const CollapseProfile& p, RuleScratch& w, double quadricTerm, double& dev, float& farDist) {
    Reject r = influenceRule(p);
    if (r != Reject::None) return r;
    r = linkCondition(p, w);
    if (r != Reject::None) return r;
    return vertexDeviation(p, w, quadricTerm, dev, farDist);
}

// ---------------------------------------------------------------------------------------------
// Region rules.

// Rule 1: on a closed component a merge may not leave fewer than two regions.
static Reject ruleLastPBoundary(const MergeProfile& m, const RuleSettings&) {
    return m.closedComponent && m.regionsAfter < 2 && m.regions > 1 ? Reject::Rule1 : Reject::None;
}

// Regions become texture charts: a merge may not turn a region further than a cap of
// maxRegionConeDeg half-angle (measured by the mean resultant length of its normals).
static Reject ruleNormalCone(const MergeProfile& m, const RuleSettings& settings) {
    return m.regions > 1 && length(m.merged.normalSum) < settings.minRegionCoherence * m.merged.area ? Reject::Cone
                                                                                                     : Reject::None;
}

// The rules that may forbid a merge, in the order they are asked; the first objection is the
// collapse's reason.
using MergeRule = Reject (*)(const MergeProfile&, const RuleSettings&);
constexpr MergeRule kMergeRules[] = {ruleLastPBoundary, ruleNormalCone};

// Rule 3's geometry ("respect the p-boundary"): when v_i is interior with exactly two p-boundary
// spokes, the collapse runs along one of them and each side keeps a surviving face, the distance
// of V_i to the new boundary edge (v_j, v_k); -1 when rule 3 does not apply. sideA, sideB: the
// regions on either side.
static double keptBoundaryChord(const CollapseProfile& p, uint32_t& sideA, uint32_t& sideB) {
    const CollapseState& s = p.mesh;
    const RegionState& r = p.regions;
    const uint32_t vi = p.vi;
    if (s.border[vi] || s.pinch[vi] || !isPBoundarySpoke(r, p.edge)) return -1;
    uint32_t spokes = 0, vk = kNone;
    for (const RingEntry& e : p.ring)
        if (isPBoundarySpoke(r, e)) {
            ++spokes;
            if (e.w != p.vj()) vk = e.w;
        }
    if (spokes != 2 || vk == kNone) return -1;
    sideA = r.faceRegion[p.edge.f0];
    sideB = r.faceRegion[p.edge.f1];
    bool keptA = false, keptB = false;
    for (uint32_t f : s.vfaces[vi]) {
        if (f == p.edge.f0 || f == p.edge.f1) continue;
        keptA |= r.faceRegion[f] == sideA;
        keptB |= r.faceRegion[f] == sideB;
    }
    if (!keptA || !keptB) return -1;
    const auto& P = s.mesh.positions;
    Vec3 a = P[p.vj()], ab = P[vk] - a;
    double l2 = length2(ab);
    double t = l2 > 0 ? std::clamp(dot(P[vi] - a, ab) / l2, 0.0, 1.0) : 0.0;
    return length(P[vi] - (a + ab * t));
}

Reject planRegions(const CollapseProfile& p, RuleScratch& w, Candidate& c) {
    const RegionState& r = p.regions;
    c.rule3 = false;
    uint32_t sideA = kNone, sideB = kNone;
    const double chord = keptBoundaryChord(p, sideA, sideB);
    auto keepBoundary = [&] {
        c.rule3 = true;
        c.shape = std::max(regionShape(r.stats[sideA], r.totalArea), regionShape(r.stats[sideB], r.totalArea));
        return Reject::None;
    };
    const double eps = std::max(p.settings.epsilonDeviationFactor * c.dev, p.settings.epsilonBox);
    if (chord >= 0 && chord <= eps) return keepBoundary();
    // Otherwise the regions merge (each group into one), unless a merge rule objects. Then a
    // collapse that rule 3's geometry allows still keeps the boundary, its cost raised to the
    // boundary's displacement (the texture error of keeping the chart cut on the new edge).
    collectMergeGroups(p.mesh, r, p.vi, p.fan, w.groups);
    const uint32_t comp = p.mesh.componentOf(p.vi);
    const bool closed = p.mesh.components.open[comp] == 0;
    double shape = 0;
    for (size_t g = 0; g < w.groups.count(); ++g) {
        const uint32_t* regions = w.groups.begin(g);
        const size_t n = w.groups.size(g);
        RegionStats merged = r.stats[regions[0]];
        for (size_t k = 1; k < n; ++k) mergeStats(merged, r.stats[regions[k]]);
        const MergeProfile m{merged, n, r.componentRegions[comp] - uint32_t(n - 1), closed};
        for (MergeRule rule : kMergeRules) {
            Reject why = rule(m, p.settings);
            if (why == Reject::None) continue;
            if (chord < 0) return why;
            c.dev = std::max(c.dev, chord);
            return keepBoundary();
        }
        shape = std::max(shape, double(regionShape(merged, r.totalArea)));
    }
    c.shape = float(shape);
    return Reject::None;
}

// ---------------------------------------------------------------------------------------------
// Exact measure under an error target.

double measureAttached(const CollapseState& s, RuleScratch& w, uint32_t vi, uint32_t vj) {
    const auto& P = s.mesh.positions;
    auto newCorners = [&](uint32_t f, Tri& t) {  // false when f vanishes
        t = s.tri[f];
        int ci = s.corner(f, vi);
        if (ci < 0) return true;
        if (s.corner(f, vj) >= 0) return false;
        t[ci] = vj;
        return true;
    };
    auto dist2ToFan = [&](uint32_t p, uint32_t x) {
        double best = std::numeric_limits<double>::infinity();
        Tri t;
        for (uint32_t f : s.vfaces[x])
            if (newCorners(f, t)) best = std::min(best, closestWithDistance(P[p], P[t[0]], P[t[1]], P[t[2]]).dist2);
        if (x == vj)
            for (uint32_t f : s.vfaces[vi])
                if (s.corner(f, vj) < 0 && newCorners(f, t))
                    best = std::min(best, closestWithDistance(P[p], P[t[0]], P[t[1]], P[t[2]]).dist2);
        return best;
    };
    double worst = dist2ToFan(vi, vj);
    for (uint32_t p = s.attachHead[vi]; p != kNone; p = s.attachNext[p]) worst = std::max(worst, dist2ToFan(p, vj));
    ++w.stampJ;
    for (uint32_t f : s.vfaces[vi])
        for (uint32_t x : s.tri[f]) {
            if (x == vi || w.markJ[x] == w.stampJ) continue;
            w.markJ[x] = w.stampJ;
            for (uint32_t p = s.attachHead[x]; p != kNone; p = s.attachNext[p]) worst = std::max(worst, dist2ToFan(p, x));
        }
    return std::sqrt(worst);
}

}  // namespace lodbake::simplify_detail
