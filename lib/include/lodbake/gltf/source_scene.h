// The input asset as it is, for a chain whose LOD0 is the original (pack --lod0 original): its
// own meshes, materials, textures, samplers, node hierarchy, skins, morph targets, animations,
// lights and cameras, carried into the chain's file untouched (writeLodChain: lodbake/gltf/msft_lod.h).
// The document stays glTF JSON (text) plus one binary buffer: no tinygltf type leaves lib/src/gltf.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lodbake {

struct SourceScene {
    std::string path;
    // The file's glTF JSON, rewritten so that it stands alone on `bin`: one buffer (buffer 0 =
    // `bin`), every bufferView copied into it (EXT_meshopt_compression views decoded; views no
    // accessor or image uses, such as Draco bitstreams, left out), KHR_draco_mesh_compression
    // primitives decoded into plain FLOAT / UNSIGNED_SHORT / UNSIGNED_INT accessors, every image
    // in a buffer view (its mimeType set). Everything else is the file's own JSON, indices
    // unchanged except bufferViews. Its `scenes` / `scene` are left out: `roots` are the nodes of
    // the scene readGltf reads.
    std::string json;
    std::vector<unsigned char> bin;
    std::vector<int> roots;
    // What it draws (the nodes reachable from `roots`): one draw call per primitive of a mesh node
    // (an EXT_mesh_gpu_instancing node draws each primitive once, instanced), the distinct
    // materials those primitives use (no material = the default one, counted once), and the
    // triangles of readGltf's flattened mesh of the same file.
    size_t drawCalls = 0, materials = 0, meshes = 0, nodes = 0, textures = 0, images = 0, skins = 0, animations = 0;
    size_t triangles = 0, vertices = 0;  // ... and the vertices of its triangle primitives (as stored)
    uint64_t geometryBytes = 0, imageBytes = 0;  // of `bin`: image views, and the rest
    // The flattened asset's rig (readGltf(path).rig): the glTF node of each Rig::nodes entry and the
    // glTF animation of each Rig::animations entry, indices into `json`.
    std::vector<int> rigNodes, rigAnimations;
    std::vector<std::string> decoded;  // the compression decoded, e.g. "KHR_draco_mesh_compression (3 primitives)"
};

// Reads `path` (.gltf or .glb) as readGltf does (lodbake/gltf/gltf.h) and keeps its document.
// \throw the errors of readGltf; Impossible for a file with LODBAKE_multires (an intermediate,
//        not an original) or a node with MSFT_lod (already a chain); Unsupported for a
//        Draco-compressed primitive that is not triangles or has morph targets.
SourceScene readSourceScene(const std::string& path);

}  // namespace lodbake
