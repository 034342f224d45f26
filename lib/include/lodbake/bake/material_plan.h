// The one material every level of a chain uses, planned from the materials the asset's triangles
// use (DESIGN.md "Bake and gap fill", output material per level): which channels vary over the
// surface and so are baked into textures, and which are constant and so become factors.
#pragma once

#include <string>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

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
    std::vector<std::string> warnings;  // mixed alpha modes, sidedness or shading models
    bool ormTexture() const { return occlusionTexture || metallicRoughnessTexture; }
};

// `plan` with only its base colour baked (with alpha): a diffuse material (metallic 0, roughness
// 1, no emission), no normal map.
MaterialPlan baseColorPlan(MaterialPlan plan);

// Plans the chain's material from the materials asset.mesh's triangles use (-1 = the glTF
// default material: white, metallic 1, roughness 1).
MaterialPlan planMaterial(const Asset& asset);

}  // namespace lodbake
