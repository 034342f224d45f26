// Private to lib/src/gltf: what the steps of readGltf share. The model tinygltf loaded, its JSON
// (for what tinygltf does not keep: extensions, LODBAKE_multires), bounds-checked accessor reads
// and the decoding of one primitive into glTF-local arrays.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lodbake/core/mesh.h"

namespace tinygltf {
class Model;
}

namespace lodbake::gltf_detail {

struct ReadContext {
    std::string path;
    // The file's bytes when they are already in memory (readGltfBytes; loading moves them out, so
    // no second copy lives beside tinygltf's buffers); null = read `path`.
    std::vector<unsigned char>* bytes = nullptr;
    const tinygltf::Model* model = nullptr;
    nlohmann::json root;
};

// \throw InvalidInput naming the JSON pointer of the first structural error of c.root (the schema's
// types for what the reader uses, indexed semantics continuous, bufferViews inside their buffers).
void checkStructure(const ReadContext& c);

// \throw InvalidInput "<path>: <what>".
[[noreturn]] void fail(const ReadContext& c, const std::string& what);

// The integer member `key` of `o`, or `def` when it is absent or not an integer.
int jint(const nlohmann::json& o, const char* key, int def = -1);

// The bytes [offset, offset + length) of bufferView `viewIndex`, bounds-checked against its buffer.
const unsigned char* viewBytes(const ReadContext& c, int viewIndex, size_t& length, const std::string& what);

// Accessor `index` as unsigned integers / floats with `comps` components per element; empty when
// index < 0. \throw InvalidInput on a wrong component count or out-of-range values.
std::vector<uint32_t> readU32(const ReadContext& c, int index, int comps, const std::string& what);
std::vector<float> readF32(const ReadContext& c, int index, int comps, const std::string& what);

// One primitive's data, glTF-local (before node transforms).
struct PrimData {
    std::vector<Vec3> pos;
    std::vector<Vec3> normal;
    std::vector<Vec4> tangent;
    std::vector<Vec2> uv0, uv1;
    std::vector<Vec4> color;
    // JOINTS_n / WEIGHTS_n, n = 0 .. influenceSets-1: 4 * influenceSets per vertex, skin joint
    // indices and weights as stored (weights normalised when the accessor is).
    int influenceSets = 0;
    std::vector<uint32_t> joints;
    std::vector<double> weights;
    std::vector<Tri> tris;  // glTF vertex indices, glTF winding
    // Morph targets: per target, POSITION deltas per vertex, NORMAL / TANGENT deltas (xyz) per
    // vertex or empty.
    struct Target {
        std::vector<Vec3> position, normal, tangent;
    };
    std::vector<Target> targets;
};

// Triangles of `idx` under glTF primitive `mode` (TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN)
// appended to p.tris. \pre p.pos holds the vertices. \throw InvalidInput on an index out of range.
void assembleTriangles(const ReadContext& c, const std::vector<uint32_t>& idx, int mode, PrimData& p, const std::string& what);

// \throw InvalidInput when a position is NaN or infinite.
void checkFinitePositions(const ReadContext& c, const PrimData& p, const std::string& what);

// Decodes primitive `primIndex` of mesh `meshIndex` (accessors or KHR_draco_mesh_compression);
// returns false, with a warning in `asset`, for primitives that are dropped (points, lines, no
// POSITION).
bool decodePrimitive(const ReadContext& c, int meshIndex, int primIndex, Asset& asset, PrimData& p);

// Where the flattened asset's rig came from: the glTF node of each Rig::nodes entry and the glTF
// animation of each Rig::animations entry.
struct RigSources {
    std::vector<int> nodes;
    std::vector<int> animations;
};

// readGltf (default options, no LODBAKE_multires) that keeps the loaded file: `model` with its
// buffers (EXT_meshopt_compression views decoded; the images' bytes move to the asset) and c.root
// the file's JSON, for source_scene.cpp. \throw as readGltf.
Asset readKeepingModel(ReadContext& c, tinygltf::Model& model, RigSources& rigSources);

}  // namespace lodbake::gltf_detail
