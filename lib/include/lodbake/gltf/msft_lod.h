// Writing the final LOD chain (`pack`'s output): a glTF whose LOD0 node carries MSFT_lod, every
// level one mesh / one primitive / one material with its baked atlas pages (or, where the input's
// materials disagree on what glTF cannot vary per texel, one primitive per LodPart, the parts'
// materials sharing the level's textures), optionally
// compressed with KHR_draco_mesh_compression or EXT_meshopt_compression, optionally quantized
// (KHR_mesh_quantization). Takes lodbake's own structs only (images already
// encoded: lodbake/texture/codec.h); tinygltf-free, Draco stays inside lib/src/io (STYLE.md practice 10).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/core/material_uniforms.h"
#include "lodbake/core/mesh.h"

namespace lodbake {

struct SourceScene;  // lodbake/gltf/source_scene.h

// The one material of a level: baked textures where a channel varies, factors where it does not
// (lodbake/bake/material_plan.h). Texture images are encoded; an empty `encoded` = no texture.
struct LodMaterial {
    Image baseColor;              // RGB, or RGBA when alpha varies (sRGB)
    Image orm;                    // occlusion R, roughness G, metallic B (linear); metallicRoughness and occlusion
    Image emissive;               // RGB (sRGB)
    Image normal;                 // tangent-space normal map (linear); needs the level's tangents
    Vec4 baseColorFactor{1, 1, 1, 1};
    double metallicFactor = 0;
    double roughnessFactor = 1;
    bool occlusion = false;       // orm's R channel is the occlusion map
    bool metallicRoughness = false;  // orm's G and B channels are roughness and metallic
    Vec3 emissiveFactor{0, 0, 0};
    double emissiveStrength = 1;  // > 1: KHR_materials_emissive_strength
    AlphaMode alphaMode = AlphaMode::Opaque;
    double alphaCutoff = 0.5;
    bool doubleSided = false;
    bool unlit = false;           // KHR_materials_unlit
    // KHR_materials_* extensions (present ones written, with their factors and properties); a
    // texture reference's `texture` indexes extensionImages (-1 = none), several may share one.
    MaterialExtensions ext;
    std::vector<Image> extensionImages;  // encoded; Image::name = the suffix of its glTF name ("clearcoat", ...)
    // The textures' GL min / mag filters; 0 = the chain's (LINEAR_MIPMAP_LINEAR, LINEAR). A page
    // holding the original's texels one to one keeps the original's filters.
    int minFilter = 0, magFilter = 0;
    // The textures wrap REPEAT: they hold one period of a repeating material, which the level's
    // UVs (outside [0,1]) tile; else CLAMP_TO_EDGE (an atlas page). Textures of repeating
    // materials equal to ones an earlier level wrote are shared across the chain's levels.
    bool repeat = false;
};

// One primitive of a level drawn as several (lodbake/bake/draw_split.h): its triangles and the
// values glTF cannot vary per texel that its material holds. Every part uses the level's vertices,
// pages and UVs; its material is the level's (or a variant's) with these values.
struct LodPart {
    size_t triangles = 0;        // the next this many triangles of LodLevelData::indices
    MaterialUniforms uniforms;   // of the level's default material on this part
    // Per variant (LodChainWriteOptions::variants): the values of its material on this part.
    std::vector<MaterialUniforms> variantUniforms;
};

// One level of the chain, ready to write: an indexed triangle list (CCW) in world space.
struct LodLevelData {
    std::string name;                // node / mesh / material name, e.g. "LOD1"
    std::vector<float> positions;    // xyz per vertex
    std::vector<float> normals;      // xyz per vertex, unit length (same count as positions)
    std::vector<float> uvs;          // TEXCOORD_0 per vertex (glTF: [0,1], v down)
    std::vector<float> tangents;     // TANGENT xyzw per vertex (lodbake/core/tangents.h); empty = none
    std::vector<uint16_t> joints;    // JOINTS_0, 4 per vertex, into the chain's Rig::joints; empty = not skinned
    std::vector<float> weights;      // WEIGHTS_0, 4 per vertex (with joints)
    // Morph targets (the chain's MorphTargets, in order): per target, 3 floats per vertex each;
    // normal / tangent deltas empty when absent.
    std::vector<std::vector<float>> targetPositions, targetNormals, targetTangents;
    std::vector<uint32_t> indices;   // 3 per triangle
    LodMaterial material;
    // KHR_materials_variants (the chain's variants, LodChainWriteOptions::variants): per variant,
    // the index into variantMaterials of its material on this level, -1 = `material` (the variant
    // changes nothing this level shows). Empty without variants.
    std::vector<int> variantMaterial;
    std::vector<LodMaterial> variantMaterials;
    // Empty: one primitive draws every triangle with `material`. Else one primitive per part, the
    // parts' triangle counts summing to the level's (its triangles ordered by part).
    std::vector<LodPart> parts;
};

struct LodChainWriteOptions {
    std::string generator = "lodbake pack";
    bool embedImages = true;  // .gltf only: false writes images beside the file (GLB always embeds)
    bool draco = false;       // KHR_draco_mesh_compression on every primitive (then also extensionsRequired)
    int quantPosition = 14;   // Draco quantisation bits (1..30) for POSITION
    int quantTexcoord = 12;   // ... TEXCOORD_0
    int quantNormal = 10;     // ... NORMAL and TANGENT
    int dracoSpeed = 3;       // Draco encoder speed 0 (best compression) .. 10 (fastest); decoding speed the same
    // Reorder every level's triangles and vertices for the GPU (meshoptimizer: vertex cache, then
    // overdraw within 5 % of the cache order's ACMR, then vertex fetch; all attributes move together).
    // Deterministic; the geometry is unchanged.
    bool optimize = true;
    // EXT_meshopt_compression on every vertex and index stream (required, fallback-free: the
    // uncompressed views live in a buffer without data). Normals and tangents use the OCTAHEDRAL
    // filter (16-bit, or 8-bit with `quantize`) and so KHR_mesh_quantization. Not with `draco`.
    bool meshopt = false;
    // KHR_mesh_quantization: positions unsigned 16-bit integers on one grid for every level
    // (quantPositionBits, dequantised by each node's translation + uniform scale), normals and
    // tangents normalized 8-bit, UVs normalized unsigned 16-bit (a level with UVs outside [0,1]
    // keeps FLOAT UVs). Not with `draco`.
    bool quantize = false;
    int quantPositionBits = 14;  // --quantize position grid bits (1..16)
    // KHR_materials_variants: the root list of variant names (LodLevelData::variantMaterial indexes
    // it); empty = none. Each level's variant materials follow all the levels' default materials
    // (so a level's default material keeps its index), named "<level>_<variant>", and images
    // equal to one the level already wrote are shared.
    std::vector<std::string> variants;
    int threads = 1;  // levels optimised side by side (0 = all cores); the file is the same for any count
};

// meshopt_analyzeVertexCache with a 16-entry FIFO: ACMR = vertex shader invocations per triangle
// (0.5 is ideal for a large regular grid, 3 the worst), ATVR = invocations per vertex (1 ideal).
struct VertexCacheStats {
    double acmr = 0;
    double atvr = 0;
};

struct LodChainWriteStats {
    std::vector<uint64_t> levelGeometryBytes;  // buffer bytes of each level's mesh (indices + attributes or Draco)
    std::vector<uint64_t> levelImageBytes;     // encoded image bytes of each level
    uint64_t fileBytes = 0;                    // the .glb (or .gltf + .bin + images) on disk
    std::vector<VertexCacheStats> levelCacheBefore;  // each level's index order as the chain built it
    std::vector<VertexCacheStats> levelCacheAfter;   // ... as written (the same when !optimize; for
                                                     // Draco, the order handed to the encoder)
    std::vector<std::string> warnings;               // fallbacks taken (e.g. FLOAT UVs under quantize)
};

// Writes `levels` as one glTF (.glb or .gltf by the extension of `path`), atomically.
// With more than one level: node 0 = levels[0] with extensions.MSFT_lod.ids = [1 .. n-1] and
// extras.MSFT_screencoverage = `screenCoverage` (one value per level, i.e. one more than the
// ids, decreasing: LOD k is drawn at coverage >= value k, nothing below the last); only node 0 (with the rig's roots and the scene's light and camera nodes) is in the scene; MSFT_lod is listed in extensionsUsed, never required.
// With one level and no coverage: a plain single-mesh file (pack --split).
// With a non-empty `rig` (and joints on every level): the rig's nodes, its one skin and its
// animations are written once; every level node uses the skin; the rig's roots join node 0 in
// the scene. Draco is not applied to skinned levels (they are written with plain accessors).
// With a non-empty `morph` (and targets on every level): every level's primitive has the targets,
// its mesh the default weights, and the rig's weights animations drive every level node (one
// shared sampler). Morphed levels are never Draco-compressed (Draco reorders vertices, which the
// targets' accessors cannot follow) and keep FLOAT positions under --quantize; both with a warning.
// With a non-empty `scene`: its lights (KHR_lights_punctual, then in extensionsUsed), cameras and
// extras, each light / camera node a scene root at its world transform (after the levels' and the
// rig's nodes).
// With a non-null `lod0` (the input's own document: pack --lod0 original), LOD0 is that scene
// and `levels` are LOD1 onwards (`screenCoverage` has one value more than `levels`; `levels` may be
// empty: the original alone, for pack --split). Node 0 is a group named "LOD0" whose children are
// the original's scene roots (its nodes follow at index + 1, with their transforms, skins, morph
// targets, lights and cameras); every other array of the original keeps its indices and the
// levels' meshes, materials, textures, images and sampler come after. The original's animations
// drive it; the levels' skin (`rig`, when the levels are skinned) takes the original's nodes as
// joints (lod0->rigNodes), so the same animations move the levels, and the rig's morph weight
// channels join the original's animations for the level nodes. `scene` is not written (the
// original carries its own lights, cameras and extras). LOD0 is never compressed or quantized
// (a warning when options ask for it); its stats are those of the original's buffer (no vertex
// cache figures: zeros).
// \pre every level has >= 1 triangle and matching attribute sizes; a normal map comes with tangents.
// \throw InvalidInput (inconsistent level data; a rig that is not lod0's), IOError (cannot write),
//        SolverError (Draco failed), Unsupported (draco with meshopt or quantize).
LodChainWriteStats writeLodChain(const std::string& path, const std::vector<LodLevelData>& levels,
                                 const std::vector<double>& screenCoverage, const LodChainWriteOptions& options = {},
                                 const Rig* rig = nullptr, const MorphTargets* morph = nullptr,
                                 const SceneExtras* scene = nullptr, const SourceScene* lod0 = nullptr);

}  // namespace lodbake
