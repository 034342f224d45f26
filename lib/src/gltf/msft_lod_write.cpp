// The final LOD chain writer (pack's output).
//
// Pipeline of writeLodChain:
//   1. per level: buffers reordered for the GPU (gpu_streams.h), then one mesh with one primitive
//      (plain, quantized and/or meshopt-compressed streams, or a Draco buffer with accessor stubs
//      whose counts are the encoder's), one material and its textures (base colour, ORM,
//      emissive, normal, the KHR_materials_* extension images: those the level has); with
//      quantized positions every node carries the
//      grid's translation and scale;
//   2. node 0 (LOD0) with MSFT_lod.ids and extras.MSFT_screencoverage; in the scene node 0, the
//      rig's roots and the nodes of the asset's lights and cameras (scene_extras_codec.h);
//   With the original as LOD0 (a SourceScene), its document comes first (startWithSource): node 0
//   is a group over its scene roots, its nodes follow at +1, every other array (meshes, materials,
//   accessors, views, skins, animations, ...) keeps its indices and the baked levels are appended;
//   their skin's joints are the original's nodes and its animations drive both (addSourceRig);
//   3. serialise (.glb container, or .gltf + .bin [+ images]) and rename into place.
// JSON is built with nlohmann::json (sorted keys: byte-identical output for identical input).

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <tuple>

#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <nlohmann/json.hpp>

#include "gltf/gltf_buffer.h"
#include "gltf/gltf_internal.h"
#include "gltf/gpu_streams.h"
#include "gltf/material_json.h"
#include "lodbake/core/material_uniforms.h"
#include "gltf/rig_write.h"
#include "gltf/scene_extras_codec.h"
#include "gltf/variants_codec.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/parallel.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/gltf/msft_lod.h"
#include "lodbake/gltf/source_scene.h"

