// The one material every level of a chain uses, planned from the materials the asset's triangles
// use (DESIGN.md "Bake and gap fill", output material per level): which channels vary over the
// surface and so are baked into textures, and which are constant and so become factors.
#pragma once

#include <string>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

// The chain material's KHR_materials_* extensions. An extension is present when some used
// material has it; the parts whose material lacks it take its neutral value (clearcoat 0, sheen
// black, transmission 0, thickness 0, specular 1 and white, iridescence 0, diffuse transmission 0
// and white). Per channel: baked into a texture when its value differs between the used materials
// or one of them has a texture for it; else `factors` holds the constant value.
// What glTF cannot vary per texel (ior, attenuation distance and colour, dispersion, iridescence
// ior) is here the area-weighted mean over the triangles whose material has the extension
// (mergeUniforms): the value of a level drawn as one primitive. Where the inputs disagree, the
// level is split (lodbake/bake/draw_split.h), which also warns about what a merge leaves.
// Baked channels read as follows in `factors`:
//   - scalar and colour channels: factor 1 (the texture holds factor x texture of the input),
//     except specular colour: its factor is specularColorScale (the texture holds value / scale);
//   - volume thickness: thicknessFactor = the largest input thickness factor (the texture holds
//     thickness / that factor);
//   - iridescence thickness: [thicknessMinimum, thicknessMaximum] = the union of the inputs'
//     thickness ranges (the texture holds the thickness in nm normalised into it).
struct ExtensionPlan {
    MaterialExtensions factors;  // `present` flags, factors and properties of the chain's material (no textures)
    bool clearcoatTexture = false, clearcoatRoughnessTexture = false;
    // The roughness baked where a part lacks the clearcoat / sheen (it matters only under one):
    // the first such material's factor, so these parts do not make the roughness vary.
    double clearcoatRoughnessFill = 0, sheenRoughnessFill = 0;
    bool clearcoatNormalTexture = false;  // some used material has a clearcoat normal map
    bool sheenColorTexture = false, sheenRoughnessTexture = false;
    bool transmissionTexture = false, thicknessTexture = false;
    bool specularTexture = false, specularColorTexture = false;
    double specularColorScale = 1;  // the largest specular colour factor component when above 1, else 1
    bool iridescenceTexture = false, iridescenceThicknessTexture = false;
    bool diffuseTransmissionTexture = false, diffuseTransmissionColorTexture = false;
    // Anisotropy is always baked when present: its direction is relative to the tangent frames,
    // which differ between the original and a level (factors: strength 1, rotation 0).
    bool anisotropyTexture = false;
    bool any() const;  // some extension is present
};

struct MaterialPlan {
    // Base colour: a texture when any used material has a base-colour texture, the mesh has vertex
    // colours or the used materials' factors differ; otherwise baseColorFactor.
    bool baseColorTexture = false;
    Vec4 baseColorFactor{1, 1, 1, 1};
    // Alpha: carried in the base-colour texture's A channel when any used material is not OPAQUE
    // and its alpha varies (texture alpha, vertex alpha, differing factors).
    bool alphaTexture = false;
    AlphaMode alphaMode = AlphaMode::Opaque;  // BLEND if any used material blends, else MASK if any masks
    double alphaCutoff = 0.5;                 // the smallest cutoff of the MASK materials
    // Occlusion (ORM R), roughness (G), metallic (B): one ORM texture when occlusion or
    // metallic-roughness vary; constant metallic/roughness become the factors.
    bool occlusionTexture = false;
    bool metallicRoughnessTexture = false;
    double metallicFactor = 1, roughnessFactor = 1;
    // Emissive: a texture when it varies, else emissiveFactor (zero = no emission).
    bool emissiveTexture = false;
    Vec3 emissiveFactor{0, 0, 0};
    // Normal map: some used material has one (then LOD0 carries it too). Coarse levels get a
    // baked normal map whenever the original surface has finer shading than theirs.
    bool normalTexture = false;
    bool doubleSided = false;  // every used material is double-sided
    bool backFaces = false;    // some, not all, are: their triangles get reversed copies instead
    bool unlit = false;        // every used material is KHR_materials_unlit
    // KHR_materials_* extensions: the union of those the used materials carry (ExtensionPlan).
    ExtensionPlan ext;
    // Mixed sidedness. Mixed alpha modes, shading models and disagreeing per-primitive properties
    // are draw_split.h's to warn about (a split keeps them exact).
    std::vector<std::string> warnings;
    bool ormTexture() const { return occlusionTexture || metallicRoughnessTexture; }
};

// `plan` with only its base colour baked (with alpha): a diffuse material (metallic 0, roughness
// 1, no emission), no normal map, no extensions.
MaterialPlan baseColorPlan(MaterialPlan plan);

// Plans the chain's material from the materials asset.mesh's triangles use (-1 = the glTF
// default material: white, metallic 1, roughness 1).
MaterialPlan planMaterial(const Asset& asset);

}  // namespace lodbake
