// Posing on the CPU (pose.h): node transforms at a time, morph weights, linear blend skinning.
#include "lodbake/core/pose.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace lodbake {
namespace {

Vec4 normalizeQuat(Vec4 q) {
    double l = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
    if (!(l > 0)) return {0, 0, 0, 1};
    return {q.x / l, q.y / l, q.z / l, q.w / l};
}

// glTF's "linear" rotation: spherical interpolation along the shorter arc.
Vec4 slerp(Vec4 a, Vec4 b, double t) {
    double d = a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
    if (d < 0) { b = {-b.x, -b.y, -b.z, -b.w}; d = -d; }
    double wa = 1 - t, wb = t;
    if (d < 0.9995) {
        double theta = std::acos(std::min(d, 1.0)), s = std::sin(theta);
        wa = std::sin((1 - t) * theta) / s;
        wb = std::sin(t * theta) / s;
    }
    return normalizeQuat({wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z, wa * a.w + wb * b.w});
}

}  // namespace

void sampleAnimation(const AnimationSampler& s, double time, bool rotation, double* out) {
    const int c = s.comps;
    const size_t n = s.times.size();
    const bool cubic = s.interpolation == Interpolation::CubicSpline;
    auto value = [&](size_t k, int d) { return cubic ? s.values[(3 * k + 1) * size_t(c) + size_t(d)] : s.values[k * size_t(c) + size_t(d)]; };
    if (n == 0) return;
    size_t hi = size_t(std::upper_bound(s.times.begin(), s.times.end(), time) - s.times.begin());
    if (hi == 0 || hi == n || s.interpolation == Interpolation::Step) {
        size_t k = hi == 0 ? 0 : hi - 1;
        for (int d = 0; d < c; ++d) out[d] = value(k, d);
        return;
    }
    const size_t lo = hi - 1;
    const double dt = s.times[hi] - s.times[lo];
    const double t = dt > 0 ? (time - s.times[lo]) / dt : 0;
    if (cubic) {
        const double t2 = t * t, t3 = t2 * t;
        const double h00 = 2 * t3 - 3 * t2 + 1, h10 = t3 - 2 * t2 + t, h01 = -2 * t3 + 3 * t2, h11 = t3 - t2;
        for (int d = 0; d < c; ++d) {
            double outTangent = s.values[(3 * lo + 2) * size_t(c) + size_t(d)];
            double inTangent = s.values[(3 * hi) * size_t(c) + size_t(d)];
            out[d] = h00 * value(lo, d) + h10 * dt * outTangent + h01 * value(hi, d) + h11 * dt * inTangent;
        }
        if (rotation) {
            Vec4 q = normalizeQuat({out[0], out[1], out[2], out[3]});
            out[0] = q.x; out[1] = q.y; out[2] = q.z; out[3] = q.w;
        }
        return;
    }
    if (rotation) {
        Vec4 q = slerp({value(lo, 0), value(lo, 1), value(lo, 2), value(lo, 3)}, {value(hi, 0), value(hi, 1), value(hi, 2), value(hi, 3)}, t);
        out[0] = q.x; out[1] = q.y; out[2] = q.z; out[3] = q.w;
        return;
    }
    for (int d = 0; d < c; ++d) out[d] = (1 - t) * value(lo, d) + t * value(hi, d);
}

Mat4 trsMatrix(Vec3 tr, Vec4 rot, Vec3 sc) {
    Vec4 q = normalizeQuat(rot);
    const double x = q.x, y = q.y, z = q.z, w = q.w;
    Mat4 r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0,
              2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0,
              2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0,
              0, 0, 0, 1};
    Mat4 t = identity4(), s = identity4();
    t[12] = tr.x; t[13] = tr.y; t[14] = tr.z;
    s[0] = sc.x; s[5] = sc.y; s[10] = sc.z;
    return mul(t, mul(r, s));
}

