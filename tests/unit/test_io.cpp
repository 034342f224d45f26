// io module tests: glTF reading (accessor types, sparse, interleaved, strips/fans, transforms,
// Draco, data URIs), validation errors, welding, LODBAKE_multires round trip, real assets.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include "lodbake/core/errors.h"
#include "lodbake/core/multires.h"
#include "lodbake/texture/codec.h"
#include "lodbake/gltf/gltf.h"
#include "unit/gltf_test_files.h"

using namespace lodbake;
using namespace lodbake::testing;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

constexpr int kU8 = 5121, kI16 = 5122, kU16 = 5123, kU32 = 5125, kF32 = 5126;

Vec3 triNormal(const TriMesh& m, size_t t) {
    const Tri& tr = m.triangles[t];
    return cross(m.positions[tr[1]] - m.positions[tr[0]], m.positions[tr[2]] - m.positions[tr[0]]);
}

// Expects `fn` to throw an Error of `kind` whose message starts with `path` and contains `needle`.
template <class F>
void expectError(F fn, ErrorKind kind, const std::string& path, const std::string& needle = "") {
    try {
        fn();
        ADD_FAILURE() << "no exception for " << path;
    } catch (const Error& e) {
        EXPECT_EQ(int(e.kind()), int(kind)) << e.what();
        std::string msg = e.what();
        EXPECT_EQ(msg.rfind(path, 0), 0u) << msg;
        EXPECT_NE(msg.find(needle), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

// Removes this run's temporary folder at exit unless LODBAKE_KEEP_TEST_FILES is set.
class TempCleanup : public ::testing::Environment {
public:
    void TearDown() override {
        if (std::getenv("LODBAKE_KEEP_TEST_FILES")) return;
        std::error_code ec;
        fs::remove_all(tempDir("x").parent_path(), ec);
    }
};
[[maybe_unused]] ::testing::Environment* const kTempCleanup = ::testing::AddGlobalTestEnvironment(new TempCleanup);

std::string sharedDir() {
    const char* e = std::getenv("LODBAKE_SHARED");
    if (e && *e) return e;
    return "/work/main/../shared";
}

}  // namespace

//  Cube: 6 faces x 4 glTF vertices = 24 vertices, 12 triangles.
//  Welding by position gives the 8 cube corners; wedges stay 24 (one per glTF vertex).
TEST(IoRead, CubeWeldsTo8Vertices) {
    auto dir = tempDir("cube");
    std::vector<float> pos, nrm;
    std::vector<uint16_t> idx;
    cubeData(pos, nrm, idx);
    TestGltf g;
    int p = g.add(pos, kF32, "VEC3"), n = g.add(nrm, kF32, "VEC3"), i = g.add(idx, kU16, "SCALAR");
    meshNode(g, {prim({{"POSITION", p}, {"NORMAL", n}}, i)});
    Asset a = readGltf(g.writeGltf(dir, "cube"));
    EXPECT_EQ(a.mesh.vertexCount(), 8u);
    EXPECT_EQ(a.mesh.triangleCount(), 12u);
    EXPECT_EQ(a.mesh.wedges.size(), 24u);
    EXPECT_EQ(a.mesh.wedges.normal.size(), 24u);
    EXPECT_TRUE(a.mesh.wedges.uv0.empty());
    EXPECT_EQ(a.mesh.triangleMaterial, std::vector<int32_t>(12, -1));
    // Outward normals: the geometric normal points away from the cube centre.
    for (size_t t = 0; t < 12; ++t) {
        const Tri& tr = a.mesh.triangles[t];
        Vec3 c = (a.mesh.positions[tr[0]] + a.mesh.positions[tr[1]] + a.mesh.positions[tr[2]]) / 3.0;
        EXPECT_GT(dot(triNormal(a.mesh, t), c - Vec3{0.5, 0.5, 0.5}), 0) << t;
        // The wedge normal agrees with the geometric normal.
        EXPECT_GT(dot(triNormal(a.mesh, t), a.mesh.wedges.normal[a.mesh.cornerWedges[t][0]]), 0);
        for (int k = 0; k < 3; ++k) EXPECT_EQ(a.mesh.wedges.vertex[a.mesh.cornerWedges[t][size_t(k)]], tr[size_t(k)]);
    }
    // Welded ids in order of first appearance: the first triangle's corners are 0, 1, 2.
    EXPECT_EQ(a.mesh.triangles[0], (Tri{0, 1, 2}));
}

// KHR_mesh_quantization: int16 normalized positions, uint8 normalized UVs, int8 normals.
TEST(IoRead, QuantizedAccessors) {
    auto dir = tempDir("quant");
    TestGltf g;
    g.j["extensionsUsed"] = {"KHR_mesh_quantization"};
    g.j["extensionsRequired"] = {"KHR_mesh_quantization"};
    std::vector<int16_t> pos = {0, 0, 0, 0, 32767, 0, 0, 0, 0, 32767, 0, 0};  // VEC3 padded to 8 bytes
    int pv = g.view(pos.data(), pos.size() * 2, 8);
    int pa = g.accessor(pv, 0, kI16, 3, "VEC3", true);
    std::vector<uint8_t> uv = {0, 0, 255, 0, 0, 255};
    int ua = g.add(uv, kU8, "VEC2", true);
    std::vector<int8_t> nrm = {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0};
    int nv = g.view(nrm.data(), nrm.size(), 4);
    int na = g.accessor(nv, 0, 5120, 3, "VEC3", true);
    meshNode(g, {prim({{"POSITION", pa}, {"TEXCOORD_0", ua}, {"NORMAL", na}})});
    Asset a = readGltf(g.writeGltf(dir, "quant"));
    ASSERT_EQ(a.mesh.vertexCount(), 3u);
    EXPECT_DOUBLE_EQ(a.mesh.positions[1].x, 1.0);
    EXPECT_DOUBLE_EQ(a.mesh.positions[2].y, 1.0);
    EXPECT_DOUBLE_EQ(a.mesh.wedges.uv0[1].x, 1.0);
    EXPECT_DOUBLE_EQ(a.mesh.wedges.uv0[2].y, 1.0);
    EXPECT_NEAR(a.mesh.wedges.normal[0].z, 1.0, 1e-12);
}

// Unnormalized uint16 positions (also legal with KHR_mesh_quantization) read as integers.
TEST(IoRead, QuantizedUnnormalized) {
    auto dir = tempDir("quant2");
    TestGltf g;
    std::vector<uint16_t> pos = {0, 0, 0, 0, 7, 0, 0, 0, 0, 5, 0, 0};
    int pv = g.view(pos.data(), pos.size() * 2, 8);
    meshNode(g, {prim(json{{"POSITION", g.accessor(pv, 0, kU16, 3, "VEC3")}})});
    Asset a = readGltf(g.writeGltf(dir, "q"));
    EXPECT_DOUBLE_EQ(a.mesh.positions[1].x, 7.0);
    EXPECT_DOUBLE_EQ(a.mesh.positions[2].y, 5.0);
}

// Sparse accessor: base triangle, vertex 2 replaced by (0, 5, 0).
TEST(IoRead, SparseAccessor) {
    auto dir = tempDir("sparse");
    TestGltf g;
    int pa = g.add(unitTrianglePositions(), kF32, "VEC3");
    std::vector<uint8_t> si = {2, 0, 0, 0};
    std::vector<float> sv = {0, 5, 0};
    int iv = g.view(si.data(), 1), vv = g.view(sv.data(), 12);
    g.j["accessors"][size_t(pa)]["sparse"] = {{"count", 1},
                                              {"indices", {{"bufferView", iv}, {"componentType", kU8}}},
                                              {"values", {{"bufferView", vv}}}};
    meshNode(g, {prim(json{{"POSITION", pa}})});
    Asset a = readGltf(g.writeGltf(dir, "sparse"));
    ASSERT_EQ(a.mesh.vertexCount(), 3u);
    EXPECT_DOUBLE_EQ(a.mesh.positions[2].y, 5.0);

    // Sparse-only accessor (no bufferView): zeros + the override.
    TestGltf h;
    std::vector<uint8_t> si2 = {1, 2, 0, 0};
    std::vector<float> sv2 = {1, 0, 0, 0, 1, 0};
    int iv2 = h.view(si2.data(), 2), vv2 = h.view(sv2.data(), 24);
    h.j["accessors"].push_back({{"componentType", kF32}, {"count", 3}, {"type", "VEC3"},
                                {"sparse", {{"count", 2}, {"indices", {{"bufferView", iv2}, {"componentType", kU8}}}, {"values", {{"bufferView", vv2}}}}}});
    meshNode(h, {prim(json{{"POSITION", 0}})});
    Asset b = readGltf(h.writeGltf(dir, "sparse2"));
    ASSERT_EQ(b.mesh.vertexCount(), 3u);
    EXPECT_DOUBLE_EQ(b.mesh.positions[1].x, 1.0);
    EXPECT_DOUBLE_EQ(b.mesh.positions[2].y, 1.0);
}

// Interleaved view: [pos.xyz uv.xy] per vertex, byteStride 20.
TEST(IoRead, InterleavedView) {
    auto dir = tempDir("interleaved");
    TestGltf g;
    std::vector<float> data = {0, 0, 0, 0.1f, 0.2f, 1, 0, 0, 0.3f, 0.4f, 0, 1, 0, 0.5f, 0.6f};
    int v = g.view(data.data(), data.size() * 4, 20);
    int pa = g.accessor(v, 0, kF32, 3, "VEC3"), ua = g.accessor(v, 12, kF32, 3, "VEC2");
    meshNode(g, {prim({{"POSITION", pa}, {"TEXCOORD_0", ua}})});
    Asset a = readGltf(g.writeGltf(dir, "il"));
    ASSERT_EQ(a.mesh.vertexCount(), 3u);
    EXPECT_DOUBLE_EQ(a.mesh.positions[1].x, 1.0);
    EXPECT_FLOAT_EQ(float(a.mesh.wedges.uv0[2].y), 0.6f);
}

//  Strip 0-1-2-3 (a quad, 2 triangles) and fan around 0 (pentagon, 3 triangles), all facing +z.
TEST(IoRead, StripAndFan) {
    auto dir = tempDir("stripfan");
    TestGltf g;
    std::vector<float> strip = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
    std::vector<float> fan = {0, 0, 1, 1, 0, 1, 1, 1, 1, 0.5f, 1.5f, 1, 0, 1, 1};
    int sa = g.add(strip, kF32, "VEC3"), fa = g.add(fan, kF32, "VEC3");
    meshNode(g, {prim(json{{"POSITION", sa}}, -1, 5), prim(json{{"POSITION", fa}}, -1, 6), prim(json{{"POSITION", fa}}, -1, 1)});
    Asset a = readGltf(g.writeGltf(dir, "sf"));
    EXPECT_EQ(a.mesh.triangleCount(), 5u);
    for (size_t t = 0; t < a.mesh.triangleCount(); ++t) EXPECT_GT(triNormal(a.mesh, t).z, 0) << t;
    EXPECT_EQ(a.stats.droppedPrimitives, 1u);
    ASSERT_FALSE(a.warnings.empty());
}

// Node scale (-1, 1, 1): mirrored, so winding must flip to keep the front face outward (+z).
TEST(IoRead, NegativeScaleFlipsWinding) {
    auto dir = tempDir("negscale");
    TestGltf g;
    std::vector<float> nrm = {0, 0, 1, 0, 0, 1, 0, 0, 1};
    int pa = g.add(unitTrianglePositions(), kF32, "VEC3"), na = g.add(nrm, kF32, "VEC3");
    meshNode(g, {prim({{"POSITION", pa}, {"NORMAL", na}})}, json{{"scale", {-1, 1, 1}}});
    Asset a = readGltf(g.writeGltf(dir, "neg"));
    ASSERT_EQ(a.mesh.triangleCount(), 1u);
    EXPECT_GT(triNormal(a.mesh, 0).z, 0);
    EXPECT_NEAR(a.mesh.wedges.normal[0].z, 1.0, 1e-12);
    bool hasMinusX = false;
    for (const Vec3& p : a.mesh.positions) hasMinusX |= p.x < 0;
    EXPECT_TRUE(hasMinusX);
}

// Parent: matrix translating by (10, 0, 0). Child: TRS, scale 2, rotation 90 deg about z.
// Vertex (1,0,0) -> scale (2,0,0) -> rotate (0,2,0) -> translate (10,2,0).
TEST(IoRead, MatrixAndTrsHierarchy) {
    auto dir = tempDir("hier");
    TestGltf g;
    std::vector<float> nrm = {1, 0, 0, 1, 0, 0, 1, 0, 0};
    int pa = g.add(unitTrianglePositions(), kF32, "VEC3"), na = g.add(nrm, kF32, "VEC3");
    int mesh = g.addMesh(json::array({prim({{"POSITION", pa}, {"NORMAL", na}})}));
    double s = std::sqrt(0.5);
    g.addNode({{"mesh", mesh}, {"scale", {2, 2, 2}}, {"rotation", {0, 0, s, s}}}, false);
    g.addNode({{"children", {0}}, {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1}}});
    Asset a = readGltf(g.writeGltf(dir, "h"));
    ASSERT_EQ(a.mesh.vertexCount(), 3u);
    EXPECT_NEAR(a.mesh.positions[1].x, 10.0, 1e-12);
    EXPECT_NEAR(a.mesh.positions[1].y, 2.0, 1e-12);
    EXPECT_NEAR(a.mesh.positions[0].x, 10.0, 1e-12);
    EXPECT_NEAR(a.mesh.wedges.normal[0].y, 1.0, 1e-12);  // (1,0,0) rotated to (0,1,0), unit length
    EXPECT_EQ(a.stats.nodes, 2u);
}

TEST(IoRead, DataUriBufferAndGlb) {
    auto dir = tempDir("datauri");
    std::vector<float> pos, nrm;
    std::vector<uint16_t> idx;
    cubeData(pos, nrm, idx);
    TestGltf g;
    int p = g.add(pos, kF32, "VEC3"), i = g.add(idx, kU16, "SCALAR");
    meshNode(g, {prim(json{{"POSITION", p}}, i)});
    TestGltf g2 = g;
    Asset a = readGltf(g.writeGltfDataUri(dir, "cube"));
    EXPECT_EQ(a.mesh.triangleCount(), 12u);
    // A .glb saved under a .gltf name is still detected by its magic bytes.
    std::string glb = (dir / "really_glb.gltf").string();
    writeBytes(glb, g2.glbBytes());
    Asset b = readGltf(glb);
    EXPECT_EQ(b.mesh.triangleCount(), 12u);
}

TEST(IoRead, ColorsAndMaterials) {
    auto dir = tempDir("colors");
    TestGltf g;
    std::vector<uint8_t> col = {255, 0, 0, 0, 255, 0, 0, 0, 255};
    int pa = g.add(unitTrianglePositions(), kF32, "VEC3"), ca = g.add(col, kU8, "VEC3", true);
    json tt = {{"offset", {0.5, 0.25}}, {"rotation", 0.1}, {"scale", {2, 3}}, {"texCoord", 1}};
    json mat = json::object();
    mat["name"] = "m";
    mat["pbrMetallicRoughness"]["baseColorFactor"] = {0.5, 0.5, 0.5, 1};
    mat["pbrMetallicRoughness"]["baseColorTexture"]["index"] = 0;
    mat["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]["KHR_texture_transform"] = tt;
    mat["extensions"]["KHR_materials_unlit"] = json::object();
    g.j["materials"] = json::array({mat});
    g.j["textures"] = json::array({json{{"source", 0}}});
    g.j["images"] = json::array({json{{"uri", "missing.png"}}});
    meshNode(g, {prim({{"POSITION", pa}, {"COLOR_0", ca}}, -1, -1, 0)});
    ReadOptions ro;
    ro.requireImageData = false;
    Asset a = readGltf(g.writeGltf(dir, "c"), ro);
    ASSERT_EQ(a.mesh.wedges.color.size(), 3u);
    EXPECT_DOUBLE_EQ(a.mesh.wedges.color[0].x, 1.0);
    EXPECT_DOUBLE_EQ(a.mesh.wedges.color[0].w, 1.0);
    EXPECT_DOUBLE_EQ(a.mesh.wedges.color[1].x, 0.0);
    ASSERT_EQ(a.materials.size(), 1u);
    const Material& m = a.materials[0];
    EXPECT_TRUE(m.unlit);
    EXPECT_EQ(m.baseColor.texture, 0);
    EXPECT_TRUE(m.baseColor.transform.present);
    EXPECT_DOUBLE_EQ(m.baseColor.transform.offset.x, 0.5);
    EXPECT_DOUBLE_EQ(m.baseColor.transform.scale.y, 3);
    EXPECT_DOUBLE_EQ(m.baseColor.transform.rotation, 0.1);
    EXPECT_EQ(m.baseColor.transform.texCoord, 1);
    EXPECT_EQ(a.mesh.triangleMaterial[0], 0);
    // By default the missing image file is an error naming it.
    expectError([&] { readGltf((dir / "c.gltf").string()); }, ErrorKind::IO, (dir / "c.gltf").string(), "missing.png");
}

// KHR_draco_mesh_compression: cube encoded with Draco (14-bit positions), embedded in a GLB.
TEST(IoRead, DracoPrimitive) {
    auto dir = tempDir("draco");
    std::vector<float> pos, nrm;
    std::vector<uint16_t> idx;
    cubeData(pos, nrm, idx);
    draco::TriangleSoupMeshBuilder mb;
    mb.Start(12);
    int pAtt = mb.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    int nAtt = mb.AddAttribute(draco::GeometryAttribute::NORMAL, 3, draco::DT_FLOAT32);
    for (int f = 0; f < 12; ++f) {
        const float* v[3];
        const float* n[3];
        for (int k = 0; k < 3; ++k) { v[k] = &pos[3 * idx[size_t(3 * f + k)]]; n[k] = &nrm[3 * idx[size_t(3 * f + k)]]; }
        mb.SetAttributeValuesForFace(pAtt, draco::FaceIndex(uint32_t(f)), v[0], v[1], v[2]);
        mb.SetAttributeValuesForFace(nAtt, draco::FaceIndex(uint32_t(f)), n[0], n[1], n[2]);
    }
    std::unique_ptr<draco::Mesh> dm = mb.Finalize();
    ASSERT_TRUE(dm);
    draco::Encoder enc;
    enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 14);
    enc.SetAttributeQuantization(draco::GeometryAttribute::NORMAL, 10);
    draco::EncoderBuffer eb;
    ASSERT_TRUE(enc.EncodeMeshToBuffer(*dm, &eb).ok());
    TestGltf g;
    int view = g.view(eb.data(), eb.size());
    g.j["accessors"] = {{{"componentType", kF32}, {"count", dm->num_points()}, {"type", "VEC3"}},
                        {{"componentType", kF32}, {"count", dm->num_points()}, {"type", "VEC3"}},
                        {{"componentType", kU16}, {"count", 36}, {"type", "SCALAR"}}};
    json ext = {{"bufferView", view},
                {"attributes", {{"POSITION", dm->attribute(0)->unique_id()}, {"NORMAL", dm->attribute(1)->unique_id()}}}};
    g.j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
    g.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
    json dp = prim({{"POSITION", 0}, {"NORMAL", 1}}, 2);
    dp["extensions"]["KHR_draco_mesh_compression"] = ext;
    meshNode(g, {dp});
    Asset a = readGltf(g.writeGlb(dir, "draco.glb"));
    EXPECT_EQ(a.stats.dracoPrimitives, 1u);
    EXPECT_EQ(a.mesh.vertexCount(), 8u);
    EXPECT_EQ(a.mesh.triangleCount(), 12u);
    Box3 b = bounds(a.mesh);
    EXPECT_NEAR(b.min.x, 0, 1e-3);
    EXPECT_NEAR(b.max.z, 1, 1e-3);
    ASSERT_EQ(a.mesh.wedges.normal.size(), a.mesh.wedges.size());
    EXPECT_NEAR(length(a.mesh.wedges.normal[0]), 1.0, 1e-9);
}

// ------------------------------------------------------------------------------------------
// Errors

TEST(IoErrors, UnknownRequiredExtension) {
    auto dir = tempDir("extreq");
    TestGltf g;
    int pa = g.add(unitTrianglePositions(), kF32, "VEC3");
    meshNode(g, {prim(json{{"POSITION", pa}})});
    g.j["extensionsUsed"] = {"EXT_unknown_thing", "EXT_only_used"};
    g.j["extensionsRequired"] = {"EXT_unknown_thing"};
    std::string p = g.writeGltf(dir, "ext");
    expectError([&] { readGltf(p); }, ErrorKind::Unsupported, p, "EXT_unknown_thing");
}

TEST(IoErrors, TruncatedEmptyMissingNonJson) {
    auto dir = tempDir("bad");
    std::vector<float> pos, nrm;
    std::vector<uint16_t> idx;
    cubeData(pos, nrm, idx);
    TestGltf g;
    int p = g.add(pos, kF32, "VEC3"), i = g.add(idx, kU16, "SCALAR");
    meshNode(g, {prim(json{{"POSITION", p}}, i)});
    std::string bytes = g.glbBytes();
    for (size_t cut : {size_t(3), size_t(11), size_t(19), size_t(40), bytes.size() / 2, bytes.size() - 4}) {
        std::string t = (dir / ("trunc" + std::to_string(cut) + ".glb")).string();
        writeBytes(t, bytes.substr(0, cut));
        expectError([&] { readGltf(t); }, ErrorKind::InvalidInput, t);
    }
    std::string empty = (dir / "empty.glb").string();
    writeBytes(empty, "");
    expectError([&] { readGltf(empty); }, ErrorKind::InvalidInput, empty, "empty");
    std::string text = (dir / "text.gltf").string();
    writeBytes(text, "hello world");
    expectError([&] { readGltf(text); }, ErrorKind::InvalidInput, text);
    std::string broken = (dir / "broken.gltf").string();
    writeBytes(broken, "{\"asset\": {\"version\": \"2.0\"");
    expectError([&] { readGltf(broken); }, ErrorKind::InvalidInput, broken);
    std::string missing = (dir / "nope.glb").string();
    expectError([&] { readGltf(missing); }, ErrorKind::IO, missing);
}

TEST(IoErrors, NanPositionIndexRangeAndBounds) {
    auto dir = tempDir("invalid");
    {
        TestGltf g;
        std::vector<float> pos = unitTrianglePositions();
        pos[4] = std::nanf("");
        meshNode(g, {prim(json{{"POSITION", g.add(pos, kF32, "VEC3")}})});
        std::string p = g.writeGltf(dir, "nan");
        expectError([&] { readGltf(p); }, ErrorKind::InvalidInput, p, "non-finite");
    }
    {
        TestGltf g;
        std::vector<uint32_t> idx = {0, 1, 7};
        int pa = g.add(unitTrianglePositions(), kF32, "VEC3"), ia = g.add(idx, kU32, "SCALAR");
        meshNode(g, {prim(json{{"POSITION", pa}}, ia)});
        std::string p = g.writeGltf(dir, "idx");
        expectError([&] { readGltf(p); }, ErrorKind::InvalidInput, p, "index 7 out of range");
    }
    {
        TestGltf g;
        int pa = g.add(unitTrianglePositions(), kF32, "VEC3");
        g.j["accessors"][size_t(pa)]["count"] = 1000000000;  // far beyond the 36-byte view
        meshNode(g, {prim(json{{"POSITION", pa}})});
        std::string p = g.writeGltf(dir, "oob");
        expectError([&] { readGltf(p); }, ErrorKind::InvalidInput, p, "accessor 0");
    }
    {
        TestGltf g;
        int pa = g.add(unitTrianglePositions(), kF32, "VEC3");
        g.j["accessors"][size_t(pa)]["byteOffset"] = 4;  // 3 vertices no longer fit
        meshNode(g, {prim(json{{"POSITION", pa}})});
        std::string p = g.writeGltf(dir, "oob2");
        expectError([&] { readGltf(p); }, ErrorKind::InvalidInput, p, "exceed");
    }
    {
        TestGltf g;
        g.j["accessors"].push_back({{"componentType", kF32}, {"count", 4000000000ull}, {"type", "VEC3"}});
        meshNode(g, {prim(json{{"POSITION", 0}})});
        std::string p = g.writeGltf(dir, "huge");
        expectError([&] { readGltf(p); }, ErrorKind::InvalidInput, p, "too large");
    }
}

TEST(IoErrors, SharedBadInputsThrow) {
    fs::path bad = fs::path(sharedDir()) / "bad-inputs";
    if (!fs::exists(bad)) GTEST_SKIP() << "no " << bad;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(bad)) {
        std::string ext = e.path().extension().string();
        if (ext == ".gltf" || ext == ".glb") files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    for (const fs::path& f : files) {
        try {
            readGltf(f.string());
            ADD_FAILURE() << f << " was accepted";
        } catch (const Error& e) {
            std::string msg = e.what();
            std::cout << "  " << msg << "\n";
            EXPECT_EQ(msg.rfind(f.string(), 0), 0u) << msg;
            if (f.filename() == "MissingBin.gltf") {
                EXPECT_NE(msg.find(".bin"), std::string::npos) << msg;
            }
        }
    }
}

// ------------------------------------------------------------------------------------------
// Writing and LODBAKE_multires

namespace {

// A cube asset read from a synthetic file (float-exact positions), one material per 2 faces.
Asset cubeAsset(const fs::path& dir) {
    std::vector<float> pos, nrm;
    std::vector<uint16_t> idx;
    cubeData(pos, nrm, idx);
    std::vector<float> uv;
    for (size_t i = 0; i < pos.size() / 3; ++i) { uv.push_back(float(i % 4) * 0.25f); uv.push_back(float(i / 4) * 0.125f); }
    TestGltf g;
    int p = g.add(pos, kF32, "VEC3"), n = g.add(nrm, kF32, "VEC3"), t = g.add(uv, kF32, "VEC2");
    std::vector<uint16_t> a(idx.begin(), idx.begin() + 12), b(idx.begin() + 12, idx.end());
    int ia = g.add(a, kU16, "SCALAR"), ib = g.add(b, kU16, "SCALAR");
    g.j["materials"] = {{{"name", "red"}, {"pbrMetallicRoughness", {{"baseColorFactor", {1, 0, 0, 1}}}}},
                        {{"name", "green"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0, 1, 0, 1}}}}}};
    json attrs = {{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", t}};
    meshNode(g, {prim(attrs, ia, -1, 1), prim(attrs, ib, -1, 0)});
    return readGltf(g.writeGltf(dir, "cubesrc"));
}

Multires fakeMultires(const TriMesh& m) {
    Multires mr;
    mr.generator = "simplify";
    // Level 1: faces 0..9 survive; corners of faces 0/1 moved to vertex 0 where possible.
    for (int li = 0; li < 2; ++li) {
        Level L;
        L.targetRatio = li == 0 ? 0.5 : 0.1;
        L.targetTriangles = li == 0 ? 6 : 1;
        L.targetError = 0.125;
        L.stopReason = li == 0 ? "target" : "p-boundary";
        size_t keep = li == 0 ? 10 : 4;
        for (uint32_t f = 0; f < keep; ++f) {
            L.faces.push_back(f * (li + 1) % uint32_t(m.triangleCount()));
            L.triangles.push_back(m.triangles[L.faces.back()]);
            L.cornerWedges.push_back(m.cornerWedges[L.faces.back()]);
        }
        for (uint32_t f = 0; f < m.triangleCount(); ++f) L.faceRegion.push_back(f / (2 + uint32_t(li)) * (2 + uint32_t(li)));
        L.regionCount = 6 - uint32_t(li);
        if (li == 1) L.triangleMaterial = {1, -1, 0, 1};  // level 2: explicit per-triangle materials
        for (uint32_t v = 0; v < 3; ++v) {
            SimplificationPair s;
            s.vertex = v + uint32_t(li);
            s.coarse = {1, 2, 2};
            s.bary = {0.25f, 0.75f, 0.0f};
            s.face = 3 + v;
            s.deviation = 0.1f * float(v) + 1e-7f;
            L.pairs.push_back(s);
        }
        L.collapseCount = uint32_t(li + 1);
        L.maxDeviation = 0.1 * (li + 1) + 1e-13;
        L.meanDeviation = 1.0 / 3.0;
        L.seconds = 0.0123456789;
        mr.levels.push_back(L);
    }
    mr.collapses = {{7, 0, 0.05f, 0, 2}, {6, 1, 0.25f, 2, 3}};
    mr.regionUpdates = {{1, 0}, {3, 2}, {5, 4}};
    // A chart layout: two charts, UVs exactly representable as float.
    mr.charts.chartCount = 2;
    mr.charts.material = 0;
    mr.charts.image = -1;
    for (uint32_t f = 0; f < m.triangleCount(); ++f) {
        mr.charts.faceChart.push_back(f % 2);
        mr.charts.cornerUV.push_back({Vec2{0.25 * (f % 4), 0.5}, Vec2{0.125, 0.75}, Vec2{1.0 / 1024 * f, 0.0}});
    }
    mr.charts.islands.push_back({Tri{0, 2, 1}, {Vec2{0.875, 0.125}, Vec2{0.9375, 0.125}, Vec2{0.875, 0.25}}});
    return mr;
}

void expectSameMesh(const TriMesh& a, const TriMesh& b) {
    ASSERT_EQ(a.vertexCount(), b.vertexCount());
    for (size_t i = 0; i < a.vertexCount(); ++i) {
        EXPECT_EQ(a.positions[i].x, b.positions[i].x);
        EXPECT_EQ(a.positions[i].y, b.positions[i].y);
        EXPECT_EQ(a.positions[i].z, b.positions[i].z);
    }
    EXPECT_EQ(a.triangles, b.triangles);
    EXPECT_EQ(a.cornerWedges, b.cornerWedges);
    EXPECT_EQ(a.triangleMaterial, b.triangleMaterial);
    EXPECT_TRUE(a.wedges.vertex == b.wedges.vertex);
    ASSERT_EQ(a.wedges.uv0.size(), b.wedges.uv0.size());
    for (size_t i = 0; i < a.wedges.uv0.size(); ++i) {
        EXPECT_EQ(a.wedges.uv0[i].x, b.wedges.uv0[i].x);
        EXPECT_EQ(a.wedges.uv0[i].y, b.wedges.uv0[i].y);
    }
    ASSERT_EQ(a.wedges.normal.size(), b.wedges.normal.size());
    for (size_t i = 0; i < a.wedges.normal.size(); ++i) EXPECT_EQ(a.wedges.normal[i].z, b.wedges.normal[i].z);
}

void expectSameMultires(const Multires& a, const Multires& b) {
    EXPECT_EQ(a.generator, b.generator);
    ASSERT_EQ(a.levels.size(), b.levels.size());
    for (size_t i = 0; i < a.levels.size(); ++i) {
        const Level &x = a.levels[i], &y = b.levels[i];
        EXPECT_EQ(x.targetRatio, y.targetRatio);
        EXPECT_EQ(x.targetTriangles, y.targetTriangles);
        EXPECT_EQ(x.targetError, y.targetError);
        EXPECT_EQ(x.stopReason, y.stopReason);
        EXPECT_TRUE(x.faces == y.faces) << "faces: " << x.faces.size() << " vs " << y.faces.size();
        EXPECT_EQ(x.triangles, y.triangles);
        EXPECT_EQ(x.cornerWedges, y.cornerWedges);
        EXPECT_TRUE(x.faceRegion == y.faceRegion) << "faceRegion: " << x.faceRegion.size() << " vs " << y.faceRegion.size();
        EXPECT_EQ(x.regionCount, y.regionCount);
        EXPECT_EQ(x.triangleMaterial, y.triangleMaterial);
        ASSERT_EQ(x.pairs.size(), y.pairs.size());
        for (size_t k = 0; k < x.pairs.size(); ++k) {
            EXPECT_EQ(x.pairs[k].vertex, y.pairs[k].vertex);
            EXPECT_EQ(x.pairs[k].coarse, y.pairs[k].coarse);
            EXPECT_EQ(x.pairs[k].bary, y.pairs[k].bary);
            EXPECT_EQ(x.pairs[k].face, y.pairs[k].face);
            EXPECT_EQ(x.pairs[k].deviation, y.pairs[k].deviation);
        }
        EXPECT_EQ(x.collapseCount, y.collapseCount);
        EXPECT_EQ(x.maxDeviation, y.maxDeviation);
        EXPECT_EQ(x.meanDeviation, y.meanDeviation);
        EXPECT_EQ(y.seconds, 0.0);  // timings stay out of the file: output is byte-identical across runs
    }
    ASSERT_EQ(a.collapses.size(), b.collapses.size());
    for (size_t k = 0; k < a.collapses.size(); ++k) {
        EXPECT_EQ(a.collapses[k].removed, b.collapses[k].removed);
        EXPECT_EQ(a.collapses[k].kept, b.collapses[k].kept);
        EXPECT_EQ(a.collapses[k].deviation, b.collapses[k].deviation);
        EXPECT_EQ(a.collapses[k].regionBegin, b.collapses[k].regionBegin);
        EXPECT_EQ(a.collapses[k].regionEnd, b.collapses[k].regionEnd);
    }
    ASSERT_EQ(a.regionUpdates.size(), b.regionUpdates.size());
    for (size_t k = 0; k < a.regionUpdates.size(); ++k) {
        EXPECT_EQ(a.regionUpdates[k].oldRep, b.regionUpdates[k].oldRep);
        EXPECT_EQ(a.regionUpdates[k].newRep, b.regionUpdates[k].newRep);
    }
    EXPECT_EQ(a.charts.chartCount, b.charts.chartCount);
    EXPECT_EQ(a.charts.material, b.charts.material);
    EXPECT_EQ(a.charts.image, b.charts.image);
    EXPECT_EQ(a.charts.faceChart, b.charts.faceChart);
    ASSERT_EQ(a.charts.cornerUV.size(), b.charts.cornerUV.size());
    for (size_t f = 0; f < a.charts.cornerUV.size(); ++f)
        for (size_t k = 0; k < 3; ++k) {
            EXPECT_EQ(a.charts.cornerUV[f][k].x, b.charts.cornerUV[f][k].x);
            EXPECT_EQ(a.charts.cornerUV[f][k].y, b.charts.cornerUV[f][k].y);
        }
    ASSERT_EQ(a.charts.islands.size(), b.charts.islands.size());
    for (size_t i = 0; i < a.charts.islands.size(); ++i) {
        EXPECT_EQ(a.charts.islands[i].vertices, b.charts.islands[i].vertices);
        for (size_t k = 0; k < 3; ++k) {
            EXPECT_EQ(a.charts.islands[i].uv[k].x, b.charts.islands[i].uv[k].x);
            EXPECT_EQ(a.charts.islands[i].uv[k].y, b.charts.islands[i].uv[k].y);
        }
    }
}

}  // namespace

