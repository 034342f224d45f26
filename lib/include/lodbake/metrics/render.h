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
// Alpha: MASK materials discard texels below alphaCutoff; BLEND is drawn opaque.
// Culling: back faces of single-sided materials are culled; double-sided ones are drawn.
// Background: black (0,0,0); `coverage` tells which pixels a triangle covers.
#pragma once

#include <cstdint>
#include <vector>

#include "lodbake/core/math.h"
#include "lodbake/core/mesh.h"

namespace lodbake {

enum class RenderMode { BaseColor, Shaded };

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

// A decoded image: linear-light RGBA float, mip pyramid (level 0 = full size, box-filtered down to 1x1).
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
    std::vector<MipImage> images;  // per Asset::images entry; empty pyramid when unused/undecodable
    std::vector<std::string> warnings;  // images that could not be decoded (rendered as white)
};

// Decodes (with OpenImageIO) the images the mesh's materials reference and builds their pyramids.
RenderScene prepareRenderScene(const Asset& asset, const TriMesh& mesh);

struct RenderOptions {
    int width = 256, height = 256;  // pixels
    RenderMode mode = RenderMode::BaseColor;
};

struct Rendering {
    int width = 0, height = 0;
    std::vector<float> rgb;          // width * height * 3, sRGB-encoded values in [0,1], row 0 = top
    std::vector<uint8_t> coverage;   // width * height, 1 where the surface is visible
};

Rendering render(const RenderScene& scene, const Camera& camera, const RenderOptions& options = {});

}  // namespace lodbake
