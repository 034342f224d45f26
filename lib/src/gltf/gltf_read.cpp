// glTF 2.0 reader: tinygltf parses JSON and loads buffers/images (kept encoded); everything
// else (accessor decoding with bounds checks, Draco, transforms, welding, LODBAKE_multires) is
// done here.
//
// Pipeline of readGltf:
//   1. read the file bytes, detect GLB/JSON by magic, let tinygltf load the model;
//   2. parse the raw JSON again with nlohmann (extensions, materials, LODBAKE_multires);
//   3. check extensionsRequired;
//   4. flatten the scene, decode each triangle primitive, weld by world position;
//      (or, for a file with LODBAKE_multires, rebuild the original TriMesh exactly);
//   5. materials, textures, samplers, images (kept encoded; lodbake/texture/codec.h checks them).

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>

#include <draco/compression/decode.h>
#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

#include "gltf/gltf_internal.h"
#include "lodbake/core/errors.h"
#include "lodbake/gltf/gltf.h"

namespace lodbake {
namespace {

using json = nlohmann::json;
using namespace gltf_detail;

// Limit on elements of an accessor that has no bufferView (all zeros or sparse only): such an
// accessor costs no file bytes, so its count must be capped before we allocate.
constexpr size_t kMaxVirtualCount = size_t(1) << 26;

struct Ctx {
    std::string path;
    const tinygltf::Model* model = nullptr;
    json root;
};

[[noreturn]] void fail(const Ctx& c, const std::string& what) { throw InvalidInput(c.path + ": " + what); }

// ---------------------------------------------------------------------------------------------
// Accessor decoding

int componentCount(int type) {
    switch (type) {
        case TINYGLTF_TYPE_SCALAR: return 1;
        case TINYGLTF_TYPE_VEC2: return 2;
        case TINYGLTF_TYPE_VEC3: return 3;
        case TINYGLTF_TYPE_VEC4: return 4;
        case TINYGLTF_TYPE_MAT2: return 4;
        case TINYGLTF_TYPE_MAT3: return 9;
        case TINYGLTF_TYPE_MAT4: return 16;
    }
    return 0;
}

int componentSize(int ct) {
    switch (ct) {
        case kByte: case kUnsignedByte: return 1;
        case kShort: case kUnsignedShort: return 2;
        case kUnsignedInt: case kFloat: return 4;
    }
    return 0;
}

double readComponent(const unsigned char* p, int ct, bool normalized) {
    switch (ct) {
        case kByte: { int8_t v; std::memcpy(&v, p, 1); return normalized ? std::max(v / 127.0, -1.0) : v; }
        case kUnsignedByte: { uint8_t v = *p; return normalized ? v / 255.0 : v; }
        case kShort: { int16_t v; std::memcpy(&v, p, 2); return normalized ? std::max(v / 32767.0, -1.0) : v; }
        case kUnsignedShort: { uint16_t v; std::memcpy(&v, p, 2); return normalized ? v / 65535.0 : v; }
        case kUnsignedInt: { uint32_t v; std::memcpy(&v, p, 4); return normalized ? v / 4294967295.0 : v; }
        case kFloat: { float v; std::memcpy(&v, p, 4); return v; }
    }
    return 0;
}

struct AccessorData {
    size_t count = 0;
    int comps = 0;
    std::vector<double> v;  // count * comps, normalisation applied
    double at(size_t i, int c) const { return v[i * size_t(comps) + size_t(c)]; }
};

// The bytes [offset, offset + length) of bufferView `viewIndex`, bounds-checked against its buffer.
const unsigned char* viewBytes(const Ctx& c, int viewIndex, size_t& length, const std::string& what) {
    const auto& m = *c.model;
    if (viewIndex < 0 || size_t(viewIndex) >= m.bufferViews.size())
        fail(c, what + ": bufferView " + std::to_string(viewIndex) + " does not exist");
    const auto& view = m.bufferViews[size_t(viewIndex)];
    if (view.buffer < 0 || size_t(view.buffer) >= m.buffers.size())
        fail(c, what + ": bufferView " + std::to_string(viewIndex) + " names missing buffer " + std::to_string(view.buffer));
    const auto& buf = m.buffers[size_t(view.buffer)];
    if (view.byteOffset > buf.data.size() || view.byteLength > buf.data.size() - view.byteOffset)
        fail(c, what + ": bufferView " + std::to_string(viewIndex) + " (offset " + std::to_string(view.byteOffset) +
                    ", length " + std::to_string(view.byteLength) + ") exceeds buffer " + std::to_string(view.buffer) +
                    " (" + std::to_string(buf.data.size()) + " bytes)");
    length = view.byteLength;
    return buf.data.data() + view.byteOffset;
}

// Reads `count` elements of `comps` components of type `ct` from a view, bounds-checked.
void readStrided(const Ctx& c, int viewIndex, size_t byteOffset, size_t count, int comps, int ct, bool normalized,
                 bool allowStride, double* out, const std::string& what) {
    if (count == 0) return;
    size_t length = 0;
    const unsigned char* base = viewBytes(c, viewIndex, length, what);
    size_t csize = size_t(componentSize(ct));
    size_t elem = csize * size_t(comps);
    size_t stride = elem;
    if (allowStride) {
        size_t s = c.model->bufferViews[size_t(viewIndex)].byteStride;
        if (s != 0) {
            if (s < elem) fail(c, what + ": byteStride " + std::to_string(s) + " smaller than element size " + std::to_string(elem));
            stride = s;
        }
    }
    // offset + stride*(count-1) + elem <= length, without overflow.
    if (byteOffset > length || count - 1 > (length - byteOffset) / stride ||
        byteOffset + stride * (count - 1) + elem > length)
        fail(c, what + ": " + std::to_string(count) + " elements at offset " + std::to_string(byteOffset) + " stride " +
                    std::to_string(stride) + " exceed bufferView " + std::to_string(viewIndex) + " (" + std::to_string(length) +
                    " bytes)");
    for (size_t i = 0; i < count; ++i) {
        const unsigned char* p = base + byteOffset + i * stride;
        for (int k = 0; k < comps; ++k) out[i * size_t(comps) + size_t(k)] = readComponent(p + size_t(k) * csize, ct, normalized);
    }
}

AccessorData readAccessor(const Ctx& c, int index, const std::string& what, bool forceNormalize = false) {
    const auto& m = *c.model;
    std::string w = what + ": accessor " + std::to_string(index);
    if (index < 0 || size_t(index) >= m.accessors.size()) fail(c, w + " does not exist");
    const auto& acc = m.accessors[size_t(index)];
    AccessorData d;
    d.comps = componentCount(acc.type);
    int csize = componentSize(acc.componentType);
    if (d.comps == 0 || csize == 0) fail(c, w + ": invalid type/componentType");
    bool normalized = acc.normalized || (forceNormalize && acc.componentType != kFloat);
    d.count = acc.count;
    if (acc.bufferView >= 0) {
        size_t length = 0;
        viewBytes(c, acc.bufferView, length, w);
        if (d.count > length) fail(c, w + ": count " + std::to_string(d.count) + " exceeds its bufferView");
    } else if (d.count > kMaxVirtualCount) {
        fail(c, w + ": count " + std::to_string(d.count) + " without bufferView is too large");
    }
    d.v.assign(d.count * size_t(d.comps), 0.0);
    if (acc.bufferView >= 0)
        readStrided(c, acc.bufferView, acc.byteOffset, d.count, d.comps, acc.componentType, normalized, true, d.v.data(), w);
    if (acc.sparse.isSparse) {
        int sc = acc.sparse.count;
        if (sc < 0 || size_t(sc) > d.count) fail(c, w + ": sparse count " + std::to_string(sc) + " out of range");
        int ict = acc.sparse.indices.componentType;
        if (ict != kUnsignedByte && ict != kUnsignedShort && ict != kUnsignedInt) fail(c, w + ": invalid sparse index type");
        if (acc.sparse.indices.byteOffset < 0 || acc.sparse.values.byteOffset < 0) fail(c, w + ": negative sparse byteOffset");
        std::vector<double> idx(static_cast<size_t>(sc));
        std::vector<double> vals(static_cast<size_t>(sc) * size_t(d.comps));
        readStrided(c, acc.sparse.indices.bufferView, size_t(acc.sparse.indices.byteOffset), size_t(sc), 1, ict, false, false,
                    idx.data(), w + " sparse indices");
        readStrided(c, acc.sparse.values.bufferView, size_t(acc.sparse.values.byteOffset), size_t(sc), d.comps,
                    acc.componentType, normalized, false, vals.data(), w + " sparse values");
        for (size_t i = 0; i < size_t(sc); ++i) {
            if (idx[i] >= double(d.count)) fail(c, w + ": sparse index " + std::to_string(uint64_t(idx[i])) + " out of range");
            size_t t = size_t(idx[i]);
            for (int k = 0; k < d.comps; ++k) d.v[t * size_t(d.comps) + size_t(k)] = vals[i * size_t(d.comps) + size_t(k)];
        }
    }
    return d;
}

std::vector<uint32_t> readU32(const Ctx& c, int index, int comps, const std::string& what) {
    if (index < 0) return {};
    AccessorData d = readAccessor(c, index, what);
    if (d.comps != comps) fail(c, what + ": accessor " + std::to_string(index) + " has " + std::to_string(d.comps) + " components, expected " + std::to_string(comps));
    std::vector<uint32_t> out(d.v.size());
    for (size_t i = 0; i < d.v.size(); ++i) {
        double x = d.v[i];
        if (!(x >= 0 && x <= 4294967295.0)) fail(c, what + ": value out of range");
        out[i] = uint32_t(x);
    }
    return out;
}

std::vector<float> readF32(const Ctx& c, int index, int comps, const std::string& what) {
    if (index < 0) return {};
    AccessorData d = readAccessor(c, index, what);
    if (d.comps != comps) fail(c, what + ": accessor " + std::to_string(index) + " has " + std::to_string(d.comps) + " components, expected " + std::to_string(comps));
    std::vector<float> out(d.v.size());
    for (size_t i = 0; i < d.v.size(); ++i) out[i] = float(d.v[i]);
    return out;
}

// ---------------------------------------------------------------------------------------------
// Primitive decoding (glTF-local data, before transforms)

struct PrimData {
    std::vector<Vec3> pos;
    std::vector<Vec3> normal;
    std::vector<Vec4> tangent;
    std::vector<Vec2> uv0, uv1;
    std::vector<Vec4> color;
    std::vector<Tri> tris;  // glTF vertex indices, glTF winding
};

void assembleTriangles(const Ctx& c, const std::vector<uint32_t>& idx, int mode, PrimData& p, const std::string& what) {
    size_t n = idx.size();
    for (uint32_t i : idx)
        if (i >= p.pos.size())
            fail(c, what + ": index " + std::to_string(i) + " out of range (" + std::to_string(p.pos.size()) + " vertices)");
    if (mode == TINYGLTF_MODE_TRIANGLES) {
        p.tris.reserve(n / 3);
        for (size_t i = 0; i + 2 < n; i += 3) p.tris.push_back({idx[i], idx[i + 1], idx[i + 2]});
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        for (size_t i = 0; i + 2 < n; ++i) {
            if (i % 2 == 0) p.tris.push_back({idx[i], idx[i + 1], idx[i + 2]});
            else p.tris.push_back({idx[i + 1], idx[i], idx[i + 2]});
        }
    } else {  // fan
        for (size_t i = 1; i + 1 < n; ++i) p.tris.push_back({idx[0], idx[i], idx[i + 1]});
    }
}

void checkFinitePositions(const Ctx& c, const PrimData& p, const std::string& what) {
    for (size_t i = 0; i < p.pos.size(); ++i)
        if (!isFinite(p.pos[i])) fail(c, what + ": vertex " + std::to_string(i) + " has a non-finite position");
}

void decodeDraco(const Ctx& c, const json& ext, PrimData& p, const std::string& what) {
    std::string w = what + ": KHR_draco_mesh_compression";
    if (!ext.is_object() || !ext.contains("bufferView") || !ext["bufferView"].is_number_integer())
        fail(c, w + ": missing bufferView");
    size_t length = 0;
    const unsigned char* bytes = viewBytes(c, ext["bufferView"].get<int>(), length, w);
    draco::DecoderBuffer buffer;
    buffer.Init(reinterpret_cast<const char*>(bytes), length);
    draco::Decoder decoder;
    auto status = decoder.DecodeMeshFromBuffer(&buffer);
    if (!status.ok()) fail(c, w + ": cannot decode: " + status.status().error_msg_string());
    std::unique_ptr<draco::Mesh> mesh = std::move(status).value();
    size_t nPoints = mesh->num_points();
    auto attr = [&](const char* name, int comps) -> std::vector<float> {
        if (!ext.contains("attributes") || !ext["attributes"].is_object() || !ext["attributes"].contains(name)) return {};
        const json& id = ext["attributes"][name];
        if (!id.is_number_integer()) fail(c, w + ": attribute " + name + " id is not an integer");
        const draco::PointAttribute* a = mesh->GetAttributeByUniqueId(id.get<uint32_t>());
        if (!a) fail(c, w + ": attribute " + name + " (id " + id.dump() + ") not in the Draco data");
        std::vector<float> out(nPoints * size_t(comps), comps == 4 ? 1.0f : 0.0f);
        for (size_t i = 0; i < nPoints; ++i) {
            float tmp[4] = {0, 0, 0, 1};
            int nc = std::min<int>(comps, a->num_components());
            if (!a->ConvertValue<float>(a->mapped_index(draco::PointIndex(uint32_t(i))), int8_t(nc), tmp))
                fail(c, w + ": cannot convert attribute " + name);
            for (int k = 0; k < nc; ++k) out[i * size_t(comps) + size_t(k)] = tmp[k];
        }
        if (comps == 4 && std::string(name) == "COLOR_0") {
            // num_components 3 → alpha 1 stays from the fill value
        }
        return out;
    };
    std::vector<float> P = attr("POSITION", 3);
    if (P.empty()) fail(c, w + ": no POSITION attribute");
    p.pos.resize(nPoints);
    for (size_t i = 0; i < nPoints; ++i) p.pos[i] = {P[3 * i], P[3 * i + 1], P[3 * i + 2]};
    std::vector<float> N = attr("NORMAL", 3);
    if (!N.empty()) { p.normal.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.normal[i] = {N[3 * i], N[3 * i + 1], N[3 * i + 2]}; }
    std::vector<float> T = attr("TANGENT", 4);
    if (!T.empty()) { p.tangent.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.tangent[i] = {T[4 * i], T[4 * i + 1], T[4 * i + 2], T[4 * i + 3]}; }
    std::vector<float> U0 = attr("TEXCOORD_0", 2);
    if (!U0.empty()) { p.uv0.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.uv0[i] = {U0[2 * i], U0[2 * i + 1]}; }
    std::vector<float> U1 = attr("TEXCOORD_1", 2);
    if (!U1.empty()) { p.uv1.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.uv1[i] = {U1[2 * i], U1[2 * i + 1]}; }
    std::vector<float> C = attr("COLOR_0", 4);
    if (!C.empty()) { p.color.resize(nPoints); for (size_t i = 0; i < nPoints; ++i) p.color[i] = {C[4 * i], C[4 * i + 1], C[4 * i + 2], C[4 * i + 3]}; }
    std::vector<uint32_t> idx;
    idx.reserve(size_t(mesh->num_faces()) * 3);
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
        const auto& face = mesh->face(f);
        for (int k = 0; k < 3; ++k) idx.push_back(face[k].value());
    }
    assembleTriangles(c, idx, TINYGLTF_MODE_TRIANGLES, p, w);
    checkFinitePositions(c, p, w);
}

// Decodes one primitive; returns false (with a warning) for primitives we drop.
bool decodePrimitive(const Ctx& c, int meshIndex, int primIndex, Asset& asset, PrimData& p) {
    const auto& prim = c.model->meshes[size_t(meshIndex)].primitives[size_t(primIndex)];
    std::string what = "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(primIndex);
    int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (prim.mode < -1 || mode > TINYGLTF_MODE_TRIANGLE_FAN) fail(c, what + ": invalid mode " + std::to_string(mode) + " (glTF modes are 0 to 6)");
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        asset.warnings.push_back(what + ": mode " + std::to_string(mode) + " (points/lines) dropped");
        asset.stats.droppedPrimitives++;
        return false;
    }
    if (!prim.targets.empty()) asset.warnings.push_back(what + ": morph targets ignored");
    const json* draco = nullptr;
    const json& jp = c.root["meshes"][size_t(meshIndex)]["primitives"][size_t(primIndex)];
    if (jp.contains("extensions") && jp["extensions"].is_object() && jp["extensions"].contains("KHR_draco_mesh_compression"))
        draco = &jp["extensions"]["KHR_draco_mesh_compression"];
    if (draco) {
        decodeDraco(c, *draco, p, what);
        asset.stats.dracoPrimitives++;
        return true;
    }
    auto attrIndex = [&](const char* name) {
        auto it = prim.attributes.find(name);
        return it == prim.attributes.end() ? -1 : it->second;
    };
    int posIdx = attrIndex("POSITION");
    if (posIdx < 0) {
        asset.warnings.push_back(what + ": no POSITION attribute, dropped");
        asset.stats.droppedPrimitives++;
        return false;
    }
    AccessorData P = readAccessor(c, posIdx, what + " POSITION");
    if (P.comps != 3) fail(c, what + ": POSITION is not VEC3");
    size_t n = P.count;
    p.pos.resize(n);
    for (size_t i = 0; i < n; ++i) p.pos[i] = {P.at(i, 0), P.at(i, 1), P.at(i, 2)};
    checkFinitePositions(c, p, what);
    auto readAttr = [&](const char* name, bool forceNorm, const std::vector<int>& comps) -> AccessorData {
        int ai = attrIndex(name);
        if (ai < 0) return {};
        AccessorData d = readAccessor(c, ai, what + " " + name, forceNorm);
        if (std::find(comps.begin(), comps.end(), d.comps) == comps.end()) fail(c, what + ": " + name + " has wrong type");
        if (d.count != n) fail(c, what + ": " + name + " count " + std::to_string(d.count) + " differs from POSITION count " + std::to_string(n));
        return d;
    };
    AccessorData N = readAttr("NORMAL", false, {3});
    if (N.count) { p.normal.resize(n); for (size_t i = 0; i < n; ++i) p.normal[i] = {N.at(i, 0), N.at(i, 1), N.at(i, 2)}; }
    AccessorData T = readAttr("TANGENT", false, {4});
    if (T.count) { p.tangent.resize(n); for (size_t i = 0; i < n; ++i) p.tangent[i] = {T.at(i, 0), T.at(i, 1), T.at(i, 2), T.at(i, 3)}; }
    AccessorData U0 = readAttr("TEXCOORD_0", false, {2});
    if (U0.count) { p.uv0.resize(n); for (size_t i = 0; i < n; ++i) p.uv0[i] = {U0.at(i, 0), U0.at(i, 1)}; }
    AccessorData U1 = readAttr("TEXCOORD_1", false, {2});
    if (U1.count) { p.uv1.resize(n); for (size_t i = 0; i < n; ++i) p.uv1[i] = {U1.at(i, 0), U1.at(i, 1)}; }
    AccessorData C = readAttr("COLOR_0", true, {3, 4});
    if (C.count) {
        p.color.resize(n);
        for (size_t i = 0; i < n; ++i) p.color[i] = {C.at(i, 0), C.at(i, 1), C.at(i, 2), C.comps == 4 ? C.at(i, 3) : 1.0};
    }
    std::vector<uint32_t> idx;
    if (prim.indices >= 0) {
        AccessorData I = readAccessor(c, prim.indices, what + " indices");
        const auto& acc = c.model->accessors[size_t(prim.indices)];
        if (I.comps != 1 || acc.componentType == kFloat || acc.componentType == kByte || acc.componentType == kShort)
            fail(c, what + ": indices accessor must be unsigned SCALAR");
        idx.resize(I.count);
        for (size_t i = 0; i < I.count; ++i) idx[i] = uint32_t(I.v[i]);
    } else {
        if (n > std::numeric_limits<uint32_t>::max()) fail(c, what + ": too many vertices");
        idx.resize(n);
        for (size_t i = 0; i < n; ++i) idx[i] = uint32_t(i);
    }
    assembleTriangles(c, idx, mode, p, what);
    return true;
}