TEST(IoWrite, PlainRoundTrip) {
    auto dir = tempDir("plainrt");
    Asset a = cubeAsset(dir);
    ASSERT_EQ(a.mesh.triangleCount(), 12u);
    for (const char* name : {"out.glb", "out.gltf"}) {
        std::string p = (dir / name).string();
        writeGltf(p, a);
        std::optional<Multires> mr;
        Asset b = readGltf(p, {}, &mr);
        EXPECT_FALSE(mr.has_value());
        EXPECT_EQ(b.mesh.triangleCount(), 12u);
        EXPECT_EQ(b.mesh.vertexCount(), 8u);
        EXPECT_EQ(b.materials.size(), 2u);
        EXPECT_EQ(b.materials[1].name, "green");
    }
    EXPECT_TRUE(fs::exists(dir / "out.bin"));
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().string().find(".tmp-"), std::string::npos);
}

TEST(IoWrite, MultiresRoundTripIsExact) {
    auto dir = tempDir("mrrt");
    Asset a = cubeAsset(dir);
    // Make welding on re-read differ from the stored topology: permute welded ids.
    Multires mr = fakeMultires(a.mesh);
    for (const char* name : {"mr.glb", "mr.gltf"}) {
        std::string p = (dir / name).string();
        writeGltf(p, a, &mr);
        std::optional<Multires> back;
        Asset b = readGltf(p, {}, &back);
        ASSERT_TRUE(back.has_value());
        expectSameMesh(a.mesh, b.mesh);
        expectSameMultires(mr, *back);
        // Without a multires out-param, the mesh is still the original node only.
        Asset c = readGltf(p);
        EXPECT_EQ(c.mesh.triangleCount(), a.mesh.triangleCount());
    }
    // Deterministic: same input, byte-identical output.
    std::string p2 = (dir / "mr2.glb").string();
    writeGltf(p2, a, &mr);
    EXPECT_EQ(readBytes(dir / "mr.glb"), readBytes(p2));
}

