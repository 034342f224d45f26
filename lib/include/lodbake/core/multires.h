// The multiresolution model: what `simplify` (and later `agsphere-build`) produce and
// `parameterize`, `texture-refine` and `pack` consume. It travels between tools inside the glTF
// as the LODBAKE_multires vendor extension (docs/LODBAKE_multires.md): the simplification
// hierarchy, the chart layout and the texture hierarchy together.
#pragma once

#include <string>
#include <vector>

#include "lodbake/core/chart_layout.h"
#include "lodbake/core/mesh.h"
#include "lodbake/core/simplification_hierarchy.h"
#include "lodbake/core/texture_hierarchy.h"

namespace lodbake {

// The three parts as one value, the contents of one LODBAKE_multires file.
struct Multires {
    std::vector<Level> levels;  // finest first (excluding the original, which is the TriMesh itself)
    std::vector<CollapseRecord> collapses;
    std::vector<RegionUpdate> regionUpdates;
    ChartLayout charts;
    TextureHierarchy textures;  // empty until texture-refine ran
    std::string generator = "simplify";  // "simplify" or "agsphere-build"
};

// The TriMesh of level `level` (0 = the original `mesh` itself, k >= 1 = multires.levels[k-1]):
// same positions and wedges as `mesh`, the level's triangles, corners and materials.
// \pre multires was produced for `mesh`; 0 <= level <= multires.levels.size().
TriMesh levelMesh(const TriMesh& mesh, const Multires& multires, size_t level);

}  // namespace lodbake
