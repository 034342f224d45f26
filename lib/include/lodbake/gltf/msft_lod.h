// Writing the final LOD chain (`pack`'s output): a glTF whose LOD0 node carries MSFT_lod, every
// level one mesh / one primitive / one material with a baked base-colour atlas, optionally
// compressed with KHR_draco_mesh_compression. Takes lodbake's own structs only (images already
// encoded: lodbake/texture/codec.h); tinygltf-free, Draco stays inside lib/src/io (STYLE.md practice 10).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

// One level of the chain, ready to write: an indexed triangle list (CCW) in world space.
struct LodLevelData {
    std::string name;                // node / mesh / material name, e.g. "LOD1"
    std::vector<float> positions;    // xyz per vertex
    std::vector<float> normals;      // xyz per vertex, unit length (same count as positions)
    std::vector<float> uvs;          // TEXCOORD_0 per vertex (glTF: [0,1], v down)
    std::vector<uint32_t> indices;   // 3 per triangle
    Image image;                     // encoded base-colour atlas (PNG or JPEG), width/height set
    double metallicFactor = 0;
    double roughnessFactor = 1;
    bool doubleSided = false;
};

struct LodChainWriteOptions {
    std::string generator = "lodbake pack";
    bool embedImages = true;  // .gltf only: false writes images beside the file (GLB always embeds)
    bool draco = false;       // KHR_draco_mesh_compression on every primitive (then also extensionsRequired)
    int quantPosition = 14;   // Draco quantisation bits (1..30) for POSITION
    int quantTexcoord = 12;   // ... TEXCOORD_0
    int quantNormal = 10;     // ... NORMAL
    int dracoSpeed = 3;       // Draco encoder speed 0 (best compression) .. 10 (fastest); decoding speed the same
};

struct LodChainWriteStats {
    std::vector<uint64_t> levelGeometryBytes;  // buffer bytes of each level's mesh (indices + attributes or Draco)
    std::vector<uint64_t> levelImageBytes;     // encoded image bytes of each level
    uint64_t fileBytes = 0;                    // the .glb (or .gltf + .bin + images) on disk
};

// Writes `levels` as one glTF (.glb or .gltf by the extension of `path`), atomically.
// With more than one level: node 0 = levels[0] with extensions.MSFT_lod.ids = [1 .. n-1] and
// extras.MSFT_screencoverage = `screenCoverage` (one value per level, i.e. one more than the
// ids, decreasing: LOD k is drawn at coverage >= value k, nothing below the last); only node 0 is in the scene; MSFT_lod is listed in extensionsUsed, never required.
// With one level and no coverage: a plain single-mesh file (pack --split).
// \pre every level has >= 1 triangle, matching attribute sizes, an encoded image.
// \throw InvalidInput (inconsistent level data), IOError (cannot write), SolverError (Draco failed).
LodChainWriteStats writeLodChain(const std::string& path, const std::vector<LodLevelData>& levels,
                                 const std::vector<double>& screenCoverage, const LodChainWriteOptions& options = {});

}  // namespace lodbake
