// The simplify stage (simplify.h): load, simplify(), write the levels, report.
#include "lodbake/stages/simplify.h"

#include <cstdio>

#include "lodbake/core/parallel.h"
#include "lodbake/core/timing.h"
#include "stages/multires_stage.h"

namespace lodbake {
namespace {

// A level the gross-error bound stopped before its target keeps the triangles it had: how many,
// against what it was asked.
std::string grossStopWarning(const Level& L, size_t k, size_t inputTriangles) {
    std::string asked = std::to_string(L.targetTriangles) + " triangles";
    if (L.targetRatio > 0) {
        char ratio[32];
        std::snprintf(ratio, sizeof ratio, "ratio %g = ", L.targetRatio);
        asked = ratio + asked;
    }
    char kept[32];
    std::snprintf(kept, sizeof kept, "%.3g", inputTriangles ? double(L.triangles.size()) / double(inputTriangles) : 0.0);
    return "level " + std::to_string(k + 1) + " did not reach its target (" + asked + "): it keeps " +
           std::to_string(L.triangles.size()) + " triangles (ratio " + kept + "); " + L.stopReason;
}

// A level that could not get coarser than the previous one repeats it (its stop reason says
// why), and a level the gross-error bound stopped keeps more triangles than asked: said in the
// report and on the warning callback (pack's report says a repeat again).
std::vector<std::string> levelWarnings(const Asset& asset, const SimplifyResult& r) {
    std::vector<std::string> out;
    for (size_t k = 0; k < r.multires.levels.size(); ++k) {
        const Level& L = r.multires.levels[k];
        const size_t previous = k > 0 ? r.multires.levels[k - 1].triangles.size() : asset.mesh.triangleCount();
        if (L.grossErrorBound > 0)
            out.push_back(grossStopWarning(L, k, asset.mesh.triangleCount()));
        else if (!L.triangles.empty() && L.triangles.size() >= previous)
            out.push_back("level " + std::to_string(k + 1) + " is no coarser than " +
                          (k > 0 ? "level " + std::to_string(k) : std::string("the original")) + " (" +
                          std::to_string(L.triangles.size()) + " triangles, target " + std::to_string(L.targetTriangles) +
                          "): " + L.stopReason);
    }
    return out;
}

nlohmann::json makeReport(const SimplifySettings& s, const Asset& asset, const SimplifyResult& r, size_t poses,
                          const std::vector<std::string>& warnings, double loadSeconds, double simplifySeconds,
                          double writeSeconds) {
    nlohmann::json levels = nlohmann::json::array();
    for (size_t k = 0; k < r.multires.levels.size(); ++k) {
        const Level& L = r.multires.levels[k];
        nlohmann::json level = levelJson(asset.mesh, L, k + 1, r.diagonal);
        nlohmann::json& target = level["target"];
        if (L.targetRatio > 0) target["ratio"] = L.targetRatio;
        if (L.targetError > 0) target["maxError"] = L.targetError / (r.diagonal > 0 ? r.diagonal : 1);
        target["triangles"] = L.targetTriangles;
        level["baseRegions"] = L.regionCount;
        level["collapses"] = L.collapseCount;
        level["stopReason"] = L.stopReason;
        if (L.grossErrorBound > 0) {
            const double scale = r.diagonal > 0 ? r.diagonal : 1;
            level["grossError"] = {{"bound", L.grossErrorBound / scale}, {"refusedDeviation", L.grossErrorRefused / scale}};
        }
        levels.push_back(level);
    }
    nlohmann::json rep;
    rep["tool"] = "simplify";
    rep["input"] = inputJson(s.common, asset, r.diagonal);
    rep["output"] = s.common.output;
    rep["levels"] = levels;
    if (!s.levelsChosen.empty()) rep["levelsChosen"] = s.levelsChosen;
    rep["posedSamples"] = poses;
    rep["warnings"] = warnings;
    rep["time"] = {{"load", loadSeconds}, {"simplify", simplifySeconds}, {"write", writeSeconds}};
    return rep;
}

std::string statistics(const Asset& asset, const nlohmann::json& rep) {
    std::string out = inputStatistics(asset);
    for (const auto& L : rep["levels"])
        appendf(out, "level %d: %d triangles, max deviation %.4g (%.3g%% of diagonal), %d base regions, %s\n",
                L["level"].get<int>(), L["triangles"].get<int>(), L["maxDeviation"].get<double>(),
                100 * L["maxDeviationRelative"].get<double>(), L["baseRegions"].get<int>(),
                L["stopReason"].get<std::string>().c_str());
    return out;
}

}  // namespace

StageResult runSimplify(const SimplifySettings& s) {
    double loadSeconds = 0;
    Asset asset = loadMeshInput(s.common, loadSeconds, "the scene has no triangles to simplify");

    SimplifyOptions opt = s.simplify;
    opt.threads = resolveThreads(s.common.threads);
    opt.progress = s.common.progress;
    Clock::time_point t1 = Clock::now();
    const std::vector<PoseSample> poses = samplePoses(asset.rig, s.poses);
    opt.posed = poseWedges(asset.rig, asset.morph, asset.mesh, poses);
    SimplifyResult result = simplify(asset.mesh, opt);
    double simplifySeconds = secondsSince(t1);
    double writeSeconds = writeStageOutput(s.common, asset, &result.multires, "simplify");

    StageResult out;
    std::vector<std::string> warnings = asset.warnings;  // the loader's, already passed to s.common.warning
    for (const std::string& w : levelWarnings(asset, result)) {
        if (s.common.warning) s.common.warning(w);
        warnings.push_back(w);
    }
    out.report = makeReport(s, asset, result, opt.posed.positions.size(), warnings, loadSeconds, simplifySeconds, writeSeconds);
    if (!s.common.report.empty()) writeReport(s.common.report, out.report);
    if (s.common.verbose) out.statistics = statistics(asset, out.report);
    return out;
}

}  // namespace lodbake
