// Baking the original appearance into a new UV atlas (DESIGN.md "Bake and gap fill").
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"

namespace lodbake {

class FaceGrid;

// The channels a bake produces (MaterialPlan decides which the chain needs). Base colour is
// always baked.
struct BakeChannels {
    bool alpha = false;     // base colour alpha: factor x texture x COLOR_0 alpha
    bool orm = false;       // occlusion (1 + strength (ao - 1)), roughness, metallic
    bool emissive = false;  // emissiveFactor x strength x emissive texture
    bool normal = false;    // the original shading normal in the target's tangent frames (needs a BakeTarget)
    // KHR_materials_* extensions, packed as glTF reads them (each value factor x texture of the
    // original material at the texel, the extension's neutral value where it lacks it):
    bool clearcoat = false;            // R clearcoat, G clearcoat roughness
    bool clearcoatNormal = false;      // the original's clearcoat normal in the target's tangent frames (needs a BakeTarget)
    bool sheen = false;                // RGB sheen colour (sRGB), A sheen roughness
    bool specular = false;             // RGB specular colour / specularColorScale (sRGB), A specular
    bool transmission = false;         // R transmission, G volume thickness / thicknessScale
    bool iridescence = false;          // R iridescence, G thickness normalised into [iridescenceThicknessMin, Max]
    bool diffuseTransmission = false;  // RGB diffuse transmission colour (sRGB), A diffuse transmission
    bool anisotropy = false;           // RG direction in the target's tangent frames (x 0.5 + 0.5), B strength (needs a BakeTarget)
    double clearcoatRoughnessFill = 0; // clearcoat roughness where the material has no clearcoat
    double sheenRoughnessFill = 0;     // sheen roughness where the material has no sheen
    double specularColorScale = 1;     // > 0
    double thicknessScale = 1;         // mesh units; > 0
    double iridescenceThicknessMin = 100, iridescenceThicknessMax = 400;  // nanometres
};

struct BakeOptions {
    int size = 1024;        // square atlas side in texels: cornerUV [0,1] spans `size` texels
    // The region baked: texels [0, width) x [0, height) of the size x size grid (0 = size). A page
    // narrower or shorter than `size` (pack's non-square pages) is baked and gap-filled alone.
    int width = 0, height = 0;
    double dilation = 1;    // conservative rasterisation margin around each triangle, texels
    // Dilated texels read the textures where their nearest triangle's map continues (its affine
    // extension), not at its closest point. On a page whose charts copy the original's texels at
    // an integer offset, the margin then holds the original's own neighbouring texels, wrapped
    // by its sampler, so bilinear taps and mips across a chart's border read what the original's
    // read there. Vertex colours, normals and frames still take the closest point.
    bool extendCharts = false;
    bool fillGaps = true;   // pull-push fill of uncovered texels (pullPushFill)
    bool encodePng = true;  // BakeResult::image (false: pixels only, for callers that encode themselves)
    int threads = 1;        // texel shading threads (0 = all cores); the result is the same for any count
    BakeChannels channels;
};

// The surface that will wear the baked page (a level of the chain), at the page's UVs: the frames
// its normal map is expressed in. Per triangle, per corner, in the cornerUV convention; normals
// unit, tangents as glTF's TANGENT (lodbake/core/tangents.h). A texel takes the frame of the
// target triangle it lies in (or the nearest within `reach` texels; beyond, the original's own).
struct BakeTarget {
    std::vector<std::array<Vec2, 3>> uv;
    std::vector<std::array<Vec3, 3>> normal;
    std::vector<std::array<Vec4, 3>> tangent;
    double reach = 4;
};

// The original faces a projected island samples, described rather than listed (projectedIslandNear):
// the faces of `grid` whose boxes meet [lo, hi] and lie within `reach` of `centre`, those facing
// the island's way unless allFaces. A texel's closest point among them is then found around the
// texel, at the cost of the faces near it, rather than among a list of every one.
struct IslandNear {
    const FaceGrid* grid = nullptr;
    Vec3 lo{}, hi{}, centre{};
    double reach = 0;
    bool allFaces = false;
};

// A UV triangle of the atlas that is not an original face (parameterize's level islands): each
// texel it covers maps to a point X of the 3D triangle `position` and shows the original surface
// at the point of `faces` closest to X (same shading as the original faces), among the faces that
// face the triangle's way when there are any (a thin wall's other sheet is not read).
struct BakeIsland {
    std::array<Vec3, 3> position{};
    std::array<Vec2, 3> uv{};            // glTF convention, like cornerUV
    std::vector<uint32_t> faces;         // original faces to sample (non-empty unless near.grid is set)
    IslandNear near;                     // with a grid: the faces, described (faces unused)
};

// The level-triangle islands of a chart layout as the bake takes them: the layout's UVs, and as
// faces those of the charts holding one of the island's vertices that lie near enough to hold a
// closest point of the island (the bake's facesNearTriangle keeps no others).
// \throw InvalidInput (an island touching no chart).
std::vector<BakeIsland> layoutBakeIslands(const TriMesh& mesh, const ChartLayout& layout);

// The faces of `grid` (built over `mesh`) meeting box [lo, hi] that the bake keeps for an island
// on triangle `tri`, described (IslandNear); false when the box holds none. Found at the cost of
// the faces near the triangle rather than of the box's.
bool projectedIslandNear(const TriMesh& mesh, const FaceGrid& grid, const std::array<Vec3, 3>& tri, Vec3 lo, Vec3 hi,
                         IslandNear& near);
// A projected island's faces among those of `grid` meeting box [lo, hi]: listed (island.faces)
// when the box holds few, described (projectedIslandNear) when it holds many; false when it holds
// none.
bool projectedIslandFaces(const TriMesh& mesh, const FaceGrid& grid, Vec3 lo, Vec3 hi, BakeIsland& island);
// The faces `near` describes for an island on `tri`, ascending: what the bake's filter keeps of
// the faces meeting [near.lo, near.hi].
std::vector<uint32_t> nearFaces(const TriMesh& mesh, const IslandNear& near, const std::array<Vec3, 3>& tri);

struct BakeResult {
    Image image;                 // PNG, RGB 8-bit sRGB, width x height (empty without encodePng)
    std::vector<float> pixels;   // the same as floats in [0,1] (encoded sRGB), RGB interleaved, top row first
    // The other channels, as they are written (8-bit steps in [0,1], top row first), each empty
    // unless asked for: alpha (1 per texel, linear), orm (RGB = occlusion, roughness, metallic,
    // linear), emissive (RGB, sRGB-encoded, divided by emissiveScale), normal (RGB = tangent-space
    // xyz x 0.5 + 0.5).
    std::vector<float> alpha, orm, emissive, normal;
    // The extension images (BakeChannels), as written: clearcoat, transmission and iridescence
    // RGB (B = 0), clearcoatNormal RGB like normal, sheen, specular and diffuseTransmission RGBA,
    // anisotropy RGB.
    std::vector<float> clearcoat, clearcoatNormal, sheen, specular, transmission, iridescence, diffuseTransmission, anisotropy;
    double emissiveScale = 1;    // the largest linear emissive value when above 1 (KHR_materials_emissive_strength), else 1
    size_t coveredTexels = 0;    // texels hit by a triangle (incl. dilation)
    size_t texturedLookups = 0;  // texels shaded with a filtered base colour texture fetch
    size_t islandTexels = 0;     // texels filled from islands
    double seconds = 0;
};

// The asset's images, decoded once for every bake of that asset (each to MIP levels on the first
// bake that reads it, lodbake/bake/texture_fetch.h): pack
// bakes one page per level, texture-refine one per layout and size. The asset must outlive it.
class BakeSources {
public:
    // \throw IOError (an image cannot be decoded).
    explicit BakeSources(const Asset& asset);
    ~BakeSources();
    BakeSources(const BakeSources&) = delete;
    BakeSources& operator=(const BakeSources&) = delete;
    const Asset& asset() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    friend struct BakeSourcesAccess;  // the bake reads the decoded sources (lib/src/bake/bake_sources.h)
};

// Rasterises the ORIGINAL triangles of asset.mesh at `cornerUV` (per face corner, glTF convention:
// [0,1], v down) and stores at each texel the original base colour = baseColorFactor x
// baseColorTexture (texCoord set, sampler wrap, KHR_texture_transform; filtered with derivatives
// from the UV Jacobian) x COLOR_0, composed in linear space and stored as sRGB.
// Islands (see BakeIsland) are rasterised too; where an island and a face cover a texel, the
// exact (undilated) hit wins, then the face.
// \pre cornerUV.size() == asset.mesh.triangleCount().
// \throw InvalidInput (size mismatch, island without faces), IOError (an image cannot be decoded).
BakeResult bakeBaseColor(const BakeSources& sources, const std::vector<std::array<Vec2, 3>>& cornerUV,
                         const BakeOptions& options = {}, const std::vector<BakeIsland>& islands = {});
// The same with every channel of options.channels: each texel shows the original material at
// the original surface point the layout maps it to. The normal channel is the original's shading
// normal (interpolated normal perturbed by its normal map in its own tangent frame: the file's
// TANGENT or computeWedgeTangents) expressed in the tangent frame of `target` at that texel; the
// clearcoat normal likewise with the clearcoat normal map (none: the interpolated normal), and the
// anisotropy direction likewise in the target's tangent plane.
// \pre as bakeBaseColor; target (when channels.normal, clearcoatNormal or anisotropy) has the same UV scale as cornerUV.
BakeResult bakeMaterial(const BakeSources& sources, const std::vector<std::array<Vec2, 3>>& cornerUV,
                        const BakeOptions& options, const std::vector<BakeIsland>& islands = {},
                        const BakeTarget* target = nullptr);
// The same for one bake (the images are decoded for this call).
BakeResult bakeBaseColor(const Asset& asset, const std::vector<std::array<Vec2, 3>>& cornerUV,
                         const BakeOptions& options = {}, const std::vector<BakeIsland>& islands = {});

}  // namespace lodbake
