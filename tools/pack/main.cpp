// pack: parameterized multiresolution glTF in, final glTF LOD chain out (MSFT_lod, one mesh /
// one material / one draw call per level, atlases sized for each level's screen size).
#include <chrono>
#include <cstdio>
#include <iostream>

#include "common/cli.h"
#include "lodbake/core/errors.h"
#include "lodbake/texture/codec.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/lod/lod_chain.h"

using namespace lodbake;

namespace {

struct Settings {
    cli::CommonSettings common;
    PackOptions pack;
    PackWriteOptions write;
    std::string imageFormat = "png";
};

Settings defaults() {
    Settings s;
    s.write.chain.generator = "lodbake pack 0.1.0";
    return s;
}

Settings parseArgs(int argc, char** argv, bool& proceed) {
    Settings s = defaults();
    cli::ArgParser p("pack", "-i INPUT.uv.glb -o OUTPUT.lod.glb [options]");
    p.addCommon(s.common);
    p.option("--pixel-error", "PX", "largest on-screen geometric deviation of a level, pixels (default 1)",
             [&](const std::string& v) { s.pack.pixelError = cli::parseDouble("--pixel-error", v); });
    p.option("--viewport-height", "PX", "viewport height the coverage is computed for, pixels (default 1080)",
             [&](const std::string& v) { s.pack.viewportHeight = cli::parseInt("--viewport-height", v); });
    p.option("--fov", "DEG", "vertical field of view for the reported switch distances (default 60)",
             [&](const std::string& v) { s.pack.fovY = cli::parseDouble("--fov", v); });
    p.option("--cutoff-pixels", "PX", "cull the chain below this projected height, pixels (default 2)",
             [&](const std::string& v) { s.pack.cutoffPixels = cli::parseDouble("--cutoff-pixels", v); });
    p.option("--max-size", "N", "atlas page side cap, texels (default 2048)",
             [&](const std::string& v) { s.pack.maxSize = cli::parseInt("--max-size", v); });
    p.flag("--pot", "power-of-two atlas pages", [&] { s.pack.powerOfTwo = true; });
    p.option("--max-mips", "N", "gutters sized for at most N mip levels (default 4)",
             [&](const std::string& v) { s.pack.maxMips = cli::parseInt("--max-mips", v); });
    p.option("--samples", "N", "area samples per side for the measured Hausdorff distance (default 100000)",
             [&](const std::string& v) { s.pack.distanceSamples = size_t(cli::parseInt("--samples", v)); });
    p.option("--image-format", "png|jpeg", "atlas image format (default png)", [&](const std::string& v) {
        if (v != "png" && v != "jpeg" && v != "jpg") throw UsageError("--image-format must be png or jpeg");
        s.imageFormat = v;
    });
    p.option("--jpeg-quality", "Q", "JPEG quality 1..100 (default 90)",
             [&](const std::string& v) { s.pack.jpegQuality = cli::parseInt("--jpeg-quality", v); });
    p.flag("--split", "one file per level (OUTPUT.lodK.glb) plus OUTPUT.lods.json with the coverage values",
           [&] { s.write.split = true; });
    p.flag("--lod0-density", "texture every level at LOD0's texel density (pages about LOD0's size), for comparisons "
           "that render every level close up", [&] { s.pack.lod0Density = true; });
    p.flag("--no-texture-hierarchy", "texture every level with T0 even when the input has texture-refine's hierarchy",
           [&] { s.pack.useTextureHierarchy = false; });
    p.flag("--draco", "compress every level with KHR_draco_mesh_compression", [&] { s.write.chain.draco = true; });
    p.option("--qp", "BITS", "Draco position quantisation bits (default 14)",
             [&](const std::string& v) { s.write.chain.quantPosition = cli::parseInt("--qp", v); });
    p.option("--qt", "BITS", "Draco texture coordinate quantisation bits (default 12)",
             [&](const std::string& v) { s.write.chain.quantTexcoord = cli::parseInt("--qt", v); });
    p.option("--qn", "BITS", "Draco normal quantisation bits (default 10)",
             [&](const std::string& v) { s.write.chain.quantNormal = cli::parseInt("--qn", v); });
    p.flag("--external-images", ".gltf output: write the atlases beside the file instead of into the .bin",
           [&] { s.write.chain.embedImages = false; });
    proceed = p.parse(argc, argv);
    s.pack.imageFormat = s.imageFormat == "png" ? ImageFormat::Png : ImageFormat::Jpeg;
    s.pack.threads = s.common.threads;
    return s;
}

void validate(const Settings& s) {
    const PackOptions& o = s.pack;
    if (!(o.pixelError > 0)) throw UsageError("--pixel-error must be > 0");
    if (o.viewportHeight < 16) throw UsageError("--viewport-height must be >= 16");
    if (!(o.fovY > 0 && o.fovY < 180)) throw UsageError("--fov must be in (0, 180)");
    if (!(o.cutoffPixels > 0)) throw UsageError("--cutoff-pixels must be > 0");
    if (o.maxSize < 16 || o.maxSize > 16384) throw UsageError("--max-size must be in [16, 16384]");
    if (o.maxMips < 0 || o.maxMips > 12) throw UsageError("--max-mips must be in [0, 12]");
    if (o.jpegQuality < 1 || o.jpegQuality > 100) throw UsageError("--jpeg-quality must be in [1, 100]");
    const LodChainWriteOptions& c = s.write.chain;
    for (int q : {c.quantPosition, c.quantTexcoord, c.quantNormal})
        if (q < 1 || q > 30) throw UsageError("--qp/--qt/--qn must be in [1, 30]");
    cli::checkPaths(s.common);
}

int run(Settings s) {
    validate(s);
    std::optional<Multires> multires;
    double loadSeconds = 0;
    Asset asset = cli::loadInput("pack", s.common, loadSeconds, &multires, [](Asset& a) { checkImages(a); });
    if (!multires) throw Impossible(s.common.input + ": no LODBAKE_multires extension; run simplify and parameterize first");

    cli::Progress progress("pack", cli::progressEnabled(s.common));
    s.pack.progress = [&progress](double f) { return progress(f); };
    PackResult res = packLodChain(asset, *multires, s.pack);
    progress.done();

    auto t1 = std::chrono::steady_clock::now();
    PackWriteStats ws = writePackResult(s.common.output, res, s.write);
    double writeSeconds = cli::secondsSince(t1);

    nlohmann::json levels = nlohmann::json::array();
    for (size_t k = 0; k < res.reports.size(); ++k) {
        const PackLevelReport& r = res.reports[k];
        levels.push_back({{"lod", k},
                          {"source", r.source},
                          {"triangles", r.triangles},
                          {"vertices", r.vertices},
                          {"drawCalls", 1},
                          {"texels", uint64_t(r.width) * uint64_t(r.height)},
                          {"width", r.width},
                          {"height", r.height},
                          {"bytes", ws.levelBytes[k]},
                          {"charts", r.charts},
                          {"gutter", r.gutter},
                          {"mips", r.mips},
                          {"utilisation", r.utilisation},
                          {"boxUtilisation", r.boxUtilisation},
                          {"rasterUtilisation", r.rasterUtilisation},
                          {"footprintUtilisation", r.footprintUtilisation},
                          {"texelsPerUnit", r.texelsPerUnit},
                          {"texelLimit", r.texelLimit},
                          {"deviation", {{"hausdorff", r.hausdorff}, {"relHausdorff", r.relHausdorff}, {"rms", r.rms},
                                         {"relRms", r.relRms}, {"simplifyMax", r.maxDeviation}}},
                          {"screenCoverage", r.coverage},
                          {"maxScreenCoverage", r.maxCoverage},
                          {"switchDistance", r.switchDistance},
                          {"bakeSeconds", r.bakeSeconds},
                          {"textureRank", r.rank},
                          {"pageSideNeeded", r.sideNeeded},
                          {"hierarchyTextureSize", r.textureSize}});
    }
    nlohmann::json rep;
    rep["tool"] = "pack";
    rep["input"] = {{"path", s.common.input}, {"triangles", asset.mesh.triangleCount()}, {"levels", multires->levels.size()},
                    {"charts", multires->charts.chartCount}};
    rep["output"] = {{"path", s.common.output}, {"files", ws.files}, {"bytes", ws.totalBytes}};
    rep["options"] = {{"pixelError", s.pack.pixelError}, {"viewportHeight", s.pack.viewportHeight}, {"fov", s.pack.fovY},
                      {"cutoffPixels", s.pack.cutoffPixels}, {"maxSize", s.pack.maxSize}, {"pot", s.pack.powerOfTwo},
                      {"maxMips", s.pack.maxMips}, {"imageFormat", s.imageFormat}, {"jpegQuality", s.pack.jpegQuality},
                      {"split", s.write.split}, {"textureHierarchy", s.pack.useTextureHierarchy},
                      {"lod0Density", s.pack.lod0Density}, {"draco", s.write.chain.draco},
                      {"qp", s.write.chain.quantPosition}, {"qt", s.write.chain.quantTexcoord}, {"qn", s.write.chain.quantNormal}};
    rep["utilisationDefinition"] = "chart texels / page texels; chart texels = the charts' triangle coverage (UV area); "
                                   "boxUtilisation uses the charts' rotated bounding rectangles (above 1 when charts nest), "
                                   "rasterUtilisation the texels their triangles touch, footprintUtilisation adds each "
                                   "chart's gutter ring (which may reach past the page border)";
    rep["radius"] = res.radius;
    rep["diagonal"] = res.diagonal;
    rep["screenCoverage"] = res.screenCoverage;
    rep["levels"] = levels;
    rep["warnings"] = asset.warnings;
    rep["time"] = {{"load", loadSeconds}, {"pack", res.seconds}, {"write", writeSeconds}};
    if (!s.common.report.empty()) cli::writeReport(s.common.report, rep);
    if (s.common.verbose) {
        std::printf("lod  triangles  page        util   box    gutter  hausdorff(rel)  coverage\n");
        for (size_t k = 0; k < res.reports.size(); ++k) {
            const PackLevelReport& r = res.reports[k];
            std::printf("%3zu  %9zu  %4dx%-5d  %5.1f%% %5.1f%% %6d  %.3g (%.2e)  %.4g\n", k, r.triangles, r.width, r.height,
                        100 * r.utilisation, 100 * r.boxUtilisation, r.gutter, r.hausdorff, r.relHausdorff, r.coverage);
        }
        std::printf("output: %s (%llu bytes), time: pack %.2fs, write %.2fs\n", s.common.output.c_str(),
                    static_cast<unsigned long long>(ws.totalBytes), res.seconds, writeSeconds);
    }
    return cli::kOk;
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Settings>("pack", argc, argv, parseArgs, run); }
