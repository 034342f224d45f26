// A level's primitives (see level_parts.h).
#include "lod/level_parts.h"

#include <algorithm>

namespace lodbake::lod_detail {

void splitLevel(const DrawSplit& split, const std::vector<uint32_t>& triangleGroup, const std::vector<size_t>& selectionOfVariant,
                LodLevelData& L, PackLevelReport& report) {
    if (split.groups.size() < 2) return;
    const size_t triangles = L.indices.size() / 3;
    std::vector<size_t> count(split.groups.size(), 0);
    for (size_t t = 0; t < triangles; ++t) ++count[triangleGroup[t]];
    // Counting sort by group: stable.
    std::vector<size_t> start(split.groups.size() + 1, 0);
    for (size_t g = 0; g < count.size(); ++g) start[g + 1] = start[g] + count[g];
    std::vector<uint32_t> indices(L.indices.size());
    for (size_t t = 0; t < triangles; ++t) {
        const size_t to = start[triangleGroup[t]]++;
        std::copy_n(L.indices.begin() + std::ptrdiff_t(3 * t), 3, indices.begin() + std::ptrdiff_t(3 * to));
    }
    L.indices = std::move(indices);
    L.parts.clear();
    for (size_t g = 0; g < count.size(); ++g) {
        if (count[g] == 0) continue;
        LodPart part;
        part.triangles = count[g];
        part.uniforms = split.groups[g].values[0];
        for (size_t s : selectionOfVariant) part.variantUniforms.push_back(split.groups[g].values[s]);
        L.parts.push_back(std::move(part));
    }
    report.drawCalls = report.materials = L.parts.size();
    report.splitBy.clear();
    for (size_t a = 0; a < L.parts.size(); ++a)
        for (size_t b = a + 1; b < L.parts.size(); ++b) {
            std::vector<std::pair<const MaterialUniforms*, const MaterialUniforms*>> pairs{{&L.parts[a].uniforms, &L.parts[b].uniforms}};
            for (size_t v = 0; v < selectionOfVariant.size(); ++v)
                pairs.push_back({&L.parts[a].variantUniforms[v], &L.parts[b].variantUniforms[v]});
            for (const auto& [x, y] : pairs)
                for (const std::string& d : uniformDifferences(*x, *y))
                    if (std::find(report.splitBy.begin(), report.splitBy.end(), d) == report.splitBy.end()) report.splitBy.push_back(d);
        }
    // One part left (the level shows one group only): one primitive, as an unsplit level.
    if (L.parts.size() == 1) {
        const LodPart& p = L.parts[0];
        applyUniforms(p.uniforms, L.material.alphaMode, L.material.alphaCutoff, L.material.unlit, L.material.ext);
        for (size_t v = 0; v < p.variantUniforms.size() && v < L.variantMaterial.size(); ++v)
            if (L.variantMaterial[v] >= 0) {
                LodMaterial& m = L.variantMaterials[size_t(L.variantMaterial[v])];
                applyUniforms(p.variantUniforms[v], m.alphaMode, m.alphaCutoff, m.unlit, m.ext);
            }
        L.parts.clear();
    }
}

}  // namespace lodbake::lod_detail
