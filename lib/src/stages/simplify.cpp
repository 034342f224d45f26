#include "lodbake/stages/simplify.h"

#include "lodbake/core/errors.h"
#include "lodbake/core/parallel.h"
#include "lodbake/core/timing.h"
#include "lodbake/gltf/gltf.h"

namespace lodbake {
namespace {

nlohmann::json makeReport(const SimplifySettings& s, const Asset& asset, const SimplifyResult& r, double loadSeconds,
                          double simplifySeconds, double writeSeconds) {
    nlohmann::json levels = nlohmann::json::array();
    const TriMesh& m = asset.mesh;
    for (size_t k = 0; k < r.multires.levels.size(); ++k) {
        const Level& L = r.multires.levels[k];
        std::vector<uint8_t> seen(m.vertexCount(), 0);
        size_t usedVertices = 0;
        for (const Tri& t : L.triangles)
            for (uint32_t v : t)
                if (v < seen.size() && !seen[v]) {
                    seen[v] = 1;
                    ++usedVertices;
                }
        nlohmann::json target;
        if (L.targetRatio > 0) target["ratio"] = L.targetRatio;
        if (L.targetError > 0) target["maxError"] = L.targetError / (r.diagonal > 0 ? r.diagonal : 1);
        target["triangles"] = L.targetTriangles;
        levels.push_back({{"level", k + 1},
                          {"target", target},
                          {"triangles", L.triangles.size()},
                          {"vertices", usedVertices},
                          {"ratio", m.triangleCount() ? double(L.triangles.size()) / m.triangleCount() : 0.0},
                          {"maxDeviation", L.maxDeviation},
                          {"meanDeviation", L.meanDeviation},
                          {"maxDeviationRelative", r.diagonal > 0 ? L.maxDeviation / r.diagonal : 0.0},
                          {"meanDeviationRelative", r.diagonal > 0 ? L.meanDeviation / r.diagonal : 0.0},
                          {"baseRegions", L.regionCount},
                          {"pairs", L.pairs.size()},
                          {"collapses", L.collapseCount},
                          {"stopReason", L.stopReason},
                          {"seconds", L.seconds}});
    }
    nlohmann::json rep;
    rep["tool"] = "simplify";
    rep["input"] = {{"path", s.common.input},
                    {"triangles", m.triangleCount()},
                    {"vertices", m.vertexCount()},
                    {"wedges", m.wedges.size()},
                    {"materials", asset.materials.size()},
                    {"primitives", asset.stats.primitives},
                    {"diagonal", r.diagonal}};
    rep["output"] = s.common.output;
    rep["levels"] = levels;
    rep["warnings"] = asset.warnings;
    rep["time"] = {{"load", loadSeconds}, {"simplify", simplifySeconds}, {"write", writeSeconds}};
    return rep;
}

std::string statistics(const Asset& asset, const nlohmann::json& rep) {
    std::string out;
    appendf(out, "input: %zu triangles, %zu vertices\n", asset.mesh.triangleCount(), asset.mesh.vertexCount());
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
    Asset asset = loadStageInput(s.common, loadSeconds);
    if (asset.mesh.triangleCount() == 0) throw Impossible(s.common.input + ": the scene has no triangles to simplify");

    SimplifyOptions opt = s.simplify;
    opt.threads = resolveThreads(s.common.threads);
    opt.progress = s.common.progress;
    Clock::time_point t1 = Clock::now();
    SimplifyResult result = simplify(asset.mesh, opt);
    double simplifySeconds = secondsSince(t1);

    Clock::time_point t2 = Clock::now();
    WriteOptions wopt;
    wopt.generator = "lodbake simplify 0.1.0";
    writeGltf(s.common.output, asset, &result.multires, wopt);
    double writeSeconds = secondsSince(t2);

    StageResult out;
    out.report = makeReport(s, asset, result, loadSeconds, simplifySeconds, writeSeconds);
    if (!s.common.report.empty()) writeReport(s.common.report, out.report);
    if (s.common.verbose) out.statistics = statistics(asset, out.report);
    return out;
}

}  // namespace lodbake
