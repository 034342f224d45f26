// The chain's plan (lib/src/lod/level_plan.h): screen coverages from measured deviations, the
// texel limit each level can show, its page side estimate and the eligible hierarchy ranks.
// Figures are powers of two so the expected values are exact.
#include <gtest/gtest.h>

#include <cmath>

#include "lod/level_plan.h"
#include "lodbake/core/math.h"

using namespace lodbake;
using namespace lodbake::lod_detail;

namespace {

// A chain of three levels on a bounding sphere of radius 1 (diagonal 2): LOD0 (the original),
// LOD1 measured at 1/128, LOD2 at 1/16 model units; a surface of area 4 (sqrt = 2); T0 only.
LevelPlanInput threeLevels() {
    LevelPlanInput in;
    in.hausdorff = {0, 1.0 / 128, 1.0 / 16};
    in.multiresLevel = {0, 1, 2};
    in.radius = 1;
    in.diagonal = 2;
    in.area3D = 4;
    in.layoutUvPerUnit = {1};
    return in;
}

LevelPlanOptions viewport1024() {
    LevelPlanOptions o;
    o.viewportHeight = 1024;
    o.pixelError = 1;
    o.cutoffPixels = 2;
    o.lod0Coverage = 1;
    return o;
}

HierarchyTexture texture(uint32_t rank, uint32_t first, uint32_t last, int size) {
    HierarchyTexture h;
    h.rank = rank;
    h.firstLevel = first;
    h.lastLevel = last;
    h.size = size;
    return h;
}

}  // namespace

// Coverage of level k = 2 R p / (e_{k+1} H): LOD0 while LOD1's 1/128 stays under a pixel (2 / 8),
// LOD1 while LOD2's 1/16 does (2 / 64); the last value culls at 2 pixels (2 / 1024).
TEST(LevelPlan, CoverageFromMeasuredDeviation) {
    const LevelPlan plan = planLevels(threeLevels(), viewport1024());
    ASSERT_EQ(plan.screenCoverage.size(), 3u);
    EXPECT_EQ(plan.screenCoverage[0], 0.25);
    EXPECT_EQ(plan.screenCoverage[1], 1.0 / 32);
    EXPECT_EQ(plan.screenCoverage[2], 1.0 / 512);
    ASSERT_EQ(plan.levels.size(), 3u);
    EXPECT_EQ(plan.levels[0].coverage, 0.25);
    EXPECT_EQ(plan.levels[0].maxCoverage, 1.0);  // lod0Coverage
    EXPECT_EQ(plan.levels[1].maxCoverage, 0.25);
    EXPECT_EQ(plan.levels[2].maxCoverage, 1.0 / 32);
    // Switch distance: R / (coverage x tan(fovY / 2)).
    EXPECT_DOUBLE_EQ(plan.levels[0].switchDistance, 1 / (0.25 * std::tan(kPi / 6)));
}

// A coarser level that measures closer than the finer one is not drawn at a larger coverage; a
// deviation below float precision is none: the coarser level serves at lod0Coverage.
TEST(LevelPlan, CoveragesDecreaseAndExactLevelsServeEverywhere) {
    LevelPlanInput in = threeLevels();
    in.hausdorff = {0, 1.0 / 16, 1.0 / 128};
    LevelPlan plan = planLevels(in, viewport1024());
    EXPECT_EQ(plan.screenCoverage[0], 1.0 / 32);
    EXPECT_EQ(plan.screenCoverage[1], 1.0 / 32);
    EXPECT_EQ(plan.screenCoverage[2], 1.0 / 512);

    in.hausdorff = {0, 0.5 * kExactDeviation * in.diagonal, 1.0 / 16};
    plan = planLevels(in, viewport1024());
    EXPECT_EQ(plan.screenCoverage[0], 1.0);
    EXPECT_EQ(plan.screenCoverage[1], 1.0 / 32);
}

// The cutoff is at most half the previous value: a coarse last level is still drawn down to
// half the coverage at which it took over.
TEST(LevelPlan, CutoffAtMostHalfThePreviousCoverage) {
    LevelPlanInput in = threeLevels();
    in.hausdorff = {0, 1.0 / 128, 1.0};  // LOD1 serves down to 2 / 1024: the cutoff halves that
    const LevelPlan plan = planLevels(in, viewport1024());
    EXPECT_EQ(plan.screenCoverage[1], 1.0 / 512);
    EXPECT_EQ(plan.screenCoverage[2], 1.0 / 1024);
}

