// Writing a packed LOD chain: one MSFT_lod file, or one file per level and a JSON manifest.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/gltf/msft_lod.h"
#include "lodbake/lod/lod_chain.h"

namespace lodbake {

struct PackWriteOptions {
    LodChainWriteOptions chain;
    bool split = false;  // one file per level (PATH stem + ".lodK" + ext) plus PATH stem + ".lods.json"
};

struct PackWriteStats {
    std::vector<std::string> files;          // written files (chain or per level, then the manifest)
    std::vector<uint64_t> levelBytes;        // geometry + image bytes per level
    std::vector<uint64_t> levelGeometryBytes, levelImageBytes;  // the two parts
    uint64_t totalBytes = 0;                 // bytes of every written file
    std::vector<VertexCacheStats> cacheBefore, cacheAfter;  // per level (LodChainWriteStats)
    std::vector<std::string> warnings;       // the writer's fallbacks
};

// Writes the chain to `path` (MSFT_lod) or, with split, one file per level and a JSON manifest
// {"levels": [{"file", "screenCoverage", "triangles"}...], "cutoff": value}.
// \throw IOError when a file cannot be written.
PackWriteStats writePackResult(const std::string& path, const PackResult& result, const PackWriteOptions& options);

}  // namespace lodbake
