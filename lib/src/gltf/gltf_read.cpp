// glTF 2.0 reader: tinygltf parses JSON and loads buffers and images (kept encoded); accessor and
// primitive decoding (primitive_read.cpp, draco_decode.cpp), scene flattening, the welded mesh
// (scene_mesh.cpp) and the LODBAKE_multires extension (multires_codec.cpp) are ours.
//
// Pipeline of readGltf:
//   1. loadModel: read the file bytes, detect GLB/JSON by magic, parse the JSON with nlohmann
//      (extensions, materials, LODBAKE_multires), check extensionsRequired, let tinygltf load it;
//   2. flattenScene: scene roots (or an MSFT_lod level), node hierarchy with world transforms;
//   3. weldScene (scene_mesh.cpp): decode each triangle primitive, transform, weld by world
//      position (core/weld.h) (or, for a file with LODBAKE_multires, readMultiresOriginal
//      rebuilds the original exactly);
//   4. readMaterials, readImages: materials, textures, samplers, images (kept encoded;
//      lodbake/texture/codec.h checks them).

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <optional>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "gltf/gltf_files.h"
#include "gltf/gltf_internal.h"
#include "gltf/gltf_read_context.h"
#include "gltf/material_json.h"
#include "gltf/meshopt_decode.h"
#include "gltf/multires_codec.h"
#include "gltf/morph_read.h"
#include "gltf/rig_read.h"
#include "gltf/scene_extras_codec.h"
#include "gltf/scene_mesh.h"
#include "gltf/variants_codec.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/pose.h"
#include "lodbake/gltf/gltf.h"

