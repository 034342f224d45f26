// simplify's flags (stage_flags.h).
#include <cstdint>

#include "common/stage_flags.h"

namespace lodbake::cli {
namespace {
constexpr double kDefaultRatios[] = {0.5, 0.1, 0.02};
}  // namespace

void addSimplifyFlags(ArgParser& p, SimplifyFlags& a) {
    SimplifyOptions& o = a.settings.simplify;
    p.option("--ratio", "R,...", "levels as fractions of the input triangle count (default 0.5,0.1,0.02 when no level flag is given)",
             [&a](const std::string& v) { a.ratios = parseDoubleList("--ratio", v); });
    p.option("--triangles", "N,...", "levels as absolute triangle counts",
             [&a](const std::string& v) { a.triangles = parseDoubleList("--triangles", v); });
    p.option("--max-error", "E,...", "levels by maximum vertex deviation relative to the bounding-box diagonal",
             [&a](const std::string& v) { a.maxErrors = parseDoubleList("--max-error", v); });
    p.option("--max-region-cone", "DEG",
             "largest normal spread of a region (half-angle of the equivalent cap, degrees; default " +
                 std::to_string(int(o.maxRegionConeDeg)) + ", 180 = off): regions become texture charts",
             [&o](const std::string& v) {
                 o.maxRegionConeDeg = parseDouble("--max-region-cone", v);
                 if (!(o.maxRegionConeDeg > 0 && o.maxRegionConeDeg <= 180))
                     throw UsageError("--max-region-cone must be in (0, 180]");
             });
    p.option("--max-part-removal", "F",
             "when a triangle target cannot be reached otherwise (parts stuck on non-manifold edges or pinch "
             "vertices), remove whole parts up to this half-diagonal, as a fraction of the model's diagonal, "
             "smallest first (default " + number(o.pruneStuckSize) + ", 0 = never)",
             [&o](const std::string& v) {
                 o.pruneStuckSize = parseDouble("--max-part-removal", v);
                 if (!(o.pruneStuckSize >= 0 && o.pruneStuckSize <= 1))
                     throw UsageError("--max-part-removal must be in [0, 1]");
             });
    p.option("--gross-error", "F",
             "--ratio and --triangles levels stop before a collapse or a part removal would take them further than "
             "this fraction of the bounding-box diagonal from the input, and keep the triangles they have; the report "
             "says so (default " + number(o.grossError) + ", 0 = off)",
             [&o](const std::string& v) {
                 o.grossError = parseDouble("--gross-error", v);
                 if (!(o.grossError >= 0)) throw UsageError("--gross-error must be >= 0");
             });
    p.flag("--two-sided-cost",
           "cost a collapse also by the new surface's distance to the old one, not only by the vertex deviation "
           "(removed points to the new surface)",
           [&o] { o.twoSidedCost = true; });
    p.flag("--no-visual-weight",
           "prune parts by size, and during passes closed parts only, instead of lightest (least area) first and "
           "also stuck open or locked parts smaller than the pass's error limit",
           [&o] { o.visualWeight = false; });
    p.option("--max-influence-change", "D",
             "skinned meshes: a vertex collapses only onto a neighbour whose joint weights differ by at most this "
             "total variation (0 = identical influences, 1 = any; default: 1 when animations are sampled, whose posed "
             "measure then judges the collapse, " + number(SimplifyOptions::kBindPoseInfluenceChange) +
             " with --pose-samples 0 or no animation)",
             [&o](const std::string& v) {
                 o.maxInfluenceChange = parseDouble("--max-influence-change", v);
                 if (!(o.maxInfluenceChange >= 0 && o.maxInfluenceChange <= 1))
                     throw UsageError("--max-influence-change must be in [0, 1]");
             });
    PoseSampleOptions& ps = a.settings.poses;
    p.option("--pose-samples", "N",
             "rigged inputs: collapse costs and level deviations are also measured in the rest pose and at N "
             "evenly spaced times of each animation, at most " + std::to_string(ps.maxPoses) +
                 " poses in all (default " + std::to_string(ps.perAnimation) + ", 0 = bind pose only)",
             [&ps](const std::string& v) {
                 ps.perAnimation = parseInt("--pose-samples", v);
                 if (ps.perAnimation < 0) throw UsageError("--pose-samples must be >= 0");
             });
}

void validateSimplify(SimplifyFlags& a) {
    std::vector<LevelTarget>& targets = a.settings.simplify.levels;
    targets.clear();
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
    if (targets.empty()) {
        // No level flag: the chain most users want, as gltfpack's -si and Blender's Decimate
        // presets give: half, a tenth and a fiftieth of the triangles.
        for (double r : kDefaultRatios) targets.push_back({r, 0, 0});
        a.settings.levelsChosen = "default --ratio 0.5,0.1,0.02 (no --ratio, --triangles or --max-error given)";
    } else {
        a.settings.levelsChosen = "given by the level flags";
    }
}

}  // namespace lodbake::cli
