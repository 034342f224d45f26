// sourceTexelLayout (lib/src/lod/source_texels.h): LOD0's charts are the original's texture
// islands in source texels; faces without a texture area keep their T0 pieces.
#include <gtest/gtest.h>

#include "lod/source_texels.h"

using namespace lodbake;
using namespace lodbake::lod_detail;

namespace {

// Two unit squares side by side (x in [0, 2]), four triangles, one material with a 64 x 32
// texture. The left square reads u in [0, 0.5]; the right one u in [right, right + 0.5] (0.5:
// the same island; else an island of its own, or on the left square's texels again when 0).
Asset twoSquares(double right) {
    Asset a;
    TriMesh& m = a.mesh;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
    m.wedges.vertex = {0, 1, 2, 3, 1, 4, 5, 2};
    m.wedges.uv0 = {{0, 1}, {0.5, 1}, {0.5, 0}, {0, 0}, {right, 1}, {right + 0.5, 1}, {right + 0.5, 0}, {right, 0}};
    m.cornerWedges = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
    m.triangleMaterial = {0, 0, 0, 0};
    Material mat;
    mat.baseColor.texture = 0;
    a.materials.push_back(mat);
    a.textures.push_back(Texture{0, -1});
    a.images.push_back(Image{});
    return a;
}

// A one-chart T0 layout: position (x, y) -> (x / 2, y).
ChartLayout t0For(const Asset& a) {
    ChartLayout t0;
    t0.chartCount = 1;
    t0.faceChart.assign(a.mesh.triangles.size(), 0);
    t0.cornerUV.resize(a.mesh.triangles.size());
    for (size_t f = 0; f < a.mesh.triangles.size(); ++f)
        for (size_t k = 0; k < 3; ++k) {
            const Vec3 p = a.mesh.positions[a.mesh.triangles[f][k]];
            t0.cornerUV[f][k] = {p.x / 2, p.y};
        }
    return t0;
}

}  // namespace

TEST(SourceTexels, IslandsInSourceTexels) {
    const Asset joined = twoSquares(0.5);
    SourceTexelLayout s = sourceTexelLayout(joined, {{64, 32}}, t0For(joined), 10);
    ASSERT_FALSE(s.layout.empty()) << s.reason;
    EXPECT_EQ(s.islands, 1u);
    EXPECT_EQ(s.layout.chartCount, 1u);
    // UV (0.5, 1) -> texel (32, 32).
    EXPECT_EQ(s.layout.cornerUV[0][1].x, 32.0);
    EXPECT_EQ(s.layout.cornerUV[0][1].y, 32.0);

    const Asset split = twoSquares(0.505);  // u in [0.505, 1.005]: no texel of the left square
    s = sourceTexelLayout(split, {{64, 32}}, t0For(split), 10);
    EXPECT_EQ(s.islands, 2u);
    EXPECT_NE(s.layout.faceChart[0], s.layout.faceChart[2]);
    EXPECT_EQ(s.layout.faceChart[2], s.layout.faceChart[3]);

    // The right square on the left one's texels: one chart, the texels stored once.
    const Asset shared = twoSquares(0);
    s = sourceTexelLayout(shared, {{64, 32}}, t0For(shared), 10);
    EXPECT_EQ(s.islands, 1u);
}

TEST(SourceTexels, MaterialsSharingTexelsKeepTheirOwnCharts) {
    // Both squares on the same texels, the right one through a second material that shows the
    // texture as emission: the texels shade differently, so each square is a chart of its own, and
    // only the first keeps its place on the page (the second would cover the same page texels).
    Asset a = twoSquares(0);
    Material glow;
    glow.emissive.texture = 0;
    a.materials.push_back(glow);
    a.mesh.triangleMaterial = {0, 0, 1, 1};
    SourceTexelLayout s = sourceTexelLayout(a, {{64, 32}}, t0For(a), 10);
    ASSERT_FALSE(s.layout.empty()) << s.reason;
    EXPECT_EQ(s.islands, 2u);
    EXPECT_EQ(s.inPlace, 1u);
    EXPECT_EQ(s.layout.faceChart[0], 0u);
    EXPECT_EQ(s.layout.faceChart[2], 1u);
    EXPECT_EQ(s.layout.faceChart[2], s.layout.faceChart[3]);
    // Both charts in the texture's texels: UV (0.5, 1) -> texel (32, 32).
    EXPECT_EQ(s.layout.cornerUV[2][1].x, 32.0);
    EXPECT_EQ(s.layout.cornerUV[2][1].y, 32.0);

    // A second material that differs only in what glTF keeps per primitive (its ior) shades the
    // texels alike: the texels are stored once again.
    Asset b = twoSquares(0);
    Material refracting = b.materials[0];
    refracting.ext.ior.present = true;
    refracting.ext.ior.ior = 1.33;
    b.materials.push_back(refracting);
    b.mesh.triangleMaterial = {0, 0, 1, 1};
    s = sourceTexelLayout(b, {{64, 32}}, t0For(b), 10);
    EXPECT_EQ(s.islands, 1u);
    EXPECT_EQ(s.inPlace, 1u);
}