namespace lodbake {
namespace {

using json = nlohmann::json;
using namespace gltf_detail;

// A mesh node of the flattened scene and its world matrix.
using SceneNode = std::pair<int, Mat4>;

// ---------------------------------------------------------------------------------------------
// 1. Loading

// tinygltf's image callback; user data: the model being loaded (its buffers are in place). tinygltf
// hands over a bufferView's bytes without checking them against the buffer: do it here.
bool keepImageBytes(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
                    const unsigned char* bytes, int size, void* userData) {
    const auto* model = static_cast<const tinygltf::Model*>(userData);
    if (image->bufferView >= 0) {
        const tinygltf::BufferView& view = model->bufferViews[size_t(image->bufferView)];
        const size_t bufferSize = model->buffers[size_t(view.buffer)].data.size();
        if (view.byteOffset > bufferSize || view.byteLength > bufferSize - view.byteOffset || size < 0) {
            if (err)
                *err += "image " + std::to_string(index) + ": bufferView " + std::to_string(image->bufferView) + " (offset " +
                        std::to_string(view.byteOffset) + ", length " + std::to_string(view.byteLength) +
                        ") exceeds its buffer (" + std::to_string(bufferSize) + " bytes)\n";
            return false;
        }
    }
    image->image.assign(bytes, bytes + std::max(size, 0));
    image->width = image->height = -1;
    image->component = -1;
    return true;
}

// Texture extensions whose images (KTX2/Basis Universal, WebP, AVIF) lodbake does not decode.
const std::vector<std::string> kImageExtensions = {"KHR_texture_basisu", "EXT_texture_webp", "EXT_texture_avif"};

// Extensions the reader implements, so a file may require them: geometry (decoded), texture
// transforms, instancing (expanded), lights (carried) and every material extension it reads
// (pbrSpecularGlossiness converted on reading).
const std::vector<std::string> kSupportedRequired = [] {
    std::vector<std::string> v = {"EXT_mesh_gpu_instancing", "EXT_meshopt_compression", "KHR_draco_mesh_compression",
                                  "KHR_lights_punctual", "KHR_materials_emissive_strength",
                                  "KHR_materials_pbrSpecularGlossiness", "KHR_materials_unlit", "KHR_materials_variants",
                                  "KHR_mesh_quantization", "KHR_texture_transform"};
    v.insert(v.end(), readMaterialExtensionNames().begin(), readMaterialExtensionNames().end());
    return v;
}();


// The JSON text of a GLB (its first chunk) or of a .gltf (the whole file, after checking that it
// starts with an object).
std::string jsonTextOf(const ReadContext& c, const std::vector<unsigned char>& bytes, bool isGlb) {
    std::string jsonText;
    if (isGlb) {
        if (bytes.size() < 20) fail(c, "truncated GLB (" + std::to_string(bytes.size()) + " bytes)");
        uint32_t total = 0, chunkLen = 0, chunkType = 0;
        std::memcpy(&total, bytes.data() + 8, 4);
        std::memcpy(&chunkLen, bytes.data() + 12, 4);
        std::memcpy(&chunkType, bytes.data() + 16, 4);
        if (total > bytes.size()) fail(c, "truncated GLB (header says " + std::to_string(total) + " bytes, file has " + std::to_string(bytes.size()) + ")");
        if (chunkType != 0x4E4F534Au || uint64_t(chunkLen) + 20 > bytes.size()) fail(c, "invalid GLB JSON chunk");
        jsonText.assign(reinterpret_cast<const char*>(bytes.data() + 20), chunkLen);
    } else {
        size_t i = 0;
        if (bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF) i = 3;
        while (i < bytes.size() && std::isspace(bytes[i])) ++i;
        if (i == bytes.size() || bytes[i] != '{') fail(c, "not a glTF file (neither GLB nor a JSON object)");
        jsonText.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    }
    return jsonText;
}

// \throw Unsupported for an extensionsRequired entry this reader does not implement.
void checkRequiredExtensions(const ReadContext& c) {
    if (c.root.contains("extensionsRequired") && c.root["extensionsRequired"].is_array())
        for (const json& e : c.root["extensionsRequired"]) {
            std::string name = e.is_string() ? e.get<std::string>() : e.dump();
            if (std::find(kSupportedRequired.begin(), kSupportedRequired.end(), name) == kSupportedRequired.end()) {
                // KHR_meshopt_compression adds a vertex codec version and filter that
                // meshoptimizer 0.18 (Debian's) does not decode.
                if (name == "KHR_meshopt_compression")
                    throw Unsupported(c.path + ": required extension " + name +
                                      " is not supported by this build's meshoptimizer (0.18 decodes EXT_meshopt_compression only)");
                if (std::find(kImageExtensions.begin(), kImageExtensions.end(), name) != kImageExtensions.end())
                    throw Unsupported(c.path + ": required extension " + name +
                                      " is not supported (lodbake decodes PNG and JPEG images only)");
                throw Unsupported(c.path + ": required extension " + name + " is not supported");
            }
        }
}

// tinygltf rejects index accessors without a bufferView, which is how Draco primitives declare
// them; we never use those accessors, so they are hidden from tinygltf: the indices of Draco
// primitives are dropped from `patched` (a copy of `root`, made on first change).
bool hideDracoIndices(const json& root, std::optional<json>& patched) {
    bool changed = false;
    if (root.contains("meshes") && root["meshes"].is_array())
        for (size_t mi = 0; mi < root["meshes"].size(); ++mi) {
            const json& jm = root["meshes"][mi];
            if (!jm.is_object() || !jm.contains("primitives") || !jm["primitives"].is_array()) continue;
            for (size_t pi = 0; pi < jm["primitives"].size(); ++pi) {
                const json& jp = jm["primitives"][pi];
                if (jp.is_object() && jp.contains("indices") && jp.contains("extensions") && jp["extensions"].is_object() &&
                    jp["extensions"].contains("KHR_draco_mesh_compression")) {
                    if (!patched) patched = root;
                    changed = true;
                    (*patched)["meshes"][mi]["primitives"][pi].erase("indices");
                }
            }
        }
    return changed;
}

// Replaces the JSON tinygltf will parse by `root`: in `bytes` (GLB) or `jsonText` (.gltf).
void replaceJson(const json& root, bool isGlb, std::vector<unsigned char>& bytes, std::string& jsonText) {
    std::string text = root.dump();
    if (isGlb) {
        std::vector<unsigned char> glbBytes;
        while (text.size() % 4) text.push_back(' ');
        uint32_t oldLen = 0;
        std::memcpy(&oldLen, bytes.data() + 12, 4);
        size_t rest = 20 + size_t(oldLen);
        glbBytes.assign(bytes.begin(), bytes.begin() + 20);
        uint32_t newLen = uint32_t(text.size()), total = uint32_t(20 + text.size() + (bytes.size() - rest));
        std::memcpy(glbBytes.data() + 8, &total, 4);
        std::memcpy(glbBytes.data() + 12, &newLen, 4);
        glbBytes.insert(glbBytes.end(), text.begin(), text.end());
        glbBytes.insert(glbBytes.end(), bytes.begin() + long(rest), bytes.end());
        bytes.swap(glbBytes);
    } else {
        jsonText = text;
    }
}

// Step 1: the file into `model` (buffers loaded, images kept encoded) and its JSON into c.root.
// \throw IOError, InvalidInput, Unsupported.
void loadModel(ReadContext& c, tinygltf::Model& model) {
    const std::string& path = c.path;
    if (!c.bytes && std::filesystem::is_directory(path)) throw IOError(path + ": is a directory");
    std::vector<unsigned char> bytes = c.bytes ? std::move(*c.bytes) : readFileBytes(path);
    if (bytes.empty()) fail(c, "empty file");

    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keepImageBytes, &model);
    std::string err, warn;
    std::string baseDir = std::filesystem::path(path).parent_path().string();
    if (baseDir.empty()) baseDir = ".";
    bool isGlb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    std::string jsonText = jsonTextOf(c, bytes, isGlb);
    try {
        c.root = json::parse(jsonText);
    } catch (const json::exception& e) {
        fail(c, std::string("invalid JSON: ") + firstLine(e.what()));
    }
    if (!c.root.is_object()) fail(c, "JSON root is not an object");
    checkStructure(c);
    checkRequiredExtensions(c);
    std::optional<json> patched;  // the JSON tinygltf sees, when it differs from the file's
    bool changed = hideDracoIndices(c.root, patched);
    changed = hideMeshoptFallbackBuffers(c.root, patched) || changed;
    GlbBinChunk bin;
    const bool binTaken = isGlb && takeGlbBinChunk(c.root, patched, bytes, bin);
    if (binTaken) {
        isGlb = false;  // tinygltf parses the JSON alone and takes buffer 0 from `bin`
        jsonText = patched->dump();
    } else if (changed) {
        replaceJson(*patched, isGlb, bytes, jsonText);
    }
    loader.SetFsCallbacks(fileCallbacks(binTaken ? &bin : nullptr));
    bool ok = false;
    try {
        ok = isGlb ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()), baseDir)
                   : loader.LoadASCIIFromString(&model, &err, &warn, jsonText.data(), unsigned(jsonText.size()), baseDir);
    } catch (const std::exception& e) {  // tinygltf indexes some malformed input with .at()
        fail(c, std::string("malformed glTF (tinygltf: ") + firstLine(e.what()) + ")");
    }
    if (!ok) {
        std::string e = firstLine(err.empty() ? warn : err);
        if (e.empty()) e = "cannot load glTF";
        const std::string notFound = "File not found : ";
        if (e.rfind(notFound, 0) == 0)
            throw IOError(path + ": cannot read buffer file '" + e.substr(notFound.size()) + "': No such file or directory");
        bool io = e.find("not found") != std::string::npos || e.find("Failed to load") != std::string::npos ||
                  e.find("open") != std::string::npos;
        if (io) throw IOError(path + ": " + e);
        fail(c, e);
    }
    decodeMeshoptViews(c, model);
    c.model = &model;
}

