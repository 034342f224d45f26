// What a scene holds besides its meshes: EXT_mesh_gpu_instancing expanded on reading, lights,
// cameras and extras read, carried through the intermediates (writeGltf) and into the MSFT_lod
// chain (writeLodChain); the extensions a file may require.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "gltf/scene_extras_codec.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/pose.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/gltf/msft_lod.h"
#include "unit/gltf_test_files.h"

using namespace lodbake;
using namespace lodbake::testing;
using json = nlohmann::json;

namespace {

constexpr int kI16 = 5122, kU16 = 5123, kF32 = 5126;

bool hasVertexNear(const TriMesh& m, Vec3 p) {
    for (const Vec3& q : m.positions)
        if (length(q - p) < 1e-6) return true;
    return false;
}

bool hasWarning(const Asset& a, const std::string& needle) {
    for (const std::string& w : a.warnings)
        if (w.find(needle) != std::string::npos) return true;
    return false;
}

// The JSON chunk of a .glb.
json glbJson(const std::string& path) {
    std::string b = readBytes(path);
    uint32_t n = 0;
    std::memcpy(&n, b.data() + 12, 4);
    return json::parse(b.substr(20, n));
}

// A unit cube [0,1]^3 mesh (12 triangles) on a node with three instances:
//   0: identity;  1: translated (5,0,0), scale 2;  2: translated (0,5,0), 90 degrees about z.
// The node itself is translated by (100,0,0). ROTATION is normalized SHORT (the spec allows it).
TestGltf instancedCubes(int rotationCount = 3) {
    std::vector<float> pos, nrm;
    std::vector<uint16_t> idx;
    cubeData(pos, nrm, idx);
    TestGltf g;
    int p = g.add(pos, kF32, "VEC3"), n = g.add(nrm, kF32, "VEC3"), i = g.add(idx, kU16, "SCALAR");
    std::vector<float> t = {0, 0, 0, 5, 0, 0, 0, 5, 0}, s = {1, 1, 1, 2, 2, 2, 1, 1, 1};
    const int16_t h = int16_t(std::lround(std::sqrt(0.5) * 32767));
    std::vector<int16_t> r = {0, 0, 0, 32767, 0, 0, 0, 32767, 0, 0, h, h};
    r.resize(size_t(4 * rotationCount), 0);
    int ta = g.add(t, kF32, "VEC3"), sa = g.add(s, kF32, "VEC3"), ra = g.add(r, kI16, "VEC4", true);
    meshNode(g, {prim({{"POSITION", p}, {"NORMAL", n}}, i)},
             json{{"translation", {100, 0, 0}},
                  {"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", ta}, {"ROTATION", ra}, {"SCALE", sa}}}}}}}});
    g.j["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
    g.j["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
    return g;
}

// Scene: a mesh node; a parent translated (0,0,10) holding a spot light node (rotated 90 degrees
// about x) and a camera node; a directional light at the root. Extras on the root, asset, scene.
TestGltf litScene() {
    TestGltf g;
    int pa = g.add(unitTrianglePositions(), kF32, "VEC3");
    meshNode(g, {prim(json{{"POSITION", pa}})});
    const double s = std::sqrt(0.5);
    int spot = g.addNode({{"name", "spot"}, {"rotation", {s, 0, 0, s}},
                          {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}, false);
    int cam = g.addNode({{"name", "eye"}, {"camera", 0}, {"translation", {0, 1, 0}}}, false);
    g.addNode({{"name", "rig"}, {"translation", {0, 0, 10}}, {"children", {spot, cam}}});
    g.addNode({{"name", "sun"}, {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    g.j["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"name", "Spot"}, {"type", "spot"}, {"color", {1, 0.5, 0.25}}, {"intensity", 20}, {"range", 8},
         {"spot", {{"innerConeAngle", 0.2}, {"outerConeAngle", 0.6}}}},
        {{"type", "directional"}, {"intensity", 3}}};
    g.j["cameras"] = {{{"name", "Cam"}, {"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"znear", 0.1}, {"aspectRatio", 1.5}}}}};
    g.j["extensionsUsed"] = {"KHR_lights_punctual"};
    g.j["extras"] = {{"author", "test"}};
    g.j["asset"]["extras"] = {{"note", 1}};
    g.j["scenes"][0]["extras"] = {{"sky", "blue"}};
    return g;
}

void expectLitScene(const SceneExtras& s) {
    ASSERT_EQ(s.lights.size(), 2u);
    ASSERT_EQ(s.cameras.size(), 1u);
    ASSERT_EQ(s.placements.size(), 3u);
    EXPECT_EQ(s.lights[0].name, "Spot");
    EXPECT_EQ(int(s.lights[0].type), int(SceneLight::Type::Spot));
    EXPECT_DOUBLE_EQ(s.lights[0].intensity, 20);
    EXPECT_DOUBLE_EQ(s.lights[0].range, 8);
    EXPECT_DOUBLE_EQ(s.lights[0].color.y, 0.5);
    EXPECT_DOUBLE_EQ(s.lights[0].outerConeAngle, 0.6);
    EXPECT_EQ(int(s.lights[1].type), int(SceneLight::Type::Directional));
    EXPECT_EQ(s.cameras[0].name, "Cam");
    EXPECT_DOUBLE_EQ(s.cameras[0].aspectRatio, 1.5);
    EXPECT_DOUBLE_EQ(s.cameras[0].zfar, 0);
    // Depth-first order: spot, eye (below "rig"), sun.
    EXPECT_EQ(s.placements[0].name, "spot");
    EXPECT_EQ(s.placements[0].light, 0);
    EXPECT_EQ(s.placements[1].name, "eye");
    EXPECT_EQ(s.placements[1].camera, 0);
    EXPECT_EQ(s.placements[2].light, 1);
    // The spot's world: translated (0,0,10), its local +y turned to +z.
    const Mat4& w = s.placements[0].world;
    EXPECT_NEAR(w[14], 10, 1e-9);
    EXPECT_NEAR(w[6], 1, 1e-9);
    EXPECT_NEAR(s.placements[1].world[13], 1, 1e-9);
    EXPECT_EQ(s.rootExtras, R"({"author":"test"})");
    EXPECT_EQ(s.assetExtras, R"({"note":1})");
    EXPECT_EQ(s.sceneExtras, R"({"sky":"blue"})");
}

}  // namespace

TEST(SceneInstancing, EveryInstanceIsExpanded) {
    auto dir = tempDir("instancing");
    TestGltf g = instancedCubes();
    Asset a = readGltf(g.writeGltf(dir, "inst"));
    EXPECT_EQ(a.mesh.triangleCount(), 36u);  // 3 instances x 12 triangles
    EXPECT_EQ(a.mesh.vertexCount(), 24u);    // no corner shared between the copies
    EXPECT_TRUE(hasVertexNear(a.mesh, {101, 1, 1}));  // instance 0: node translation only
    EXPECT_TRUE(hasVertexNear(a.mesh, {107, 2, 2}));  // instance 1: scale 2, then (5,0,0)
    EXPECT_TRUE(hasVertexNear(a.mesh, {99, 6, 1}));   // instance 2: (1,1,1) -> (-1,1,1), then (0,5,0)
    EXPECT_FALSE(hasWarning(a, "instances"));
}

// More than 1,000 copies of one mesh: all expanded, with a warning saying how many.
TEST(SceneInstancing, ManyInstancesAreExpandedWithAWarning) {
    auto dir = tempDir("instancing_many");
    TestGltf g;
    int pa = g.add(unitTrianglePositions(), kF32, "VEC3");
    std::vector<float> t;
    for (int i = 0; i < 1001; ++i) t.insert(t.end(), {float(2 * i), 0, 0});
    int ta = g.add(t, kF32, "VEC3");
    meshNode(g, {prim(json{{"POSITION", pa}})}, json{{"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", ta}}}}}}}});
    Asset a = readGltf(g.writeGltf(dir, "many"));
    EXPECT_EQ(a.mesh.triangleCount(), 1001u);
    EXPECT_TRUE(hasVertexNear(a.mesh, {2000, 1, 0}));
    EXPECT_TRUE(hasWarning(a, "node 0 EXT_mesh_gpu_instancing: 1001 instances of mesh 0 (1 triangle each) expanded into 1001 triangles"));
}

