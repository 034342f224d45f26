// Private to lib/src/gltf: KHR_draco_mesh_compression, the only file that includes Draco.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "gltf/gltf_read_context.h"

namespace lodbake::gltf_detail {

// Decodes the Draco bitstream a primitive's KHR_draco_mesh_compression object `ext` names into
// `p` (attributes by the ids in ext.attributes, triangles). \throw InvalidInput when the data
// is missing or cannot be decoded.
void decodeDraco(const ReadContext& c, const nlohmann::json& ext, PrimData& p, const std::string& what);

}  // namespace lodbake::gltf_detail
