// Planar polygon triangulation used by agsphere-build to retriangulate regions (thesis 2.4,
// "two-pass ear clipping on the candidate boundary projected to the cell plane").
// Header-only types, implementation in lib/src/agsphere/polygon.cpp. No dependencies.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "lodbake/core/math.h"
#include "lodbake/core/mesh.h"

namespace lodbake {

// A polygon with holes: `loops` hold point ids (indices into `points`), each loop closed
// implicitly (last -> first). The outer loop is counter-clockwise (positive area), holes are
// clockwise. An id may appear more than once (a boundary that touches itself at a vertex, or a
// hole touching the outer loop there); distinct ids are distinct points.
struct PlanarPolygon {
    std::vector<Vec2> points;
    std::vector<std::vector<uint32_t>> loops;
};

// Whether the polygon is (weakly) simple: no two of its segments meet except consecutive
// segments at their shared id or segments meeting at a repeated id, no segment is repeated and
// no two segments at a shared id overlap; exactly one loop has positive area.
bool polygonIsSimple(const PlanarPolygon& polygon);

// Triangulates the polygon by ear clipping after bridging the holes into the outer loop.
// Appends triangles (point ids, counter-clockwise) to `out` and returns true, or returns false and
// leaves `out` unchanged when it cannot (not simple, or an ear could not be found).
//
// Guarantee: when the polygon is simple (polygonIsSimple) and this returns true, every triangle
// has strictly positive area and the triangles tile the polygon without overlap: each clipped ear
// has positive area, and the ears' boundary chains sum to the polygon's boundary, so their
// indicator functions sum to the polygon's winding number (1 inside, 0 outside).
// `allowDiagonal(a, b)`, when given, may veto a diagonal between point ids a and b (used to keep
// a region's new edges off edges its neighbours already use); `allowTriangle(a, b, c)` may veto
// any triangle (used to keep new triangles facing their region's surface). A diagonal that would
// repeat a current edge of the polygon is never made.
bool triangulatePolygon(const PlanarPolygon& polygon, std::vector<Tri>& out,
                        const std::function<bool(uint32_t, uint32_t)>& allowDiagonal = {},
                        const std::function<bool(uint32_t, uint32_t, uint32_t)>& allowTriangle = {});

}  // namespace lodbake