// ---------------------------------------------------------------------------------------------
// Transforms and welding

Mat4 nodeMatrix(const tinygltf::Node& node) {
    if (node.matrix.size() == 16) {
        Mat4 m;
        for (int i = 0; i < 16; ++i) m[size_t(i)] = node.matrix[size_t(i)];
        return m;
    }
    Mat4 t = identity4(), r = identity4(), s = identity4();
    if (node.translation.size() == 3) { t[12] = node.translation[0]; t[13] = node.translation[1]; t[14] = node.translation[2]; }
    if (node.rotation.size() == 4) {
        double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
        double l = std::sqrt(x * x + y * y + z * z + w * w);
        if (l > 0) { x /= l; y /= l; z /= l; w /= l; }
        r = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0,
             2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0,
             2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0,
             0, 0, 0, 1};
    }
    if (node.scale.size() == 3) { s[0] = node.scale[0]; s[5] = node.scale[1]; s[10] = node.scale[2]; }
    return mul(t, mul(r, s));
}

// Cofactor matrix of the upper 3x3: (M^-1)^T = C / det.
std::array<double, 9> cofactor3(const Mat4& m) {
    auto M = [&](int r, int c) { return m[size_t(c * 4 + r)]; };
    std::array<double, 9> C{};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
            C[size_t(r * 3 + c)] = M((r + 1) % 3, (c + 1) % 3) * M((r + 2) % 3, (c + 2) % 3) -
                                   M((r + 1) % 3, (c + 2) % 3) * M((r + 2) % 3, (c + 1) % 3);
    return C;
}