// ---------------------------------------------------------------------------------------------
// 2. Scene flattening

Mat4 nodeMatrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        Mat4 m;
        for (int i = 0; i < 16; ++i) m[size_t(i)] = node.matrix[size_t(i)];
        return m;
    }
    Vec3 t{0, 0, 0}, s{1, 1, 1};
    Vec4 r{0, 0, 0, 1};
    if (node.translation.size() == 3) t = {node.translation[0], node.translation[1], node.translation[2]};
    if (node.rotation.size() == 4) r = {node.rotation[0], node.rotation[1], node.rotation[2], node.rotation[3]};
    if (node.scale.size() == 3) s = {node.scale[0], node.scale[1], node.scale[2]};
    return trsMatrix(t, r, s);
}

// The root nodes: those of the default scene (or scene 0), or every node that is no child when the
// file has no scene.
std::vector<int> sceneRoots(const ReadContext& c) {
    const tinygltf::Model& model = *c.model;
    std::vector<int> roots;
    int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : (model.scenes.empty() ? -1 : 0);
    if (sceneIndex >= int(model.scenes.size())) fail(c, "scene " + std::to_string(sceneIndex) + " does not exist");
    if (sceneIndex >= 0) {
        roots = model.scenes[size_t(sceneIndex)].nodes;
    } else {
        std::vector<char> isChild(model.nodes.size(), 0);
        for (const auto& n : model.nodes)
            for (int ch : n.children)
                if (ch >= 0 && size_t(ch) < isChild.size()) isChild[size_t(ch)] = 1;
        for (size_t i = 0; i < model.nodes.size(); ++i)
            if (!isChild[i]) roots.push_back(int(i));
    }
    return roots;
}

