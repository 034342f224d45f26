// Writing a Rig and per-vertex influences into a glTF (rig_write.h).
#include "gltf/rig_write.h"

#include "gltf/gltf_internal.h"

namespace lodbake::gltf_detail {

using json = nlohmann::json;

std::vector<int> writeRig(BufferBuilder& b, json& root, json& nodes, const Rig& rig, const std::vector<int>& morphNodes) {
    const int first = int(nodes.size());
    std::vector<int> roots;
    if (rig.empty()) {
        writeAnimations(b, root, rig, -1, morphNodes);
        return roots;
    }
    std::vector<json> written(rig.nodes.size());
    for (size_t i = 0; i < rig.nodes.size(); ++i) {
        const RigNode& n = rig.nodes[i];
        json o = json::object();
        if (!n.name.empty()) o["name"] = n.name;
        if (n.hasMatrix) {
            if (n.matrix != identity4()) o["matrix"] = n.matrix;
        } else {
            if (n.translation.x != 0 || n.translation.y != 0 || n.translation.z != 0)
                o["translation"] = {n.translation.x, n.translation.y, n.translation.z};
            if (n.rotation.x != 0 || n.rotation.y != 0 || n.rotation.z != 0 || n.rotation.w != 1)
                o["rotation"] = {n.rotation.x, n.rotation.y, n.rotation.z, n.rotation.w};
            if (n.scale.x != 1 || n.scale.y != 1 || n.scale.z != 1) o["scale"] = {n.scale.x, n.scale.y, n.scale.z};
        }
        written[i] = o;
        if (n.parent >= 0 && size_t(n.parent) < i) written[size_t(n.parent)]["children"].push_back(first + int(i));
        else roots.push_back(first + int(i));
    }
    for (json& o : written) nodes.push_back(std::move(o));

    std::vector<float> ibm;
    ibm.reserve(16 * rig.inverseBind.size());
    for (const Mat4& m : rig.inverseBind)
        for (double e : m) ibm.push_back(float(e));
    const int ibmView = b.addView(ibm.data(), ibm.size() * 4, 0);
    const int ibmAccessor = b.addAccessor({{"bufferView", ibmView}, {"componentType", kFloat}, {"count", rig.inverseBind.size()}, {"type", "MAT4"}});
    json joints = json::array();
    for (int j : rig.joints) joints.push_back(first + j);
    root["skins"] = json::array({json{{"joints", joints}, {"inverseBindMatrices", ibmAccessor}}});
    writeAnimations(b, root, rig, first, morphNodes);
    return roots;
}

void writeAnimations(BufferBuilder& b, json& root, const Rig& rig, int first, const std::vector<int>& morphNodes) {
    json animations = json::array();
    for (const Animation& a : rig.animations) {
        json samplers = json::array(), channels = json::array();
        std::vector<char> weights(a.samplers.size(), 0);  // morph weights are stored as SCALAR outputs
        for (const AnimationChannel& ch : a.channels)
            if (ch.path == AnimationPath::Weights && ch.sampler >= 0 && size_t(ch.sampler) < weights.size()) weights[size_t(ch.sampler)] = 1;
        for (size_t si = 0; si < a.samplers.size(); ++si) {
            const AnimationSampler& s = a.samplers[si];
            std::vector<float> times(s.times.begin(), s.times.end()), values(s.values.begin(), s.values.end());
            const char* interpolation = s.interpolation == Interpolation::Step ? "STEP" : s.interpolation == Interpolation::CubicSpline ? "CUBICSPLINE" : "LINEAR";
            samplers.push_back({{"input", b.addFloat(times, 1, 0, true)}, {"output", b.addFloat(values, weights[si] ? 1 : s.comps, 0, false)},
                                {"interpolation", interpolation}});
        }
        for (const AnimationChannel& ch : a.channels) {
            if (ch.path == AnimationPath::Weights) {
                // One channel per mesh node, all sharing the sampler: the levels morph together.
                for (int n : morphNodes) channels.push_back({{"sampler", ch.sampler}, {"target", {{"node", n}, {"path", "weights"}}}});
                continue;
            }
            if (first < 0) continue;
            const char* path = ch.path == AnimationPath::Translation ? "translation" : ch.path == AnimationPath::Rotation ? "rotation" : "scale";
            channels.push_back({{"sampler", ch.sampler}, {"target", {{"node", first + ch.node}, {"path", path}}}});
        }
        if (channels.empty()) continue;
        json o = {{"samplers", samplers}, {"channels", channels}};
        if (!a.name.empty()) o["name"] = a.name;
        animations.push_back(o);
    }
    if (!animations.empty()) root["animations"] = animations;
}

void appendWeightChannels(BufferBuilder& b, json& animation, const Animation& a, const std::vector<int>& morphNodes) {
    std::vector<int> written(a.samplers.size(), -1);  // rig sampler -> index in `animation`
    for (const AnimationChannel& ch : a.channels) {
        if (ch.path != AnimationPath::Weights || ch.sampler < 0 || size_t(ch.sampler) >= a.samplers.size()) continue;
        int& index = written[size_t(ch.sampler)];
        if (index < 0) {
            const AnimationSampler& s = a.samplers[size_t(ch.sampler)];
            std::vector<float> times(s.times.begin(), s.times.end()), values(s.values.begin(), s.values.end());
            const char* interpolation = s.interpolation == Interpolation::Step ? "STEP" : s.interpolation == Interpolation::CubicSpline ? "CUBICSPLINE" : "LINEAR";
            index = int(animation["samplers"].size());
            animation["samplers"].push_back({{"input", b.addFloat(times, 1, 0, true)}, {"output", b.addFloat(values, 1, 0, false)},
                                             {"interpolation", interpolation}});
        }
        for (int n : morphNodes) animation["channels"].push_back({{"sampler", index}, {"target", {{"node", n}, {"path", "weights"}}}});
    }
}

void addMorphTargets(BufferBuilder& b, json& primitive, const std::vector<std::vector<float>>& position,
                     const std::vector<std::vector<float>>& normal, const std::vector<std::vector<float>>& tangent) {
    if (position.empty()) return;
    json targets = json::array();
    for (size_t t = 0; t < position.size(); ++t) {
        json o = {{"POSITION", b.addFloat(position[t], 3, kArrayBuffer, true)}};
        if (t < normal.size() && !normal[t].empty()) o["NORMAL"] = b.addFloat(normal[t], 3, kArrayBuffer, false);
        if (t < tangent.size() && !tangent[t].empty()) o["TANGENT"] = b.addFloat(tangent[t], 3, kArrayBuffer, false);
        targets.push_back(o);
    }
    primitive["targets"] = targets;
}

void addMorphDefaults(json& mesh, const MorphTargets& morph) {
    if (morph.empty()) return;
    mesh["weights"] = morph.weights;
    bool named = false;
    for (const std::string& n : morph.names) named |= !n.empty();
    if (named) mesh["extras"]["targetNames"] = morph.names;
}

void addInfluences(BufferBuilder& b, json& attributes, const std::vector<uint16_t>& joints, const std::vector<float>& weights) {
    if (joints.empty()) return;
    const int view = b.addView(joints.data(), joints.size() * 2, kArrayBuffer);
    attributes["JOINTS_0"] = b.addAccessor({{"bufferView", view}, {"componentType", kUnsignedShort}, {"count", joints.size() / 4}, {"type", "VEC4"}});
    attributes["WEIGHTS_0"] = b.addFloat(weights, 4, kArrayBuffer, false);
}

}  // namespace lodbake::gltf_detail
