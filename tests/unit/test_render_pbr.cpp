// Unit tests of the rasteriser's Pbr mode (render.h) on a camera-facing quad and a sphere built in
// code, with textures encoded as PNG and decoded by prepareRenderScene.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "lodbake/metrics/compare.h"
#include "lodbake/metrics/image_metrics.h"
#include "lodbake/metrics/render.h"
#include "lodbake/texture/codec.h"
#include "lodbake/texture/color_space.h"
#include "synthetic_meshes.h"

using namespace lodbake;

namespace {

// The square [-1,1]^2 at z = 0 facing +z, wedge normals +z, uv0 with u along +x and v down
// (v = 0 at y = 1), as glTF stores it; material 0.
TriMesh facingQuad() {
    TriMesh m;
    m.positions = {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.cornerWedges = m.triangles;
    m.wedges.vertex = {0, 1, 2, 3};
    m.wedges.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    m.wedges.normal.assign(4, Vec3{0, 0, 1});
    m.triangleMaterial = {0, 0};
    return m;
}

// sphere(3) with its unit normals as wedge normals (uv0 = xy).
TriMesh smoothSphere() {
    TriMesh m = test::sphere(3);
    for (uint32_t v : m.wedges.vertex) m.wedges.normal.push_back(normalize(m.positions[v]));
    return m;
}

// Camera on +z looking at the quad's centre, +y up: camera space = world space.
Camera frontCamera() {
    Camera c;
    c.eye = {0, 0, 3};
    c.target = {0, 0, 0};
    return c;
}

// An asset holding `mesh` and one dielectric grey material.
Asset assetOf(const TriMesh& mesh) {
    Asset a;
    a.mesh = mesh;
    Material m;
    m.baseColorFactor = {0.5, 0.5, 0.5, 1};
    m.metallicFactor = 0;
    m.roughnessFactor = 0.8;
    a.materials.push_back(m);
    return a;
}

// Adds a 4x4 PNG of one 8-bit RGB value and a texture on it; returns the texture index.
int addFlatTexture(Asset& a, uint8_t r, uint8_t g, uint8_t b) {
    std::vector<uint8_t> rgb;
    for (int i = 0; i < 16; ++i) rgb.insert(rgb.end(), {r, g, b});
    a.images.push_back(encodePng(rgb, 4, 4));
    a.textures.push_back(Texture{static_cast<int>(a.images.size()) - 1, -1});
    return static_cast<int>(a.textures.size()) - 1;
}

// A tangent-space unit normal encoded as a normal-map texel.
uint8_t encodeNormal(double c) { return static_cast<uint8_t>(std::lround((c + 1) / 2 * 255)); }

int addNormalMap(Asset& a, Vec3 n) {
    n = normalize(n);
    return addFlatTexture(a, encodeNormal(n.x), encodeNormal(n.y), encodeNormal(n.z));
}

Rendering renderPbr(const Asset& a, const Camera& c = frontCamera()) {
    RenderScene s = prepareRenderScene(a, a.mesh);
    EXPECT_TRUE(s.warnings.empty());
    return render(s, c, RenderOptions{48, 48, RenderMode::Pbr});
}

// Mean sRGB value over covered pixels and channels.
double meanCovered(const Rendering& r) {
    double sum = 0;
    size_t n = 0;
    for (size_t i = 0; i < r.coverage.size(); ++i)
        if (r.coverage[i]) {
            sum += r.rgb[3 * i] + r.rgb[3 * i + 1] + r.rgb[3 * i + 2];
            n += 3;
        }
    EXPECT_GT(n, 0u);
    return n ? sum / static_cast<double>(n) : 0;
}

// The key light comes from the upper left, in front: (-0.5, 0.6, 0.62) in camera space.
const Vec3 kTowardsKey{-0.5, 0.6, 0.62};

}  // namespace

TEST(RenderPbr, NormalMapTiltedTowardsTheKeyLightIsBrighter) {
    Asset flat = assetOf(facingQuad());
    Asset towards = flat, away = flat;
    towards.materials[0].normal.texture = addNormalMap(towards, kTowardsKey);
    // Mirrored in y: only right if +Y of the map points up the image (glTF convention).
    away.materials[0].normal.texture = addNormalMap(away, {-0.5, -0.6, 0.62});
    const double lFlat = meanCovered(renderPbr(flat));
    const double lTowards = meanCovered(renderPbr(towards));
    const double lAway = meanCovered(renderPbr(away));
    EXPECT_GT(lTowards, lFlat + 0.03);
    EXPECT_LT(lAway, lTowards - 0.03);

    // The mesh's own tangents (+x, right-handed) give the same picture as computed ones.
    Asset withTangents = towards;
    withTangents.mesh.wedges.tangent.assign(4, Vec4{1, 0, 0, 1});
    EXPECT_NEAR(meanCovered(renderPbr(withTangents)), lTowards, 1e-3);

    // A flat map (0, 0, 1) changes nothing.
    Asset neutral = flat;
    neutral.materials[0].normal.texture = addFlatTexture(neutral, 128, 128, 255);
    EXPECT_NEAR(meanCovered(renderPbr(neutral)), lFlat, 0.01);
}

TEST(RenderPbr, MetallicOneDiffersFromZero) {
    Asset dielectric = assetOf(facingQuad());
    dielectric.materials[0].baseColorFactor = {0.8, 0.3, 0.2, 1};
    dielectric.materials[0].roughnessFactor = 0.5;
    Asset metal = dielectric;
    metal.materials[0].metallicFactor = 1;
    const Rendering a = renderPbr(dielectric), b = renderPbr(metal);
    const ImageMetrics m = compareImages(a, b);
    EXPECT_EQ(m.iou, 1.0);
    EXPECT_LT(m.psnr, 30);

    // Metallic through the metallicRoughness texture (B channel, linear): the same as the factor.
    Asset textured = dielectric;
    textured.materials[0].metallicFactor = 1;
    textured.materials[0].metallicRoughness.texture = addFlatTexture(textured, 0, 255, 255);
    EXPECT_GT(compareImages(renderPbr(textured), b).psnr, 60);
}

TEST(RenderPbr, DataTexturesAreNotSrgbDecoded) {
    // Roughness 0.5 from a texel of 128 (linear 0.502; sRGB-decoded it would be 0.216), on a
    // sphere, whose highlight shows the roughness.
    Asset byFactor = assetOf(smoothSphere());
    byFactor.materials[0].roughnessFactor = 128 / 255.0;
    Asset byTexture = byFactor;
    byTexture.materials[0].roughnessFactor = 1;
    byTexture.materials[0].metallicRoughness.texture = addFlatTexture(byTexture, 0, 128, 0);
    Asset srgbDecoded = byFactor;
    srgbDecoded.materials[0].roughnessFactor = srgbToLinear(128 / 255.0);
    const Rendering expected = renderPbr(byFactor);
    EXPECT_GT(compareImages(expected, renderPbr(byTexture)).psnr, 60);
    EXPECT_LT(compareImages(expected, renderPbr(srgbDecoded)).psnr, 45);
}

TEST(RenderPbr, EmissiveIsBrightWithoutReflectedLight) {
    Asset black = assetOf(facingQuad());
    black.materials[0].baseColorFactor = {0, 0, 0, 1};
    black.materials[0].roughnessFactor = 1;
    EXPECT_LT(meanCovered(renderPbr(black)), 0.3);

    Asset glowing = black;
    glowing.materials[0].emissiveFactor = {0.25, 0.25, 0.25};
    glowing.materials[0].emissiveStrength = 4;  // KHR_materials_emissive_strength
    EXPECT_GT(meanCovered(renderPbr(glowing)), 0.99);

    // Emissive texture (sRGB) times the factor.
    Asset textured = black;
    textured.materials[0].emissiveFactor = {1, 1, 1};
    textured.materials[0].emissive.texture = addFlatTexture(textured, 255, 255, 255);
    EXPECT_GT(meanCovered(renderPbr(textured)), 0.99);
}

TEST(RenderPbr, OcclusionDarkensTheAmbientOnly) {
    Asset open = assetOf(facingQuad());
    Asset occluded = open;
    occluded.materials[0].occlusion.texture = addFlatTexture(occluded, 0, 255, 255);
    const double lOpen = meanCovered(renderPbr(open)), lOccluded = meanCovered(renderPbr(occluded));
    EXPECT_LT(lOccluded, lOpen);
    EXPECT_GT(lOccluded, 0.2);  // direct light remains
    occluded.materials[0].occlusion.scale = 0;  // strength 0: no effect
    EXPECT_NEAR(meanCovered(renderPbr(occluded)), lOpen, 1e-6);
}

TEST(RenderPbr, UnlitShowsTheBaseColour) {
    Asset a = assetOf(facingQuad());
    a.materials[0].unlit = true;
    RenderScene s = prepareRenderScene(a, a.mesh);
    const Rendering pbr = render(s, frontCamera(), RenderOptions{48, 48, RenderMode::Pbr});
    const Rendering base = render(s, frontCamera(), RenderOptions{48, 48, RenderMode::BaseColor});
    EXPECT_EQ(pbr.rgb, base.rgb);
}

TEST(RenderPbr, DoubleSidedBackFaceIsLitLikeTheFront) {
    Asset a = assetOf(facingQuad());
    a.materials[0].doubleSided = true;
    Camera back = frontCamera();
    back.eye = {0, 0, -3};
    const double front = meanCovered(renderPbr(a)), behind = meanCovered(renderPbr(a, back));
    EXPECT_NEAR(behind, front, 1e-6);
}

TEST(RenderPbr, IdenticalAssetsGiveTheCap) {
    Asset a = assetOf(smoothSphere());
    a.materials[0].normal.texture = addNormalMap(a, kTowardsKey);
    a.materials[0].occlusion.texture = addFlatTexture(a, 200, 200, 200);
    Asset b = a;
    CompareOptions o;
    o.geometry = false;
    o.views = 4;
    o.resolution = 48;
    const CompareResult r = compareAssets(a, a.mesh, b, b.mesh, o);
    EXPECT_EQ(r.pbr.psnr, kMaxPsnr);
    EXPECT_EQ(r.pbr.iou, 1.0);
    EXPECT_EQ(r.pbrPerView.size(), 4u);
    EXPECT_TRUE(r.warnings.empty());
}

// A level of odd side filters each texel's whole footprint: no source texel is dropped, so every
// level keeps the mean of the image (a dropped column would shift the rest by up to half a texel).
TEST(RenderPbr, OddSidedMipLevelsKeepEveryTexel) {
    Asset a = assetOf(facingQuad());
    std::vector<uint8_t> rgb;
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 5; ++x) rgb.insert(rgb.end(), {uint8_t(40 * x + 60 * y), uint8_t(200 - 30 * x), uint8_t(90 * y)});
    a.images.push_back(encodePng(rgb, 5, 3));
    a.textures.push_back(Texture{0, -1});
    a.materials[0].metallicRoughness.texture = 0;
    const RenderScene s = prepareRenderScene(a, a.mesh);
    ASSERT_EQ(s.dataImages.size(), 1u);
    const MipImage& mip = s.dataImages[0];
    ASSERT_EQ(mip.levels.size(), 3u);  // 5x3, 2x1, 1x1
    EXPECT_EQ(mip.levels[1].width, 2);
    EXPECT_EQ(mip.levels[1].height, 1);
    auto mean = [](const MipImage::Level& l, int c) {
        double sum = 0;
        for (int i = 0; i < l.width * l.height; ++i) sum += l.rgba[size_t(i) * 4 + size_t(c)];
        return sum / (l.width * l.height);
    };
    for (int c = 0; c < 3; ++c)
        for (const MipImage::Level& l : mip.levels) EXPECT_NEAR(mean(l, c), mean(mip.levels[0], c), 1e-5);
}

