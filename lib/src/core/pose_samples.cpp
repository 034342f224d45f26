// Sampled poses of a rig (lodbake/core/pose_samples.h).

#include "lodbake/core/pose_samples.h"

#include <algorithm>
#include <cmath>

#include "lodbake/core/pose.h"

namespace lodbake {

std::vector<PoseSample> samplePoses(const Rig& rig, const PoseSampleOptions& options) {
    std::vector<PoseSample> out;
    if (rig.empty() || options.perAnimation <= 0 || options.maxPoses <= 0) return out;
    out.push_back({-1, 0.0});
    const size_t animations = rig.animations.size();
    if (animations == 0) return out;
    const size_t room = size_t(std::max(options.maxPoses - 1, 0));
    const size_t per = std::min(size_t(options.perAnimation), std::max<size_t>(1, room / animations));
    for (size_t a = 0; a < animations && out.size() < size_t(options.maxPoses); ++a) {
        const TimeRange r = animationTimes(rig.animations[a]);
        if (per == 1 || !(r.end > r.start)) {
            out.push_back({int(a), 0.5 * (r.start + r.end)});
            continue;
        }
        for (size_t i = 0; i < per; ++i)
            out.push_back({int(a), r.start + (r.end - r.start) * double(i) / double(per - 1)});
    }
    return out;
}

// Whether the 3x3 part of m is a rotation (orthonormal columns, determinant +1) to the precision
// of float-stored inverse bind matrices and keys.
static bool isRigid(const Mat4& m) {
    constexpr double kTolerance = 1e-5;
    const Vec3 c[3] = {{m[0], m[1], m[2]}, {m[4], m[5], m[6]}, {m[8], m[9], m[10]}};
    for (int i = 0; i < 3; ++i)
        for (int j = i; j < 3; ++j)
            if (std::fabs(dot(c[i], c[j]) - (i == j ? 1.0 : 0.0)) > kTolerance) return false;
    return det3(m) > 0;
}

PosedWedges poseWedges(const Rig& rig, const MorphTargets& morph, const TriMesh& mesh, const std::vector<PoseSample>& samples) {
    PosedWedges out;
    const Wedges& W = mesh.wedges;
    if (samples.empty() || rig.empty() || W.size() == 0 || W.joints.size() != W.size() || W.weights.size() != W.size())
        return out;
    // Each wedge's posed position is the position of its posed vertex in poseMesh's output, so
    // this measure poses exactly as compare and the viewers do.
    std::vector<uint8_t> rigid(rig.joints.size(), 1);
    for (const PoseSample& s : samples) {
        const TriMesh posed = poseMesh(rig, morph, mesh, s.animation, s.time);
        std::vector<Vec3> p(W.size());
        for (size_t w = 0; w < W.size(); ++w) {
            const uint32_t v = posed.wedges.vertex[w];
            p[w] = v < posed.positions.size() ? posed.positions[v] : mesh.positions[W.vertex[w]];
        }
        out.positions.push_back(std::move(p));
        const std::vector<Mat4> global = poseNodes(rig, s.animation, s.time);
        for (size_t j = 0; j < rig.joints.size(); ++j) {
            const int node = rig.joints[j];
            if (node < 0 || size_t(node) >= global.size() || j >= rig.inverseBind.size() ||
                !isRigid(mul(global[size_t(node)], rig.inverseBind[j])))
                rigid[j] = 0;
        }
    }
    out.rigidJoint.assign(W.size(), PosedWedges::kNotRigid);
    for (size_t w = 0; w < W.size(); ++w) {
        const Vec4& q = W.weights[w];
        const double weight[4] = {q.x, q.y, q.z, q.w};
        int only = -1, nonZero = 0;
        for (int k = 0; k < 4; ++k)
            if (weight[k] != 0) ++nonZero, only = k;
        if (nonZero != 1 || std::fabs(weight[only] - 1) > 1e-6) continue;
        const uint16_t j = W.joints[w][size_t(only)];
        if (j < rigid.size() && rigid[j]) out.rigidJoint[w] = j;
    }
    return out;
}

}  // namespace lodbake
