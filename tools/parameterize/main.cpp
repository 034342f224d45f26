// parameterize: multiresolution glTF in, same + new atlas UVs and one baked base-colour texture
// valid for every level (thesis 3.3). Parses the flags into ParameterizeSettings, validates them
// and runs the stage (lodbake/stages/parameterize.h).
#include "common/cli.h"
#include "lodbake/stages/parameterize.h"

using namespace lodbake;

namespace {

struct Args {
    ParameterizeSettings stage;
    bool quiet = false;
    int maxCharts = 0;  // --max-charts as given (checked >= 0 before it becomes charts.maxCharts)
};

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    ParameterizeOptions& o = a.stage.parameterize;
    a.maxCharts = int(o.charts.maxCharts);
    cli::ArgParser p("parameterize", "-i INPUT.mr.glb -o OUTPUT.uv.glb [options]");
    p.addCommon(a.stage.common, a.quiet);
    p.option("--size", "N", "atlas side in texels (default " + std::to_string(o.textureSize) + ")",
             [&](const std::string& v) { o.textureSize = cli::parseInt("--size", v); });
    p.option("--alpha", "A", "edge vs area weight in E_pixel, in [0,1] (default " + cli::number(o.solve.energy.alpha) + ")",
             [&](const std::string& v) { o.solve.energy.alpha = cli::parseDouble("--alpha", v); });
    p.option("--beta", "B", "E_pixel vs E_poly weight, in [0,1] (default " + cli::number(o.solve.energy.beta) + ")",
             [&](const std::string& v) { o.solve.energy.beta = cli::parseDouble("--beta", v); });
    p.option("--max-charts", "N", "merge charts down to at most N (0 = by shape limits only)",
             [&](const std::string& v) { a.maxCharts = cli::parseInt("--max-charts", v); });
    p.option("--iterations", "N",
             "Ceres iterations per chart (0 = keep the Tutte maps; default " + std::to_string(o.solve.maxIterations) + ")",
             [&](const std::string& v) { o.solve.maxIterations = cli::parseInt("--iterations", v); });
    p.flag("--no-level-islands",
           "no fallback islands: a level triangle that folds in its chart keeps its folded UVs (reported, with a "
           "warning)",
           [&] { o.levelIslands = false; });
    p.flag("--no-crossing-islands",
           "a level triangle that crosses a chart boundary takes projected UVs in one chart instead of its own "
           "island (smears that chart's texture over it)",
           [&] { o.crossingIslands = false; });
    p.flag("--allow-level-folds",
           "deprecated, no effect: folds that survive every fallback are now a warning and the output is written",
           [] {});
    p.exitCodes(
        "Every level is checked in the packed atlas (flipped or overlapping UV triangles). A level\n"
        "triangle that still folds inside its chart (usually one a collapse moved across a chart cut)\n"
        "falls back to its own small UV island: the coarse triangle laid flat at the atlas density,\n"
        "baked by sampling the closest point of the original surface at each texel (same density,\n"
        "but its texels are not continuous with the neighbouring charts', so filtering can show a\n"
        "seam). The report counts islands per level (islandTriangles). An original face still folded\n"
        "in the packed atlas, and every face of a chart the solver cannot flatten, gets a chart of\n"
        "its own (carvedFaces); each fallback is a warning. docs/parameterize.md.\n"
        "Exit codes: 0 success, 1 usage error, 2 unreadable or invalid input,\n"
        "            3 valid input but the operation is impossible (the charts do not fit the\n"
        "            texture), 4 internal failure.\n");
    proceed = p.parse(argc, argv);
    return a;
}

void validate(Args& a) {
    const ParameterizeOptions& o = a.stage.parameterize;
    if (o.textureSize < 16 || o.textureSize > 16384) throw UsageError("--size must be in [16, 16384]");
    if (!(o.solve.energy.alpha >= 0 && o.solve.energy.alpha <= 1)) throw UsageError("--alpha must be in [0, 1]");
    if (!(o.solve.energy.beta >= 0 && o.solve.energy.beta <= 1)) throw UsageError("--beta must be in [0, 1]");
    if (a.maxCharts < 0) throw UsageError("--max-charts must be >= 0");
    if (o.solve.maxIterations < 0) throw UsageError("--iterations must be >= 0");
    cli::checkPaths(a.stage.common);
    a.stage.parameterize.charts.maxCharts = uint32_t(a.maxCharts);
}

int run(Args& a) {
    validate(a);
    return cli::runStage("parameterize", a.stage, a.quiet, runParameterize);
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("parameterize", argc, argv, parseArgs, run); }
