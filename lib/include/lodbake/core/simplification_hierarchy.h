// The simplification hierarchy `simplify` and `agsphere-build` produce (thesis 2.3, 3.2): the
// levels, the half-edge collapses that lead to them with the region updates each made, and the
// simplification pairs tying removed vertices to the coarse surfaces.
//
// Indices: "face" = triangle index in the original TriMesh (level 0); "vertex" = welded vertex
// index of the original TriMesh. Half-edge collapse keeps vertices at their original positions,
// so every coarse vertex is an original vertex and every coarse triangle is a surviving original
// face whose corners moved to kept vertices.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

// A removed original vertex V (or a sample on a modified edge) and its closest point P on the
// coarse surface of one level: P = sum_k bary[k] * position(coarse[k]). On a p-boundary P lies
// on a coarse edge: then coarse[2] == coarse[1] and bary[2] == 0.
struct SimplificationPair {
    uint32_t vertex = 0;          // original welded vertex V_i
    std::array<uint32_t, 3> coarse{};  // welded vertices of the coarse triangle (or edge)
    std::array<float, 3> bary{};  // barycentric coordinates of P_i
    uint32_t face = 0;            // the coarse triangle (an original face id) P_i lies on
    float deviation = 0;          // |V_i - P_i|, model units
};

// One level of the hierarchy: a coarser mesh made of surviving original faces.
struct Level {
    // What was asked and what was reached.
    double targetRatio = 0;         // 0 when the target was a count or an error
    uint64_t targetTriangles = 0;
    double targetError = 0;         // --max-error target (model units), 0 if none
    std::string stopReason;         // "target" or the constraint that stopped simplification

    // Geometry: surviving original faces with their current corners.
    std::vector<uint32_t> faces;    // original face id of each level triangle
    std::vector<Tri> triangles;     // welded vertex ids of each level triangle (CCW)
    std::vector<Tri> cornerWedges;  // original wedge used at each corner (for original materials/UVs)
    std::vector<int32_t> triangleMaterial;  // per level triangle; empty = the original faces' materials

    // Regions at this level: faceRegion[f] = representative face of original face f's region.
    std::vector<uint32_t> faceRegion;
    uint32_t regionCount = 0;

    std::vector<SimplificationPair> pairs;

    uint32_t collapseCount = 0;     // collapses applied to reach this level (prefix of Multires::collapses)
    double maxDeviation = 0;        // model units; non-decreasing along the levels
    double meanDeviation = 0;       // mean of pair deviations
    double seconds = 0;             // time spent producing this level (report only, not written to files)
    // When the gross-error bound stopped the level before its triangle target: the bound and the
    // deviation of the cheapest collapse it refused, model units (report only, not written to
    // files; the stop reason says it too). 0 = the bound did not stop the level.
    double grossErrorBound = 0;
    double grossErrorRefused = 0;
};

// One half-edge collapse (removed -> kept) and the region updates it made: the entries
// [regionBegin, regionEnd) of Multires::regionUpdates.
struct CollapseRecord {
    uint32_t removed = 0;
    uint32_t kept = 0;
    float deviation = 0;
    uint32_t regionBegin = 0;
    uint32_t regionEnd = 0;
};

// Region oldRep joined region newRep, or (when no face is labelled newRep yet) was renamed to it:
// every face labelled oldRep takes the label newRep (representative face ids). The records of a
// collapse prefix, replayed in order on the identity table, give the faceRegion of its level; they
// are also the edges of the region hierarchy (child region -> parent).
struct RegionUpdate {
    uint32_t oldRep = 0;
    uint32_t newRep = 0;
};

}  // namespace lodbake
