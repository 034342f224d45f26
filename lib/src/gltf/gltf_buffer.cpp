// The buffer, views and accessors of a glTF being written, and its .glb / .gltf serialisation
// (gltf_buffer.h).
#include "gltf/gltf_buffer.h"

#include <algorithm>
#include <cstring>
#include <filesystem>

#include "gltf/gltf_internal.h"
#include "lodbake/core/errors.h"
#include "lodbake/gltf/gltf.h"

namespace lodbake::gltf_detail {

using json = nlohmann::json;

const char* accessorType(int comps) {
    switch (comps) {
        case 1: return "SCALAR";
        case 2: return "VEC2";
        case 3: return "VEC3";
        default: return "VEC4";
    }
}

json floatAccessorJson(const std::vector<float>& v, int comps, bool minmax) {
    size_t n = v.size() / size_t(comps);
    json a = {{"componentType", kFloat}, {"count", n}, {"type", accessorType(comps)}};
    if (minmax && n > 0) {
        std::vector<float> lo(v.begin(), v.begin() + comps), hi = lo;
        for (size_t i = 0; i < n; ++i)
            for (size_t k = 0; k < size_t(comps); ++k) {
                lo[k] = std::min(lo[k], v[i * size_t(comps) + k]);
                hi[k] = std::max(hi[k], v[i * size_t(comps) + k]);
            }
        a["min"] = lo;
        a["max"] = hi;
    }
    return a;
}

int BufferBuilder::addView(const void* data, size_t bytes, int target) {
    // One chunk per view (no reallocation of one growing buffer): alignment padding, then the bytes.
    const size_t pad = (4 - size % 4) % 4;
    std::string chunk(pad + bytes, '\0');
    if (bytes) std::memcpy(chunk.data() + pad, data, bytes);
    json v = {{"buffer", 0}, {"byteOffset", size + pad}, {"byteLength", bytes}};
    if (target) v["target"] = target;
    size += chunk.size();
    chunks.push_back(std::move(chunk));
    views.push_back(v);
    return int(views.size()) - 1;
}

int BufferBuilder::addMeshoptView(const std::vector<unsigned char>& encoded, size_t count, size_t stride,
                                  const char* mode, const char* filter, int target) {
    const int index = addView(encoded.data(), encoded.size(), 0);
    json& v = views[size_t(index)];
    json ext = {{"buffer", 0}, {"byteOffset", v["byteOffset"]}, {"byteLength", encoded.size()}, {"byteStride", stride},
                {"count", count}, {"mode", mode}};
    if (std::string(filter) != "NONE") ext["filter"] = filter;
    fallbackSize += (4 - fallbackSize % 4) % 4;
    v = {{"buffer", 1}, {"byteOffset", fallbackSize}, {"byteLength", count * stride}, {"target", target},
         {"extensions", {{"EXT_meshopt_compression", ext}}}};
    if (std::string(mode) == "ATTRIBUTES") v["byteStride"] = stride;
    fallbackSize += count * stride;
    return index;
}

int BufferBuilder::addAccessor(json accessor) {
    accessors.push_back(std::move(accessor));
    return int(accessors.size()) - 1;
}

int BufferBuilder::addFloat(const std::vector<float>& v, int comps, int target, bool minmax) {
    if (v.empty()) return -1;
    json a = floatAccessorJson(v, comps, minmax);
    a["bufferView"] = addView(v.data(), v.size() * 4, target);
    return addAccessor(std::move(a));
}

int BufferBuilder::addU32(const std::vector<uint32_t>& v, int comps) {
    if (v.empty()) return -1;
    return addAccessor({{"bufferView", addView(v.data(), v.size() * 4, 0)}, {"componentType", kUnsignedInt},
                        {"count", v.size() / size_t(comps)}, {"type", accessorType(comps)}});
}

int BufferBuilder::addIndices(const std::vector<uint32_t>& idx, size_t vertexCount) {
    int view;
    int ct;
    if (vertexCount < 65536) {
        std::vector<uint16_t> s(idx.begin(), idx.end());
        view = addView(s.data(), s.size() * 2, kElementArrayBuffer);
        ct = kUnsignedShort;
    } else {
        view = addView(idx.data(), idx.size() * 4, kElementArrayBuffer);
        ct = kUnsignedInt;
    }
    return addAccessor({{"bufferView", view}, {"componentType", ct}, {"count", idx.size()}, {"type", "SCALAR"}});
}

size_t writeGltfFiles(const std::string& path, json& root, BufferBuilder& buffer, bool glb,
                      std::vector<unsigned char>* memory) {
    if (buffer.size % 4) {
        buffer.chunks.emplace_back(4 - buffer.size % 4, '\0');
        buffer.size += buffer.chunks.back().size();
    }
    const size_t binSize = buffer.size;
    std::vector<std::string_view> bin(buffer.chunks.begin(), buffer.chunks.end());
    std::string binName = std::filesystem::path(path).stem().string() + ".bin";
    if (binSize) {
        json buf = {{"byteLength", binSize}};
        if (!glb) buf["uri"] = binName;
        root["buffers"] = json::array({buf});
        if (buffer.fallbackSize)
            root["buffers"].push_back(
                {{"byteLength", buffer.fallbackSize}, {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}});
        root["bufferViews"] = buffer.views;
        if (!buffer.accessors.empty()) root["accessors"] = buffer.accessors;
    }
    std::string text = root.dump();
    if (!glb) {
        std::filesystem::path dir = std::filesystem::path(path).parent_path();
        if (binSize) writeFileAtomic((dir / binName).string(), bin);
        writeFileAtomic(path, text);
        return binSize + text.size();
    }
    while (text.size() % 4) text.push_back(' ');
    auto u32 = [](std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); };
    size_t total = 12 + 8 + text.size() + (binSize ? 8 + binSize : 0);
    if (total > 0xFFFFFFFFull) throw IOError(path + ": GLB would exceed 4 GiB");
    // Header and JSON chunk in one string, the binary chunk written from the buffer's chunks.
    std::string head, binHead;
    head.reserve(20 + text.size());
    u32(head, 0x46546C67u);  // "glTF"
    u32(head, 2);
    u32(head, uint32_t(total));
    u32(head, uint32_t(text.size()));
    u32(head, 0x4E4F534Au);  // "JSON"
    head += text;
    if (binSize) {
        u32(binHead, uint32_t(binSize));
        u32(binHead, 0x004E4942u);  // "BIN\0"
    }
    bin.insert(bin.begin(), {head, binHead});
    if (memory) {
        // Each chunk is freed once copied: the container and the whole buffer are not held at once.
        memory->clear();
        memory->reserve(total);
        for (const std::string& part : {head, binHead}) memory->insert(memory->end(), part.begin(), part.end());
        for (std::string& chunk : buffer.chunks) {
            memory->insert(memory->end(), chunk.begin(), chunk.end());
            std::string().swap(chunk);
        }
    } else {
        writeFileAtomic(path, bin);
    }
    return total;
}

}  // namespace lodbake::gltf_detail
