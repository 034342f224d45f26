// simplify: any glTF in, multiresolution glTF out (half-edge collapse with region hierarchy).
// Parses the flags into SimplifySettings, validates them and runs the stage (lodbake/stages/simplify.h).
#include "common/cli.h"
#include "lodbake/stages/simplify.h"

using namespace lodbake;

namespace {

struct Args {
    SimplifySettings stage;
    bool quiet = false;
    std::vector<double> ratios, triangles, maxErrors;  // the level flags, turned into stage.simplify.levels
};

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    SimplifyOptions& o = a.stage.simplify;
    cli::ArgParser p("simplify", "-i INPUT -o OUTPUT (--ratio R,... | --triangles N,... | --max-error E,...) [options]");
    p.addCommon(a.stage.common, a.quiet);
    p.option("--ratio", "R,...", "levels as fractions of the input triangle count, e.g. 0.5,0.1,0.02",
             [&](const std::string& v) { a.ratios = cli::parseDoubleList("--ratio", v); });
    p.option("--triangles", "N,...", "levels as absolute triangle counts",
             [&](const std::string& v) { a.triangles = cli::parseDoubleList("--triangles", v); });
    p.option("--max-error", "E,...", "levels by maximum vertex deviation relative to the bounding-box diagonal",
             [&](const std::string& v) { a.maxErrors = cli::parseDoubleList("--max-error", v); });
    p.option("--max-region-cone", "DEG",
             "largest normal spread of a region (half-angle of the equivalent cap, degrees; default " +
                 std::to_string(int(o.maxRegionConeDeg)) + ", 180 = off): regions become texture charts",
             [&](const std::string& v) {
                 o.maxRegionConeDeg = cli::parseDouble("--max-region-cone", v);
                 if (!(o.maxRegionConeDeg > 0 && o.maxRegionConeDeg <= 180))
                     throw UsageError("--max-region-cone must be in (0, 180]");
             });
    p.option("--max-influence-change", "D",
             "skinned meshes: a vertex collapses only onto a neighbour whose joint weights differ by at most this "
             "total variation (0 = identical influences, 1 = any; default " + cli::number(o.maxInfluenceChange) + ")",
             [&](const std::string& v) {
                 o.maxInfluenceChange = cli::parseDouble("--max-influence-change", v);
                 if (!(o.maxInfluenceChange >= 0 && o.maxInfluenceChange <= 1))
                     throw UsageError("--max-influence-change must be in [0, 1]");
             });
    p.option("--max-part-removal", "F",
             "when a triangle target cannot be reached otherwise (parts stuck on non-manifold edges or pinch "
             "vertices), remove whole parts up to this half-diagonal, as a fraction of the model's diagonal, "
             "smallest first (default " + cli::number(o.pruneStuckSize) + ", 0 = never)",
             [&](const std::string& v) {
                 o.pruneStuckSize = cli::parseDouble("--max-part-removal", v);
                 if (!(o.pruneStuckSize >= 0 && o.pruneStuckSize <= 1))
                     throw UsageError("--max-part-removal must be in [0, 1]");
             });
    proceed = p.parse(argc, argv);
    return a;
}

// Checks the paths and the level flags, in this order, and sets the level targets.
void validate(Args& a) {
    cli::checkPaths(a.stage.common);
    std::vector<LevelTarget>& targets = a.stage.simplify.levels;
    for (double r : a.ratios) {
        if (!(r > 0 && r <= 1)) throw UsageError("--ratio values must be in (0, 1]");
        targets.push_back({r, 0, 0});
    }
    for (double t : a.triangles) {
        if (!(t >= 1) || t != static_cast<double>(static_cast<uint64_t>(t)))
            throw UsageError("--triangles values must be positive integers");
        targets.push_back({0, static_cast<uint64_t>(t), 0});
    }
    for (double e : a.maxErrors) {
        if (!(e > 0)) throw UsageError("--max-error values must be > 0");
        targets.push_back({0, 0, e});
    }
    if (targets.empty()) throw UsageError("give at least one level: --ratio, --triangles or --max-error");
}

int run(Args& a) {
    validate(a);
    return cli::runStage("simplify", a.stage, a.quiet, runSimplify);
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("simplify", argc, argv, parseArgs, run); }