// An animated instanced node: every copy is bound rigidly to the node, so posing moves them all
// with it. The node moves from (0,0,0) to (0,0,10) over one second; instances at x = 0 and x = 5.
TEST(SceneInstancing, AnimatedNodeMovesEveryCopy) {
    auto dir = tempDir("instancing_animated");
    TestGltf g;
    int pa = g.add(unitTrianglePositions(), kF32, "VEC3");
    std::vector<float> t = {0, 0, 0, 5, 0, 0}, times = {0, 1}, moves = {0, 0, 0, 0, 0, 10};
    int ta = g.add(t, kF32, "VEC3"), in = g.add(times, kF32, "SCALAR"), out = g.add(moves, kF32, "VEC3");
    g.j["accessors"][size_t(in)]["min"] = {0};
    g.j["accessors"][size_t(in)]["max"] = {1};
    meshNode(g, {prim(json{{"POSITION", pa}})}, json{{"extensions", {{"EXT_mesh_gpu_instancing", {{"attributes", {{"TRANSLATION", ta}}}}}}}});
    g.j["animations"] = {{{"samplers", {{{"input", in}, {"output", out}}}},
                          {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}};
    Asset a = readGltf(g.writeGltf(dir, "anim"));
    ASSERT_EQ(a.mesh.triangleCount(), 2u);
    ASSERT_FALSE(a.rig.empty());
    TriMesh posed = poseMesh(a.rig, a.morph, a.mesh, 0, 1.0);
    EXPECT_TRUE(hasVertexNear(posed, {1, 0, 10}));
    EXPECT_TRUE(hasVertexNear(posed, {6, 0, 10}));
    EXPECT_FALSE(hasVertexNear(posed, {6, 0, 0}));
}

TEST(SceneInstancing, MismatchedCountsAreInvalid) {
    auto dir = tempDir("instancing_bad");
    TestGltf g = instancedCubes(2);
    std::string p = g.writeGltf(dir, "inst");
    try {
        readGltf(p);
        ADD_FAILURE() << "no exception";
    } catch (const Error& e) {
        EXPECT_EQ(int(e.kind()), int(ErrorKind::InvalidInput)) << e.what();
        EXPECT_NE(std::string(e.what()).find("different counts"), std::string::npos) << e.what();
    }
}

// Every extension the reader implements may be required; an unknown one is still refused.
TEST(SceneRequired, ImplementedExtensionsMayBeRequired) {
    auto dir = tempDir("required");
    TestGltf g;
    int pa = g.add(unitTrianglePositions(), kF32, "VEC3");
    meshNode(g, {prim(json{{"POSITION", pa}})});
    const json names = {"EXT_mesh_gpu_instancing", "KHR_lights_punctual", "KHR_materials_emissive_strength",
                        "KHR_materials_pbrSpecularGlossiness", "KHR_materials_unlit", "KHR_mesh_quantization",
                        "KHR_texture_transform"};
    g.j["extensionsUsed"] = names;
    g.j["extensionsRequired"] = names;
    EXPECT_EQ(readGltf(g.writeGltf(dir, "ok")).mesh.triangleCount(), 1u);
    g.j["extensionsRequired"].push_back("KHR_technique_webgl");
    try {
        readGltf(g.writeGltf(dir, "refused"));
        ADD_FAILURE() << "no exception";
    } catch (const Error& e) {
        EXPECT_EQ(int(e.kind()), int(ErrorKind::Unsupported));
        EXPECT_NE(std::string(e.what()).find("KHR_technique_webgl"), std::string::npos) << e.what();
    }
}

TEST(SceneExtrasRead, LightsCamerasAndExtras) {
    auto dir = tempDir("lights");
    TestGltf g = litScene();
    Asset a = readGltf(g.writeGltf(dir, "lit"));
    EXPECT_EQ(a.mesh.triangleCount(), 1u);
    expectLitScene(a.scene);
    EXPECT_TRUE(a.warnings.empty()) << a.warnings.front();
}

// A light below an animated node keeps its rest transform, with a warning; an unknown root
// extension is named in a warning.
TEST(SceneExtrasRead, WarnsAboutWhatIsNotCarried) {
    auto dir = tempDir("lights_warn");
    TestGltf g = litScene();
    std::vector<float> times = {0, 1}, moves = {0, 0, 10, 0, 0, 20};
    int in = g.add(times, kF32, "SCALAR"), out = g.add(moves, kF32, "VEC3");
    g.j["accessors"][size_t(in)]["min"] = {0};
    g.j["accessors"][size_t(in)]["max"] = {1};
    g.j["animations"] = {{{"samplers", {{{"input", in}, {"output", out}}}},
                          {"channels", {{{"sampler", 0}, {"target", {{"node", 3}, {"path", "translation"}}}}}}}};
    g.j["extensions"]["EXT_unknown_root"] = json::object();
    g.j["nodes"][4]["extensions"]["EXT_unknown_node"] = json::object();
    Asset a = readGltf(g.writeGltf(dir, "lit"));
    EXPECT_TRUE(hasWarning(a, "node 1 'spot': the light below animated node 3 keeps its rest transform")) << a.warnings.size();
    EXPECT_TRUE(hasWarning(a, "node 2 'eye': the camera below animated node 3"));
    EXPECT_TRUE(hasWarning(a, "root extension EXT_unknown_root is not carried"));
    EXPECT_TRUE(hasWarning(a, "node 4: extension EXT_unknown_node is not carried"));
    EXPECT_FALSE(hasWarning(a, "'sun'"));
    EXPECT_FALSE(hasWarning(a, "KHR_lights_punctual is not carried"));
}

// The intermediates carry the scene: written, read back, the same lights, cameras, placements.
TEST(SceneExtrasWrite, IntermediateRoundTrip) {
    auto dir = tempDir("lights_rt");
    TestGltf g = litScene();
    Asset a = readGltf(g.writeGltf(dir, "lit"));
    const std::string p = (dir / "lit.mr.glb").string();
    writeGltf(p, a);
    json j = glbJson(p);
    EXPECT_EQ(j["extensionsUsed"], json({"KHR_lights_punctual"}));
    EXPECT_EQ(j["scenes"][0]["nodes"].size(), 4u);  // the mesh node and three placements
    Asset b = readGltf(p);
    expectLitScene(b.scene);
    for (size_t k = 0; k < 3; ++k)
        for (size_t e = 0; e < 16; ++e) EXPECT_NEAR(b.scene.placements[k].world[e], a.scene.placements[k].world[e], 1e-6);
    // The same asset, the same bytes.
    const std::string q = (dir / "again.glb").string();
    writeGltf(q, a);
    EXPECT_EQ(readBytes(p), readBytes(q));
}

// The MSFT_lod chain: light and camera nodes beside the LOD node, in the scene.
TEST(SceneExtrasWrite, LodChainCarriesLightsAndCameras) {
    auto dir = tempDir("lights_lod");
    TestGltf g = litScene();
    Asset a = readGltf(g.writeGltf(dir, "lit"));
    LodLevelData L;
    L.name = "LOD0";
    L.positions = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    L.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    L.uvs = {0, 0, 1, 0, 0, 1};
    L.indices = {0, 1, 2};
    LodLevelData L1 = L;
    L1.name = "LOD1";
    const std::string p = (dir / "lit.lod.glb").string();
    LodChainWriteOptions o;
    writeLodChain(p, {L, L1}, {0.5, 0.1}, o, nullptr, nullptr, &a.scene);
    json j = glbJson(p);
    EXPECT_EQ(j["extensionsUsed"], json({"KHR_lights_punctual", "MSFT_lod"}));
    EXPECT_EQ(j["extensions"]["KHR_lights_punctual"]["lights"].size(), 2u);
    EXPECT_EQ(j["cameras"].size(), 1u);
    EXPECT_EQ(j["scenes"][0]["nodes"], json({0, 2, 3, 4}));  // LOD0, then the placements (LOD1 is node 1)
    EXPECT_EQ(j["nodes"][2]["name"], "spot");
    EXPECT_EQ(j["nodes"][2]["extensions"]["KHR_lights_punctual"]["light"], 0);
    EXPECT_EQ(j["nodes"][3]["camera"], 0);
    EXPECT_EQ(j["extras"]["author"], "test");
    EXPECT_EQ(j["asset"]["extras"]["note"], 1);
    EXPECT_EQ(j["scenes"][0]["extras"]["sky"], "blue");
    Asset b = readGltf(p);
    EXPECT_EQ(b.mesh.triangleCount(), 1u);
    expectLitScene(b.scene);
}

// T * R * S of the decomposition gives the matrix back, with a negative determinant too.
TEST(SceneExtrasWrite, DecomposeTrs) {
    const Mat4 m = mul(trsMatrix({1, 2, 3}, {0.1, 0.7, -0.2, 0.6}, {2, 0.5, 3}), trsMatrix({0, 0, 0}, {0, 0, 0, 1}, {-1, 1, 1}));
    Vec3 t, s;
    Vec4 r;
    gltf_detail::decomposeTrs(m, t, r, s);
    EXPECT_NEAR(r.x * r.x + r.y * r.y + r.z * r.z + r.w * r.w, 1, 1e-12);
    EXPECT_GE(r.w, 0);
    const Mat4 back = trsMatrix(t, r, s);
    for (size_t e = 0; e < 16; ++e) EXPECT_NEAR(back[e], m[e], 1e-12) << e;
}
