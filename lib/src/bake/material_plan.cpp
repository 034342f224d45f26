// Which channels of the chain's one material vary (baked textures) and which are factors.
#include "lodbake/bake/material_plan.h"

#include "lodbake/bake/draw_split.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <type_traits>

namespace lodbake {
namespace {

bool hasTexture(const TextureRef& r, const Asset& a) { return r.texture >= 0 && size_t(r.texture) < a.textures.size(); }

bool sameVec(Vec4 a, Vec4 b) { return a.x == b.x && a.y == b.y && a.z == b.z && a.w == b.w; }
bool sameVec(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// The vertex colours' alpha differs from 1 somewhere.
bool vertexAlpha(const TriMesh& m) {
    return std::any_of(m.wedges.color.begin(), m.wedges.color.end(), [](const Vec4& c) { return c.w < 1; });
}

// The used materials with the area of their triangles (m2 of the original surface).
struct UsedMaterial {
    const Material* m;
    double area;
};

// Whether a channel of the used materials needs a texture: some material has a texture for it,
// or its value (neutral where the material lacks the extension) differs between them. V is
// double or Vec3; `value(m)` gives a material's value, `texture(m)` its texture (or null);
// `counts` (when given) keeps only the materials where the channel matters.
template <class V, class ValueFn, class TextureFn>
bool channelVaries(const std::vector<UsedMaterial>& mats, const Asset& asset, ValueFn value, TextureFn texture,
                   bool (*counts)(const Material&) = nullptr) {
    const Material* firstMaterial = nullptr;
    for (const UsedMaterial& u : mats)
        if (!counts || counts(*u.m)) {
            firstMaterial = u.m;
            break;
        }
    if (!firstMaterial) return false;
    const V first = value(*firstMaterial);
    for (const UsedMaterial& u : mats) {
        if (counts && !counts(*u.m)) continue;
        const TextureRef* t = texture(*u.m);
        if (t && hasTexture(*t, asset)) return true;
        const V v = value(*u.m);
        if constexpr (std::is_same_v<V, double>) {
            if (v != first) return true;
        } else if (!sameVec(v, first)) {
            return true;
        }
    }
    return false;
}

// The first used material for which `has` holds (the caller knows there is one).
template <class HasFn>
const Material& firstWith(const std::vector<UsedMaterial>& mats, HasFn has) {
    for (const UsedMaterial& u : mats)
        if (has(*u.m)) return *u.m;
    return *mats.front().m;
}

// The extensions' channels and properties of the chain's material (ExtensionPlan).
void planExtensions(const Asset& asset, const std::vector<UsedMaterial>& mats, MaterialPlan& p) {
    // The properties glTF cannot vary per texel: merged over every used material here (the one
    // material a level drawn as one primitive carries); draw_split.h splits where they disagree
    // and warns where a merge remains.
    std::vector<WeightedMaterial> weighted;
    for (const UsedMaterial& u : mats) weighted.push_back({u.m, u.area});
    const MaterialUniforms uniforms = mergeUniforms(weighted, nullptr);
    ExtensionPlan& x = p.ext;
    MaterialExtensions& f = x.factors;
    for (const UsedMaterial& u : mats) {
        const MaterialExtensions& e = u.m->ext;
        f.clearcoat.present |= e.clearcoat.present;
        f.sheen.present |= e.sheen.present;
        f.transmission.present |= e.transmission.present;
        f.volume.present |= e.volume.present;
        f.specular.present |= e.specular.present;
        f.ior.present |= e.ior.present;
        f.iridescence.present |= e.iridescence.present;
        f.anisotropy.present |= e.anisotropy.present;
        f.dispersion.present |= e.dispersion.present;
        f.diffuseTransmission.present |= e.diffuseTransmission.present;
    }
    if (f.anisotropy.present) {
        x.anisotropyTexture = true;
        f.anisotropy.strength = 1;
        f.anisotropy.rotation = 0;
    }
    const MaterialExtensions& e0 = mats.front().m->ext;
    // Values of an absent extension are its struct's defaults, which are the neutral values
    // except where noted below.
    if (f.clearcoat.present) {
        x.clearcoatTexture = channelVaries<double>(mats, asset, [](const Material& m) { return m.ext.clearcoat.factor; },
                                                   [](const Material& m) { return &m.ext.clearcoat.texture; });
        // Roughness matters only under a coat: parts without one take the first coat's, so they
        // do not make it vary (and a renderer never sees a roughness of 0 it did not ask for).
        const Material& coated = firstWith(mats, [](const Material& m) { return m.ext.clearcoat.present; });
        x.clearcoatRoughnessFill = coated.ext.clearcoat.roughnessFactor;
        x.clearcoatRoughnessTexture = channelVaries<double>(
            mats, asset, [](const Material& m) { return m.ext.clearcoat.roughnessFactor; },
            [](const Material& m) { return &m.ext.clearcoat.roughnessTexture; },
            [](const Material& m) { return m.ext.clearcoat.present; });
        f.clearcoat.factor = x.clearcoatTexture ? 1 : e0.clearcoat.factor;
        f.clearcoat.roughnessFactor = x.clearcoatRoughnessTexture ? 1 : x.clearcoatRoughnessFill;
        for (const UsedMaterial& u : mats) x.clearcoatNormalTexture |= hasTexture(u.m->ext.clearcoat.normalTexture, asset);
    }
    if (f.sheen.present) {
        x.sheenColorTexture = channelVaries<Vec3>(mats, asset, [](const Material& m) { return m.ext.sheen.colorFactor; },
                                                  [](const Material& m) { return &m.ext.sheen.colorTexture; });
        // As the clearcoat's roughness: it matters only where there is sheen (three.js divides by
        // the sheen roughness even under a black sheen colour).
        const Material& sheened = firstWith(mats, [](const Material& m) { return m.ext.sheen.present; });
        x.sheenRoughnessFill = sheened.ext.sheen.roughnessFactor;
        x.sheenRoughnessTexture = channelVaries<double>(mats, asset, [](const Material& m) { return m.ext.sheen.roughnessFactor; },
                                                        [](const Material& m) { return &m.ext.sheen.roughnessTexture; },
                                                        [](const Material& m) { return m.ext.sheen.present; });
        f.sheen.colorFactor = x.sheenColorTexture ? Vec3{1, 1, 1} : e0.sheen.colorFactor;
        f.sheen.roughnessFactor = x.sheenRoughnessTexture ? 1 : x.sheenRoughnessFill;
    }
    if (f.transmission.present) {
        x.transmissionTexture = channelVaries<double>(mats, asset, [](const Material& m) { return m.ext.transmission.factor; },
                                                      [](const Material& m) { return &m.ext.transmission.texture; });
        f.transmission.factor = x.transmissionTexture ? 1 : e0.transmission.factor;
    }
    if (f.volume.present) {
        x.thicknessTexture = channelVaries<double>(mats, asset, [](const Material& m) { return m.ext.volume.thicknessFactor; },
                                                   [](const Material& m) { return &m.ext.volume.thicknessTexture; });
        double largest = 0;
        for (const UsedMaterial& u : mats) largest = std::max(largest, u.m->ext.volume.thicknessFactor);
        f.volume.thicknessFactor = x.thicknessTexture ? largest : e0.volume.thicknessFactor;
        f.volume.attenuationDistance = uniforms.attenuationDistance;
        f.volume.attenuationColor = uniforms.attenuationColor;
    }
    if (f.specular.present) {
        x.specularTexture = channelVaries<double>(mats, asset, [](const Material& m) { return m.ext.specular.factor; },
                                                  [](const Material& m) { return &m.ext.specular.texture; });
        x.specularColorTexture = channelVaries<Vec3>(mats, asset, [](const Material& m) { return m.ext.specular.colorFactor; },
                                                     [](const Material& m) { return &m.ext.specular.colorTexture; });
        for (const UsedMaterial& u : mats) {
            const Vec3 c = u.m->ext.specular.colorFactor;
            x.specularColorScale = std::max({x.specularColorScale, c.x, c.y, c.z});
        }
        if (!x.specularColorTexture) x.specularColorScale = 1;
        f.specular.factor = x.specularTexture ? 1 : e0.specular.factor;
        f.specular.colorFactor = x.specularColorTexture ? Vec3{1, 1, 1} * x.specularColorScale : e0.specular.colorFactor;
    }
    if (f.ior.present) f.ior.ior = uniforms.ior;
    if (f.dispersion.present) f.dispersion.dispersion = uniforms.dispersion;
    if (f.iridescence.present) {
        auto has = [](const Material& m) { return m.ext.iridescence.present; };
        x.iridescenceTexture = channelVaries<double>(mats, asset, [](const Material& m) { return m.ext.iridescence.factor; },
                                                     [](const Material& m) { return &m.ext.iridescence.texture; });
        f.iridescence.factor = x.iridescenceTexture ? 1 : e0.iridescence.factor;
        f.iridescence.ior = uniforms.iridescenceIor;
        // The thickness a material shows: [minimum, maximum] with a thickness texture, else the
        // maximum. Parts without iridescence (factor 0) do not count.
        double lo = std::numeric_limits<double>::infinity(), hi = -lo, constant = 0;
        bool varies = false, firstConstant = true;
        for (const UsedMaterial& u : mats) {
            if (!has(*u.m)) continue;
            const IridescenceExtension& i = u.m->ext.iridescence;
            if (hasTexture(i.thicknessTexture, asset)) {
                lo = std::min({lo, i.thicknessMinimum, i.thicknessMaximum});
                hi = std::max({hi, i.thicknessMinimum, i.thicknessMaximum});
                varies = true;
            } else {
                lo = std::min(lo, i.thicknessMaximum);
                hi = std::max(hi, i.thicknessMaximum);
                varies |= !firstConstant && i.thicknessMaximum != constant;
                constant = i.thicknessMaximum;
                firstConstant = false;
            }
        }
        x.iridescenceThicknessTexture = varies;
        f.iridescence.thicknessMinimum = varies ? lo : hi;
        f.iridescence.thicknessMaximum = hi;
    }
    if (f.diffuseTransmission.present) {
        x.diffuseTransmissionTexture = channelVaries<double>(
            mats, asset, [](const Material& m) { return m.ext.diffuseTransmission.factor; },
            [](const Material& m) { return &m.ext.diffuseTransmission.texture; });
        x.diffuseTransmissionColorTexture = channelVaries<Vec3>(
            mats, asset, [](const Material& m) { return m.ext.diffuseTransmission.colorFactor; },
            [](const Material& m) { return &m.ext.diffuseTransmission.colorTexture; });
        f.diffuseTransmission.factor = x.diffuseTransmissionTexture ? 1 : e0.diffuseTransmission.factor;
        f.diffuseTransmission.colorFactor = x.diffuseTransmissionColorTexture ? Vec3{1, 1, 1} : e0.diffuseTransmission.colorFactor;
    }
}

}  // namespace

bool ExtensionPlan::any() const {
    const MaterialExtensions& f = factors;
    return f.clearcoat.present || f.sheen.present || f.transmission.present || f.volume.present || f.specular.present ||
           f.ior.present || f.iridescence.present || f.anisotropy.present || f.dispersion.present || f.diffuseTransmission.present;
}

MaterialPlan baseColorPlan(MaterialPlan p) {
    p.baseColorTexture = true;
    p.occlusionTexture = p.metallicRoughnessTexture = p.emissiveTexture = p.normalTexture = false;
    p.metallicFactor = 0;
    p.roughnessFactor = 1;
    p.emissiveFactor = {0, 0, 0};
    p.ext = {};
    return p;
}

MaterialPlan planMaterial(const Asset& asset) {
    const TriMesh& mesh = asset.mesh;
    std::set<int32_t> used(mesh.triangleMaterial.begin(), mesh.triangleMaterial.end());
    static const Material kDefault;
    std::vector<const Material*> mats;
    for (int32_t i : used)
        mats.push_back(i >= 0 && size_t(i) < asset.materials.size() ? &asset.materials[size_t(i)] : &kDefault);
    MaterialPlan p;
    if (mats.empty()) return p;
    const Material& first = *mats.front();
    p.baseColorFactor = first.baseColorFactor;
    p.metallicFactor = first.metallicFactor;
    p.roughnessFactor = first.roughnessFactor;
    p.emissiveFactor = first.emissiveFactor * first.emissiveStrength;
    p.baseColorTexture = !mesh.wedges.color.empty();
    bool anyMask = false, anyBlend = false, anyOpaque = false, allUnlit = true;
    bool anySingle = false;
    double cutoff = 1;
    for (const Material* m : mats) {
        p.baseColorTexture |= hasTexture(m->baseColor, asset) || !sameVec(m->baseColorFactor, first.baseColorFactor);
        p.occlusionTexture |= hasTexture(m->occlusion, asset) && m->occlusion.scale > 0;
        p.metallicRoughnessTexture |= hasTexture(m->metallicRoughness, asset) || hasTexture(m->specularGlossiness, asset) ||
                                      m->metallicFactor != first.metallicFactor || m->roughnessFactor != first.roughnessFactor;
        p.emissiveTexture |= (hasTexture(m->emissive, asset) && !sameVec(m->emissiveFactor, Vec3{})) ||
                             !sameVec(m->emissiveFactor * m->emissiveStrength, p.emissiveFactor);
        p.normalTexture |= hasTexture(m->normal, asset);
        p.doubleSided |= m->doubleSided;
        anySingle |= !m->doubleSided;
        allUnlit &= m->unlit;
        anyMask |= m->alphaMode == AlphaMode::Mask;
        anyBlend |= m->alphaMode == AlphaMode::Blend;
        anyOpaque |= m->alphaMode == AlphaMode::Opaque;
        if (m->alphaMode == AlphaMode::Mask) cutoff = std::min(cutoff, m->alphaCutoff);
    }
    p.alphaMode = anyBlend ? AlphaMode::Blend : anyMask ? AlphaMode::Mask : AlphaMode::Opaque;
    p.alphaCutoff = anyMask ? cutoff : 0.5;
    if (p.alphaMode != AlphaMode::Opaque) {
        bool varies = vertexAlpha(mesh) || anyOpaque;
        for (const Material* m : mats)
            varies |= m->baseColorFactor.w != first.baseColorFactor.w || hasTexture(m->baseColor, asset);
        p.alphaTexture = varies;
        p.baseColorTexture |= varies;
    }
    if (!p.baseColorTexture && p.alphaMode == AlphaMode::Opaque) p.baseColorFactor.w = 1;
    p.unlit = allUnlit;
    if (p.doubleSided && anySingle) {
        p.doubleSided = false;
        p.backFaces = true;
        p.warnings.push_back("materials mix single- and double-sided: the double-sided parts get back faces");
    }
    if (!p.unlit) {
        std::map<int32_t, double> area;
        for (size_t t = 0; t < mesh.triangleCount(); ++t) {
            const Tri& tri = mesh.triangles[t];
            area[mesh.triangleMaterial[t]] +=
                0.5 * length(cross(mesh.positions[tri[1]] - mesh.positions[tri[0]], mesh.positions[tri[2]] - mesh.positions[tri[0]]));
        }
        std::vector<UsedMaterial> withArea;
        size_t k = 0;
        for (int32_t i : used) withArea.push_back({mats[k++], area[i]});
        planExtensions(asset, withArea, p);
    }
    return p;
}

}  // namespace lodbake
