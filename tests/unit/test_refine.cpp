// Unit tests for texture-refine: chart splitting, layout measures, the rank hierarchy and the
// LODBAKE_multires textureHierarchy round trip.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <set>

#include "lodbake/atlas/atlas_apply.h"
#include "lodbake/bake/bake.h"
#include "lodbake/texture/codec.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/chart/charts.h"
#include "lodbake/param/parameterize.h"
#include "lodbake/texture_hierarchy/refine.h"
#include "lodbake/simplify/simplify.h"
#include "parameterized_assets.h"
#include "synthetic_meshes.h"

using namespace lodbake;

using test::hemisphereAsset;
using test::Parameterized;

TEST(RefineSplit, PiecesAreDisksInsideTheirParent) {
    const Parameterized& p = hemisphereAsset();
    const TriMesh& m = p.asset.mesh;
    ASSERT_GE(p.mr.levels.size(), 2u);
    const std::vector<uint32_t>& regions = p.mr.levels[0].faceRegion;  // the finest level's regions
    uint32_t count = 0;
    std::vector<uint32_t> split = splitCharts(m, p.mr.charts.faceChart, p.mr.charts.chartCount, regions, 4, count);
    ASSERT_EQ(split.size(), m.triangleCount());
    EXPECT_GT(count, p.mr.charts.chartCount);
    EXPECT_LE(count, 4 * p.mr.charts.chartCount + 4);  // ~4 per chart (disk rule may leave a few more)
    std::map<uint32_t, std::vector<uint32_t>> pieces;
    for (uint32_t f = 0; f < split.size(); ++f) pieces[split[f]].push_back(f);
    EXPECT_EQ(pieces.size(), count);
    for (const auto& [rep, faces] : pieces) {
        EXPECT_EQ(rep, faces.front());  // the representative is the piece's smallest face
        std::set<uint32_t> parents;
        for (uint32_t f : faces) parents.insert(p.mr.charts.faceChart[f]);
        EXPECT_EQ(parents.size(), 1u) << "a piece straddles two parent charts";
        EXPECT_TRUE(isDisk(m, faces));
    }
}

TEST(RefineSplit, RememberedPiecesGiveTheSameSplit) {
    // refineTextures re-splits only some parents per round; the memo must not change any result.
    const Parameterized& p = hemisphereAsset();
    const TriMesh& m = p.asset.mesh;
    const std::vector<uint32_t>& regions = p.mr.levels[0].faceRegion;
    const uint32_t parents = p.mr.charts.chartCount;
    ASSERT_GE(parents, 1u);
    SplitMemo memo;
    std::vector<uint32_t> per(parents, 4);
    uint32_t countMemo = 0, countFresh = 0;
    EXPECT_EQ(splitCharts(m, p.mr.charts.faceChart, parents, regions, per, countMemo, &memo),
              splitCharts(m, p.mr.charts.faceChart, parents, regions, per, countFresh));
    EXPECT_EQ(countMemo, countFresh);
    EXPECT_EQ(memo.size(), parents);
    for (uint32_t target : {8u, 2u, 4u}) {  // 4 again: taken from the memo
        per[0] = target;
        EXPECT_EQ(splitCharts(m, p.mr.charts.faceChart, parents, regions, per, countMemo, &memo),
                  splitCharts(m, p.mr.charts.faceChart, parents, regions, per, countFresh));
        EXPECT_EQ(countMemo, countFresh);
    }
    EXPECT_EQ(memo.size(), parents + 2);
}

TEST(RefineSolveCache, RememberedSolvesGiveTheSameLayout) {
    // A second parameterize through the same cache takes every chart's map from it: the layout and
    // the reports are those of a run without the cache.
    const Parameterized& p = hemisphereAsset();
    ParameterizeOptions po;
    po.textureSize = 256;
    ParameterizeResult fresh = parameterize(p.asset.mesh, p.mr, po);
    po.solveCache = makeChartSolveCache();
    ParameterizeResult first = parameterize(p.asset.mesh, p.mr, po);
    ParameterizeResult again = parameterize(p.asset.mesh, p.mr, po);
    for (const ParameterizeResult* r : {&first, &again}) {
        EXPECT_EQ(r->charts.faceChart, fresh.charts.faceChart);
        ASSERT_EQ(r->cornerUV.size(), fresh.cornerUV.size());
        for (size_t f = 0; f < fresh.cornerUV.size(); ++f)
            for (size_t k = 0; k < 3; ++k) {
                EXPECT_EQ(r->cornerUV[f][k].x, fresh.cornerUV[f][k].x);
                EXPECT_EQ(r->cornerUV[f][k].y, fresh.cornerUV[f][k].y);
            }
        ASSERT_EQ(r->chartReports.size(), fresh.chartReports.size());
        for (size_t c = 0; c < fresh.chartReports.size(); ++c) {
            EXPECT_EQ(r->chartReports[c].method, fresh.chartReports[c].method);
            EXPECT_EQ(r->chartReports[c].final.E, fresh.chartReports[c].final.E);
        }
    }
    // Remembered reports are copies: the second run's solve times are the first run's.
    for (size_t c = 0; c < first.chartReports.size(); ++c) EXPECT_EQ(again.chartReports[c].seconds, first.chartReports[c].seconds);
}