struct PosKey {
    uint64_t b[3];
    bool operator==(const PosKey& o) const { return b[0] == o.b[0] && b[1] == o.b[1] && b[2] == o.b[2]; }
};
// A position's hash for the weld table. Positions read from floats leave the low 29 mantissa bits
// zero, so the words are mixed (MurmurHash3's 64-bit finaliser) before the table's low bits are used.
uint64_t hashOf(const PosKey& k) {
    uint64_t h = 0;
    for (uint64_t x : k.b) {
        h = (h ^ x) * 0x9e3779b97f4a7c15ull;
        h ^= h >> 33;
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
        h *= 0xc4ceb9fe1a85ec53ull;
        h ^= h >> 33;
    }
    return h;
}

// Welding by exact position: an open-addressing table (linear probing) of welded vertex ids, which
// are handed out in order of first appearance (id = number of positions before it).
class PositionWeld {
public:
    // Room for `more` new positions without rehashing (geometric growth: many small primitives
    // stay linear).
    void reserve(size_t more) {
        size_t need = 2 * (keys_.size() + more), cap = std::max<size_t>(64, slots_.size());
        while (cap < need) cap *= 2;
        if (cap != slots_.size()) rehash(cap);
        if (keys_.capacity() < keys_.size() + more) keys_.reserve(std::max(keys_.size() + more, 2 * keys_.capacity()));
    }
    // The id of `k`; a new key gets the next id (`inserted` is then true).
    uint32_t insert(const PosKey& k, bool& inserted) {
        if (2 * (keys_.size() + 1) > slots_.size()) reserve(std::max<size_t>(keys_.size(), 32));
        const size_t mask = slots_.size() - 1;
        for (size_t i = size_t(hashOf(k)) & mask;; i = (i + 1) & mask) {
            const uint32_t id = slots_[i];
            if (id == kEmpty) {
                slots_[i] = uint32_t(keys_.size());
                keys_.push_back(k);
                inserted = true;
                return slots_[i];
            }
            if (keys_[id] == k) {
                inserted = false;
                return id;
            }
        }
    }

private:
    static constexpr uint32_t kEmpty = ~0u;
    std::vector<uint32_t> slots_;
    std::vector<PosKey> keys_;

    void rehash(size_t cap) {
        slots_.assign(cap, kEmpty);
        for (uint32_t id = 0; id < keys_.size(); ++id)
            for (size_t i = size_t(hashOf(keys_[id])) & (cap - 1);; i = (i + 1) & (cap - 1))
                if (slots_[i] == kEmpty) {
                    slots_[i] = id;
                    break;
                }
    }
};

PosKey keyOf(Vec3 p) {
    PosKey k;
    double v[3] = {p.x + 0.0, p.y + 0.0, p.z + 0.0};  // + 0.0 turns -0 into +0
    for (int i = 0; i < 3; ++i) std::memcpy(&k.b[i], &v[i], 8);
    return k;
}

struct MeshBuilder {
    TriMesh mesh;
    PositionWeld weld;
    // Wedge attributes are stored once a primitive has them (earlier wedges get the defaults).
    bool hasNormal = false, hasTangent = false, hasUv0 = false, hasUv1 = false, hasColor = false;
    size_t degenerate = 0;

