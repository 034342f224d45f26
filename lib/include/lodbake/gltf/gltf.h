// glTF 2.0 reading and writing. The only module that includes tinygltf and Draco.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"

namespace lodbake {

struct ReadOptions {
    // Images stay encoded (checkImages in lodbake/texture/codec.h decodes them). A missing or
    // unreadable image file is an error, or with false a warning (the image is then left empty).
    bool requireImageData = true;
    // MSFT_lod level to read: -1 = the scene as it is (LOD0 of an MSFT_lod chain); K >= 0 replaces
    // every scene root node that carries extensions.MSFT_lod by its level K (0 = the node itself,
    // K >= 1 = ids[K-1]). Ignored for LODBAKE_multires files. \throw Impossible when K >= 1 and no
    // root has MSFT_lod, or a root's chain is shorter than K.
    int lod = -1;
};

// Reads a .gltf or .glb: default scene (or scene 0, or every root node when there is no scene),
// node hierarchy flattened with TRS/matrix transforms (negative determinant flips winding),
// every TRIANGLES / TRIANGLE_STRIP / TRIANGLE_FAN primitive (points and lines dropped with a
// warning), all accessor component types (normalized or not), sparse accessors, interleaved
// views, data URIs, external files relative to the asset, KHR_draco_mesh_compression,
// KHR_mesh_quantization, KHR_texture_transform, KHR_materials_unlit. Skinned meshes are flattened
// in bind pose (the node transform of the mesh node); skins, the joint hierarchy and node
// animations become asset.rig with per-wedge influences (lodbake/core/rig.h), and an unskinned
// mesh node of an asset that moves becomes a joint of its own. Morph targets are dropped with a
// warning. EXT_mesh_gpu_instancing is expanded (one copy of the mesh per instance, node world x
// instance TRS); KHR_lights_punctual lights, cameras, the nodes placing them and the root / asset /
// scene extras go to asset.scene (lodbake/core/scene_extras.h), which writeGltf and writeLodChain
// write back. What is not carried (another root or node extension) is named in asset.warnings.
//
// When the file carries a LODBAKE_multires extension, `multires` (if non-null) receives it and
// asset.mesh is the original (level-0) mesh it refers to.
//
// \throw IOError (missing/unreadable file), InvalidInput (malformed glTF, out-of-range indices,
//        NaN/Inf positions), Unsupported (extensionsRequired entry not supported), all with
//        one-line messages starting with the path.
Asset readGltf(const std::string& path, const ReadOptions& options = {},
               std::optional<Multires>* multires = nullptr);

// readGltf of a file whose bytes are already in memory (the lodbake chain passes each stage's
// output on this way; it moves them in, so they are freed once parsed). `path` names the data in
// messages and in Asset::sourcePath, and relative URIs resolve against its folder.
// \throw as readGltf.
Asset readGltfBytes(const std::string& path, std::vector<unsigned char> bytes, const ReadOptions& options = {},
                    std::optional<Multires>* multires = nullptr);

struct WriteOptions {
    std::string generator = "lodbake";
    bool embedImages = true;  // images go into the buffer (GLB chunk or .bin) rather than beside
};

// Writes `asset` (and, when non-null, the levels of `multires` as extra meshes plus the
// LODBAKE_multires extension). Output format follows the extension of `path` (.glb or .gltf,
// which writes PATH.bin beside it). Written atomically: temporary files renamed into place.
//
// Layout: node 0 / mesh 0 = the original mesh, node k / mesh k = level k (k >= 1); all nodes are
// in the scene, level nodes translated side by side along +x (1.25 bounding-box widths apart) so
// a viewer shows the chain; the mesh data itself stays in the original's world space. One
// primitive per material per mesh. readGltf of such a file returns node 0 only as asset.mesh.
// With a rig (asset.rig), every mesh node uses its one skin (JOINTS_0 / WEIGHTS_0), the levels
// are not translated, and the rig's nodes and animations follow the mesh nodes; reading the file
// back gives the same rig and influences. asset.scene's light and camera nodes come last, each a
// scene root at its world transform.
//
// \throw IOError when the file cannot be written.
void writeGltf(const std::string& path, const Asset& asset, const Multires* multires = nullptr,
               const WriteOptions& options = {});

// The bytes writeGltf writes to a .glb file (images embedded whatever options.embedImages says);
// `path`, which must end in .glb, names the data in messages. \throw as writeGltf.
std::vector<unsigned char> encodeGlb(const std::string& path, const Asset& asset, const Multires* multires = nullptr,
                                     const WriteOptions& options = {});

// Writes `bytes` to `path` atomically (temp file in the same folder, then rename).
void writeFileAtomic(const std::string& path, const std::string& bytes);
// The same for a file made of `parts` one after another (no copy into one string).
void writeFileAtomic(const std::string& path, const std::vector<std::string_view>& parts);

}  // namespace lodbake
