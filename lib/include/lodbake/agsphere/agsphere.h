// M-AGSphere: the multiresolution Aligned Gaussian Sphere (thesis 2.4, DESIGN.md).
//
// Faces are mapped to the Gaussian sphere by their normals. The sphere is cut into cells: 8 at
// depth 0 (the octants, i.e. the faces of an octahedron), each split into 4 at the next depth (a
// quadtree; the subdivision is the regular midpoint split of the octahedron's faces, projected
// radially onto the sphere). At a selection of cells (a "cut" of the quadtree), a region is a set
// of edge-connected faces whose normals fall in one selected cell; finer cuts refine regions, so
// the levels form a region hierarchy.
//
// Each level is built from its cut: region boundaries are split into runs (maximal chains between
// junction vertices, shared by exactly the same two regions or by a region and the mesh border);
// each run is simplified (Douglas-Peucker) within the error threshold of its cells, the same way
// on both sides, so neighbouring regions never crack; each region is retriangulated by ear
// clipping its (simplified) boundary projected onto the plane orthogonal to the region's normal
// (else onto its cell's plane), never producing a triangle that faces away from the region.
// Interior vertices disappear; every coarse vertex is an original vertex (point-consistent
// mapping). docs/agsphere.md describes the algorithm, the fallbacks and the measurements.
//
// Output is the same Multires that `simplify` makes (generator "agsphere-build"):
//   - Level::faces[t] is an original face of the region the triangle belongs to (a face of that
//     region incident to the triangle's corners), so materials, wedges and texture charts follow
//     the region; several level triangles may name the same face.
//   - Level::faceRegion[f] is the smallest face id of f's region; regionCount counts regions.
//   - Level::pairs: every removed vertex with its closest point on its region's new triangles
//     (interior vertices) or on the simplified boundary edge (removed run vertices, edge form).
//   - Multires::collapses and regionUpdates stay empty (regions are given per level by
//     faceRegion; no half-edge collapse sequence exists); Level::collapseCount is 0.
// A region whose projected boundary is not a simple polygon (it overlaps itself in projection, or
// has a handle) first gets its boundary runs restored, then keeps its original faces, and then
// (16 faces or more) has its cell split and the level rebuilt.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"