    void add(const Ctx& c, const PrimData& p, const Mat4& world, int material, const std::string& what) {
        double det = det3(world);
        double sgn = det < 0 ? -1.0 : 1.0;
        std::array<double, 9> C = cofactor3(world);
        std::vector<Vec3> wp(p.pos.size());
        std::vector<PosKey> keys(p.pos.size());
        for (size_t i = 0; i < wp.size(); ++i) {
            wp[i] = transformPoint(world, p.pos[i]);
            if (!isFinite(wp[i])) fail(c, what + ": vertex " + std::to_string(i) + " has a non-finite world position");
            keys[i] = keyOf(wp[i]);
        }
        Wedges& W = mesh.wedges;
        const size_t wedges = W.vertex.size();
        auto start = [&](bool& has, bool present, auto& column, auto fill) {
            if (present && !has) column.assign(wedges, fill);
            has |= present;
        };
        start(hasNormal, !p.normal.empty(), W.normal, Vec3{0, 0, 0});
        start(hasTangent, !p.tangent.empty(), W.tangent, Vec4{1, 0, 0, 1});
        start(hasUv0, !p.uv0.empty(), W.uv0, Vec2{0, 0});
        start(hasUv1, !p.uv1.empty(), W.uv1, Vec2{0, 0});
        start(hasColor, !p.color.empty(), W.color, Vec4{1, 1, 1, 1});
        std::vector<int64_t> local(p.pos.size(), -1);
        // Room for this primitive up front (geometric growth: many small primitives stay linear).
        auto grow = [](auto& v, size_t more) {
            if (v.capacity() < v.size() + more) v.reserve(std::max(v.size() + more, 2 * v.capacity()));
        };
        size_t nv = p.pos.size(), nt = p.tris.size();
        weld.reserve(nv);
        grow(mesh.positions, nv);
        grow(W.vertex, nv);
        if (hasNormal) grow(W.normal, nv);
        if (hasTangent) grow(W.tangent, nv);
        if (hasUv0) grow(W.uv0, nv);
        if (hasUv1) grow(W.uv1, nv);
        if (hasColor) grow(W.color, nv);
        grow(mesh.cornerWedges, nt);
        grow(mesh.triangles, nt);
        grow(mesh.triangleMaterial, nt);
        auto wedgeOf = [&](uint32_t i) -> uint32_t {
            if (local[i] >= 0) return uint32_t(local[i]);
            bool inserted = false;
            uint32_t v = weld.insert(keys[i], inserted);
            if (inserted) mesh.positions.push_back(Vec3{wp[i].x + 0.0, wp[i].y + 0.0, wp[i].z + 0.0});
            uint32_t w = uint32_t(W.vertex.size());
            W.vertex.push_back(v);
            if (hasNormal) {
                Vec3 n{0, 0, 0};
                if (!p.normal.empty()) {
                    Vec3 a = p.normal[i];
                    n = normalize(Vec3{C[0] * a.x + C[1] * a.y + C[2] * a.z, C[3] * a.x + C[4] * a.y + C[5] * a.z,
                                       C[6] * a.x + C[7] * a.y + C[8] * a.z}) * sgn;
                    if (!isFinite(n)) n = {0, 0, 0};
                }
                W.normal.push_back(n);
            }
            if (hasTangent) {
                Vec4 t{1, 0, 0, 1};
                if (!p.tangent.empty()) {
                    Vec3 d = normalize(transformVector(world, Vec3{p.tangent[i].x, p.tangent[i].y, p.tangent[i].z}));
                    t = {d.x, d.y, d.z, (p.tangent[i].w < 0 ? -1.0 : 1.0) * sgn};
                }
                W.tangent.push_back(t);
            }
            if (hasUv0) W.uv0.push_back(p.uv0.empty() ? Vec2{0, 0} : p.uv0[i]);
            if (hasUv1) W.uv1.push_back(p.uv1.empty() ? Vec2{0, 0} : p.uv1[i]);
            if (hasColor) W.color.push_back(p.color.empty() ? Vec4{1, 1, 1, 1} : p.color[i]);
            local[i] = w;
            return w;
        };
        for (Tri t : p.tris) {
            if (det < 0) std::swap(t[1], t[2]);
            if (keys[t[0]] == keys[t[1]] || keys[t[1]] == keys[t[2]] || keys[t[0]] == keys[t[2]]) {
                degenerate++;
                continue;
            }
            Tri cw{wedgeOf(t[0]), wedgeOf(t[1]), wedgeOf(t[2])};
            mesh.cornerWedges.push_back(cw);
            mesh.triangles.push_back({W.vertex[cw[0]], W.vertex[cw[1]], W.vertex[cw[2]]});
            mesh.triangleMaterial.push_back(material);
        }
    }

    void finish(Asset& asset) {
        if (degenerate) asset.warnings.push_back(std::to_string(degenerate) + " degenerate triangles dropped");
        asset.mesh = std::move(mesh);
    }
};

// World matrices of the mesh nodes reachable from `roots`, in depth-first order.
void collectNodes(const Ctx& c, int node, const Mat4& parent, std::vector<char>& onStack,
                  std::vector<std::pair<int, Mat4>>& out, size_t& visited) {
    const auto& m = *c.model;
    if (node < 0 || size_t(node) >= m.nodes.size()) fail(c, "node " + std::to_string(node) + " does not exist");
    if (onStack[size_t(node)]) fail(c, "node " + std::to_string(node) + " is part of a cycle");
    onStack[size_t(node)] = 1;
    visited++;
    Mat4 world = mul(parent, nodeMatrix(m.nodes[size_t(node)]));
    out.emplace_back(node, world);
    for (int child : m.nodes[size_t(node)].children) collectNodes(c, child, world, onStack, out, visited);
    onStack[size_t(node)] = 0;
}

// ---------------------------------------------------------------------------------------------
// LODBAKE_multires

int jint(const json& o, const char* key, int def = -1) {
    return o.contains(key) && o[key].is_number_integer() ? o[key].get<int>() : def;
}

