// KHR_materials_variants of an asset: the root list of variant names and, per triangle of the
// flattened mesh, the mapping of the glTF primitive it came from (which material each variant
// selects for it). Selecting variant v replaces a triangle's material by its mapping's material
// for v, or keeps the triangle's own material (TriMesh::triangleMaterial) when the mapping has
// none for v; that is how glTF viewers apply a variant.
//
// Mappings are stored once per distinct table (many primitives usually share one), so the
// per-triangle cost is one index, and an asset without the extension carries empty vectors.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace lodbake {

struct MaterialVariants {
    std::vector<std::string> names;  // root KHR_materials_variants.variants, in file order (a variant's index)
    // Distinct mapping tables: mappings[m][v] = the material (index into Asset::materials) that
    // mapping m selects for variant v; -1 = none (the triangle keeps its own material).
    std::vector<std::vector<int32_t>> mappings;
    // Per triangle of Asset::mesh: index into `mappings`, -1 = its primitive has no mapping.
    // Empty, or as long as the mesh's triangles.
    std::vector<int32_t> triangleMapping;

    bool empty() const { return names.empty(); }
};

// The material of each triangle when variant `v` is selected: `triangleMaterial` with every
// triangle whose mapping names a material for v given that material.
// \pre v < variants.names.size(); triangleMapping empty or as long as triangleMaterial.
inline std::vector<int32_t> variantTriangleMaterials(const MaterialVariants& variants, const std::vector<int32_t>& triangleMaterial,
                                                     size_t v) {
    std::vector<int32_t> out = triangleMaterial;
    for (size_t f = 0; f < out.size() && f < variants.triangleMapping.size(); ++f) {
        const int32_t m = variants.triangleMapping[f];
        if (m < 0 || size_t(m) >= variants.mappings.size()) continue;
        const std::vector<int32_t>& table = variants.mappings[size_t(m)];
        if (v < table.size() && table[v] >= 0) out[f] = table[v];
    }
    return out;
}

// The index of `table` in variants.mappings, appended when it is new; -1 for a table that maps
// no variant (the primitive behaves as without the extension).
inline int32_t internMapping(MaterialVariants& variants, const std::vector<int32_t>& table) {
    bool any = false;
    for (int32_t m : table) any |= m >= 0;
    if (!any) return -1;
    for (size_t i = 0; i < variants.mappings.size(); ++i)
        if (variants.mappings[i] == table) return int32_t(i);
    variants.mappings.push_back(table);
    return int32_t(variants.mappings.size() - 1);
}

}  // namespace lodbake
