// The texture-refine stage (texture_refine.h): load, the texture hierarchy, write, report.
#include "lodbake/stages/texture_refine.h"

#include "lodbake/core/errors.h"
#include "lodbake/core/timing.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/texture/codec.h"

namespace lodbake {
namespace {

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

// Why a rank carries no measure (RankResult::measured).
constexpr const char* kUnmeasured =
    "not measured: the input is over the triangle budget (--max-refine-triangles), so no rank is compared with T0";

// Resolution modifier r of a `side` x `side` texture: E is quoted per 512^2 texels.
double resolutionModifier(int side) { return (512.0 * 512.0) / (double(side) * side); }

nlohmann::json makeReport(const TextureRefineSettings& s, const Asset& asset, const Multires& multires,
                          const RefineResult& res, double loadSeconds, double writeSeconds) {
    const RefineOptions& o = s.refine;
    size_t flips = 0, overlaps = 0;
    for (const RankResult& r : res.ranks) {
        flips += r.measure.flips;
        overlaps += r.measure.overlaps;
    }
    nlohmann::json ranks = nlohmann::json::array(), textures = nlohmann::json::array();
    const double rSize = resolutionModifier(o.param.textureSize);
    for (const RankResult& r : res.ranks) {
        nlohmann::json j = {{"rank", r.rank},
                            {"validLevels", {r.firstLevel, r.lastLevel}},
                            {"regions", r.regions},
                            {"charts", r.layout.chartCount},
                            {"levelIslands", r.layout.islands.size()},
                            {"resolution", o.param.textureSize},
                            {"measured", r.measured}};
        if (r.measured) {
            j["refined"] = measureJson(r.measure, rSize);
            j["T0"] = measureJson(r.base, rSize);
            j["lowerE"] = r.measure.energy.E < r.base.energy.E;
            j["lowerAreaRatioStdDev"] = r.measure.areaRatioStdDev < r.base.areaRatioStdDev;
        } else {
            j["why"] = kUnmeasured;
        }
        if (r.rank > 0) {
            j["parameterize"] = {{"flips", r.chartFlips}, {"overlaps", r.chartOverlaps}, {"levelFlipsInSolve", r.levelFlipsInSolve},
                                 {"methods", r.methods}, {"resplits", r.resplits}, {"unsplitCharts", r.unsplit},
                                 {"seconds", r.parameterizeSeconds}};
            j["comparison"] = "T0 measured over the same levels at the same texel count (" + std::to_string(o.param.textureSize) +
                              "^2 texels each)";
        }
        ranks.push_back(j);
    }
    for (const RefinedImage& img : res.images) {
        const RankResult& r = res.ranks[img.rank];
        nlohmann::json t = {{"rank", img.rank},
                            {"validLevels", {r.firstLevel, r.lastLevel}},
                            {"resolution", img.size},
                            {"charts", r.layout.chartCount},
                            {"measured", r.measured},
                            {"coveredTexels", img.coveredTexels},
                            {"bytes", img.image.encoded.size()},
                            {"bakeSeconds", img.seconds}};
        if (r.measured) {
            const nlohmann::json e = energyJson(r.measure.energy, resolutionModifier(img.size));
            t["E"] = e["E"];
            t["E_pixel"] = e["E_pixel"];
            t["E_poly"] = e["E_poly"];
            t["areaRatioStdDev"] = r.measure.areaRatioStdDev;
        }
        textures.push_back(std::move(t));
    }

    nlohmann::json rep;
    rep["tool"] = "texture-refine";
    rep["input"] = {{"path", s.common.input}, {"triangles", asset.mesh.triangleCount()}, {"levels", multires.levels.size()},
                    {"charts", multires.charts.chartCount}};
    rep["output"] = s.common.output;
    rep["options"] = {{"size", o.param.textureSize}, {"sizes", o.sizes}, {"imagesBaked", o.bakeImages}, {"ranks", o.ranks},
                      {"minRefinedSize", o.minRefinedSize}, {"keepLevelTrianglesWhole", o.keepLevelTrianglesWhole},
                      {"minStdDev", o.minAreaRatioStdDev}, {"maxExtraCuts", o.maxExtraCutFraction},
                      {"split", o.splitPerChart}, {"maxTriangles", o.maxTriangles}, {"alpha", o.param.solve.energy.alpha}, {"beta", o.param.solve.energy.beta}, {"iterations", o.param.solve.maxIterations}};
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
    return rep;
}

std::string statistics(const TextureRefineSettings& s, const RefineResult& res, double writeSeconds) {
    std::string out;
    const double rSize = resolutionModifier(s.refine.param.textureSize);
    for (const RankResult& r : res.ranks) {
        if (!r.measured) {
            appendf(out, "rank %u: levels %u..%u, %u charts, %s\n", r.rank, r.firstLevel, r.lastLevel, r.layout.chartCount, kUnmeasured);
            continue;
        }
        appendf(out, "rank %u: levels %u..%u, %u charts, E %.6g (T0 %.6g), area-ratio std-dev %.4f (T0 %.4f), flips %zu, overlaps %zu\n",
                r.rank, r.firstLevel, r.lastLevel, r.layout.chartCount, r.measure.energy.E * rSize,
                r.base.energy.E * rSize, r.measure.areaRatioStdDev, r.base.areaRatioStdDev, r.measure.flips,
                r.measure.overlaps);
    }
    appendf(out, "images: %zu; time: refine %.2fs, write %.2fs\n", res.images.size(), res.seconds, writeSeconds);
    return out;
}

}  // namespace

StageResult runTextureRefine(const TextureRefineSettings& s) {
    std::optional<Multires> multires;
    double loadSeconds = 0;
    // Without bakes this stage reads no pixels: a header check names an unreadable image, and the
    // stage that reads the pixels (pack) decodes them.
    void (*headerOnly)(Asset&, ImageCheck) = [](Asset& a, ImageCheck) { checkImages(a, ImageCheck::Header); };
    Asset asset = loadStageInput(s.common, loadSeconds, &multires, s.refine.bakeImages ? &checkImages : headerOnly);
    if (!multires) throw Impossible(s.common.input + ": no LODBAKE_multires extension; run simplify and parameterize first");
    if (multires->charts.empty()) throw Impossible(s.common.input + ": no chart layout; run parameterize first");

    RefineOptions opt = s.refine;
    opt.param.threads = s.common.threads;
    opt.progress = s.common.progress;
    RefineResult res = refineTextures(asset, *multires, opt);
    for (const std::string& w : res.warnings) {  // printed now (stderr) and kept for the report
        if (s.common.warning) s.common.warning(w);
        asset.warnings.push_back(w);
    }

    applyTextureHierarchy(asset, *multires, res);
    double writeSeconds = writeStageOutput(s.common, asset, &*multires, "texture-refine");

    StageResult out;
    out.report = makeReport(s, asset, *multires, res, loadSeconds, writeSeconds);
    if (!s.common.report.empty()) writeReport(s.common.report, out.report);
    if (s.common.verbose) out.statistics = statistics(s, res, writeSeconds);
    return out;
}

}  // namespace lodbake