// Rebuilds the original TriMesh exactly from mesh `meshIndex` and the extension's maps.
TriMesh rebuildOriginal(const Ctx& c, const json& ext, const json& orig, int meshIndex, const Mat4& world, Asset& asset) {
    std::string what = std::string(kMultiresExtension) + ": original";
    TriMesh mesh;
    size_t V = orig.value("vertexCount", size_t(0)), F = orig.value("faceCount", size_t(0));
    std::vector<uint32_t> wedgeVertex = readU32(c, jint(orig, "wedgeVertex"), 1, what + " wedgeVertex");
    std::vector<uint32_t> faceVertices = readU32(c, jint(orig, "faceVertices"), 3, what + " faceVertices");
    size_t W = wedgeVertex.size();
    if (faceVertices.size() != 3 * F) fail(c, what + ": faceVertices count differs from faceCount");
    for (uint32_t v : wedgeVertex) if (v >= V) fail(c, what + ": wedgeVertex entry out of range");
    for (uint32_t v : faceVertices) if (v >= V) fail(c, what + ": faceVertices entry out of range");
    mesh.positions.assign(V, Vec3{});
    mesh.triangles.resize(F);
    mesh.cornerWedges.assign(F, Tri{0, 0, 0});
    mesh.triangleMaterial.assign(F, -1);
    mesh.wedges.vertex = wedgeVertex;
    std::vector<char> faceSeen(F, 0);
    for (size_t f = 0; f < F; ++f) mesh.triangles[f] = {faceVertices[3 * f], faceVertices[3 * f + 1], faceVertices[3 * f + 2]};
    const json& prims = orig.contains("primitives") ? orig["primitives"] : json::array();
    size_t nPrims = meshIndex >= 0 ? c.model->meshes[size_t(meshIndex)].primitives.size() : 0;
    if (!prims.is_array() || prims.size() != nPrims) fail(c, what + ": primitive maps do not match mesh " + std::to_string(meshIndex));
    bool hasN = false, hasT = false, hasU0 = false, hasU1 = false, hasC = false;
    Wedges& Wd = mesh.wedges;
    Wd.normal.assign(W, Vec3{}); Wd.tangent.assign(W, Vec4{1, 0, 0, 1}); Wd.uv0.assign(W, Vec2{});
    Wd.uv1.assign(W, Vec2{}); Wd.color.assign(W, Vec4{1, 1, 1, 1});
    for (size_t pi = 0; pi < nPrims; ++pi) {
        PrimData p;
        if (!decodePrimitive(c, meshIndex, int(pi), asset, p)) fail(c, what + ": primitive " + std::to_string(pi) + " is not a triangle primitive");
        asset.stats.primitives++;
        asset.stats.inputVertices += p.pos.size();
        int material = c.model->meshes[size_t(meshIndex)].primitives[pi].material;
        std::vector<uint32_t> wedges = readU32(c, jint(prims[pi], "wedges"), 1, what + " primitive wedges");
        std::vector<uint32_t> faces = readU32(c, jint(prims[pi], "faces"), 1, what + " primitive faces");
        if (wedges.size() != p.pos.size() || faces.size() != p.tris.size())
            fail(c, what + ": primitive " + std::to_string(pi) + " maps do not match its vertices/triangles");
        hasN |= !p.normal.empty(); hasT |= !p.tangent.empty(); hasU0 |= !p.uv0.empty(); hasU1 |= !p.uv1.empty(); hasC |= !p.color.empty();
        for (size_t i = 0; i < wedges.size(); ++i) {
            uint32_t w = wedges[i];
            if (w >= W) fail(c, what + ": wedge id out of range");
            if (!p.normal.empty()) Wd.normal[w] = p.normal[i];
            if (!p.tangent.empty()) Wd.tangent[w] = p.tangent[i];
            if (!p.uv0.empty()) Wd.uv0[w] = p.uv0[i];
            if (!p.uv1.empty()) Wd.uv1[w] = p.uv1[i];
            if (!p.color.empty()) Wd.color[w] = p.color[i];
        }
        for (size_t t = 0; t < faces.size(); ++t) {
            uint32_t f = faces[t];
            if (f >= F) fail(c, what + ": face id out of range");
            faceSeen[f] = 1;
            for (int k = 0; k < 3; ++k) {
                uint32_t li = p.tris[t][size_t(k)];
                mesh.cornerWedges[f][size_t(k)] = wedges[li];
                mesh.positions[mesh.triangles[f][size_t(k)]] = transformPoint(world, p.pos[li]);
            }
            mesh.triangleMaterial[f] = material;
        }
    }
    for (size_t f = 0; f < F; ++f) if (!faceSeen[f]) fail(c, what + ": face " + std::to_string(f) + " is in no primitive");
    // Wedges used only by levels (parameterize's atlas UVs): attributes from the level primitives.
    std::vector<char> wedgeSeen(W, 0);
    for (const Tri& cw : mesh.cornerWedges) for (uint32_t w : cw) wedgeSeen[w] = 1;
    const json& levelsJ = ext.contains("levels") && ext["levels"].is_array() ? ext["levels"] : json::array();
    for (size_t li = 0; li < levelsJ.size(); ++li) {
        const json& L = levelsJ[li];
        int lm = jint(L, "mesh");
        if (!L.contains("primitives") || lm < 0 || size_t(lm) >= c.model->meshes.size()) continue;
        const json& lp = L["primitives"];
        if (!lp.is_array() || lp.size() != c.model->meshes[size_t(lm)].primitives.size())
            fail(c, what + ": level " + std::to_string(li + 1) + " primitive maps do not match its mesh");
        for (size_t pi = 0; pi < lp.size(); ++pi) {
            std::vector<uint32_t> wedges = readU32(c, jint(lp[pi], "wedges"), 1, what + " level primitive wedges");
            bool needed = false;
            for (uint32_t w : wedges) {
                if (w >= W) fail(c, what + ": level wedge id out of range");
                needed |= !wedgeSeen[w];
            }
            if (!needed) continue;
            PrimData p;
            if (!decodePrimitive(c, lm, int(pi), asset, p) || wedges.size() != p.pos.size())
                fail(c, what + ": level " + std::to_string(li + 1) + " primitive maps do not match its vertices");
            hasN |= !p.normal.empty(); hasT |= !p.tangent.empty(); hasU0 |= !p.uv0.empty(); hasU1 |= !p.uv1.empty(); hasC |= !p.color.empty();
            for (size_t i = 0; i < wedges.size(); ++i) {
                uint32_t w = wedges[i];
                if (wedgeSeen[w] == 1) continue;
                wedgeSeen[w] = 2;
                if (!p.normal.empty()) Wd.normal[w] = p.normal[i];  // level nodes only translate
                if (!p.tangent.empty()) Wd.tangent[w] = p.tangent[i];
                if (!p.uv0.empty()) Wd.uv0[w] = p.uv0[i];
                if (!p.uv1.empty()) Wd.uv1[w] = p.uv1[i];
                if (!p.color.empty()) Wd.color[w] = p.color[i];
            }
        }
    }
    if (!hasN) Wd.normal.clear();
    if (!hasT) Wd.tangent.clear();
    if (!hasU0) Wd.uv0.clear();
    if (!hasU1) Wd.uv1.clear();
    if (!hasC) Wd.color.clear();
    return mesh;
}

// A chart layout (charts, or a textureHierarchy rank), checked against the original mesh.
ChartLayout readLayout(const Ctx& c, const json& C, const TriMesh& mesh, const std::string& what) {
    const size_t V = mesh.vertexCount(), F = mesh.triangleCount();
    auto checkRange = [&](const std::vector<uint32_t>& v, size_t limit, const std::string& name) {
        for (uint32_t x : v) if (x >= limit) fail(c, what + ": " + name + " entry " + std::to_string(x) + " out of range");
    };
    ChartLayout ch;
    ch.chartCount = uint32_t(std::max(0, jint(C, "count", 0)));
    ch.image = jint(C, "image");
    ch.faceChart = readU32(c, jint(C, "faceChart"), 1, what + " faceChart");
    std::vector<float> uv = readF32(c, jint(C, "cornerUV"), 2, what + " cornerUV");
    if (ch.faceChart.size() != F || uv.size() != 6 * F) fail(c, what + ": accessors do not match the face count");
    checkRange(ch.faceChart, ch.chartCount, "faceChart");
    ch.cornerUV.resize(F);
    for (size_t f = 0; f < F; ++f)
        for (size_t k = 0; k < 3; ++k) ch.cornerUV[f][k] = {uv[6 * f + 2 * k], uv[6 * f + 2 * k + 1]};
    if (C.contains("islandVertices")) {
        std::vector<uint32_t> iv = readU32(c, jint(C, "islandVertices"), 1, what + " islandVertices");
        std::vector<float> iuv = readF32(c, jint(C, "islandUV"), 2, what + " islandUV");
        if (iv.size() % 3 != 0 || iuv.size() != 2 * iv.size()) fail(c, what + ": island accessors do not match");
        checkRange(iv, V, "islandVertices");
        ch.islands.resize(iv.size() / 3);
        for (size_t i = 0; i < ch.islands.size(); ++i)
            for (size_t k = 0; k < 3; ++k) {
                ch.islands[i].vertices[k] = iv[3 * i + k];
                ch.islands[i].uv[k] = {iuv[6 * i + 2 * k], iuv[6 * i + 2 * k + 1]};
            }
    }
    return ch;
}

// Version 1 files: a region's faces were listed one after another with the same (oldRep, newRep),
// so the consecutive repeats within each collapse's range are dropped.
void upgradePerFaceUpdates(Multires& mr) {
    std::vector<RegionUpdate> out;
    for (CollapseRecord& r : mr.collapses) {
        const uint32_t begin = uint32_t(out.size());
        for (uint32_t u = r.regionBegin; u < r.regionEnd; ++u) {
            const RegionUpdate& up = mr.regionUpdates[u];
            if (out.size() == begin || out.back().oldRep != up.oldRep || out.back().newRep != up.newRep) out.push_back(up);
        }
        r.regionBegin = begin;
        r.regionEnd = uint32_t(out.size());
    }
    mr.regionUpdates = std::move(out);
}