// ReadOptions::lod: replaces each scene root carrying MSFT_lod by its level `lod`.
std::vector<int> selectMsftLod(const ReadContext& c, const std::vector<int>& roots, int lod) {
    const std::string& path = c.path;
    std::vector<int> out;
    bool any = false;
    const json* nodes = c.root.contains("nodes") && c.root["nodes"].is_array() ? &c.root["nodes"] : nullptr;
    for (int r : roots) {
        const json* chain = nullptr;
        if (nodes && r >= 0 && size_t(r) < nodes->size()) {
            const json& n = (*nodes)[size_t(r)];
            if (n.contains("extensions") && n["extensions"].is_object() && n["extensions"].contains("MSFT_lod") &&
                n["extensions"]["MSFT_lod"].is_object() && n["extensions"]["MSFT_lod"].contains("ids") &&
                n["extensions"]["MSFT_lod"]["ids"].is_array())
                chain = &n["extensions"]["MSFT_lod"]["ids"];
        }
        if (!chain) { out.push_back(r); continue; }
        any = true;
        if (lod == 0) { out.push_back(r); continue; }
        if (size_t(lod) > chain->size())
            throw Impossible(path + ": --lod " + std::to_string(lod) + " asked but node " + std::to_string(r) + "'s MSFT_lod chain has " +
                             std::to_string(chain->size() + 1) + " levels");
        const json& id = (*chain)[size_t(lod) - 1];
        if (!id.is_number_integer() || id.get<long long>() < 0 || size_t(id.get<long long>()) >= nodes->size())
            fail(c, "node " + std::to_string(r) + ": MSFT_lod id out of range");
        out.push_back(id.get<int>());
    }
    if (!any && lod > 0) throw Impossible(path + ": --lod " + std::to_string(lod) + " asked but the file has no MSFT_lod chain");
    return out;
}

// World matrices of the mesh nodes reachable from `roots`, in depth-first order.
void collectNodes(const ReadContext& c, int node, const Mat4& parent, std::vector<char>& onStack,
                  std::vector<SceneNode>& out, size_t& visited) {
    const auto& m = *c.model;
    if (node < 0 || size_t(node) >= m.nodes.size()) fail(c, "node " + std::to_string(node) + " does not exist");
    if (onStack[size_t(node)]) fail(c, "node " + std::to_string(node) + " is part of a cycle");
    onStack[size_t(node)] = 1;
    visited++;
    Mat4 world = mul(parent, nodeMatrix(m.nodes[size_t(node)]));
    out.emplace_back(node, world);
    for (int child : m.nodes[size_t(node)].children) collectNodes(c, child, world, onStack, out, visited);
    onStack[size_t(node)] = 0;
}


// Step 2: every node reachable from `roots` with its world matrix, depth first; counts them in
// `visited`. \throw InvalidInput on a missing node or a cycle.
std::vector<SceneNode> flattenScene(const ReadContext& c, const std::vector<int>& roots, size_t& visited) {
    std::vector<SceneNode> nodes;
    std::vector<char> onStack(c.model->nodes.size(), 0);
    for (int r : roots) collectNodes(c, r, identity4(), onStack, nodes, visited);
    return nodes;
}

