// glTF 2.0 writer: JSON built with nlohmann::json (sorted keys, so byte-identical output for
// identical input), binary buffer and GLB container written by hand, files replaced atomically.
//
// Pipeline of writeGltf:
//   1. mesh 0 = the original, one primitive per material (vertices = distinct (vertex, wedge)
//      corners in order of first use); meshes 1..n = the multires levels;
//   2. materials, textures, samplers, images (embedded in the buffer);
//   3. LODBAKE_multires extension (multires_codec.cpp) with its arrays as accessors;
//   4. serialise (.glb container, or .gltf + .bin) and rename into place.

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "gltf/gltf_buffer.h"
#include "gltf/gltf_internal.h"
#include "gltf/material_json.h"
#include "gltf/multires_codec.h"
#include "gltf/rig_write.h"
#include "gltf/scene_extras_codec.h"
#include "gltf/variants_codec.h"
#include "lodbake/core/errors.h"
#include "lodbake/gltf/gltf.h"

namespace lodbake {
namespace {

using json = nlohmann::json;
using namespace gltf_detail;

using Writer = BufferBuilder;

Vec3 unitOr(Vec3 n, Vec3 fallback) {
    double l = length(n);
    return (l > 1e-20 && std::isfinite(l)) ? n / l : fallback;
}

// glTF vertex ids of a primitive's distinct (vertex, wedge) corners, in order of first use. A wedge
// is normally used with one vertex only, so ids are indexed by wedge; a wedge met again with another
// vertex goes to a hash map. clear() resets only the wedges the primitive used.
class CornerIds {
public:
    explicit CornerIds(size_t wedges) : byWedge_(wedges, kUnset) {}

    uint32_t id(uint32_t v, uint32_t wd, PrimMap& pm) {
        uint32_t& slot = byWedge_[wd];
        if (slot == kUnset) {
            slot = add(v, wd, pm);
            return slot;
        }
        if (pm.vertex[slot] == v) return slot;
        auto [it, inserted] = other_.emplace((uint64_t(v) << 32) | wd, 0u);
        if (inserted) it->second = add(v, wd, pm);
        return it->second;
    }

