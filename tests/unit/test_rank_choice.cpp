// Rank choice by the bake (lib/src/lod/rank_choice.h): the probe's samples, the read-back
// deviation of a candidate page, and the choice between a seamless and a seamed page.
#include <gtest/gtest.h>

#include <cmath>

#include "lod/rank_choice.h"

using namespace lodbake;
using namespace lodbake::lod_detail;

namespace {

// The surface colour of the test: a linear ramp over the unit right triangle (0,0,0) (1,0,0)
// (0,1,0), so that a bilinear read-back of texels holding it exactly is exact.
Vec3 ramp(double x, double y) { return {0.2 + 0.5 * x, 0.3 + 0.4 * y, 0.6}; }

const std::array<Vec3, 3> kTriangle{Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 1, 0}};

// A probe page as its bake would fill it: each sample's texel holds the ramp at its point.
std::vector<float> probePixels(const ProbeLayout& p) {
    std::vector<float> px(size_t(p.side) * size_t(p.side) * 3, 0.f);
    for (const ProbeLayout::Sample& s : p.samples) {
        const Vec3 X = kTriangle[0] * s.bary[0] + kTriangle[1] * s.bary[1] + kTriangle[2] * s.bary[2];
        const Vec3 c = ramp(X.x, X.y);
        for (size_t k = 0; k < 3; ++k) px[size_t(s.texel) * 3 + k] = float(c[int(k)]);
    }
    return px;
}

// An n x n page on which the triangle's UV legs span [lo, hi] in both directions (texel-centre
// coordinates: texel x's centre is at x): texels hold the ramp at their point, extended affinely
// beyond the triangle (a seamless page), or black when their centre lies outside [lo, hi] (a
// chart against an empty gutter: a seam where the chart's border falls between texel centres).
std::vector<float> page(int n, double lo, double hi, bool gutterBlack, std::vector<std::array<Vec2, 3>>& uv) {
    std::vector<float> px(size_t(n) * size_t(n) * 3, 0.f);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            if (gutterBlack && (x < lo || x > hi || y < lo || y > hi)) continue;
            const Vec3 c = ramp((x - lo) / (hi - lo), (y - lo) / (hi - lo));
            for (size_t k = 0; k < 3; ++k) px[(size_t(y) * size_t(n) + size_t(x)) * 3 + k] = float(c[int(k)]);
        }
    // Texel centre t sits at UV (t + 0.5) / n.
    auto at = [&](double tx, double ty) { return Vec2{(tx + 0.5) / n, (ty + 0.5) / n}; };
    uv = {{at(lo, lo), at(hi, lo), at(lo, hi)}};
    return px;
}

}  // namespace

TEST(RankChoice, ProbeSamplesLieInsideTheirCellAndWeighTheArea) {
    // One triangle: a 32-texel cell (the cap), 31 x 32 / 2 samples strictly inside its lower-left half.
    ProbeLayout p = probeLayout({kTriangle});
    ASSERT_EQ(p.cell, 32);
    ASSERT_EQ(p.side, 32);
    ASSERT_EQ(p.samples.size(), size_t(31 * 32 / 2));
    double weight = 0;
    for (const ProbeLayout::Sample& s : p.samples) {
        const int x = int(s.texel) % p.side, y = int(s.texel) / p.side;
        // Texel centre = the sample's barycentric point on the cell's triangle (corners (0,0), (c,0), (0,c)).
        EXPECT_NEAR(x + 0.5, s.bary[1] * p.cell, 1e-9);
        EXPECT_NEAR(y + 0.5, s.bary[2] * p.cell, 1e-9);
        EXPECT_GT(s.bary[0], 0.0);
        weight += s.weight;
    }
    EXPECT_NEAR(weight, 0.5, 1e-12);  // the triangle's area
}

TEST(RankChoice, ManyTrianglesShareCellsAndKeepTheirArea) {
    // 40,000 triangles > 64^2 cells: every tenth gets a cell and weighs for its group.
    std::vector<std::array<Vec3, 3>> tris(40000, kTriangle);
    ProbeLayout p = probeLayout(tris);
    EXPECT_EQ(p.cell, 4);
    EXPECT_LE(p.side, 256);
    EXPECT_EQ(p.triangles.size(), size_t(4000));
    EXPECT_EQ(p.triangles[1], 10u);
    double weight = 0;
    for (const ProbeLayout::Sample& s : p.samples) weight += s.weight;
    EXPECT_NEAR(weight, 0.5 * 40000, 1e-6);
}