// An attribute no primitive of the original has is absent after reading a multires file, and
// keeps no storage: the mesh stays loaded for a whole stage (parameterize, pack).
TEST(IoRead, MultiresAbsentAttributesHoldNoStorage) {
    auto dir = tempDir("mrabsent");
    Asset a = cubeAsset(dir);
    Multires mr = fakeMultires(a.mesh);
    std::string p = (dir / "mr.glb").string();
    writeGltf(p, a, &mr);
    std::optional<Multires> back;
    Asset b = readGltf(p, {}, &back);
    ASSERT_TRUE(back.has_value());
    const Wedges& w = b.mesh.wedges;
    EXPECT_EQ(w.normal.size(), w.size());  // the cube has normals and TEXCOORD_0
    EXPECT_EQ(w.uv0.size(), w.size());
    EXPECT_EQ(w.tangent.capacity(), 0u);
    EXPECT_EQ(w.uv1.capacity(), 0u);
    EXPECT_EQ(w.color.capacity(), 0u);
}

// Files are read in blocks: a GLB and a .bin of several blocks and a partial last one read as the
// same bytes handed over in memory.
TEST(IoRead, FileOfSeveralBlocksReadsWhole) {
    auto dir = tempDir("blocks");
    const uint32_t side = 150;  // 22500 vertices: a 270 KB position buffer
    std::vector<float> pos;
    std::vector<uint32_t> idx;
    for (uint32_t y = 0; y < side; ++y)
        for (uint32_t x = 0; x < side; ++x) pos.insert(pos.end(), {float(x), float(y), float((x * 7 + y * 3) % 5)});
    for (uint32_t y = 0; y + 1 < side; ++y)
        for (uint32_t x = 0; x + 1 < side; ++x) {
            uint32_t v = y * side + x;
            idx.insert(idx.end(), {v, v + 1, v + side, v + 1, v + side + 1, v + side});
        }
    TestGltf g;
    meshNode(g, {prim({{"POSITION", g.add(pos, kF32, "VEC3")}}, g.add(idx, kU32, "SCALAR"))});
    const std::string glb = g.writeGlb(dir, "grid.glb");
    const std::string gltf = g.writeGltf(dir, "grid");
    for (const fs::path& data : {fs::path(glb), dir / "grid.bin"}) {
        EXPECT_GT(fs::file_size(data), uintmax_t(4) << 16);
        EXPECT_NE(fs::file_size(data) % (uintmax_t(1) << 16), 0u);
    }
    for (const std::string& p : {glb, gltf}) {
        const std::string bytes = readBytes(p);
        Asset a = readGltf(p);
        Asset b = readGltfBytes(p, std::vector<unsigned char>(bytes.begin(), bytes.end()));
        EXPECT_EQ(a.mesh.triangleCount(), size_t(2) * (side - 1) * (side - 1));
        expectSameMesh(a.mesh, b.mesh);
    }
}

