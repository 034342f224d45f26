// KHR_materials_variants, both directions (variants_codec.h).
#include "gltf/variants_codec.h"

#include <map>

#include <tiny_gltf.h>

namespace lodbake::gltf_detail {

using json = nlohmann::json;

namespace {

// The extension object of `o` (a primitive or the root), or null.
const json* variantsExtension(const json& o) {
    if (!o.is_object() || !o.contains("extensions") || !o["extensions"].is_object()) return nullptr;
    const json& e = o["extensions"];
    return e.contains(kMaterialVariants) ? &e[kMaterialVariants] : nullptr;
}

}  // namespace

std::vector<std::string> readVariantNames(const ReadContext& c) {
    std::vector<std::string> names;
    const json* ext = variantsExtension(c.root);
    if (!ext) return names;
    const std::string what = std::string(kMaterialVariants) + ": ";
    if (!ext->is_object() || !ext->contains("variants") || !(*ext)["variants"].is_array()) fail(c, what + "root variants is not an array");
    for (const json& v : (*ext)["variants"]) {
        if (!v.is_object()) fail(c, what + "a variant is not an object");
        std::string name = v.contains("name") && v["name"].is_string() ? v["name"].get<std::string>() : "";
        names.push_back(name.empty() ? "variant " + std::to_string(names.size()) : name);
    }
    return names;
}

int32_t readPrimitiveMapping(const ReadContext& c, int meshIndex, int primIndex, MaterialVariants& variants) {
    if (meshIndex < 0 || !c.root.contains("meshes") || !c.root["meshes"].is_array() || size_t(meshIndex) >= c.root["meshes"].size())
        return -1;
    const json& mesh = c.root["meshes"][size_t(meshIndex)];
    if (!mesh.contains("primitives") || !mesh["primitives"].is_array() || size_t(primIndex) >= mesh["primitives"].size()) return -1;
    const json* ext = variantsExtension(mesh["primitives"][size_t(primIndex)]);
    if (!ext) return -1;
    const std::string what = "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(primIndex) + ": " + kMaterialVariants + ": ";
    if (!ext->is_object() || !ext->contains("mappings") || !(*ext)["mappings"].is_array()) fail(c, what + "mappings is not an array");
    const size_t materials = c.model ? c.model->materials.size() : 0;
    std::vector<int32_t> table(variants.names.size(), -1);
    for (const json& m : (*ext)["mappings"]) {
        if (!m.is_object() || !m.contains("material") || !m["material"].is_number_integer() || !m.contains("variants") ||
            !m["variants"].is_array())
            fail(c, what + "a mapping lacks its material or variants");
        const long long material = m["material"].get<long long>();
        if (material < 0 || size_t(material) >= materials) fail(c, what + "material " + std::to_string(material) + " does not exist");
        for (const json& v : m["variants"]) {
            if (!v.is_number_integer() || v.get<long long>() < 0 || size_t(v.get<long long>()) >= table.size())
                fail(c, what + "variant " + v.dump() + " does not exist");
            table[size_t(v.get<long long>())] = int32_t(material);  // glTF: a variant is in one mapping at most
        }
    }
    return internMapping(variants, table);
}

void assignTriangleMapping(MaterialVariants& variants, size_t first, size_t end, int32_t mapping) {
    if (variants.triangleMapping.size() < end) variants.triangleMapping.resize(end, -1);
    for (size_t f = first; f < end; ++f) variants.triangleMapping[f] = mapping;
}

json variantsRootJson(const std::vector<std::string>& names) {
    json list = json::array();
    for (const std::string& n : names) list.push_back({{"name", n}});
    return {{"variants", list}};
}

json primitiveVariantsJson(const std::vector<int32_t>& table, size_t materialBase) {
    std::map<int32_t, std::vector<size_t>> byMaterial;
    for (size_t v = 0; v < table.size(); ++v)
        if (table[v] >= 0) byMaterial[table[v]].push_back(v);
    if (byMaterial.empty()) return nullptr;
    json mappings = json::array();
    for (const auto& [material, vs] : byMaterial) mappings.push_back({{"material", materialBase + size_t(material)}, {"variants", vs}});
    return {{"mappings", mappings}};
}

}  // namespace lodbake::gltf_detail
