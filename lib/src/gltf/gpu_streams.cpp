// GPU-ready streams of the LOD chain (meshoptimizer 0.18).
//
// Pipeline, per level, as msft_lod_write.cpp runs it:
//   1. optimizeLevelBuffers: triangle order for the post-transform vertex cache (Forsyth-style,
//      meshopt_optimizeVertexCache), then for overdraw without losing more than 5 % of that ACMR
//      (meshopt_optimizeOverdraw, 1.05), then vertices in first-use order (meshopt_optimizeVertexFetchRemap);
//   2. gpuPrimitive: each attribute becomes one stream in its storage format (FLOAT, or the
//      KHR_mesh_quantization integer formats), then one view: plain, or EXT_meshopt_compression
//      (vertex codec for attributes, index codec version 1 for triangles).
// Stream formats (the choices gltfpack makes):
//   POSITION  FLOAT VEC3 | quantized: UNSIGNED_SHORT VEC3 on the file's grid, stride 8
//   NORMAL    FLOAT VEC3 | BYTE normalized, stride 4 | meshopt: OCTAHEDRAL filter, BYTE (8 bits,
//             quantized) or SHORT (12 bits in 16, stride 8) normalized
//   TANGENT   as NORMAL with VEC4 (w = handedness, kept exactly by the filter)
//   TEXCOORD  FLOAT VEC2 | quantized: UNSIGNED_SHORT normalized (atlas UVs lie in [0,1])
//   indices   UNSIGNED_SHORT below 65536 vertices, else UNSIGNED_INT

#include "gltf/gpu_streams.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include <meshoptimizer.h>

#include "gltf/gltf_internal.h"
#include "gltf/rig_write.h"

