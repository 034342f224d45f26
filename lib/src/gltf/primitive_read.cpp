// Accessor decoding (all component types, normalized or not, strides, sparse accessors; every
// read bounds-checked) and the decoding of one primitive into glTF-local arrays.
#include <algorithm>
#include <cstring>
#include <limits>

#include <tiny_gltf.h>

#include "gltf/draco_decode.h"
#include "gltf/gltf_internal.h"
#include "gltf/gltf_read_context.h"
#include "lodbake/core/errors.h"

namespace lodbake::gltf_detail {
namespace {

using json = nlohmann::json;

// Limit on elements of an accessor that has no bufferView (all zeros or sparse only): such an
// accessor costs no file bytes, so its count must be capped before we allocate.
constexpr size_t kMaxVirtualCount = size_t(1) << 26;

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

}  // namespace

void fail(const ReadContext& c, const std::string& what) { throw InvalidInput(c.path + ": " + what); }

int jint(const json& o, const char* key, int def) {
    return o.contains(key) && o[key].is_number_integer() ? o[key].get<int>() : def;
}

const unsigned char* viewBytes(const ReadContext& c, int viewIndex, size_t& length, const std::string& what) {
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

namespace {

// Reads `count` elements of `comps` components of type `ct` from a view, bounds-checked.
void readStrided(const ReadContext& c, int viewIndex, size_t byteOffset, size_t count, int comps, int ct, bool normalized,
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

AccessorData readAccessor(const ReadContext& c, int index, const std::string& what, bool forceNormalize = false) {
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

}  // namespace

std::vector<uint32_t> readU32(const ReadContext& c, int index, int comps, const std::string& what) {
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

std::vector<float> readF32(const ReadContext& c, int index, int comps, const std::string& what) {
    if (index < 0) return {};
    AccessorData d = readAccessor(c, index, what);
    if (d.comps != comps) fail(c, what + ": accessor " + std::to_string(index) + " has " + std::to_string(d.comps) + " components, expected " + std::to_string(comps));
    std::vector<float> out(d.v.size());
    for (size_t i = 0; i < d.v.size(); ++i) out[i] = float(d.v[i]);
    return out;
}

void assembleTriangles(const ReadContext& c, const std::vector<uint32_t>& idx, int mode, PrimData& p, const std::string& what) {
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

void checkFinitePositions(const ReadContext& c, const PrimData& p, const std::string& what) {
    for (size_t i = 0; i < p.pos.size(); ++i)
        if (!isFinite(p.pos[i])) fail(c, what + ": vertex " + std::to_string(i) + " has a non-finite position");
}

bool decodePrimitive(const ReadContext& c, int meshIndex, int primIndex, Asset& asset, PrimData& p) {
    const auto& prim = c.model->meshes[size_t(meshIndex)].primitives[size_t(primIndex)];
    std::string what = "mesh " + std::to_string(meshIndex) + " primitive " + std::to_string(primIndex);
    int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (prim.mode < -1 || mode > TINYGLTF_MODE_TRIANGLE_FAN) fail(c, what + ": invalid mode " + std::to_string(mode) + " (glTF modes are 0 to 6)");
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        asset.warnings.push_back(what + ": mode " + std::to_string(mode) + " (points/lines) dropped");
        asset.stats.droppedPrimitives++;
        return false;
    }
    const json* draco = nullptr;
    const json& jp = c.root["meshes"][size_t(meshIndex)]["primitives"][size_t(primIndex)];
    if (jp.contains("extensions") && jp["extensions"].is_object() && jp["extensions"].contains("KHR_draco_mesh_compression"))
        draco = &jp["extensions"]["KHR_draco_mesh_compression"];
    if (draco) {
        decodeDraco(c, *draco, p, what);
        asset.stats.dracoPrimitives++;
        // Draco reorders vertices; the targets' accessors follow the uncompressed order.
        if (!prim.targets.empty()) asset.warnings.push_back(what + ": morph targets of a Draco-compressed primitive ignored");
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
    auto setName = [](const char* base, int set) { return std::string(base) + std::to_string(set); };
    while (attrIndex(setName("JOINTS_", p.influenceSets).c_str()) >= 0 && attrIndex(setName("WEIGHTS_", p.influenceSets).c_str()) >= 0)
        p.influenceSets++;
    const size_t sets = size_t(p.influenceSets);
    p.joints.resize(4 * n * sets);
    p.weights.resize(4 * n * sets);
    for (size_t set = 0; set < sets; ++set) {
        const std::string j = setName("JOINTS_", int(set)), w = setName("WEIGHTS_", int(set));
        AccessorData J = readAttr(j.c_str(), false, {4}), Wt = readAttr(w.c_str(), true, {4});
        for (size_t i = 0; i < n; ++i)
            for (int k = 0; k < 4; ++k) {
                const double ji = J.at(i, k);
                if (!(ji >= 0 && ji < 65536)) fail(c, what + ": " + j + " value out of range");
                p.joints[(i * sets + set) * 4 + size_t(k)] = uint32_t(ji);
                p.weights[(i * sets + set) * 4 + size_t(k)] = Wt.at(i, k);
            }
    }
    for (size_t t = 0; t < prim.targets.size(); ++t) {
        PrimData::Target target;
        auto deltas = [&](const char* name, std::vector<Vec3>& out) {
            auto it = prim.targets[t].find(name);
            if (it == prim.targets[t].end()) return;
            const std::string tw = what + " target " + std::to_string(t) + " " + name;
            AccessorData D = readAccessor(c, it->second, tw);
            if (D.comps != 3) fail(c, tw + " is not VEC3");
            if (D.count != n) fail(c, tw + " count " + std::to_string(D.count) + " differs from POSITION count " + std::to_string(n));
            out.resize(n);
            for (size_t i = 0; i < n; ++i) {
                out[i] = {D.at(i, 0), D.at(i, 1), D.at(i, 2)};
                if (!isFinite(out[i])) fail(c, tw + ": vertex " + std::to_string(i) + " has a non-finite delta");
            }
        };
        deltas("POSITION", target.position);
        deltas("NORMAL", target.normal);
        deltas("TANGENT", target.tangent);
        if (target.position.empty()) target.position.assign(n, Vec3{0, 0, 0});
        p.targets.push_back(std::move(target));
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

}  // namespace lodbake::gltf_detail
