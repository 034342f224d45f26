// Texture references and KHR_materials_* extensions <-> glTF JSON (see material_json.h). One
// field list (visitExtensions) drives both directions, so what is written is what is read.
#include "gltf/material_json.h"

#include <algorithm>
#include <cmath>

#include "gltf/gltf_read_context.h"

namespace lodbake::gltf_detail {
namespace {

using json = nlohmann::json;

// Every field of every extension lodbake reads, in the glTF names. `v` is a reader or a writer;
// E is MaterialExtensions (reading) or const MaterialExtensions (writing).
template <class E, class V>
void visitExtensions(E& e, V& v) {
    if (v.begin("KHR_materials_clearcoat", e.clearcoat.present)) {
        v.number("clearcoatFactor", e.clearcoat.factor);
        v.texture("clearcoatTexture", e.clearcoat.texture, nullptr);
        v.number("clearcoatRoughnessFactor", e.clearcoat.roughnessFactor);
        v.texture("clearcoatRoughnessTexture", e.clearcoat.roughnessTexture, nullptr);
        v.texture("clearcoatNormalTexture", e.clearcoat.normalTexture, "scale");
    }
    if (v.begin("KHR_materials_sheen", e.sheen.present)) {
        v.vec3("sheenColorFactor", e.sheen.colorFactor);
        v.texture("sheenColorTexture", e.sheen.colorTexture, nullptr);
        v.number("sheenRoughnessFactor", e.sheen.roughnessFactor);
        v.texture("sheenRoughnessTexture", e.sheen.roughnessTexture, nullptr);
    }
    if (v.begin("KHR_materials_transmission", e.transmission.present)) {
        v.number("transmissionFactor", e.transmission.factor);
        v.texture("transmissionTexture", e.transmission.texture, nullptr);
    }
    if (v.begin("KHR_materials_volume", e.volume.present)) {
        v.number("thicknessFactor", e.volume.thicknessFactor);
        v.texture("thicknessTexture", e.volume.thicknessTexture, nullptr);
        v.number("attenuationDistance", e.volume.attenuationDistance);
        v.vec3("attenuationColor", e.volume.attenuationColor);
    }
    if (v.begin("KHR_materials_specular", e.specular.present)) {
        v.number("specularFactor", e.specular.factor);
        v.texture("specularTexture", e.specular.texture, nullptr);
        v.vec3("specularColorFactor", e.specular.colorFactor);
        v.texture("specularColorTexture", e.specular.colorTexture, nullptr);
    }
    if (v.begin("KHR_materials_ior", e.ior.present)) v.number("ior", e.ior.ior);
    if (v.begin("KHR_materials_iridescence", e.iridescence.present)) {
        v.number("iridescenceFactor", e.iridescence.factor);
        v.texture("iridescenceTexture", e.iridescence.texture, nullptr);
        v.number("iridescenceIor", e.iridescence.ior);
        v.number("iridescenceThicknessMinimum", e.iridescence.thicknessMinimum);
        v.number("iridescenceThicknessMaximum", e.iridescence.thicknessMaximum);
        v.texture("iridescenceThicknessTexture", e.iridescence.thicknessTexture, nullptr);
    }
    if (v.begin("KHR_materials_anisotropy", e.anisotropy.present)) {
        v.number("anisotropyStrength", e.anisotropy.strength);
        v.number("anisotropyRotation", e.anisotropy.rotation);
        v.texture("anisotropyTexture", e.anisotropy.texture, nullptr);
    }
    if (v.begin("KHR_materials_dispersion", e.dispersion.present)) v.number("dispersion", e.dispersion.dispersion);
    if (v.begin("KHR_materials_diffuse_transmission", e.diffuseTransmission.present)) {
        v.number("diffuseTransmissionFactor", e.diffuseTransmission.factor);
        v.texture("diffuseTransmissionTexture", e.diffuseTransmission.texture, nullptr);
        v.vec3("diffuseTransmissionColorFactor", e.diffuseTransmission.colorFactor);
        v.texture("diffuseTransmissionColorTexture", e.diffuseTransmission.colorTexture, nullptr);
    }
}

// Reads fields; a field absent or of the wrong type keeps the extension's default.
struct Reader {
    const json& extensions;
    const json* o = nullptr;
    bool begin(const char* name, bool& present) {
        present = extensions.is_object() && extensions.contains(name) && extensions[name].is_object();
        o = present ? &extensions[name] : nullptr;
        return present;
    }
    void number(const char* key, double& x) {
        if (o->contains(key) && (*o)[key].is_number()) x = (*o)[key].get<double>();
    }
    void vec3(const char* key, Vec3& x) {
        const json* a = o->contains(key) ? &(*o)[key] : nullptr;
        if (a && a->is_array() && a->size() == 3 && (*a)[0].is_number() && (*a)[1].is_number() && (*a)[2].is_number())
            x = {(*a)[0].get<double>(), (*a)[1].get<double>(), (*a)[2].get<double>()};
    }
    void texture(const char* key, TextureRef& r, const char* scaleKey) {
        if (o->contains(key)) r = readTextureRef((*o)[key], scaleKey);
    }
};

// Writes every field of a present extension (infinite numbers, glTF's "absent", are left out).
struct Writer {
    const std::function<int(const TextureRef&)>& textureIndex;
    json& extensions;
    std::vector<std::string>& used;
    bool& usedTransform;
    json* o = nullptr;
    bool begin(const char* name, bool present) {
        if (!present) return false;
        extensions[name] = json::object();
        o = &extensions[name];
        used.push_back(name);
        return true;
    }
    void number(const char* key, double x) {
        if (std::isfinite(x)) (*o)[key] = x;
    }
    void vec3(const char* key, Vec3 x) { (*o)[key] = {x.x, x.y, x.z}; }
    void texture(const char* key, const TextureRef& r, const char* scaleKey) {
        const int index = r.texture >= 0 ? textureIndex(r) : -1;
        if (index >= 0) (*o)[key] = textureRefJson(r, index, scaleKey, usedTransform);
    }
};

}  // namespace

TextureRef readTextureRef(const json& o, const char* scaleKey) {
    TextureRef r;
    if (!o.is_object()) return r;
    r.texture = jint(o, "index", -1);
    r.texCoord = jint(o, "texCoord", 0);
    if (scaleKey && o.contains(scaleKey) && o[scaleKey].is_number()) r.scale = o[scaleKey].get<double>();
    if (o.contains("extensions") && o["extensions"].is_object() && o["extensions"].contains("KHR_texture_transform")) {
        const json& t = o["extensions"]["KHR_texture_transform"];
        TextureTransform& x = r.transform;
        x.present = true;
        if (t.contains("offset") && t["offset"].is_array() && t["offset"].size() == 2) x.offset = {t["offset"][0].get<double>(), t["offset"][1].get<double>()};
        if (t.contains("scale") && t["scale"].is_array() && t["scale"].size() == 2) x.scale = {t["scale"][0].get<double>(), t["scale"][1].get<double>()};
        if (t.contains("rotation") && t["rotation"].is_number()) x.rotation = t["rotation"].get<double>();
        x.texCoord = jint(t, "texCoord", -1);
    }
    return r;
}

json textureRefJson(const TextureRef& r, int index, const char* scaleKey, bool& usedTransform) {
    json o = {{"index", index}};
    if (r.texCoord != 0) o["texCoord"] = r.texCoord;
    if (scaleKey && r.scale != 1) o[scaleKey] = r.scale;
    if (r.transform.present) {
        const TextureTransform& t = r.transform;
        json x = json::object();
        if (t.offset.x != 0 || t.offset.y != 0) x["offset"] = {t.offset.x, t.offset.y};
        if (t.rotation != 0) x["rotation"] = t.rotation;
        if (t.scale.x != 1 || t.scale.y != 1) x["scale"] = {t.scale.x, t.scale.y};
        if (t.texCoord >= 0) x["texCoord"] = t.texCoord;
        o["extensions"]["KHR_texture_transform"] = x;
        usedTransform = true;
    }
    return o;
}

const std::vector<std::string>& readMaterialExtensionNames() {
    struct Names {
        std::vector<std::string> list;
        bool begin(const char* name, bool) {
            list.push_back(name);
            return false;
        }
        void number(const char*, double) {}
        void vec3(const char*, Vec3) {}
        void texture(const char*, const TextureRef&, const char*) {}
    };
    static const std::vector<std::string> names = [] {
        Names n;
        const MaterialExtensions e;
        visitExtensions(e, n);
        std::sort(n.list.begin(), n.list.end());
        return n.list;
    }();
    return names;
}

MaterialExtensions readMaterialExtensions(const json& extensions) {
    MaterialExtensions e;
    Reader r{extensions};
    visitExtensions(e, r);
    return e;
}

void writeMaterialExtensions(const MaterialExtensions& e, const std::function<int(const TextureRef&)>& textureIndex,
                             json& extensions, std::vector<std::string>& used, bool& usedTransform) {
    Writer w{textureIndex, extensions, used, usedTransform};
    visitExtensions(e, w);
}

}  // namespace lodbake::gltf_detail
