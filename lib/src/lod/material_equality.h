// Field-by-field equality of materials and their parts, for sharing what two materials would
// make alike (a variant's images, LOD0's source texels).
#pragma once

#include <tuple>
#include <vector>

#include "lodbake/core/material_extensions.h"
#include "lodbake/core/mesh.h"

namespace lodbake::lod_detail {

inline bool sameRef(const TextureRef& a, const TextureRef& b) {
    const TextureTransform &s = a.transform, &t = b.transform;
    return std::tie(a.texture, a.texCoord, a.scale, s.present, s.offset.x, s.offset.y, s.rotation, s.scale.x, s.scale.y, s.texCoord) ==
           std::tie(b.texture, b.texCoord, b.scale, t.present, t.offset.x, t.offset.y, t.rotation, t.scale.x, t.scale.y, t.texCoord);
}

inline bool sameVec3(const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

// Field by field: the writer's JSON of two materials that compare equal is the same.
inline bool sameExtensions(const MaterialExtensions& a, const MaterialExtensions& b) {
    const ClearcoatExtension &cA = a.clearcoat, &cB = b.clearcoat;
    const SheenExtension &sA = a.sheen, &sB = b.sheen;
    const VolumeExtension &vA = a.volume, &vB = b.volume;
    const SpecularExtension &pA = a.specular, &pB = b.specular;
    const IridescenceExtension &iA = a.iridescence, &iB = b.iridescence;
    const AnisotropyExtension &nA = a.anisotropy, &nB = b.anisotropy;
    const DiffuseTransmissionExtension &dA = a.diffuseTransmission, &dB = b.diffuseTransmission;
    return cA.present == cB.present && cA.factor == cB.factor && sameRef(cA.texture, cB.texture) && cA.roughnessFactor == cB.roughnessFactor &&
           sameRef(cA.roughnessTexture, cB.roughnessTexture) && sameRef(cA.normalTexture, cB.normalTexture) &&
           sA.present == sB.present && sameVec3(sA.colorFactor, sB.colorFactor) && sameRef(sA.colorTexture, sB.colorTexture) &&
           sA.roughnessFactor == sB.roughnessFactor && sameRef(sA.roughnessTexture, sB.roughnessTexture) &&
           a.transmission.present == b.transmission.present && a.transmission.factor == b.transmission.factor &&
           sameRef(a.transmission.texture, b.transmission.texture) &&
           vA.present == vB.present && vA.thicknessFactor == vB.thicknessFactor && sameRef(vA.thicknessTexture, vB.thicknessTexture) &&
           vA.attenuationDistance == vB.attenuationDistance && sameVec3(vA.attenuationColor, vB.attenuationColor) &&
           pA.present == pB.present && pA.factor == pB.factor && sameRef(pA.texture, pB.texture) && sameVec3(pA.colorFactor, pB.colorFactor) &&
           sameRef(pA.colorTexture, pB.colorTexture) &&
           a.ior.present == b.ior.present && a.ior.ior == b.ior.ior &&
           iA.present == iB.present && iA.factor == iB.factor && sameRef(iA.texture, iB.texture) && iA.ior == iB.ior &&
           iA.thicknessMinimum == iB.thicknessMinimum && iA.thicknessMaximum == iB.thicknessMaximum &&
           sameRef(iA.thicknessTexture, iB.thicknessTexture) &&
           nA.present == nB.present && nA.strength == nB.strength && nA.rotation == nB.rotation && sameRef(nA.texture, nB.texture) &&
           a.dispersion.present == b.dispersion.present && a.dispersion.dispersion == b.dispersion.dispersion &&
           dA.present == dB.present && dA.factor == dB.factor && sameRef(dA.texture, dB.texture) && sameVec3(dA.colorFactor, dB.colorFactor) &&
           sameRef(dA.colorTexture, dB.colorTexture);
}

// Per texture: the first texture of `textures` with its image and sampler (they read alike).
inline std::vector<int> canonicalTextures(const std::vector<Texture>& textures) {
    std::vector<int> first(textures.size());
    for (size_t t = 0; t < textures.size(); ++t) {
        first[t] = int(t);
        for (size_t u = 0; u < t; ++u)
            if (textures[u].image == textures[t].image && textures[u].sampler == textures[t].sampler) { first[t] = int(u); break; }
    }
    return first;
}

// Two materials whose texels shade alike: equal in every field a texel of the page holds (core
// factors and texture references, every extension's; textures compared by image and sampler
// through `canonical`, from canonicalTextures), whatever their names and the properties glTF
// cannot vary per texel (alpha mode and cutoff, double-sidedness, ior, attenuation, dispersion,
// iridescence ior), which the chain keeps per primitive (draw_split.h).
inline bool sameTexelShading(const Material& a, const Material& b, const std::vector<int>& canonical) {
    auto perTexel = [&](Material m) {
        m.name.clear();
        m.alphaMode = AlphaMode::Opaque;
        m.alphaCutoff = 0.5;
        m.doubleSided = false;
        m.ext.ior = {};
        m.ext.volume.attenuationDistance = 0;
        m.ext.volume.attenuationColor = {0, 0, 0};
        m.ext.dispersion = {};
        m.ext.iridescence.ior = 0;
        std::vector<TextureRef*> refs = {&m.baseColor, &m.metallicRoughness, &m.normal, &m.occlusion, &m.emissive, &m.specularGlossiness};
        for (const TextureRef* r : textureRefs(m.ext)) refs.push_back(const_cast<TextureRef*>(r));  // m is this copy
        for (TextureRef* r : refs)
            if (r->texture >= 0 && size_t(r->texture) < canonical.size()) r->texture = canonical[size_t(r->texture)];
        return m;
    };
    const Material x = perTexel(a), y = perTexel(b);
    const Vec4 &f = x.baseColorFactor, &g = y.baseColorFactor;
    return f.x == g.x && f.y == g.y && f.z == g.z && f.w == g.w && sameRef(x.baseColor, y.baseColor) &&
           x.metallicFactor == y.metallicFactor && x.roughnessFactor == y.roughnessFactor &&
           sameRef(x.metallicRoughness, y.metallicRoughness) && sameRef(x.normal, y.normal) && sameRef(x.occlusion, y.occlusion) &&
           sameRef(x.emissive, y.emissive) && sameVec3(x.emissiveFactor, y.emissiveFactor) &&
           x.emissiveStrength == y.emissiveStrength && sameRef(x.specularGlossiness, y.specularGlossiness) &&
           x.glossinessFactor == y.glossinessFactor && x.unlit == y.unlit && sameExtensions(x.ext, y.ext);
}

}  // namespace lodbake::lod_detail
