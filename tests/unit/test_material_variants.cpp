// KHR_materials_variants: the asset model (a variant's triangle materials, mapping tables kept
// once), reading (root names, each primitive's mapping, extensionsRequired, bad indices) and the
// intermediate files' round trip, on two triangles built in code, one primitive each:
//
//   (0,1) +-----+ (1,1)     triangle 0 = (0,0) (1,0) (1,1), primitive 0, material 0
//         | 1 / |           triangle 1 = (0,0) (1,1) (0,1), primitive 1, material 1
//         | / 0 |           variants: "a" = primitive 0 on material 2;
//   (0,0) +-----+ (1,0)               "b" = primitive 0 on material 2, primitive 1 on material 0
#include <gtest/gtest.h>

#include "lodbake/core/errors.h"
#include "lodbake/core/material_variants.h"
#include "lodbake/gltf/gltf.h"
#include "unit/gltf_test_files.h"

namespace lodbake {
namespace {

using json = nlohmann::json;
using namespace lodbake::testing;

constexpr int kF32 = 5126;

json mapping(int material, std::vector<int> variants) { return {{"material", material}, {"variants", variants}}; }

TestGltf twoPrimitives(const json& mappings0, const json& mappings1) {
    TestGltf g;
    const int p0 = g.add(std::vector<float>{0, 0, 0, 1, 0, 0, 1, 1, 0}, kF32, "VEC3");
    const int p1 = g.add(std::vector<float>{0, 0, 0, 1, 1, 0, 0, 1, 0}, kF32, "VEC3");
    json a = prim({{"POSITION", p0}}, -1, -1, 0), b = prim({{"POSITION", p1}}, -1, -1, 1);
    if (!mappings0.is_null()) a["extensions"]["KHR_materials_variants"]["mappings"] = mappings0;
    if (!mappings1.is_null()) b["extensions"]["KHR_materials_variants"]["mappings"] = mappings1;
    meshNode(g, {a, b});
    g.j["materials"] = json::array({json{{"name", "m0"}}, json{{"name", "m1"}}, json{{"name", "m2"}}});
    g.j["extensions"]["KHR_materials_variants"]["variants"] = json::array({json{{"name", "a"}}, json{{"name", "b"}}});
    g.j["extensionsUsed"] = {"KHR_materials_variants"};
    return g;
}

TestGltf example() { return twoPrimitives(json::array({mapping(2, {0, 1})}), json::array({mapping(0, {1})})); }

// The triangle materials of every variant (triangles in primitive order).
std::vector<std::vector<int32_t>> variantMaterials(const Asset& a) {
    std::vector<std::vector<int32_t>> out;
    for (size_t v = 0; v < a.variants.names.size(); ++v) out.push_back(variantTriangleMaterials(a.variants, a.mesh.triangleMaterial, v));
    return out;
}

TEST(MaterialVariants, SelectionFallsBackToTheTriangleMaterial) {
    MaterialVariants v;
    v.names = {"a", "b"};
    EXPECT_EQ(internMapping(v, {-1, -1}), -1);  // maps nothing: as without the extension
    EXPECT_EQ(internMapping(v, {2, -1}), 0);
    EXPECT_EQ(internMapping(v, {2, -1}), 0);    // kept once
    EXPECT_EQ(internMapping(v, {-1, 0}), 1);
    v.triangleMapping = {0, 1, -1};
    const std::vector<int32_t> own = {5, 6, 7};
    EXPECT_EQ(variantTriangleMaterials(v, own, 0), (std::vector<int32_t>{2, 6, 7}));
    EXPECT_EQ(variantTriangleMaterials(v, own, 1), (std::vector<int32_t>{5, 0, 7}));
}

TEST(MaterialVariants, ReadNamesAndEachPrimitivesMapping) {
    TestGltf g = example();
    g.j["extensionsRequired"] = {"KHR_materials_variants"};
    const Asset a = readGltf(g.writeGltf(tempDir("variants_read"), "v"));
    EXPECT_EQ(a.variants.names, (std::vector<std::string>{"a", "b"}));
    ASSERT_EQ(a.mesh.triangleCount(), 2u);
    ASSERT_EQ(a.variants.triangleMapping.size(), 2u);
    EXPECT_EQ(a.mesh.triangleMaterial, (std::vector<int32_t>{0, 1}));
    EXPECT_EQ(variantMaterials(a), (std::vector<std::vector<int32_t>>{{2, 1}, {2, 0}}));
    for (const std::string& w : a.warnings) EXPECT_EQ(w.find("KHR_materials_variants"), std::string::npos) << w;
}

TEST(MaterialVariants, IntermediateFilesKeepTheMappings) {
    const auto dir = tempDir("variants_roundtrip");
    const Asset a = readGltf(example().writeGltf(dir, "v"));
    writeGltf((dir / "one.glb").string(), a);
    const Asset b = readGltf((dir / "one.glb").string());
    EXPECT_EQ(b.variants.names, a.variants.names);
    EXPECT_EQ(b.mesh.triangleMaterial, a.mesh.triangleMaterial);
    EXPECT_EQ(variantMaterials(b), variantMaterials(a));
    // Without variants the writer groups by material alone: no extension appears.
    Asset plain = a;
    plain.variants = {};
    writeGltf((dir / "plain.glb").string(), plain);
    EXPECT_TRUE(readGltf((dir / "plain.glb").string()).variants.empty());
}

TEST(MaterialVariants, BadIndicesAreInvalidInput) {
    const auto dir = tempDir("variants_bad");
    EXPECT_THROW(readGltf(twoPrimitives(json::array({mapping(7, {0})}), nullptr).writeGltf(dir, "material")), InvalidInput);
    EXPECT_THROW(readGltf(twoPrimitives(json::array({mapping(0, {2})}), nullptr).writeGltf(dir, "variant")), InvalidInput);
    TestGltf g = example();
    g.j["extensions"]["KHR_materials_variants"]["variants"] = 3;
    EXPECT_THROW(readGltf(g.writeGltf(dir, "root")), InvalidInput);
}

}  // namespace
}  // namespace lodbake
