// parameterize's flags (stage_flags.h).
#include "common/stage_flags.h"

namespace lodbake::cli {

void addParameterizeFlags(ArgParser& p, ParameterizeFlags& a) {
    ParameterizeOptions& o = a.settings.parameterize;
    a.maxCharts = int(o.charts.maxCharts);
    p.option("--size", "N", "atlas side in texels (default " + std::to_string(o.textureSize) + ")",
             [&o](const std::string& v) { o.textureSize = parseInt("--size", v); });
    p.option("--alpha", "A", "edge vs area weight in E_pixel, in [0,1] (default " + number(o.solve.energy.alpha) + ")",
             [&o](const std::string& v) { o.solve.energy.alpha = parseDouble("--alpha", v); });
    p.option("--beta", "B", "E_pixel vs E_poly weight, in [0,1] (default " + number(o.solve.energy.beta) + ")",
             [&o](const std::string& v) { o.solve.energy.beta = parseDouble("--beta", v); });
    p.option("--max-charts", "N", "merge charts down to at most N (0 = by shape limits only)",
             [&a](const std::string& v) { a.maxCharts = parseInt("--max-charts", v); });
    p.option("--iterations", "N",
             "Ceres iterations per chart (0 = keep the Tutte maps; default " + std::to_string(o.solve.maxIterations) + ")",
             [&o](const std::string& v) { o.solve.maxIterations = parseInt("--iterations", v); });
    p.flag("--no-level-islands",
           "no fallback islands: a level triangle that folds in its chart keeps its folded UVs (reported, with a "
           "warning)",
           [&o] { o.levelIslands = false; });
    p.flag("--no-crossing-islands",
           "a level triangle that crosses a chart boundary takes projected UVs in one chart instead of its own "
           "island (smears that chart's texture over it)",
           [&o] { o.crossingIslands = false; });
    p.flag("--allow-level-folds",
           "deprecated, no effect: folds that survive every fallback are now a warning and the output is written",
           [] {});
}

void validateParameterize(ParameterizeFlags& a) {
    const ParameterizeOptions& o = a.settings.parameterize;
    if (o.textureSize < 16 || o.textureSize > 16384) throw UsageError("--size must be in [16, 16384]");
    if (!(o.solve.energy.alpha >= 0 && o.solve.energy.alpha <= 1)) throw UsageError("--alpha must be in [0, 1]");
    if (!(o.solve.energy.beta >= 0 && o.solve.energy.beta <= 1)) throw UsageError("--beta must be in [0, 1]");
    if (a.maxCharts < 0) throw UsageError("--max-charts must be >= 0");
    if (o.solve.maxIterations < 0) throw UsageError("--iterations must be >= 0");
    a.settings.parameterize.charts.maxCharts = uint32_t(a.maxCharts);
}

std::string parameterizeExitCodes() {
    return "Every level is checked in the packed atlas (flipped or overlapping UV triangles). A level\n"
           "triangle that still folds inside its chart (usually one a collapse moved across a chart cut)\n"
           "falls back to its own small UV island: the coarse triangle laid flat at the atlas density,\n"
           "baked by sampling the closest point of the original surface at each texel (same density,\n"
           "but its texels are not continuous with the neighbouring charts', so filtering can show a\n"
           "seam). The report counts islands per level (islandTriangles). An original face still folded\n"
           "in the packed atlas, and every face of a chart the solver cannot flatten, gets a chart of\n"
           "its own (carvedFaces); each fallback is a warning. docs/parameterize.md.\n"
           "Exit codes: 0 success, 1 usage error, 2 unreadable or invalid input,\n"
           "            3 valid input but the operation is impossible (the charts do not fit the\n"
           "            texture), 4 internal failure.\n";
}

}  // namespace lodbake::cli