TEST(RefineMeasure, T0IsInjectiveOnTheOriginalAndEnergyGrowsWithLevels) {
    const Parameterized& p = hemisphereAsset();
    const uint32_t n = uint32_t(p.mr.levels.size());
    LayoutMeasure all = measureLayout(p.asset.mesh, p.mr, p.mr.charts, n);
    LayoutMeasure fine = measureLayout(p.asset.mesh, p.mr, p.mr.charts, 1);
    ASSERT_EQ(all.levels.size(), n + 1);
    EXPECT_EQ(all.levels[0].flips, 0u);
    EXPECT_EQ(all.levels[0].overlaps, 0u);
    EXPECT_GT(all.triangles, fine.triangles);
    // E_pixel only depends on the layout; E_poly sums over more pairs with more levels.
    EXPECT_NEAR(all.energy.pixel, fine.energy.pixel, 1e-9 * all.energy.pixel);
    EXPECT_GT(all.pairs, fine.pairs);
    EXPECT_GE(all.energy.poly, fine.energy.poly);
    uint32_t histogram = 0;
    for (uint32_t b : all.areaRatioHistogram) histogram += b;
    EXPECT_EQ(histogram, all.triangles);
    EXPECT_GT(all.areaRatioStdDev, 0);
}

// The measures of every prefix of levels from one pass are exactly those measured one by one.
TEST(RefineMeasure, EveryLevelAtOnceEqualsEachLevelAlone) {
    const Parameterized& p = hemisphereAsset();
    const uint32_t n = uint32_t(p.mr.levels.size());
    const std::vector<LayoutMeasure> byLevel = measureLayoutLevels(p.asset.mesh, p.mr, p.mr.charts, n);
    ASSERT_EQ(byLevel.size(), n + 1);
    for (uint32_t v = 0; v <= n; ++v) {
        const LayoutMeasure alone = measureLayout(p.asset.mesh, p.mr, p.mr.charts, v);
        const LayoutMeasure& m = byLevel[v];
        EXPECT_EQ(m.lastLevel, v);
        EXPECT_EQ(m.pairs, alone.pairs);
        EXPECT_EQ(m.energy.E, alone.energy.E);
        EXPECT_EQ(m.energy.poly, alone.energy.poly);
        EXPECT_EQ(m.areaRatioStdDev, alone.areaRatioStdDev);
        EXPECT_EQ(m.areaRatioHistogram, alone.areaRatioHistogram);
        EXPECT_EQ(m.triangles, alone.triangles);
        EXPECT_EQ(m.crossing, alone.crossing);
        EXPECT_EQ(m.flips, alone.flips);
        EXPECT_EQ(m.overlaps, alone.overlaps);
        ASSERT_EQ(m.chartEnergies.size(), alone.chartEnergies.size());
        for (size_t c = 0; c < m.chartEnergies.size(); ++c) EXPECT_EQ(m.chartEnergies[c].E, alone.chartEnergies[c].E);
    }
}

