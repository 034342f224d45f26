// The structural rules of the glTF 2.0 schema for what the reader uses, checked on the JSON before
// tinygltf loads the file, so a malformed file is one clear error instead of a property silently
// ignored (Khronos glTF-Validator reports these as errors too):
//   - top-level collections are arrays of objects; `name` is a string;
//   - every `extensions` is an object of objects;
//   - a mesh has an array of primitives, a primitive an object of attributes with non-negative
//     integer accessor indices, and indexed semantics (TEXCOORD_n, COLOR_n, JOINTS_n, WEIGHTS_n)
//     start at 0 and are continuous;
//   - a material's pbrMetallicRoughness is an object; a texture reference is an object with a
//     non-negative integer `index` (and texCoord), its scale / strength a number;
//   - a bufferView lies inside its buffer's declared byteLength.
// What the validator flags but the reader handles on purpose (zero-length normals, missing
// tangents, non-unit vectors) is not checked here.
#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "gltf/gltf_read_context.h"

namespace lodbake::gltf_detail {
namespace {

using json = nlohmann::json;

bool isIndex(const json& v) { return v.is_number_unsigned() || (v.is_number_integer() && v.get<int64_t>() >= 0); }

void checkExtensions(const ReadContext& c, const json& v, const std::string& where) {
    if (v.is_object()) {
        for (const auto& [key, child] : v.items()) {
            if (key == "extras") continue;
            if (key == "extensions") {
                if (!child.is_object()) fail(c, where + "/extensions is not an object");
                for (const auto& [name, ext] : child.items())
                    if (!ext.is_object()) fail(c, where + "/extensions/" + name + " is not an object");
            }
            checkExtensions(c, child, where + "/" + key);
        }
    } else if (v.is_array()) {
        for (size_t i = 0; i < v.size(); ++i) checkExtensions(c, v[i], where + "/" + std::to_string(i));
    }
}

void checkTextureInfo(const ReadContext& c, const json& m, const char* key, const char* factor, const std::string& where) {
    if (!m.contains(key)) return;
    const json& t = m[key];
    const std::string w = where + "/" + key;
    if (!t.is_object()) fail(c, w + " is not an object");
    if (!t.contains("index")) fail(c, w + ": index is missing");
    if (!isIndex(t["index"])) fail(c, w + ": index is not a non-negative integer");
    if (t.contains("texCoord") && !isIndex(t["texCoord"])) fail(c, w + ": texCoord is not a non-negative integer");
    if (factor && t.contains(factor) && !t[factor].is_number()) fail(c, w + ": " + factor + " is not a number");
}

void checkMaterial(const ReadContext& c, const json& m, const std::string& w) {
    if (m.contains("pbrMetallicRoughness")) {
        const json& p = m["pbrMetallicRoughness"];
        if (!p.is_object()) fail(c, w + "/pbrMetallicRoughness is not an object");
        checkTextureInfo(c, p, "baseColorTexture", nullptr, w + "/pbrMetallicRoughness");
        checkTextureInfo(c, p, "metallicRoughnessTexture", nullptr, w + "/pbrMetallicRoughness");
    }
    checkTextureInfo(c, m, "normalTexture", "scale", w);
    checkTextureInfo(c, m, "occlusionTexture", "strength", w);
    checkTextureInfo(c, m, "emissiveTexture", nullptr, w);
}

void checkPrimitive(const ReadContext& c, const json& p, const std::string& w) {
    if (!p.is_object()) fail(c, w + " is not an object");
    if (!p.contains("attributes") || !p["attributes"].is_object()) fail(c, w + ": attributes is missing or not an object");
    std::map<std::string, std::vector<int>> sets;
    for (const auto& [name, index] : p["attributes"].items()) {
        if (!isIndex(index)) fail(c, w + "/attributes/" + name + " is not a non-negative integer");
        const size_t us = name.rfind('_');
        if (us == std::string::npos || name[0] == '_') continue;
        const std::string semantic = name.substr(0, us);
        if (semantic != "TEXCOORD" && semantic != "COLOR" && semantic != "JOINTS" && semantic != "WEIGHTS") continue;
        const std::string n = name.substr(us + 1);
        if (n.empty() || n.find_first_not_of("0123456789") != std::string::npos || n.size() > 4) continue;
        sets[semantic].push_back(std::stoi(n));
    }
    for (auto& [semantic, ns] : sets) {
        std::sort(ns.begin(), ns.end());
        for (size_t i = 0; i < ns.size(); ++i)
            if (ns[i] != int(i))
                fail(c, w + ": " + semantic + "_" + std::to_string(ns[i]) + " without " + semantic + "_" + std::to_string(i) +
                            " (indexed attributes must start at 0 and be continuous)");
    }
    if (p.contains("indices") && !isIndex(p["indices"])) fail(c, w + "/indices is not a non-negative integer");
}

}  // namespace

void checkStructure(const ReadContext& c) {
    const json& root = c.root;
    for (const char* key : {"accessors", "animations", "buffers", "bufferViews", "cameras", "images", "materials", "meshes",
                            "nodes", "samplers", "scenes", "skins", "textures"}) {
        if (!root.contains(key)) continue;
        const json& a = root[key];
        if (!a.is_array()) fail(c, std::string("/") + key + " is not an array");
        for (size_t i = 0; i < a.size(); ++i) {
            const std::string w = std::string("/") + key + "/" + std::to_string(i);
            if (!a[i].is_object()) fail(c, w + " is not an object");
            if (a[i].contains("name") && !a[i]["name"].is_string()) fail(c, w + "/name is not a string");
        }
    }
    checkExtensions(c, root, "");
    if (root.contains("meshes"))
        for (size_t i = 0; i < root["meshes"].size(); ++i) {
            const json& m = root["meshes"][i];
            const std::string w = "/meshes/" + std::to_string(i);
            if (!m.contains("primitives") || !m["primitives"].is_array() || m["primitives"].empty())
                fail(c, w + "/primitives is missing or not a non-empty array");
            for (size_t k = 0; k < m["primitives"].size(); ++k)
                checkPrimitive(c, m["primitives"][k], w + "/primitives/" + std::to_string(k));
        }
    if (root.contains("materials"))
        for (size_t i = 0; i < root["materials"].size(); ++i) checkMaterial(c, root["materials"][i], "/materials/" + std::to_string(i));
    if (root.contains("bufferViews") && root.contains("buffers"))
        for (size_t i = 0; i < root["bufferViews"].size(); ++i) {
            const json& v = root["bufferViews"][i];
            const std::string w = "/bufferViews/" + std::to_string(i);
            if (!v.contains("buffer") || !isIndex(v["buffer"])) fail(c, w + "/buffer is missing or not a non-negative integer");
            const size_t b = v["buffer"].get<size_t>();
            if (b >= root["buffers"].size()) fail(c, w + ": buffer " + std::to_string(b) + " does not exist");
            const json& buf = root["buffers"][b];
            if (!buf.contains("byteLength") || !isIndex(buf["byteLength"]) || !v.contains("byteLength") || !isIndex(v["byteLength"]) ||
                (v.contains("byteOffset") && !isIndex(v["byteOffset"])))
                continue;  // tinygltf reports missing or malformed lengths
            const uint64_t offset = v.value("byteOffset", uint64_t(0)), length = v["byteLength"].get<uint64_t>();
            const uint64_t size = buf["byteLength"].get<uint64_t>();
            if (size == 0) continue;  // tinygltf rejects an empty buffer itself
            if (offset > size || length > size - offset)
                fail(c, w + " (offset " + std::to_string(offset) + ", length " + std::to_string(length) + ") exceeds its buffer (buffer " +
                            std::to_string(b) + ", byteLength " + std::to_string(size) + ")");
        }
}

}  // namespace lodbake::gltf_detail
