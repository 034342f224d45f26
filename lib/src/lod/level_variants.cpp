// KHR_materials_variants in pack (see level_variants.h).
#include "lod/level_variants.h"

#include <tuple>

#include "lod/level_material.h"
#include "lod/material_equality.h"

namespace lodbake::lod_detail {
namespace {

bool sameImage(const Image& a, const Image& b) { return a.encoded == b.encoded && a.channels == b.channels; }

// Two level materials that render the same: the same images (encoded bytes) and factors.
bool sameMaterial(const LodMaterial& a, const LodMaterial& b) {
    if (!sameImage(a.baseColor, b.baseColor) || !sameImage(a.orm, b.orm) || !sameImage(a.emissive, b.emissive) ||
        !sameImage(a.normal, b.normal) || a.extensionImages.size() != b.extensionImages.size())
        return false;
    for (size_t i = 0; i < a.extensionImages.size(); ++i)
        if (!sameImage(a.extensionImages[i], b.extensionImages[i]) || a.extensionImages[i].name != b.extensionImages[i].name) return false;
    const Vec4 &f = a.baseColorFactor, &g = b.baseColorFactor;
    return f.x == g.x && f.y == g.y && f.z == g.z && f.w == g.w && a.metallicFactor == b.metallicFactor &&
           a.roughnessFactor == b.roughnessFactor && a.occlusion == b.occlusion && a.metallicRoughness == b.metallicRoughness &&
           sameVec3(a.emissiveFactor, b.emissiveFactor) && a.emissiveStrength == b.emissiveStrength && a.alphaMode == b.alphaMode &&
           a.alphaCutoff == b.alphaCutoff && a.doubleSided == b.doubleSided && a.unlit == b.unlit && a.minFilter == b.minFilter &&
           a.magFilter == b.magFilter && sameExtensions(a.ext, b.ext);
}

bool needsTangents(const BakeChannels& c) { return c.normal || c.clearcoatNormal || c.anisotropy; }

}  // namespace

ChainVariants chainVariants(const Asset& asset, bool baseColorOnly) {
    ChainVariants out;
    out.names = asset.variants.names;
    std::vector<std::vector<int32_t>> selections;  // triangle materials of each bake
    for (size_t v = 0; v < out.names.size(); ++v) {
        std::vector<int32_t> materials = variantTriangleMaterials(asset.variants, asset.mesh.triangleMaterial, v);
        int bake = -1;
        if (materials != asset.mesh.triangleMaterial) {
            for (size_t b = 0; b < selections.size() && bake < 0; ++b)
                if (selections[b] == materials) bake = int(b);
            if (bake < 0) {
                // A copy of the asset with the variant's materials: the bake reads materials
                // through the mesh, and its images are decoded for this selection.
                auto vb = std::make_unique<VariantBake>();
                vb->asset = asset;
                vb->asset.mesh.triangleMaterial = materials;
                vb->plan = baseColorOnly ? baseColorPlan(planMaterial(vb->asset)) : planMaterial(vb->asset);
                for (const std::string& w : vb->plan.warnings) out.warnings.push_back("variant '" + out.names[v] + "': " + w);
                vb->sources = std::make_unique<BakeSources>(vb->asset);
                out.bakes.push_back(std::move(vb));
                selections.push_back(std::move(materials));
                bake = int(out.bakes.size() - 1);
            }
        }
        out.bakeOf.push_back(bake);
    }
    return out;
}

bool variantsNeedTangents(const ChainVariants& variants, const LevelChannelsFn& channels) {
    for (const auto& b : variants.bakes)
        if (needsTangents(channels(b->plan))) return true;
    return false;
}

void bakeLevelVariants(const ChainVariants& variants, const LevelChannelsFn& channels, const LevelBakeFn& bake,
                       const LevelMaterialFn& material, LodLevelData& L, PackLevelReport& report) {
    L.variantMaterial.assign(variants.names.size(), -1);
    L.variantMaterials.clear();
    std::vector<int> materialOfBake(variants.bakes.size(), -1);  // index into L.variantMaterials, -1 = the default
    for (size_t b = 0; b < variants.bakes.size(); ++b) {
        const VariantBake& vb = *variants.bakes[b];
        size_t first = 0;  // the first variant of this bake names its material
        while (variants.bakeOf[first] != int(b)) ++first;
        LodMaterial m = material(vb.plan, bake(*vb.sources, channels(vb.plan)), L.name + "_" + variants.names[first]);
        m.minFilter = L.material.minFilter;
        m.magFilter = L.material.magFilter;
        if (sameMaterial(m, L.material)) continue;
        for (size_t i = 0; i < L.variantMaterials.size() && materialOfBake[b] < 0; ++i)
            if (sameMaterial(m, L.variantMaterials[i])) materialOfBake[b] = int(i);
        if (materialOfBake[b] >= 0) continue;
        L.variantMaterials.push_back(std::move(m));
        materialOfBake[b] = int(L.variantMaterials.size() - 1);
    }
    for (size_t v = 0; v < variants.names.size(); ++v)
        if (variants.bakeOf[v] >= 0) L.variantMaterial[v] = materialOfBake[size_t(variants.bakeOf[v])];
    copyLevelVariants(L, variants, L, report);
}

void copyLevelVariants(const LodLevelData& from, const ChainVariants& variants, LodLevelData& L, PackLevelReport& report) {
    if (&from != &L) {
        L.variantMaterial = from.variantMaterial;
        L.variantMaterials = from.variantMaterials;
    }
    report.variants.clear();
    for (size_t v = 0; v < variants.names.size(); ++v) {
        const int m = v < L.variantMaterial.size() ? L.variantMaterial[v] : -1;
        report.variants.push_back({variants.names[v], m, channelNames(m >= 0 ? L.variantMaterials[size_t(m)] : L.material)});
    }
}

}  // namespace lodbake::lod_detail