TEST(RankChoice, ObjectSpaceTargetHasTheObjectAxesAsFrames) {
    BakeTarget t = objectSpaceTarget({{Vec2{0, 0}, Vec2{1, 0}, Vec2{0, 1}}});
    ASSERT_EQ(t.normal.size(), 1u);
    EXPECT_EQ(t.normal[0][2].z, 1.0);
    EXPECT_EQ(t.tangent[0][1].x, 1.0);
    EXPECT_EQ(t.tangent[0][1].w, 1.0);
}

// Two candidate layouts of one triangle at equal texel count: "T0" a seamless page (its texels
// continue the surface past the triangle), "rank 1" the same triangle as a smaller chart against
// black gutters, whose border taps mix them in: the seam a bake's chart borders show. The choice
// keeps T0, with the seamless page's deviation zero, whatever the energy rule would pick.
TEST(RankChoice, TheSeamlessPageWins) {
    ProbeLayout p = probeLayout({kTriangle});
    const std::vector<float> probe = probePixels(p);
    const PageChannels probePage{p.side, p.side, &probe, nullptr};
    std::vector<std::array<Vec2, 3>> uvA, uvB;
    const std::vector<float> a = page(16, 0, 15, false, uvA);  // the whole page: seamless
    const std::vector<float> b = page(16, 1.5, 9.5, true, uvB);  // a smaller chart with a black gutter
    RankCandidate t0, r1;
    t0.rank = 0;
    r1.rank = 1;
    t0.deviation = textureDeviation(p, probePage, PageChannels{16, 16, &a, nullptr}, uvA);
    r1.deviation = textureDeviation(p, probePage, PageChannels{16, 16, &b, nullptr}, uvB);
    EXPECT_LT(t0.deviation.score, 1e-6);
    EXPECT_EQ(t0.deviation.normal, 0.0);  // no normals compared
    EXPECT_GT(r1.deviation.score, 0.01);
    EXPECT_EQ(r1.deviation.score, r1.deviation.color);
    const std::vector<RankCandidate> candidates{t0, r1};
    EXPECT_EQ(bestCandidate(candidates), 0u);
    const std::string why = choiceReason(candidates, 0, 1);
    EXPECT_NE(why.find("T0 shows the least texture deviation"), std::string::npos) << why;
    EXPECT_NE(why.find("the energy rule would pick rank 1"), std::string::npos) << why;
}

TEST(RankChoice, ATieKeepsTheLowerRank) {
    RankCandidate a, b;
    a.rank = 0;
    b.rank = 2;
    a.deviation.score = b.deviation.score = 0.25;
    EXPECT_EQ(bestCandidate({a, b}), 0u);
    b.deviation.score = 0.2;
    EXPECT_EQ(bestCandidate({a, b}), 1u);
    EXPECT_NE(choiceReason({a, b}, 1, 2).find("also the energy rule's pick"), std::string::npos);
}

// The energy rule's pick (rank 2) stays while it scores within kScoreMargin of the best; beyond,
// the best wins.
TEST(RankChoice, TheEnergyPickStaysWithinTheMargin) {
    std::vector<RankCandidate> c(3);
    for (uint32_t r = 0; r < 3; ++r) c[r].rank = r;
    c[0].deviation.score = 0.100;
    c[1].deviation.score = 0.120;
    c[2].deviation.score = 0.100 * (1 + 0.5 * kScoreMargin);
    EXPECT_EQ(chooseCandidate(c, 2), 2u);
    EXPECT_NE(choiceReason(c, 2, 2).find("within the margin"), std::string::npos) << choiceReason(c, 2, 2);
    c[2].deviation.score = 0.100 * (1 + 2 * kScoreMargin);
    EXPECT_EQ(chooseCandidate(c, 2), 0u);
    EXPECT_EQ(chooseCandidate(c, 2, 0.0), 0u);
    c[2].deviation.score = 0.05;
    EXPECT_EQ(chooseCandidate(c, 2), 2u);
}
