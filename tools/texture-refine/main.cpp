// texture-refine: parameterized multiresolution glTF in, same + texture hierarchy out (MIP-style
// resolutions and rank-refined layouts, thesis chapter 4). `pack` picks from it per LOD.
#include <chrono>
#include <cstdio>
#include <iostream>

#include "common/cli.h"
#include "lodbake/core/errors.h"
#include "lodbake/texture/codec.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/texture_hierarchy/refine.h"

using namespace lodbake;

namespace {

struct Settings {
    cli::CommonSettings common;
    RefineOptions refine;
};

Settings parseArgs(int argc, char** argv, bool& proceed) {
    Settings s;
    cli::ArgParser p("texture-refine", "-i INPUT.uv.glb -o OUTPUT.tex.glb [options]");
    p.addCommon(s.common);
    p.option("--size", "N", "side of the atlas the rank layouts are packed for, texels; E is reported at this resolution (default 512)",
             [&](const std::string& v) { s.refine.param.textureSize = cli::parseInt("--size", v); });
    p.option("--sizes", "LIST", "MIP-style hierarchy: every layout is baked at each of these sides (default 128,256,512,1024)",
             [&](const std::string& v) {
                 s.refine.sizes.clear();
                 for (double x : cli::parseDoubleList("--sizes", v)) {
                     if (x != double(int(x))) throw UsageError("--sizes takes integers");
                     s.refine.sizes.push_back(int(x));
                 }
             });
    p.option("--min-refined-size", "N", "refined ranks are baked only at --sizes >= N; pack uses a rank only on pages >= its smallest size (default 128)",
             [&](const std::string& v) { s.refine.minRefinedSize = cli::parseInt("--min-refined-size", v); });
    p.option("--min-std-dev", "X", "do not refine levels where T0's UV-area/3D-area std-dev is below X (default 0.05)",
             [&](const std::string& v) { s.refine.minAreaRatioStdDev = cli::parseDouble("--min-std-dev", v); });
    p.option("--max-extra-cuts", "X", "a rank serves a level only if its chart boundaries cut at most this fraction of the level's triangles more than T0's (default 0.005)",
             [&](const std::string& v) { s.refine.maxExtraCutFraction = cli::parseDouble("--max-extra-cuts", v); });
    p.flag("--keep-level-triangles-whole", "merge pieces back while their boundaries cut more level triangles than their parent chart did",
           [&] { s.refine.keepLevelTrianglesWhole = true; });
    p.option("--ranks", "N", "refine up to rank N (fewer when no finer level splits the charts; 0 = MIP-style only; default 2)",
             [&](const std::string& v) { s.refine.ranks = cli::parseInt("--ranks", v); });
    p.option("--split", "N", "charts each chart is split into per rank (default 4)",
             [&](const std::string& v) { s.refine.splitPerChart = uint32_t(std::max(0, cli::parseInt("--split", v))); });
    p.option("--alpha", "A", "edge vs area weight in E_pixel, in [0,1] (default 0.8)",
             [&](const std::string& v) { s.refine.param.solve.energy.alpha = cli::parseDouble("--alpha", v); });
    p.option("--beta", "B", "E_pixel vs E_poly weight, in [0,1] (default 0.7)",
             [&](const std::string& v) { s.refine.param.solve.energy.beta = cli::parseDouble("--beta", v); });
    p.option("--iterations", "N", "Ceres iterations per chart (0 = Tutte maps; default 50)",
             [&](const std::string& v) { s.refine.param.solve.maxIterations = cli::parseInt("--iterations", v); });
    proceed = p.parse(argc, argv);
    return s;
}

void validate(const Settings& s) {
    const RefineOptions& o = s.refine;
    if (o.param.textureSize < 16 || o.param.textureSize > 16384) throw UsageError("--size must be in [16, 16384]");
    if (o.sizes.empty()) throw UsageError("--sizes must list at least one size");
    for (int x : o.sizes)
        if (x < 16 || x > 16384) throw UsageError("--sizes entries must be in [16, 16384]");
    if (o.minRefinedSize < 0) throw UsageError("--min-refined-size must be >= 0");
    if (!(o.minAreaRatioStdDev >= 0)) throw UsageError("--min-std-dev must be >= 0");
    if (!(o.maxExtraCutFraction >= 0 && o.maxExtraCutFraction <= 1)) throw UsageError("--max-extra-cuts must be in [0, 1]");
    if (o.ranks < 0 || o.ranks > 16) throw UsageError("--ranks must be in [0, 16]");
    if (o.splitPerChart < 2) throw UsageError("--split must be >= 2");
    if (!(o.param.solve.energy.alpha >= 0 && o.param.solve.energy.alpha <= 1)) throw UsageError("--alpha must be in [0, 1]");
    if (!(o.param.solve.energy.beta >= 0 && o.param.solve.energy.beta <= 1)) throw UsageError("--beta must be in [0, 1]");
    if (o.param.solve.maxIterations < 0) throw UsageError("--iterations must be >= 0");
    cli::checkPaths(s.common);
}

// E and its terms at resolution modifier r (the measure is at r = 1; every term is linear in r).
nlohmann::json energyJson(const ChartEnergy& e, double r) {
    return {{"E", e.E * r}, {"E_pixel", e.pixel * r}, {"E_poly", e.poly * r}, {"E_l", e.edge}, {"E_s", e.area}};
}

nlohmann::json measureJson(const LayoutMeasure& m, double r) {
    nlohmann::json levels = nlohmann::json::array();
    for (size_t k = 0; k < m.levels.size(); ++k)
        levels.push_back({{"level", k}, {"triangles", m.levels[k].triangles}, {"flips", m.levels[k].flips},
                          {"overlaps", m.levels[k].overlaps}, {"crossingTriangles", m.crossing[k]}});
    nlohmann::json j = energyJson(m.energy, r);
    j["charts"] = m.charts;
    j["pairs"] = m.pairs;
    j["areaRatioStdDev"] = m.areaRatioStdDev;
    j["areaRatioHistogram"] = m.areaRatioHistogram;
    j["triangles"] = m.triangles;
    j["flips"] = m.flips;
    j["overlaps"] = m.overlaps;
    j["levels"] = levels;
    return j;
}

int run(Settings s) {
    validate(s);
    std::optional<Multires> multires;
    double loadSeconds = 0;
    Asset asset = cli::loadInput("texture-refine", s.common, loadSeconds, &multires, [](Asset& a) { checkImages(a); });
    if (!multires) throw Impossible(s.common.input + ": no LODBAKE_multires extension; run simplify and parameterize first");
    if (multires->charts.empty()) throw Impossible(s.common.input + ": no chart layout; run parameterize first");

    cli::Progress progress("texture-refine", cli::progressEnabled(s.common));
    s.refine.progress = [&progress](double f) { return progress(f); };
    s.refine.param.threads = s.common.threads;
    RefineResult res = refineTextures(asset, *multires, s.refine);
    progress.done();
    size_t flips = 0, overlaps = 0;
    for (const RankResult& r : res.ranks) {
        flips += r.measure.flips;
        overlaps += r.measure.overlaps;
    }

    nlohmann::json ranks = nlohmann::json::array(), textures = nlohmann::json::array();
    const double rSize = (512.0 * 512.0) / (double(s.refine.param.textureSize) * s.refine.param.textureSize);
    for (const RankResult& r : res.ranks) {
        nlohmann::json j = {{"rank", r.rank},
                            {"validLevels", {r.firstLevel, r.lastLevel}},
                            {"regions", r.regions},
                            {"charts", r.layout.chartCount},
                            {"levelIslands", r.layout.islands.size()},
                            {"resolution", s.refine.param.textureSize},
                            {"refined", measureJson(r.measure, rSize)},
                            {"T0", measureJson(r.base, rSize)},
                            {"lowerE", r.measure.energy.E < r.base.energy.E},
                            {"lowerAreaRatioStdDev", r.measure.areaRatioStdDev < r.base.areaRatioStdDev}};
        if (r.rank > 0) {
            j["parameterize"] = {{"flips", r.chartFlips}, {"overlaps", r.chartOverlaps}, {"levelFlipsInSolve", r.levelFlipsInSolve},
                                 {"methods", r.methods}, {"resplits", r.resplits}, {"unsplitCharts", r.unsplit},
                                 {"seconds", r.parameterizeSeconds}};
            j["comparison"] = "T0 measured over the same levels at the same texel count (" + std::to_string(s.refine.param.textureSize) +
                              "^2 texels each)";
        }
        ranks.push_back(j);
    }
    for (const RefinedImage& img : res.images) {
        const RankResult& r = res.ranks[img.rank];
        double rr = (512.0 * 512.0) / (double(img.size) * img.size);
        nlohmann::json e = energyJson(r.measure.energy, rr);
        textures.push_back({{"rank", img.rank},
                            {"validLevels", {r.firstLevel, r.lastLevel}},
                            {"resolution", img.size},
                            {"charts", r.layout.chartCount},
                            {"E", e["E"]},
                            {"E_pixel", e["E_pixel"]},
                            {"E_poly", e["E_poly"]},
                            {"areaRatioStdDev", r.measure.areaRatioStdDev},
                            {"coveredTexels", img.coveredTexels},
                            {"bytes", img.image.encoded.size()},
                            {"bakeSeconds", img.seconds}});
    }

    applyTextureHierarchy(asset, *multires, res);
    auto t1 = std::chrono::steady_clock::now();
    WriteOptions wopt;
    wopt.generator = "lodbake texture-refine 0.1.0";
    writeGltf(s.common.output, asset, &*multires, wopt);
    double writeSeconds = cli::secondsSince(t1);

    nlohmann::json rep;
    rep["tool"] = "texture-refine";
    rep["input"] = {{"path", s.common.input}, {"triangles", asset.mesh.triangleCount()}, {"levels", multires->levels.size()},
                    {"charts", multires->charts.chartCount}};
    rep["output"] = s.common.output;
    rep["options"] = {{"size", s.refine.param.textureSize}, {"sizes", s.refine.sizes}, {"ranks", s.refine.ranks},
                      {"minRefinedSize", s.refine.minRefinedSize}, {"keepLevelTrianglesWhole", s.refine.keepLevelTrianglesWhole}, {"minStdDev", s.refine.minAreaRatioStdDev},
                      {"maxExtraCuts", s.refine.maxExtraCutFraction},
                      {"split", s.refine.splitPerChart}, {"alpha", s.refine.param.solve.energy.alpha}, {"beta", s.refine.param.solve.energy.beta},
                      {"iterations", s.refine.param.solve.maxIterations}};
    rep["levelNumbering"] = "0 = original mesh, k = multires level k (coarser as k grows); a texture is valid for levels validLevels[0]..validLevels[1]";
    rep["energyDefinition"] = "E = beta E_pixel + (1 - beta) E_poly over the layout's charts in model-unit UVs, pairs of the "
                              "levels served, r = 512^2 / texels; areaRatioStdDev over the triangles of the levels served";
    nlohmann::json rejected = nlohmann::json::array();
    for (const RejectedRank& x : res.rejected) rejected.push_back({{"level", x.level}, {"charts", x.charts}, {"reason", x.reason}});
    rep["ranks"] = ranks;
    rep["rejectedCandidates"] = rejected;
    rep["textures"] = textures;
    rep["total"] = {{"flips", flips}, {"overlaps", overlaps}, {"images", res.images.size()}};
    rep["warnings"] = asset.warnings;
    rep["time"] = {{"load", loadSeconds}, {"refine", res.seconds}, {"write", writeSeconds}};
    if (!s.common.report.empty()) cli::writeReport(s.common.report, rep);

    if (s.common.verbose) {
        for (const RankResult& r : res.ranks)
            std::printf("rank %u: levels %u..%u, %u charts, E %.6g (T0 %.6g), area-ratio std-dev %.4f (T0 %.4f), flips %zu, overlaps %zu\n",
                        r.rank, r.firstLevel, r.lastLevel, r.layout.chartCount, r.measure.energy.E * rSize,
                        r.base.energy.E * rSize, r.measure.areaRatioStdDev, r.base.areaRatioStdDev, r.measure.flips,
                        r.measure.overlaps);
        std::printf("images: %zu; time: refine %.2fs, write %.2fs\n", res.images.size(), res.seconds, writeSeconds);
    }
    return cli::kOk;
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Settings>("texture-refine", argc, argv, parseArgs, run); }
