// pack: the final glTF LOD chain. From a parameterized multiresolution asset, every
// level (LOD0 = the original triangles, LOD k = multires level k) gets its own atlas page: the
// charts of its layout repacked at the texel density the level can show, the ORIGINAL appearance
// baked into it (bakeBaseColor, pull-push gap fill), one mesh / one material / one draw call per
// level (several primitives on the same pages where the materials disagree on what glTF cannot
// vary per texel: PackOptions::maxDraws). The layout is T0 (multires.charts) or, when
// texture-refine added a texture hierarchy (multires.textures), a texture valid for the level that
// the hierarchy offers at the page side the level needs: of those and T0, the one whose bake shows
// the least texture deviation.
// Screen coverage thresholds come from each level's measured two-sided Hausdorff distance to
// the original.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"
#include "lodbake/core/pose_samples.h"
#include "lodbake/texture/codec.h"
#include "lodbake/gltf/msft_lod.h"
#include "lodbake/gltf/source_scene.h"
#include "lodbake/lod/pack_profile.h"

namespace lodbake {

// When a level's page gets a baked normal map.
enum class NormalMaps {
    Auto,    // when the input has normal maps, and on every level coarser than the original
    Always,  // on every level, LOD0 included
    Never,
};

// What LOD0 is.
enum class Lod0 {
    Baked,     // the original triangles, one mesh / one material / one draw call like every level
    Original,  // the input asset itself: its own meshes, materials and nodes (several draw calls,
               // exact appearance up close); the baked one-draw levels are LOD1 onwards
};

struct PackOptions {
    double pixelError = 1;       // a level is used while its deviation projects to <= this many pixels
    int viewportHeight = 1080;   // pixels
    double fovY = 60;            // vertical field of view, degrees (switch distances in the report)
    double lod0Coverage = 1;     // the largest screen coverage LOD0's texture is sized for (1 = fills the viewport height)
    double cutoffPixels = 2;     // the last MSFT_screencoverage value: the chain is culled below this many pixels tall
    int maxSize = 2048;          // page side cap, texels
    bool powerOfTwo = false;     // power-of-two pages
    int maxMips = 4;             // gutters are sized for at most this many mip levels below the page
    int minMipSide = 16;         // ... and never for mips whose page side is below this (texels)
    size_t distanceSamples = 100000;  // area samples per side for the measured Hausdorff distance
    // Rigged inputs: the measured distance is the largest over the bind pose and these poses.
    PoseSampleOptions poses;
    int threads = 0;             // 0 = all cores
    ImageFormat imageFormat = ImageFormat::Png;
    int jpegQuality = 90;
    // Non-empty: textures as KTX2 (KHR_texture_basisu) through this Basis Universal encoder
    // executable (lodbake/texture/ktx2.h: findBasisu), from PNG whatever imageFormat says.
    std::string ktx2Encoder;
    // Every level textured at LOD0's texel density (pages about as large as LOD0's) instead of the
    // density it can show at its largest coverage: for comparisons at equal texel density that
    // render every level close up (scripts/bench.py quality).
    bool lod0Density = false;
    NormalMaps normalMaps = NormalMaps::Auto;
    // Coarse levels' texels show the original surface at the closest point of their own surface
    // (true), or where the shared chart layout maps them (false; exact only where the layout's
    // parameterisation is affine over each coarse triangle).
    bool projectLevels = true;
    // Coarse levels baked by projection get their vertices moved towards the original surface
    // (least squares over the two-sided distance; lod/vertex_placement.h); a level keeps the moved
    // vertices only when its measured Hausdorff distance does not grow.
    bool vertexPlacement = true;
    // Bake base colour only (every other channel a constant factor, no normal map): the chain
    // without its material channels, for comparisons.
    bool baseColorOnly = false;
    bool useTextureHierarchy = true;  // false: every level uses T0 even when the file has a texture hierarchy
    // Where T0 and hierarchy ranks are eligible for a level, the one whose bake shows the least
    // texture deviation (lod/rank_choice.h; a few half-side bakes per level); false: the highest
    // eligible rank (the rank with the lowest mapping energy E).
    bool rankByBake = true;
    // LOD0's page copies the original's texels one to one, its charts the original's texture
    // islands (lod/source_texels.h), where the original allows it (else, and when false, LOD0
    // resamples them at its layout's density like every level).
    bool sourceTexels = true;
    // Where every triangle wears one material whose textures repeat (lod/tiled_levels.h), the
    // levels keep its texture coordinates and their pages hold one period of it, repeated by the
    // sampler, instead of an atlas of the surface.
    bool keepTiling = true;
    // At most this many primitives (draw calls) per baked level where the input's materials
    // disagree on what glTF cannot vary per texel (ior, attenuation, dispersion, iridescence ior,
    // unlit, alpha mode and cutoff: lodbake/bake/draw_split.h); 0 = as many as keep every
    // combination exact, 1 = one primitive with area-weighted values (and a warning per property).
    size_t maxDraws = 0;
    Lod0 lod0 = Lod0::Baked;
    // Lod0::Original: the input asset the chain was made from (the file simplify read). Its
    // flattened triangles must be the multires original's. Empty with Lod0::Original = an error.
    std::string original;
    std::function<bool(double)> progress;  // fraction done; return false to cancel (throws Cancelled); may be empty
    PackProfile* profile = nullptr;        // non-null: receives where the time went
};

struct PackLevelReport {
    std::string source;           // "original" or "level K" of the multires input
    size_t triangles = 0, vertices = 0;
    size_t drawCalls = 1, materials = 1;  // primitives and their materials (the original as LOD0: its own)
    std::vector<std::string> splitBy;     // the properties the level's primitives differ in (uniformDifferences)
    int width = 0, height = 0;    // atlas page, texels
    int gutter = 0, mips = 0;     // gutter (texels) and the mip levels it was sized for
    size_t charts = 0;            // charts on the page
    size_t absorbedIslands = 0;   // projection bake: level-triangle islands unfolded onto a neighbouring chart
    double utilisation = 0;       // chart texels (actual triangle coverage) / page texels
    double boxUtilisation = 0;    // chart bounding rectangles / page texels (above 1 when charts nest)
    double rasterUtilisation = 0;     // texels the charts' triangles touch (conservative raster) / page texels
    double footprintUtilisation = 0;  // ... with each chart's gutter ring / page texels
    double texelsPerUnit = 0;     // texels per model unit (area-averaged)
    double texelLimit = 0;        // texels per model unit the level can show at its largest coverage
    double hausdorff = 0, relHausdorff = 0;  // measured two-sided, model units / relative to the diagonal
    double rms = 0, relRms = 0;
    double maxDeviation = 0;      // simplify's own Level::maxDeviation (0 for LOD0)
    // Vertex placement (projected coarse levels with vertexPlacement): whether the moved vertices
    // were kept, the measured distance before placement (the figures above are after it), and
    // what moved.
    struct Placement {
        bool tried = false, applied = false;
        // Before placement; when it was kept, measured only until they reached the figures after it.
        double hausdorff = 0, relHausdorff = 0, rms = 0, relRms = 0;
        size_t moved = 0, fixed = 0, shortened = 0;  // vertices moved / held on open edges / steps shortened against flips
        int rounds = 0;               // least-squares rounds run
        std::string skipped;          // why placement was not tried on a level it could not improve
    } placement;
    double coverage = 0;          // MSFT_screencoverage value: the level is used at coverage >= this
    double maxCoverage = 0;       // ... and below this (the next finer level's threshold; LOD0: lod0Coverage)
    double switchDistance = 0;    // camera distance (model units, fovY) at which the next coarser level takes over
    std::vector<std::string> channels;  // the textures of the level's material (level_material.h channelNames)
    double sideNeeded = 0;        // page side estimate the level needs: sqrt(3D area) x texelLimit / 0.8, capped by maxSize
    // LOD0: its page holds the original's texels one to one (PackOptions::sourceTexels), or why not.
    bool sourceTexels = false;
    std::string sourceTexelsNote;
    // The level keeps the input material's tiling (PackOptions::keepTiling, lod/tiled_levels.h):
    // its UVs are the original's texture coordinates, its page (width x height) one period of the
    // material, its sampler repeats. `note` says why (or why not: the chain is not eligible, or the
    // level's UVs stretch over too much of its area and it takes an atlas page).
    struct Tiling {
        bool tiled = false;
        std::string note;
        double span = 0;              // extent of the texture coordinates, tiles
        size_t rechosen = 0;          // triangles that took other wedges of their corners (corners across UV seams)
        size_t stretched = 0;         // ... still stretched or flipped after that
        double stretchedArea = 0;     // their share of the level's area
    } tiling;
    // KHR_materials_variants, per variant of the input: its name, the level's variant material it
    // uses (-1 = the level's default material: the variant changes nothing the level shows; two
    // variants with equal materials share one) and that material's textures (channelNames).
    struct Variant {
        std::string name;
        int material = -1;
        std::vector<std::string> channels;
    };
    std::vector<Variant> variants;
    uint32_t rank = 0;            // texture hierarchy rank the level is textured with (0 = T0)
    int textureSize = 0;          // the hierarchy texture of that rank whose resolution the level needs
                                  // (smallest side >= its texel limit, else the largest); 0 = no hierarchy
    // How `rank` was chosen where more than one layout was eligible (PackOptions::rankByBake):
    // every candidate's page baked at half the side and read back at sample points of the level
    // against a probe bake of them (lod/rank_choice.h). Empty candidates: one layout was eligible.
    struct RankChoice {
        struct Candidate {
            uint32_t rank = 0;
            double score = 0;                 // RMS texture deviation over the compared channels (lower is better)
            double baseColor = 0, normal = 0; // RMS per channel (encoded [0,1] values; normal in object space)
            int width = 0, height = 0;        // the scored page
            size_t charts = 0;
        };
        std::vector<Candidate> candidates;    // T0 first, then the eligible ranks, ascending
        uint32_t byEnergy = 0;                // the rank the energy rule picks (the highest eligible)
        std::string reason;
    } rankChoice;
};

struct PackResult {
    std::vector<LodLevelData> levels;       // LOD0 first; with `original`, the baked levels LOD1 onwards
    std::optional<SourceScene> original;    // Lod0::Original: the input asset, written as LOD0
    std::vector<double> screenCoverage;     // one per level (= ids + 1), decreasing; the last culls the coarsest
    std::vector<PackLevelReport> reports;   // per level
    double radius = 0, diagonal = 0;        // bounding sphere radius (half the bbox diagonal) and the diagonal
    std::vector<std::string> warnings;      // the material plan's (mixed alpha modes, sidedness, shading)
    Rig rig;                                // the asset's skin and animations, written once for every level
    MorphTargets morph;                     // the asset's morph target names and default weights
    SceneExtras scene;                      // the asset's lights, cameras and extras, written with the chain
    std::vector<std::string> variants;      // the asset's KHR_materials_variants names (levels' variantMaterial index them)
};

// With Lod0::Original, LOD0's page is still packed (the next level's page is held to its texel
// count, as in a baked chain, so LOD1 onwards are the same as there) but not baked, and the
// report's LOD0 describes the original (no page, its draw calls and materials, deviation 0).
// \pre `multires.charts` is set (the asset went through parameterize) and matches asset.mesh.
// \throw Impossible (no chart layout, no triangles), InvalidInput (inconsistent multires; an
//        `original` whose triangles are not the chain's), IOError (bake temp files / image
//        encoding), and readSourceScene's errors for `original`.
PackResult packLodChain(const Asset& asset, const Multires& multires, const PackOptions& options = {});

}  // namespace lodbake
