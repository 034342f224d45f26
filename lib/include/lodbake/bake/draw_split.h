// Which primitives a chain level is drawn with. Every level has one set of baked pages and one UV
// set; what glTF cannot vary per texel (alpha mode and cutoff, unlit, ior, volume attenuation,
// dispersion, iridescence ior: lodbake/core/material_uniforms.h) is one value per primitive, and
// so is whether it transmits (renderers refract only the primitives drawn without transmission).
// The input's triangles are grouped so that each group's materials agree on those values: a level
// gets one primitive per group it has triangles of, all on the same pages and UVs, their materials
// differing in these values only. Sidedness never splits (mixed sidedness gets back
// faces: material_plan.h), and an OPAQUE material joins a MASK group (its alpha is baked as 1).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/core/material_uniforms.h"
#include "lodbake/core/mesh.h"

namespace lodbake {

struct DrawSplitOptions {
    // At most this many groups; 0 = as many as the combinations need. Beyond it the smallest group
    // (by area) merges into its nearest (fewest disagreeing properties, then the largest) until
    // the count fits; a merged group takes area-weighted values and a warning per property.
    size_t maxDraws = 0;
    // false: only alpha mode, cutoff and unlit split (a chain whose material has no extensions,
    // e.g. pack --base-color-only, shows none of the others).
    bool extensionProperties = true;
};

// One group of triangles drawn as one primitive on each level.
struct DrawGroup {
    std::vector<MaterialUniforms> values;  // per selection (the `selections` of splitDraws)
    double area = 0;                       // of its original triangles, model units squared
};

struct DrawSplit {
    std::vector<DrawGroup> groups;    // one when the materials agree (or the mesh is empty)
    std::vector<uint32_t> groupOf;    // per triangle of asset.mesh: its group
    // Per selection: the merged groups' disagreements (mixed alpha modes, shading models, a
    // property's spread and the value taken), worded as the one-material chain always did.
    std::vector<std::vector<std::string>> warnings;
    std::vector<std::string> splitBy;  // the properties on which some two groups differ (uniformDifferences)
};

// A used material and the area of its triangles (model units squared).
struct WeightedMaterial {
    const Material* material;
    double area;
};

// The values one primitive shows for `materials` (non-empty): BLEND if any blends, else MASK if any
// masks (the smallest cutoff); unlit if all are; each extension property the area-weighted mean over
// the materials where it shows: ior over the lit ones (1.5 without KHR_materials_ior), attenuation
// (through its coefficient 1 / distance) and dispersion (0 without the extension) over those with a
// volume, iridescence ior over those with iridescence; transmission if any lit one transmits (a
// transmission factor above 0). Where a value shows on none: `unseen`'s value, or the default
// without it. With `warnings`: one per mix or disagreement.
MaterialUniforms mergeUniforms(const std::vector<WeightedMaterial>& materials, std::vector<std::string>* warnings,
                               const MaterialUniforms* unseen = nullptr);

// Groups asset.mesh's triangles. `selections` (>= 1, the first the default): per triangle the
// material index each selection (a KHR_materials_variants variant) gives it (-1 = the glTF default
// material); the groups keep every selection's values exact.
// \pre every selection has asset.mesh.triangleCount() entries.
DrawSplit splitDraws(const Asset& asset, const std::vector<const std::vector<int32_t>*>& selections,
                     const DrawSplitOptions& options = {});

}  // namespace lodbake