namespace lodbake {
namespace {

using json = nlohmann::json;
using namespace gltf_detail;

constexpr const char* kQuantization = "KHR_mesh_quantization";
constexpr const char* kBasisu = "KHR_texture_basisu";
constexpr const char* kLod = "MSFT_lod";
constexpr const char* kEmissiveStrength = "KHR_materials_emissive_strength";
constexpr const char* kUnlit = "KHR_materials_unlit";
constexpr const char* kLights = "KHR_lights_punctual";
constexpr int kLinear = 9729, kLinearMipmapLinear = 9987, kClampToEdge = 33071, kRepeat = 10497;  // GL enums

using Buffer = BufferBuilder;

void checkLevel(const std::string& path, const LodLevelData& L) {
    size_t n = L.positions.size() / 3;
    bool ok = n > 0 && L.positions.size() == 3 * n && L.normals.size() == 3 * n && L.uvs.size() == 2 * n &&
              (L.tangents.empty() || L.tangents.size() == 4 * n) && (L.joints.empty() || L.joints.size() == 4 * n) &&
              L.weights.size() == L.joints.size() && !L.indices.empty() && L.indices.size() % 3 == 0;
    for (auto* targets : {&L.targetPositions, &L.targetNormals, &L.targetTangents})
        for (const std::vector<float>& d : *targets) ok = ok && (d.empty() || d.size() == 3 * n);
    for (const std::vector<float>& d : L.targetPositions) ok = ok && !d.empty();
    for (uint32_t i : L.indices) ok = ok && i < n;
    size_t partTriangles = 0;
    for (const LodPart& p : L.parts) {
        ok = ok && p.triangles > 0;
        partTriangles += p.triangles;
    }
    ok = ok && (L.parts.empty() || 3 * partTriangles == L.indices.size());
    if (!ok) throw InvalidInput(path + ": level '" + L.name + "' has inconsistent mesh data");
    auto normalMapped = [](const LodMaterial& M) {
        return !M.normal.encoded.empty() || M.ext.clearcoat.normalTexture.texture >= 0 || M.ext.anisotropy.texture.texture >= 0;
    };
    bool normalMaps = normalMapped(L.material);
    for (const LodMaterial& M : L.variantMaterials) normalMaps = normalMaps || normalMapped(M);
    if (normalMaps && L.tangents.empty()) throw InvalidInput(path + ": level '" + L.name + "' has a normal map but no tangents");
    for (int m : L.variantMaterial)
        if (m >= int(L.variantMaterials.size())) throw InvalidInput(path + ": level '" + L.name + "' names a missing variant material");
}

// Draco quantisation bits for a level's UVs: `bits` over one unit of UV, so UVs that tile a
// repeating texture over a range of R units keep that step (log2 R bits more; at most 30).
int texcoordBits(const std::vector<float>& uvs, int bits) {
    float lo = 0, hi = 1;
    for (float x : uvs) {
        lo = std::min(lo, x);
        hi = std::max(hi, x);
    }
    const double range = double(hi) - double(lo);
    return range > 1 ? std::min(30, bits + int(std::ceil(std::log2(range)))) : bits;
}

// KHR_draco_mesh_compression: the Draco bitstream in a buffer view, accessors without views whose
// counts are what the decoder will produce (the encoder may split non-manifold vertices).
json dracoPrimitive(Buffer& b, const LodLevelData& L, const LodChainWriteOptions& o, const std::string& path) {
    size_t n = L.positions.size() / 3, f = L.indices.size() / 3;
    draco::Mesh dm;
    dm.set_num_points(uint32_t(n));
    auto add = [&](draco::GeometryAttribute::Type type, const std::vector<float>& v, int comps) {
        draco::GeometryAttribute ga;
        ga.Init(type, nullptr, int8_t(comps), draco::DT_FLOAT32, false, int64_t(sizeof(float)) * comps, 0);
        int id = dm.AddAttribute(ga, true, uint32_t(n));
        draco::PointAttribute* a = dm.attribute(id);
        for (size_t i = 0; i < n; ++i) a->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), &v[i * size_t(comps)]);
        return a->unique_id();
    };
    uint32_t pid = add(draco::GeometryAttribute::POSITION, L.positions, 3);
    uint32_t nid = add(draco::GeometryAttribute::NORMAL, L.normals, 3);
    uint32_t tid = add(draco::GeometryAttribute::TEX_COORD, L.uvs, 2);
    const bool tangents = !L.tangents.empty();
    uint32_t gid = tangents ? add(draco::GeometryAttribute::GENERIC, L.tangents, 4) : 0;
    // Skin influences as generic attributes (the extension names them JOINTS_0 / WEIGHTS_0).
    const bool skinned = !L.joints.empty();
    uint32_t jid = 0, wid = 0;
    if (skinned) {
        draco::GeometryAttribute ga;
        ga.Init(draco::GeometryAttribute::GENERIC, nullptr, 4, draco::DT_UINT16, false, int64_t(sizeof(uint16_t)) * 4, 0);
        int id = dm.AddAttribute(ga, true, uint32_t(n));
        draco::PointAttribute* a = dm.attribute(id);
        for (size_t i = 0; i < n; ++i) a->SetAttributeValue(draco::AttributeValueIndex(uint32_t(i)), &L.joints[i * 4]);
        jid = a->unique_id();
        wid = add(draco::GeometryAttribute::GENERIC, L.weights, 4);
    }
    dm.SetNumFaces(f);
    for (size_t t = 0; t < f; ++t) {
        draco::Mesh::Face face = {draco::PointIndex(L.indices[3 * t]), draco::PointIndex(L.indices[3 * t + 1]),
                                  draco::PointIndex(L.indices[3 * t + 2])};
        dm.SetFace(draco::FaceIndex(uint32_t(t)), face);
    }
    draco::Encoder enc;
    enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, o.quantPosition);
    enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, texcoordBits(L.uvs, o.quantTexcoord));
    enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, o.quantNormal);
    // Generic attributes: tangents and skin weights (integer joints are never quantised).
    if (tangents || skinned) enc.SetAttributeQuantization(draco::GeometryAttribute::GENERIC, o.quantNormal);
    enc.SetSpeedOptions(o.dracoSpeed, o.dracoSpeed);
    enc.SetTrackEncodedProperties(true);
    draco::EncoderBuffer out;
    draco::Status st = enc.EncodeMeshToBuffer(dm, &out);
    if (!st.ok()) throw SolverError(path + ": Draco encoding of '" + L.name + "' failed: " + st.error_msg_string());
    size_t points = enc.num_encoded_points(), faces = enc.num_encoded_faces();
    int view = b.addView(out.data(), out.size(), 0);
    json attrs;
    json pa = floatAccessorJson(L.positions, 3, true);
    pa["count"] = points;
    attrs["POSITION"] = b.addAccessor(pa);
    json na = floatAccessorJson(L.normals, 3, false);
    na["count"] = points;
    attrs["NORMAL"] = b.addAccessor(na);
    json ta = floatAccessorJson(L.uvs, 2, false);
    ta["count"] = points;
    attrs["TEXCOORD_0"] = b.addAccessor(ta);
    json ids = {{"POSITION", pid}, {"NORMAL", nid}, {"TEXCOORD_0", tid}};
    if (tangents) {
        json ga = floatAccessorJson(L.tangents, 4, false);
        ga["count"] = points;
        attrs["TANGENT"] = b.addAccessor(ga);
        ids["TANGENT"] = gid;
    }
    if (skinned) {
        attrs["JOINTS_0"] = b.addAccessor({{"componentType", kUnsignedShort}, {"count", points}, {"type", "VEC4"}});
        json wa = floatAccessorJson(L.weights, 4, false);
        wa["count"] = points;
        attrs["WEIGHTS_0"] = b.addAccessor(wa);
        ids["JOINTS_0"] = jid;
        ids["WEIGHTS_0"] = wid;
    }
    int ia = b.addAccessor({{"componentType", points < 65536 ? kUnsignedShort : kUnsignedInt}, {"count", faces * 3}, {"type", "SCALAR"}});
    json ext = {{"bufferView", view}, {"attributes", ids}};
    return {{"attributes", attrs}, {"indices", ia}, {"mode", 4}, {"extensions", {{kDraco, ext}}}};
}

