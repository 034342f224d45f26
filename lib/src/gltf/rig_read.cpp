// Skins, the joint hierarchy and node animations of a glTF, merged into one Rig for the
// flattened mesh (lodbake/core/rig.h states the invariant this keeps).
#include "gltf/rig_read.h"

#include "gltf/morph_read.h"

#include <algorithm>
#include <set>

#include <tiny_gltf.h>

#include "lodbake/core/errors.h"
#include "lodbake/core/pose.h"

namespace lodbake::gltf_detail {
namespace {

RigNode rigNodeOf(const tinygltf::Node& n) {
    RigNode r;
    r.name = n.name;
    if (n.matrix.size() == 16) {
        r.hasMatrix = true;
        for (size_t i = 0; i < 16; ++i) r.matrix[i] = n.matrix[i];
    }
    if (n.translation.size() == 3) r.translation = {n.translation[0], n.translation[1], n.translation[2]};
    if (n.rotation.size() == 4) r.rotation = {n.rotation[0], n.rotation[1], n.rotation[2], n.rotation[3]};
    if (n.scale.size() == 3) r.scale = {n.scale[0], n.scale[1], n.scale[2]};
    return r;
}

}  // namespace

AnimationSampler readSampler(const ReadContext& c, const tinygltf::AnimationSampler& s, int comps, const std::string& what, bool scalarOutput) {
    AnimationSampler out;
    out.comps = comps;
    out.interpolation = s.interpolation == "STEP" ? Interpolation::Step
                        : s.interpolation == "CUBICSPLINE" ? Interpolation::CubicSpline
                                                           : Interpolation::Linear;
    std::vector<float> times = readF32(c, s.input, 1, what + " input");
    std::vector<float> values = readF32(c, s.output, scalarOutput ? 1 : comps, what + " output");
    const size_t per = out.interpolation == Interpolation::CubicSpline ? 3 : 1;
    if (times.empty() || values.size() != times.size() * per * size_t(comps))
        fail(c, what + ": " + std::to_string(values.size() / size_t(comps)) + " output values for " + std::to_string(times.size()) +
                    " key times");
    for (size_t i = 1; i < times.size(); ++i)
        if (!(times[i] > times[i - 1])) fail(c, what + ": key times are not increasing");
    out.times.assign(times.begin(), times.end());
    out.values.assign(values.begin(), values.end());
    return out;
}

namespace {

// The translation / rotation / scale animations of the rig nodes (glTF node -> rig node in
// `rigIndex`) and the morph weights of the union of `layout`, into rig.animations.
void readAnimations(const ReadContext& c, std::map<int, int>& rigIndex, const MorphLayout& layout, RigRead& rr, Asset& asset) {
    Rig& rig = rr.rig;
    const tinygltf::Model& m = *c.model;
    for (size_t ai = 0; ai < m.animations.size(); ++ai) {
        const tinygltf::Animation& a = m.animations[ai];
        Animation out;
        out.name = a.name;
        std::map<int, int> samplerIndex;
        std::vector<std::pair<int, int>> weights;  // (node, sampler) of the weights channels
        for (const auto& ch : a.channels) {
            const std::string& path = ch.target_path;
            if (path == "weights") weights.emplace_back(ch.target_node, ch.sampler);
            if (path != "translation" && path != "rotation" && path != "scale") continue;
            if (!rigIndex.count(ch.target_node)) continue;
            if (ch.sampler < 0 || size_t(ch.sampler) >= a.samplers.size())
                fail(c, "animation " + std::to_string(ai) + ": sampler " + std::to_string(ch.sampler) + " does not exist");
            AnimationChannel oc;
            oc.node = rigIndex[ch.target_node];
            oc.path = path == "translation" ? AnimationPath::Translation : path == "rotation" ? AnimationPath::Rotation : AnimationPath::Scale;
            auto [it, inserted] = samplerIndex.emplace(ch.sampler, int(out.samplers.size()));
            if (inserted)
                out.samplers.push_back(readSampler(c, a.samplers[size_t(ch.sampler)], oc.path == AnimationPath::Rotation ? 4 : 3,
                                                   "animation " + std::to_string(ai) + " sampler " + std::to_string(ch.sampler)));
            else if (out.samplers[size_t(it->second)].comps != (oc.path == AnimationPath::Rotation ? 4 : 3))
                fail(c, "animation " + std::to_string(ai) + ": sampler " + std::to_string(ch.sampler) + " drives paths of different types");
            oc.sampler = it->second;
            out.channels.push_back(oc);
        }
        mergeWeightChannels(c, layout, ai, a, weights, out, asset);
        if (out.channels.empty()) continue;
        rig.animations.push_back(std::move(out));
        rr.animationSource.push_back(int(ai));
    }
}

}  // namespace

RigRead readRig(const ReadContext& c, const std::vector<std::pair<int, Mat4>>& nodes, const MorphLayout& layout, Asset& asset) {
    const tinygltf::Model& m = *c.model;
    RigRead rr;
    std::vector<int> parent(m.nodes.size(), -1);
    for (size_t i = 0; i < m.nodes.size(); ++i)
        for (int ch : m.nodes[i].children)
            if (ch >= 0 && size_t(ch) < m.nodes.size()) parent[size_t(ch)] = int(i);
    std::map<int, Mat4> world(nodes.begin(), nodes.end());
    auto validNode = [&](int n) { return n >= 0 && size_t(n) < m.nodes.size(); };

    // Which mesh nodes move: skinned ones, and those below an animated node.
    std::set<int> animated;
    for (const auto& a : m.animations)
        for (const auto& ch : a.channels) {
            if (ch.target_path == "weights") continue;
            if (validNode(ch.target_node) && world.count(ch.target_node)) animated.insert(ch.target_node);
        }
    bool moving = false;
    for (const auto& [n, w] : nodes) {
        const tinygltf::Node& node = m.nodes[size_t(n)];
        if (node.mesh < 0) continue;
        if (node.skin >= 0) {
            if (size_t(node.skin) >= m.skins.size()) fail(c, "node " + std::to_string(n) + ": skin " + std::to_string(node.skin) + " does not exist");
            moving = true;
        }
        for (int a = n; a >= 0 && !moving; a = parent[size_t(a)]) moving = animated.count(a) > 0;
    }
    if (!moving) {
        if (!m.animations.empty() && !animated.empty()) asset.warnings.push_back("animations dropped: they move no mesh");
        std::map<int, int> noNodes;
        readAnimations(c, noNodes, layout, rr, asset);  // morph weights only
        return rr;
    }

    // Rig nodes: joints, animation targets, unskinned mesh nodes and their ancestors; parents
    // before children (by depth, then glTF index).
    std::set<int> members(animated.begin(), animated.end());
    for (const auto& [n, w] : nodes) {
        const tinygltf::Node& node = m.nodes[size_t(n)];
        if (node.mesh < 0) continue;
        if (node.skin < 0) { members.insert(n); continue; }
        for (int j : m.skins[size_t(node.skin)].joints) {
            if (!validNode(j)) fail(c, "skin " + std::to_string(node.skin) + ": joint node " + std::to_string(j) + " does not exist");
            members.insert(j);
        }
    }
    for (int n : std::vector<int>(members.begin(), members.end()))
        for (int a = parent[size_t(n)], guard = 0; a >= 0 && guard <= int(m.nodes.size()); a = parent[size_t(a)], ++guard) members.insert(a);
    auto depth = [&](int n) {
        int d = 0;
        for (int a = parent[size_t(n)]; a >= 0 && d <= int(m.nodes.size()); a = parent[size_t(a)]) ++d;
        return d;
    };
    std::vector<std::pair<int, int>> order;
    for (int n : members) order.emplace_back(depth(n), n);
    std::sort(order.begin(), order.end());
    std::map<int, int> rigIndex;
    Rig& rig = rr.rig;
    for (const auto& [d, n] : order) {
        rigIndex[n] = int(rig.nodes.size());
        rig.nodes.push_back(rigNodeOf(m.nodes[size_t(n)]));
        rr.nodeSource.push_back(n);
    }
    for (const auto& [d, n] : order) {
        const int p = parent[size_t(n)];
        rig.nodes[size_t(rigIndex[n])].parent = p >= 0 && rigIndex.count(p) ? rigIndex[p] : -1;
    }

    // The unified skin: one joint per distinct (node, inverse bind in the flattened frame).
    std::map<std::pair<int, Mat4>, uint16_t> jointOf;
    auto joint = [&](int node, const Mat4& inverseBind) {
        auto [it, inserted] = jointOf.emplace(std::make_pair(rigIndex.at(node), inverseBind), uint16_t(rig.joints.size()));
        if (inserted) {
            if (rig.joints.size() >= 65535) fail(c, "more than 65535 joints over all skins");
            rig.joints.push_back(rigIndex.at(node));
            rig.inverseBind.push_back(inverseBind);
        }
        return it->second;
    };
    size_t singular = 0;
    for (const auto& [n, w] : nodes) {
        const tinygltf::Node& node = m.nodes[size_t(n)];
        if (node.mesh < 0) continue;
        Mat4 unflatten = identity4();  // M^-1: from the flattened frame back to the mesh node's
        if (!invertAffine(w, unflatten)) singular++;
        NodeInfluence& b = rr.meshNodes[n];
        if (node.skin < 0) {
            b.rigid = joint(n, unflatten);
            continue;
        }
        const tinygltf::Skin& skin = m.skins[size_t(node.skin)];
        const std::string what = "skin " + std::to_string(node.skin);
        if (skin.joints.empty()) fail(c, what + ": no joints");
        std::vector<float> ibm = readF32(c, skin.inverseBindMatrices, 16, what + " inverseBindMatrices");
        if (!ibm.empty() && ibm.size() != 16 * skin.joints.size()) fail(c, what + ": inverseBindMatrices count differs from the joints");
        b.skinned = true;
        for (size_t k = 0; k < skin.joints.size(); ++k) {
            Mat4 inverseBind = identity4();
            if (!ibm.empty())
                for (size_t e = 0; e < 16; ++e) inverseBind[e] = ibm[16 * k + e];
            b.joint.push_back(joint(skin.joints[k], mul(inverseBind, unflatten)));
        }
    }
    if (singular) asset.warnings.push_back(std::to_string(singular) + " mesh nodes with a singular transform bound with identity inverse bind matrices");

    readAnimations(c, rigIndex, layout, rr, asset);
    return rr;
}

void primitiveInfluences(const ReadContext& c, const PrimData& p, const NodeInfluence& b, RigRead& rr,
                         std::vector<std::array<uint16_t, 4>>& joints, std::vector<Vec4>& weights, const std::string& what) {
    const size_t n = p.pos.size(), per = 4 * size_t(p.influenceSets);
    if (!b.skinned || per == 0) {
        if (b.skinned) rr.unweighted += n;
        const uint16_t j = b.skinned ? b.joint.front() : b.rigid;
        joints.insert(joints.end(), n, std::array<uint16_t, 4>{j, 0, 0, 0});
        weights.insert(weights.end(), n, Vec4{1, 0, 0, 0});
        return;
    }
    std::vector<std::pair<double, uint16_t>> all;
    for (size_t i = 0; i < n; ++i) {
        all.clear();
        for (size_t k = 0; k < per; ++k) {
            const double w = p.weights[i * per + k];
            if (!(w > 0)) continue;
            const uint32_t sj = p.joints[i * per + k];
            if (sj >= b.joint.size()) fail(c, what + ": joint " + std::to_string(sj) + " beyond its skin's " + std::to_string(b.joint.size()) + " joints");
            const uint16_t u = b.joint[sj];
            auto same = std::find_if(all.begin(), all.end(), [&](const auto& e) { return e.second == u; });
            if (same != all.end()) same->first += w;
            else all.emplace_back(w, u);
        }
        // Largest weight first; equal weights by joint, so the choice never depends on slot order.
        std::sort(all.begin(), all.end(), [](const auto& x, const auto& y) { return x.first != y.first ? x.first > y.first : x.second < y.second; });
        if (all.size() > 4) { rr.truncated++; all.resize(4); }
        double sum = 0;
        for (const auto& e : all) sum += e.first;
        std::array<uint16_t, 4> j{0, 0, 0, 0};
        double w[4] = {0, 0, 0, 0};
        if (all.empty() || !(sum > 0)) {
            j[0] = b.joint.front();
            w[0] = 1;
        } else {
            for (size_t k = 0; k < all.size(); ++k) { j[k] = all[k].second; w[k] = all[k].first / sum; }
        }
        joints.push_back(j);
        weights.push_back({w[0], w[1], w[2], w[3]});
    }
}

std::vector<std::string> influenceWarnings(const RigRead& rr) {
    std::vector<std::string> out;
    if (rr.truncated)
        out.push_back(std::to_string(rr.truncated) + " vertices had more than 4 joint influences: the 4 largest kept, renormalised");
    if (rr.unweighted)
        out.push_back(std::to_string(rr.unweighted) + " vertices of skinned meshes have no JOINTS_0: bound to their skin's first joint");
    return out;
}

}  // namespace lodbake::gltf_detail
