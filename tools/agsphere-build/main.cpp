// agsphere-build: any glTF in, multiresolution glTF out (M-AGSphere, thesis 2.4), with
// view- and light-silhouette-preserving levels. Same output format as `simplify`.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <set>

#include "common/cli.h"
#include "lodbake/agsphere/agsphere.h"
#include "lodbake/core/errors.h"
#include "lodbake/gltf/gltf.h"

using namespace lodbake;

namespace {

struct Settings {
    cli::CommonSettings common;
    std::vector<double> ratios;
    std::vector<double> triangles;
    std::vector<Vec3> views, lights;
    int maxDepth = AgsphereOptions{}.maxDepth;
    double boundaryTolerance = AgsphereOptions{}.boundaryTolerance;
    double silhouetteBand = AgsphereOptions{}.silhouetteBandDeg;
    bool keepOutline = AgsphereOptions{}.keepOutline;
    double viewDistance = AgsphereOptions{}.viewDistance;
    int outlineRings = AgsphereOptions{}.outlineRings;
};

Vec3 direction(const std::string& flag, const std::string& v) {
    std::vector<double> d = cli::parseVec3(flag, v);
    Vec3 r{d[0], d[1], d[2]};
    if (!(length(r) > 0)) throw UsageError(flag + " needs a non-zero direction");
    return r;
}

Settings parseArgs(int argc, char** argv, bool& proceed) {
    Settings s;
    cli::ArgParser p("agsphere-build",
                     "-i INPUT -o OUTPUT (--ratio R,... | --triangles N,...) [--view X,Y,Z]... [--light X,Y,Z]... [options]");
    p.addCommon(s.common);
    p.option("--ratio", "R,...", "levels as fractions of the input triangle count, e.g. 0.5,0.1,0.02",
             [&](const std::string& v) { s.ratios = cli::parseDoubleList("--ratio", v); });
    p.option("--triangles", "N,...", "levels as absolute triangle counts",
             [&](const std::string& v) { s.triangles = cli::parseDoubleList("--triangles", v); });
    p.option("--view", "X,Y,Z",
             "a view direction (from the object towards the camera; repeatable): the faces on the outline seen "
             "from it are kept unchanged; silhouette cells two sphere depths finer than the reference cell, the "
             "others one",
             [&](const std::string& v) { s.views.push_back(direction("--view", v)); });
    p.option("--light", "X,Y,Z",
             "a light direction (from the object towards the light; repeatable): the faces on the outline seen "
             "from the light (the shadow's outline) are kept unchanged; light-silhouette cells finer, cells facing "
             "away from every light coarsest",
             [&](const std::string& v) { s.lights.push_back(direction("--light", v)); });
    p.option("--max-depth", "D",
             "finest sphere depth (8 * 4^D cells; default " + std::to_string(s.maxDepth) + ", at most " +
                 std::to_string(kAgsphereMaxDepth) + ")",
             [&](const std::string& v) {
                 s.maxDepth = cli::parseInt("--max-depth", v);
                 if (s.maxDepth < 0 || s.maxDepth > kAgsphereMaxDepth)
                     throw UsageError("--max-depth must be in [0, " + std::to_string(kAgsphereMaxDepth) + "]");
             });
    p.option("--boundary-tolerance", "S",
             "scale on the cells' error thresholds for simplifying shared region boundaries (default 1; 0 keeps "
             "every boundary vertex except on straight runs)",
             [&](const std::string& v) {
                 s.boundaryTolerance = cli::parseDouble("--boundary-tolerance", v);
                 if (!(s.boundaryTolerance >= 0)) throw UsageError("--boundary-tolerance must be >= 0");
             });
    p.option("--silhouette-band", "DEG",
             "a cell is a silhouette cell when its normals come within DEG of 90 degrees to a view or light "
             "(default " + std::to_string(int(s.silhouetteBand)) + ")",
             [&](const std::string& v) {
                 s.silhouetteBand = cli::parseDouble("--silhouette-band", v);
                 if (!(s.silhouetteBand >= 0 && s.silhouetteBand < 90)) throw UsageError("--silhouette-band must be in [0, 90)");
             });
    p.option("--view-distance", "K",
             "eye distance for --view outlines, in bounding radii from the bounding-box centre (default 0: "
             "infinitely far; compare's cameras are at 2)",
             [&](const std::string& v) {
                 s.viewDistance = cli::parseDouble("--view-distance", v);
                 if (!(s.viewDistance == 0 || s.viewDistance > 1)) throw UsageError("--view-distance must be 0 or > 1");
             });
    p.option("--outline-rings", "N", "extra rings of faces kept unchanged around each view's outline faces (default 0)",
             [&](const std::string& v) {
                 s.outlineRings = cli::parseInt("--outline-rings", v);
                 if (s.outlineRings < 0 || s.outlineRings > 8) throw UsageError("--outline-rings must be in [0, 8]");
             });
    p.flag("--no-keep-outline",
           "with --view/--light, do not keep the outline faces unchanged (cell selection only, as in the thesis)",
           [&] { s.keepOutline = false; });
    proceed = p.parse(argc, argv);
    return s;
}

std::vector<AgsphereTarget> validate(const Settings& s) {
    cli::checkPaths(s.common);
    std::vector<AgsphereTarget> targets;
    for (double r : s.ratios) {
        if (!(r > 0 && r <= 1)) throw UsageError("--ratio values must be in (0, 1]");
        targets.push_back({r, 0});
    }
    for (double t : s.triangles) {
        if (!(t >= 1) || t != static_cast<double>(static_cast<uint64_t>(t)))
            throw UsageError("--triangles values must be positive integers");
        targets.push_back({0, static_cast<uint64_t>(t)});
    }
    if (targets.empty()) throw UsageError("give at least one level: --ratio or --triangles");
    return targets;
}

nlohmann::json vec(Vec3 v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json makeReport(const Settings& s, const Asset& asset, const AgsphereResult& r, double loadSeconds,
                          double writeSeconds) {
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
        std::set<uint32_t> used;
        for (const Tri& t : L.triangles) used.insert(t.begin(), t.end());
        nlohmann::json target;
        if (L.targetRatio > 0) target["ratio"] = L.targetRatio;
        target["triangles"] = L.targetTriangles;
        levels.push_back({{"level", k + 1},
                          {"target", target},
                          {"triangles", L.triangles.size()},
                          {"estimatedTriangles", st.estimatedTriangles},
                          {"vertices", used.size()},
                          {"ratio", m.triangleCount() ? double(L.triangles.size()) / m.triangleCount() : 0.0},
                          {"maxDeviation", L.maxDeviation},
                          {"meanDeviation", L.meanDeviation},
                          {"maxDeviationRelative", r.diagonal > 0 ? L.maxDeviation / r.diagonal : 0.0},
                          {"meanDeviationRelative", r.diagonal > 0 ? L.meanDeviation / r.diagonal : 0.0},
                          {"regions", L.regionCount},
                          {"pairs", L.pairs.size()},
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
                          {"stopReason", st.stopReason},
                          {"seconds", L.seconds}});
    }
    nlohmann::json views = nlohmann::json::array(), lights = nlohmann::json::array();
    for (Vec3 v : s.views) views.push_back(vec(v));
    for (Vec3 v : s.lights) lights.push_back(vec(v));
    nlohmann::json rep;
    rep["tool"] = "agsphere-build";
    rep["input"] = {{"path", s.common.input},
                    {"triangles", m.triangleCount()},
                    {"vertices", m.vertexCount()},
                    {"wedges", m.wedges.size()},
                    {"materials", asset.materials.size()},
                    {"primitives", asset.stats.primitives},
                    {"diagonal", r.diagonal}};
    rep["output"] = s.common.output;
    rep["sphere"] = {{"maxDepth", s.maxDepth},
                     {"boundaryTolerance", s.boundaryTolerance},
                     {"silhouetteBandDeg", s.silhouetteBand},
                     {"depths", depths}};
    rep["views"] = views;
    rep["outline"] = {{"keep", s.keepOutline && !(s.views.empty() && s.lights.empty())},
                      {"viewDistance", s.viewDistance},
                      {"rings", s.outlineRings},
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

int run(const Settings& s) {
    std::vector<AgsphereTarget> targets = validate(s);
    double loadSeconds = 0;
    Asset asset = cli::loadInput("agsphere-build", s.common, loadSeconds);
    if (asset.mesh.triangleCount() == 0) throw Impossible(s.common.input + ": the scene has no triangles");

    AgsphereOptions opt;
    opt.levels = targets;
    opt.maxDepth = s.maxDepth;
    opt.views = s.views;
    opt.lights = s.lights;
    opt.boundaryTolerance = s.boundaryTolerance;
    opt.silhouetteBandDeg = s.silhouetteBand;
    opt.keepOutline = s.keepOutline;
    opt.viewDistance = s.viewDistance;
    opt.outlineRings = s.outlineRings;
    opt.threads = cli::resolveThreads(s.common.threads);
    cli::Progress progress("agsphere-build", cli::progressEnabled(s.common));
    opt.progress = [&progress](double f) { return progress(f); };
    AgsphereResult result = buildAgsphere(asset.mesh, opt);
    progress.done();

    auto t2 = std::chrono::steady_clock::now();
    WriteOptions wopt;
    wopt.generator = "lodbake agsphere-build 0.1.0";
    writeGltf(s.common.output, asset, &result.multires, wopt);
    double writeSeconds = cli::secondsSince(t2);

    nlohmann::json rep = makeReport(s, asset, result, loadSeconds, writeSeconds);
    if (!s.common.report.empty()) cli::writeReport(s.common.report, rep);
    if (s.common.verbose) {
        std::printf("input: %zu triangles, %zu vertices\n", asset.mesh.triangleCount(), asset.mesh.vertexCount());
        for (const auto& d : rep["sphere"]["depths"])
            std::printf("sphere depth %d: %d cells, %d regions, ~%d triangles\n", d["depth"].get<int>(),
                        d["cells"].get<int>(), d["regions"].get<int>(), d["estimatedTriangles"].get<int>());
        for (const auto& L : rep["levels"])
            std::printf("level %d: %d triangles, %d regions, max deviation %.4g (%.3g%% of diagonal), %s\n",
                        L["level"].get<int>(), L["triangles"].get<int>(), L["regions"].get<int>(),
                        L["maxDeviation"].get<double>(), 100 * L["maxDeviationRelative"].get<double>(),
                        L["stopReason"].get<std::string>().c_str());
    }
    return cli::kOk;
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Settings>("agsphere-build", argc, argv, parseArgs, run); }
