// Private to lib/src/agsphere: the faces that make a mesh's outline seen from a view.
#pragma once

#include <cstdint>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

struct OutlineOptions {
    // Eye distance from the bounding-box centre, in bounding radii (the farthest vertex from that
    // centre); 0 = infinitely far (orthographic: the contour depends on the direction only).
    // \pre 0 or > 1.
    double viewDistance = 0;
    int rasterSize = 2048;     // square raster of the projected mesh, pixels
    double bandPixels = 3;     // a contour edge within this many raster pixels of the outline counts
    int rings = 0;             // extra rings of faces (sharing a vertex) around the outline faces
};

// One view's projection and raster (kept to test new triangles against the original's outline).
struct OutlineView {
    Vec3 centre, d, u, w, eye;
    bool perspective = false;
    double x0 = 0, y0 = 0, scale = 1, margin = 0;  // raster pixel = (projected - (x0, y0)) * scale + margin
    int size = 0;
    std::vector<char> outside;  // per pixel: uncovered by the original, and so are its 8 neighbours
    std::vector<uint32_t> outsideSum;  // (size + 1)^2 summed-area table of `outside`
    // Raster coordinates of p; false when p is behind the eye.
    bool project(Vec3 p, double& x, double& y) const;
};

struct OutlineFaces {
    std::vector<OutlineView> views;
    std::vector<char> keep;     // per face: 1 = on the outline of some view
    uint32_t contourEdges = 0;  // front/back (and mesh-border) edges, over all views
    uint32_t outlineEdges = 0;  // of which on the projected outline
    uint32_t faces = 0;         // faces with keep = 1
};

// For each view direction (from the object towards the eye; need not be unit): the contour edges
// (a manifold edge between a face facing the eye and one facing away, or a mesh-border edge) whose
// projection lies on the outline of the projected mesh (the border of the union of all projected
// triangles, rasterized), and both faces of each. \pre finite positions, valid indices.
OutlineFaces outlineFaces(const TriMesh& mesh, const std::vector<Vec3>& views, const OutlineOptions& options);

// True when triangle (a, b, c) covers, in some view, a raster pixel centre that the original
// leaves uncovered (with its 8 neighbours): the triangle would push the outline out.
bool protrudes(const OutlineFaces& outline, Vec3 a, Vec3 b, Vec3 c);

}  // namespace lodbake
