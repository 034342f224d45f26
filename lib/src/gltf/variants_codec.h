// Private to lib/src/gltf: KHR_materials_variants (lodbake/core/material_variants.h) read from a
// glTF's JSON and written into one. The intermediates keep the original's mappings on its
// primitives, so the variants reach pack through every stage; the MSFT_lod chain writes one
// material per variant per level and each level primitive's mappings.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "gltf/gltf_read_context.h"
#include "lodbake/core/material_variants.h"

namespace lodbake::gltf_detail {

constexpr const char* kMaterialVariants = "KHR_materials_variants";

// The root variant names of c.root (empty without the extension). A variant without a name gets
// "variant N". \throw InvalidInput on a malformed root extension.
std::vector<std::string> readVariantNames(const ReadContext& c);

// The mapping of primitive `primIndex` of mesh `meshIndex` (c.root's JSON), interned into
// `variants` (names set): its index in variants.mappings, or -1 without one.
// \throw InvalidInput on a material or variant index out of range.
int32_t readPrimitiveMapping(const ReadContext& c, int meshIndex, int primIndex, MaterialVariants& variants);

// Sets triangles [first, end) of variants.triangleMapping to `mapping` (the vector grows with -1).
void assignTriangleMapping(MaterialVariants& variants, size_t first, size_t end, int32_t mapping);

// {"variants": [{"name": ...}, ...]}: the root extension's object.
nlohmann::json variantsRootJson(const std::vector<std::string>& names);

// A primitive's extension object {"mappings": [{"material", "variants"}...]} for `table`
// (table[v] = material of variant v, -1 = none; materials offset by `materialBase`), one entry
// per material in increasing order; null when the table maps nothing.
nlohmann::json primitiveVariantsJson(const std::vector<int32_t>& table, size_t materialBase = 0);

}  // namespace lodbake::gltf_detail