bool invertAffine(const Mat4& m, Mat4& out) {
    const double det = det3(m);
    if (!(std::fabs(det) > 0) || !std::isfinite(det)) return false;
    auto M = [&](int r, int c) { return m[size_t(c * 4 + r)]; };
    Mat4 inv = identity4();
    auto I = [&](int r, int c) -> double& { return inv[size_t(c * 4 + r)]; };
    I(0, 0) = (M(1, 1) * M(2, 2) - M(1, 2) * M(2, 1)) / det;
    I(0, 1) = (M(0, 2) * M(2, 1) - M(0, 1) * M(2, 2)) / det;
    I(0, 2) = (M(0, 1) * M(1, 2) - M(0, 2) * M(1, 1)) / det;
    I(1, 0) = (M(1, 2) * M(2, 0) - M(1, 0) * M(2, 2)) / det;
    I(1, 1) = (M(0, 0) * M(2, 2) - M(0, 2) * M(2, 0)) / det;
    I(1, 2) = (M(0, 2) * M(1, 0) - M(0, 0) * M(1, 2)) / det;
    I(2, 0) = (M(1, 0) * M(2, 1) - M(1, 1) * M(2, 0)) / det;
    I(2, 1) = (M(0, 1) * M(2, 0) - M(0, 0) * M(2, 1)) / det;
    I(2, 2) = (M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0)) / det;
    for (int r = 0; r < 3; ++r) I(r, 3) = -(I(r, 0) * M(0, 3) + I(r, 1) * M(1, 3) + I(r, 2) * M(2, 3));
    out = inv;
    return true;
}

Mat4 localMatrix(const RigNode& node) {
    return node.hasMatrix ? node.matrix : trsMatrix(node.translation, node.rotation, node.scale);
}

TimeRange animationTimes(const Animation& animation) {
    TimeRange r;
    bool any = false;
    for (const AnimationSampler& s : animation.samplers) {
        if (s.times.empty()) continue;
        r.start = any ? std::min(r.start, s.times.front()) : s.times.front();
        r.end = any ? std::max(r.end, s.times.back()) : s.times.back();
        any = true;
    }
    return r;
}

std::vector<Mat4> poseNodes(const Rig& rig, int animation, double time) {
    std::vector<RigNode> nodes = rig.nodes;
    if (animation >= 0 && size_t(animation) < rig.animations.size()) {
        const Animation& a = rig.animations[size_t(animation)];
        for (const AnimationChannel& ch : a.channels) {
            if (ch.node < 0 || size_t(ch.node) >= nodes.size() || ch.sampler < 0 || size_t(ch.sampler) >= a.samplers.size()) continue;
            RigNode& n = nodes[size_t(ch.node)];
            double v[4] = {0, 0, 0, 1};
            const bool rotation = ch.path == AnimationPath::Rotation;
            sampleAnimation(a.samplers[size_t(ch.sampler)], time, rotation, v);
            if (ch.path == AnimationPath::Translation) n.translation = {v[0], v[1], v[2]};
            else if (rotation) n.rotation = {v[0], v[1], v[2], v[3]};
            else n.scale = {v[0], v[1], v[2]};
        }
    }
    std::vector<Mat4> global(nodes.size());
    for (size_t i = 0; i < nodes.size(); ++i) {
        const Mat4 local = localMatrix(nodes[i]);
        const int p = nodes[i].parent;
        global[i] = p >= 0 && size_t(p) < i ? mul(global[size_t(p)], local) : local;
    }
    return global;
}

std::vector<double> morphWeights(const Rig& rig, const MorphTargets& morph, int animation, double time) {
    std::vector<double> w = morph.weights;
    if (animation < 0 || size_t(animation) >= rig.animations.size() || w.empty()) return w;
    const Animation& a = rig.animations[size_t(animation)];
    for (const AnimationChannel& ch : a.channels) {
        if (ch.path != AnimationPath::Weights || ch.sampler < 0 || size_t(ch.sampler) >= a.samplers.size()) continue;
        const AnimationSampler& s = a.samplers[size_t(ch.sampler)];
        if (size_t(s.comps) != w.size()) continue;
        sampleAnimation(s, time, false, w.data());
    }
    return w;
}

