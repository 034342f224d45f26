// Private to lib/src/gltf: EXT_meshopt_compression, the only file that includes meshoptimizer.
#pragma once

#include <optional>

#include <nlohmann/json.hpp>

#include "gltf/gltf_read_context.h"

namespace tinygltf {
class Model;
}

namespace lodbake::gltf_detail {

// A fallback buffer (EXT_meshopt_compression {fallback: true}) may have no data; tinygltf would
// reject it (or read the GLB's BIN chunk in its place), so in the JSON tinygltf sees, `patched`
// (a copy of `root`, made on first change), each fallback buffer without a uri becomes a one-byte
// data-URI buffer. Returns whether anything was changed.
bool hideMeshoptFallbackBuffers(const nlohmann::json& root, std::optional<nlohmann::json>& patched);

// Decodes every bufferView whose JSON (c.root) has EXT_meshopt_compression (modes ATTRIBUTES,
// TRIANGLES, INDICES; filters NONE, OCTAHEDRAL, QUATERNION, EXPONENTIAL) into a new buffer of
// `model` and points the view at it, so accessors read decoded bytes.
// \pre model is c's model as tinygltf loaded it. \throw InvalidInput when a view's extension is
// malformed, names missing data or its stream does not decode.
void decodeMeshoptViews(const ReadContext& c, tinygltf::Model& model);

}  // namespace lodbake::gltf_detail
