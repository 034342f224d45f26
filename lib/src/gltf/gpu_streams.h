// Private to lib/src/gltf: GPU-ready vertex and index streams of the LOD chain (meshoptimizer).
// Reordering for the post-transform cache, overdraw and vertex fetch; KHR_mesh_quantization
// formats; EXT_meshopt_compression encoding with filters. Only msft_lod_write.cpp uses them.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "gltf/gltf_buffer.h"
#include "lodbake/gltf/msft_lod.h"

namespace lodbake::gltf_detail {

// meshopt_analyzeVertexCache of the level's index buffer, 16-entry FIFO cache.
VertexCacheStats analyzeVertexCache(const LodLevelData& level);

// Reorders the level's triangles for the vertex cache, then for overdraw (threshold 1.05), then
// its vertices for fetch order; every attribute array moves with its vertex. Vertices no triangle
// uses are dropped. Deterministic.
void optimizeLevelBuffers(LodLevelData& level);

// The KHR_mesh_quantization position grid shared by the levels of one file: q = round((p - origin)
// / step) in [0, 2^bits - 1], dequantised by the node transform translation = origin, scale = step
// (uniform, so normals need no correction).
struct PositionGrid {
    double origin[3] = {0, 0, 0};
    double step = 1;
};
PositionGrid positionGrid(const std::vector<LodLevelData>& levels, int bits);

struct StreamOptions {
    bool meshopt = false;   // EXT_meshopt_compression views
    bool quantize = false;  // KHR_mesh_quantization formats on `grid`
    PositionGrid grid;
    int positionBits = 14;
    // With quantize: positions on `grid` (the node's transform dequantizes them); false keeps
    // them FLOAT (a skinned mesh ignores its node's transform).
    bool positionsOnGrid = true;
};

struct PrimitiveStreams {
    nlohmann::json primitive;        // attributes, indices, mode (the first part's with parts)
    std::vector<nlohmann::json> primitives;  // one per LodPart (the same attributes), or `primitive`
    bool quantized = false;          // some accessor needs KHR_mesh_quantization
    bool floatUvFallback = false;    // quantize asked, but UVs outside [0,1] stayed FLOAT
};

// One primitive's accessors (one per part, sharing the vertex streams) over new views of `buffer`: FLOAT streams (byte-identical to plain
// accessors) unless `options` asks for quantized formats or meshopt compression.
PrimitiveStreams gpuPrimitive(BufferBuilder& buffer, const LodLevelData& level, const StreamOptions& options);

}  // namespace lodbake::gltf_detail