TEST(RefineHierarchy, RanksLowerEnergyAndAreaRatioSpread) {
    const Parameterized& p = hemisphereAsset();
    RefineOptions o;
    o.param.textureSize = 256;
    o.sizes = {64, 128};
    o.minRefinedSize = 0;
    RefineResult r = refineTextures(p.asset, p.mr, o);
    ASSERT_GE(r.ranks.size(), 2u);
    EXPECT_EQ(r.ranks[0].lastLevel, p.mr.levels.size());
    for (size_t j = 1; j < r.ranks.size(); ++j) {
        const RankResult& rr = r.ranks[j];
        EXPECT_EQ(rr.rank, j);
        EXPECT_LE(rr.lastLevel, r.ranks[j - 1].lastLevel);  // a higher rank serves no coarser level
        EXPECT_GT(rr.layout.chartCount, r.ranks[j - 1].layout.chartCount);
        EXPECT_LT(rr.measure.energy.E, rr.base.energy.E) << "rank " << j;
        EXPECT_LT(rr.measure.areaRatioStdDev, rr.base.areaRatioStdDev) << "rank " << j;
        EXPECT_EQ(rr.measure.levels[0].flips, 0u);
        EXPECT_EQ(rr.measure.levels[0].overlaps, 0u);
        // Every level it serves: no flipped or overlapping triangle (level islands take the ones
        // that would fold), and its chart boundaries cut at most maxExtraCutFraction of the
        // level's triangles more than T0's.
        ASSERT_EQ(rr.measure.levels.size(), size_t(rr.lastLevel) + 1);
        ASSERT_EQ(rr.base.levels.size(), rr.measure.levels.size());
        for (size_t l = 0; l < rr.measure.levels.size(); ++l) {
            EXPECT_EQ(rr.measure.levels[l].flips, 0u) << "rank " << j << " level " << l;
            EXPECT_EQ(rr.measure.levels[l].overlaps, 0u) << "rank " << j << " level " << l;
            EXPECT_LE(double(rr.measure.crossing[l]),
                      double(rr.base.crossing[l]) + o.maxExtraCutFraction * double(rr.measure.levels[l].triangles))
                << "rank " << j << " level " << l;
        }
        for (const auto& c : rr.layout.cornerUV)
            for (const Vec2& q : c) {
                EXPECT_GT(q.x, 0);
                EXPECT_LT(q.x, 1);
                EXPECT_GT(q.y, 0);
                EXPECT_LT(q.y, 1);
            }
    }
    EXPECT_EQ(r.images.size(), r.ranks.size() * 2);
    for (const RefinedImage& img : r.images) {
        EXPECT_EQ(img.image.width, img.size);
        EXPECT_GT(img.coveredTexels, 0u);
    }

    // Deterministic, whatever the number of threads.
    RefineOptions o2 = o;
    o2.param.threads = 2;
    RefineResult again = refineTextures(p.asset, p.mr, o2);
    ASSERT_EQ(again.ranks.size(), r.ranks.size());
    for (size_t j = 0; j < r.ranks.size(); ++j) {
        EXPECT_EQ(again.ranks[j].layout.faceChart, r.ranks[j].layout.faceChart);
        EXPECT_EQ(again.ranks[j].measure.energy.E, r.ranks[j].measure.energy.E);
    }
    for (size_t i = 0; i < r.images.size(); ++i) EXPECT_EQ(again.images[i].image.encoded, r.images[i].image.encoded);

    // Round trip through the LODBAKE_multires textureHierarchy.
    Asset a = p.asset;
    Multires mr = p.mr;
    applyTextureHierarchy(a, mr, r);
    ASSERT_EQ(mr.textures.ranks.size(), r.ranks.size() - 1);
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / "lodbake_test_refine";
    fs::create_directories(dir);
    std::string path = (dir / "refined.glb").string();
    writeGltf(path, a, &mr);
    std::optional<Multires> back;
    Asset b = readGltf(path, {}, &back);
    checkImages(b, ImageCheck::Header);
    ASSERT_TRUE(back.has_value());
    ASSERT_EQ(back->textures.textures.size(), mr.textures.textures.size());
    for (size_t i = 0; i < mr.textures.textures.size(); ++i) {
        const HierarchyTexture &x = mr.textures.textures[i], &y = back->textures.textures[i];
        EXPECT_EQ(x.rank, y.rank);
        EXPECT_EQ(x.firstLevel, y.firstLevel);
        EXPECT_EQ(x.lastLevel, y.lastLevel);
        EXPECT_EQ(x.size, y.size);
        ASSERT_GE(y.image, 0);
        EXPECT_EQ(b.images[size_t(y.image)].width, x.size);
    }
    ASSERT_EQ(back->textures.ranks.size(), mr.textures.ranks.size());
    for (size_t j = 0; j < mr.textures.ranks.size(); ++j) {
        EXPECT_EQ(back->textures.ranks[j].faceChart, mr.textures.ranks[j].faceChart);
        EXPECT_EQ(back->textures.ranks[j].chartCount, mr.textures.ranks[j].chartCount);
        for (size_t f = 0; f < mr.textures.ranks[j].cornerUV.size(); ++f)
            for (size_t k = 0; k < 3; ++k)
                EXPECT_NEAR(back->textures.ranks[j].cornerUV[f][k].x, mr.textures.ranks[j].cornerUV[f][k].x, 1e-6);
        ASSERT_EQ(back->textures.ranks[j].islands.size(), mr.textures.ranks[j].islands.size());
        for (size_t i = 0; i < mr.textures.ranks[j].islands.size(); ++i)
            EXPECT_EQ(back->textures.ranks[j].islands[i].vertices, mr.textures.ranks[j].islands[i].vertices);
    }
    fs::remove_all(dir);
}

TEST(RefineHierarchy, FileWithoutHierarchyReadsEmpty) {
    const Parameterized& p = hemisphereAsset();
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / "lodbake_test_refine_plain";
    fs::create_directories(dir);
    std::string path = (dir / "plain.glb").string();
    writeGltf(path, p.asset, &p.mr);
    std::optional<Multires> back;
    readGltf(path, {}, &back);
    ASSERT_TRUE(back.has_value());
    EXPECT_TRUE(back->textures.empty());
    EXPECT_TRUE(back->textures.ranks.empty());
    EXPECT_EQ(back->charts.chartCount, p.mr.charts.chartCount);
    fs::remove_all(dir);
}
