// Private to lib/src/gltf: the binary buffer, buffer views and accessors of a glTF being written,
// and the .glb / .gltf+.bin serialisation both writers (gltf_write.cpp, msft_lod_write.cpp) share.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace lodbake::gltf_detail {

// "SCALAR", "VEC2", "VEC3", "VEC4" for 1..4 components.
const char* accessorType(int comps);

// A FLOAT accessor's JSON without its bufferView; `minmax` adds min/max (required for POSITION).
nlohmann::json floatAccessorJson(const std::vector<float>& v, int comps, bool minmax);

struct BufferBuilder {
    std::vector<std::string> chunks;  // the binary buffer: one chunk per view (with its alignment
    size_t size = 0;                  // padding in front), written in order; size = total bytes
    nlohmann::json views = nlohmann::json::array();
    nlohmann::json accessors = nlohmann::json::array();
    // Bytes of buffer 1, EXT_meshopt_compression's fallback buffer: it has no data, only the
    // layout of the decoded views (0 = no such buffer).
    size_t fallbackSize = 0;

    // Appends bytes 4-byte aligned as a new buffer view (target 0 = none); returns its index.
    int addView(const void* data, size_t bytes, int target);
    // EXT_meshopt_compression: `encoded` appended to buffer 0 and named by the view's extension;
    // the view itself spans `count` * `stride` decoded bytes of the fallback buffer. `mode` is
    // "ATTRIBUTES" (the view gets byteStride) or "TRIANGLES"; `filter` "NONE" is omitted.
    int addMeshoptView(const std::vector<unsigned char>& encoded, size_t count, size_t stride, const char* mode,
                       const char* filter, int target);
    // Appends an accessor; returns its index.
    int addAccessor(nlohmann::json accessor);
    // FLOAT / UNSIGNED_INT accessors over new views; -1 for an empty array.
    int addFloat(const std::vector<float>& v, int comps, int target, bool minmax);
    int addU32(const std::vector<uint32_t>& v, int comps);
    // Triangle indices as UNSIGNED_SHORT when vertexCount < 65536, else UNSIGNED_INT.
    int addIndices(const std::vector<uint32_t>& idx, size_t vertexCount);
};

// Adds buffer 0 (when the buffer is non-empty), the fallback buffer 1 (when used), bufferViews and accessors to `root`, then writes
// `path` atomically: a GLB container when `glb`, else the JSON plus PATH-stem.bin beside it.
// Returns the bytes written. With `memory` (and `glb`), the container goes there instead of a
// file, and the buffer's chunks are emptied as they are copied. \throw IOError.
size_t writeGltfFiles(const std::string& path, nlohmann::json& root, BufferBuilder& buffer, bool glb,
                      std::vector<unsigned char>* memory = nullptr);

}  // namespace lodbake::gltf_detail