TriMesh poseMesh(const Rig& rig, const MorphTargets& morph, const TriMesh& mesh, int animation, double time) {
    const Wedges& W = mesh.wedges;
    const bool skinned = !rig.empty() && W.joints.size() == W.size() && W.weights.size() == W.size();
    // Targets that apply: a non-zero weight and deltas for every wedge.
    const std::vector<double> weight = morphWeights(rig, morph, animation, time);
    std::vector<size_t> active;
    for (size_t t = 0; t < W.targets.size() && t < weight.size(); ++t)
        if (weight[t] != 0 && W.targets[t].position.size() == W.size()) active.push_back(t);
    if (!skinned && active.empty()) return mesh;
    std::vector<Mat4> skinning;
    if (skinned) {
        const std::vector<Mat4> global = poseNodes(rig, animation, time);
        skinning.assign(rig.joints.size(), identity4());
        for (size_t j = 0; j < rig.joints.size(); ++j) {
            const int node = rig.joints[j];
            if (node >= 0 && size_t(node) < global.size() && j < rig.inverseBind.size()) skinning[j] = mul(global[size_t(node)], rig.inverseBind[j]);
        }
    }
    auto blended = [&](size_t w) {
        if (!skinned) return identity4();
        Mat4 m{};
        for (int k = 0; k < 4; ++k) {
            const double wt = k == 0 ? W.weights[w].x : k == 1 ? W.weights[w].y : k == 2 ? W.weights[w].z : W.weights[w].w;
            if (wt == 0) continue;
            const uint16_t j = W.joints[w][size_t(k)];
            const Mat4& s = j < skinning.size() ? skinning[j] : skinning.empty() ? m : skinning[0];
            for (size_t e = 0; e < 16; ++e) m[e] += wt * s[e];
        }
        return m;
    };
    // Morph targets apply first, in the bind frame (glTF: before skinning).
    auto morphed = [&](size_t w) {
        Vec3 p = mesh.positions[W.vertex[w]];
        for (size_t t : active) p += W.targets[t].position[w] * weight[t];
        return p;
    };
    auto morphedVector = [&](Vec3 v, size_t w, bool tangent) {
        for (size_t t : active) {
            const std::vector<Vec3>& d = tangent ? W.targets[t].tangent : W.targets[t].normal;
            if (d.size() == W.size()) v += d[w] * weight[t];
        }
        return v;
    };
    TriMesh out = mesh;
    out.positions.clear();
    out.wedges.vertex.assign(W.size(), 0);
    // One posed vertex per (welded vertex, influence set, morphed position), numbered in order of
    // first use.
    using Key = std::tuple<uint32_t, std::array<uint16_t, 4>, std::array<double, 4>, std::array<double, 3>>;
    std::map<Key, uint32_t> posed;
    std::vector<char> wedgeDone(W.size(), 0);
    auto place = [&](uint32_t w) {
        const Vec4 q = skinned ? W.weights[w] : Vec4{0, 0, 0, 0};
        const Vec3 p = morphed(w);
        Key key{W.vertex[w], skinned ? W.joints[w] : std::array<uint16_t, 4>{0, 0, 0, 0}, {q.x, q.y, q.z, q.w}, {p.x, p.y, p.z}};
        auto [it, inserted] = posed.emplace(key, uint32_t(out.positions.size()));
        if (inserted) out.positions.push_back(transformPoint(blended(w), p));
        return it->second;
    };
    for (size_t f = 0; f < mesh.triangles.size(); ++f)
        for (size_t k = 0; k < 3; ++k) {
            const uint32_t w = mesh.cornerWedges[f][k];
            const uint32_t v = place(w);
            out.triangles[f][k] = v;
            out.wedges.vertex[w] = v;
            wedgeDone[w] = 1;
        }
    for (uint32_t w = 0; w < W.size(); ++w) {
        if (!wedgeDone[w] && W.vertex[w] < mesh.positions.size()) out.wedges.vertex[w] = place(w);
        const Mat4 m = blended(w);
        if (!out.wedges.normal.empty()) {
            // Normals by the inverse transpose; a blend of rigid joints is close to rigid, so the
            // linear part, renormalised, is what renderers use too.
            Mat4 inv;
            Vec3 n = morphedVector(W.normal[w], w, false);
            if (invertAffine(m, inv)) n = {inv[0] * n.x + inv[1] * n.y + inv[2] * n.z, inv[4] * n.x + inv[5] * n.y + inv[6] * n.z,
                                           inv[8] * n.x + inv[9] * n.y + inv[10] * n.z};
            out.wedges.normal[w] = normalize(n);
        }
        if (!out.wedges.tangent.empty()) {
            const Vec4& t = W.tangent[w];
            Vec3 d = normalize(transformVector(m, morphedVector(Vec3{t.x, t.y, t.z}, w, true)));
            out.wedges.tangent[w] = {d.x, d.y, d.z, t.w};
        }
    }
    return out;
}

}  // namespace lodbake
