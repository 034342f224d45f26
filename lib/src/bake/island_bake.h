// Island baking: the bake's side of parameterize's fold fallback. A level island is a UV triangle
// that is not an original face (a level triangle parameterize could not keep injective in its
// chart); each texel it covers maps to a point of its 3D triangle and shows the original surface
// at that point's closest point. layoutBakeIslands (lodbake/bake/bake.h) builds them from a chart
// layout; this header holds what the bake does with them.
#pragma once

#include <vector>

#include "bake/texel_raster.h"
#include "lodbake/bake/bake.h"

namespace lodbake::bake_detail {

// Adds the islands' texels to `hits` (the faces' hits, rasterizeTriangles): texel -> point X of
// the island's 3D triangle -> closest point of those of its faces that face its way (geometric
// normal less than about 143 degrees from the island's: not a thin wall's other sheet; all of
// them when none do). A texel takes the nearest hit, a face's before an island's, the earlier
// island on ties. Islands are measured on `threads` threads, then merged in island order, so the
// hits do not depend on the count.
// \throw InvalidInput (an island without faces).
void rasterizeIslands(const TriMesh& mesh, const std::vector<BakeIsland>& islands, const TexelRegion& g, double dilation,
                      int threads, std::vector<TexelHit>& hits);

// The box of half-side h around c clipped to [lo, hi] ([qlo, qhi]); false when they do not meet.
bool clipToBox(Vec3 c, double h, Vec3 lo, Vec3 hi, Vec3& qlo, Vec3& qhi);
// The grid entries nearFaces scans to list `near`'s faces: its cost.
size_t nearEntries(const IslandNear& near);
// Whether `box` lies farther from p than a face at squared distance best2 by more than `margin`
// (far above rounding: a face's computed closest point can lie an ulp outside its box), so that
// no face in it can be as close.
bool boxFarther(const std::array<double, 6>& box, Vec3 p, double best2, double margin);
// Whether face f (meeting [near.lo, near.hi]) is one `near` describes; n: the island's normal.
bool inNear(const TriMesh& mesh, const IslandNear& near, Vec3 n, uint32_t f);
// The first (lowest id) closest face to p of those `near` describes, as a scan of nearFaces finds
// it, looked up through near.grid in cubes around p doubling from half-side `start`: its squared
// distance (1e300, face untouched, when there is none).
double closestNearFace(const TriMesh& mesh, const IslandNear& near, Vec3 n, Vec3 p, double start, uint32_t& face,
                       std::array<double, 3>& bary);

// d(original UV)/d(texel x) and /d(texel y) at a texel of island `isl` (UVs scaled by `size`)
// whose closest point lies on face f with original UVs T: texel -> 3D on the island's triangle
// (affine), then 3D -> original UV on face f (its tangent plane, affine). Zero for a degenerate
// island or face.
void islandDerivatives(const TriMesh& mesh, const BakeIsland& isl, int size, uint32_t f, const Vec2 T[3], Vec2& dx, Vec2& dy);

}  // namespace lodbake::bake_detail