// A GLB's BIN chunk moves into the reader's buffer instead of being copied: what it reads is the
// .gltf's mesh whether buffer 0 fills the chunk or not, no file of the URI the hand-over uses is
// looked up (a .gltf may name one), and a buffer longer than the chunk is still an error.
TEST(IoRead, GlbBinChunkHandedOverReadsAsTheGltf) {
    auto dir = tempDir("binchunk");
    std::vector<float> pos, nrm;
    std::vector<uint16_t> idx;
    cubeData(pos, nrm, idx);
    TestGltf g;
    meshNode(g, {prim(json{{"POSITION", g.add(pos, kF32, "VEC3")}, {"NORMAL", g.add(nrm, kF32, "VEC3")}}, g.add(idx, kU16, "SCALAR"))});
    TestGltf named = g;
    const Asset reference = readGltf(g.writeGltf(dir, "cube"));
    const Asset plain = readGltf(g.writeGlb(dir, "cube.glb"));
    expectSameMesh(reference.mesh, plain.mesh);

    // Buffer 0 shorter than its chunk, beside a file named as the hand-over's URI.
    writeBytes(dir / "lodbake-glb-bin-chunk", "not a buffer");
    const std::string padded = (dir / "padded.glb").string();
    writeBytes(padded, TestGltf::glbOf(g.j, g.bin + std::string(8, '\0')));
    expectSameMesh(reference.mesh, readGltf(padded).mesh);
    const std::string bytes = readBytes(padded);
    expectSameMesh(reference.mesh, readGltfBytes(padded, std::vector<unsigned char>(bytes.begin(), bytes.end())).mesh);

    // A .gltf whose buffer file has that name reads the file.
    named.finishBuffer("lodbake-glb-bin-chunk");
    writeBytes(dir / "lodbake-glb-bin-chunk", named.bin);
    writeBytes(dir / "named.gltf", named.j.dump());
    expectSameMesh(reference.mesh, readGltf((dir / "named.gltf").string()).mesh);

    json longer = g.j;
    longer["buffers"][0]["byteLength"] = g.bin.size() + 4;
    const std::string bad = (dir / "longer.glb").string();
    writeBytes(bad, TestGltf::glbOf(longer, g.bin));
    expectError([&] { readGltf(bad); }, ErrorKind::InvalidInput, bad, "byteLength");
}

