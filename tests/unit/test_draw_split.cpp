// Draw groups (lodbake/bake/draw_split.h): which triangles share a primitive because their
// materials agree on what glTF cannot vary per texel, and how --max-draws merges groups. Each test
// asset is one right triangle per material, side s_i, so triangle i has area s_i^2 / 2:
//
//   (x_i, s_i) +
//              | \          triangle i = (x_i, 0) (x_i + s_i, 0) (x_i, s_i), material i
//              |   \        (x_i: side by side, no overlap)
//   (x_i, 0)   +-----+ (x_i + s_i, 0)
#include <gtest/gtest.h>

#include <cmath>

#include "lodbake/bake/draw_split.h"

namespace lodbake {
namespace {

Asset trianglesOf(const std::vector<Material>& materials, const std::vector<double>& sides) {
    Asset a;
    TriMesh& m = a.mesh;
    double x = 0;
    for (size_t i = 0; i < materials.size(); ++i) {
        const double s = sides[i];
        const uint32_t v = uint32_t(m.positions.size());
        m.positions.push_back({x, 0, 0});
        m.positions.push_back({x + s, 0, 0});
        m.positions.push_back({x, s, 0});
        m.triangles.push_back({v, v + 1, v + 2});
        m.triangleMaterial.push_back(int32_t(i));
        x += s + 1;
    }
    a.materials = materials;
    return a;
}

Material withIor(double ior) {
    Material m;
    m.ext.ior = {true, ior};
    return m;
}

bool warned(const DrawSplit& s, const std::string& needle) {
    for (const std::string& w : s.warnings[0])
        if (w.find(needle) != std::string::npos) return true;
    return false;
}

TEST(DrawSplit, AgreeingMaterialsKeepOneGroup) {
    Material red = withIor(1.5), plain;  // plain has no KHR_materials_ior: its ior is the default 1.5
    red.baseColorFactor = {1, 0, 0, 1};
    const Asset a = trianglesOf({red, plain}, {1, 1});
    const DrawSplit s = splitDraws(a, {&a.mesh.triangleMaterial});
    ASSERT_EQ(s.groups.size(), 1u);
    EXPECT_TRUE(s.splitBy.empty());
    EXPECT_TRUE(s.warnings[0].empty());
    EXPECT_EQ(s.groups[0].values[0].ior, 1.5);
}

TEST(DrawSplit, DisagreeingIorSplitsWithExactValues) {
    const Asset a = trianglesOf({withIor(1.5), withIor(1.33)}, {2, 1});
    const DrawSplit s = splitDraws(a, {&a.mesh.triangleMaterial});
    ASSERT_EQ(s.groups.size(), 2u);
    EXPECT_NE(s.groupOf[0], s.groupOf[1]);
    EXPECT_EQ(s.groups[s.groupOf[0]].values[0].ior, 1.5);
    EXPECT_EQ(s.groups[s.groupOf[1]].values[0].ior, 1.33);
    EXPECT_EQ(s.splitBy, std::vector<std::string>{"ior"});
    EXPECT_TRUE(s.warnings[0].empty());  // exact: nothing to warn about
}

TEST(DrawSplit, OpaqueJoinsMaskButNotBlend) {
    Material opaque, mask, blend;
    mask.alphaMode = AlphaMode::Mask;
    mask.alphaCutoff = 0.3;
    blend.alphaMode = AlphaMode::Blend;
    // OPAQUE + MASK: one MASK group (opaque parts are baked with alpha 1), as before.
    const Asset a = trianglesOf({opaque, mask}, {1, 1});
    const DrawSplit s = splitDraws(a, {&a.mesh.triangleMaterial});
    ASSERT_EQ(s.groups.size(), 1u);
    EXPECT_EQ(s.groups[0].values[0].alphaMode, AlphaMode::Mask);
    EXPECT_EQ(s.groups[0].values[0].alphaCutoff, 0.3);
    EXPECT_TRUE(warned(s, "mix alpha modes"));
    // OPAQUE + BLEND: an opaque primitive and a blended one.
    const Asset b = trianglesOf({opaque, blend}, {1, 1});
    const DrawSplit t = splitDraws(b, {&b.mesh.triangleMaterial});
    ASSERT_EQ(t.groups.size(), 2u);
    EXPECT_EQ(t.groups[t.groupOf[0]].values[0].alphaMode, AlphaMode::Opaque);
    EXPECT_EQ(t.groups[t.groupOf[1]].values[0].alphaMode, AlphaMode::Blend);
    EXPECT_EQ(t.splitBy, std::vector<std::string>{"alphaMode"});
    // Two MASK cutoffs: two groups, each its own cutoff.
    Material mask5 = mask;
    mask5.alphaCutoff = 0.5;
    const Asset c = trianglesOf({mask, mask5}, {1, 1});
    const DrawSplit u = splitDraws(c, {&c.mesh.triangleMaterial});
    ASSERT_EQ(u.groups.size(), 2u);
    EXPECT_EQ(u.splitBy, std::vector<std::string>{"alphaCutoff"});
}

TEST(DrawSplit, AttenuationWithoutAVolumeIsFree) {
    Material glass, tinted, solid;
    glass.ext.volume.present = tinted.ext.volume.present = true;
    glass.ext.volume.attenuationDistance = 2;
    tinted.ext.volume.attenuationDistance = 2;
    tinted.ext.volume.attenuationColor = {1, 0.5, 0.5};
    // solid has no volume (thin-walled): it joins whichever volume group comes first.
    const Asset a = trianglesOf({glass, tinted, solid}, {2, 1, 1});
    const DrawSplit s = splitDraws(a, {&a.mesh.triangleMaterial});
    ASSERT_EQ(s.groups.size(), 2u);
    EXPECT_EQ(s.groupOf[2], s.groupOf[0]);  // the larger volume group is formed first
    EXPECT_EQ(s.groups[s.groupOf[1]].values[0].attenuationColor.y, 0.5);
    EXPECT_EQ(s.groups[s.groupOf[0]].values[0].attenuationDistance, 2);
    EXPECT_EQ(s.splitBy, std::vector<std::string>{"attenuationColor"});
}

// A: ior 1.5 (area 8), B: ior 2 (area 0.5), C: ior 1.5 and BLEND (area 2).
TEST(DrawSplit, MaxDrawsMergesTheSmallestIntoItsNearest) {
    Material c = withIor(1.5);
    c.alphaMode = AlphaMode::Blend;
    const Asset a = trianglesOf({withIor(1.5), withIor(2), c}, {4, 1, 2});
    EXPECT_EQ(splitDraws(a, {&a.mesh.triangleMaterial}).groups.size(), 3u);
    DrawSplitOptions two;
    two.maxDraws = 2;
    // B conflicts with A on ior only, with C on ior and alpha mode: B joins A.
    const DrawSplit s = splitDraws(a, {&a.mesh.triangleMaterial}, two);
    ASSERT_EQ(s.groups.size(), 2u);
    EXPECT_EQ(s.groupOf[0], s.groupOf[1]);
    EXPECT_NE(s.groupOf[0], s.groupOf[2]);
    EXPECT_DOUBLE_EQ(s.groups[s.groupOf[0]].values[0].ior, (1.5 * 8 + 2 * 0.5) / 8.5);
    EXPECT_TRUE(warned(s, "KHR_materials_ior ior (spread 0.5)"));
    EXPECT_EQ(s.splitBy, (std::vector<std::string>{"alphaMode", "ior"}));  // C keeps 1.5, A + B take the mean
    // One draw: everything merged, the one-material chain's values and warnings.
    DrawSplitOptions one;
    one.maxDraws = 1;
    const DrawSplit m = splitDraws(a, {&a.mesh.triangleMaterial}, one);
    ASSERT_EQ(m.groups.size(), 1u);
    EXPECT_EQ(m.groups[0].values[0].alphaMode, AlphaMode::Blend);
    EXPECT_DOUBLE_EQ(m.groups[0].values[0].ior, (1.5 * 8 + 2 * 0.5 + 1.5 * 2) / 10.5);
    EXPECT_TRUE(warned(m, "KHR_materials_ior ior (spread 0.5)"));
    EXPECT_TRUE(warned(m, "mix alpha modes"));
    EXPECT_TRUE(m.splitBy.empty());
}

TEST(DrawSplit, VariantSelectionsSplitToo) {
    // Both triangles ior 1.5 by default; a variant gives triangle 1 ior 1.33.
    const Asset a = trianglesOf({withIor(1.5), withIor(1.33)}, {1, 1});
    const std::vector<int32_t> defaults = {0, 0};
    const std::vector<int32_t> variant = {0, 1};
    const DrawSplit s = splitDraws(a, {&defaults, &variant});
    ASSERT_EQ(s.groups.size(), 2u);
    EXPECT_EQ(s.groups[s.groupOf[1]].values[0].ior, 1.5);
    EXPECT_EQ(s.groups[s.groupOf[1]].values[1].ior, 1.33);
    EXPECT_EQ(s.groups[s.groupOf[0]].values[1].ior, 1.5);
}

TEST(DrawSplit, TransmissiveAndSolidPartsSplitAndTheSolidOneDropsTransmission) {
    Material glass, zero, solid;
    glass.ext.transmission = {true, 0.9, {}};
    glass.ext.volume.present = true;
    glass.ext.volume.thicknessFactor = 0.2;
    zero.ext.transmission = {true, 0, {}};  // transmits nothing: solid
    const Asset a = trianglesOf({glass, zero, solid}, {2, 1, 1});
    const DrawSplit s = splitDraws(a, {&a.mesh.triangleMaterial});
    ASSERT_EQ(s.groups.size(), 2u);
    EXPECT_NE(s.groupOf[0], s.groupOf[1]);
    EXPECT_EQ(s.groupOf[1], s.groupOf[2]);
    EXPECT_TRUE(s.groups[s.groupOf[0]].values[0].transmission);
    EXPECT_FALSE(s.groups[s.groupOf[1]].values[0].transmission);
    EXPECT_EQ(s.splitBy, std::vector<std::string>{"transmission"});
    // The level material carries the union; the solid part's copy loses transmission and volume.
    MaterialExtensions ext = glass.ext;
    AlphaMode mode = AlphaMode::Opaque;
    double cutoff = 0.5;
    bool unlit = false;
    applyUniforms(s.groups[s.groupOf[1]].values[0], mode, cutoff, unlit, ext);
    EXPECT_FALSE(ext.transmission.present);
    EXPECT_FALSE(ext.volume.present);
    ext = glass.ext;
    applyUniforms(s.groups[s.groupOf[0]].values[0], mode, cutoff, unlit, ext);
    EXPECT_TRUE(ext.transmission.present);
    EXPECT_TRUE(ext.volume.present);
    // Forced into one primitive: it transmits, with a warning about the solid parts.
    DrawSplitOptions one;
    one.maxDraws = 1;
    const DrawSplit m = splitDraws(a, {&a.mesh.triangleMaterial}, one);
    ASSERT_EQ(m.groups.size(), 1u);
    EXPECT_TRUE(m.groups[0].values[0].transmission);
    EXPECT_TRUE(warned(m, "transmissive and solid"));
}

TEST(DrawSplit, MergeUniformsAveragesAttenuationThroughItsCoefficient) {
    Material a, b;
    a.ext.volume.present = b.ext.volume.present = true;
    a.ext.volume.attenuationDistance = 1;  // coefficient 1; b: infinite, coefficient 0
    std::vector<std::string> warnings;
    const MaterialUniforms u = mergeUniforms({{&a, 1}, {&b, 1}}, &warnings);
    EXPECT_DOUBLE_EQ(u.attenuationDistance, 2);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_NE(warnings[0].find("attenuationDistance"), std::string::npos);
}

}  // namespace
}  // namespace lodbake
