// Posed deviations of collapses and levels (posed_guard.h).

#include "posed_guard.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "lodbake/core/parallel.h"

namespace lodbake::simplify_detail {

namespace {

constexpr uint32_t kNotRigid = PosedWedges::kNotRigid;
constexpr size_t kPairChunk = 4096;  // pairs per chunk (fixed: thread-independent)

// The closest point of a bind-pose point on a set of faces (the first face among equals), as
// barycentric coordinates over the face's corner wedges.
struct Landing {
    double dist2 = std::numeric_limits<double>::infinity();
    std::array<uint32_t, 3> wedges{};
    std::array<double, 3> bary{};
    void consider(const Closest& c, const std::array<uint32_t, 3>& w) {
        if (!(c.dist2 < dist2)) return;
        dist2 = c.dist2;
        wedges = w;
        bary = {c.bary[0], c.bary[1], c.bary[2]};
    }
    bool found() const { return std::isfinite(dist2); }
    Vec3 posed(const std::vector<Vec3>& P) const {
        return P[wedges[0]] * bary[0] + P[wedges[1]] * bary[1] + P[wedges[2]] * bary[2];
    }
};

}  // namespace

double posedDeviation(const CollapseProfile& p, const PosedWedges& posed) {
    const CollapseState& s = p.mesh;
    if (posed.empty() || s.influenceWedge.empty() || s.wedge.empty()) return 0;
    const uint32_t vi = p.vi, vj = p.vj();
    const uint32_t wi = s.influenceWedge[vi], wj = s.influenceWedge[vj];
    if (wi >= posed.rigidJoint.size() || wj >= posed.rigidJoint.size()) return 0;
    const uint32_t far = s.farPoint[vi];
    const uint32_t wf = far != kNone ? s.influenceWedge[far] : wi;
    if (wf >= posed.rigidJoint.size()) return 0;

    // One rigid joint moves every point involved: distances are those of the bind pose.
    const uint32_t joint = posed.rigidJoint[wi];
    bool rigid = joint != kNotRigid && posed.rigidJoint[wj] == joint && posed.rigidJoint[wf] == joint;
    for (uint32_t f : s.vfaces[vi]) {
        if (!rigid) break;
        if (f == p.edge.f0 || f == p.edge.f1) continue;
        for (uint32_t w : s.wedge[f]) rigid &= posed.rigidJoint[w] == joint;
    }
    if (rigid) return 0;

    // Where V_i and its farthest point land on the new fan in the bind pose: the closest point,
    // as barycentric coordinates of a moved face's wedges.
    const auto& B = s.mesh.positions;
    const Vec3 bi = B[vi], bf = far != kNone ? B[far] : bi;
    Landing li, lf;
    for (uint32_t f : s.vfaces[vi]) {
        if (f == p.edge.f0 || f == p.edge.f1) continue;
        const Tri& t = s.tri[f];
        const int ci = s.corner(f, vi);
        Vec3 q[3];
        std::array<uint32_t, 3> w{};
        for (int c = 0; c < 3; ++c) {
            q[c] = c == ci ? B[vj] : B[t[size_t(c)]];
            w[size_t(c)] = c == ci ? wj : s.wedge[f][size_t(c)];
        }
        li.consider(closestWithDistance(bi, q[0], q[1], q[2]), w);
        if (far != kNone) lf.consider(closestWithDistance(bf, q[0], q[1], q[2]), w);
    }
    if (!li.found()) return 0;  // no moved face: nothing to measure (the ear check rejects it)

    // In each pose, the distance between each posed point and its landing point posed with the
    // face: a face that sweeps away from the points it stood in for when the joints turn (a chord
    // across a bending knee) costs what it sweeps, not the distance to the nearest other face.
    double worst2 = 0;
    for (const std::vector<Vec3>& P : posed.positions) {
        worst2 = std::max(worst2, length2(P[wi] - li.posed(P)));
        if (far != kNone && lf.found()) worst2 = std::max(worst2, length2(P[wf] - lf.posed(P)));
    }
    return std::sqrt(worst2);
}

void raisePosedLevelDeviation(const CollapseState& s, const PosedWedges& posed, int threads, HierarchyRecorder& rec) {
    if (posed.empty() || s.influenceWedge.empty() || s.wedge.empty() || rec.out.levels.empty()) return;
    Level& level = rec.out.levels.back();
    const std::vector<SimplificationPair>& pairs = level.pairs;
    std::vector<double> chunkMax(chunkCount(pairs.size(), kPairChunk), 0.0);
    parallelChunks(pairs.size(), kPairChunk, threads, [&](size_t begin, size_t end, size_t) {
        double worst2 = 0;
        for (size_t k = begin; k < end; ++k) {
            const SimplificationPair& pair = pairs[k];
            const uint32_t wv = s.influenceWedge[pair.vertex];
            if (wv >= posed.rigidJoint.size()) continue;
            uint32_t wc[3];
            for (int c = 0; c < 3; ++c) wc[c] = s.wedge[pair.face][size_t(s.corner(pair.face, pair.coarse[size_t(c)]))];
            const uint32_t joint = posed.rigidJoint[wv];
            if (joint != kNotRigid && posed.rigidJoint[wc[0]] == joint && posed.rigidJoint[wc[1]] == joint &&
                posed.rigidJoint[wc[2]] == joint)
                continue;  // a rigid motion of the bind-pose pair: its deviation is already counted
            for (const std::vector<Vec3>& P : posed.positions) {
                const Vec3 q = P[wc[0]] * double(pair.bary[0]) + P[wc[1]] * double(pair.bary[1]) +
                               P[wc[2]] * double(pair.bary[2]);
                worst2 = std::max(worst2, length2(P[wv] - q));
            }
        }
        chunkMax[begin / kPairChunk] = worst2;
    });
    double worst2 = 0;
    for (double m : chunkMax) worst2 = std::max(worst2, m);
    const double worst = std::sqrt(worst2);
    level.maxDeviation = std::max(level.maxDeviation, worst);
    rec.levelMax = std::max(rec.levelMax, worst);
}

}  // namespace lodbake::simplify_detail