// Part `part` of L as a level of its own: its triangles and the vertices they use (in first-use
// order), for Draco, which encodes a primitive's vertices with its faces.
LodLevelData partLevel(const LodLevelData& L, size_t part) {
    size_t first = 0;
    for (size_t p = 0; p < part; ++p) first += 3 * L.parts[p].triangles;
    const size_t count = 3 * L.parts[part].triangles;
    LodLevelData out;
    out.name = L.name;
    std::vector<uint32_t> remap(L.positions.size() / 3, UINT32_MAX);
    auto copy = [](const std::vector<float>& from, std::vector<float>& to, size_t v, size_t comps) {
        if (!from.empty()) to.insert(to.end(), from.begin() + std::ptrdiff_t(comps * v), from.begin() + std::ptrdiff_t(comps * (v + 1)));
    };
    for (size_t i = first; i < first + count; ++i) {
        const uint32_t v = L.indices[i];
        if (remap[v] == UINT32_MAX) {
            remap[v] = uint32_t(out.positions.size() / 3);
            copy(L.positions, out.positions, v, 3);
            copy(L.normals, out.normals, v, 3);
            copy(L.uvs, out.uvs, v, 2);
            copy(L.tangents, out.tangents, v, 4);
            copy(L.weights, out.weights, v, 4);
            if (!L.joints.empty()) out.joints.insert(out.joints.end(), L.joints.begin() + std::ptrdiff_t(4 * v), L.joints.begin() + std::ptrdiff_t(4 * v + 4));
        }
        out.indices.push_back(remap[v]);
    }
    return out;
}

// The arrays of the file being written.
struct Document {
    json meshes = json::array(), nodes = json::array(), materials = json::array(), textures = json::array(),
         images = json::array(), samplers = json::array(), skins = json::array(), animations = json::array();
    json top = json::object();  // the source's root extensions, cameras, extras and asset extras
    std::vector<std::string> used, required;  // the source's extensionsUsed / extensionsRequired
};

json arrayOf(const json& o, const char* key) { return o.contains(key) && o[key].is_array() ? o[key] : json::array(); }

// The original's document first: buffer, views, accessors and every array at their own indices,
// except nodes, which move up by one behind node 0, the LOD0 group over the original's roots.
void startWithSource(const SourceScene& src, Buffer& b, Document& d) {
    json in = json::parse(src.json);
    b.chunks.emplace_back(src.bin.begin(), src.bin.end());
    b.size = src.bin.size();
    b.views = arrayOf(in, "bufferViews");
    b.accessors = arrayOf(in, "accessors");
    d.meshes = arrayOf(in, "meshes");
    d.materials = arrayOf(in, "materials");
    d.textures = arrayOf(in, "textures");
    d.images = arrayOf(in, "images");
    d.samplers = arrayOf(in, "samplers");
    d.skins = arrayOf(in, "skins");
    d.animations = arrayOf(in, "animations");
    json group = {{"name", "LOD0"}};
    for (int r : src.roots) group["children"].push_back(r + 1);
    d.nodes.push_back(group);
    for (json n : arrayOf(in, "nodes")) {
        if (n.contains("children"))
            for (json& ch : n["children"]) ch = ch.get<int>() + 1;
        d.nodes.push_back(std::move(n));
    }
    for (json& skin : d.skins) {
        for (json& j : skin["joints"]) j = j.get<int>() + 1;
        if (skin.contains("skeleton")) skin["skeleton"] = skin["skeleton"].get<int>() + 1;
    }
    for (json& a : d.animations)
        for (json& ch : a["channels"])
            if (ch["target"].contains("node")) ch["target"]["node"] = ch["target"]["node"].get<int>() + 1;
    for (const char* key : {"extensions", "cameras", "extras"})
        if (in.contains(key)) d.top[key] = in[key];
    if (in.contains("asset"))
        for (const char* key : {"copyright", "extras"})
            if (in["asset"].contains(key)) d.top["asset"][key] = in["asset"][key];
    for (const json& e : arrayOf(in, "extensionsUsed")) d.used.push_back(e.get<std::string>());
    for (const json& e : arrayOf(in, "extensionsRequired")) d.required.push_back(e.get<std::string>());
}