// EXT_mesh_gpu_instancing: above this many copies of one mesh, or this many triangles over all
// copies of it, the expansion is still done but warned about (every copy is simplified and baked).
constexpr size_t kManyInstances = 1000;
constexpr size_t kManyInstancedTriangles = 4000000;

// Triangles of mesh `mesh` as its JSON declares them (index or POSITION counts; for the warning
// only, before anything is decoded).
size_t declaredTriangles(const ReadContext& c, int mesh) {
    const json& jm = c.root.at("meshes").at(size_t(mesh));
    size_t tris = 0;
    if (!jm.contains("primitives") || !jm["primitives"].is_array()) return 0;
    for (const json& p : jm["primitives"]) {
        const int mode = jint(p, "mode", 4);
        if (mode < 4 || mode > 6) continue;
        int acc = jint(p, "indices", -1);
        if (acc < 0 && p.contains("attributes") && p["attributes"].is_object()) acc = jint(p["attributes"], "POSITION", -1);
        if (acc < 0 || !c.root.contains("accessors") || size_t(acc) >= c.root["accessors"].size()) continue;
        const size_t n = size_t(std::max(jint(c.root["accessors"][size_t(acc)], "count", 0), 0));
        tris += mode == 4 ? n / 3 : (n >= 2 ? n - 2 : 0);
    }
    return tris;
}

// Step 2b: the mesh nodes to weld. A node with EXT_mesh_gpu_instancing becomes one entry per
// instance, world x the instance's TRS (TRANSLATION / ROTATION / SCALE accessors, any component
// type the accessor declares, normalized or not; an absent attribute is the identity); others stay
// as they are. The rig and morph readers keep `nodes` (one entry per glTF node): an instance's
// vertices are in world space like any mesh node's, so a rigid binding moves every copy with its
// node. \throw InvalidInput on instance accessors of different counts.
std::vector<SceneNode> expandInstances(const ReadContext& c, const std::vector<SceneNode>& nodes, Asset& asset) {
    std::vector<SceneNode> out;
    out.reserve(nodes.size());
    for (const SceneNode& sn : nodes) {
        const int n = sn.first;
        const json& node = c.root.at("nodes").at(size_t(n));  // flattening checked that it exists
        const json* inst = nullptr;
        if (node.contains("mesh") && node.contains("extensions") && node["extensions"].is_object() &&
            node["extensions"].contains("EXT_mesh_gpu_instancing") && node["extensions"]["EXT_mesh_gpu_instancing"].is_object())
            inst = &node["extensions"]["EXT_mesh_gpu_instancing"];
        if (!inst || !inst->contains("attributes") || !(*inst)["attributes"].is_object()) {
            out.push_back(sn);
            continue;
        }
        const json& attrs = (*inst)["attributes"];
        const std::string what = "node " + std::to_string(n) + " EXT_mesh_gpu_instancing";
        const std::vector<float> t = readF32(c, jint(attrs, "TRANSLATION", -1), 3, what + " TRANSLATION");
        const std::vector<float> r = readF32(c, jint(attrs, "ROTATION", -1), 4, what + " ROTATION");
        const std::vector<float> s = readF32(c, jint(attrs, "SCALE", -1), 3, what + " SCALE");
        size_t count = 0;
        bool any = false;
        for (auto [size, comps] : {std::pair{t.size(), size_t(3)}, std::pair{r.size(), size_t(4)}, std::pair{s.size(), size_t(3)}}) {
            if (size == 0) continue;
            if (any && size / comps != count) fail(c, what + ": TRANSLATION, ROTATION and SCALE have different counts");
            count = size / comps;
            any = true;
        }
        if (!any) {  // no attribute the reader knows: the mesh is drawn once, as without the extension
            out.push_back(sn);
            continue;
        }
        for (size_t i = 0; i < count; ++i) {
            Vec3 ti = t.empty() ? Vec3{0, 0, 0} : Vec3{t[3 * i], t[3 * i + 1], t[3 * i + 2]};
            Vec4 ri = r.empty() ? Vec4{0, 0, 0, 1} : Vec4{r[4 * i], r[4 * i + 1], r[4 * i + 2], r[4 * i + 3]};
            Vec3 si = s.empty() ? Vec3{1, 1, 1} : Vec3{s[3 * i], s[3 * i + 1], s[3 * i + 2]};
            out.emplace_back(n, mul(sn.second, trsMatrix(ti, ri, si)));
        }
        const int mesh = jint(node, "mesh", -1);
        const bool meshExists = mesh >= 0 && c.root.contains("meshes") && size_t(mesh) < c.root["meshes"].size();
        const size_t tris = meshExists ? declaredTriangles(c, mesh) : 0;
        if (count > kManyInstances || count * tris > kManyInstancedTriangles)
            asset.warnings.push_back(what + ": " + std::to_string(count) + " instances of mesh " + std::to_string(mesh) + " (" +
                                     std::to_string(tris) + (tris == 1 ? " triangle" : " triangles") + " each) expanded into " +
                                     std::to_string(count * tris) + " triangles; every copy is simplified and baked on its own");
    }
    return out;
}

