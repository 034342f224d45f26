#include "gltf/rig_write.h"

#include "gltf/gltf_internal.h"

namespace lodbake::gltf_detail {

using json = nlohmann::json;

std::vector<int> writeRig(BufferBuilder& b, json& root, json& nodes, const Rig& rig) {
    const int first = int(nodes.size());
    std::vector<int> roots;
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

    if (rig.animations.empty()) return roots;
    json animations = json::array();
    for (const Animation& a : rig.animations) {
        json samplers = json::array(), channels = json::array();
        for (const AnimationSampler& s : a.samplers) {
            std::vector<float> times(s.times.begin(), s.times.end()), values(s.values.begin(), s.values.end());
            const char* interpolation = s.interpolation == Interpolation::Step ? "STEP" : s.interpolation == Interpolation::CubicSpline ? "CUBICSPLINE" : "LINEAR";
            samplers.push_back({{"input", b.addFloat(times, 1, 0, true)}, {"output", b.addFloat(values, s.comps, 0, false)},
                                {"interpolation", interpolation}});
        }
        for (const AnimationChannel& ch : a.channels) {
            const char* path = ch.path == AnimationPath::Translation ? "translation" : ch.path == AnimationPath::Rotation ? "rotation" : "scale";
            channels.push_back({{"sampler", ch.sampler}, {"target", {{"node", first + ch.node}, {"path", path}}}});
        }
        json o = {{"samplers", samplers}, {"channels", channels}};
        if (!a.name.empty()) o["name"] = a.name;
        animations.push_back(o);
    }
    root["animations"] = animations;
    return roots;
}

void addInfluences(BufferBuilder& b, json& attributes, const std::vector<uint16_t>& joints, const std::vector<float>& weights) {
    if (joints.empty()) return;
    const int view = b.addView(joints.data(), joints.size() * 2, kArrayBuffer);
    attributes["JOINTS_0"] = b.addAccessor({{"bufferView", view}, {"componentType", kUnsignedShort}, {"count", joints.size() / 4}, {"type", "VEC4"}});
    attributes["WEIGHTS_0"] = b.addFloat(weights, 4, kArrayBuffer, false);
}

}  // namespace lodbake::gltf_detail
