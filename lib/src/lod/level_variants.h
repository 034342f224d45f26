// KHR_materials_variants in pack: every variant of the input gets its own material on every
// level, baked by the level's own page bake (same mesh, same UVs, same page) from the asset with
// each triangle's material replaced by its primitive's mapping for that variant (its default
// material where the mapping names none). A variant whose material comes out equal to the
// level's default (the level shows none of the parts it changes) is not written: the level's
// default material serves it.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "lodbake/bake/bake.h"
#include "lodbake/bake/material_plan.h"
#include "lodbake/gltf/msft_lod.h"
#include "lodbake/lod/lod_chain.h"

namespace lodbake::lod_detail {

// One distinct selection of materials: the asset with a variant selected, its material plan and
// its decoded images. Held by pointer: `sources` refers to `asset`.
struct VariantBake {
    Asset asset;
    MaterialPlan plan;
    std::unique_ptr<BakeSources> sources;
};

// The chain's variants, prepared once for every level.
struct ChainVariants {
    std::vector<std::string> names;  // the input's variant names, in order
    // Per variant: index into `bakes`, -1 = it selects the default materials on every triangle.
    // Variants that select the same materials everywhere share one bake.
    std::vector<int> bakeOf;
    std::vector<std::unique_ptr<VariantBake>> bakes;
    std::vector<std::string> warnings;  // the variant plans' own (mixed alpha modes, ...), once each
    bool empty() const { return names.empty(); }
};

// \throw IOError (an image cannot be decoded).
ChainVariants chainVariants(const Asset& asset, bool baseColorOnly);

// The channels a level bakes for a material plan (levelChannels with the level's normal-map rule).
using LevelChannelsFn = std::function<BakeChannels(const MaterialPlan&)>;
// The level's page bake (the default material's call) with other sources and channels.
using LevelBakeFn = std::function<BakeResult(const BakeSources&, const BakeChannels&)>;
// The level's material from a bake (levelMaterial with the level's page size and image options).
using LevelMaterialFn = std::function<LodMaterial(const MaterialPlan&, const BakeResult&, const std::string& name)>;

// True when some variant's channels need the level's tangent frames (normal, clearcoat normal or
// anisotropy maps): the level then gets tangents and a bake target even when its default does not.
bool variantsNeedTangents(const ChainVariants& variants, const LevelChannelsFn& channels);

// Bakes and encodes every variant's material of level L (its default material made) into
// L.variantMaterial / L.variantMaterials and the report's variants; a material equal to the
// default or to an earlier variant's is shared, not kept twice. Variant materials take the
// default's texture filters.
void bakeLevelVariants(const ChainVariants& variants, const LevelChannelsFn& channels, const LevelBakeFn& bake,
                       const LevelMaterialFn& material, LodLevelData& L, PackLevelReport& report);

// The report's variants of a level whose materials were copied from `from` (a repeated level).
void copyLevelVariants(const LodLevelData& from, const ChainVariants& variants, LodLevelData& L, PackLevelReport& report);

}  // namespace lodbake::lod_detail