// The baked levels' skin over the original's own nodes (the rig's joints are those nodes: the
// original's animations move them), and the rig's morph weight animations added to the
// original's animation each came from, one channel per level node. Returns the skin index (-1
// without joints). \throw InvalidInput when the rig does not come from this source.
int addSourceRig(Buffer& b, Document& d, const Rig& rig, const SourceScene& src, const std::vector<int>& morphNodes,
                 const std::string& path) {
    if (src.rigNodes.size() != rig.nodes.size() || src.rigAnimations.size() != rig.animations.size())
        throw InvalidInput(path + ": the original's skin and animations (" + src.path + ") are not those of the chain");
    int skin = -1;
    if (!rig.empty()) {
        std::vector<float> ibm;
        ibm.reserve(16 * rig.inverseBind.size());
        for (const Mat4& m : rig.inverseBind)
            for (double e : m) ibm.push_back(float(e));
        const int view = b.addView(ibm.data(), ibm.size() * 4, 0);
        const int accessor = b.addAccessor({{"bufferView", view}, {"componentType", kFloat}, {"count", rig.inverseBind.size()}, {"type", "MAT4"}});
        json joints = json::array();
        for (int j : rig.joints) joints.push_back(src.rigNodes[size_t(j)] + 1);
        skin = int(d.skins.size());
        d.skins.push_back({{"name", "LOD1+"}, {"joints", joints}, {"inverseBindMatrices", accessor}});
    }
    for (size_t ai = 0; ai < rig.animations.size() && !morphNodes.empty(); ++ai) {
        const size_t target = size_t(src.rigAnimations[ai]);
        if (target >= d.animations.size()) throw InvalidInput(path + ": animation " + std::to_string(target) + " of the original is missing");
        appendWeightChannels(b, d.animations[target], rig.animations[ai], morphNodes);
    }
    return skin;
}

std::string lowerExt(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    return e;
}

}  // namespace