// ---------------------------------------------------------------------------------------------
// 3. The welded mesh: weldScene, scene_mesh.cpp

// ---------------------------------------------------------------------------------------------
// 4. Materials, textures, samplers, images

// KHR_materials_pbrSpecularGlossiness as metallic-roughness: diffuse becomes base colour, metallic
// 0, roughness 1 - glossiness (factor x the specular-glossiness texture's alpha, sampled by the
// bake). The specular colour is not kept: a dielectric's F0 of 0.04 stands in for it.
void convertSpecularGlossiness(const json& sg, Material& mat) {
    mat.baseColorFactor = {1, 1, 1, 1};
    mat.baseColor = {};
    if (sg.contains("diffuseFactor") && sg["diffuseFactor"].is_array() && sg["diffuseFactor"].size() == 4) {
        const json& f = sg["diffuseFactor"];
        mat.baseColorFactor = {f[0].get<double>(), f[1].get<double>(), f[2].get<double>(), f[3].get<double>()};
    }
    if (sg.contains("diffuseTexture")) mat.baseColor = readTextureRef(sg["diffuseTexture"], nullptr);
    mat.glossinessFactor = sg.value("glossinessFactor", 1.0);
    mat.metallicFactor = 0;
    mat.roughnessFactor = 1 - mat.glossinessFactor;
    mat.metallicRoughness = {};
    if (sg.contains("specularGlossinessTexture")) mat.specularGlossiness = readTextureRef(sg["specularGlossinessTexture"], nullptr);
}

Material readMaterial(const json& m) {
    Material mat;
    mat.name = m.value("name", std::string());
    if (m.contains("pbrMetallicRoughness") && m["pbrMetallicRoughness"].is_object()) {
        const json& p = m["pbrMetallicRoughness"];
        if (p.contains("baseColorFactor") && p["baseColorFactor"].is_array() && p["baseColorFactor"].size() == 4) {
            const json& f = p["baseColorFactor"];
            mat.baseColorFactor = {f[0].get<double>(), f[1].get<double>(), f[2].get<double>(), f[3].get<double>()};
        }
        mat.metallicFactor = p.value("metallicFactor", 1.0);
        mat.roughnessFactor = p.value("roughnessFactor", 1.0);
        if (p.contains("baseColorTexture")) mat.baseColor = readTextureRef(p["baseColorTexture"], nullptr);
        if (p.contains("metallicRoughnessTexture")) mat.metallicRoughness = readTextureRef(p["metallicRoughnessTexture"], nullptr);
    }
    if (m.contains("normalTexture")) mat.normal = readTextureRef(m["normalTexture"], "scale");
    if (m.contains("occlusionTexture")) mat.occlusion = readTextureRef(m["occlusionTexture"], "strength");
    if (m.contains("emissiveTexture")) mat.emissive = readTextureRef(m["emissiveTexture"], nullptr);
    if (m.contains("emissiveFactor") && m["emissiveFactor"].is_array() && m["emissiveFactor"].size() == 3) {
        const json& f = m["emissiveFactor"];
        mat.emissiveFactor = {f[0].get<double>(), f[1].get<double>(), f[2].get<double>()};
    }
    std::string mode = m.value("alphaMode", std::string("OPAQUE"));
    mat.alphaMode = mode == "MASK" ? AlphaMode::Mask : mode == "BLEND" ? AlphaMode::Blend : AlphaMode::Opaque;
    mat.alphaCutoff = m.value("alphaCutoff", 0.5);
    mat.doubleSided = m.value("doubleSided", false);
    const json* ext = m.contains("extensions") && m["extensions"].is_object() ? &m["extensions"] : nullptr;
    mat.unlit = ext && ext->contains("KHR_materials_unlit");
    if (ext && ext->contains("KHR_materials_emissive_strength") && (*ext)["KHR_materials_emissive_strength"].is_object())
        mat.emissiveStrength = (*ext)["KHR_materials_emissive_strength"].value("emissiveStrength", 1.0);
    if (ext && ext->contains("KHR_materials_pbrSpecularGlossiness") && (*ext)["KHR_materials_pbrSpecularGlossiness"].is_object())
        convertSpecularGlossiness((*ext)["KHR_materials_pbrSpecularGlossiness"], mat);
    if (ext) mat.ext = readMaterialExtensions(*ext);
    return mat;
}

