// Private to lib/src/gltf: the bytes tinygltf reads besides the JSON. A .gltf's URIs name files
// (regular files only); a GLB's BIN chunk is handed to tinygltf as buffer 0's file, so that the
// chunk moves into the model instead of being copied beside the file's bytes (on a million-triangle
// intermediate that copy is 200 MB at the peak of the stage that loads it).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <tiny_gltf.h>

namespace lodbake::gltf_detail {

// The whole file. \throw IOError naming `path`.
std::vector<unsigned char> readFileBytes(const std::string& path);

// A GLB's BIN chunk, waiting for tinygltf to take it as buffer 0.
struct GlbBinChunk {
    std::vector<unsigned char> bytes;
};

// When `glb` is a well-formed GLB whose BIN chunk holds buffer 0 (it has no uri, every other buffer
// of `root` or of `patched` has one, its byteLength fits the chunk): moves buffer 0's bytes from
// `glb` into `bin` and points buffer 0 at them in `patched` (a copy of `root`, made on first change).
// Otherwise nothing changes and tinygltf reads the GLB itself (reporting what is malformed).
bool takeGlbBinChunk(const nlohmann::json& root, std::optional<nlohmann::json>& patched, std::vector<unsigned char>& glb,
                     GlbBinChunk& bin);

// The file callbacks for tinygltf: URIs read as regular files, and buffer 0 from `bin` (may be null).
tinygltf::FsCallbacks fileCallbacks(GlbBinChunk* bin);

}  // namespace lodbake::gltf_detail
