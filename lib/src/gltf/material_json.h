// Private to lib/src/gltf: a material's texture references and KHR_materials_* extensions to and
// from glTF JSON, shared by the reader, the intermediate writer and the MSFT_lod writer. Writing
// then reading gives back the same values (every field of a present extension is written).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lodbake/core/material_extensions.h"

namespace lodbake::gltf_detail {

// A textureInfo object (index, texCoord, `scaleKey` when given, KHR_texture_transform).
TextureRef readTextureRef(const nlohmann::json& o, const char* scaleKey);

// The textureInfo of `r` with index `index`; `scaleKey` written when r.scale != 1. Sets
// usedTransform when it writes KHR_texture_transform.
nlohmann::json textureRefJson(const TextureRef& r, int index, const char* scaleKey, bool& usedTransform);

// The extension names readMaterialExtensions reads (KHR_materials_clearcoat, ...), sorted.
const std::vector<std::string>& readMaterialExtensionNames();

// The extensions of `extensions` (a material's "extensions" object) that lodbake reads.
MaterialExtensions readMaterialExtensions(const nlohmann::json& extensions);

// Writes the present extensions of `e` into `extensions` (a material's "extensions" object) and
// adds their names to `used`. `textureIndex` maps a reference to the glTF texture index to write,
// -1 = leave the reference out.
void writeMaterialExtensions(const MaterialExtensions& e, const std::function<int(const TextureRef&)>& textureIndex,
                             nlohmann::json& extensions, std::vector<std::string>& used, bool& usedTransform);

}  // namespace lodbake::gltf_detail
