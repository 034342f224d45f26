// Levels that keep a repeating material tiling (lib/src/lod/tiled_levels.h): the eligibility
// rule, level UVs across a UV seam, and the tile bake of one period.
#include <gtest/gtest.h>

#include <cmath>

#include "lod/tiled_levels.h"
#include "lodbake/texture/codec.h"

using namespace lodbake;
using namespace lodbake::lod_detail;

namespace {

// A unit square of two triangles wearing one material whose base colour and normal map (64 x 32
// images) repeat 4 x 4 through the same transform, sampled with REPEAT.
Asset tiledSquare() {
    Asset a;
    TriMesh& m = a.mesh;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.wedges.vertex = {0, 1, 2, 3};
    m.wedges.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    m.cornerWedges = m.triangles;
    m.triangleMaterial = {0, 0};
    Material mat;
    mat.baseColor.texture = 0;
    mat.normal.texture = 1;
    for (TextureRef* r : {&mat.baseColor, &mat.normal}) {
        r->transform.present = true;
        r->transform.scale = {4, -4};
    }
    a.materials.push_back(mat);
    a.samplers.push_back(Sampler{});  // REPEAT both ways
    a.textures = {Texture{0, 0}, Texture{1, 0}};
    a.images.resize(2);
    return a;
}

const std::vector<std::pair<int, int>> kSizes{{64, 32}, {32, 32}};

}  // namespace

TEST(TiledLevels, EligibleWhenOneMaterialRepeats) {
    const TilingEligibility e = tilingEligibility(tiledSquare(), kSizes);
    ASSERT_TRUE(e.eligible) << e.reason;
    EXPECT_EQ(e.material, 0);
    EXPECT_EQ(e.uvSet, 0);
    EXPECT_EQ(e.width, 64);  // the largest sides of the material's images
    EXPECT_EQ(e.height, 32);
    EXPECT_DOUBLE_EQ(e.span, 4);
}

TEST(TiledLevels, SpanAloneMakesTexturesRepeat) {
    Asset a = tiledSquare();
    for (TextureRef* r : {&a.materials[0].baseColor, &a.materials[0].normal}) r->transform = TextureTransform{};
    EXPECT_FALSE(tilingEligibility(a, kSizes).eligible) << "UVs within one tile";
    for (Vec2& uv : a.mesh.wedges.uv0) uv = uv * 3;
    const TilingEligibility e = tilingEligibility(a, kSizes);
    EXPECT_TRUE(e.eligible) << e.reason;
    EXPECT_DOUBLE_EQ(e.span, 3);
}

TEST(TiledLevels, NotEligible) {
    {
        Asset a = tiledSquare();
        a.materials.push_back(a.materials[0]);
        a.mesh.triangleMaterial[1] = 1;
        EXPECT_FALSE(tilingEligibility(a, kSizes).eligible) << "two materials";
    }
    {
        Asset a = tiledSquare();
        a.materials[0].normal.transform.scale = {8, -8};
        EXPECT_FALSE(tilingEligibility(a, kSizes).eligible) << "two transforms";
    }
    {
        Asset a = tiledSquare();
        a.materials[0].normal.texCoord = 1;
        a.mesh.wedges.uv1 = a.mesh.wedges.uv0;
        EXPECT_FALSE(tilingEligibility(a, kSizes).eligible) << "two UV sets";
    }
    {
        Asset a = tiledSquare();
        a.samplers[0].wrapT = 33071;  // CLAMP_TO_EDGE
        EXPECT_FALSE(tilingEligibility(a, kSizes).eligible) << "a sampler that clamps";
    }
    {
        Asset a = tiledSquare();
        a.mesh.wedges.color = {{1, 1, 1, 1}, {1, 0, 0, 1}, {1, 1, 1, 1}, {1, 1, 1, 1}};
        EXPECT_FALSE(tilingEligibility(a, kSizes).eligible) << "vertex colours that vary";
        a.mesh.wedges.color[1] = {1, 1, 1, 1};
        EXPECT_TRUE(tilingEligibility(a, kSizes).eligible) << "constant vertex colour";
    }
    {
        Asset a = tiledSquare();
        a.materials[0].baseColor.texture = a.materials[0].normal.texture = -1;
        EXPECT_FALSE(tilingEligibility(a, kSizes).eligible) << "no texture";
    }
}

