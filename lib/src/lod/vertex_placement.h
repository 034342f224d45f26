// Vertex placement of a coarse level whose connectivity is final (issue 24): half-edge collapse
// keeps every coarse vertex at an original vertex's position, so a coarse level lies inside the
// surface where the original bulges and outside where it is hollow. Placement moves the level's
// vertices to minimise the two-sided squared distance to the original surface:
//
//   E(x) = sum over simplification pairs   w_p |P(x) - V|^2        (removed vertex V, its point P on the level)
//        + sum over samples S of the original   w_o |Q(x) - S|^2   (Q: S's closest point on the level)
//        + sum over samples L(x) of the level   w_l |L(x) - C|^2   (C: L's closest point on the original)
//        + sum over level vertices   w_a |x_v - x_v^0|^2           (damping towards the round's start)
//
// (each weight then scaled by 1 + (d / rms)^p, see PlacementOptions::reweightPower)
// with P, Q and L fixed barycentric combinations of the level's vertices, so each round is a
// linear least-squares problem (solved through its normal equations); the closest points are
// found again between rounds (ICP-style). The weights make the sample sums area integrals (w = area / samples), so
// both sides count alike whatever their triangle counts.
//
// Constraints: vertices on an open or non-manifold edge of the level stay where they are (the
// boundary of an open surface, and the rim where parts touch); a welded vertex moves as one, so all
// its wedges (charts, regions, materials, skin weights) follow it; a round's step is shortened
// per vertex until no level face turns by 90 degrees or more from its unmoved orientation (or
// loses almost all its area). Output depends on the inputs only, never on the thread count.
#pragma once

#include <cstddef>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/simplification_hierarchy.h"
#include "lodbake/metrics/distance.h"

namespace lodbake::lod_detail {

struct PlacementOptions {
    // Closest points found again and the least squares solved this many times. No early stop: the
    // sampled RMS distance levels off after 2-3 rounds while the reweighting keeps lowering the
    // largest distances.
    int rounds = 8;
    // Each term's weight is multiplied by 1 + (d / rms)^p, d its distance at the round's start and
    // rms that of all sample terms: least squares alone lowers the mean distance, the reweighting
    // leans it towards the largest ones (the Hausdorff distance). 0 = plain least squares.
    double reweightPower = 2;
    // Area samples per side and round: samplesPerTriangle per triangle of the original, at least
    // minSamples, at most one per original triangle between samplesPerSide and samplesPerSideMax
    // (fewer samples than triangles miss a dense original's narrow features, which the Hausdorff
    // distance finds); at most samplesPerSideLarge for an original of more than largeOriginal
    // triangles, where the rounds' closest-point queries would dominate the chain's time.
    size_t samplesPerTriangle = 16;
    size_t minSamples = 2000;
    size_t samplesPerSide = 20000;
    size_t samplesPerSideMax = 60000;
    size_t largeOriginal = 250000;
    size_t samplesPerSideLarge = 20000;
    // ... and at most samplesPerVertex per free level vertex (at least minSamples): few unknowns need
    // few samples.
    size_t samplesPerVertex = 128;
    double damping = 1e-2;        // weight of |x - x_round_start|^2 relative to the mean area per level vertex
    int threads = 0;              // closest-point queries; 0 = all cores (never changes the result)
};

struct PlacementResult {
    std::vector<Vec3> positions;  // the original's welded positions with the level's vertices moved
    size_t moved = 0;             // level vertices that moved
    size_t fixed = 0;             // level vertices held on an open or non-manifold edge
    size_t shortened = 0;         // vertex steps shortened (summed over rounds) to keep faces from flipping
    int rounds = 0;               // rounds run
};

// `original` is the full-resolution mesh and `surface` its nearest-point reference (shared with
// the measurement of the levels); `level` names its vertices (welded ids of `original`) and carries
// the simplification pairs.
PlacementResult placeLevelVertices(const TriMesh& original, const DistanceReference& surface, const Level& level,
                                   const PlacementOptions& options = {});

}  // namespace lodbake::lod_detail