// One texel per pixel at the largest coverage: maxCoverage x H / (2 R) texels per model unit;
// with lod0Density every level takes LOD0's.
TEST(LevelPlan, TexelLimitAtTheLargestCoverage) {
    LevelPlanOptions o = viewport1024();
    LevelPlan plan = planLevels(threeLevels(), o);
    EXPECT_EQ(plan.levels[0].texelLimit, 512.0);
    EXPECT_EQ(plan.levels[1].texelLimit, 128.0);
    EXPECT_EQ(plan.levels[2].texelLimit, 16.0);
    o.lod0Density = true;
    plan = planLevels(threeLevels(), o);
    for (const PlannedLevel& l : plan.levels) EXPECT_EQ(l.texelLimit, 512.0);
}

// Page side estimate: sqrt(area) x texel limit / kPageSideFill, capped by maxSize.
TEST(LevelPlan, PageSideNeeded) {
    LevelPlanOptions o = viewport1024();
    LevelPlan plan = planLevels(threeLevels(), o);
    EXPECT_DOUBLE_EQ(plan.levels[0].sideNeeded, 2 * 512 / kPageSideFill);
    EXPECT_DOUBLE_EQ(plan.levels[1].sideNeeded, 2 * 128 / kPageSideFill);
    EXPECT_DOUBLE_EQ(plan.levels[2].sideNeeded, 2 * 16 / kPageSideFill);
    o.maxSize = 1024;
    plan = planLevels(threeLevels(), o);
    EXPECT_EQ(plan.levels[0].sideNeeded, 1024.0);
}

// Without a hierarchy every level is on T0 with no hierarchy texture.
TEST(LevelPlan, WithoutHierarchyT0Only) {
    const LevelPlan plan = planLevels(threeLevels(), viewport1024());
    for (const PlannedLevel& l : plan.levels) {
        EXPECT_EQ(l.eligibleRanks, std::vector<uint32_t>{0});
        EXPECT_EQ(l.rank, 0u);
        EXPECT_EQ(l.textureSize, 0);
    }
}

// Hierarchy: rank 0 (T0's MIP variants, 512 and 1024, levels 0-2), rank 1 (256 and 1024, levels
// 1-2), rank 2 (2048, levels 1-2). LOD0 (multires level 0) may use rank 0 only; LOD1 (side needed
// 320) rank 1 too, whose smallest texture (256) fits, not rank 2 (2048); LOD2 (side 40) neither.
// The texture size is the smallest of the rank at the texel limit (layout units): LOD1's 128 -> 256.
TEST(LevelPlan, EligibleRanksAndTextureSize) {
    LevelPlanInput in = threeLevels();
    in.layoutUvPerUnit = {1, 1, 1};
    in.textures = {texture(0, 0, 2, 512), texture(0, 0, 2, 1024), texture(1, 1, 2, 256), texture(1, 1, 2, 1024),
                   texture(2, 1, 2, 2048)};
    const LevelPlan plan = planLevels(in, viewport1024());
    EXPECT_EQ(plan.levels[0].eligibleRanks, std::vector<uint32_t>{0});
    EXPECT_EQ(plan.levels[0].textureSize, 512);
    EXPECT_EQ(plan.levels[1].eligibleRanks, (std::vector<uint32_t>{0, 1}));
    EXPECT_EQ(plan.levels[1].rank, 1u);
    EXPECT_EQ(plan.levels[1].textureSize, 256);
    EXPECT_EQ(plan.levels[2].eligibleRanks, std::vector<uint32_t>{0});
    EXPECT_EQ(plan.levels[2].textureSize, 512);
}

// The smallest texture at the density, else the largest; none of the rank: 0.
TEST(LevelPlan, HierarchyTextureSize) {
    const std::vector<HierarchyTexture> t{texture(0, 0, 2, 256), texture(0, 0, 2, 512), texture(0, 0, 2, 1024)};
    EXPECT_EQ(hierarchyTextureSize(t, 0, 100), 256);
    EXPECT_EQ(hierarchyTextureSize(t, 0, 300), 512);
    EXPECT_EQ(hierarchyTextureSize(t, 0, 512), 512);
    EXPECT_EQ(hierarchyTextureSize(t, 0, 4096), 1024);
    EXPECT_EQ(hierarchyTextureSize(t, 1, 100), 0);
}
