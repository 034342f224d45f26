// Tangent frames (core/tangents.h), the material plan (bake/material_plan.h) and the bake of every
// material channel (bakeMaterial) on a unit quad built in code:
//
//   (0,1) +-----+ (1,1)      uv = (x, 1 - y): u along +x, v down the image = along -y
//         |   / |
//         | /   |
//   (0,0) +-----+ (1,0)
#include <gtest/gtest.h>

#include <cmath>

#include "lodbake/bake/bake.h"
#include "lodbake/bake/material_plan.h"
#include "lodbake/core/tangents.h"
#include "lodbake/texture/codec.h"

namespace lodbake {
namespace {

Asset unitQuad(bool mirrorU = false) {
    Asset a;
    TriMesh& m = a.mesh;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.cornerWedges = m.triangles;
    m.triangleMaterial = {0, 0};
    for (uint32_t v = 0; v < 4; ++v) {
        m.wedges.vertex.push_back(v);
        m.wedges.normal.push_back({0, 0, 1});
        const Vec3& p = m.positions[v];
        m.wedges.uv0.push_back({mirrorU ? 1 - p.x : p.x, 1 - p.y});
    }
    a.materials.push_back(Material{});
    return a;
}

// The bake's UVs of the quad: its own uv0, so every texel maps to the point it shows.
std::vector<std::array<Vec2, 3>> ownUVs(const TriMesh& m) {
    std::vector<std::array<Vec2, 3>> uv(m.triangleCount());
    for (size_t f = 0; f < uv.size(); ++f)
        for (size_t k = 0; k < 3; ++k) uv[f][k] = m.wedges.uv0[m.cornerWedges[f][k]];
    return uv;
}

// The quad itself as the bake's target surface (its frames from computeWedgeTangents).
BakeTarget ownTarget(const TriMesh& m) {
    const std::vector<Vec4> t = computeWedgeTangents(m, m.wedges.uv0);
    BakeTarget target;
    target.uv = ownUVs(m);
    for (size_t f = 0; f < m.triangleCount(); ++f) {
        std::array<Vec3, 3> n;
        std::array<Vec4, 3> tan;
        for (size_t k = 0; k < 3; ++k) {
            n[k] = m.wedges.normal[m.cornerWedges[f][k]];
            tan[k] = t[m.cornerWedges[f][k]];
        }
        target.normal.push_back(n);
        target.tangent.push_back(tan);
    }
    return target;
}

// Adds a constant-colour 8x8 PNG as a texture; returns the texture index.
int addConstantTexture(Asset& a, const uint8_t (&rgb)[3]) {
    std::vector<uint8_t> px(8 * 8 * 3);
    for (size_t i = 0; i < px.size(); ++i) px[i] = rgb[i % 3];
    a.images.push_back(encodePng(px, 8, 8, "constant"));
    a.textures.push_back(Texture{int(a.images.size()) - 1, -1});
    return int(a.textures.size()) - 1;
}

TEST(Tangents, AlongUAndRightHandedForGltfUVs) {
    const Asset a = unitQuad();
    for (const Vec4& t : computeWedgeTangents(a.mesh, a.mesh.wedges.uv0)) {
        EXPECT_NEAR(t.x, 1, 1e-12);
        EXPECT_NEAR(t.y, 0, 1e-12);
        EXPECT_NEAR(t.z, 0, 1e-12);
        EXPECT_EQ(t.w, 1);  // bitangent cross(N, T) = +y = up the image
    }
}

TEST(Tangents, MirroredUVsFlipTheHandedness) {
    const Asset a = unitQuad(true);
    for (const Vec4& t : computeWedgeTangents(a.mesh, a.mesh.wedges.uv0)) {
        EXPECT_NEAR(t.x, -1, 1e-12);
        EXPECT_EQ(t.w, -1);
    }
}

TEST(Tangents, FrameFollowsTheInterpolatedHandednessAndRoundTrips) {
    const Vec3 N{0, 0, 1};
    TangentFrame f;
    // Tangents tilted out of the plane are made orthogonal to N; w > 0: B = cross(N, T) = +y.
    ASSERT_TRUE(tangentFrameAt(N, {Vec4{1, 0, 0.5, 1}, Vec4{1, 0, 0.5, 1}, Vec4{1, 0, 0.5, 1}}, {0.2, 0.3, 0.5}, f));
    EXPECT_NEAR(f.T.x, 1, 1e-12);
    EXPECT_NEAR(f.T.z, 0, 1e-12);
    EXPECT_NEAR(f.B.y, 1, 1e-12);
    // Mixed handedness: the sign of the interpolated w decides, whichever corner comes first.
    ASSERT_TRUE(tangentFrameAt(N, {Vec4{1, 0, 0, 1}, Vec4{1, 0, 0, -1}, Vec4{1, 0, 0, -1}}, {0.6, 0.2, 0.2}, f));
    EXPECT_NEAR(f.B.y, 1, 1e-12);
    ASSERT_TRUE(tangentFrameAt(N, {Vec4{1, 0, 0, 1}, Vec4{1, 0, 0, -1}, Vec4{1, 0, 0, -1}}, {0.2, 0.4, 0.4}, f));
    EXPECT_NEAR(f.B.y, -1, 1e-12);
    const Vec3 v = normalize(Vec3{0.3, -0.2, 0.9});
    const Vec3 back = f.toWorld(f.toTangent(v));
    EXPECT_NEAR(back.x, v.x, 1e-12);
    EXPECT_NEAR(back.y, v.y, 1e-12);
    EXPECT_NEAR(back.z, v.z, 1e-12);
    // A tangent along N leaves no frame.
    EXPECT_FALSE(tangentFrameAt(N, {Vec4{0, 0, 1, 1}, Vec4{0, 0, 1, 1}, Vec4{0, 0, 1, 1}}, {0.2, 0.3, 0.5}, f));
}

TEST(MaterialPlan, ConstantChannelsAreFactors) {
    Asset a = unitQuad();
    a.materials[0].metallicFactor = 0.25;
    a.materials[0].roughnessFactor = 0.5;
    const MaterialPlan p = planMaterial(a);
    EXPECT_FALSE(p.baseColorTexture);
    EXPECT_FALSE(p.ormTexture());
    EXPECT_FALSE(p.emissiveTexture);
    EXPECT_FALSE(p.normalTexture);
    EXPECT_EQ(p.metallicFactor, 0.25);
    EXPECT_EQ(p.roughnessFactor, 0.5);
}

TEST(MaterialPlan, MixedSidednessGetsBackFaces) {
    Asset a = unitQuad();
    a.materials.push_back(Material{});
    a.materials[1].doubleSided = true;
    a.mesh.triangleMaterial = {0, 1};
    const MaterialPlan p = planMaterial(a);
    EXPECT_FALSE(p.doubleSided);
    EXPECT_TRUE(p.backFaces);
    EXPECT_EQ(p.warnings.size(), 1u);
}

// A normal map baked from the quad onto the quad itself gives back the map's normal.
TEST(BakeMaterial, NormalMapRoundTripsThroughTheSameFrame) {
    Asset a = unitQuad();
    const uint8_t tilted[3] = {166, 140, 233};  // (0.30, 0.10, 0.83) before normalising
    a.materials[0].normal.texture = addConstantTexture(a, tilted);
    BakeSources sources(a);
    BakeOptions o;
    o.size = 16;
    o.channels.normal = true;
    const BakeTarget target = ownTarget(a.mesh);
    const BakeResult r = bakeMaterial(sources, ownUVs(a.mesh), o, {}, &target);
    ASSERT_EQ(r.normal.size(), size_t(16 * 16 * 3));
    const Vec3 want = normalize(Vec3{166 / 127.5 - 1, 140 / 127.5 - 1, 233 / 127.5 - 1});
    for (size_t i = 0; i < 16 * 16; ++i)
        for (size_t c = 0; c < 3; ++c) ASSERT_NEAR(r.normal[i * 3 + c], want[int(c)] * 0.5 + 0.5, 2.5 / 255) << "texel " << i;
}

TEST(BakeMaterial, OrmAndEmissiveFollowFactorsAndTextures) {
    Asset a = unitQuad();
    const uint8_t mr[3] = {0, 128, 255};  // roughness 0.5, metallic 1
    a.materials[0].metallicRoughness.texture = addConstantTexture(a, mr);
    a.materials[0].roughnessFactor = 0.5;
    a.materials[0].emissiveFactor = {1, 0.5, 0};
    a.materials[0].emissiveStrength = 4;
    BakeSources sources(a);
    BakeOptions o;
    o.size = 8;
    o.channels.orm = o.channels.emissive = true;
    const BakeResult r = bakeMaterial(sources, ownUVs(a.mesh), o);
    EXPECT_NEAR(r.emissiveScale, 4, 1e-9);  // the peak linear value, written as emissive strength
    for (size_t i = 0; i < 8 * 8; ++i) {
        ASSERT_NEAR(r.orm[i * 3 + 0], 1, 1e-6);              // no occlusion map
        ASSERT_NEAR(r.orm[i * 3 + 1], 0.25, 1.0 / 255);      // 0.5 x 0.5
        ASSERT_NEAR(r.orm[i * 3 + 2], 1, 1.0 / 255);
        ASSERT_NEAR(r.emissive[i * 3 + 0], 1, 1e-6);         // 4 / 4, sRGB 1
        ASSERT_NEAR(r.emissive[i * 3 + 2], 0, 1e-6);
    }
}

// Adds an 8x8 PNG whose texels vary (a different value per texel and channel) as a texture.
int addVaryingTexture(Asset& a, int seed) {
    std::vector<uint8_t> px(8 * 8 * 3);
    for (size_t i = 0; i < px.size(); ++i) px[i] = uint8_t((i * 37 + size_t(seed) * 91) % 256);
    a.images.push_back(encodePng(px, 8, 8, "varying"));
    a.textures.push_back(Texture{int(a.images.size()) - 1, -1});
    return int(a.textures.size()) - 1;
}

// The quad on the upper-left part of a larger page, leaving texels for the gap fill; every
// channel textured with varying texels.
struct PartialPage {
    Asset asset;
    std::vector<std::array<Vec2, 3>> uv;
    BakeTarget target;
    PartialPage() : asset(unitQuad()) {
        Material& m = asset.materials[0];
        m.baseColor.texture = addVaryingTexture(asset, 1);
        m.metallicRoughness.texture = addVaryingTexture(asset, 2);
        m.emissive.texture = addVaryingTexture(asset, 3);
        m.normal.texture = addVaryingTexture(asset, 4);
        m.emissiveFactor = {1, 1, 1};
        m.alphaMode = AlphaMode::Blend;
        m.baseColorFactor = {1, 1, 1, 0.5};
        uv = ownUVs(asset.mesh);
        for (auto& t : uv)
            for (Vec2& p : t) p = {0.1 + 0.5 * p.x, 0.2 + 0.6 * p.y};
        target = ownTarget(asset.mesh);
        target.uv = uv;
    }
};

// Rows are shaded on any number of threads and the gap fill runs once for every channel: each
// channel comes out the same for 1 and 2 threads, and the same as when it is baked alone.
TEST(BakeMaterial, ChannelsDoNotDependOnThreadsOrOnEachOther) {
    const PartialPage page;
    BakeSources sources(page.asset);
    BakeOptions o;
    o.size = 40;
    o.width = 36;
    o.channels.alpha = o.channels.orm = o.channels.emissive = o.channels.normal = true;
    o.threads = 1;
    const BakeResult one = bakeMaterial(sources, page.uv, o, {}, &page.target);
    o.threads = 2;
    const BakeResult two = bakeMaterial(sources, page.uv, o, {}, &page.target);
    ASSERT_GT(one.coveredTexels, 0u);
    ASSERT_LT(one.coveredTexels, size_t(36 * 40));  // some texels are gap-filled
    EXPECT_EQ(one.pixels, two.pixels);
    EXPECT_EQ(one.alpha, two.alpha);
    EXPECT_EQ(one.orm, two.orm);
    EXPECT_EQ(one.emissive, two.emissive);
    EXPECT_EQ(one.normal, two.normal);
    const auto alone = [&](void (*pick)(BakeChannels&)) {
        BakeOptions a = o;
        a.channels = BakeChannels{};
        pick(a.channels);
        return bakeMaterial(sources, page.uv, a, {}, &page.target);
    };
    EXPECT_EQ(alone([](BakeChannels&) {}).pixels, one.pixels);
    EXPECT_EQ(alone([](BakeChannels& c) { c.alpha = true; }).alpha, one.alpha);
    EXPECT_EQ(alone([](BakeChannels& c) { c.orm = true; }).orm, one.orm);
    EXPECT_EQ(alone([](BakeChannels& c) { c.emissive = true; }).emissive, one.emissive);
    EXPECT_EQ(alone([](BakeChannels& c) { c.normal = true; }).normal, one.normal);
}

// A chart copying source texels at a whole-texel offset (a source-texel page): with extendCharts
// its dilated ring holds the texels next to the copied ones in the source, exactly what a chart
// covering one more texel on every side shows there; without, the ring repeats the border.
TEST(BakeMaterial, ExtendedChartsContinueTheirCopyIntoTheRing) {
    auto quadOver = [](double first, double texels) {  // the quad's uv0 over source texels [first, first + texels)
        Asset a = unitQuad();
        for (uint32_t v = 0; v < 4; ++v) {
            const Vec3& p = a.mesh.positions[v];
            a.mesh.wedges.uv0[v] = {(first + texels * p.x) / 8, (first + texels * (1 - p.y)) / 8};
        }
        a.materials[0].baseColor.texture = addVaryingTexture(a, 5);
        return a;
    };
    const int size = 24, shift = 8;  // page texel = source texel + shift
    auto pageUVs = [&](const Asset& a) {
        std::vector<std::array<Vec2, 3>> uv = ownUVs(a.mesh);
        for (auto& t : uv)
            for (Vec2& p : t) p = {(p.x * 8 + shift) / size, (p.y * 8 + shift) / size};
        return uv;
    };
    const Asset inner = quadOver(2, 4), outer = quadOver(1, 6);
    BakeOptions o;
    o.size = size;
    o.fillGaps = false;
    o.encodePng = false;
    const BakeResult whole = bakeBaseColor(outer, pageUVs(outer), o);
    o.extendCharts = true;
    const BakeResult extended = bakeBaseColor(inner, pageUVs(inner), o);
    o.extendCharts = false;
    const BakeResult clamped = bakeBaseColor(inner, pageUVs(inner), o);
    int ringDiffers = 0;
    for (int y = 1 + shift; y < 7 + shift; ++y)
        for (int x = 1 + shift; x < 7 + shift; ++x)
            for (int c = 0; c < 3; ++c) {
                const size_t i = (size_t(y) * size + size_t(x)) * 3 + size_t(c);
                ASSERT_NEAR(extended.pixels[i], whole.pixels[i], 1e-5) << x << "," << y;
                ringDiffers += std::abs(clamped.pixels[i] - whole.pixels[i]) > 1e-3;
            }
    EXPECT_GT(ringDiffers, 0);
}

}  // namespace
}  // namespace lodbake
