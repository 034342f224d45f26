// Lights, cameras, their nodes and extras: read from a glTF's JSON, written into one
// (scene_extras_codec.h). The JSON is nlohmann's (sorted keys), so the output is the same bytes for
// the same SceneExtras.

#include "gltf/scene_extras_codec.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <tiny_gltf.h>

namespace lodbake::gltf_detail {
namespace {

using json = nlohmann::json;

constexpr const char* kLights = "KHR_lights_punctual";

// Root extensions whose content reaches the output: lights here, LODBAKE_multires and
// KHR_materials_variants by their codecs.
const std::vector<std::string> kCarriedRootExtensions = {kLights, "LODBAKE_multires", "KHR_materials_variants"};
// Node extensions the reader uses: lights here, instancing expanded by the reader, MSFT_lod (a
// chain read as input: its levels are nodes of their own).
const std::vector<std::string> kReadNodeExtensions = {kLights, "EXT_mesh_gpu_instancing", "MSFT_lod"};

double number(const json& o, const char* key, double def) {
    return o.is_object() && o.contains(key) && o[key].is_number() ? o[key].get<double>() : def;
}

std::string text(const json& o, const char* key) {
    return o.is_object() && o.contains(key) && o[key].is_string() ? o[key].get<std::string>() : std::string();
}

SceneLight readLight(const ReadContext& c, const json& l, size_t index) {
    SceneLight light;
    const std::string what = "KHR_lights_punctual light " + std::to_string(index);
    if (!l.is_object()) fail(c, what + " is not an object");
    light.name = text(l, "name");
    const std::string type = text(l, "type");
    if (type == "directional") light.type = SceneLight::Type::Directional;
    else if (type == "point") light.type = SceneLight::Type::Point;
    else if (type == "spot") light.type = SceneLight::Type::Spot;
    else fail(c, what + ": unknown type '" + type + "'");
    if (l.contains("color") && l["color"].is_array() && l["color"].size() == 3)
        light.color = {l["color"][0].get<double>(), l["color"][1].get<double>(), l["color"][2].get<double>()};
    light.intensity = number(l, "intensity", 1);
    light.range = std::max(number(l, "range", 0), 0.0);
    if (light.type == SceneLight::Type::Spot && l.contains("spot")) {
        light.innerConeAngle = number(l["spot"], "innerConeAngle", light.innerConeAngle);
        light.outerConeAngle = number(l["spot"], "outerConeAngle", light.outerConeAngle);
    }
    return light;
}

SceneCamera readCamera(const ReadContext& c, const json& o, size_t index) {
    SceneCamera cam;
    const std::string what = "camera " + std::to_string(index);
    if (!o.is_object()) fail(c, what + " is not an object");
    cam.name = text(o, "name");
    const std::string type = text(o, "type");
    if (type == "perspective" && o.contains("perspective")) {
        const json& p = o["perspective"];
        cam.type = SceneCamera::Type::Perspective;
        cam.aspectRatio = std::max(number(p, "aspectRatio", 0), 0.0);
        cam.yfov = number(p, "yfov", cam.yfov);
        cam.znear = number(p, "znear", cam.znear);
        cam.zfar = std::max(number(p, "zfar", 0), 0.0);
    } else if (type == "orthographic" && o.contains("orthographic")) {
        const json& p = o["orthographic"];
        cam.type = SceneCamera::Type::Orthographic;
        cam.xmag = number(p, "xmag", cam.xmag);
        cam.ymag = number(p, "ymag", cam.ymag);
        cam.znear = number(p, "znear", 0);
        cam.zfar = number(p, "zfar", 1);
    } else {
        fail(c, what + ": type '" + type + "' without its parameters");
    }
    return cam;
}

// Nodes whose translation, rotation or scale an animation drives (a weights channel moves none).
std::set<int> animatedNodes(const ReadContext& c) {
    std::set<int> out;
    if (!c.root.contains("animations") || !c.root["animations"].is_array()) return out;
    for (const json& a : c.root["animations"]) {
        if (!a.is_object() || !a.contains("channels") || !a["channels"].is_array()) continue;
        for (const json& ch : a["channels"]) {
            if (!ch.is_object() || !ch.contains("target") || !ch["target"].is_object()) continue;
            const json& t = ch["target"];
            const std::string path = text(t, "path");
            if (path != "weights" && t.contains("node") && t["node"].is_number_integer()) out.insert(t["node"].get<int>());
        }
    }
    return out;
}

json lightJson(const SceneLight& l) {
    static const char* kTypes[] = {"directional", "point", "spot"};
    json o = {{"type", kTypes[int(l.type)]}};
    if (!l.name.empty()) o["name"] = l.name;
    if (l.color.x != 1 || l.color.y != 1 || l.color.z != 1) o["color"] = {l.color.x, l.color.y, l.color.z};
    if (l.intensity != 1) o["intensity"] = l.intensity;
    if (l.range > 0 && l.type != SceneLight::Type::Directional) o["range"] = l.range;
    if (l.type == SceneLight::Type::Spot) o["spot"] = {{"innerConeAngle", l.innerConeAngle}, {"outerConeAngle", l.outerConeAngle}};
    return o;
}

json cameraJson(const SceneCamera& c) {
    json o;
    if (!c.name.empty()) o["name"] = c.name;
    if (c.type == SceneCamera::Type::Perspective) {
        json p = {{"yfov", c.yfov}, {"znear", c.znear}};
        if (c.aspectRatio > 0) p["aspectRatio"] = c.aspectRatio;
        if (c.zfar > 0) p["zfar"] = c.zfar;
        o["type"] = "perspective";
        o["perspective"] = p;
    } else {
        o["type"] = "orthographic";
        o["orthographic"] = {{"xmag", c.xmag}, {"ymag", c.ymag}, {"znear", c.znear}, {"zfar", c.zfar}};
    }
    return o;
}

}  // namespace

SceneExtras readSceneExtras(const ReadContext& c, const std::vector<std::pair<int, Mat4>>& nodes,
                            std::vector<std::string>& warnings) {
    SceneExtras s;
    const json& root = c.root;
    const json* ext = root.contains("extensions") && root["extensions"].is_object() ? &root["extensions"] : nullptr;
    if (ext && ext->contains(kLights) && (*ext)[kLights].is_object() && (*ext)[kLights].contains("lights") &&
        (*ext)[kLights]["lights"].is_array())
        for (const json& l : (*ext)[kLights]["lights"]) s.lights.push_back(readLight(c, l, s.lights.size()));
    if (root.contains("cameras") && root["cameras"].is_array())
        for (const json& cam : root["cameras"]) s.cameras.push_back(readCamera(c, cam, s.cameras.size()));

    // Placements, in the flattened scene's order. A node below an animated one is placed at rest.
    const std::set<int> animated = animatedNodes(c);
    const tinygltf::Model& m = *c.model;
    std::vector<int> parent(m.nodes.size(), -1);
    for (size_t i = 0; i < m.nodes.size(); ++i)
        for (int ch : m.nodes[i].children)
            if (ch >= 0 && size_t(ch) < m.nodes.size()) parent[size_t(ch)] = int(i);
    for (const auto& [n, world] : nodes) {
        // Every node of `nodes` exists (flattening checked it), in the JSON as in the model.
        const json& node = root.at("nodes").at(size_t(n));
        if (node.contains("extensions") && node["extensions"].is_object())
            for (const auto& [name, value] : node["extensions"].items())
                if (std::find(kReadNodeExtensions.begin(), kReadNodeExtensions.end(), name) == kReadNodeExtensions.end())
                    warnings.push_back("node " + std::to_string(n) + ": extension " + name + " is not carried to the output");
        ScenePlacement p;
        p.camera = node.contains("camera") && node["camera"].is_number_integer() ? node["camera"].get<int>() : -1;
        if (node.contains("extensions") && node["extensions"].is_object() && node["extensions"].contains(kLights)) {
            const json& l = node["extensions"][kLights];
            p.light = l.is_object() && l.contains("light") && l["light"].is_number_integer() ? l["light"].get<int>() : -2;
        }
        if (p.camera < -1 || p.camera >= int(s.cameras.size()))
            fail(c, "node " + std::to_string(n) + ": camera " + std::to_string(p.camera) + " does not exist");
        if (p.light < -1 || p.light >= int(s.lights.size()))
            fail(c, "node " + std::to_string(n) + ": KHR_lights_punctual light " + std::to_string(p.light) + " does not exist");
        if (p.camera < 0 && p.light < 0) continue;
        p.name = text(node, "name");
        p.world = world;
        for (int a = n, guard = 0; a >= 0 && guard <= int(m.nodes.size()); a = parent[size_t(a)], ++guard)
            if (animated.count(a)) {
                warnings.push_back("node " + std::to_string(n) + (p.name.empty() ? "" : " '" + p.name + "'") + ": the " +
                                   (p.light >= 0 ? "light" : "camera") + " below animated node " + std::to_string(a) +
                                   " keeps its rest transform (its animation is not carried)");
                break;
            }
        s.placements.push_back(std::move(p));
    }

    // Extras: the root's, its asset's and the default scene's (or scene 0's), kept as JSON text.
    if (root.contains("extras")) s.rootExtras = root["extras"].dump();
    if (root.contains("asset") && root["asset"].is_object() && root["asset"].contains("extras"))
        s.assetExtras = root["asset"]["extras"].dump();
    const int scene = m.defaultScene >= 0 ? m.defaultScene : (m.scenes.empty() ? -1 : 0);
    if (scene >= 0 && root.contains("scenes") && root["scenes"].is_array() && size_t(scene) < root["scenes"].size() &&
        root["scenes"][size_t(scene)].is_object() && root["scenes"][size_t(scene)].contains("extras"))
        s.sceneExtras = root["scenes"][size_t(scene)]["extras"].dump();

    if (ext)
        for (const auto& [name, value] : ext->items())
            if (std::find(kCarriedRootExtensions.begin(), kCarriedRootExtensions.end(), name) == kCarriedRootExtensions.end())
                warnings.push_back("root extension " + name + " is not carried to the output");
    return s;
}

void decomposeTrs(const Mat4& m, Vec3& translation, Vec4& rotation, Vec3& scale) {
    translation = {m[12], m[13], m[14]};
    Vec3 c0{m[0], m[1], m[2]}, c1{m[4], m[5], m[6]}, c2{m[8], m[9], m[10]};
    const double sign = det3(m) < 0 ? -1 : 1;
    // Gram-Schmidt frame (x flipped with a negative determinant, so the frame is a rotation).
    Vec3 r0 = normalize(c0 * sign);
    Vec3 r1 = normalize(c1 - r0 * dot(c1, r0));
    Vec3 r2 = cross(r0, r1);
    if (!(length(r0) > 0.5 && length(r1) > 0.5 && isFinite(r2))) {
        // A singular matrix has no frame: identity rotation, the columns' lengths as scale.
        rotation = {0, 0, 0, 1};
        scale = {length(c0), length(c1), length(c2)};
        return;
    }
    // A scale within rounding of 1 (the frame's own, e.g. 0.9999999999999998) is written as 1.
    auto unit = [](double v) { return std::abs(std::abs(v) - 1) < 1e-12 ? std::copysign(1.0, v) : v; };
    scale = {unit(sign * length(c0)), unit(dot(c1, r1)), unit(dot(c2, r2))};
    // Quaternion of the rotation matrix [r0 r1 r2] (Shepperd: the largest diagonal term first).
    const double R[3][3] = {{r0.x, r1.x, r2.x}, {r0.y, r1.y, r2.y}, {r0.z, r1.z, r2.z}};
    const double tr = R[0][0] + R[1][1] + R[2][2];
    double x, y, z, w;
    if (tr > 0) {
        double t = std::sqrt(tr + 1) * 2;
        w = t / 4;
        x = (R[2][1] - R[1][2]) / t;
        y = (R[0][2] - R[2][0]) / t;
        z = (R[1][0] - R[0][1]) / t;
    } else if (R[0][0] > R[1][1] && R[0][0] > R[2][2]) {
        double t = std::sqrt(1 + R[0][0] - R[1][1] - R[2][2]) * 2;
        w = (R[2][1] - R[1][2]) / t;
        x = t / 4;
        y = (R[0][1] + R[1][0]) / t;
        z = (R[0][2] + R[2][0]) / t;
    } else if (R[1][1] > R[2][2]) {
        double t = std::sqrt(1 + R[1][1] - R[0][0] - R[2][2]) * 2;
        w = (R[0][2] - R[2][0]) / t;
        x = (R[0][1] + R[1][0]) / t;
        y = t / 4;
        z = (R[1][2] + R[2][1]) / t;
    } else {
        double t = std::sqrt(1 + R[2][2] - R[0][0] - R[1][1]) * 2;
        w = (R[1][0] - R[0][1]) / t;
        x = (R[0][2] + R[2][0]) / t;
        y = (R[1][2] + R[2][1]) / t;
        z = t / 4;
    }
    const double len = std::sqrt(x * x + y * y + z * z + w * w), s = w < 0 ? -1 / len : 1 / len;
    rotation = {x * s, y * s, z * s, w * s};
}

bool writeSceneExtras(const SceneExtras& s, json& root, json& nodes, json& scene) {
    if (s.empty()) return false;
    if (!s.lights.empty()) {
        json lights = json::array();
        for (const SceneLight& l : s.lights) lights.push_back(lightJson(l));
        root["extensions"][kLights] = {{"lights", lights}};
    }
    if (!s.cameras.empty()) {
        json cameras = json::array();
        for (const SceneCamera& c : s.cameras) cameras.push_back(cameraJson(c));
        root["cameras"] = cameras;
    }
    for (const ScenePlacement& p : s.placements) {
        Vec3 t, sc;
        Vec4 r;
        decomposeTrs(p.world, t, r, sc);
        json node = json::object();
        if (!p.name.empty()) node["name"] = p.name;
        if (t.x != 0 || t.y != 0 || t.z != 0) node["translation"] = {t.x, t.y, t.z};
        if (r.x != 0 || r.y != 0 || r.z != 0 || r.w != 1) node["rotation"] = {r.x, r.y, r.z, r.w};
        if (sc.x != 1 || sc.y != 1 || sc.z != 1) node["scale"] = {sc.x, sc.y, sc.z};
        if (p.camera >= 0 && size_t(p.camera) < s.cameras.size()) node["camera"] = p.camera;
        if (p.light >= 0 && size_t(p.light) < s.lights.size()) node["extensions"][kLights] = {{"light", p.light}};
        scene["nodes"].push_back(nodes.size());
        nodes.push_back(node);
    }
    if (!s.rootExtras.empty()) root["extras"] = json::parse(s.rootExtras);
    if (!s.assetExtras.empty()) root["asset"]["extras"] = json::parse(s.assetExtras);
    if (!s.sceneExtras.empty()) scene["extras"] = json::parse(s.sceneExtras);
    return !s.lights.empty();
}

}  // namespace lodbake::gltf_detail