Multires readMultires(const Ctx& c, const json& ext, const TriMesh& mesh) {
    std::string what = kMultiresExtension;
    Multires mr;
    mr.generator = ext.value("generator", std::string("simplify"));
    size_t V = mesh.vertexCount(), F = mesh.triangleCount(), W = mesh.wedges.size();
    auto checkRange = [&](const std::vector<uint32_t>& v, size_t limit, const std::string& name) {
        for (uint32_t x : v) if (x >= limit) fail(c, what + ": " + name + " entry " + std::to_string(x) + " out of range");
    };
    if (ext.contains("levels")) {
        if (!ext["levels"].is_array()) fail(c, what + ": levels is not an array");
        for (size_t li = 0; li < ext["levels"].size(); ++li) {
            const json& L = ext["levels"][li];
            std::string lw = what + " level " + std::to_string(li + 1);
            Level lv;
            lv.targetRatio = L.value("targetRatio", 0.0);
            lv.targetTriangles = L.value("targetTriangles", uint64_t(0));
            lv.targetError = L.value("targetError", 0.0);
            lv.stopReason = L.value("stopReason", std::string());
            lv.regionCount = L.value("regionCount", uint32_t(0));
            lv.collapseCount = L.value("collapseCount", uint32_t(0));
            lv.maxDeviation = L.value("maxDeviation", 0.0);
            lv.meanDeviation = L.value("meanDeviation", 0.0);
            lv.faces = readU32(c, jint(L, "faces"), 1, lw + " faces");
            std::vector<uint32_t> t = readU32(c, jint(L, "triangles"), 3, lw + " triangles");
            std::vector<uint32_t> cw = readU32(c, jint(L, "cornerWedges"), 3, lw + " cornerWedges");
            lv.faceRegion = readU32(c, jint(L, "faceRegion"), 1, lw + " faceRegion");
            std::vector<uint32_t> tm = readU32(c, jint(L, "triangleMaterial"), 1, lw + " triangleMaterial");
            lv.triangleMaterial.assign(tm.begin(), tm.end());  // uint32 bit patterns back to int32 (-1)
            checkRange(lv.faces, F, "faces");
            checkRange(t, V, "triangles");
            checkRange(cw, W, "cornerWedges");
            checkRange(lv.faceRegion, F, "faceRegion");
            if (t.size() != 3 * lv.faces.size() || cw.size() != t.size()) fail(c, lw + ": faces/triangles/cornerWedges counts differ");
            if (!lv.faceRegion.empty() && lv.faceRegion.size() != F) fail(c, lw + ": faceRegion count differs from face count");
            if (!lv.triangleMaterial.empty() && lv.triangleMaterial.size() != lv.faces.size())
                fail(c, lw + ": triangleMaterial count differs from triangle count");
            lv.triangles.resize(lv.faces.size());
            lv.cornerWedges.resize(lv.faces.size());
            for (size_t i = 0; i < lv.faces.size(); ++i) {
                lv.triangles[i] = {t[3 * i], t[3 * i + 1], t[3 * i + 2]};
                lv.cornerWedges[i] = {cw[3 * i], cw[3 * i + 1], cw[3 * i + 2]};
            }
            if (L.contains("pairs")) {
                const json& P = L["pairs"];
                std::vector<uint32_t> pv = readU32(c, jint(P, "vertex"), 1, lw + " pairs.vertex");
                std::vector<uint32_t> pc = readU32(c, jint(P, "coarse"), 3, lw + " pairs.coarse");
                std::vector<float> pb = readF32(c, jint(P, "bary"), 3, lw + " pairs.bary");
                std::vector<uint32_t> pf = readU32(c, jint(P, "face"), 1, lw + " pairs.face");
                std::vector<float> pd = readF32(c, jint(P, "deviation"), 1, lw + " pairs.deviation");
                size_t n = pv.size();
                if (pc.size() != 3 * n || pb.size() != 3 * n || pf.size() != n || pd.size() != n)
                    fail(c, lw + ": pairs accessors have different counts");
                checkRange(pv, V, "pairs.vertex");
                checkRange(pc, V, "pairs.coarse");
                checkRange(pf, F, "pairs.face");
                lv.pairs.resize(n);
                for (size_t i = 0; i < n; ++i) {
                    SimplificationPair& s = lv.pairs[i];
                    s.vertex = pv[i];
                    s.coarse = {pc[3 * i], pc[3 * i + 1], pc[3 * i + 2]};
                    s.bary = {pb[3 * i], pb[3 * i + 1], pb[3 * i + 2]};
                    s.face = pf[i];
                    s.deviation = pd[i];
                }
            }
            mr.levels.push_back(std::move(lv));
        }
    }
    if (ext.contains("collapses")) {
        const json& C = ext["collapses"];
        std::vector<uint32_t> vk = readU32(c, jint(C, "vertices"), 2, what + " collapses.vertices");
        std::vector<float> dev = readF32(c, jint(C, "deviation"), 1, what + " collapses.deviation");
        std::vector<uint32_t> rg = readU32(c, jint(C, "regions"), 2, what + " collapses.regions");
        size_t n = dev.size();
        if (vk.size() != 2 * n || rg.size() != 2 * n) fail(c, what + ": collapses accessors have different counts");
        checkRange(vk, V, "collapses.vertices");
        mr.collapses.resize(n);
        for (size_t i = 0; i < n; ++i) mr.collapses[i] = {vk[2 * i], vk[2 * i + 1], dev[i], rg[2 * i], rg[2 * i + 1]};
    }
    // Version 1 listed one (face, oldRep, newRep) record per relabelled face; version 2 one
    // (oldRep, newRep) per region.
    const bool perFace = ext.value("version", 1) < 2;
    if (ext.contains("regionUpdates")) {
        const size_t width = perFace ? 3 : 2;
        std::vector<uint32_t> ru = readU32(c, jint(ext, "regionUpdates"), int(width), what + " regionUpdates");
        checkRange(ru, F, "regionUpdates");
        mr.regionUpdates.resize(ru.size() / width);
        for (size_t i = 0; i < mr.regionUpdates.size(); ++i)
            mr.regionUpdates[i] = {ru[width * i + width - 2], ru[width * i + width - 1]};
    }
    for (const CollapseRecord& r : mr.collapses)
        if (r.regionBegin > r.regionEnd || r.regionEnd > mr.regionUpdates.size()) fail(c, what + ": collapse region range out of bounds");
    if (perFace) upgradePerFaceUpdates(mr);
    if (ext.contains("charts")) {
        mr.charts = readLayout(c, ext["charts"], mesh, what + " charts");
        mr.charts.material = jint(ext["charts"], "material");
    }
    if (ext.contains("textureHierarchy")) {
        // Written by texture-refine: rank layouts (same schema as charts) and the textures.
        const json& T = ext["textureHierarchy"];
        const std::string tw = what + " textureHierarchy";
        if (!T.is_object()) fail(c, tw + " is not an object");
        const size_t images = c.model ? c.model->images.size() : 0;
        if (T.contains("ranks")) {
            if (!T["ranks"].is_array()) fail(c, tw + ".ranks is not an array");
            for (const json& R : T["ranks"]) {
                ChartLayout lay = readLayout(c, R, mesh, tw + " rank");
                if (lay.image >= int(images)) fail(c, tw + ": rank image out of range");
                mr.textures.ranks.push_back(std::move(lay));
            }
        }
        if (T.contains("textures")) {
            if (!T["textures"].is_array()) fail(c, tw + ".textures is not an array");
            for (const json& X : T["textures"]) {
                HierarchyTexture h;
                int rank = jint(X, "rank", 0), first = -1, last = -1;
                if (X.contains("levels") && X["levels"].is_array() && X["levels"].size() == 2 &&
                    X["levels"][0].is_number_integer() && X["levels"][1].is_number_integer()) {
                    first = X["levels"][0].get<int>();
                    last = X["levels"][1].get<int>();
                }
                h.image = jint(X, "image");
                h.size = jint(X, "size", 0);
                if (rank < 0 || size_t(rank) > mr.textures.ranks.size()) fail(c, tw + ": texture rank out of range");
                if (first < 0 || last < first || size_t(last) > mr.levels.size()) fail(c, tw + ": texture levels out of range");
                if (h.image < 0 || h.image >= int(images) || h.size <= 0) fail(c, tw + ": texture image or size out of range");
                h.rank = uint32_t(rank);
                h.firstLevel = uint32_t(first);
                h.lastLevel = uint32_t(last);
                mr.textures.textures.push_back(h);
            }
        }
        if (!mr.textures.textures.empty() && mr.charts.empty()) fail(c, tw + " without charts");
    }
    return mr;
}

// ---------------------------------------------------------------------------------------------
// Materials, textures, images

TextureRef readTextureRef(const json& o, const char* scaleKey) {
    TextureRef r;
    if (!o.is_object()) return r;
    r.texture = jint(o, "index", -1);
    r.texCoord = jint(o, "texCoord", 0);
    if (scaleKey && o.contains(scaleKey) && o[scaleKey].is_number()) r.scale = o[scaleKey].get<double>();
    if (o.contains("extensions") && o["extensions"].is_object() && o["extensions"].contains("KHR_texture_transform")) {
        const json& t = o["extensions"]["KHR_texture_transform"];
        TextureTransform& x = r.transform;
        x.present = true;
        if (t.contains("offset") && t["offset"].is_array() && t["offset"].size() == 2) x.offset = {t["offset"][0].get<double>(), t["offset"][1].get<double>()};
        if (t.contains("scale") && t["scale"].is_array() && t["scale"].size() == 2) x.scale = {t["scale"][0].get<double>(), t["scale"][1].get<double>()};
        if (t.contains("rotation") && t["rotation"].is_number()) x.rotation = t["rotation"].get<double>();
        x.texCoord = jint(t, "texCoord", -1);
    }
    return r;
}

