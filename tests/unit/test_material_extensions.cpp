// KHR_materials_* extensions: reading (every field, texture transforms, extensionsRequired), the
// intermediate files' round trip, the chain's plan (union, neutral values, uniform properties)
// and the bake of the extension channels, on one or two triangles built in code:
//
//   (0,1) +-----+ (1,1)     triangle 0 = (0,0) (1,0) (1,1), material 0
//         | 1 / |           triangle 1 = (0,0) (1,1) (0,1), material 1
//         | / 0 |           uv = (x, 1 - y)
//   (0,0) +-----+ (1,0)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "lodbake/bake/bake.h"
#include "lodbake/bake/draw_split.h"
#include "lodbake/bake/material_plan.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/texture/codec.h"
#include "lodbake/texture/color_space.h"
#include "unit/gltf_test_files.h"

namespace lodbake {
namespace {

using json = nlohmann::json;
using namespace lodbake::testing;

constexpr int kF32 = 5126;

// Every field of every extension lodbake reads, with values unlike the defaults.
json allExtensions() {
    json tt = {{"offset", {0.25, 0.5}}, {"rotation", 0.3}, {"scale", {2, 4}}, {"texCoord", 1}};
    json e;
    e["KHR_materials_clearcoat"] = {{"clearcoatFactor", 0.9}, {"clearcoatTexture", {{"index", 0}}},
                                    {"clearcoatRoughnessFactor", 0.2}, {"clearcoatRoughnessTexture", {{"index", 1}, {"texCoord", 1}}},
                                    {"clearcoatNormalTexture", {{"index", 2}, {"scale", 0.5}}}};
    e["KHR_materials_sheen"] = {{"sheenColorFactor", {0.1, 0.2, 0.3}}, {"sheenColorTexture", {{"index", 0}}},
                                {"sheenRoughnessFactor", 0.7}, {"sheenRoughnessTexture", {{"index", 1}}}};
    e["KHR_materials_transmission"] = {{"transmissionFactor", 0.8}, {"transmissionTexture", {{"index", 0}}}};
    e["KHR_materials_volume"] = {{"thicknessFactor", 0.25}, {"thicknessTexture", {{"index", 1}}},
                                 {"attenuationDistance", 2.5}, {"attenuationColor", {0.9, 0.8, 0.7}}};
    e["KHR_materials_specular"] = {{"specularFactor", 0.6}, {"specularTexture", {{"index", 0}}},
                                   {"specularColorFactor", {1.5, 1, 0.5}}, {"specularColorTexture", {{"index", 1}}}};
    e["KHR_materials_ior"] = {{"ior", 1.33}};
    e["KHR_materials_iridescence"] = {{"iridescenceFactor", 0.4}, {"iridescenceTexture", {{"index", 0}}},
                                      {"iridescenceIor", 1.8}, {"iridescenceThicknessMinimum", 150},
                                      {"iridescenceThicknessMaximum", 600}, {"iridescenceThicknessTexture", {{"index", 1}}}};
    e["KHR_materials_anisotropy"] = {{"anisotropyStrength", 0.5}, {"anisotropyRotation", 1.2}, {"anisotropyTexture", {{"index", 2}}}};
    e["KHR_materials_dispersion"] = {{"dispersion", 0.1}};
    e["KHR_materials_diffuse_transmission"] = {{"diffuseTransmissionFactor", 0.35}, {"diffuseTransmissionTexture", {{"index", 0}}},
                                               {"diffuseTransmissionColorFactor", {0.2, 0.4, 0.6}},
                                               {"diffuseTransmissionColorTexture", {{"index", 1}, {"extensions", {{"KHR_texture_transform", tt}}}}}};
    return e;
}

// One triangle on material 0 whose extensions are `extensions`, three textures on one image.
TestGltf triangleWith(const json& extensions) {
    TestGltf g;
    const int pa = g.add(unitTrianglePositions(), kF32, "VEC3");
    const std::vector<float> uv = {0, 1, 1, 1, 0, 0};
    const int ua = g.add(uv, kF32, "VEC2"), ub = g.add(uv, kF32, "VEC2");
    json mat = {{"name", "all"}, {"extensions", extensions}};
    g.j["materials"] = json::array({mat});
    g.j["textures"] = json::array({json{{"source", 0}}, json{{"source", 0}}, json{{"source", 0}}});
    g.j["images"] = json::array({json{{"uri", "missing.png"}}});
    meshNode(g, {prim({{"POSITION", pa}, {"TEXCOORD_0", ua}, {"TEXCOORD_1", ub}}, -1, -1, 0)});
    return g;
}

Asset readLenient(const std::string& path) {
    ReadOptions ro;
    ro.requireImageData = false;
    return readGltf(path, ro);
}

bool anyWarning(const Asset& a, const std::string& needle) {
    for (const std::string& w : a.warnings)
        if (w.find(needle) != std::string::npos) return true;
    return false;
}

TEST(MaterialExtensions, EveryFieldIsRead) {
    TestGltf g = triangleWith(allExtensions());
    const Asset a = readLenient(g.writeGltf(tempDir("ext_read"), "all"));
    ASSERT_EQ(a.materials.size(), 1u);
    const MaterialExtensions& e = a.materials[0].ext;
    EXPECT_TRUE(e.clearcoat.present);
    EXPECT_DOUBLE_EQ(e.clearcoat.factor, 0.9);
    EXPECT_EQ(e.clearcoat.texture.texture, 0);
    EXPECT_DOUBLE_EQ(e.clearcoat.roughnessFactor, 0.2);
    EXPECT_EQ(e.clearcoat.roughnessTexture.texture, 1);
    EXPECT_EQ(e.clearcoat.roughnessTexture.texCoord, 1);
    EXPECT_EQ(e.clearcoat.normalTexture.texture, 2);
    EXPECT_DOUBLE_EQ(e.clearcoat.normalTexture.scale, 0.5);
    EXPECT_DOUBLE_EQ(e.sheen.colorFactor.z, 0.3);
    EXPECT_EQ(e.sheen.roughnessTexture.texture, 1);
    EXPECT_DOUBLE_EQ(e.transmission.factor, 0.8);
    EXPECT_DOUBLE_EQ(e.volume.thicknessFactor, 0.25);
    EXPECT_DOUBLE_EQ(e.volume.attenuationDistance, 2.5);
    EXPECT_DOUBLE_EQ(e.volume.attenuationColor.y, 0.8);
    EXPECT_DOUBLE_EQ(e.specular.factor, 0.6);
    EXPECT_DOUBLE_EQ(e.specular.colorFactor.x, 1.5);
    EXPECT_DOUBLE_EQ(e.ior.ior, 1.33);
    EXPECT_DOUBLE_EQ(e.iridescence.ior, 1.8);
    EXPECT_DOUBLE_EQ(e.iridescence.thicknessMinimum, 150);
    EXPECT_DOUBLE_EQ(e.iridescence.thicknessMaximum, 600);
    EXPECT_EQ(e.iridescence.thicknessTexture.texture, 1);
    EXPECT_DOUBLE_EQ(e.anisotropy.rotation, 1.2);
    EXPECT_DOUBLE_EQ(e.dispersion.dispersion, 0.1);
    EXPECT_DOUBLE_EQ(e.diffuseTransmission.colorFactor.y, 0.4);
    const TextureRef& t = e.diffuseTransmission.colorTexture;
    EXPECT_TRUE(t.transform.present);
    EXPECT_DOUBLE_EQ(t.transform.offset.y, 0.5);
    EXPECT_DOUBLE_EQ(t.transform.rotation, 0.3);
    EXPECT_EQ(t.transform.texCoord, 1);
    EXPECT_FALSE(anyWarning(a, "is not carried"));
}

TEST(MaterialExtensions, AbsentExtensionsKeepDefaultsAndUnknownOnesWarn) {
    json e;
    e["KHR_materials_volume"] = json::object();
    e["VENDOR_materials_glitter"] = json::object();
    TestGltf g = triangleWith(e);
    const Asset a = readLenient(g.writeGltf(tempDir("ext_defaults"), "d"));
    const MaterialExtensions& x = a.materials[0].ext;
    EXPECT_TRUE(x.volume.present);
    EXPECT_TRUE(std::isinf(x.volume.attenuationDistance));
    EXPECT_FALSE(x.clearcoat.present);
    EXPECT_DOUBLE_EQ(x.specular.factor, 1);
    EXPECT_DOUBLE_EQ(x.iridescence.thicknessMaximum, 400);
    EXPECT_TRUE(anyWarning(a, "VENDOR_materials_glitter is not carried"));
    EXPECT_FALSE(anyWarning(a, "KHR_materials_volume"));
}

TEST(MaterialExtensions, RequiredMaterialExtensionsAreAccepted) {
    TestGltf g = triangleWith(allExtensions());
    g.j["extensionsRequired"] = {"KHR_materials_clearcoat", "KHR_materials_iridescence", "KHR_materials_pbrSpecularGlossiness",
                                 "KHR_materials_sheen", "KHR_materials_transmission", "KHR_materials_volume"};
    EXPECT_NO_THROW(readLenient(g.writeGltf(tempDir("ext_required"), "r")));
}

// Written then read: the same values (the second write is byte-identical to the first).
TEST(MaterialExtensions, IntermediateFilesRoundTripExactly) {
    TestGltf g = triangleWith(allExtensions());
    const auto dir = tempDir("ext_roundtrip");
    const Asset a = readLenient(g.writeGltf(dir, "all"));
    WriteOptions wo;
    wo.embedImages = false;
    writeGltf((dir / "one.gltf").string(), a, nullptr, wo);
    const Asset b = readLenient((dir / "one.gltf").string());
    writeGltf((dir / "two.gltf").string(), b, nullptr, wo);
    const json one = json::parse(readBytes(dir / "one.gltf")), two = json::parse(readBytes(dir / "two.gltf"));
    EXPECT_EQ(one["materials"], two["materials"]);
    EXPECT_EQ(json::parse(readBytes(dir / "all.gltf"))["materials"][0]["extensions"], one["materials"][0]["extensions"]);
    for (const char* name : {"KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_diffuse_transmission",
                             "KHR_texture_transform"})
        EXPECT_NE(std::find(one["extensionsUsed"].begin(), one["extensionsUsed"].end(), name), one["extensionsUsed"].end()) << name;
    const MaterialExtensions &x = a.materials[0].ext, &y = b.materials[0].ext;
    EXPECT_EQ(x.iridescence.thicknessMaximum, y.iridescence.thicknessMaximum);
    EXPECT_EQ(x.volume.attenuationDistance, y.volume.attenuationDistance);
    EXPECT_EQ(x.diffuseTransmission.colorTexture.transform.scale.y, y.diffuseTransmission.colorTexture.transform.scale.y);
}

// RGBA PNGs hold straight alpha (glTF): colour is neither divided by alpha on encoding nor
// multiplied by it on decoding (a sheen colour beside its roughness in A stays the colour).
TEST(MaterialExtensions, RgbaPngKeepsStraightAlpha) {
    const std::vector<float> px = {56 / 255.f, 107 / 255.f, 1, 54 / 255.f, 1, 0.5f, 0, 0};
    const Image png = encodeImage(px, 2, 1, EncodeOptions{ImageFormat::Png, 90, 4, true});
    DecodedImage d;
    std::string error;
    ASSERT_TRUE(decodeImage(png, d, error, DecodeDepth::KeepEightBit)) << error;
    ASSERT_EQ(d.bytes.size(), 8u);
    const std::vector<uint8_t> expected = {56, 107, 255, 54, 255, 128, 0, 0};
    EXPECT_EQ(d.bytes, expected);
}

// Two triangles of areas 1/2 each (the unit square) on two materials.
Asset twoMaterials(const Material& m0, const Material& m1) {
    Asset a;
    TriMesh& m = a.mesh;
    m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.triangleMaterial = {0, 1};
    // Separate wedges per triangle so each carries its own UVs.
    for (uint32_t f = 0; f < 2; ++f)
        for (uint32_t v : m.triangles[f]) {
            m.wedges.vertex.push_back(v);
            m.wedges.normal.push_back({0, 0, 1});
            m.wedges.uv0.push_back({m.positions[v].x, 1 - m.positions[v].y});
        }
    m.cornerWedges = {{0, 1, 2}, {3, 4, 5}};
    a.materials = {m0, m1};
    return a;
}

TEST(MaterialPlanExtensions, UnionNeutralValuesAndUniformProperties) {
    Material coat, plain;
    coat.ext.clearcoat.present = true;
    coat.ext.clearcoat.factor = 1;
    coat.ext.ior = {true, 1.5};
    coat.ext.sheen.present = true;
    coat.ext.sheen.colorFactor = {0.5, 0.5, 0.5};
    plain.ext.ior = {true, 2.0};
    plain.ext.sheen.present = true;
    plain.ext.sheen.colorFactor = {0.5, 0.5, 0.5};
    const MaterialPlan p = planMaterial(twoMaterials(coat, plain));
    const ExtensionPlan& x = p.ext;
    EXPECT_TRUE(x.factors.clearcoat.present);
    EXPECT_TRUE(x.clearcoatTexture);              // 1 on one half, the neutral 0 on the other
    EXPECT_FALSE(x.clearcoatRoughnessTexture);    // 0 on both
    EXPECT_DOUBLE_EQ(x.factors.clearcoat.roughnessFactor, 0);
    EXPECT_FALSE(x.sheenColorTexture);            // the same colour everywhere: a factor
    EXPECT_DOUBLE_EQ(x.factors.sheen.colorFactor.x, 0.5);
    EXPECT_FALSE(x.factors.transmission.present);
    EXPECT_DOUBLE_EQ(x.factors.ior.ior, 1.75);    // equal areas: a level drawn as one primitive
    // The disagreement splits the chain's levels (draw_split.h); forced into one draw, it warns.
    const Asset asset = twoMaterials(coat, plain);
    EXPECT_EQ(splitDraws(asset, {&asset.mesh.triangleMaterial}).groups.size(), 2u);
    DrawSplitOptions one;
    one.maxDraws = 1;
    const DrawSplit merged = splitDraws(asset, {&asset.mesh.triangleMaterial}, one);
    EXPECT_DOUBLE_EQ(merged.groups[0].values[0].ior, 1.75);
    bool warned = false;
    for (const std::string& w : merged.warnings[0]) warned |= w.find("KHR_materials_ior ior (spread 0.5)") != std::string::npos;
    EXPECT_TRUE(warned);
    EXPECT_FALSE(baseColorPlan(p).ext.any());
}

TEST(MaterialPlanExtensions, AttenuationAveragesItsCoefficientAndIridescenceTakesTheUnionRange) {
    Material a, b;
    a.ext.volume.present = b.ext.volume.present = true;
    a.ext.volume.attenuationDistance = 1;  // coefficient 1; b: infinite distance, coefficient 0
    a.ext.volume.thicknessFactor = 0.5;
    a.ext.iridescence = {true, 1, {}, 1.3, 100, 300, {}};
    b.ext.iridescence = {true, 1, {}, 1.3, 100, 500, {}};
    const MaterialPlan p = planMaterial(twoMaterials(a, b));
    EXPECT_DOUBLE_EQ(p.ext.factors.volume.attenuationDistance, 2);
    EXPECT_TRUE(p.ext.thicknessTexture);
    EXPECT_DOUBLE_EQ(p.ext.factors.volume.thicknessFactor, 0.5);
    EXPECT_TRUE(p.ext.iridescenceThicknessTexture);  // 300 nm against 500 nm
    EXPECT_FALSE(p.ext.iridescenceTexture);
    EXPECT_DOUBLE_EQ(p.ext.factors.iridescence.thicknessMinimum, 300);
    EXPECT_DOUBLE_EQ(p.ext.factors.iridescence.thicknessMaximum, 500);
}

// The texel at the centre of triangle f's half of an n x n bake (values per texel: comps).
const float* texelOf(const std::vector<float>& v, int n, size_t comps, int f) {
    const int x = f == 0 ? 3 * n / 4 : n / 4, y = f == 0 ? 3 * n / 4 : n / 4;  // uv (x, 1 - y): triangle 0 lies bottom-right
    return &v[(size_t(y) * size_t(n) + size_t(x)) * comps];
}

TEST(BakeExtensions, ChannelsFollowFactorsTexturesAndNeutralValues) {
    Material m0, m1;
    m0.ext.sheen = {true, {1, 0, 0}, {}, 0.4, {}};
    m0.ext.clearcoat.present = true;
    m0.ext.clearcoat.factor = 0.5;
    m0.ext.clearcoat.roughnessFactor = 0.2;
    m0.ext.transmission = {true, 1, {}};
    m0.ext.volume.present = true;
    m0.ext.volume.thicknessFactor = 0.5;
    m0.ext.specular.present = true;
    m0.ext.specular.factor = 0.25;
    m0.ext.specular.colorFactor = {2, 1, 0};
    m0.ext.iridescence = {true, 1, {}, 1.3, 200, 400, {}};
    m1.ext.iridescence = {true, 0.5, {}, 1.3, 100, 300, {}};
    Asset a = twoMaterials(m0, m1);
    // m1's clearcoat comes from a texture (R 128): factor 1 x 128/255.
    a.materials[1].ext.clearcoat.present = true;
    a.materials[1].ext.clearcoat.factor = 1;
    std::vector<uint8_t> px(8 * 8 * 3, 128);
    a.images.push_back(encodePng(px, 8, 8, "grey"));
    a.textures.push_back(Texture{0, -1});
    a.materials[1].ext.clearcoat.texture.texture = 0;
    const MaterialPlan plan = planMaterial(a);
    BakeOptions o;
    o.size = 32;
    BakeChannels& ch = o.channels;
    ch.clearcoat = ch.sheen = ch.specular = ch.transmission = ch.iridescence = true;
    ch.specularColorScale = plan.ext.specularColorScale;
    ch.sheenRoughnessFill = plan.ext.sheenRoughnessFill;
    EXPECT_FALSE(plan.ext.sheenRoughnessTexture);  // only m0 has sheen: its roughness is a factor
    ch.thicknessScale = plan.ext.factors.volume.thicknessFactor;
    ch.iridescenceThicknessMin = plan.ext.factors.iridescence.thicknessMinimum;
    ch.iridescenceThicknessMax = plan.ext.factors.iridescence.thicknessMaximum;
    EXPECT_DOUBLE_EQ(ch.specularColorScale, 2);
    EXPECT_DOUBLE_EQ(ch.iridescenceThicknessMin, 300);
    EXPECT_DOUBLE_EQ(ch.iridescenceThicknessMax, 400);
    std::vector<std::array<Vec2, 3>> uv(2);
    for (size_t f = 0; f < 2; ++f)
        for (size_t k = 0; k < 3; ++k) uv[f][k] = a.mesh.wedges.uv0[a.mesh.cornerWedges[f][k]];
    const BakeSources sources(a);
    const BakeResult r = bakeMaterial(sources, uv, o);
    const int n = o.size;
    ASSERT_EQ(r.clearcoat.size(), size_t(n * n * 3));
    ASSERT_EQ(r.sheen.size(), size_t(n * n * 4));
    ASSERT_EQ(r.specular.size(), size_t(n * n * 4));
    ASSERT_EQ(r.transmission.size(), size_t(n * n * 3));
    ASSERT_EQ(r.iridescence.size(), size_t(n * n * 3));
    const float step = 1 / 255.0f + 1e-6f;
    // Clearcoat R G: 0.5, 0.2 on m0; 128/255, 0 (neutral roughness) on m1.
    EXPECT_NEAR(texelOf(r.clearcoat, n, 3, 0)[0], 0.5, step);
    EXPECT_NEAR(texelOf(r.clearcoat, n, 3, 0)[1], 0.2, step);
    EXPECT_NEAR(texelOf(r.clearcoat, n, 3, 1)[0], 128 / 255.0, step);
    EXPECT_NEAR(texelOf(r.clearcoat, n, 3, 1)[1], 0, step);
    // Sheen RGBA: red (sRGB 1, 0, 0), roughness 0.4 on m0; black on m1 (neutral).
    EXPECT_NEAR(texelOf(r.sheen, n, 4, 0)[0], 1, step);
    EXPECT_NEAR(texelOf(r.sheen, n, 4, 0)[3], 0.4, step);
    EXPECT_NEAR(texelOf(r.sheen, n, 4, 1)[0], 0, step);
    EXPECT_NEAR(texelOf(r.sheen, n, 4, 1)[3], 0.4, step);  // no sheen: the sheen's roughness (sheenRoughnessFill)
    // Specular: colour / 2 in sRGB, strength in A; m1 neutral white / 2 and 1.
    EXPECT_NEAR(texelOf(r.specular, n, 4, 0)[0], 1, step);
    EXPECT_NEAR(texelOf(r.specular, n, 4, 0)[1], linearToSrgb(0.5), step);
    EXPECT_NEAR(texelOf(r.specular, n, 4, 0)[3], 0.25, step);
    EXPECT_NEAR(texelOf(r.specular, n, 4, 1)[1], linearToSrgb(0.5), step);
    EXPECT_NEAR(texelOf(r.specular, n, 4, 1)[3], 1, step);
    // Transmission R, thickness G / 0.5; neutral 0 on m1.
    EXPECT_NEAR(texelOf(r.transmission, n, 3, 0)[0], 1, step);
    EXPECT_NEAR(texelOf(r.transmission, n, 3, 0)[1], 1, step);
    EXPECT_NEAR(texelOf(r.transmission, n, 3, 1)[1], 0, step);
    // Iridescence: factor R; thickness 400 nm -> 1 and 300 nm -> 0 in [300, 400].
    EXPECT_NEAR(texelOf(r.iridescence, n, 3, 0)[0], 1, step);
    EXPECT_NEAR(texelOf(r.iridescence, n, 3, 0)[1], 1, step);
    EXPECT_NEAR(texelOf(r.iridescence, n, 3, 1)[0], 0.5, step);
    EXPECT_NEAR(texelOf(r.iridescence, n, 3, 1)[1], 0, step);
    EXPECT_TRUE(r.diffuseTransmission.empty());
    // The same for any thread count.
    o.threads = 2;
    const BakeResult r2 = bakeMaterial(sources, uv, o);
    EXPECT_EQ(r.sheen, r2.sheen);
    EXPECT_EQ(r.iridescence, r2.iridescence);
}

// Anisotropy: the direction (the tangent rotated by anisotropyRotation) is re-expressed in the
// target's tangent frame. The quad's own frame (T = +x, B = +y) and a target whose tangents
// point along +y (so its bitangent is -x) see the same world direction differently.
TEST(BakeExtensions, AnisotropyDirectionFollowsTheTargetFrame) {
    Material m;
    m.ext.anisotropy = {true, 0.6, kPi / 2, {}};  // world +y
    Asset a = twoMaterials(m, m);
    std::vector<std::array<Vec2, 3>> uv(2);
    BakeTarget same, turned;
    for (size_t f = 0; f < 2; ++f) {
        std::array<Vec3, 3> n;
        std::array<Vec4, 3> t0, t1;
        for (size_t k = 0; k < 3; ++k) {
            uv[f][k] = a.mesh.wedges.uv0[a.mesh.cornerWedges[f][k]];
            n[k] = {0, 0, 1};
            t0[k] = {1, 0, 0, 1};
            t1[k] = {0, 1, 0, 1};
        }
        for (BakeTarget* t : {&same, &turned}) {
            t->uv.push_back(uv[f]);
            t->normal.push_back(n);
        }
        same.tangent.push_back(t0);
        turned.tangent.push_back(t1);
    }
    const MaterialPlan plan = planMaterial(a);
    EXPECT_TRUE(plan.ext.anisotropyTexture);
    EXPECT_DOUBLE_EQ(plan.ext.factors.anisotropy.strength, 1);
    BakeOptions o;
    o.size = 16;
    o.channels.anisotropy = true;
    const BakeSources sources(a);
    const float step = 1 / 255.0f + 1e-6f;
    const BakeResult r0 = bakeMaterial(sources, uv, o, {}, &same);
    EXPECT_NEAR(texelOf(r0.anisotropy, 16, 3, 0)[0], 0.5, step);  // direction (0, 1)
    EXPECT_NEAR(texelOf(r0.anisotropy, 16, 3, 0)[1], 1, step);
    EXPECT_NEAR(texelOf(r0.anisotropy, 16, 3, 0)[2], 0.6, step);
    const BakeResult r1 = bakeMaterial(sources, uv, o, {}, &turned);
    EXPECT_NEAR(texelOf(r1.anisotropy, 16, 3, 1)[0], 1, step);  // direction (1, 0): along the target's tangent
    EXPECT_NEAR(texelOf(r1.anisotropy, 16, 3, 1)[1], 0.5, step);
}

}  // namespace
}  // namespace lodbake
