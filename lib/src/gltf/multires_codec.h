// Private to lib/src/gltf: the LODBAKE_multires extension (docs/LODBAKE_multires.md) in both
// directions. readGltf and writeGltf call these; the schema lives only in multires_codec.cpp.
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf/gltf_buffer.h"
#include "gltf/gltf_read_context.h"
#include "gltf/rig_read.h"
#include "lodbake/core/multires.h"
#include "lodbake/gltf/gltf.h"

namespace lodbake::gltf_detail {

struct MorphLayout;

constexpr const char* kMultiresExtension = "LODBAKE_multires";
constexpr int kMultiresVersion = 2;  // 2: regionUpdates per region (oldRep, newRep); 1: per face

// ---- Reading

// The file's LODBAKE_multires object, nullptr when it has none.
// \throw InvalidInput (not an object), Unsupported (a version newer than kMultiresVersion).
const nlohmann::json* findMultiresExtension(const ReadContext& c);

// True when `ext` maps the original mesh (files written by writeGltf with a Multires).
bool hasMultiresOriginal(const nlohmann::json& ext);

// The glTF node that holds the original mesh (ext.original.node; 0 when absent).
int multiresOriginalNode(const nlohmann::json& ext);

// The original TriMesh, rebuilt exactly (welded vertices, wedges, face order) from the mesh of
// node ext.original.node and the extension's maps; `nodes` = the flattened scene (node, world
// matrix), `rr` = its rig (the original node's skin binding), `layout` = the original node's morph
// targets. Counts the primitives it decodes in asset.stats. \pre hasMultiresOriginal(ext).
// \throw InvalidInput when a map does not match the mesh.
TriMesh readMultiresOriginal(const ReadContext& c, const nlohmann::json& ext, const std::vector<std::pair<int, Mat4>>& nodes,
                             RigRead& rr, const MorphLayout& layout, Asset& asset);

// Levels, collapses, region updates, chart layout and texture hierarchy of `ext`, every index
// checked against `mesh` (the original read by readMultiresOriginal). Version 1 files are upgraded.
// \throw InvalidInput.
Multires readMultires(const ReadContext& c, const nlohmann::json& ext, const TriMesh& mesh);

// ---- Writing

// One written primitive: which (vertex, wedge) each glTF vertex is and which face each triangle is.
struct PrimMap {
    int material = -1;
    std::vector<uint32_t> vertex, wedge, faces;
};

// The meshes writeGltf wrote for the original and the levels (mesh index -1 = no triangles).
struct WrittenMeshes {
    std::vector<PrimMap> originalPrims;
    int originalMesh = -1;
    std::vector<int> levelMeshes;                // per level
    std::vector<std::vector<PrimMap>> levelPrims;  // per level
};

// The LODBAKE_multires object for `mr` over `asset`; its arrays become accessors of `w`.
nlohmann::json writeMultires(BufferBuilder& w, const Asset& asset, const Multires& mr, const WrittenMeshes& written,
                             const WriteOptions& options);

}  // namespace lodbake::gltf_detail
