// agsphere-build: any glTF in, multiresolution glTF out (M-AGSphere, thesis 2.4), with
// view- and light-silhouette-preserving levels. Same output format as `simplify`.
// Parses the flags into AgsphereBuildSettings, validates them and runs the stage
// (lodbake/stages/agsphere_build.h).
#include "common/cli.h"
#include "lodbake/stages/agsphere_build.h"

using namespace lodbake;

namespace {

struct Args {
    AgsphereBuildSettings stage;
    bool quiet = false;
    std::vector<double> ratios, triangles;  // the level flags, turned into stage.agsphere.levels
};

Vec3 direction(const std::string& flag, const std::string& v) {
    std::vector<double> d = cli::parseVec3(flag, v);
    Vec3 r{d[0], d[1], d[2]};
    if (!(length(r) > 0)) throw UsageError(flag + " needs a non-zero direction");
    return r;
}

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    AgsphereOptions& o = a.stage.agsphere;
    cli::ArgParser p("agsphere-build",
                     "-i INPUT -o OUTPUT (--ratio R,... | --triangles N,...) [--view X,Y,Z]... [--light X,Y,Z]... [options]");
    p.addCommon(a.stage.common, a.quiet);
    p.option("--ratio", "R,...", "levels as fractions of the input triangle count, e.g. 0.5,0.1,0.02",
             [&](const std::string& v) { a.ratios = cli::parseDoubleList("--ratio", v); });
    p.option("--triangles", "N,...", "levels as absolute triangle counts",
             [&](const std::string& v) { a.triangles = cli::parseDoubleList("--triangles", v); });
    p.option("--view", "X,Y,Z",
             "a view direction (from the object towards the camera; repeatable): the faces on the outline seen "
             "from it are kept unchanged; silhouette cells two sphere depths finer than the reference cell, the "
             "others one",
             [&](const std::string& v) { o.views.push_back(direction("--view", v)); });
    p.option("--light", "X,Y,Z",
             "a light direction (from the object towards the light; repeatable): the faces on the outline seen "
             "from the light (the shadow's outline) are kept unchanged; light-silhouette cells finer, cells facing "
             "away from every light coarsest",
             [&](const std::string& v) { o.lights.push_back(direction("--light", v)); });
    p.option("--max-depth", "D",
             "finest sphere depth (8 * 4^D cells; default " + std::to_string(o.maxDepth) + ", at most " +
                 std::to_string(kAgsphereMaxDepth) + ")",
             [&](const std::string& v) {
                 o.maxDepth = cli::parseInt("--max-depth", v);
                 if (o.maxDepth < 0 || o.maxDepth > kAgsphereMaxDepth)
                     throw UsageError("--max-depth must be in [0, " + std::to_string(kAgsphereMaxDepth) + "]");
             });
    p.option("--boundary-tolerance", "S",
             "scale on the cells' error thresholds for simplifying shared region boundaries (default " +
                 cli::number(o.boundaryTolerance) + "; 0 keeps every boundary vertex except on straight runs)",
             [&](const std::string& v) {
                 o.boundaryTolerance = cli::parseDouble("--boundary-tolerance", v);
                 if (!(o.boundaryTolerance >= 0)) throw UsageError("--boundary-tolerance must be >= 0");
             });
    p.option("--silhouette-band", "DEG",
             "a cell is a silhouette cell when its normals come within DEG of 90 degrees to a view or light "
             "(default " + std::to_string(int(o.silhouetteBandDeg)) + ")",
             [&](const std::string& v) {
                 o.silhouetteBandDeg = cli::parseDouble("--silhouette-band", v);
                 if (!(o.silhouetteBandDeg >= 0 && o.silhouetteBandDeg < 90))
                     throw UsageError("--silhouette-band must be in [0, 90)");
             });
    p.option("--view-distance", "K",
             "eye distance for --view outlines, in bounding radii from the bounding-box centre (default " +
                 cli::number(o.viewDistance) + ": infinitely far; compare's cameras are at 2)",
             [&](const std::string& v) {
                 o.viewDistance = cli::parseDouble("--view-distance", v);
                 if (!(o.viewDistance == 0 || o.viewDistance > 1)) throw UsageError("--view-distance must be 0 or > 1");
             });
    p.option("--outline-rings", "N",
             "extra rings of faces kept unchanged around each view's outline faces (default " +
                 std::to_string(o.outlineRings) + ")",
             [&](const std::string& v) {
                 o.outlineRings = cli::parseInt("--outline-rings", v);
                 if (o.outlineRings < 0 || o.outlineRings > 8) throw UsageError("--outline-rings must be in [0, 8]");
             });
    p.flag("--no-keep-outline",
           "with --view/--light, do not keep the outline faces unchanged (cell selection only, as in the thesis)",
           [&] { o.keepOutline = false; });
    proceed = p.parse(argc, argv);
    return a;
}

// Checks the paths and the level flags, in this order, and sets the level targets.
void validate(Args& a) {
    cli::checkPaths(a.stage.common);
    std::vector<AgsphereTarget>& targets = a.stage.agsphere.levels;
    for (double r : a.ratios) {
        if (!(r > 0 && r <= 1)) throw UsageError("--ratio values must be in (0, 1]");
        targets.push_back({r, 0});
    }
    for (double t : a.triangles) {
        if (!(t >= 1) || t != static_cast<double>(static_cast<uint64_t>(t)))
            throw UsageError("--triangles values must be positive integers");
        targets.push_back({0, static_cast<uint64_t>(t)});
    }
    if (targets.empty()) throw UsageError("give at least one level: --ratio or --triangles");
}

int run(Args& a) {
    validate(a);
    return cli::runStage("agsphere-build", a.stage, a.quiet, runAgsphereBuild);
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("agsphere-build", argc, argv, parseArgs, run); }
