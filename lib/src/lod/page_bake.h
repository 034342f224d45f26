// A level's page baked from the original: the original triangles at the page UVs (bakePage), or,
// for a coarse level, each level triangle's texels from the original surface at the closest point
// (bakeProjected).
#pragma once

#include <cstddef>

#include "lodbake/bake/bake.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/gltf/msft_lod.h"
#include "lod/level_page.h"

namespace lodbake::lod_detail {

// How far beyond the level's measured deviation the projection bake searches the original, x the
// bounding box diagonal.
constexpr double kProjectionSlack = 1e-4;

// The projection bake's search reach around a level triangle (model units): its measured
// Hausdorff distance, with a margin, and a little more for a level that measured no deviation.
inline double projectionReach(double hausdorff, double diagonal) { return 1.5 * hausdorff + kProjectionSlack * diagonal; }

// A width x height page's bake: UVs scaled by the longer side, only the page baked, pixels left
// for the chain to encode.
BakeOptions pageBakeOptions(int width, int height, const BakeChannels& channels, int threads);

// Bakes the original triangles at the page UVs: every channel of `channels`, the normal map in
// the frames of `target` (the level's own mesh on this page; null without a normal map).
// `sourceTexels`: the page copies the original's texels (its gutters continue each chart's copy).
// Finds L's island faces on the first page that places an island (islandFacesOf).
BakeResult bakePage(const BakeSources& sources, LayoutData& L, const LevelAtlas& la, const BakeChannels& channels,
                    const BakeTarget* target, int threads, bool sourceTexels);

// The grid bakeProjected searches: the original's faces less coincident copies (withoutCopies,
// over the index-valid faces in id order). A copy loses every closest-point tie to the first face
// at its place, and every filter of the search keeps or drops a face's copies with it, so no bake
// answer changes, while an instanced part's k copies cost one face in every search.
FaceGrid projectionGrid(const TriMesh& mesh, int threads);

// The projection bake of a coarse level: every level triangle is an island of the page (its own
// 3D triangle at its page UVs) whose texels show the original surface at the closest point, found
// among the original faces whose boxes lie within `reach` of the triangle's box (the level's
// measured deviation bounds how far that point can be; the search widens, up to 4 x `diagonal`,
// until it finds faces). `front` = the level triangles before back-face copies (those share their UVs).
BakeResult bakeProjected(const BakeSources& sources, const FaceGrid& grid, const LodLevelData& L, size_t front, int width,
                         int height, double reach, double diagonal, const BakeChannels& channels, const BakeTarget* target,
                         int threads);

}  // namespace lodbake::lod_detail