// In memory (the lodbake chain): encodeGlb gives the bytes writeGltf writes to a .glb, and
// readGltfBytes reads them as readGltf reads the file, messages naming the given path.
TEST(IoWrite, InMemoryGlbMatchesTheFile) {
    auto dir = tempDir("memglb");
    Asset a = cubeAsset(dir);
    Multires mr = fakeMultires(a.mesh);
    std::string p = (dir / "mr.glb").string();
    WriteOptions opt;
    opt.generator = "lodbake test";
    writeGltf(p, a, &mr, opt);
    std::vector<unsigned char> bytes = encodeGlb("memory:mr.glb", a, &mr, opt);
    std::string file = readBytes(p);
    EXPECT_EQ(std::string(bytes.begin(), bytes.end()), file);

    std::optional<Multires> back;
    Asset b = readGltfBytes("memory:mr.glb", bytes, {}, &back);
    ASSERT_TRUE(back.has_value());
    expectSameMesh(a.mesh, b.mesh);
    expectSameMultires(mr, *back);
    EXPECT_EQ(b.sourcePath, "memory:mr.glb");

    EXPECT_THROW(encodeGlb("memory:mr.gltf", a, &mr), IOError);
    std::vector<unsigned char> cut(bytes.begin(), bytes.begin() + 40);
    try {
        readGltfBytes("memory:cut.glb", cut);
        FAIL() << "a truncated GLB was read";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).rfind("memory:cut.glb: ", 0), 0u) << e.what();
    }
}

