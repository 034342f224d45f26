// simplify: any glTF in, multiresolution glTF out (half-edge collapse with region hierarchy).
#include <chrono>
#include <cstdio>
#include <iostream>
#include <vector>

#include "common/cli.h"
#include "lodbake/core/errors.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/simplify/simplify.h"

using namespace lodbake;

namespace {

struct Settings {
    cli::CommonSettings common;
    std::vector<double> ratios;
    std::vector<double> triangles;
    std::vector<double> maxErrors;
    double maxRegionConeDeg = SimplifyOptions{}.maxRegionConeDeg;
    double pruneStuckSize = SimplifyOptions{}.pruneStuckSize;
};

Settings parseArgs(int argc, char** argv, bool& proceed) {
    Settings s;
    cli::ArgParser p("simplify", "-i INPUT -o OUTPUT (--ratio R,... | --triangles N,... | --max-error E,...) [options]");
    p.addCommon(s.common);
    p.option("--ratio", "R,...", "levels as fractions of the input triangle count, e.g. 0.5,0.1,0.02",
             [&](const std::string& v) { s.ratios = cli::parseDoubleList("--ratio", v); });
    p.option("--triangles", "N,...", "levels as absolute triangle counts",
             [&](const std::string& v) { s.triangles = cli::parseDoubleList("--triangles", v); });
    p.option("--max-error", "E,...", "levels by maximum vertex deviation relative to the bounding-box diagonal",
             [&](const std::string& v) { s.maxErrors = cli::parseDoubleList("--max-error", v); });
    p.option("--max-region-cone", "DEG",
             "largest normal spread of a region (half-angle of the equivalent cap, degrees; default " +
                 std::to_string(int(s.maxRegionConeDeg)) + ", 180 = off): regions become texture charts",
             [&](const std::string& v) {
                 s.maxRegionConeDeg = cli::parseDouble("--max-region-cone", v);
                 if (!(s.maxRegionConeDeg > 0 && s.maxRegionConeDeg <= 180))
                     throw UsageError("--max-region-cone must be in (0, 180]");
             });
    p.option("--max-part-removal", "F",
             "when a triangle target cannot be reached otherwise (parts stuck on non-manifold edges or pinch "
             "vertices), remove whole parts up to this half-diagonal, as a fraction of the model's diagonal, "
             "smallest first (default 0.2, 0 = never)",
             [&](const std::string& v) {
                 s.pruneStuckSize = cli::parseDouble("--max-part-removal", v);
                 if (!(s.pruneStuckSize >= 0 && s.pruneStuckSize <= 1))
                     throw UsageError("--max-part-removal must be in [0, 1]");
             });
    proceed = p.parse(argc, argv);
    return s;
}

std::vector<LevelTarget> validate(const Settings& s) {
    cli::checkPaths(s.common);
    std::vector<LevelTarget> targets;
    for (double r : s.ratios) {
        if (!(r > 0 && r <= 1)) throw UsageError("--ratio values must be in (0, 1]");
        targets.push_back({r, 0, 0});
    }
    for (double t : s.triangles) {
        if (!(t >= 1) || t != static_cast<double>(static_cast<uint64_t>(t)))
            throw UsageError("--triangles values must be positive integers");
        targets.push_back({0, static_cast<uint64_t>(t), 0});
    }
    for (double e : s.maxErrors) {
        if (!(e > 0)) throw UsageError("--max-error values must be > 0");
        targets.push_back({0, 0, e});
    }
    if (targets.empty()) throw UsageError("give at least one level: --ratio, --triangles or --max-error");
    return targets;
}

nlohmann::json makeReport(const Settings& s, const Asset& asset, const SimplifyResult& r, double loadSeconds,
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

int run(const Settings& s) {
    std::vector<LevelTarget> targets = validate(s);
    double loadSeconds = 0;
    Asset asset = cli::loadInput("simplify", s.common, loadSeconds);
    if (asset.mesh.triangleCount() == 0) throw Impossible(s.common.input + ": the scene has no triangles to simplify");

    SimplifyOptions opt;
    opt.levels = targets;
    opt.maxRegionConeDeg = s.maxRegionConeDeg;
    opt.pruneStuckSize = s.pruneStuckSize;
    opt.threads = cli::resolveThreads(s.common.threads);
    cli::Progress progress("simplify", cli::progressEnabled(s.common));
    opt.progress = [&progress](double f) { return progress(f); };
    auto t1 = std::chrono::steady_clock::now();
    SimplifyResult result = simplify(asset.mesh, opt);
    double simplifySeconds = cli::secondsSince(t1);
    progress.done();

    auto t2 = std::chrono::steady_clock::now();
    WriteOptions wopt;
    wopt.generator = "lodbake simplify 0.1.0";
    writeGltf(s.common.output, asset, &result.multires, wopt);
    double writeSeconds = cli::secondsSince(t2);

    nlohmann::json rep = makeReport(s, asset, result, loadSeconds, simplifySeconds, writeSeconds);
    if (!s.common.report.empty()) cli::writeReport(s.common.report, rep);
    if (s.common.verbose) {
        std::printf("input: %zu triangles, %zu vertices\n", asset.mesh.triangleCount(), asset.mesh.vertexCount());
        for (const auto& L : rep["levels"])
            std::printf("level %d: %d triangles, max deviation %.4g (%.3g%% of diagonal), %d base regions, %s\n",
                        L["level"].get<int>(), L["triangles"].get<int>(), L["maxDeviation"].get<double>(),
                        100 * L["maxDeviationRelative"].get<double>(), L["baseRegions"].get<int>(),
                        L["stopReason"].get<std::string>().c_str());
    }
    return cli::kOk;
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Settings>("simplify", argc, argv, parseArgs, run); }