namespace lodbake {

// ---- The Gaussian-sphere cells -------------------------------------------------------------
// A cell at depth d has index in [0, 8 * 4^d): the octant (bit 0: x < 0, bit 1: y < 0,
// bit 2: z < 0) times 4^d plus the base-4 path of children (0..2: the child at corner 0..2 of
// the parent triangle, 3: the centre child). Its parent is index / 4 (for d >= 1).
constexpr int kAgsphereMaxDepth = 8;
uint64_t sphereCellCount(int depth);
// \pre depth in [0, kAgsphereMaxDepth]; n non-zero (a zero vector maps to octant 0).
uint32_t sphereCell(Vec3 n, int depth);
// Unit directions of the cell's three corners and of its centre (the normalized centroid of the
// corners on the octahedron); radius = largest angle (radians) from the centre to a corner.
std::array<Vec3, 3> sphereCellCorners(uint32_t cell, int depth);
Vec3 sphereCellCenter(uint32_t cell, int depth);
double sphereCellRadius(uint32_t cell, int depth);
// Cells at `depth` sharing an edge with `cell` (3 for every cell).
std::vector<uint32_t> sphereCellNeighbours(uint32_t cell, int depth);

// Regions at a uniform depth: faceRegion[f] = smallest face id of f's region (faces with a
// repeated vertex index are regions of their own). Returns the number of regions.
uint32_t agsphereRegions(const TriMesh& mesh, int depth, std::vector<uint32_t>& faceRegion);

// ---- Building levels -----------------------------------------------------------------------
struct AgsphereTarget {
    double ratio = 0;        // fraction of the input triangle count, (0, 1]; 0 = unused
    uint64_t triangles = 0;  // absolute triangle count; 0 = unused
};

struct AgsphereOptions {
    std::vector<AgsphereTarget> levels;  // any order; written finest first
    int maxDepth = 6;                    // finest sphere depth (8 * 4^maxDepth cells), <= kAgsphereMaxDepth
    // Reference directions, from the object towards the viewer / the light (need not be unit).
    // Empty views and lights = view-independent levels (error-driven refinement).
    std::vector<Vec3> views;
    std::vector<Vec3> lights;
    // A cell is a silhouette (orthogonal) cell when its angular range to a reference direction
    // comes within this many degrees of 90.
    double silhouetteBandDeg = 30;
    // Cells facing away from every view (never seen from those directions) stay at depth 0.
    bool backCellsCoarsest = true;
    // With views or lights: the faces on each view's (light's) outline keep their original
    // triangles as regions of their own, and the boundary runs around them keep every vertex, so
    // the level's outline seen from the view is the original's. Outline faces: both faces of every
    // contour edge (between a face towards and a face away from the eye, or a mesh-border edge)
    // whose projection lies on the border of the projected mesh. Seen from a light, the outline is
    // the light silhouette (the shadow's outline). A region whose new triangles would cover, seen
    // from a view or light, what the original leaves uncovered is restored (runs, then original
    // faces). false = the thesis's cell-only selection.
    bool keepOutline = true;
    // Eye distance for the outline, in bounding radii (farthest vertex from the bounding-box centre)
    // from the box centre; 0 = infinitely far (orthographic: the contour depends on the direction
    // only), else > 1. `compare`'s cameras sit at 1 / sin(30 degrees) = 2 radii.
    double viewDistance = 0;
    // Extra rings of faces (sharing a vertex) kept around the outline faces.
    int outlineRings = 0;
    // Boundary runs are simplified while every removed vertex is within
    // boundaryTolerance * (the smaller error threshold of the run's two cells); 0 keeps every
    // boundary vertex (only exactly straight runs lose their middle vertices).
    double boundaryTolerance = 1;
    int threads = 1;  // accepted for the common CLI; the build is single-threaded (results never depend on it)
    // Progress in [0,1]; return false to cancel (throws Cancelled). May be empty.
    std::function<bool(double)> progress;
};

// Statistics of one uniform sphere depth (all cells at that depth).
struct AgsphereDepthStats {
    int depth = 0;
    uint32_t cells = 0;               // non-empty cells
    uint32_t regions = 0;
    uint64_t estimatedTriangles = 0;  // after boundary simplification, before retriangulation
    double maxThreshold = 0;          // largest cell error threshold (model units)
};

struct AgsphereLevelStats {
    std::vector<uint32_t> cellsPerDepth;  // selected cells at each depth (index = depth)
    uint32_t orthogonalCells = 0, referenceCells = 0, coarsestCells = 0, otherCells = 0;
    uint64_t estimatedTriangles = 0;
    uint32_t retriangulatedRegions = 0;
    uint32_t keptRegions = 0;       // regions that kept their original faces (not a simple polygon)
    uint32_t outlineFaces = 0;      // outline faces kept unchanged (keepOutline)
    uint32_t restoredRuns = 0;      // runs whose simplification was undone (failures, collisions)
    uint32_t runs = 0, simplifiedRuns = 0;
    // "target"; "coarsest cut" (the default cut already has more triangles than the target: the
    // region count bounds how far the sphere can go); "finest depth" (no cell left to refine).
    std::string stopReason;
};

struct AgsphereResult {
    Multires multires;               // levels finest first, generator "agsphere-build"
    std::vector<AgsphereLevelStats> levelStats;  // parallel to multires.levels
    std::vector<AgsphereDepthStats> depths;      // depth 0 .. maxDepth
    double diagonal = 0;
    uint32_t contourEdges = 0, outlineEdges = 0, outlineFaces = 0;  // keepOutline, over all views
    double secondsCells = 0, secondsDepths = 0, secondsSelect = 0, secondsLevels = 0;
};

// \pre mesh has finite positions and valid indices (the reader guarantees it).
// \throw Impossible when the mesh has no triangles or a target is invalid.
AgsphereResult buildAgsphere(const TriMesh& mesh, const AgsphereOptions& options);

}  // namespace lodbake