// Two squares side by side whose UVs meet at a seam: the right square's island is shifted by
// 0.3 in u. A level triangle spanning both squares, descending from a left face, takes its
// corners from the left island.
TEST(TiledLevels, LevelCornersFromTheFacesIsland) {
    Asset a = tiledSquare();
    TriMesh& m = a.mesh;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {1, 4, 5}, {1, 5, 2}};
    // Wedges 0..3 the left island, 4..7 the right one (vertices 1, 4, 5, 2), u shifted by 0.3.
    m.wedges.vertex = {0, 1, 2, 3, 1, 4, 5, 2};
    m.wedges.uv0 = {{0, 1}, {0.5, 1}, {0.5, 0}, {0, 0}, {0.8, 1}, {1.3, 1}, {1.3, 0}, {0.8, 0}};
    m.cornerWedges = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
    m.triangleMaterial.assign(4, 0);
    const TilingEligibility e = tilingEligibility(a, kSizes);
    ASSERT_TRUE(e.eligible) << e.reason;
    // Level: vertex 1 removed; triangles (0, 4, 5) from face 0 and (0, 5, 3) from face 1.
    const std::vector<Tri> level{{0, 4, 5}, {0, 5, 3}};
    const TiledLevelUVs uvs = tiledLevelUVs(m, m.positions, level, {0, 1}, e);
    // Vertex 0 from face 0's own wedge: uv (0, 1) -> tile (0, -4).
    EXPECT_DOUBLE_EQ(uvs.uv[0][0].x, 0);
    EXPECT_DOUBLE_EQ(uvs.uv[0][0].y, -4);
    // Vertex 4 is only in the right island: its one wedge, u 1.3 -> 5.2. The triangle is not
    // stretched beyond 3x (UV area 10.4 over 3D area 1, against the original's 8).
    EXPECT_NEAR(uvs.uv[0][1].x, 5.2, 1e-12);
    EXPECT_EQ(uvs.stretched, 0u);

    // The right island 12 tiles further (u + 2.7): both level triangles reach into it from the
    // left island (UV areas 3.5 and 4 times the original's ratio) and their corners there have
    // no other wedges: both stretched, the whole level's area.
    for (size_t w = 4; w < 8; ++w) m.wedges.uv0[w].x += 2.7;
    const TiledLevelUVs far = tiledLevelUVs(m, m.positions, level, {0, 1}, tilingEligibility(a, kSizes));
    EXPECT_EQ(far.stretched, 2u);
    EXPECT_NEAR(far.stretchedArea, 1, 1e-12);
}

TEST(TiledLevels, TileHoldsOnePeriod) {
    // A 4 x 2 texture, every texel its own colour, repeated 4 x 4: the tile is the image itself.
    Asset a = tiledSquare();
    a.materials[0].normal.texture = -1;
    std::vector<uint8_t> px;
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) px.insert(px.end(), {uint8_t(40 * x + 20), uint8_t(100 * y + 50), uint8_t(200)});
    a.images = {encodePng(px, 4, 2, "texels")};
    a.images.resize(2);
    a.samplers[0].magFilter = 9728;  // NEAREST: each tile texel reads its source texel alone
    a.samplers[0].minFilter = 9728;
    const TilingEligibility e = tilingEligibility(a, {{4, 2}, {0, 0}});
    ASSERT_TRUE(e.eligible) << e.reason;
    const BakeResult tile = bakeTile(a, e, BakeChannels{}, 1);
    ASSERT_EQ(tile.pixels.size(), 4u * 2 * 3);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x)
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(tile.pixels[(size_t(y) * 4 + x) * 3 + c] * 255, px[(size_t(y) * 4 + x) * 3 + c], 1.0) << x << "," << y;
}
