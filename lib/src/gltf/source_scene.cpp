// The input's own document, kept for a chain whose LOD0 is the original (lodbake/gltf/source_scene.h).
//
// Pipeline of readSourceScene:
//   1. readKeepingModel: the file read as readGltf reads it (the flattened asset gives the
//      triangle count and the rig's sources), with tinygltf's model and the JSON kept;
//   2. checkOriginal: neither a lodbake intermediate nor already an MSFT_lod chain;
//   3. decodeDracoPrimitives: each KHR_draco_mesh_compression primitive's attributes and indices
//      as plain accessors (written over the accessors the primitive named, so no index moves);
//   4. copyViews: every bufferView an accessor or image uses, its bytes (meshopt views decoded)
//      copied into the one buffer, indices remapped; images from URIs become buffer views;
//   5. the extensions of the decoded compression leave extensionsUsed / extensionsRequired, and
//      the counts of what the scene draws.

#include "lodbake/gltf/source_scene.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "gltf/gltf_buffer.h"
#include "gltf/gltf_internal.h"
#include "gltf/gltf_read_context.h"
#include "lodbake/core/errors.h"

namespace lodbake {
namespace {

using json = nlohmann::json;
using namespace gltf_detail;

bool hasExtension(const json& o, const char* name) {
    return o.is_object() && o.contains("extensions") && o["extensions"].is_object() && o["extensions"].contains(name);
}

// Step 2.
void checkOriginal(const ReadContext& c) {
    if (hasExtension(c.root, "LODBAKE_multires"))
        throw Impossible(c.path + ": a lodbake intermediate (LODBAKE_multires), not an original asset: give the file simplify read");
    if (c.root.contains("nodes"))
        for (const json& n : c.root["nodes"])
            if (hasExtension(n, "MSFT_lod"))
                throw Impossible(c.path + ": already an MSFT_lod chain; its LOD0 cannot be carried as one level");
}

// Draco's quantized weights may sum to 1 +- 1e-4, which glTF-Validator reports as an error: each
// vertex's largest weight takes up the difference (sums within float precision of 1 are kept).
void normalizeWeights(std::vector<float>& w) {
    for (size_t i = 0; i + 3 < w.size(); i += 4) {
        const size_t big = size_t(std::max_element(w.begin() + long(i), w.begin() + long(i) + 4) - w.begin());
        double others = 0, sum = 0;
        for (size_t k = i; k < i + 4; ++k) {
            sum += w[k];
            if (k != big) others += w[k];
        }
        if (std::abs(sum - 1) > 1e-6 && sum > 0) w[big] = float(1 - others);
    }
}

// Step 3: the decoded primitive's attributes in plain accessors; `rewritten` holds the accessors
// already replaced (one shared by two primitives gets a new index the second time).
void rewriteDracoPrimitive(const ReadContext& c, Asset& scratch, int mi, int pi, BufferBuilder& b, json& out,
                           std::set<int>& rewritten) {
    json& jp = out["meshes"][size_t(mi)]["primitives"][size_t(pi)];
    const std::string what = "mesh " + std::to_string(mi) + " primitive " + std::to_string(pi);
    if (jint(jp, "mode", 4) != 4) throw Unsupported(c.path + ": " + what + ": a Draco-compressed primitive that is not TRIANGLES");
    if (jp.contains("targets")) throw Unsupported(c.path + ": " + what + ": a Draco-compressed primitive with morph targets");
    PrimData p;
    if (!decodePrimitive(c, mi, pi, scratch, p)) throw Unsupported(c.path + ": " + what + ": cannot decode");
    const json named = jp["attributes"];
    // Puts `accessor` at the index the primitive named (or a new one); returns it.
    auto place = [&](int index, json accessor) {
        if (index >= 0 && size_t(index) < out["accessors"].size() && rewritten.insert(index).second) {
            out["accessors"][size_t(index)] = std::move(accessor);
            return index;
        }
        out["accessors"].push_back(std::move(accessor));
        return int(out["accessors"].size()) - 1;
    };
    // The attributes the decoder reads; any other the extension names is left out.
    json attributes = json::object();
    auto floats = [&](const char* name, const std::vector<float>& v, int comps, bool minmax) {
        if (v.empty()) return;
        json a = floatAccessorJson(v, comps, minmax);
        a["bufferView"] = b.addView(v.data(), v.size() * 4, kArrayBuffer);
        attributes[name] = place(jint(named, name, -1), a);
    };
    std::vector<float> pos, normal, tangent, uv0, uv1, color;
    for (const Vec3& v : p.pos) pos.insert(pos.end(), {float(v.x), float(v.y), float(v.z)});
    for (const Vec3& v : p.normal) normal.insert(normal.end(), {float(v.x), float(v.y), float(v.z)});
    for (const Vec4& v : p.tangent) tangent.insert(tangent.end(), {float(v.x), float(v.y), float(v.z), float(v.w)});
    for (const Vec2& v : p.uv0) uv0.insert(uv0.end(), {float(v.x), float(v.y)});
    for (const Vec2& v : p.uv1) uv1.insert(uv1.end(), {float(v.x), float(v.y)});
    for (const Vec4& v : p.color) color.insert(color.end(), {float(v.x), float(v.y), float(v.z), float(v.w)});
    floats("POSITION", pos, 3, true);
    floats("NORMAL", normal, 3, false);
    floats("TANGENT", tangent, 4, false);
    floats("TEXCOORD_0", uv0, 2, false);
    floats("TEXCOORD_1", uv1, 2, false);
    floats("COLOR_0", color, 4, false);
    if (p.influenceSets == 1) {
        std::vector<uint16_t> joints(p.joints.begin(), p.joints.end());
        std::vector<float> weights(p.weights.begin(), p.weights.end());
        normalizeWeights(weights);
        const int view = b.addView(joints.data(), joints.size() * 2, kArrayBuffer);
        attributes["JOINTS_0"] = place(jint(named, "JOINTS_0", -1),
                                       {{"bufferView", view}, {"componentType", kUnsignedShort}, {"count", p.pos.size()}, {"type", "VEC4"}});
        floats("WEIGHTS_0", weights, 4, false);
    }
    jp["attributes"] = attributes;
    std::vector<uint32_t> idx;
    idx.reserve(3 * p.tris.size());
    for (const Tri& t : p.tris) idx.insert(idx.end(), t.begin(), t.end());
    const bool shortIdx = p.pos.size() < 65536;
    std::vector<uint16_t> idx16(idx.begin(), idx.end());
    const int view = shortIdx ? b.addView(idx16.data(), idx16.size() * 2, kElementArrayBuffer)
                              : b.addView(idx.data(), idx.size() * 4, kElementArrayBuffer);
    jp["indices"] = place(jint(jp, "indices", -1), {{"bufferView", view}, {"componentType", shortIdx ? kUnsignedShort : kUnsignedInt},
                                                    {"count", idx.size()}, {"type", "SCALAR"}});
    jp["extensions"].erase(kDraco);
    if (jp["extensions"].empty()) jp.erase("extensions");
}

// The scene roots readGltf reads: the default scene's, scene 0's, or every node that is no child.
std::vector<int> rootsOf(const json& root) {
    std::vector<int> roots;
    const int scene = jint(root, "scene", root.contains("scenes") && !root["scenes"].empty() ? 0 : -1);
    if (scene >= 0) {
        const json& s = root["scenes"][size_t(scene)];
        if (s.contains("nodes"))
            for (const json& n : s["nodes"]) roots.push_back(n.get<int>());
        return roots;
    }
    const size_t count = root.contains("nodes") ? root["nodes"].size() : 0;
    std::vector<char> child(count, 0);
    for (size_t i = 0; i < count; ++i)
        if (root["nodes"][i].contains("children"))
            for (const json& ch : root["nodes"][i]["children"]) child[ch.get<size_t>()] = 1;
    for (size_t i = 0; i < count; ++i)
        if (!child[i]) roots.push_back(int(i));
    return roots;
}

// Step 5: the draw calls and materials of the nodes reachable from the roots.
void countDraws(const json& root, SourceScene& s) {
    std::set<int> materials;
    std::vector<int> stack = s.roots;
    std::set<int> seen;
    while (!stack.empty()) {
        const int n = stack.back();
        stack.pop_back();
        if (!seen.insert(n).second) continue;
        const json& node = root["nodes"][size_t(n)];
        if (node.contains("children"))
            for (const json& ch : node["children"]) stack.push_back(ch.get<int>());
        const int mesh = jint(node, "mesh", -1);
        if (mesh < 0) continue;
        for (const json& p : root["meshes"][size_t(mesh)]["primitives"]) {
            s.drawCalls++;
            materials.insert(jint(p, "material", -1));
        }
    }
    s.materials = materials.size();
}

void dropExtension(json& root, const char* list, const char* name) {
    if (!root.contains(list)) return;
    json kept = json::array();
    for (const json& e : root[list])
        if (e != name) kept.push_back(e);
    if (kept.empty()) root.erase(list);
    else root[list] = kept;
}

}  // namespace

SourceScene readSourceScene(const std::string& path) {
    ReadContext c;
    c.path = path;
    tinygltf::Model model;
    RigSources rigSources;
    Asset asset = readKeepingModel(c, model, rigSources);  // 1
    checkOriginal(c);                                      // 2
    SourceScene s;
    s.path = path;
    s.triangles = asset.mesh.triangleCount();
    s.vertices = asset.stats.inputVertices;
    s.rigNodes = rigSources.nodes;
    s.rigAnimations = rigSources.animations;
    json out = c.root;
    if (!out.contains("accessors")) out["accessors"] = json::array();

    // 4a. The views the accessors and images use, in their order, then the decoded Draco data.
    BufferBuilder b;
    std::map<int, int> viewIndex;  // file's bufferView -> new
    auto copyView = [&](int v) {
        auto it = viewIndex.find(v);
        if (it != viewIndex.end()) return it->second;
        size_t length = 0;
        const unsigned char* bytes = viewBytes(c, v, length, "bufferView " + std::to_string(v));
        const int index = b.addView(bytes, length, 0);
        json& view = b.views[size_t(index)];
        const json& old = c.root["bufferViews"][size_t(v)];
        for (const char* key : {"byteStride", "target", "name", "extras"})
            if (old.contains(key)) view[key] = old[key];
        if (old.contains("extensions")) {
            json ext = old["extensions"];
            ext.erase(kMeshopt);
            if (!ext.empty()) view["extensions"] = ext;
        }
        viewIndex[v] = index;
        return index;
    };
    for (json& a : out["accessors"]) {
        if (a.contains("bufferView")) a["bufferView"] = copyView(a["bufferView"].get<int>());
        if (a.contains("sparse")) {
            json& sp = a["sparse"];
            sp["indices"]["bufferView"] = copyView(sp["indices"]["bufferView"].get<int>());
            sp["values"]["bufferView"] = copyView(sp["values"]["bufferView"].get<int>());
        }
    }
    // 4b. Images: buffer views (copied), or their decoded bytes from a URI.
    if (out.contains("images"))
        for (size_t i = 0; i < out["images"].size(); ++i) {
            json& img = out["images"][i];
            const size_t before = b.size;
            if (img.contains("bufferView")) {
                img["bufferView"] = copyView(img["bufferView"].get<int>());
            } else {
                const Image& src = asset.images[i];
                img["bufferView"] = b.addView(src.encoded.data(), src.encoded.size(), 0);
                img.erase("uri");
                std::string mime = sniffImageMime(src.encoded.data(), src.encoded.size());
                if (mime.empty()) mime = src.mimeType.empty() ? "image/png" : src.mimeType;
                img["mimeType"] = mime;
            }
            s.imageBytes += b.size - before;
        }
    // 3. Draco primitives, decoded.
    size_t draco = 0;
    std::set<int> rewritten;
    if (out.contains("meshes"))
        for (size_t mi = 0; mi < out["meshes"].size(); ++mi)
            for (size_t pi = 0; pi < out["meshes"][mi]["primitives"].size(); ++pi)
                if (hasExtension(out["meshes"][mi]["primitives"][pi], kDraco)) {
                    rewriteDracoPrimitive(c, asset, int(mi), int(pi), b, out, rewritten);
                    ++draco;
                }
    // Accessors a Draco primitive named but no longer uses (an attribute the decoder does not
    // read) keep no bufferView: valid glTF (zeros), used by nothing.
    out["bufferViews"] = b.views;
    if (b.views.empty()) out.erase("bufferViews");
    if (out["accessors"].empty()) out.erase("accessors");
    out.erase("buffers");
    for (const std::string& chunk : b.chunks) s.bin.insert(s.bin.end(), chunk.begin(), chunk.end());
    s.geometryBytes = s.bin.size() - s.imageBytes;

    // 5. Compression decoded; the scene's counts.
    if (draco) s.decoded.push_back(std::string(kDraco) + " (" + std::to_string(draco) + " primitives)");
    bool meshopt = false;
    if (c.root.contains("bufferViews"))
        for (const json& v : c.root["bufferViews"]) meshopt = meshopt || hasExtension(v, kMeshopt);
    if (meshopt) s.decoded.push_back(kMeshopt);
    for (const char* list : {"extensionsUsed", "extensionsRequired"}) {
        dropExtension(out, list, kDraco);
        dropExtension(out, list, kMeshopt);
    }
    s.roots = rootsOf(c.root);
    out.erase("scene");
    out.erase("scenes");
    countDraws(out, s);
    auto count = [&](const char* key) { return out.contains(key) ? out[key].size() : size_t(0); };
    s.meshes = count("meshes");
    s.nodes = count("nodes");
    s.textures = count("textures");
    s.images = count("images");
    s.skins = count("skins");
    s.animations = count("animations");
    s.json = out.dump();
    return s;
}

}  // namespace lodbake