// Extensions of a material that lodbake reads; any other is named in a warning (not carried).
const std::vector<std::string> kReadMaterialExtensions = [] {
    std::vector<std::string> v = {"KHR_materials_unlit", "KHR_materials_emissive_strength",
                                  "KHR_materials_pbrSpecularGlossiness", "KHR_texture_transform"};
    v.insert(v.end(), readMaterialExtensionNames().begin(), readMaterialExtensionNames().end());
    return v;
}();

// Step 4a: materials (from the JSON: tinygltf drops the extensions we read), samplers, textures.
void readMaterials(const ReadContext& c, Asset& asset) {
    const tinygltf::Model& model = *c.model;
    if (c.root.contains("materials") && c.root["materials"].is_array())
        for (const json& m : c.root["materials"]) {
            asset.materials.push_back(readMaterial(m));
            if (!m.contains("extensions") || !m["extensions"].is_object()) continue;
            for (const auto& [name, value] : m["extensions"].items())
                if (std::find(kReadMaterialExtensions.begin(), kReadMaterialExtensions.end(), name) == kReadMaterialExtensions.end())
                    asset.warnings.push_back("material " + std::to_string(asset.materials.size() - 1) + ": " + name +
                                             " is not carried to the output");
        }
    for (const auto& s : model.samplers) {
        Sampler smp;
        smp.magFilter = std::max(s.magFilter, 0);
        smp.minFilter = std::max(s.minFilter, 0);
        smp.wrapS = s.wrapS;
        smp.wrapT = s.wrapT;
        asset.samplers.push_back(smp);
    }
    // Image formats lodbake does not decode (KTX2/Basis, WebP, AVIF): an optional extension's
    // texture uses its fallback `source` (PNG/JPEG), with a warning; a required one was refused
    // by checkRequiredExtensions.
    if (c.root.contains("textures"))
        for (size_t i = 0; i < c.root["textures"].size(); ++i) {
            const json& t = c.root["textures"][i];
            if (!t.contains("extensions")) continue;
            for (const std::string& name : kImageExtensions)
                if (t["extensions"].contains(name))
                    asset.warnings.push_back("texture " + std::to_string(i) + ": " + name + " is not decoded; " +
                                             (t.contains("source") ? "its fallback image " + t["source"].dump() + " is used"
                                                                   : "it has no fallback image and is left out"));
        }
    for (const auto& t : model.textures) {
        Texture tex;
        tex.image = t.source;
        tex.sampler = t.sampler;
        if (tex.image >= int(model.images.size()) || tex.sampler >= int(model.samplers.size()))
            fail(c, "texture refers to a missing image or sampler");
        asset.textures.push_back(tex);
    }
}