Material readMaterial(const json& m) {
    Material mat;
    mat.name = m.value("name", std::string());
    if (m.contains("pbrMetallicRoughness") && m["pbrMetallicRoughness"].is_object()) {
        const json& p = m["pbrMetallicRoughness"];
        if (p.contains("baseColorFactor") && p["baseColorFactor"].is_array() && p["baseColorFactor"].size() == 4) {
            const json& f = p["baseColorFactor"];
            mat.baseColorFactor = {f[0].get<double>(), f[1].get<double>(), f[2].get<double>(), f[3].get<double>()};
        }
        mat.metallicFactor = p.value("metallicFactor", 1.0);
        mat.roughnessFactor = p.value("roughnessFactor", 1.0);
        if (p.contains("baseColorTexture")) mat.baseColor = readTextureRef(p["baseColorTexture"], nullptr);
        if (p.contains("metallicRoughnessTexture")) mat.metallicRoughness = readTextureRef(p["metallicRoughnessTexture"], nullptr);
    }
    if (m.contains("normalTexture")) mat.normal = readTextureRef(m["normalTexture"], "scale");
    if (m.contains("occlusionTexture")) mat.occlusion = readTextureRef(m["occlusionTexture"], "strength");
    if (m.contains("emissiveTexture")) mat.emissive = readTextureRef(m["emissiveTexture"], nullptr);
    if (m.contains("emissiveFactor") && m["emissiveFactor"].is_array() && m["emissiveFactor"].size() == 3) {
        const json& f = m["emissiveFactor"];
        mat.emissiveFactor = {f[0].get<double>(), f[1].get<double>(), f[2].get<double>()};
    }
    std::string mode = m.value("alphaMode", std::string("OPAQUE"));
    mat.alphaMode = mode == "MASK" ? AlphaMode::Mask : mode == "BLEND" ? AlphaMode::Blend : AlphaMode::Opaque;
    mat.alphaCutoff = m.value("alphaCutoff", 0.5);
    mat.doubleSided = m.value("doubleSided", false);
    mat.unlit = m.contains("extensions") && m["extensions"].is_object() && m["extensions"].contains("KHR_materials_unlit");
    return mat;
}

// tinygltf's image callback; user data: the model being loaded (its buffers are in place). tinygltf
// hands over a bufferView's bytes without checking them against the buffer: do it here.
bool keepImageBytes(tinygltf::Image* image, const int index, std::string* err, std::string*, int, int,
                    const unsigned char* bytes, int size, void* userData) {
    const auto* model = static_cast<const tinygltf::Model*>(userData);
    if (image->bufferView >= 0) {
        const tinygltf::BufferView& view = model->bufferViews[size_t(image->bufferView)];
        const size_t bufferSize = model->buffers[size_t(view.buffer)].data.size();
        if (view.byteOffset > bufferSize || view.byteLength > bufferSize - view.byteOffset || size < 0) {
            if (err)
                *err += "image " + std::to_string(index) + ": bufferView " + std::to_string(image->bufferView) + " (offset " +
                        std::to_string(view.byteOffset) + ", length " + std::to_string(view.byteLength) +
                        ") exceeds its buffer (" + std::to_string(bufferSize) + " bytes)\n";
            return false;
        }
    }
    image->image.assign(bytes, bytes + std::max(size, 0));
    image->width = image->height = -1;
    image->component = -1;
    return true;
}

std::vector<unsigned char> readFileBytes(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw IOError(path + ": cannot open: " + std::strerror(errno));
    std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    if (f.bad()) throw IOError(path + ": cannot read: " + std::strerror(errno));
    return bytes;
}

// ReadOptions::lod: replaces each scene root carrying MSFT_lod by its level `lod`.
std::vector<int> selectMsftLod(const Ctx& c, const std::vector<int>& roots, int lod, const std::string& path) {
    std::vector<int> out;
    bool any = false;
    const json* nodes = c.root.contains("nodes") && c.root["nodes"].is_array() ? &c.root["nodes"] : nullptr;
    for (int r : roots) {
        const json* chain = nullptr;
        if (nodes && r >= 0 && size_t(r) < nodes->size()) {
            const json& n = (*nodes)[size_t(r)];
            if (n.contains("extensions") && n["extensions"].is_object() && n["extensions"].contains("MSFT_lod") &&
                n["extensions"]["MSFT_lod"].is_object() && n["extensions"]["MSFT_lod"].contains("ids") &&
                n["extensions"]["MSFT_lod"]["ids"].is_array())
                chain = &n["extensions"]["MSFT_lod"]["ids"];
        }
        if (!chain) { out.push_back(r); continue; }
        any = true;
        if (lod == 0) { out.push_back(r); continue; }
        if (size_t(lod) > chain->size())
            throw Impossible(path + ": --lod " + std::to_string(lod) + " asked but node " + std::to_string(r) + "'s MSFT_lod chain has " +
                             std::to_string(chain->size() + 1) + " levels");
        const json& id = (*chain)[size_t(lod) - 1];
        if (!id.is_number_integer() || id.get<long long>() < 0 || size_t(id.get<long long>()) >= nodes->size())
            fail(c, "node " + std::to_string(r) + ": MSFT_lod id out of range");
        out.push_back(id.get<int>());
    }
    if (!any && lod > 0) throw Impossible(path + ": --lod " + std::to_string(lod) + " asked but the file has no MSFT_lod chain");
    return out;
}

const std::vector<std::string> kSupportedRequired = {"KHR_draco_mesh_compression", "KHR_mesh_quantization",
                                                     "KHR_texture_transform", "KHR_materials_unlit"};

}  // namespace

