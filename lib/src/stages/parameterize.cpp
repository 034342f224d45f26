// The parameterize stage (parameterize.h): load, parameterize(), write, report.
#include "lodbake/stages/parameterize.h"

#include "lodbake/atlas/atlas_apply.h"
#include "lodbake/bake/bake.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/timing.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/texture/codec.h"

namespace lodbake {
namespace {

nlohmann::json energyJson(const ChartEnergy& e) {
    return {{"E", e.E}, {"E_pixel", e.pixel}, {"E_poly", e.poly}, {"E_l", e.edge}, {"E_s", e.area}};
}

// The level triangles that fell back to their own UV island, as the baker takes them.
std::vector<BakeIsland> bakeIslands(const TriMesh& mesh, const std::vector<LevelIsland>& levelIslands) {
    std::vector<BakeIsland> islands;
    for (const LevelIsland& li : levelIslands) {
        BakeIsland b;
        for (size_t k = 0; k < 3; ++k) b.position[k] = mesh.positions[li.vertices[k]];
        b.uv = li.uv;
        b.faces = li.faces;
        islands.push_back(std::move(b));
    }
    return islands;
}

// Injectivity of every level with its final UVs (level 0 = the original triangles in the atlas), on
// `threads` threads.
std::vector<UVInjectivity> checkLevels(const TriMesh& mesh, const Multires& multires, const ParameterizeResult& param,
                                       int threads) {
    std::vector<UVInjectivity> checks;
    std::vector<std::array<Vec2, 3>> atlas0;
    for (size_t f = 0; f < mesh.triangleCount(); ++f) {
        const Tri& v = mesh.triangles[f];
        if (v[0] != v[1] && v[1] != v[2] && v[0] != v[2]) atlas0.push_back(param.cornerUV[f]);
    }
    checks.push_back(checkUVInjectivity(std::move(atlas0), 1e-7, threads));
    for (const Level& L : multires.levels) checks.push_back(checkLevelUVs(mesh, L.triangles, L.cornerWedges, 1e-7, threads));
    return checks;
}

// A warning of this run: printed now (stderr, TOOL warning:) and kept for the report.
void warn(const StageCommon& common, Asset& asset, const std::string& w) {
    if (common.warning) common.warning(w);
    asset.warnings.push_back(w);
}

struct Timings {
    double load = 0, bake = 0, checks = 0;
};

nlohmann::json makeReport(const ParameterizeSettings& s, const Asset& asset, const Multires& multires,
                          const ParameterizeResult& param, const BakeResult& baked, const AtlasApplyStats& applied,
                          const std::vector<UVInjectivity>& levelChecks, const TextureDeviation& deviation,
                          size_t levelFlips, size_t levelOverlaps, const Timings& time) {
    const ParameterizeOptions& o = s.parameterize;
    nlohmann::json charts = nlohmann::json::array();
    for (size_t c = 0; c < param.chartReports.size(); ++c) {
        const ChartReport& r = param.chartReports[c];
        charts.push_back({{"chart", c},
                          {"faces", r.faces},
                          {"vertices", r.vertices},
                          {"pairs", r.pairs},
                          {"method", r.method},
                          {"start", r.start},
                          {"iterations", r.iterations},
                          {"initial", energyJson(r.initial)},
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
                    {"levels", multires.levels.size()}};
    rep["output"] = s.common.output;
    rep["options"] = {{"size", o.textureSize}, {"alpha", o.solve.energy.alpha}, {"beta", o.solve.energy.beta}, {"maxCharts", o.charts.maxCharts},
                      {"iterations", o.solve.maxIterations}};
    rep["charts"] = charts;
    nlohmann::json levels = nlohmann::json::array();
    for (size_t k = 0; k < levelChecks.size(); ++k)
        levels.push_back({{"level", k}, {"triangles", levelChecks[k].triangles}, {"flips", levelChecks[k].flips},
                          {"overlaps", levelChecks[k].overlaps},
                          {"islandTriangles", k == 0 ? size_t(0) : param.levels[k - 1].islands},
                          {"projectedCorners", k == 0 ? size_t(0) : param.levels[k - 1].projectedCorners}});
    rep["levels"] = levels;
    rep["textureDeviation"] = {{"level", multires.levels.size()},
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
                    {"initial", energyJson(param.initialTotal)},
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
                    {"atlasSize", param.atlasSize},
                    {"texelsPerUnit", param.texelsPerUnit},
                    {"atlasFill", param.atlasFill},
                    {"newWedges", applied.newWedges},
                    {"projectedCorners", applied.projectedCorners},
                    {"islands", param.islands.size()},
                    {"floatRepairs", param.floatRepairs},
                    {"carvedFaces", param.carvedFaces},
                    {"failedCharts", param.failedCharts},
                    {"crossingIslandsSkipped", param.crossingIslandsSkipped},
                    {"islandTriangles", applied.islandTriangles},
                    {"islandTexels", baked.islandTexels},
                    {"coveredTexels", baked.coveredTexels},
                    {"texturedLookups", baked.texturedLookups},
                    {"imageBaked", s.bakeImage}};
    rep["warnings"] = asset.warnings;
    rep["time"] = {{"load", time.load}, {"parameterize", param.seconds}, {"bake", time.bake}, {"checks", time.checks}};
    return rep;
}

std::string statistics(const Multires& multires, const ParameterizeResult& param, const AtlasApplyStats& applied,
                       const std::vector<UVInjectivity>& levelChecks, const TextureDeviation& deviation,
                       double bakeSeconds) {
    std::string out;
    appendf(out, "charts: %u (from %u base regions, %u split), flips %zu, overlaps %zu\n", param.charts.chartCount,
            param.charts.baseRegions, param.charts.splitRegions, param.flips, param.overlaps);
    appendf(out, "E: start %.6g -> final %.6g (E_pixel %.6g, E_poly %.6g)\n", param.initialTotal.E, param.finalTotal.E,
            param.finalTotal.pixel, param.finalTotal.poly);
    appendf(out, "stretch L2 %.4f, Linf %.4f, area-ratio std-dev %.4f, atlas fill %.1f%%\n", param.stretchL2,
            param.stretchLinf, param.areaRatioStdDev, 100 * param.atlasFill);
    for (size_t k = 0; k < levelChecks.size(); ++k)
        appendf(out, "level %zu: %zu triangles, %zu flipped, %zu overlapping in UV\n", k, levelChecks[k].triangles,
                levelChecks[k].flips, levelChecks[k].overlaps);
    appendf(out, "texture deviation of level %zu: mean %.3g, max %.3g (x bbox diagonal)\n", multires.levels.size(),
            deviation.meanRelative, deviation.maxRelative);
    appendf(out, "projected level corners: %zu; level-triangle islands: %zu (%zu level triangles)\n",
            applied.projectedCorners, param.islands.size(), applied.islandTriangles);
    appendf(out, "time: parameterize %.2fs, bake %.2fs\n", param.seconds, bakeSeconds);
    return out;
}

}  // namespace

StageResult runParameterize(const ParameterizeSettings& s) {
    Timings time;
    std::optional<Multires> multires;
    Asset asset = loadStageInput(s.common, time.load, &multires, checkImages);
    if (!multires) throw Impossible(s.common.input + ": no LODBAKE_multires extension; run simplify first");

    ParameterizeOptions opt = s.parameterize;
    opt.threads = s.common.threads;
    opt.progress = s.common.progress;
    ParameterizeResult param = parameterize(asset.mesh, *multires, opt);
    for (const std::string& w : param.warnings) warn(s.common, asset, w);

    Clock::time_point t1 = Clock::now();
    BakeResult baked;
    if (s.bakeImage) {
        BakeOptions bo;
        bo.size = opt.textureSize;
        bo.threads = s.common.threads;
        baked = bakeBaseColor(asset, param.cornerUV, bo, bakeIslands(asset.mesh, param.islands));
    }
    time.bake = secondsSince(t1);

    AtlasApplyStats applied = applyAtlas(asset, *multires, param, baked.image);
    std::vector<UVInjectivity> levelChecks = checkLevels(asset.mesh, *multires, param, s.common.threads);

    // Texture deviation of the coarsest level (what beta < 1 is meant to lower).
    Clock::time_point t3 = Clock::now();
    TextureDeviation deviation;
    TextureDeviationOptions dopt;
    dopt.islands = &param.islands;
    dopt.threads = s.common.threads;
    if (!multires->levels.empty()) deviation = textureDeviation(asset.mesh, multires->levels.back(), multires->charts, dopt);
    time.checks = secondsSince(t3);
    size_t levelFlips = 0, levelOverlaps = 0;
    for (const UVInjectivity& c : levelChecks) {
        levelFlips += c.flips;
        levelOverlaps += c.overlaps;
    }

    // What the fallbacks could not remove is still a usable chain (a folded triangle shows a
    // smeared texel or two): it is written, and the report and a warning say where.
    if (levelFlips > 0 || levelOverlaps > 0) {
        std::string per;
        for (size_t k = 0; k < levelChecks.size(); ++k)
            if (levelChecks[k].flips || levelChecks[k].overlaps)
                per += (per.empty() ? "" : ", ") + std::to_string(k) + ": " + std::to_string(levelChecks[k].flips) + "/" +
                       std::to_string(levelChecks[k].overlaps);
        warn(s.common, asset, "the levels keep " + std::to_string(levelFlips) + " flipped and " +
                                  std::to_string(levelOverlaps) + " overlapping UV triangles (level: flipped/overlapping " +
                                  per + ")");
    }

    StageResult out;
    out.report = makeReport(s, asset, *multires, param, baked, applied, levelChecks, deviation, levelFlips,
                            levelOverlaps, time);
    if (!s.common.report.empty()) writeReport(s.common.report, out.report);
    double writeSeconds = writeStageOutput(s.common, asset, &*multires, "parameterize");
    if (s.common.verbose) {
        appendf(out.statistics, "write: %.2fs\n", writeSeconds);
        out.statistics += statistics(*multires, param, applied, levelChecks, deviation, time.bake);
    }
    return out;
}

}  // namespace lodbake