// A version 1 file (one (face, oldRep, newRep) record per relabelled face) reads as the per-region
// records of version 2: the consecutive repeats of each collapse's range are dropped.
TEST(IoRead, MultiresVersion1RegionUpdates) {
    auto dir = tempDir("mrv1");
    Asset a = cubeAsset(dir);
    Multires mr = fakeMultires(a.mesh);
    ASSERT_EQ(mr.regionUpdates.size(), 3u);  // {1, 0}, {3, 2} | {5, 4}
    std::string p = (dir / "v1.gltf").string();
    writeGltf(p, a, &mr);
    json j = json::parse(readBytes(p));
    std::string bin = readBytes(dir / j["buffers"][0]["uri"].get<std::string>());
    auto addU32 = [&](const std::vector<uint32_t>& v, const char* type) {
        while (bin.size() % 4) bin.push_back('\0');
        j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", 4 * v.size()}});
        bin.append(reinterpret_cast<const char*>(v.data()), 4 * v.size());
        size_t per = std::string(type) == "VEC3" ? 3 : 2;
        j["accessors"].push_back({{"bufferView", j["bufferViews"].size() - 1}, {"componentType", kU32},
                                  {"count", v.size() / per}, {"type", type}});
        return j["accessors"].size() - 1;
    };
    json& ext = j["extensions"]["LODBAKE_multires"];
    ext["version"] = 1;
    // Faces 1 and 4 of region 1 join region 0, face 3 joins 2; then faces 5 and 9 of region 5 join 4.
    ext["regionUpdates"] = addU32({1, 1, 0, 4, 1, 0, 3, 3, 2, 5, 5, 4, 9, 5, 4}, "VEC3");
    ext["collapses"]["regions"] = addU32({0, 3, 3, 5}, "VEC2");
    j["buffers"][0]["byteLength"] = bin.size();
    writeBytes(dir / j["buffers"][0]["uri"].get<std::string>(), bin);
    writeBytes(p, j.dump());
    std::optional<Multires> back;
    readGltf(p, {}, &back);
    ASSERT_TRUE(back.has_value());
    expectSameMultires(mr, *back);
}

