// Morph targets read into the flattened asset (lodbake/core/morph.h states what holds).
#include "gltf/morph_read.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <tiny_gltf.h>

#include "gltf/rig_read.h"
#include "lodbake/core/pose.h"

namespace lodbake::gltf_detail {
namespace {

Vec3 applyCofactor(const std::array<double, 9>& C, Vec3 a) {
    return {C[0] * a.x + C[1] * a.y + C[2] * a.z, C[3] * a.x + C[4] * a.y + C[5] * a.z, C[6] * a.x + C[7] * a.y + C[8] * a.z};
}

// A delta of a unit vector scales like the vector: the base reaches unit length in the world frame
// by dividing by its transformed length, so the transformed delta is divided by the same length.
Vec3 scaledDelta(Vec3 transformedDelta, Vec3 transformedBase) {
    const double l = length(transformedBase);
    return l > 0 ? transformedDelta * (1 / l) : transformedDelta;
}

}  // namespace

NodeFrame nodeFrame(const Mat4& world) {
    NodeFrame f;
    f.world = world;
    f.sign = det3(world) < 0 ? -1.0 : 1.0;
    // Cofactor matrix of the upper 3x3: (M^-1)^T = C / det.
    auto M = [&](int r, int c) { return world[size_t(c * 4 + r)]; };
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            f.cofactor[size_t(r * 3 + c)] = M((r + 1) % 3, (c + 1) % 3) * M((r + 2) % 3, (c + 2) % 3) -
                                            M((r + 1) % 3, (c + 2) % 3) * M((r + 2) % 3, (c + 1) % 3);
    return f;
}

MorphLayout morphLayout(const ReadContext& c, const std::vector<std::pair<int, Mat4>>& nodes) {
    const tinygltf::Model& m = *c.model;
    MorphLayout L;
    for (const auto& [n, world] : nodes) {
        const tinygltf::Node& node = m.nodes[size_t(n)];
        if (node.mesh < 0 || size_t(node.mesh) >= m.meshes.size()) continue;
        const tinygltf::Mesh& mesh = m.meshes[size_t(node.mesh)];
        size_t count = 0;
        for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
            const size_t t = mesh.primitives[pi].targets.size();
            if (pi > 0 && t != count)
                fail(c, "mesh " + std::to_string(node.mesh) + ": its primitives have different numbers of morph targets");
            count = t;
        }
        if (count == 0) continue;
        const std::vector<double>& weights = !node.weights.empty() ? node.weights : mesh.weights;
        if (!weights.empty() && weights.size() != count)
            fail(c, "node " + std::to_string(n) + ": " + std::to_string(weights.size()) + " morph weights for " + std::to_string(count) +
                        " targets");
        std::vector<std::string> names;
        if (mesh.extras.IsObject() && mesh.extras.Has("targetNames") && mesh.extras.Get("targetNames").IsArray()) {
            const tinygltf::Value& v = mesh.extras.Get("targetNames");
            for (size_t k = 0; k < v.ArrayLen(); ++k) names.push_back(v.Get(int(k)).IsString() ? v.Get(int(k)).Get<std::string>() : "");
        }
        L.first[n] = L.targets.size();
        L.count[n] = count;
        for (size_t k = 0; k < count; ++k) {
            L.targets.names.push_back(k < names.size() ? names[k] : std::string());
            L.targets.weights.push_back(weights.empty() ? 0.0 : weights[k]);
        }
    }
    return L;
}