namespace lodbake::gltf_detail {
namespace {

using json = nlohmann::json;

constexpr unsigned kCacheSize = 16;
constexpr float kOverdrawThreshold = 1.05f;
constexpr int kOctBitsShort = 12;  // oct filter bits in 16-bit storage: about 1e-3 rad
constexpr int kOctBitsByte = 8;

template <typename T>
void remapStream(std::vector<T>& v, size_t comps, size_t vertices, size_t unique, const std::vector<unsigned>& remap) {
    if (v.empty()) return;
    std::vector<T> out(unique * comps);
    meshopt_remapVertexBuffer(out.data(), v.data(), vertices, comps * sizeof(T), remap.data());
    v = std::move(out);
}

// One attribute stream in its storage format: `count` elements of `stride` bytes.
struct Stream {
    std::vector<unsigned char> bytes;
    size_t count = 0;
    size_t stride = 0;
    size_t elementBytes = 0;       // bytes of one element's components; < stride when padded
    json accessor;                 // componentType, type, normalized, min/max; no view or count
    const char* filter = "NONE";   // EXT_meshopt_compression filter already applied to `bytes`
};

template <typename T>
void put(Stream& s, size_t i, size_t k, T value) {
    std::memcpy(s.bytes.data() + i * s.stride + k * sizeof(T), &value, sizeof(T));
}

Stream floatStream(const std::vector<float>& v, int comps, bool minmax) {
    Stream s;
    s.count = v.size() / size_t(comps);
    s.stride = s.elementBytes = 4 * size_t(comps);
    s.bytes.resize(v.size() * 4);
    std::memcpy(s.bytes.data(), v.data(), s.bytes.size());
    s.accessor = floatAccessorJson(v, comps, minmax);
    s.accessor.erase("count");
    return s;
}

Stream quantizedPositions(const std::vector<float>& p, const StreamOptions& o) {
    Stream s;
    s.count = p.size() / 3;
    s.stride = 8;
    s.elementBytes = 6;
    s.bytes.assign(s.count * s.stride, 0);
    const double top = double((1 << o.positionBits) - 1);
    int lo[3] = {65535, 65535, 65535}, hi[3] = {0, 0, 0};
    for (size_t i = 0; i < s.count; ++i)
        for (size_t k = 0; k < 3; ++k) {
            const double q = std::round((double(p[3 * i + k]) - o.grid.origin[k]) / o.grid.step);
            const int v = int(std::clamp(q, 0.0, top));
            lo[k] = std::min(lo[k], v);
            hi[k] = std::max(hi[k], v);
            put(s, i, k, uint16_t(v));
        }
    s.accessor = {{"componentType", kUnsignedShort}, {"type", "VEC3"}, {"min", lo}, {"max", hi}};
    return s;
}

// Unit vectors (3 or 4 components; the 4th, tangent handedness, passes through exactly) as
// normalized signed integers: octahedral-filtered for meshopt, plain otherwise.
Stream quantizedDirections(const std::vector<float>& v, int comps, bool shortStorage, bool octahedral) {
    Stream s;
    s.count = v.size() / size_t(comps);
    s.stride = shortStorage ? 8 : 4;
    s.elementBytes = (shortStorage ? 2 : 1) * size_t(comps);
    s.bytes.assign(s.count * s.stride, 0);
    s.accessor = {{"componentType", shortStorage ? kShort : kByte}, {"normalized", true}, {"type", accessorType(comps)}};
    if (octahedral) {
        std::vector<float> xyzw(s.count * 4, 0.0f);
        for (size_t i = 0; i < s.count; ++i)
            for (size_t k = 0; k < size_t(comps); ++k) xyzw[4 * i + k] = v[i * size_t(comps) + k];
        meshopt_encodeFilterOct(s.bytes.data(), s.count, s.stride, shortStorage ? kOctBitsShort : kOctBitsByte, xyzw.data());
        s.filter = "OCTAHEDRAL";
        return s;
    }
    const double scale = shortStorage ? 32767.0 : 127.0;
    for (size_t i = 0; i < s.count; ++i)
        for (size_t k = 0; k < size_t(comps); ++k) {
            const double q = std::round(std::clamp(double(v[i * size_t(comps) + k]), -1.0, 1.0) * scale);
            if (shortStorage) put(s, i, k, int16_t(q));
            else put(s, i, k, int8_t(q));
        }
    return s;
}

bool inUnitSquare(const std::vector<float>& uv) {
    return std::all_of(uv.begin(), uv.end(), [](float u) { return u >= 0.0f && u <= 1.0f; });
}

Stream quantizedUvs(const std::vector<float>& uv) {
    Stream s;
    s.count = uv.size() / 2;
    s.stride = s.elementBytes = 4;
    s.bytes.assign(s.count * s.stride, 0);
    for (size_t i = 0; i < uv.size(); ++i) put(s, i / 2, i % 2, uint16_t(std::lround(double(uv[i]) * 65535.0)));
    s.accessor = {{"componentType", kUnsignedShort}, {"normalized", true}, {"type", "VEC2"}};
    return s;
}

// The stream's view (plain or EXT_meshopt_compression) and its accessor; returns the accessor.
int addStream(BufferBuilder& b, Stream s, bool meshopt) {
    int view;
    if (meshopt) {
        std::vector<unsigned char> enc(meshopt_encodeVertexBufferBound(s.count, s.stride));
        enc.resize(meshopt_encodeVertexBuffer(enc.data(), enc.size(), s.bytes.data(), s.count, s.stride));
        view = b.addMeshoptView(enc, s.count, s.stride, "ATTRIBUTES", s.filter, kArrayBuffer);
    } else {
        view = b.addView(s.bytes.data(), s.bytes.size(), kArrayBuffer);
        if (s.elementBytes != s.stride) b.views[size_t(view)]["byteStride"] = s.stride;
    }
    s.accessor["bufferView"] = view;
    s.accessor["count"] = s.count;
    return b.addAccessor(std::move(s.accessor));
}

int addIndexStream(BufferBuilder& b, const std::vector<uint32_t>& idx, size_t vertexCount, bool meshopt) {
    if (!meshopt) return b.addIndices(idx, vertexCount);
    const bool shortIndices = vertexCount < 65536;
    meshopt_encodeIndexVersion(1);
    std::vector<unsigned char> enc(meshopt_encodeIndexBufferBound(idx.size(), vertexCount));
    enc.resize(meshopt_encodeIndexBuffer(enc.data(), enc.size(), idx.data(), idx.size()));
    const int view = b.addMeshoptView(enc, idx.size(), shortIndices ? 2 : 4, "TRIANGLES", "NONE", kElementArrayBuffer);
    return b.addAccessor({{"bufferView", view}, {"componentType", shortIndices ? kUnsignedShort : kUnsignedInt},
                          {"count", idx.size()}, {"type", "SCALAR"}});
}

}  // namespace

VertexCacheStats analyzeVertexCache(const LodLevelData& L) {
    const meshopt_VertexCacheStatistics s =
        meshopt_analyzeVertexCache(L.indices.data(), L.indices.size(), L.positions.size() / 3, kCacheSize, 0, 0);
    return {s.acmr, s.atvr};
}

void optimizeLevelBuffers(LodLevelData& L) {
    const size_t n = L.positions.size() / 3, count = L.indices.size();
    std::vector<unsigned> cache(count), order(count);
    // Triangles move within their part only (each part is its own primitive).
    std::vector<size_t> ranges{count};
    if (!L.parts.empty()) {
        ranges.clear();
        for (const LodPart& part : L.parts) ranges.push_back(3 * part.triangles);
    }
    size_t first = 0;
    for (size_t r : ranges) {
        meshopt_optimizeVertexCache(cache.data() + first, L.indices.data() + first, r, n);
        meshopt_optimizeOverdraw(order.data() + first, cache.data() + first, r, L.positions.data(), n, 12, kOverdrawThreshold);
        first += r;
    }
    std::vector<unsigned> remap(n);
    const size_t unique = meshopt_optimizeVertexFetchRemap(remap.data(), order.data(), count, n);
    meshopt_remapIndexBuffer(L.indices.data(), order.data(), count, remap.data());
    remapStream(L.positions, 3, n, unique, remap);
    remapStream(L.normals, 3, n, unique, remap);
    remapStream(L.uvs, 2, n, unique, remap);
    remapStream(L.tangents, 4, n, unique, remap);
    remapStream(L.joints, 4, n, unique, remap);
    remapStream(L.weights, 4, n, unique, remap);
    for (auto* targets : {&L.targetPositions, &L.targetNormals, &L.targetTangents})
        for (std::vector<float>& d : *targets) remapStream(d, 3, n, unique, remap);
}

PositionGrid positionGrid(const std::vector<LodLevelData>& levels, int bits) {
    double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const LodLevelData& L : levels)
        for (size_t i = 0; i < L.positions.size(); ++i) {
            lo[i % 3] = std::min(lo[i % 3], double(L.positions[i]));
            hi[i % 3] = std::max(hi[i % 3], double(L.positions[i]));
        }
    PositionGrid g;
    double extent = 0;
    for (int k = 0; k < 3; ++k) {
        g.origin[k] = lo[k];
        extent = std::max(extent, hi[k] - lo[k]);
    }
    g.step = extent > 0 ? extent / double((1 << bits) - 1) : 1.0;
    return g;
}

