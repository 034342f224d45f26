// lodbake's own asset model: what the glTF reader produces and every algorithm consumes.
// No format-library types here (STYLE.md practice 10). TriMesh is a data structure only.
//
// Topology is welded by position: two glTF vertices with bit-identical world positions become
// one welded vertex, so UV seams, normal creases and material boundaries do not cut the surface.
// Everything a glTF vertex carries besides its position (normal, UVs, colour) stays attached to
// face corners through *wedges*: a wedge is one distinct glTF vertex, and each triangle corner
// names the wedge it uses.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/core/material_extensions.h"
#include "lodbake/core/material_variants.h"
#include "lodbake/core/math.h"
#include "lodbake/core/morph.h"
#include "lodbake/core/rig.h"
#include "lodbake/core/scene_extras.h"

namespace lodbake {

using Tri = std::array<uint32_t, 3>;

// True when a triangle repeats a vertex index: it has no area and no edges of its own.
inline bool degenerateIndices(const Tri& t) { return t[0] == t[1] || t[1] == t[2] || t[0] == t[2]; }

// Per-wedge attribute arrays; an array is either empty (attribute absent) or wedgeCount long.
struct Wedges {
    std::vector<uint32_t> vertex;  // welded vertex index of each wedge (always present)
    std::vector<Vec3> normal;      // world-space unit normal
    std::vector<Vec4> tangent;     // world-space tangent, w = handedness
    std::vector<Vec2> uv0;         // TEXCOORD_0 as stored in glTF (origin top-left, v down)
    std::vector<Vec2> uv1;         // TEXCOORD_1
    std::vector<Vec4> color;       // COLOR_0 as linear RGBA in [0,1] (RGB inputs get alpha 1)
    // Skinning (present exactly when Asset::rig is not empty): the 4 largest influences, joint
    // indices into Rig::joints, weights summing to 1; unused slots are joint 0 with weight 0.
    std::vector<std::array<uint16_t, 4>> joints;
    std::vector<Vec4> weights;
    // Morph targets (as many as Asset::morph names; lodbake/core/morph.h states what holds).
    std::vector<MorphDeltas> targets;
    size_t size() const { return vertex.size(); }
};

struct TriMesh {
    std::vector<Vec3> positions;      // welded vertices, world space
    std::vector<Tri> triangles;       // welded vertex indices, counter-clockwise front faces
    std::vector<Tri> cornerWedges;    // per triangle, the wedge of each corner
    std::vector<int32_t> triangleMaterial;  // index into Asset::materials; -1 = glTF default material
    Wedges wedges;

    size_t vertexCount() const { return positions.size(); }
    size_t triangleCount() const { return triangles.size(); }
};

enum class AlphaMode { Opaque, Mask, Blend };

struct Material {
    std::string name;
    Vec4 baseColorFactor{1, 1, 1, 1};
    TextureRef baseColor;
    double metallicFactor = 1;
    double roughnessFactor = 1;
    TextureRef metallicRoughness;
    TextureRef normal;
    TextureRef occlusion;
    TextureRef emissive;
    Vec3 emissiveFactor{0, 0, 0};
    double emissiveStrength = 1;  // KHR_materials_emissive_strength (multiplies emissiveFactor)
    // KHR_materials_pbrSpecularGlossiness, converted on reading (baseColor = diffuse, metallic 0,
    // roughness 1 - glossiness): the texture whose alpha is glossiness, and the glossiness factor.
    TextureRef specularGlossiness;
    double glossinessFactor = 1;
    AlphaMode alphaMode = AlphaMode::Opaque;
    double alphaCutoff = 0.5;
    bool doubleSided = false;
    bool unlit = false;  // KHR_materials_unlit
    MaterialExtensions ext;  // clearcoat, sheen, transmission, volume, specular, ior, ... (material_extensions.h)
};

struct Sampler {
    int magFilter = 0;  // 0 = unset, else the GL enum
    int minFilter = 0;
    int wrapS = 10497;  // GL_REPEAT
    int wrapT = 10497;
};

struct Texture {
    int image = -1;
    int sampler = -1;  // -1 = default sampler
};

// An image as the file holds it: the encoded bytes (PNG/JPEG), decoded only when needed.
struct Image {
    std::string name;
    std::string mimeType;  // "image/png" or "image/jpeg"
    std::vector<uint8_t> encoded;
    int width = 0, height = 0, channels = 0;  // 0 until checkImages (lodbake/texture/codec.h) or an encoder fills them
};

struct LoadStats {
    size_t nodes = 0;
    size_t primitives = 0;       // triangle primitives read
    size_t droppedPrimitives = 0;  // points/lines dropped
    size_t dracoPrimitives = 0;
    size_t inputVertices = 0;    // glTF vertices summed over instantiated primitives
};

struct Asset {
    std::string sourcePath;
    TriMesh mesh;
    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Sampler> samplers;
    std::vector<Image> images;
    Rig rig;  // skin and animations; empty for a static asset
    MorphTargets morph;  // names and default weights of mesh.wedges.targets; empty = no morph targets
    SceneExtras scene;   // lights, cameras and their nodes, extras (lodbake/core/scene_extras.h)
    MaterialVariants variants;  // KHR_materials_variants (lodbake/core/material_variants.h); empty = none
    std::vector<std::string> warnings;
    LoadStats stats;
};

// Bounding box of the welded positions.
inline Box3 bounds(const TriMesh& m) {
    Box3 b;
    for (const Vec3& p : m.positions) b.extend(p);
    return b;
}

}  // namespace lodbake