Asset readGltf(const std::string& path, const ReadOptions& options, std::optional<Multires>* multires) {
    if (std::filesystem::is_directory(path)) throw IOError(path + ": is a directory");
    std::vector<unsigned char> bytes = readFileBytes(path);
    Ctx c;
    c.path = path;
    if (bytes.empty()) fail(c, "empty file");

    // 1. tinygltf loads the model (buffers, images kept encoded).
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keepImageBytes, &model);
    std::string err, warn;
    std::string baseDir = std::filesystem::path(path).parent_path().string();
    if (baseDir.empty()) baseDir = ".";
    bool isGlb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    std::string jsonText;
    if (isGlb) {
        if (bytes.size() < 20) fail(c, "truncated GLB (" + std::to_string(bytes.size()) + " bytes)");
        uint32_t total = 0, chunkLen = 0, chunkType = 0;
        std::memcpy(&total, bytes.data() + 8, 4);
        std::memcpy(&chunkLen, bytes.data() + 12, 4);
        std::memcpy(&chunkType, bytes.data() + 16, 4);
        if (total > bytes.size()) fail(c, "truncated GLB (header says " + std::to_string(total) + " bytes, file has " + std::to_string(bytes.size()) + ")");
        if (chunkType != 0x4E4F534Au || uint64_t(chunkLen) + 20 > bytes.size()) fail(c, "invalid GLB JSON chunk");
        jsonText.assign(reinterpret_cast<const char*>(bytes.data() + 20), chunkLen);
    } else {
        size_t i = 0;
        if (bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF) i = 3;
        while (i < bytes.size() && std::isspace(bytes[i])) ++i;
        if (i == bytes.size() || bytes[i] != '{') fail(c, "not a glTF file (neither GLB nor a JSON object)");
        jsonText.assign(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    }
    try {
        c.root = json::parse(jsonText);
    } catch (const json::exception& e) {
        fail(c, std::string("invalid JSON: ") + firstLine(e.what()));
    }
    if (!c.root.is_object()) fail(c, "JSON root is not an object");

    // 2. extensionsRequired.
    if (c.root.contains("extensionsRequired") && c.root["extensionsRequired"].is_array())
        for (const json& e : c.root["extensionsRequired"]) {
            std::string name = e.is_string() ? e.get<std::string>() : e.dump();
            if (std::find(kSupportedRequired.begin(), kSupportedRequired.end(), name) == kSupportedRequired.end())
                throw Unsupported(path + ": required extension " + name + " is not supported");
        }

    // tinygltf rejects index accessors without a bufferView, which is how Draco primitives
    // declare them; we never use those accessors, so hide them from tinygltf.
    bool patched = false;
    json patchedRoot;
    if (c.root.contains("meshes") && c.root["meshes"].is_array())
        for (size_t mi = 0; mi < c.root["meshes"].size(); ++mi) {
            const json& jm = c.root["meshes"][mi];
            if (!jm.is_object() || !jm.contains("primitives") || !jm["primitives"].is_array()) continue;
            for (size_t pi = 0; pi < jm["primitives"].size(); ++pi) {
                const json& jp = jm["primitives"][pi];
                if (jp.is_object() && jp.contains("indices") && jp.contains("extensions") && jp["extensions"].is_object() &&
                    jp["extensions"].contains("KHR_draco_mesh_compression")) {
                    if (!patched) patchedRoot = c.root;
                    patched = true;
                    patchedRoot["meshes"][mi]["primitives"][pi].erase("indices");
                }
            }
        }
    std::vector<unsigned char> glbBytes;
    if (patched) {
        std::string text = patchedRoot.dump();
        if (isGlb) {
            while (text.size() % 4) text.push_back(' ');
            uint32_t oldLen = 0;
            std::memcpy(&oldLen, bytes.data() + 12, 4);
            size_t rest = 20 + size_t(oldLen);
            glbBytes.assign(bytes.begin(), bytes.begin() + 20);
            uint32_t newLen = uint32_t(text.size()), total = uint32_t(20 + text.size() + (bytes.size() - rest));
            std::memcpy(glbBytes.data() + 8, &total, 4);
            std::memcpy(glbBytes.data() + 12, &newLen, 4);
            glbBytes.insert(glbBytes.end(), text.begin(), text.end());
            glbBytes.insert(glbBytes.end(), bytes.begin() + long(rest), bytes.end());
            bytes.swap(glbBytes);
        } else {
            jsonText = text;
        }
    }
    bool ok = false;
    try {
        ok = isGlb ? loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), unsigned(bytes.size()), baseDir)
                   : loader.LoadASCIIFromString(&model, &err, &warn, jsonText.data(), unsigned(jsonText.size()), baseDir);
    } catch (const std::exception& e) {  // tinygltf indexes some malformed input with .at()
        fail(c, std::string("malformed glTF (tinygltf: ") + firstLine(e.what()) + ")");
    }
    if (!ok) {
        std::string e = firstLine(err.empty() ? warn : err);
        if (e.empty()) e = "cannot load glTF";
        const std::string notFound = "File not found : ";
        if (e.rfind(notFound, 0) == 0)
            throw IOError(path + ": cannot read buffer file '" + e.substr(notFound.size()) + "': No such file or directory");
        bool io = e.find("not found") != std::string::npos || e.find("Failed to load") != std::string::npos ||
                  e.find("open") != std::string::npos;
        if (io) throw IOError(path + ": " + e);
        fail(c, e);
    }
    bytes.clear();
    bytes.shrink_to_fit();
    c.model = &model;

    Asset asset;
    asset.sourcePath = path;
    try {
        // 3. Scene → mesh nodes with world transforms.
        std::vector<int> roots;
        int sceneIndex = model.defaultScene >= 0 ? model.defaultScene : (model.scenes.empty() ? -1 : 0);
        if (sceneIndex >= int(model.scenes.size())) fail(c, "scene " + std::to_string(sceneIndex) + " does not exist");
        if (sceneIndex >= 0) {
            roots = model.scenes[size_t(sceneIndex)].nodes;
        } else {
            std::vector<char> isChild(model.nodes.size(), 0);
            for (const auto& n : model.nodes)
                for (int ch : n.children)
                    if (ch >= 0 && size_t(ch) < isChild.size()) isChild[size_t(ch)] = 1;
            for (size_t i = 0; i < model.nodes.size(); ++i)
                if (!isChild[i]) roots.push_back(int(i));
        }
        const json* ext = nullptr;
        if (c.root.contains("extensions") && c.root["extensions"].is_object() && c.root["extensions"].contains(kMultiresExtension))
            ext = &c.root["extensions"][kMultiresExtension];
        if (ext && !ext->is_object()) fail(c, std::string(kMultiresExtension) + " is not an object");
        if (ext && ext->value("version", 0) > kMultiresVersion)
            throw Unsupported(path + ": " + kMultiresExtension + " version " + std::to_string(ext->value("version", 0)) +
                              " is newer than this reader (" + std::to_string(kMultiresVersion) + ")");

        if (options.lod >= 0 && !ext) roots = selectMsftLod(c, roots, options.lod, path);

        std::vector<std::pair<int, Mat4>> nodes;
        std::vector<char> onStack(model.nodes.size(), 0);
        for (int r : roots) collectNodes(c, r, identity4(), onStack, nodes, asset.stats.nodes);

        if (ext && ext->contains("original") && (*ext)["original"].is_object()) {
            // 4b. Our own multires file: the original mesh is node `original.node`, rebuilt exactly.
            const json& orig = (*ext)["original"];
            int nodeIndex = jint(orig, "node", 0);
            if (nodeIndex < 0 || size_t(nodeIndex) >= model.nodes.size()) fail(c, std::string(kMultiresExtension) + ": original node does not exist");
            Mat4 world = identity4();
            for (const auto& [n, w] : nodes) if (n == nodeIndex) world = w;
            int meshIndex = model.nodes[size_t(nodeIndex)].mesh;
            if (meshIndex >= int(model.meshes.size())) fail(c, "node " + std::to_string(nodeIndex) + ": mesh does not exist");
            asset.mesh = rebuildOriginal(c, *ext, orig, meshIndex, world, asset);
            if (multires) *multires = readMultires(c, *ext, asset.mesh);
        } else {
            // 4. Every mesh node: decode, transform, weld.
            MeshBuilder builder;
            for (const auto& [n, world] : nodes) {
                const auto& node = model.nodes[size_t(n)];
                if (node.mesh < 0) continue;
                if (size_t(node.mesh) >= model.meshes.size()) fail(c, "node " + std::to_string(n) + ": mesh " + std::to_string(node.mesh) + " does not exist");
                const auto& mesh = model.meshes[size_t(node.mesh)];
                for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
                    PrimData p;
                    if (!decodePrimitive(c, node.mesh, int(pi), asset, p)) continue;
                    asset.stats.primitives++;
                    asset.stats.inputVertices += p.pos.size();
                    int material = mesh.primitives[pi].material;
                    if (material >= int(model.materials.size())) fail(c, "mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(pi) + ": material " + std::to_string(material) + " does not exist");
                    builder.add(c, p, world, material < 0 ? -1 : material,
                                "node " + std::to_string(n) + " mesh " + std::to_string(node.mesh) + " primitive " + std::to_string(pi));
                }
            }
            builder.finish(asset);
            if (multires) multires->reset();
        }

        // 5. Materials, textures, samplers, images.
        if (c.root.contains("materials") && c.root["materials"].is_array())
            for (const json& m : c.root["materials"]) asset.materials.push_back(readMaterial(m));
        for (const auto& s : model.samplers) {
            Sampler smp;
            smp.magFilter = std::max(s.magFilter, 0);
            smp.minFilter = std::max(s.minFilter, 0);
            smp.wrapS = s.wrapS;
            smp.wrapT = s.wrapT;
            asset.samplers.push_back(smp);
        }
        for (const auto& t : model.textures) {
            Texture tex;
            tex.image = t.source;
            tex.sampler = t.sampler;
            if (tex.image >= int(model.images.size()) || tex.sampler >= int(model.samplers.size()))
                fail(c, "texture refers to a missing image or sampler");
            asset.textures.push_back(tex);
        }
        for (size_t i = 0; i < model.images.size(); ++i) {
            auto& src = model.images[i];
            Image img;
            img.name = src.name.empty() ? src.uri : src.name;
            img.encoded = std::move(src.image);
            std::string sniffed = sniffImageMime(img.encoded.data(), img.encoded.size());
            img.mimeType = !sniffed.empty() ? sniffed : src.mimeType;
            if (img.encoded.empty()) {
                std::string w = "image " + std::to_string(i) + (src.uri.empty() ? "" : " '" + src.uri + "'");
                if (options.requireImageData) throw IOError(path + ": " + w + ": cannot read image data");
                asset.warnings.push_back(w + ": no image data");
            }
            asset.images.push_back(std::move(img));
        }
    } catch (const json::exception& e) {
        fail(c, std::string("malformed JSON value: ") + firstLine(e.what()));
    }
    return asset;
}

}  // namespace lodbake