// Step 4b: the images, still encoded (their bytes move out of `model`). \throw IOError for an image
// without data when options.requireImageData.
void readImages(const ReadContext& c, tinygltf::Model& model, const ReadOptions& options, Asset& asset) {
    for (size_t i = 0; i < model.images.size(); ++i) {
        auto& src = model.images[i];
        Image img;
        img.name = src.name.empty() ? src.uri : src.name;
        img.encoded = std::move(src.image);
        std::string sniffed = sniffImageMime(img.encoded.data(), img.encoded.size());
        img.mimeType = !sniffed.empty() ? sniffed : src.mimeType;
        if (img.encoded.empty()) {
            std::string w = "image " + std::to_string(i) + (src.uri.empty() ? "" : " '" + src.uri + "'");
            if (options.requireImageData) throw IOError(c.path + ": " + w + ": cannot read image data");
            asset.warnings.push_back(w + ": no image data");
        }
        asset.images.push_back(std::move(img));
    }
}

}  // namespace

namespace {

// Steps 2-4 on a loaded model; `rigSources`, when given, receives the glTF node of each rig node
// and the glTF animation of each rig animation.
Asset readLoaded(const ReadContext& c, tinygltf::Model& model, const ReadOptions& options, std::optional<Multires>* multires,
                 RigSources* rigSources) {
    const std::string& path = c.path;
    Asset asset;
    asset.sourcePath = path;
    try {
        std::vector<int> roots = sceneRoots(c);
        const json* ext = findMultiresExtension(c);
        if (options.lod >= 0 && !ext) roots = selectMsftLod(c, roots, options.lod);
        const std::vector<SceneNode> nodes = flattenScene(c, roots, asset.stats.nodes);
        const bool ours = ext && hasMultiresOriginal(*ext);
        // Our own multires file: the levels' nodes repeat the original's targets.
        std::vector<SceneNode> morphNodes;
        for (const SceneNode& n : nodes)
            if (!ours || n.first == multiresOriginalNode(*ext)) morphNodes.push_back(n);
        const MorphLayout layout = morphLayout(c, morphNodes);
        RigRead rr = readRig(c, nodes, layout, asset);
        asset.variants.names = readVariantNames(c);  // before the mesh: its primitives' mappings index them
        if (ours) {
            // The original mesh rebuilt exactly, then the extension.
            asset.mesh = readMultiresOriginal(c, *ext, nodes, rr, layout, asset);
            if (multires) *multires = readMultires(c, *ext, asset.mesh);
        } else {
            weldScene(c, expandInstances(c, nodes, asset), rr, layout, asset);
            if (multires) multires->reset();
        }
        asset.scene = readSceneExtras(c, nodes, asset.warnings);
        asset.morph = layout.targets;
        if (rigSources) {
            rigSources->nodes = rr.nodeSource;
            rigSources->animations = rr.animationSource;
        }
        asset.rig = std::move(rr.rig);
        for (std::string& w : influenceWarnings(rr)) asset.warnings.push_back(std::move(w));
        readMaterials(c, asset);
        readImages(c, model, options, asset);
    } catch (const json::exception& e) {
        fail(c, std::string("malformed JSON value: ") + firstLine(e.what()));
    }
    return asset;
}

Asset readWith(ReadContext& c, const ReadOptions& options, std::optional<Multires>* multires) {
    tinygltf::Model model;
    loadModel(c, model);
    return readLoaded(c, model, options, multires, nullptr);
}

}  // namespace

Asset gltf_detail::readKeepingModel(ReadContext& c, tinygltf::Model& model, RigSources& rigSources) {
    loadModel(c, model);
    return readLoaded(c, model, {}, nullptr, &rigSources);
}

Asset readGltf(const std::string& path, const ReadOptions& options, std::optional<Multires>* multires) {
    ReadContext c;
    c.path = path;
    return readWith(c, options, multires);
}

Asset readGltfBytes(const std::string& path, std::vector<unsigned char> bytes, const ReadOptions& options,
                    std::optional<Multires>* multires) {
    ReadContext c;
    c.path = path;
    c.bytes = &bytes;
    return readWith(c, options, multires);
}

}  // namespace lodbake