PrimitiveStreams gpuPrimitive(BufferBuilder& b, const LodLevelData& L, const StreamOptions& o) {
    PrimitiveStreams out;
    const size_t n = L.positions.size() / 3;
    const bool mo = o.meshopt, q = o.quantize;
    // Plain FLOAT accessors keep BufferBuilder::addFloat's layout (one tight view per attribute).
    auto floatAttr = [&](const std::vector<float>& v, int comps, bool minmax) {
        return mo ? addStream(b, floatStream(v, comps, minmax), true) : b.addFloat(v, comps, kArrayBuffer, minmax);
    };
    auto direction = [&](const std::vector<float>& v, int comps) {
        if (!mo && !q) return b.addFloat(v, comps, kArrayBuffer, false);
        out.quantized = true;
        return addStream(b, quantizedDirections(v, comps, !q, mo), mo);
    };
    json attrs;
    attrs["POSITION"] = q && o.positionsOnGrid ? addStream(b, quantizedPositions(L.positions, o), mo) : floatAttr(L.positions, 3, true);
    attrs["NORMAL"] = direction(L.normals, 3);
    const bool uvQuantized = q && inUnitSquare(L.uvs);
    out.floatUvFallback = q && !uvQuantized;
    attrs["TEXCOORD_0"] = uvQuantized ? addStream(b, quantizedUvs(L.uvs), mo) : floatAttr(L.uvs, 2, false);
    if (!L.tangents.empty()) attrs["TANGENT"] = direction(L.tangents, 4);
    addInfluences(b, attrs, L.joints, L.weights);
    out.quantized = out.quantized || q;
    if (L.parts.empty()) {
        out.primitive = {{"attributes", attrs}, {"indices", addIndexStream(b, L.indices, n, mo)}, {"mode", 4}};
        addMorphTargets(b, out.primitive, L.targetPositions, L.targetNormals, L.targetTangents);
        out.primitives.push_back(out.primitive);
        return out;
    }
    // Parts: every primitive reads the same vertex streams (and morph targets), each its own indices.
    json shared = {{"attributes", attrs}, {"mode", 4}};
    addMorphTargets(b, shared, L.targetPositions, L.targetNormals, L.targetTangents);
    size_t first = 0;
    for (const LodPart& part : L.parts) {
        const std::vector<uint32_t> idx(L.indices.begin() + std::ptrdiff_t(first), L.indices.begin() + std::ptrdiff_t(first + 3 * part.triangles));
        json prim = shared;
        prim["indices"] = addIndexStream(b, idx, n, mo);
        out.primitives.push_back(std::move(prim));
        first += 3 * part.triangles;
    }
    out.primitive = out.primitives.front();
    return out;
}

}  // namespace lodbake::gltf_detail
