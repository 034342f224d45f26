// A small deterministic software rasteriser used to compare two assets in image space.
//
// Z-buffer, perspective-correct attribute interpolation, trilinear mip-mapped texture sampling
// with analytic UV derivatives (mip levels built from the decoded image in linear space),
// sampler wrap modes (REPEAT, CLAMP_TO_EDGE, MIRRORED_REPEAT) and KHR_texture_transform.
// Pixel centres are sampled once (no anti-aliasing), so renders are exactly reproducible.
//
// Modes:
//   BaseColor: unlit baseColorFactor x baseColor texture x COLOR_0, output sRGB-encoded.
//   Shaded:    Lambert-shaded grey (albedo 0.8) with geometric face normals and a headlight
//              (light at the camera), ambient 0.1; shows the shape only.
//   Pbr:       glTF metallic-roughness shading of every material channel: base colour (as in
//              BaseColor), metallicRoughness (G roughness, B metallic), occlusion, emissive
//              (x KHR_materials_emissive_strength) and the tangent-space normal map, on the
//              interpolated vertex normals (face normal when the mesh has none). Cook-Torrance
//              GGX specular (Smith-Schlick G, Schlick Fresnel, F0 = mix(0.04, base, metallic))
//              plus Lambert diffuse, under two directional lights fixed in camera space (see
//              kPbrLights in render.cpp) and an occluded ambient term; emissive added; then the
//              KHR_materials_clearcoat layer (metrics/clearcoat_layer.h); output clamped to
//              [0,1] and sRGB-encoded. Unlit materials (KHR_materials_unlit) show their base
//              colour. No image-based lighting, shadows or transmission.
// Alpha: MASK materials discard texels below alphaCutoff; BLEND is drawn opaque.
// Culling: back faces of single-sided materials are culled; double-sided ones are drawn (Pbr:
// with their normals flipped).
// Background: black (0,0,0); `coverage` tells which pixels a triangle covers.
// Seams: `seam` marks the visible pixels within RenderOptions::seamBand pixels of a texture seam
// (an edge whose two triangles give it different TEXCOORD_0 values, e.g. an atlas chart
// boundary), measured on the triangles either side, so the band is about twice as wide.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/core/math.h"
#include "lodbake/core/mesh.h"

namespace lodbake {

enum class RenderMode { BaseColor, Shaded, Pbr };

struct Camera {
    Vec3 eye{0, 0, 1};
    Vec3 target{0, 0, 0};
    Vec3 up{0, 1, 0};
    double fovY = 1.0471975511965976;  // vertical field of view, radians (60 degrees)
    double zNear = 0.01;               // model units, > 0
    double zFar = 100;                 // model units, > zNear
};

// `count` cameras on a Fibonacci lattice around the sphere (center, radius), each at the distance
// where the sphere fills the vertical field of view, looking at the centre. Deterministic.
std::vector<Camera> sphereViews(int count, Vec3 center, double radius, double fovY = 1.0471975511965976);

// A decoded image: linear-light RGBA float, mip pyramid (level 0 = full size, box-filtered down to
// 1x1; a level of odd side filters each texel's whole footprint, so no texel shifts).
struct MipImage {
    struct Level {
        int width = 0, height = 0;
        std::vector<float> rgba;  // width * height * 4
    };
    std::vector<Level> levels;
};

// What the rasteriser needs of an asset: the mesh, its materials and the decoded textures.
// Holds pointers: `asset` and `mesh` must outlive the scene.
struct RenderScene {
    const Asset* asset = nullptr;
    const TriMesh* mesh = nullptr;
    // Per Asset::images entry; an empty pyramid when unused or undecodable (sampled as white).
    std::vector<MipImage> images;      // colour: sRGB-decoded to linear (base colour, emissive)
    std::vector<MipImage> dataImages;  // data, no transfer function (metallicRoughness, occlusion, normal, clearcoat)
    // Per wedge, for normal maps on TEXCOORD_0 / TEXCOORD_1 when the mesh has no tangents (empty
    // otherwise): xyz unit tangent along +u, w = handedness (bitangent = cross(N, T) * w).
    std::array<std::vector<Vec4>, 2> tangents;
    // Per triangle: bit k set when edge k (corner k -> k + 1) is a texture seam (see above).
    std::vector<uint8_t> seamEdges;
    std::vector<std::string> warnings;  // images that could not be decoded (rendered as white)
};

// Decodes (texture/codec.h) the images the mesh's materials reference, each in the colour space of
// its use, builds their pyramids, and computes the tangents normal maps need.
RenderScene prepareRenderScene(const Asset& asset, const TriMesh& mesh);

struct RenderOptions {
    int width = 256, height = 256;  // pixels
    RenderMode mode = RenderMode::BaseColor;
    double seamBand = 2;            // pixels either side of a visible texture seam marked in `seam`
};

struct Rendering {
    int width = 0, height = 0;
    std::vector<float> rgb;          // width * height * 3, sRGB-encoded values in [0,1], row 0 = top
    std::vector<uint8_t> coverage;   // width * height, 1 where the surface is visible
    std::vector<uint8_t> seam;       // width * height, 1 where a visible texture seam is near
};

// Bit k of entry f set when triangle f's edge k (corner k -> k + 1) is a texture seam: another
// triangle shares the edge's two positions with different TEXCOORD_0 values at either end.
std::vector<uint8_t> textureSeamEdges(const TriMesh& mesh);

Rendering render(const RenderScene& scene, const Camera& camera, const RenderOptions& options = {});

}  // namespace lodbake