    void clear(const PrimMap& pm) {
        for (uint32_t wd : pm.wedge) byWedge_[wd] = kUnset;
        other_.clear();
    }

private:
    static constexpr uint32_t kUnset = 0xFFFFFFFFu;
    static uint32_t add(uint32_t v, uint32_t wd, PrimMap& pm) {
        pm.vertex.push_back(v);
        pm.wedge.push_back(wd);
        return uint32_t(pm.vertex.size() - 1);
    }
    std::vector<uint32_t> byWedge_;
    std::unordered_map<uint64_t, uint32_t> other_;
};

// Writes one mesh (triangles with welded ids and corner wedges, material per triangle); with
// `variants`, one primitive per (material, variant mapping of the triangle) carrying the mapping.
int writeMesh(Writer& w, json& meshes, const TriMesh& src, const MorphTargets& morph, const std::vector<Tri>& tris,
              const std::vector<Tri>& corners, const std::vector<int>& material, const std::string& name, std::vector<PrimMap>* maps,
              const MaterialVariants* variants = nullptr) {
    // Without variants every mapping is -1: the groups (and the file) are those of material alone.
    std::map<std::pair<int, int32_t>, std::vector<uint32_t>> groups;
    for (size_t f = 0; f < tris.size(); ++f) {
        int32_t mapping = variants && f < variants->triangleMapping.size() ? variants->triangleMapping[f] : -1;
        if (mapping >= 0 && size_t(mapping) >= variants->mappings.size()) mapping = -1;
        groups[{material[f], mapping}].push_back(uint32_t(f));
    }
    json prims = json::array();
    const Wedges& W = src.wedges;
    CornerIds ids(W.size());
    for (const auto& [key, faces] : groups) {
        const auto [mat, mapping] = key;
        PrimMap pm;
        pm.material = mat;
        pm.faces = faces;
        std::vector<uint32_t> idx;
        idx.reserve(faces.size() * 3);
        for (uint32_t f : faces)
            for (int k = 0; k < 3; ++k) idx.push_back(ids.id(tris[f][size_t(k)], corners[f][size_t(k)], pm));
        ids.clear(pm);
        size_t n = pm.vertex.size();
        std::vector<float> pos(3 * n);
        for (size_t i = 0; i < n; ++i) {
            const Vec3& p = src.positions[pm.vertex[i]];
            pos[3 * i] = float(p.x); pos[3 * i + 1] = float(p.y); pos[3 * i + 2] = float(p.z);
        }
        json attrs = {{"POSITION", w.addFloat(pos, 3, kArrayBuffer, true)}};
        if (!W.normal.empty()) {
            std::vector<float> a(3 * n);
            for (size_t i = 0; i < n; ++i) {
                Vec3 u = unitOr(W.normal[pm.wedge[i]], Vec3{0, 0, 1});
                a[3 * i] = float(u.x); a[3 * i + 1] = float(u.y); a[3 * i + 2] = float(u.z);
            }
            attrs["NORMAL"] = w.addFloat(a, 3, kArrayBuffer, false);
        }
        if (!W.tangent.empty() && !W.normal.empty()) {
            std::vector<float> a(4 * n);
            for (size_t i = 0; i < n; ++i) {
                const Vec4& t = W.tangent[pm.wedge[i]];
                Vec3 u = unitOr(Vec3{t.x, t.y, t.z}, Vec3{1, 0, 0});
                a[4 * i] = float(u.x); a[4 * i + 1] = float(u.y); a[4 * i + 2] = float(u.z); a[4 * i + 3] = t.w < 0 ? -1.f : 1.f;
            }
            attrs["TANGENT"] = w.addFloat(a, 4, kArrayBuffer, false);
        }
        auto uvs = [&](const std::vector<Vec2>& uv, const char* key) {
            if (uv.empty()) return;
            std::vector<float> a(2 * n);
            for (size_t i = 0; i < n; ++i) { a[2 * i] = float(uv[pm.wedge[i]].x); a[2 * i + 1] = float(uv[pm.wedge[i]].y); }
            attrs[key] = w.addFloat(a, 2, kArrayBuffer, false);
        };
        uvs(W.uv0, "TEXCOORD_0");
        uvs(W.uv1, "TEXCOORD_1");
        if (!W.color.empty()) {
            std::vector<float> a(4 * n);
            for (size_t i = 0; i < n; ++i) {
                const Vec4& c = W.color[pm.wedge[i]];
                double v[4] = {c.x, c.y, c.z, c.w};
                for (int k = 0; k < 4; ++k) a[4 * i + size_t(k)] = float(std::isfinite(v[k]) ? std::clamp(v[k], 0.0, 1.0) : 1.0);
            }
            attrs["COLOR_0"] = w.addFloat(a, 4, kArrayBuffer, false);
        }
        if (!W.joints.empty() && W.weights.size() == W.joints.size()) {
            std::vector<uint16_t> j(4 * n);
            std::vector<float> a(4 * n);
            for (size_t i = 0; i < n; ++i) {
                const Vec4& q = W.weights[pm.wedge[i]];
                for (size_t k = 0; k < 4; ++k) j[4 * i + k] = W.joints[pm.wedge[i]][k];
                a[4 * i] = float(q.x); a[4 * i + 1] = float(q.y); a[4 * i + 2] = float(q.z); a[4 * i + 3] = float(q.w);
            }
            addInfluences(w, attrs, j, a);
        }
        json prim = {{"attributes", attrs}, {"indices", w.addIndices(idx, n)}, {"mode", 4}};
        if (mat >= 0) prim["material"] = mat;
        if (mapping >= 0) prim["extensions"][kMaterialVariants] = primitiveVariantsJson(variants->mappings[size_t(mapping)]);
        if (!morph.empty() && W.targets.size() == morph.size()) {
            std::vector<std::vector<float>> dp(morph.size()), dn(morph.size()), dt(morph.size());
            auto gather = [&](const std::vector<Vec3>& d, std::vector<float>& out) {
                out.resize(3 * n);
                for (size_t i = 0; i < n; ++i) {
                    const Vec3& v = d[pm.wedge[i]];
                    out[3 * i] = float(v.x); out[3 * i + 1] = float(v.y); out[3 * i + 2] = float(v.z);
                }
            };
            for (size_t t = 0; t < morph.size(); ++t) {
                const MorphDeltas& D = W.targets[t];
                gather(D.position, dp[t]);
                if (!D.normal.empty() && attrs.contains("NORMAL")) gather(D.normal, dn[t]);
                if (!D.tangent.empty() && attrs.contains("TANGENT")) gather(D.tangent, dt[t]);
            }
            addMorphTargets(w, prim, dp, dn, dt);
        }
        prims.push_back(prim);
        if (maps) maps->push_back(std::move(pm));
    }
    if (prims.empty()) return -1;
    json mesh = {{"primitives", prims}};
    if (!name.empty()) mesh["name"] = name;
    if (W.targets.size() == morph.size()) addMorphDefaults(mesh, morph);
    meshes.push_back(mesh);
    return int(meshes.size()) - 1;
}

// The material extensions a file uses, for extensionsUsed.
struct UsedMaterialExtensions {
    bool unlit = false, emissiveStrength = false, specularGlossiness = false;
    std::vector<std::string> khr;  // KHR_materials_clearcoat, ... (writeMaterialExtensions)
};

json materialJson(const Material& m, size_t textureCount, bool& usedTransform, UsedMaterialExtensions& used) {
    auto valid = [&](const TextureRef& r) { return r.texture >= 0 && size_t(r.texture) < textureCount; };
    json pbr = {{"baseColorFactor", {m.baseColorFactor.x, m.baseColorFactor.y, m.baseColorFactor.z, m.baseColorFactor.w}},
                {"metallicFactor", m.metallicFactor},
                {"roughnessFactor", m.roughnessFactor}};
    if (valid(m.baseColor)) pbr["baseColorTexture"] = textureRefJson(m.baseColor, m.baseColor.texture, nullptr, usedTransform);
    if (valid(m.metallicRoughness)) pbr["metallicRoughnessTexture"] = textureRefJson(m.metallicRoughness, m.metallicRoughness.texture, nullptr, usedTransform);
    json o = {{"pbrMetallicRoughness", pbr}};
    if (!m.name.empty()) o["name"] = m.name;
    if (valid(m.normal)) o["normalTexture"] = textureRefJson(m.normal, m.normal.texture, "scale", usedTransform);
    if (valid(m.occlusion)) o["occlusionTexture"] = textureRefJson(m.occlusion, m.occlusion.texture, "strength", usedTransform);
    if (valid(m.emissive)) o["emissiveTexture"] = textureRefJson(m.emissive, m.emissive.texture, nullptr, usedTransform);
    if (m.emissiveFactor.x != 0 || m.emissiveFactor.y != 0 || m.emissiveFactor.z != 0)
        o["emissiveFactor"] = {m.emissiveFactor.x, m.emissiveFactor.y, m.emissiveFactor.z};
    if (m.alphaMode == AlphaMode::Mask) { o["alphaMode"] = "MASK"; o["alphaCutoff"] = m.alphaCutoff; }
    if (m.alphaMode == AlphaMode::Blend) o["alphaMode"] = "BLEND";
    if (m.doubleSided) o["doubleSided"] = true;
    if (m.unlit) { o["extensions"]["KHR_materials_unlit"] = json::object(); used.unlit = true; }
    if (m.emissiveStrength != 1) {
        o["extensions"]["KHR_materials_emissive_strength"] = {{"emissiveStrength", m.emissiveStrength}};
        used.emissiveStrength = true;
    }
    if (valid(m.specularGlossiness)) {
        // Converted on reading (metallic 0, roughness 1 - glossiness); the texture's alpha still
        // carries the glossiness, so the extension travels with the intermediate files.
        json sg = {{"glossinessFactor", m.glossinessFactor},
                   {"specularGlossinessTexture", textureRefJson(m.specularGlossiness, m.specularGlossiness.texture, nullptr, usedTransform)}};
        o["extensions"]["KHR_materials_pbrSpecularGlossiness"] = sg;
        used.specularGlossiness = true;
    }
    json ext = o.contains("extensions") ? o["extensions"] : json::object();
    writeMaterialExtensions(m.ext, [&](const TextureRef& r) { return valid(r) ? r.texture : -1; }, ext, used.khr, usedTransform);
    if (!ext.empty()) o["extensions"] = ext;
    return o;
}

std::string lowerExt(const std::string& path) {
    std::string e = std::filesystem::path(path).extension().string();
    std::transform(e.begin(), e.end(), e.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
    return e;
}

}  // namespace

void writeFileAtomic(const std::string& path, const std::string& bytes) { writeFileAtomic(path, {std::string_view(bytes)}); }

void writeFileAtomic(const std::string& path, const std::vector<std::string_view>& parts) {
    std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    try {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) throw IOError(path + ": cannot write: " + std::strerror(errno));
        for (std::string_view part : parts) f.write(part.data(), std::streamsize(part.size()));
        f.close();
        if (!f) throw IOError(path + ": cannot write: " + std::strerror(errno));
        if (std::rename(tmp.c_str(), path.c_str()) != 0) throw IOError(path + ": cannot rename temporary file: " + std::strerror(errno));
    } catch (...) {
        std::remove(tmp.c_str());
        throw;
    }
}

namespace {

// writeGltf, or with `memory` encodeGlb.
void writeGltfTo(const std::string& path, const Asset& asset, const Multires* multires, const WriteOptions& options,
                 std::vector<unsigned char>* memory) {
    std::string ext = lowerExt(path);
    bool glb = ext == ".glb";
    if (!glb && ext != ".gltf") throw IOError(path + ": output must end in .glb or .gltf");
    const TriMesh& mesh = asset.mesh;
    Writer w;
    json root;
    root["asset"] = {{"version", "2.0"}, {"generator", options.generator}};
    std::vector<std::string> used;

    // 1. Meshes and nodes.
    size_t nMat = asset.materials.size();
    auto materialsOf = [&](const std::vector<uint32_t>* faces, size_t n) {
        std::vector<int> m(n, -1);
        for (size_t i = 0; i < n; ++i) {
            size_t f = faces ? (*faces)[i] : i;
            int x = f < mesh.triangleMaterial.size() ? mesh.triangleMaterial[f] : -1;
            m[i] = (x >= 0 && size_t(x) < nMat) ? x : -1;
        }
        return m;
    };
    json meshes = json::array(), nodes = json::array(), sceneNodes = json::array();
    WrittenMeshes written;
    const int originalMesh = writeMesh(w, meshes, mesh, asset.morph, mesh.triangles, mesh.cornerWedges,
                                       materialsOf(nullptr, mesh.triangleCount()), "original", &written.originalPrims,
                                       asset.variants.empty() ? nullptr : &asset.variants);
    written.originalMesh = originalMesh;
    // A skinned mesh is posed by its joints (the node's own transform is ignored), so with a rig
    // every mesh node uses the skin and the levels stay in place instead of side by side.
    const bool skinned = !asset.rig.empty() && mesh.wedges.joints.size() == mesh.wedges.size();
    json node0 = {{"name", "original"}};
    if (originalMesh >= 0) node0["mesh"] = originalMesh;
    if (skinned && originalMesh >= 0) node0["skin"] = 0;
    nodes.push_back(node0);
    sceneNodes.push_back(0);
    if (multires) {
        Box3 b = bounds(mesh);
        double width = b.empty() ? 1.0 : b.max.x - b.min.x;
        if (!(width > 0)) width = b.longestSide() > 0 ? b.longestSide() : 1.0;
        for (size_t i = 0; i < multires->levels.size(); ++i) {
            const Level& L = multires->levels[i];
            for (const Tri& t : L.triangles)
                for (uint32_t v : t)
                    if (v >= mesh.vertexCount()) throw InvalidInput(path + ": level " + std::to_string(i + 1) + " refers to a missing vertex");
            for (const Tri& t : L.cornerWedges)
                for (uint32_t v : t)
                    if (v >= mesh.wedges.size()) throw InvalidInput(path + ": level " + std::to_string(i + 1) + " refers to a missing wedge");
            if (L.cornerWedges.size() != L.triangles.size() || L.faces.size() != L.triangles.size())
                throw InvalidInput(path + ": level " + std::to_string(i + 1) + ": faces/triangles/cornerWedges sizes differ");
            std::string name = "level" + std::to_string(i + 1);
            std::vector<int> levelMaterials = materialsOf(&L.faces, L.faces.size());
            if (L.triangleMaterial.size() == L.triangles.size())  // per-level override (parameterize's atlas material)
                for (size_t t = 0; t < levelMaterials.size(); ++t) {
                    int x = L.triangleMaterial[t];
                    levelMaterials[t] = (x >= 0 && size_t(x) < nMat) ? x : -1;
                }
            written.levelPrims.emplace_back();
            int mi = writeMesh(w, meshes, mesh, asset.morph, L.triangles, L.cornerWedges, levelMaterials, name, &written.levelPrims.back());
            written.levelMeshes.push_back(mi);
            json n = {{"name", name}};
            if (!skinned) n["translation"] = {double(i + 1) * 1.25 * width, 0.0, 0.0};
            if (mi >= 0) n["mesh"] = mi;
            if (skinned && mi >= 0) n["skin"] = 0;
            nodes.push_back(n);
            sceneNodes.push_back(i + 1);
        }
    }
    std::vector<int> morphNodes;  // every node with a mesh carries the targets
    if (!asset.morph.empty())
        for (size_t i = 0; i < nodes.size(); ++i)
            if (nodes[i].contains("mesh")) morphNodes.push_back(int(i));
    if (skinned)
        for (int r : writeRig(w, root, nodes, asset.rig, morphNodes)) sceneNodes.push_back(r);
    else if (!morphNodes.empty())
        writeAnimations(w, root, asset.rig, -1, morphNodes);
    // Lights, cameras and extras: their nodes after the meshes' and the rig's.
    json scene = {{"nodes", sceneNodes}};
    if (writeSceneExtras(asset.scene, root, nodes, scene)) used.push_back("KHR_lights_punctual");
    root["scene"] = 0;
    root["scenes"] = json::array({scene});
    root["nodes"] = nodes;
    if (!meshes.empty()) root["meshes"] = meshes;

    // 2. Materials, textures, samplers, images.
    bool usedTransform = false;
    UsedMaterialExtensions usedMaterial;
    if (!asset.materials.empty()) {
        json mats = json::array();
        for (const Material& m : asset.materials) mats.push_back(materialJson(m, asset.textures.size(), usedTransform, usedMaterial));
        root["materials"] = mats;
    }
    if (!asset.textures.empty()) {
        json texs = json::array();
        for (const Texture& t : asset.textures) {
            json o = json::object();
            if (t.image >= 0 && size_t(t.image) < asset.images.size()) o["source"] = t.image;
            if (t.sampler >= 0 && size_t(t.sampler) < asset.samplers.size()) o["sampler"] = t.sampler;
            texs.push_back(o);
        }
        root["textures"] = texs;
    }
    if (!asset.samplers.empty()) {
        json smps = json::array();
        for (const Sampler& s : asset.samplers) {
            json o = {{"wrapS", s.wrapS}, {"wrapT", s.wrapT}};
            if (s.magFilter) o["magFilter"] = s.magFilter;
            if (s.minFilter) o["minFilter"] = s.minFilter;
            smps.push_back(o);
        }
        root["samplers"] = smps;
    }
    std::vector<std::pair<std::string, const Image*>> sideImages;
    if (!asset.images.empty()) {
        json imgs = json::array();
        for (size_t i = 0; i < asset.images.size(); ++i) {
            const Image& img = asset.images[i];
            std::string mime = sniffImageMime(img.encoded.data(), img.encoded.size());
            if (mime.empty()) mime = img.mimeType.empty() ? "image/png" : img.mimeType;
            json o = json::object();
            if (!img.name.empty()) o["name"] = img.name;
            if (options.embedImages || img.encoded.empty()) {
                o["bufferView"] = w.addView(img.encoded.data(), img.encoded.size(), 0);
                o["mimeType"] = mime;
            } else {
                std::string file = std::filesystem::path(path).stem().string() + "_image" + std::to_string(i) +
                                   (mime == "image/jpeg" ? ".jpg" : ".png");
                o["uri"] = file;
                sideImages.emplace_back(file, &img);
            }
            imgs.push_back(o);
        }
        root["images"] = imgs;
    }
    if (usedTransform) used.push_back("KHR_texture_transform");
    if (usedMaterial.unlit) used.push_back("KHR_materials_unlit");
    if (usedMaterial.emissiveStrength) used.push_back("KHR_materials_emissive_strength");
    if (usedMaterial.specularGlossiness) used.push_back("KHR_materials_pbrSpecularGlossiness");
    std::sort(usedMaterial.khr.begin(), usedMaterial.khr.end());
    usedMaterial.khr.erase(std::unique(usedMaterial.khr.begin(), usedMaterial.khr.end()), usedMaterial.khr.end());
    used.insert(used.end(), usedMaterial.khr.begin(), usedMaterial.khr.end());

    if (!asset.variants.empty()) {
        root["extensions"][kMaterialVariants] = variantsRootJson(asset.variants.names);
        used.push_back(kMaterialVariants);
    }

    // 3. LODBAKE_multires.
    if (multires) {
        root["extensions"][kMultiresExtension] = writeMultires(w, asset, *multires, written, options);
        used.push_back(kMultiresExtension);
    }
    if (!used.empty()) {
        std::sort(used.begin(), used.end());
        root["extensionsUsed"] = used;
    }

    // 4. Buffer and container.
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    for (const auto& [file, img] : sideImages)
        writeFileAtomic((dir / file).string(), std::string(img->encoded.begin(), img->encoded.end()));
    writeGltfFiles(path, root, w, glb, memory);
}

}  // namespace

void writeGltf(const std::string& path, const Asset& asset, const Multires* multires, const WriteOptions& options) {
    writeGltfTo(path, asset, multires, options, nullptr);
}

std::vector<unsigned char> encodeGlb(const std::string& path, const Asset& asset, const Multires* multires,
                                     const WriteOptions& options) {
    if (lowerExt(path) != ".glb") throw IOError(path + ": in-memory glTF must be a .glb");
    WriteOptions embedded = options;
    embedded.embedImages = true;
    std::vector<unsigned char> bytes;
    writeGltfTo(path, asset, multires, embedded, &bytes);
    return bytes;
}

}  // namespace lodbake