// KHR_materials_clearcoat: a coat reflects light of its own (a black base shows it), its texture's
// R scales it (R = 0: no coat), and towards grazing angles its Fresnel hides the base beneath.
TEST(RenderPbr, ClearcoatReflectsAndHidesTheBaseAtGrazingAngles) {
    Asset black = assetOf(facingQuad());
    black.materials[0].baseColorFactor = {0, 0, 0, 1};
    black.materials[0].roughnessFactor = 1;
    auto coated = [](Asset a) {
        ClearcoatExtension& cc = a.materials[0].ext.clearcoat;
        cc.present = true;
        cc.factor = 1;
        cc.roughnessFactor = 0.03;
        return a;
    };
    EXPECT_GT(meanCovered(renderPbr(coated(black))), meanCovered(renderPbr(black)) + 0.02);

    Asset bare = coated(black);
    bare.materials[0].ext.clearcoat.texture.texture = addFlatTexture(bare, 0, 255, 255);
    EXPECT_GT(compareImages(renderPbr(bare), renderPbr(black)).psnr, 90);

    Asset white = black;
    white.materials[0].baseColorFactor = {1, 1, 1, 1};
    Camera grazing = frontCamera();
    grazing.eye = {0, -3 * std::sin(1.4), 3 * std::cos(1.4)};  // 80 degrees from the normal
    const double spread = meanCovered(renderPbr(white, grazing)) - meanCovered(renderPbr(black, grazing));
    const double coatedSpread =
        meanCovered(renderPbr(coated(white), grazing)) - meanCovered(renderPbr(coated(black), grazing));
    EXPECT_GT(spread, 0.05);
    EXPECT_LT(coatedSpread, 0.9 * spread);
}
