// parameterize: multiresolution glTF in, same + new atlas UVs and one baked base-colour texture
// valid for every level (thesis 3.3).
#include <chrono>
#include <cstdio>
#include <iostream>

#include "common/cli.h"
#include "lodbake/bake/bake.h"
#include "lodbake/core/errors.h"
#include "lodbake/texture/codec.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/param/parameterize.h"

using namespace lodbake;

namespace {

struct Settings {
    cli::CommonSettings common;
    int size = 1024;
    double alpha = 0.8;
    double beta = 0.7;
    int maxCharts = 0;
    int iterations = 50;
    bool allowLevelFolds = false;
    bool levelIslands = true;
    bool crossingIslands = true;
};

Settings parseArgs(int argc, char** argv, bool& proceed) {
    Settings s;
    cli::ArgParser p("parameterize", "-i INPUT.mr.glb -o OUTPUT.uv.glb [options]");
    p.addCommon(s.common);
    p.option("--size", "N", "atlas side in texels (default 1024)", [&](const std::string& v) { s.size = cli::parseInt("--size", v); });
    p.option("--alpha", "A", "edge vs area weight in E_pixel, in [0,1] (default 0.8)",
             [&](const std::string& v) { s.alpha = cli::parseDouble("--alpha", v); });
    p.option("--beta", "B", "E_pixel vs E_poly weight, in [0,1] (default 0.7)",
             [&](const std::string& v) { s.beta = cli::parseDouble("--beta", v); });
    p.option("--max-charts", "N", "merge charts down to at most N (0 = by shape limits only)",
             [&](const std::string& v) { s.maxCharts = cli::parseInt("--max-charts", v); });
    p.option("--iterations", "N", "Ceres iterations per chart (0 = keep the Tutte maps; default 50)",
             [&](const std::string& v) { s.iterations = cli::parseInt("--iterations", v); });
    p.flag("--no-level-islands",
           "no fallback islands: a level triangle that folds in its chart keeps its folded UVs (then exit 4 unless "
           "--allow-level-folds)",
           [&] { s.levelIslands = false; });
    p.flag("--no-crossing-islands",
           "a level triangle that crosses a chart boundary takes projected UVs in one chart instead of its own "
           "island (smears that chart's texture over it)",
           [&] { s.crossingIslands = false; });
    p.flag("--allow-level-folds",
           "write the output even when a level keeps flipped/overlapping UV triangles (reported); default: exit 4",
           [&] { s.allowLevelFolds = true; });
    p.exitCodes(
        "Every level is checked in the packed atlas (flipped or overlapping UV triangles). A level\n"
        "triangle that still folds inside its chart (usually one a collapse moved across a chart cut)\n"
        "falls back to its own small UV island: the coarse triangle laid flat at the atlas density,\n"
        "baked by sampling the closest point of the original surface at each texel (same density,\n"
        "but its texels are not continuous with the neighbouring charts', so filtering can show a\n"
        "seam). The report counts islands per level (islandTriangles); docs/parameterize.md.\n"
        "Exit codes: 0 success, 1 usage error, 2 unreadable or invalid input,\n"
        "            3 valid input but the operation is impossible, 4 internal or solver failure\n"
        "            (including a level that still folds, unless --allow-level-folds).\n");
    proceed = p.parse(argc, argv);
    return s;
}

void validate(const Settings& s) {
    if (s.size < 16 || s.size > 16384) throw UsageError("--size must be in [16, 16384]");
    if (!(s.alpha >= 0 && s.alpha <= 1)) throw UsageError("--alpha must be in [0, 1]");
    if (!(s.beta >= 0 && s.beta <= 1)) throw UsageError("--beta must be in [0, 1]");
    if (s.maxCharts < 0) throw UsageError("--max-charts must be >= 0");
    if (s.iterations < 0) throw UsageError("--iterations must be >= 0");
    cli::checkPaths(s.common);
}

nlohmann::json energyJson(const ChartEnergy& e) {
    return {{"E", e.E}, {"E_pixel", e.pixel}, {"E_poly", e.poly}, {"E_l", e.edge}, {"E_s", e.area}};
}

int run(const Settings& s) {
    validate(s);
    std::optional<Multires> multires;
    double loadSeconds = 0;
    Asset asset = cli::loadInput("parameterize", s.common, loadSeconds, &multires, [](Asset& a) { checkImages(a); });
    if (!multires) throw Impossible(s.common.input + ": no LODBAKE_multires extension; run simplify first");

    ParameterizeOptions opt;
    opt.solve.energy.alpha = s.alpha;
    opt.solve.energy.beta = s.beta;
    opt.textureSize = s.size;
    opt.solve.maxIterations = s.iterations;
    opt.charts.maxCharts = uint32_t(s.maxCharts);
    opt.threads = s.common.threads;
    opt.levelIslands = s.levelIslands;
    opt.crossingIslands = s.crossingIslands;
    cli::Progress progress("parameterize", cli::progressEnabled(s.common));
    opt.progress = [&progress](double f) { return progress(f); };
    ParameterizeResult param = parameterize(asset.mesh, *multires, opt);
    progress.done();
    if (param.flips > 0 || param.overlaps > 0)
        throw SolverError(s.common.input + ": " + std::to_string(param.flips) + " flipped and " +
                          std::to_string(param.overlaps) + " overlapping UV triangles remain");

    auto t1 = std::chrono::steady_clock::now();
    BakeOptions bo;
    bo.size = s.size;
    bo.threads = s.common.threads;
    std::vector<BakeIsland> islands;
    for (const LevelIsland& li : param.islands) {
        BakeIsland b;
        for (size_t k = 0; k < 3; ++k) b.position[k] = asset.mesh.positions[li.vertices[k]];
        b.uv = li.uv;
        b.faces = li.faces;
        islands.push_back(std::move(b));
    }
    BakeResult baked = bakeBaseColor(asset, param.cornerUV, bo, islands);
    double bakeSeconds = cli::secondsSince(t1);

    AtlasApplyStats applied = applyAtlas(asset, *multires, param, baked.image);

    // Injectivity of every level with its final UVs (level 0 = the original triangles in the atlas).
    std::vector<UVInjectivity> levelChecks;
    {
        std::vector<std::array<Vec2, 3>> atlas0;
        for (size_t f = 0; f < asset.mesh.triangleCount(); ++f) {
            const Tri& v = asset.mesh.triangles[f];
            if (v[0] != v[1] && v[1] != v[2] && v[0] != v[2]) atlas0.push_back(param.cornerUV[f]);
        }
        levelChecks.push_back(checkUVInjectivity(atlas0));
        for (const Level& L : multires->levels) levelChecks.push_back(checkLevelUVs(asset.mesh, L.triangles, L.cornerWedges));
    }
    // Texture deviation of the coarsest level (what beta < 1 is meant to lower).
    auto t3 = std::chrono::steady_clock::now();
    TextureDeviation deviation;
    TextureDeviationOptions dopt;
    dopt.islands = &param.islands;
    dopt.threads = s.common.threads;
    if (!multires->levels.empty()) deviation = textureDeviation(asset.mesh, multires->levels.back(), multires->charts, dopt);
    double deviationSeconds = cli::secondsSince(t3);
    size_t levelFlips = 0, levelOverlaps = 0;
    for (const UVInjectivity& c : levelChecks) {
        levelFlips += c.flips;
        levelOverlaps += c.overlaps;
    }
    nlohmann::json charts = nlohmann::json::array();
    for (size_t c = 0; c < param.chartReports.size(); ++c) {
        const ChartReport& r = param.chartReports[c];
        charts.push_back({{"chart", c},
                          {"faces", r.faces},
                          {"vertices", r.vertices},
                          {"pairs", r.pairs},
                          {"method", r.method},
                          {"iterations", r.iterations},
                          {"tutte", energyJson(r.tutte)},
                          {"final", energyJson(r.final)},
                          {"stretchL2", r.stretchL2},
                          {"stretchLinf", r.stretchLinf},
                          {"areaRatioStdDev", r.areaRatioStdDev},
                          {"flips", r.flips},
                          {"overlaps", r.overlaps},
                          {"levelFlips", r.levelFlips},
                          {"seconds", r.seconds}});
    }
    nlohmann::json rep;
    rep["tool"] = "parameterize";
    rep["input"] = {{"path", s.common.input},
                    {"triangles", asset.mesh.triangleCount()},
                    {"levels", multires->levels.size()}};
    rep["output"] = s.common.output;
    rep["options"] = {{"size", s.size}, {"alpha", s.alpha}, {"beta", s.beta}, {"maxCharts", s.maxCharts},
                      {"iterations", s.iterations}};
    rep["charts"] = charts;
    nlohmann::json levels = nlohmann::json::array();
    for (size_t k = 0; k < levelChecks.size(); ++k)
        levels.push_back({{"level", k}, {"triangles", levelChecks[k].triangles}, {"flips", levelChecks[k].flips},
                          {"overlaps", levelChecks[k].overlaps},
                          {"islandTriangles", k == 0 ? size_t(0) : param.levels[k - 1].islands},
                          {"projectedCorners", k == 0 ? size_t(0) : param.levels[k - 1].projectedCorners}});
    rep["levels"] = levels;
    rep["textureDeviation"] = {{"level", multires->levels.size()},
                               {"samples", deviation.samples},
                               {"outside", deviation.outside},
                               {"islandSamples", deviation.islandSamples},
                               {"mean", deviation.mean},
                               {"rms", deviation.rms},
                               {"max", deviation.max},
                               {"meanRelative", deviation.meanRelative},
                               {"maxRelative", deviation.maxRelative}};
    rep["total"] = {{"charts", param.charts.chartCount},
                    {"baseRegions", param.charts.baseRegions},
                    {"splitRegions", param.charts.splitRegions},
                    {"merges", param.charts.merges},
                    {"tutte", energyJson(param.tutteTotal)},
                    {"final", energyJson(param.finalTotal)},
                    {"stretchL2", param.stretchL2},
                    {"stretchLinf", param.stretchLinf},
                    {"areaRatioStdDev", param.areaRatioStdDev},
                    {"areaRatioHistogram", param.areaRatioHistogram},
                    {"flips", param.flips},
                    {"overlaps", param.overlaps},
                    {"levelFlips", levelFlips},
                    {"levelFlipsInSolve", param.levelFlips},
                    {"levelOverlaps", levelOverlaps},
                    {"texelsPerUnit", param.texelsPerUnit},
                    {"atlasFill", param.atlasFill},
                    {"newWedges", applied.newWedges},
                    {"projectedCorners", applied.projectedCorners},
                    {"islands", param.islands.size()},
                    {"floatRepairs", param.floatRepairs},
                    {"crossingIslandsSkipped", param.crossingIslandsSkipped},
                    {"islandTriangles", applied.islandTriangles},
                    {"islandTexels", baked.islandTexels},
                    {"coveredTexels", baked.coveredTexels},
                    {"texturedLookups", baked.texturedLookups}};
    rep["warnings"] = asset.warnings;
    rep["time"] = {{"load", loadSeconds}, {"parameterize", param.seconds}, {"bake", bakeSeconds},
                   {"checks", deviationSeconds}};
    if (!s.common.report.empty()) cli::writeReport(s.common.report, rep);
    // A folded level is never shipped (the report above says where).
    if ((levelFlips > 0 || levelOverlaps > 0) && !s.allowLevelFolds) {
        std::string per;
        for (size_t k = 0; k < levelChecks.size(); ++k)
            per += (k ? ", " : "") + std::to_string(k) + ": " + std::to_string(levelChecks[k].flips) + "/" +
                   std::to_string(levelChecks[k].overlaps);
        throw SolverError(s.common.input + ": the levels have " + std::to_string(levelFlips) + " flipped and " +
                          std::to_string(levelOverlaps) + " overlapping UV triangles (level: flipped/overlapping " +
                          per + ")");
    }

    auto t2 = std::chrono::steady_clock::now();
    WriteOptions wopt;
    wopt.generator = "lodbake parameterize 0.1.0";
    writeGltf(s.common.output, asset, &*multires, wopt);
    if (s.common.verbose) std::printf("write: %.2fs\n", cli::secondsSince(t2));


    if (s.common.verbose) {
        std::printf("charts: %u (from %u base regions, %u split), flips %zu, overlaps %zu\n", param.charts.chartCount,
                    param.charts.baseRegions, param.charts.splitRegions, param.flips, param.overlaps);
        std::printf("E: Tutte %.6g -> final %.6g (E_pixel %.6g, E_poly %.6g)\n", param.tutteTotal.E,
                    param.finalTotal.E, param.finalTotal.pixel, param.finalTotal.poly);
        std::printf("stretch L2 %.4f, Linf %.4f, area-ratio std-dev %.4f, atlas fill %.1f%%\n", param.stretchL2,
                    param.stretchLinf, param.areaRatioStdDev, 100 * param.atlasFill);
        for (size_t k = 0; k < levelChecks.size(); ++k)
            std::printf("level %zu: %zu triangles, %zu flipped, %zu overlapping in UV\n", k, levelChecks[k].triangles,
                        levelChecks[k].flips, levelChecks[k].overlaps);
        std::printf("texture deviation of level %zu: mean %.3g, max %.3g (x bbox diagonal)\n", multires->levels.size(),
                    deviation.meanRelative, deviation.maxRelative);
        std::printf("projected level corners: %zu; level-triangle islands: %zu (%zu level triangles)\n",
                    applied.projectedCorners, param.islands.size(), applied.islandTriangles);
        std::printf("time: parameterize %.2fs, bake %.2fs\n", param.seconds, bakeSeconds);
    }
    return cli::kOk;
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Settings>("parameterize", argc, argv, parseArgs, run); }
