// Private helpers shared by the glTF reader and writer (lib/src/gltf only).
#pragma once

#include <algorithm>
#include <cstdint>
#include <string>

namespace lodbake::gltf_detail {

// glTF enums we use by name.
constexpr int kByte = 5120, kUnsignedByte = 5121, kShort = 5122, kUnsignedShort = 5123,
              kUnsignedInt = 5125, kFloat = 5126;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;

// Extensions both the hero LOD0's reader and the chain writer name.
constexpr const char* kDraco = "KHR_draco_mesh_compression";
constexpr const char* kMeshopt = "EXT_meshopt_compression";

// "image/png" / "image/jpeg" / "image/ktx2" from magic bytes, "" when unknown.
inline std::string sniffImageMime(const uint8_t* p, size_t n) {
    if (n >= 8 && p[0] == 0x89 && p[1] == 'P' && p[2] == 'N' && p[3] == 'G') return "image/png";
    if (n >= 3 && p[0] == 0xFF && p[1] == 0xD8 && p[2] == 0xFF) return "image/jpeg";
    static const uint8_t kKtx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, '\r', '\n', 0x1A, '\n'};
    if (n >= 12 && std::equal(kKtx2, kKtx2 + 12, p)) return "image/ktx2";
    return "";
}

}  // namespace lodbake::gltf_detail
