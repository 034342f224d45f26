// texture-refine's flags (stage_flags.h).
#include <algorithm>

#include "common/stage_flags.h"

namespace lodbake::cli {
namespace {

std::string list(const std::vector<int>& values) {
    std::string out;
    for (int v : values) out += (out.empty() ? "" : ",") + std::to_string(v);
    return out;
}

}  // namespace

void addTextureRefineFlags(ArgParser& p, TextureRefineFlags& a, const std::string& clashPrefix) {
    a.clashPrefix = clashPrefix;
    RefineOptions& o = a.settings.refine;
    const std::string size = "--" + clashPrefix + "size", split = "--" + clashPrefix + "split",
                      alpha = "--" + clashPrefix + "alpha", beta = "--" + clashPrefix + "beta",
                      iterations = "--" + clashPrefix + "iterations";
    p.option(size, "N",
             "side of the atlas the rank layouts are packed for, texels; E is reported at this resolution (default " +
                 std::to_string(o.param.textureSize) + ")",
             [&o, size](const std::string& v) { o.param.textureSize = parseInt(size, v); });
    p.option("--sizes", "LIST",
             "MIP-style hierarchy: every layout is baked at each of these sides (default " + list(o.sizes) + ")",
             [&o](const std::string& v) {
                 o.sizes.clear();
                 for (double x : parseDoubleList("--sizes", v)) {
                     if (x != double(int(x))) throw UsageError("--sizes takes integers");
                     o.sizes.push_back(int(x));
                 }
             });
    p.flag("--no-images", "record the hierarchy's textures (rank, levels, size) without baking their images; pack does not read "
                          "them (lodbake bakes them only into a kept .tex.glb)",
           [&o] { o.bakeImages = false; });
    p.option("--min-refined-size", "N",
             "refined ranks are baked only at --sizes >= N; pack uses a rank only on pages >= its smallest size "
             "(default " + std::to_string(o.minRefinedSize) + ")",
             [&o](const std::string& v) { o.minRefinedSize = parseInt("--min-refined-size", v); });
    p.option("--min-std-dev", "X",
             "do not refine levels where T0's UV-area/3D-area std-dev is below X (default " +
                 number(o.minAreaRatioStdDev) + ")",
             [&o](const std::string& v) { o.minAreaRatioStdDev = parseDouble("--min-std-dev", v); });
    p.option("--max-extra-cuts", "X",
             "a rank serves a level only if its chart boundaries cut at most this fraction of the level's triangles "
             "more than T0's (default " + number(o.maxExtraCutFraction) + ")",
             [&o](const std::string& v) { o.maxExtraCutFraction = parseDouble("--max-extra-cuts", v); });
    p.flag("--keep-level-triangles-whole", "merge pieces back while their boundaries cut more level triangles than their parent chart did",
           [&o] { o.keepLevelTrianglesWhole = true; });
    p.option("--ranks", "N",
             "refine up to rank N (fewer when no finer level splits the charts; 0 = MIP-style only; default " +
                 std::to_string(o.ranks) + ")",
             [&o](const std::string& v) { o.ranks = parseInt("--ranks", v); });
    p.option("--max-refine-triangles", "N",
             "meshes with more triangles keep T0 for every level: no refined ranks, with a warning (0 = no limit; "
             "default " + std::to_string(o.maxTriangles) + ")",
             [&o](const std::string& v) { o.maxTriangles = size_t(std::max(0, parseInt("--max-refine-triangles", v))); });
    p.option(split, "N", "charts each chart is split into per rank (default " + std::to_string(o.splitPerChart) + ")",
             [&o, split](const std::string& v) { o.splitPerChart = uint32_t(std::max(0, parseInt(split, v))); });
    p.option(alpha, "A", "edge vs area weight in E_pixel, in [0,1] (default " + number(o.param.solve.energy.alpha) + ")",
             [&o, alpha](const std::string& v) { o.param.solve.energy.alpha = parseDouble(alpha, v); });
    p.option(beta, "B", "E_pixel vs E_poly weight, in [0,1] (default " + number(o.param.solve.energy.beta) + ")",
             [&o, beta](const std::string& v) { o.param.solve.energy.beta = parseDouble(beta, v); });
    p.option(iterations, "N", "Ceres iterations per chart (0 = Tutte maps; default " + std::to_string(o.param.solve.maxIterations) + ")",
             [&o, iterations](const std::string& v) { o.param.solve.maxIterations = parseInt(iterations, v); });
}

void validateTextureRefine(const TextureRefineFlags& a) {
    const RefineOptions& o = a.settings.refine;
    const std::string pre = "--" + a.clashPrefix;
    if (o.param.textureSize < 16 || o.param.textureSize > 16384) throw UsageError(pre + "size must be in [16, 16384]");
    if (o.sizes.empty()) throw UsageError("--sizes must list at least one size");
    for (int x : o.sizes)
        if (x < 16 || x > 16384) throw UsageError("--sizes entries must be in [16, 16384]");
    if (o.minRefinedSize < 0) throw UsageError("--min-refined-size must be >= 0");
    if (!(o.minAreaRatioStdDev >= 0)) throw UsageError("--min-std-dev must be >= 0");
    if (!(o.maxExtraCutFraction >= 0 && o.maxExtraCutFraction <= 1)) throw UsageError("--max-extra-cuts must be in [0, 1]");
    if (o.ranks < 0 || o.ranks > 16) throw UsageError("--ranks must be in [0, 16]");
    if (o.splitPerChart < 2) throw UsageError(pre + "split must be >= 2");
    if (!(o.param.solve.energy.alpha >= 0 && o.param.solve.energy.alpha <= 1)) throw UsageError(pre + "alpha must be in [0, 1]");
    if (!(o.param.solve.energy.beta >= 0 && o.param.solve.energy.beta <= 1)) throw UsageError(pre + "beta must be in [0, 1]");
    if (o.param.solve.maxIterations < 0) throw UsageError(pre + "iterations must be >= 0");
}

}  // namespace lodbake::cli
