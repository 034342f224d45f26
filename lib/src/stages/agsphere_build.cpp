// The agsphere-build stage (agsphere_build.h): load, M-AGSphere levels, write, report.
#include "lodbake/stages/agsphere_build.h"

#include "lodbake/core/parallel.h"
#include "stages/multires_stage.h"

namespace lodbake {
namespace {

nlohmann::json vec(Vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json makeReport(const AgsphereBuildSettings& s, const Asset& asset, const AgsphereResult& r,
                          double loadSeconds, double writeSeconds) {
    const AgsphereOptions& o = s.agsphere;
    const TriMesh& m = asset.mesh;
    nlohmann::json depths = nlohmann::json::array();
    for (const AgsphereDepthStats& d : r.depths)
        depths.push_back({{"depth", d.depth},
                          {"cells", d.cells},
                          {"regions", d.regions},
                          {"estimatedTriangles", d.estimatedTriangles},
                          {"maxThreshold", d.maxThreshold}});
    nlohmann::json levels = nlohmann::json::array();
    for (size_t k = 0; k < r.multires.levels.size(); ++k) {
        const Level& L = r.multires.levels[k];
        const AgsphereLevelStats& st = r.levelStats[k];
        nlohmann::json level = levelJson(m, L, k + 1, r.diagonal);
        nlohmann::json& target = level["target"];
        if (L.targetRatio > 0) target["ratio"] = L.targetRatio;
        target["triangles"] = L.targetTriangles;
        level.update({{"estimatedTriangles", st.estimatedTriangles},
                      {"regions", L.regionCount},
                      {"cellsPerDepth", st.cellsPerDepth},
                      {"cells",
                       {{"orthogonal", st.orthogonalCells},
                        {"reference", st.referenceCells},
                        {"coarsest", st.coarsestCells},
                        {"other", st.otherCells}}},
                      {"retriangulatedRegions", st.retriangulatedRegions},
                      {"keptRegions", st.keptRegions},
                      {"outlineFaces", st.outlineFaces},
                      {"runs", st.runs},
                      {"simplifiedRuns", st.simplifiedRuns},
                      {"restoredRuns", st.restoredRuns},
                      {"stopReason", st.stopReason}});
        levels.push_back(level);
    }
    nlohmann::json views = nlohmann::json::array(), lights = nlohmann::json::array();
    for (Vec3 v : o.views) views.push_back(vec(v));
    for (Vec3 v : o.lights) lights.push_back(vec(v));
    nlohmann::json rep;
    rep["tool"] = "agsphere-build";
    rep["input"] = inputJson(s.common, asset, r.diagonal);
    rep["output"] = s.common.output;
    rep["sphere"] = {{"maxDepth", o.maxDepth},
                     {"boundaryTolerance", o.boundaryTolerance},
                     {"silhouetteBandDeg", o.silhouetteBandDeg},
                     {"depths", depths}};
    rep["views"] = views;
    rep["outline"] = {{"keep", o.keepOutline && !(o.views.empty() && o.lights.empty())},
                      {"viewDistance", o.viewDistance},
                      {"rings", o.outlineRings},
                      {"contourEdges", r.contourEdges},
                      {"outlineEdges", r.outlineEdges},
                      {"faces", r.outlineFaces}};
    rep["lights"] = lights;
    rep["levels"] = levels;
    rep["warnings"] = asset.warnings;
    rep["time"] = {{"load", loadSeconds},
                   {"cells", r.secondsCells},
                   {"depths", r.secondsDepths},
                   {"select", r.secondsSelect},
                   {"levels", r.secondsLevels},
                   {"write", writeSeconds}};
    return rep;
}

std::string statistics(const Asset& asset, const nlohmann::json& rep) {
    std::string out = inputStatistics(asset);
    for (const auto& d : rep["sphere"]["depths"])
        appendf(out, "sphere depth %d: %d cells, %d regions, ~%d triangles\n", d["depth"].get<int>(),
                d["cells"].get<int>(), d["regions"].get<int>(), d["estimatedTriangles"].get<int>());
    for (const auto& L : rep["levels"])
        appendf(out, "level %d: %d triangles, %d regions, max deviation %.4g (%.3g%% of diagonal), %s\n",
                L["level"].get<int>(), L["triangles"].get<int>(), L["regions"].get<int>(),
                L["maxDeviation"].get<double>(), 100 * L["maxDeviationRelative"].get<double>(),
                L["stopReason"].get<std::string>().c_str());
    return out;
}

}  // namespace

StageResult runAgsphereBuild(const AgsphereBuildSettings& s) {
    double loadSeconds = 0;
    Asset asset = loadMeshInput(s.common, loadSeconds, "the scene has no triangles");

    AgsphereOptions opt = s.agsphere;
    opt.threads = resolveThreads(s.common.threads);
    opt.progress = s.common.progress;
    AgsphereResult result = buildAgsphere(asset.mesh, opt);
    double writeSeconds = writeStageOutput(s.common, asset, &result.multires, "agsphere-build");

    StageResult out;
    out.report = makeReport(s, asset, result, loadSeconds, writeSeconds);
    if (!s.common.report.empty()) writeReport(s.common.report, out.report);
    if (s.common.verbose) out.statistics = statistics(asset, out.report);
    return out;
}

}  // namespace lodbake
