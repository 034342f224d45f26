// A chain level's one material: the page bake's channels as the level's textures and factors.
#pragma once

#include <string>
#include <vector>

#include "lodbake/bake/bake.h"
#include "lodbake/bake/material_plan.h"
#include "lodbake/gltf/msft_lod.h"
#include "lodbake/texture/codec.h"

namespace lodbake::lod_detail {

// The channels a level's page bakes: those the plan textures, and the normal map when
// `normalMap` (the input has normal maps, or the level is coarser than the original).
BakeChannels levelChannels(const MaterialPlan& plan, bool normalMap);

// TANGENT (xyzw per vertex) of a level's indexed mesh, from its positions, normals and page UVs.
std::vector<float> levelTangents(const LodLevelData& level);

// The level's triangles with their frames, in the bake's UV convention (page UVs scaled by
// width / size and height / size, size = the longer page side).
BakeTarget levelBakeTarget(const LodLevelData& level, int width, int height);

struct LevelImageOptions {
    ImageFormat format = ImageFormat::Png;  // base colour, ORM and emissive; RGBA and normal maps are PNG
    int jpegQuality = 90;
    // KTX2 (KHR_texture_basisu) through this basisu executable instead of PNG/JPEG, empty = off:
    // ETC1S for the colour maps (base colour, emissive, sheen / specular / diffuse transmission
    // colour), UASTC for the normal maps, ORM and the extensions' data textures (channels that
    // are independent: ETC1S shares endpoints between channels and blurs them).
    std::string ktx2Encoder;
    int threads = 1;  // the level's images are encoded on this many threads (the bytes do not depend on it)
};

// The channels a level's material carries as textures, for reports ("baseColor" or
// "baseColorAlpha", "occlusion", "metallicRoughness", "emissive", "normal", then the extension
// channels with a texture: "clearcoat", "clearcoatRoughness", "clearcoatNormal", "sheenColor", ...).
std::vector<std::string> channelNames(const LodMaterial& material);

// Encodes the baked channels and sets the factors of the plan's constant channels.
LodMaterial levelMaterial(const MaterialPlan& plan, const BakeResult& baked, int width, int height,
                          const LevelImageOptions& options, const std::string& name);

}  // namespace lodbake::lod_detail
