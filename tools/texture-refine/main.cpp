// texture-refine: parameterized multiresolution glTF in, same + texture hierarchy out (MIP-style
// resolutions and rank-refined layouts, thesis chapter 4). `pack` picks from it per LOD.
// Parses the flags into TextureRefineSettings, validates them and runs the stage
// (lodbake/stages/texture_refine.h).
#include "common/cli.h"
#include "lodbake/stages/texture_refine.h"

using namespace lodbake;

namespace {

struct Args {
    TextureRefineSettings stage;
    bool quiet = false;
};

std::string list(const std::vector<int>& values) {
    std::string out;
    for (int v : values) out += (out.empty() ? "" : ",") + std::to_string(v);
    return out;
}

Args parseArgs(int argc, char** argv, bool& proceed) {
    Args a;
    RefineOptions& o = a.stage.refine;
    cli::ArgParser p("texture-refine", "-i INPUT.uv.glb -o OUTPUT.tex.glb [options]");
    p.addCommon(a.stage.common, a.quiet);
    p.option("--size", "N",
             "side of the atlas the rank layouts are packed for, texels; E is reported at this resolution (default " +
                 std::to_string(o.param.textureSize) + ")",
             [&](const std::string& v) { o.param.textureSize = cli::parseInt("--size", v); });
    p.option("--sizes", "LIST",
             "MIP-style hierarchy: every layout is baked at each of these sides (default " + list(o.sizes) + ")",
             [&](const std::string& v) {
                 o.sizes.clear();
                 for (double x : cli::parseDoubleList("--sizes", v)) {
                     if (x != double(int(x))) throw UsageError("--sizes takes integers");
                     o.sizes.push_back(int(x));
                 }
             });
    p.option("--min-refined-size", "N",
             "refined ranks are baked only at --sizes >= N; pack uses a rank only on pages >= its smallest size "
             "(default " + std::to_string(o.minRefinedSize) + ")",
             [&](const std::string& v) { o.minRefinedSize = cli::parseInt("--min-refined-size", v); });
    p.option("--min-std-dev", "X",
             "do not refine levels where T0's UV-area/3D-area std-dev is below X (default " +
                 cli::number(o.minAreaRatioStdDev) + ")",
             [&](const std::string& v) { o.minAreaRatioStdDev = cli::parseDouble("--min-std-dev", v); });
    p.option("--max-extra-cuts", "X",
             "a rank serves a level only if its chart boundaries cut at most this fraction of the level's triangles "
             "more than T0's (default " + cli::number(o.maxExtraCutFraction) + ")",
             [&](const std::string& v) { o.maxExtraCutFraction = cli::parseDouble("--max-extra-cuts", v); });
    p.flag("--keep-level-triangles-whole", "merge pieces back while their boundaries cut more level triangles than their parent chart did",
           [&] { o.keepLevelTrianglesWhole = true; });
    p.option("--ranks", "N",
             "refine up to rank N (fewer when no finer level splits the charts; 0 = MIP-style only; default " +
                 std::to_string(o.ranks) + ")",
             [&](const std::string& v) { o.ranks = cli::parseInt("--ranks", v); });
    p.option("--split", "N", "charts each chart is split into per rank (default " + std::to_string(o.splitPerChart) + ")",
             [&](const std::string& v) { o.splitPerChart = uint32_t(std::max(0, cli::parseInt("--split", v))); });
    p.option("--alpha", "A", "edge vs area weight in E_pixel, in [0,1] (default " + cli::number(o.param.solve.energy.alpha) + ")",
             [&](const std::string& v) { o.param.solve.energy.alpha = cli::parseDouble("--alpha", v); });
    p.option("--beta", "B", "E_pixel vs E_poly weight, in [0,1] (default " + cli::number(o.param.solve.energy.beta) + ")",
             [&](const std::string& v) { o.param.solve.energy.beta = cli::parseDouble("--beta", v); });
    p.option("--iterations", "N", "Ceres iterations per chart (0 = Tutte maps; default " + std::to_string(o.param.solve.maxIterations) + ")",
             [&](const std::string& v) { o.param.solve.maxIterations = cli::parseInt("--iterations", v); });
    proceed = p.parse(argc, argv);
    return a;
}

void validate(const Args& a) {
    const RefineOptions& o = a.stage.refine;
    if (o.param.textureSize < 16 || o.param.textureSize > 16384) throw UsageError("--size must be in [16, 16384]");
    if (o.sizes.empty()) throw UsageError("--sizes must list at least one size");
    for (int x : o.sizes)
        if (x < 16 || x > 16384) throw UsageError("--sizes entries must be in [16, 16384]");
    if (o.minRefinedSize < 0) throw UsageError("--min-refined-size must be >= 0");
    if (!(o.minAreaRatioStdDev >= 0)) throw UsageError("--min-std-dev must be >= 0");
    if (!(o.maxExtraCutFraction >= 0 && o.maxExtraCutFraction <= 1)) throw UsageError("--max-extra-cuts must be in [0, 1]");
    if (o.ranks < 0 || o.ranks > 16) throw UsageError("--ranks must be in [0, 16]");
    if (o.splitPerChart < 2) throw UsageError("--split must be >= 2");
    if (!(o.param.solve.energy.alpha >= 0 && o.param.solve.energy.alpha <= 1)) throw UsageError("--alpha must be in [0, 1]");
    if (!(o.param.solve.energy.beta >= 0 && o.param.solve.energy.beta <= 1)) throw UsageError("--beta must be in [0, 1]");
    if (o.param.solve.maxIterations < 0) throw UsageError("--iterations must be >= 0");
    cli::checkPaths(a.stage.common);
}

int run(Args& a) {
    validate(a);
    return cli::runStage("texture-refine", a.stage, a.quiet, runTextureRefine);
}

}  // namespace

int main(int argc, char** argv) { return cli::runMain<Args>("texture-refine", argc, argv, parseArgs, run); }