void storeWedgeDeltas(const MorphLayout& layout, int node, const PrimData& p, size_t i, const NodeFrame& frame, Wedges& W, size_t w) {
    auto it = layout.first.find(node);
    if (it == layout.first.end()) return;
    for (size_t k = 0; k < p.targets.size() && k < layout.count.at(node); ++k) {
        const PrimData::Target& t = p.targets[k];
        MorphDeltas& D = W.targets[it->second + k];
        D.position[w] = transformVector(frame.world, t.position[i]);
        if (!t.normal.empty()) {
            if (D.normal.empty()) D.normal.assign(W.vertex.size(), Vec3{0, 0, 0});
            const Vec3 base = p.normal.empty() ? Vec3{0, 0, 1} : p.normal[i];
            D.normal[w] = scaledDelta(applyCofactor(frame.cofactor, t.normal[i]) * frame.sign, applyCofactor(frame.cofactor, base));
        }
        if (!t.tangent.empty()) {
            if (D.tangent.empty()) D.tangent.assign(W.vertex.size(), Vec3{0, 0, 0});
            const Vec3 base = p.tangent.empty() ? Vec3{1, 0, 0} : Vec3{p.tangent[i].x, p.tangent[i].y, p.tangent[i].z};
            D.tangent[w] = scaledDelta(transformVector(frame.world, t.tangent[i]), transformVector(frame.world, base));
        }
    }
}

void appendWedgeDeltas(const MorphLayout& layout, int node, const PrimData& p, size_t i, const NodeFrame& frame, Wedges& W) {
    const size_t n = W.vertex.size();
    for (MorphDeltas& D : W.targets) {
        D.position.resize(n, Vec3{0, 0, 0});
        if (!D.normal.empty()) D.normal.resize(n, Vec3{0, 0, 0});
        if (!D.tangent.empty()) D.tangent.resize(n, Vec3{0, 0, 0});
    }
    storeWedgeDeltas(layout, node, p, i, frame, W, n - 1);
}

void mergeWeightChannels(const ReadContext& c, const MorphLayout& layout, size_t ai, const tinygltf::Animation& a,
                         const std::vector<std::pair<int, int>>& channels, Animation& out, Asset& asset) {
    struct Part {
        size_t first = 0;
        AnimationSampler sampler;
    };
    std::vector<Part> parts;
    for (const auto& [node, sampler] : channels) {
        auto it = layout.first.find(node);
        if (it == layout.first.end()) continue;
        if (sampler < 0 || size_t(sampler) >= a.samplers.size())
            fail(c, "animation " + std::to_string(ai) + ": sampler " + std::to_string(sampler) + " does not exist");
        parts.push_back({it->second, readSampler(c, a.samplers[size_t(sampler)], int(layout.count.at(node)),
                                                 "animation " + std::to_string(ai) + " sampler " + std::to_string(sampler), true)});
    }
    if (parts.empty()) return;
    AnimationChannel ch;
    ch.node = -1;
    ch.path = AnimationPath::Weights;
    ch.sampler = int(out.samplers.size());
    if (parts.size() == 1 && parts[0].first == 0 && size_t(parts[0].sampler.comps) == layout.size()) {
        out.samplers.push_back(std::move(parts[0].sampler));
        out.channels.push_back(ch);
        return;
    }
    const Interpolation mode = parts[0].sampler.interpolation;
    for (const Part& p : parts)
        if (p.sampler.interpolation != mode || mode == Interpolation::CubicSpline) {
            asset.warnings.push_back("animation " + std::to_string(ai) +
                                     ": morph weights of several meshes with CUBICSPLINE or mixed interpolation dropped");
            return;
        }
    std::set<double> times;
    for (const Part& p : parts) times.insert(p.sampler.times.begin(), p.sampler.times.end());
    AnimationSampler merged;
    merged.comps = int(layout.size());
    merged.interpolation = mode;
    merged.times.assign(times.begin(), times.end());
    std::vector<double> value(layout.size());
    for (double t : merged.times) {
        value = layout.targets.weights;
        for (const Part& p : parts) sampleAnimation(p.sampler, t, false, value.data() + p.first);
        merged.values.insert(merged.values.end(), value.begin(), value.end());
    }
    out.samplers.push_back(std::move(merged));
    out.channels.push_back(ch);
}

}  // namespace lodbake::gltf_detail