LodChainWriteStats writeLodChain(const std::string& path, const std::vector<LodLevelData>& levels,
                                 const std::vector<double>& screenCoverage, const LodChainWriteOptions& options, const Rig* rig,
                                 const MorphTargets* morph, const SceneExtras* scene, const SourceScene* lod0) {
    std::string ext = lowerExt(path);
    bool glb = ext == ".glb";
    if (!glb && ext != ".gltf") throw IOError(path + ": output must end in .glb or .gltf");
    const size_t levelCount = levels.size() + (lod0 ? 1 : 0);
    if (levelCount == 0) throw InvalidInput(path + ": no level to write");
    if (!screenCoverage.empty() && screenCoverage.size() != levelCount)
        throw InvalidInput(path + ": " + std::to_string(screenCoverage.size()) + " screen coverage values for " +
                           std::to_string(levelCount) + " levels");
    for (const LodLevelData& L : levels) checkLevel(path, L);
    const bool skinned = rig && !rig->empty() && !levels.empty() &&
                         std::all_of(levels.begin(), levels.end(), [](const LodLevelData& L) { return !L.joints.empty(); });
    const bool morphed = morph && !morph->empty() && !levels.empty() && std::all_of(levels.begin(), levels.end(), [&](const LodLevelData& L) {
        return L.targetPositions.size() == morph->size();
    });
    if (options.draco && (options.meshopt || options.quantize))
        throw Unsupported(path + ": Draco cannot be combined with meshopt compression or quantization");
    if (options.quantize && (options.quantPositionBits < 1 || options.quantPositionBits > 16))
        throw Unsupported(path + ": position quantisation bits must be in [1, 16]");
    StreamOptions streams;
    streams.meshopt = options.meshopt;
    streams.quantize = options.quantize;
    streams.positionBits = options.quantPositionBits;
    if (options.quantize) streams.grid = positionGrid(levels, options.quantPositionBits);
    // A skinned mesh ignores its node's transform, which is where the position grid lives.
    streams.positionsOnGrid = !skinned && !morphed;

    LodChainWriteStats stats;
    if (skinned && options.quantize) stats.warnings.push_back(path + ": skinned levels keep FLOAT positions (--quantize)");
    else if (morphed && options.quantize) stats.warnings.push_back(path + ": morphed levels keep FLOAT positions (--quantize)");
    if (morphed && options.draco)
        stats.warnings.push_back(path + ": morphed levels are not Draco-compressed (Draco reorders vertices; the morph targets could not follow)");
    Buffer b;
    json root;
    Document doc;
    if (lod0) {
        startWithSource(*lod0, b, doc);
        // The original's own figures come first: the levels' stats are LOD1 onwards.
        stats.levelGeometryBytes.push_back(lod0->geometryBytes);
        stats.levelImageBytes.push_back(lod0->imageBytes);
        stats.levelCacheBefore.push_back({});
        stats.levelCacheAfter.push_back({});
        if (!levels.empty() && (options.draco || options.meshopt || options.quantize))
            stats.warnings.push_back(path + ": LOD0 (the original) is written uncompressed and unquantized");
    }
    json &meshes = doc.meshes, &nodes = doc.nodes, &materials = doc.materials, &textures = doc.textures, &images = doc.images;
    // The baked levels' meshes, materials and samplers follow the original's (none without it).
    // Linear-mipmap-linear minification unless a level keeps other filters: the gutters are sized
    // for the mip levels it uses.
    const size_t meshBase = meshes.size();
    json samplers = doc.samplers;
    std::map<std::tuple<int, int, int>, size_t> samplerOf;  // (min, mag) filter, wrap -> sampler index
    auto samplerFor = [&](int minFilter, int magFilter, bool repeat) {
        const std::tuple<int, int, int> key{minFilter ? minFilter : kLinearMipmapLinear, magFilter ? magFilter : kLinear,
                                            repeat ? kRepeat : kClampToEdge};
        auto it = samplerOf.find(key);
        if (it != samplerOf.end()) return it->second;
        const int wrap = std::get<2>(key);
        samplers.push_back({{"magFilter", std::get<1>(key)}, {"minFilter", std::get<0>(key)}, {"wrapS", wrap}, {"wrapT", wrap}});
        return samplerOf[key] = samplers.size() - 1;
    };
    std::vector<int> levelNodes;
    std::vector<std::pair<std::string, const Image*>> sideImages;
    std::string stem = std::filesystem::path(path).stem().string();
    bool usesEmissiveStrength = false, usesUnlit = false, usesQuantization = false, usesBasisu = false;
    std::vector<std::string> materialExtensionsUsed;  // KHR_materials_clearcoat, ... (with repeats)
    // One material and its textures, images in the order of first use; with `written` (a chain
    // with variants: the level's textures so far), an image equal to one already written there
    // with the same sampler is shared instead of stored again. Adds the new image bytes to
    // `imageBytes`.
    struct WrittenTexture {
        const Image* image;
        size_t sampler, texture;
    };
    std::vector<std::vector<WrittenTexture>> writtenTextures(levels.size());
    std::vector<WrittenTexture> repeatTextures;  // every level's textures of repeating materials (LodMaterial::repeat)
    // With `uniforms` (a part of a split level): the material with those values (material_uniforms.h).
    auto writeMaterial = [&](const LodMaterial& M, const std::string& name, std::vector<WrittenTexture>* written, size_t& imageBytes,
                             const MaterialUniforms* uniforms = nullptr) {
        AlphaMode alphaMode = M.alphaMode;
        double alphaCutoff = M.alphaCutoff;
        bool unlit = M.unlit;
        MaterialExtensions materialExt = M.ext;
        if (uniforms) applyUniforms(*uniforms, alphaMode, alphaCutoff, unlit, materialExt);
        const size_t sampler = samplerFor(M.minFilter, M.magFilter, M.repeat);
        if (M.repeat) written = &repeatTextures;  // one period of a material: the same for every level
        // Adds one texture (and its image) of this level; returns the texture index.
        auto addTexture = [&](const Image& image, const std::string& suffix) {
            if (written)
                for (const WrittenTexture& t : *written)
                    if (t.sampler == sampler && t.image->encoded == image.encoded) return t.texture;
            const size_t index = textures.size();
            std::string mime = sniffImageMime(image.encoded.data(), image.encoded.size());
            if (mime.empty()) mime = "image/png";
            // A KTX2 image only through KHR_texture_basisu (required: there is no PNG fallback).
            if (mime == "image/ktx2") {
                textures.push_back({{"sampler", sampler}, {"extensions", {{kBasisu, {{"source", images.size()}}}}}});
                usesBasisu = true;
            } else {
                textures.push_back({{"source", images.size()}, {"sampler", sampler}});
            }
            const std::string imageName = name + suffix;
            json img = {{"name", imageName}};
            if (glb || options.embedImages) {
                img["bufferView"] = b.addView(image.encoded.data(), image.encoded.size(), 0);
                img["mimeType"] = mime;
            } else {
                std::string file = stem + "_" + imageName + (mime == "image/jpeg" ? ".jpg" : mime == "image/ktx2" ? ".ktx2" : ".png");
                img["uri"] = file;
                sideImages.emplace_back(file, &image);
            }
            imageBytes += image.encoded.size();
            images.push_back(img);
            if (written) written->push_back({&image, sampler, index});
            return index;
    };
    json pbr = {{"metallicFactor", M.metallicFactor}, {"roughnessFactor", M.roughnessFactor}};
    const Vec4& bc = M.baseColorFactor;
    if (bc.x != 1 || bc.y != 1 || bc.z != 1 || bc.w != 1) pbr["baseColorFactor"] = {bc.x, bc.y, bc.z, bc.w};
    json mat = {{"name", name}};
    if (!M.baseColor.encoded.empty()) pbr["baseColorTexture"] = {{"index", addTexture(M.baseColor, "")}};
    if (!M.orm.encoded.empty()) {
        const size_t t = addTexture(M.orm, "_orm");
        if (M.metallicRoughness) pbr["metallicRoughnessTexture"] = {{"index", t}};
        if (M.occlusion) mat["occlusionTexture"] = {{"index", t}};
    }
    if (!M.emissive.encoded.empty()) mat["emissiveTexture"] = {{"index", addTexture(M.emissive, "_emissive")}};
    if (!M.normal.encoded.empty()) mat["normalTexture"] = {{"index", addTexture(M.normal, "_normal")}};
    mat["pbrMetallicRoughness"] = pbr;
    const Vec3& e = M.emissiveFactor;
    if (e.x != 0 || e.y != 0 || e.z != 0) mat["emissiveFactor"] = {e.x, e.y, e.z};
    if (M.emissiveStrength > 1) {
        mat["extensions"][kEmissiveStrength] = {{"emissiveStrength", M.emissiveStrength}};
        usesEmissiveStrength = true;
    }
    if (unlit) {
        mat["extensions"][kUnlit] = json::object();
        usesUnlit = true;
    }
    // The extensions: each of the level's extension images becomes one texture, on first use.
    std::vector<int> extensionTexture(M.extensionImages.size(), -1);
    json ext = mat.contains("extensions") ? mat["extensions"] : json::object();
    bool transform = false;
    writeMaterialExtensions(
        materialExt,
        [&](const TextureRef& r) {
            if (r.texture < 0 || size_t(r.texture) >= M.extensionImages.size()) return -1;
            int& t = extensionTexture[size_t(r.texture)];
            if (t < 0) t = int(addTexture(M.extensionImages[size_t(r.texture)], "_" + M.extensionImages[size_t(r.texture)].name));
            return t;
        },
        ext, materialExtensionsUsed, transform);
    if (!ext.empty()) mat["extensions"] = ext;
    if (alphaMode == AlphaMode::Mask) {
        mat["alphaMode"] = "MASK";
        mat["alphaCutoff"] = alphaCutoff;
    } else if (alphaMode == AlphaMode::Blend) {
        mat["alphaMode"] = "BLEND";
    }
    if (M.doubleSided) mat["doubleSided"] = true;
    return mat;
    };
    // Every level's GPU order and cache figures first, the levels side by side (each level's own
    // work, written in order below).
    std::vector<LodLevelData> optimized(options.optimize ? levels.size() : 0);  // geometry only: the material stays the caller's
    const size_t firstStat = stats.levelCacheBefore.size();  // after the original's, when it leads
    stats.levelCacheBefore.resize(firstStat + levels.size());
    stats.levelCacheAfter.resize(firstStat + levels.size());
    parallelFor(levels.size(), options.threads, [&](size_t i) {
        if (options.optimize) {
            const LodLevelData& src = levels[i];
            LodLevelData& o = optimized[i];
            o.name = src.name;
            o.positions = src.positions;
            o.normals = src.normals;
            o.uvs = src.uvs;
            o.tangents = src.tangents;
            o.joints = src.joints;
            o.weights = src.weights;
            o.targetPositions = src.targetPositions;
            o.targetNormals = src.targetNormals;
            o.targetTangents = src.targetTangents;
            o.indices = src.indices;
            o.parts = src.parts;
            optimizeLevelBuffers(o);
        }
        stats.levelCacheBefore[firstStat + i] = analyzeVertexCache(levels[i]);
        stats.levelCacheAfter[firstStat + i] = analyzeVertexCache(options.optimize ? optimized[i] : levels[i]);
    });
    for (size_t i = 0; i < levels.size(); ++i) {
        const LodLevelData& L = options.optimize ? optimized[i] : levels[i];
        size_t before = b.size;
        std::vector<json> prims;
        if (options.draco && !morphed) {
            if (L.parts.empty()) prims.push_back(dracoPrimitive(b, L, options, path));
            for (size_t p = 0; p < L.parts.size(); ++p) prims.push_back(dracoPrimitive(b, partLevel(L, p), options, path));
        } else {
            PrimitiveStreams ps = gpuPrimitive(b, L, streams);
            prims = std::move(ps.primitives);
            usesQuantization = usesQuantization || ps.quantized;
            if (ps.floatUvFallback)
                stats.warnings.push_back(path + ": level '" + L.name + "' has UVs outside [0,1]: kept FLOAT texture coordinates");
        }
        stats.levelGeometryBytes.push_back(b.size - before);
        // The caller's material (one per part, sharing its textures): side images are written after the loop.
        size_t imageBytes = 0;
        const bool shareTextures = !options.variants.empty() || !L.parts.empty();
        if (L.parts.empty()) {
            prims[0]["material"] = materials.size();
            materials.push_back(writeMaterial(levels[i].material, L.name, shareTextures ? &writtenTextures[i] : nullptr, imageBytes));
        }
        for (size_t p = 0; p < L.parts.size(); ++p) {
            prims[p]["material"] = materials.size();
            materials.push_back(writeMaterial(levels[i].material, p == 0 ? L.name : L.name + "_part" + std::to_string(p), &writtenTextures[i],
                                              imageBytes, &L.parts[p].uniforms));
        }
        json mesh = {{"name", L.name}, {"primitives", prims}};
        if (morphed) addMorphDefaults(mesh, *morph);
        meshes.push_back(mesh);
        stats.levelImageBytes.push_back(imageBytes);
        json node = {{"name", L.name}, {"mesh", meshBase + i}};
        if (options.quantize && !skinned && !morphed) {
            const PositionGrid& g = streams.grid;
            node["translation"] = {g.origin[0], g.origin[1], g.origin[2]};
            node["scale"] = {g.step, g.step, g.step};
        }
        levelNodes.push_back(int(nodes.size()));
        nodes.push_back(node);
    }
    // A split level's variants: per part and variant, its variant material (or its default) with the
    // part's values for that variant; equal (material, values) pairs share one glTF material.
    auto writePartVariants = [&](size_t i) {
        const LodLevelData& L = levels[i];
        json& prims = meshes[meshBase + i]["primitives"];
        for (size_t p = 0; p < L.parts.size(); ++p) {
            const LodPart& part = L.parts[p];
            std::vector<std::pair<int, MaterialUniforms>> written;  // (variant material, values) per index below
            std::vector<size_t> index;
            std::vector<int32_t> table(options.variants.size(), prims[p]["material"].get<int32_t>());
            for (size_t v = 0; v < options.variants.size() && v < L.variantMaterial.size(); ++v) {
                const int m = L.variantMaterial[v];
                const MaterialUniforms& u = v < part.variantUniforms.size() ? part.variantUniforms[v] : part.uniforms;
                if (m < 0 && u == part.uniforms) continue;  // the part's default material
                size_t w = 0;
                while (w < written.size() && !(written[w].first == m && written[w].second == u)) ++w;
                if (w == written.size()) {
                    const LodMaterial& M = m < 0 ? L.material : L.variantMaterials[size_t(m)];
                    size_t imageBytes = 0;
                    index.push_back(materials.size());
                    materials.push_back(writeMaterial(M, L.name + "_" + options.variants[v] + (p == 0 ? "" : "_part" + std::to_string(p)),
                                                      &writtenTextures[i], imageBytes, &u));
                    stats.levelImageBytes[(lod0 ? 1 : 0) + i] += imageBytes;
                    written.push_back({m, u});
                }
                table[v] = int32_t(index[w]);
            }
            prims[p]["extensions"][kMaterialVariants] = primitiveVariantsJson(table);
        }
    };
    // KHR_materials_variants: each level's variant materials after every level's default ones, and
    // every variant mapped explicitly.
    for (size_t i = 0; i < levels.size() && !options.variants.empty(); ++i) {
        const LodLevelData& L = levels[i];
        if (!L.parts.empty()) {
            writePartVariants(i);
            continue;
        }
        std::vector<int32_t> table(options.variants.size(), meshes[meshBase + i]["primitives"][0]["material"].get<int32_t>());
        for (size_t m = 0; m < L.variantMaterials.size(); ++m) {
            size_t first = 0;  // the first variant that uses it names it
            while (first < L.variantMaterial.size() && L.variantMaterial[first] != int(m)) ++first;
            const std::string name = L.name + "_" + (first < options.variants.size() ? options.variants[first] : std::to_string(m));
            size_t imageBytes = 0;
            const size_t index = materials.size();
            materials.push_back(writeMaterial(L.variantMaterials[m], name, &writtenTextures[i], imageBytes));
            stats.levelImageBytes[(lod0 ? 1 : 0) + i] += imageBytes;
            for (size_t v = 0; v < table.size() && v < L.variantMaterial.size(); ++v)
                if (L.variantMaterial[v] == int(m)) table[v] = int32_t(index);
        }
        meshes[meshBase + i]["primitives"][0]["extensions"][kMaterialVariants] = primitiveVariantsJson(table);
    }
    json sceneNodes = json::array({0});
    std::vector<int> morphNodes;  // every level node carries the targets
    if (morphed) morphNodes = levelNodes;
    if (lod0) {
        const int skin = rig && (skinned || morphed) ? addSourceRig(b, doc, *rig, *lod0, morphNodes, path) : -1;
        if (skinned)
            for (int n : levelNodes) nodes[size_t(n)]["skin"] = skin;
    } else if (skinned) {
        for (int n : levelNodes) nodes[size_t(n)]["skin"] = 0;
        for (int r : writeRig(b, root, nodes, *rig, morphNodes)) sceneNodes.push_back(r);
    } else if (morphed && rig) {
        writeAnimations(b, root, *rig, -1, morphNodes);
    }
    if (lod0) {
        if (!doc.skins.empty()) root["skins"] = doc.skins;
        if (!doc.animations.empty()) root["animations"] = doc.animations;
        for (const auto& [key, value] : doc.top.items()) root[key] = value;
    }

    json asset = {{"version", "2.0"}, {"generator", options.generator}};
    if (doc.top.contains("asset")) asset.update(doc.top["asset"]);
    root["asset"] = asset;
    std::vector<std::string> used = doc.used;
    // Lights, cameras and extras: their nodes after the levels' and the rig's, in the scene (the
    // original as LOD0 carries its own, in its hierarchy).
    json sceneJson = {{"nodes", sceneNodes}};
    if (scene && !lod0 && writeSceneExtras(*scene, root, nodes, sceneJson)) used.push_back(kLights);
    if (levelCount > 1) {
        std::vector<int> ids(levelNodes.begin() + (lod0 ? 0 : 1), levelNodes.end());
        nodes[0]["extensions"][kLod] = {{"ids", ids}};
        if (!screenCoverage.empty()) nodes[0]["extras"]["MSFT_screencoverage"] = screenCoverage;
        used.push_back(kLod);
    }
    if (!options.variants.empty() && !levels.empty()) {
        root["extensions"][kMaterialVariants] = variantsRootJson(options.variants);
        used.push_back(kMaterialVariants);
    }
    if (usesEmissiveStrength) used.push_back(kEmissiveStrength);
    if (usesUnlit) used.push_back(kUnlit);
    std::sort(materialExtensionsUsed.begin(), materialExtensionsUsed.end());
    materialExtensionsUsed.erase(std::unique(materialExtensionsUsed.begin(), materialExtensionsUsed.end()), materialExtensionsUsed.end());
    used.insert(used.end(), materialExtensionsUsed.begin(), materialExtensionsUsed.end());
    std::vector<std::string> required = doc.required;
    if (options.draco && !morphed && !levels.empty()) required.push_back(kDraco);
    if (options.meshopt && !levels.empty()) required.push_back(kMeshopt);
    if (usesQuantization) required.push_back(kQuantization);
    if (usesBasisu) required.push_back(kBasisu);
    if (lod0) {  // the original's lists joined with the levels'
        std::sort(required.begin(), required.end());
        required.erase(std::unique(required.begin(), required.end()), required.end());
    }
    if (!required.empty()) {
        used.insert(used.end(), required.begin(), required.end());
        root["extensionsRequired"] = required;
    }
    if (!used.empty()) {
        std::sort(used.begin(), used.end());
        used.erase(std::unique(used.begin(), used.end()), used.end());
        root["extensionsUsed"] = used;
    }
    root["scene"] = 0;
    root["scenes"] = json::array({sceneJson});
    root["nodes"] = nodes;
    root["meshes"] = meshes;
    root["materials"] = materials;
    // Levels of factors only (no channel varies over the surface) have no texture: glTF forbids
    // empty arrays, and a sampler no texture uses is left out too.
    if (!textures.empty()) root["textures"] = textures;
    if (!images.empty()) root["images"] = images;
    // Linear-mipmap-linear minification: the gutters are sized for the mip levels this uses.
    if (!samplers.empty() && !textures.empty()) root["samplers"] = samplers;
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    for (const auto& [file, img] : sideImages) {
        writeFileAtomic((dir / file).string(), std::string(img->encoded.begin(), img->encoded.end()));
        stats.fileBytes += img->encoded.size();
    }
    stats.fileBytes += writeGltfFiles(path, root, b, glb);
    return stats;
}

}  // namespace lodbake
