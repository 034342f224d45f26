// Which channels of the chain's one material vary (baked textures) and which are factors.
#include "lodbake/bake/material_plan.h"

#include <algorithm>
#include <set>

namespace lodbake {
namespace {

bool hasTexture(const TextureRef& r, const Asset& a) { return r.texture >= 0 && size_t(r.texture) < a.textures.size(); }

bool sameVec(Vec4 a, Vec4 b) { return a.x == b.x && a.y == b.y && a.z == b.z && a.w == b.w; }
bool sameVec(Vec3 a, Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// The vertex colours' alpha differs from 1 somewhere.
bool vertexAlpha(const TriMesh& m) {
    return std::any_of(m.wedges.color.begin(), m.wedges.color.end(), [](const Vec4& c) { return c.w < 1; });
}

}  // namespace

MaterialPlan baseColorPlan(MaterialPlan p) {
    p.baseColorTexture = true;
    p.occlusionTexture = p.metallicRoughnessTexture = p.emissiveTexture = p.normalTexture = false;
    p.metallicFactor = 0;
    p.roughnessFactor = 1;
    p.emissiveFactor = {0, 0, 0};
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
    bool anyMask = false, anyBlend = false, anyOpaque = false, anyUnlit = false, allUnlit = true;
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
        anyUnlit |= m->unlit;
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
    if ((anyMask || anyBlend) && anyOpaque)
        p.warnings.push_back("materials mix alpha modes: opaque parts are baked with alpha 1 into one " +
                             std::string(anyBlend ? "BLEND" : "MASK") + " material");
    if (anyMask && anyBlend) p.warnings.push_back("materials mix MASK and BLEND: the chain's material blends");
    if (p.doubleSided && anySingle) {
        p.doubleSided = false;
        p.backFaces = true;
        p.warnings.push_back("materials mix single- and double-sided: the double-sided parts get back faces");
    }
    if (anyUnlit && !allUnlit) p.warnings.push_back("materials mix unlit and lit shading: the chain's material is lit");
    return p;
}

}  // namespace lodbake