TEST(SourceTexels, UntexturedAndFlatFacesKeepT0Pieces) {
    Asset a = twoSquares(0.505);
    // The right square reads one texel (a palette): no area, so a T0 piece; it shows one colour,
    // so it is 8 texels across (its T0 box is 1 unit) rather than at 20 texels per unit.
    for (uint32_t w : {4u, 5u, 6u, 7u}) a.mesh.wedges.uv0[w] = {0.9, 0.1};
    SourceTexelLayout s = sourceTexelLayout(a, {{64, 32}}, t0For(a), 20);
    ASSERT_FALSE(s.layout.empty()) << s.reason;
    EXPECT_EQ(s.islands, 1u);
    EXPECT_EQ(s.layout.chartCount, 2u);
    EXPECT_EQ(s.layout.cornerUV[2][1].x, 8.0);  // position (2, 0) -> T0 (1, 0) x 8

    // Reading along a line of 6 texels (u 0.8 .. 0.9 of 64) over its 0.5 units of T0 width:
    // 12 texels per unit, the texels its UVs cross.
    a.mesh.wedges.uv0[5] = a.mesh.wedges.uv0[6] = {0.8, 0.1};
    s = sourceTexelLayout(a, {{64, 32}}, t0For(a), 20);
    EXPECT_NEAR(s.layout.cornerUV[2][1].x, 12.8, 1e-9);  // T0 (1, 0) x 6.4 / 0.5

    // A line of 6 texels stays within one period of the texture: nothing differs for the
    // coarser levels' cap.
    EXPECT_TRUE(s.capLayout.empty());

    // No texture at all: nothing to copy, and the reason says so.
    a.materials[0].baseColor.texture = -1;
    s = sourceTexelLayout(a, {{64, 32}}, t0For(a), 10);
    EXPECT_TRUE(s.layout.empty());
    EXPECT_FALSE(s.reason.empty());
}

TEST(SourceTexels, FiltersAreKeptOnlyWhenEveryTextureAgrees) {
    Asset a = twoSquares(0.5);
    EXPECT_EQ(sourceFilters(a), std::make_pair(0, 0));
    a.samplers.push_back(Sampler{9729, 9986, 10497, 10497});
    a.textures[0].sampler = 0;
    EXPECT_EQ(sourceFilters(a), std::make_pair(9986, 9729));
    Material other;
    other.emissive.texture = 1;
    a.textures.push_back(Texture{0, -1});  // the default sampler
    a.materials.push_back(other);
    EXPECT_EQ(sourceFilters(a), std::make_pair(0, 0));
}

TEST(SourceTexels, LinesAcrossARepeatingTextureKeepEveryPeriod) {
    // The right square reads a repeating texture along a line: u 0.1 .. 8.1 at v 0.1, eight
    // periods of 64 texels (a grid seen along a ledge). Its 512 texels over 0.5 units of T0 width
    // are 1024 texels per unit, below the level's 2000: the piece takes them all, where a line
    // within one period is held to 64 texels along its longer side (1 unit). The cap layout, which
    // the coarser levels' texel cap counts, holds it to those 64.
    Asset a = twoSquares(0.505);
    for (uint32_t w : {4u, 7u}) a.mesh.wedges.uv0[w] = {0.1, 0.1};
    for (uint32_t w : {5u, 6u}) a.mesh.wedges.uv0[w] = {8.1, 0.1};
    const SourceTexelLayout s = sourceTexelLayout(a, {{64, 32}}, t0For(a), 2000);
    ASSERT_FALSE(s.layout.empty()) << s.reason;
    EXPECT_EQ(s.islands, 1u);
    EXPECT_NEAR(s.layout.cornerUV[2][1].x, 1024.0, 1e-9);  // position (2, 0) -> T0 (1, 0) x 1024
    ASSERT_FALSE(s.capLayout.empty());
    EXPECT_NEAR(s.capLayout.cornerUV[2][1].x, 64.0, 1e-9);
    // The islands are the same charts at the same texels in both.
    EXPECT_EQ(s.capLayout.faceChart, s.layout.faceChart);
    EXPECT_EQ(s.capLayout.cornerUV[0][1].x, s.layout.cornerUV[0][1].x);
}
