// The chain's plan (level_plan.h): coverages, texel limits, eligible ranks, page sides.
#include "lod/level_plan.h"

#include <algorithm>
#include <cmath>

#include "lodbake/core/math.h"

namespace lodbake::lod_detail {
namespace {

// Value k = the smallest coverage at which level k is drawn; a coarser level is never drawn at a
// larger coverage than a finer one.
std::vector<double> screenCoverages(const LevelPlanInput& in, const LevelPlanOptions& options) {
    const size_t n = in.hausdorff.size();
    const double H = options.viewportHeight, p = options.pixelError;
    std::vector<double> coverage(n, 0);
    for (size_t k = 0; k + 1 < n; ++k) {
        const double e = in.hausdorff[k + 1];
        double c = e > kExactDeviation * in.diagonal ? 2 * in.radius * p / (e * H) : options.lod0Coverage;
        if (k > 0) c = std::min(c, coverage[k - 1]);
        coverage[k] = c;
    }
    double cutoff = options.cutoffPixels / H;
    if (n >= 2) cutoff = std::min(cutoff, 0.5 * coverage[n - 2]);
    coverage[n - 1] = cutoff;
    return coverage;
}

// Level k's coverage range, switch distance and texel limit (one texel per pixel at its largest
// coverage; with lod0Density, at LOD0's).
PlannedLevel levelCoverage(const std::vector<double>& coverage, size_t k, double lod0MaxCoverage, double radius,
                           const LevelPlanOptions& options) {
    const double H = options.viewportHeight;
    const double tanHalf = std::tan(options.fovY * kPi / 360);
    PlannedLevel l;
    l.coverage = coverage[k];
    l.maxCoverage = k == 0 ? std::max(options.lod0Coverage, l.coverage) : coverage[k - 1];
    l.switchDistance = radius / (l.coverage * tanHalf);
    l.texelLimit = (options.lod0Density && k > 0 ? lod0MaxCoverage : l.maxCoverage) * H / (2 * radius);
    return l;
}

// The eligible layouts of planned level `l` (multires level `level`); the page side estimate does
// not depend on the layout.
void eligibleRanks(const LevelPlanInput& in, size_t level, const LevelPlanOptions& options, PlannedLevel& l) {
    l.sideNeeded = std::min(double(options.maxSize), std::sqrt(in.area3D) * l.texelLimit / kPageSideFill);
    const size_t layouts = in.layoutUvPerUnit.size();
    std::vector<char> eligible(layouts, 0);
    eligible[0] = 1;
    std::vector<int> smallest(layouts, 0);
    for (const HierarchyTexture& h : in.textures)
        if (h.rank < layouts && (smallest[h.rank] == 0 || h.size < smallest[h.rank])) smallest[h.rank] = h.size;
    for (const HierarchyTexture& h : in.textures)
        if (h.firstLevel <= level && level <= h.lastLevel && h.rank < layouts && smallest[h.rank] <= l.sideNeeded) eligible[h.rank] = 1;
    for (uint32_t j = 0; j < eligible.size(); ++j)
        if (eligible[j]) l.eligibleRanks.push_back(j);
    l.rank = l.eligibleRanks.back();
}

}  // namespace

int hierarchyTextureSize(const std::vector<HierarchyTexture>& textures, uint32_t rank, double layoutTexels) {
    int size = 0;
    for (const HierarchyTexture& h : textures)
        if (h.rank == rank && (size == 0 || (size < layoutTexels && h.size > size) || (h.size >= layoutTexels && h.size < size)))
            size = h.size;
    return size;
}

LevelPlan planLevels(const LevelPlanInput& input, const LevelPlanOptions& options) {
    LevelPlan plan;
    plan.screenCoverage = screenCoverages(input, options);
    for (size_t k = 0; k < plan.screenCoverage.size(); ++k) {
        const double lod0MaxCoverage = k == 0 ? 0 : plan.levels[0].maxCoverage;
        PlannedLevel l = levelCoverage(plan.screenCoverage, k, lod0MaxCoverage, input.radius, options);
        eligibleRanks(input, input.multiresLevel[k], options, l);
        l.textureSize = hierarchyTextureSize(input.textures, l.rank, l.texelLimit / input.layoutUvPerUnit[l.rank]);
        plan.levels.push_back(std::move(l));
    }
    return plan;
}

}  // namespace lodbake::lod_detail
