// Applying a parameterization: the atlas of a parameterize() result written into the asset (chart
// wedges, the baked material) and into every level of the multires (applyAtlas).
#pragma once

#include <cstddef>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"
#include "lodbake/param/parameterize.h"

namespace lodbake {

struct AtlasApplyStats {
    size_t newWedges = 0;
    size_t projectedCorners = 0;  // level corners whose vertex is not in the chart of the face
    size_t islandTriangles = 0;   // level triangles (all levels) written with island UVs
    int material = -1;            // index of the added material
};

// Adds the atlas to the asset: appends chart-split wedges (uv0 = atlas UV, normal/tangent/uv1
// copied, colour white: it is baked) to asset.mesh.wedges, appends a Material using `bakedImage`
// (plus its Texture and Image; factors only when bakedImage has no bytes), and gives every level new cornerWedges and a triangleMaterial
// override pointing at that material. Level 0 (the original triangles) keeps its wedges and
// materials; original wedges get uv0 = (0,0) when the asset had no TEXCOORD_0.
// The level UVs are param.levels (chart of each triangle from levelTriangleCharts; a corner whose
// vertex is not a vertex of that chart takes the UV of the closest point of the chart's surface;
// island triangles their island's UVs, with their own wedges).
// multires.charts receives the layout (faceChart, cornerUV, the added material and image).
AtlasApplyStats applyAtlas(Asset& asset, Multires& multires, const ParameterizeResult& param, const Image& bakedImage);

}  // namespace lodbake