// Stored topology wins over welding: two vertices at the same position stay distinct.
TEST(IoWrite, MultiresKeepsUnweldedTopology) {
    auto dir = tempDir("mrtopo");
    Asset a;
    //  v0=(0,0,0) v1=(1,0,0) v2=(0,1,0) v3=(1,1,0), v4 = copy of v1 (a seam not welded).
    a.mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    a.mesh.triangles = {{0, 1, 2}, {4, 3, 2}};
    a.mesh.cornerWedges = {{0, 1, 2}, {3, 4, 2}};
    a.mesh.triangleMaterial = {-1, -1};
    a.mesh.wedges.vertex = {0, 1, 2, 4, 3};
    Multires mr;
    Level L;
    L.faces = {0};
    L.triangles = {{0, 1, 2}};
    L.cornerWedges = {{0, 1, 2}};
    L.faceRegion = {0, 0};
    L.regionCount = 1;
    mr.levels.push_back(L);
    std::string p = (dir / "topo.glb").string();
    writeGltf(p, a, &mr);
    std::optional<Multires> back;
    Asset b = readGltf(p, {}, &back);
    expectSameMesh(a.mesh, b.mesh);
    ASSERT_TRUE(back);
    expectSameMultires(mr, *back);
    TriMesh l1 = levelMesh(b.mesh, *back, 1);
    EXPECT_EQ(l1.triangleCount(), 1u);
    EXPECT_EQ(l1.triangleMaterial, std::vector<int32_t>{-1});
}

