// Private to lib/src/agsphere: the input mesh as every step of the M-AGSphere pipeline reads it:
// face normals, half-edge twins, vertex -> faces, each face's cell on the (rotated) Gaussian
// sphere, and the outline faces that stay unchanged.
#pragma once

#include <cstdint>
#include <vector>

#include "agsphere/contour.h"
#include "lodbake/agsphere/agsphere.h"
#include "lodbake/core/adjacency.h"
#include "lodbake/core/mesh.h"

namespace lodbake::agsphere_detail {

// "No such item" for region, run and face ids (twins use kBorderEdge / kNonManifoldEdge).
constexpr uint32_t kNone = UINT32_MAX;

// The sphere's frame: rows of the rotation from model directions to sphere directions.
struct Frame {
    Vec3 r0{1, 0, 0}, r1{0, 1, 0}, r2{0, 0, 1};
    Vec3 toSphere(Vec3 v) const { return {dot(r0, v), dot(r1, v), dot(r2, v)}; }
    Vec3 toModel(Vec3 v) const { return r0 * v.x + r1 * v.y + r2 * v.z; }
};

// The first view (else the first light) goes to the centre of octant 0, (1,1,1)/sqrt(3): that
// octant is the reference cell, the opposite octant faces away, the six others hold the
// silhouette. Without views and lights the sphere is not rotated.
Frame alignedFrame(const AgsphereOptions& options);

struct Topology {
    const TriMesh* mesh = nullptr;
    Frame frame;
    uint32_t nf = 0, nv = 0;
    int maxDepth = 0;
    std::vector<Vec3> normal;        // unit face normal
    std::vector<char> degenerate;    // repeated vertex index
    // Per half-edge 3f+k (t[k] -> t[k+1]): its twin, kBorderEdge or kNonManifoldEdge.
    std::vector<uint32_t> twin;
    CompressedRows vertexFaces;      // vertex -> faces (ascending)
    std::vector<uint32_t> finestCell;  // per face, its cell at maxDepth
    // Per face (empty = none): an outline face of a view, kept unchanged as a region of its own
    // (its boundary runs keep every vertex).
    std::vector<char> pinned;
    OutlineFaces outline;  // the views' rasters (keepOutline): new triangles must not leave the outline
    bool isPinned(uint32_t f) const { return !pinned.empty() && pinned[f]; }
    double diagonal = 0;   // of the bounding box, model units
    const Vec3& P(uint32_t v) const { return mesh->positions[v]; }
    const Tri& T(uint32_t f) const { return mesh->triangles[f]; }
};

// Faces without a normal (zero area) take a neighbour's across a manifold edge, else +z.
// \pre maxDepth in [0, kAgsphereMaxDepth]; `mesh` outlives the result (it is referenced).
Topology buildTopology(const TriMesh& mesh, int maxDepth, const Frame& frame = {});

}  // namespace lodbake::agsphere_detail