TEST(IoWrite, LevelMeshUsesOriginalMaterials) {
    auto dir = tempDir("levelmesh");
    Asset a = cubeAsset(dir);
    Multires mr = fakeMultires(a.mesh);
    TriMesh l0 = levelMesh(a.mesh, mr, 0);
    EXPECT_EQ(l0.triangles, a.mesh.triangles);
    TriMesh l1 = levelMesh(a.mesh, mr, 1);
    ASSERT_EQ(l1.triangleCount(), mr.levels[0].faces.size());
    for (size_t i = 0; i < l1.triangleCount(); ++i) EXPECT_EQ(l1.triangleMaterial[i], a.mesh.triangleMaterial[mr.levels[0].faces[i]]);
    TriMesh l2 = levelMesh(a.mesh, mr, 2);  // explicit Level::triangleMaterial wins
    EXPECT_EQ(l2.triangleMaterial, mr.levels[1].triangleMaterial);
    EXPECT_EQ(l2.positions.size(), a.mesh.positions.size());
    EXPECT_THROW(levelMesh(a.mesh, mr, 3), Error);
}

// ------------------------------------------------------------------------------------------
// Real assets (../shared/assets)

TEST(IoAssets, ReadAndRewriteRealAssets) {
    fs::path assets = fs::path(sharedDir()) / "assets";
    if (!fs::exists(assets)) GTEST_SKIP() << "no " << assets;
    auto dir = tempDir("assets");
    for (const char* rel : {"Duck/Duck.glb", "Avocado/Avocado.gltf", "BoxTextured/BoxTextured.glb",
                            "CesiumMilkTruck/CesiumMilkTruck.glb", "2CylinderEngine/2CylinderEngine.glb",
                            "StanfordBunny/StanfordBunny.glb"}) {
        fs::path p = assets / rel;
        if (!fs::exists(p)) { std::cout << "  (missing " << p << ")\n"; continue; }
        Asset a = readGltf(p.string());
        checkImages(a);
        std::cout << "  " << rel << ": " << a.mesh.triangleCount() << " triangles, " << a.mesh.vertexCount()
                  << " welded vertices, " << a.mesh.wedges.size() << " wedges, " << a.materials.size() << " materials, "
                  << a.images.size() << " images, " << a.warnings.size() << " warnings\n";
        EXPECT_GT(a.mesh.triangleCount(), 0u) << rel;
        for (const Image& img : a.images) EXPECT_GT(img.width, 0) << rel;
        std::string out = (dir / (p.stem().string() + ".glb")).string();
        writeGltf(out, a);
        Asset b = readGltf(out);
        EXPECT_EQ(b.mesh.triangleCount(), a.mesh.triangleCount()) << rel;
        EXPECT_EQ(b.images.size(), a.images.size()) << rel;
    }
}

// The header check reads a JPEG's size and channels from its frame header: they agree with the
// full decode's, on every JPEG of the shared assets and on one written here (grey and colour).
TEST(IoAssets, JpegHeaderCheckAgreesWithDecode) {
    std::vector<Image> jpegs;
    for (int channels : {1, 3}) {
        EncodeOptions o;
        o.format = ImageFormat::Jpeg;
        o.channels = channels;
        std::vector<float> values(size_t(37) * 21 * size_t(channels));
        for (size_t i = 0; i < values.size(); ++i) values[i] = float(i % 251) / 250.f;
        jpegs.push_back(encodeImage(values, 37, 21, o, "generated"));
    }
    fs::path assets = fs::path(sharedDir()) / "assets";
    if (fs::exists(assets))
        for (const auto& entry : fs::recursive_directory_iterator(assets)) {
            const std::string ext = entry.path().extension().string();
            if (ext != ".glb" && ext != ".gltf") continue;
            for (Image& img : readGltf(entry.path().string()).images)
                if (img.mimeType == "image/jpeg") jpegs.push_back(std::move(img));
        }
    for (const Image& jpeg : jpegs) {
        Asset header, decoded;
        header.images = {jpeg};
        decoded.images = {jpeg};
        header.images[0].width = header.images[0].height = header.images[0].channels = 0;
        decoded.images[0].width = decoded.images[0].height = decoded.images[0].channels = 0;
        checkImages(header, ImageCheck::Header);
        checkImages(decoded, ImageCheck::Decode);
        EXPECT_EQ(header.images[0].width, decoded.images[0].width) << jpeg.name;
        EXPECT_EQ(header.images[0].height, decoded.images[0].height) << jpeg.name;
        EXPECT_EQ(header.images[0].channels, decoded.images[0].channels) << jpeg.name;
    }
    EXPECT_GE(jpegs.size(), 2u);
}
