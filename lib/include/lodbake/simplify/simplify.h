// Half-edge-collapse simplification with a region hierarchy (thesis 2.3 and 3.2, DESIGN.md).
//
// Collapses (v_i -> v_j) keep v_j at its original position, so coarse vertices are original
// vertices (point-consistent mapping). Collapses are ordered by vertex deviation; a collapse
// that flips or degenerates a face, changes topology (link condition) or breaks a region rule
// is rejected. Vertices on edges with 3+ faces never move nor absorb others; pinch (bow-tie)
// vertices never move but absorb their manifold neighbours; inconsistent winding is no lock.
// Regions start as single faces and merge as collapses happen; the three p-boundary rules of
// DESIGN.md are applied. Every level records its regions and its
// simplification pairs. The method: docs/simplify.md.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"
#include "lodbake/core/pose_samples.h"

namespace lodbake {

struct LevelTarget {
    double ratio = 0;        // fraction of the input triangle count, (0, 1]; 0 = unused
    uint64_t triangles = 0;  // absolute triangle count; 0 = unused
    double maxError = 0;     // stop before the vertex deviation exceeds this, relative to the
                             // bounding-box diagonal; 0 = unused
};

struct SimplifyOptions {
    std::vector<LevelTarget> levels;  // any order; levels are produced finest first
    // Rule 3 epsilon: max(epsilonDeviationFactor * deviation, epsilonBoxFactor * longest box side).
    double epsilonDeviationFactor = 0.1;
    double epsilonBoxFactor = 0.01;
    // Rule 2: collapses whose deviation is within this factor of the best are ranked by E_region.
    double similarDeviation = 0.05;   // relative tolerance; 0 disables region-shape ranking
    double maxNormalChangeDeg = 90;   // reject a collapse that turns a face normal by more
    // Regions become texture charts: reject a merge whose region would spread its normals wider
    // than a spherical cap of this half-angle (degrees; 180 disables, the default). Such a collapse
    // may still keep the boundary (rule 3) at a cost raised to the boundary's displacement.
    // \bug Experimental: with limits below 180 the levels reach their targets on the real assets,
    //      but the kept boundaries' slivers give parameterize more folded level triangles.
    double maxRegionConeDeg = 180;
    // When a triangle target cannot be reached otherwise (parts locked by non-manifold edges or
    // pinch vertices, rule 1), whole components whose half bounding-box diagonal is below this fraction of the
    // model's diagonal are removed, smallest first; their size enters the level's maxDeviation. 0 disables.
    double pruneStuckSize = 0.2;
    // Gross-error stop of triangle-count levels (--ratio, --triangles): a collapse, or a part
    // removal, that would leave the level further than this fraction of the bounding-box diagonal
    // from the original is refused, and the level keeps the triangles it has (its stop reason and
    // Level::grossError say so). A far level that is still recognisable deviates well below it; a
    // tiny asset (a 12-triangle box) would otherwise collapse into a wedge or a tetrahedron. Error
    // targets (LevelTarget::maxError) set their own bound. 0 disables.
    double grossError = 0.25;
    // Two-sided cost: besides the removed vertex's distance to the new fan (the thesis's vertex
    // deviation), a collapse costs the new fan's distance to the surface it replaces, sampled at
    // its faces' centroids and new edges' midpoints. Off by default: on the shared assets it wins
    // at 10% and loses silhouette at 2% (docs/benchmarks.md, "Coarse levels").
    bool twoSidedCost = false;
    // Parts by visual weight: components are pruned lightest (least surface area) first, and a
    // pass prunes every component smaller than its error limit that is closed or cannot shrink
    // any further (open or locked ones too), so a coarse level does not spend its budget on small
    // parts stuck on their locks while collapses of large surfaces grow expensive. false: pruning
    // by size, and in a pass closed parts only.
    bool visualWeight = true;
    // Skinned meshes (Wedges::joints): a vertex moves only onto a neighbour whose joint weights
    // differ from its own by at most this total variation (half the sum of |weight differences|
    // over the joints; 0 = identical influences, 1 = any), so a level does not tear or bend
    // differently from the original when posed. A vertex where parts of different influences
    // meet never moves. kAutoInfluenceChange (the default): 1 when `posed` holds poses of the
    // asset's motion (two or more: samplePoses gives the rest pose, then each animation's times),
    // whose measure then judges every collapse by the posed surface it leaves (a hard limit on
    // the weights forbids the collapses along painted limbs, where every ring binds its own way,
    // that a coarse level needs: the budget then goes to collapses that spike the body), and
    // kBindPoseInfluenceChange otherwise: in the bind pose only, or with the rest pose alone (a
    // skin without animations, to be moved by motions this measure never sees).
    static constexpr double kAutoInfluenceChange = -1;
    static constexpr double kBindPoseInfluenceChange = 0.1;
    double maxInfluenceChange = kAutoInfluenceChange;
    // Rigged meshes: the mesh's wedges at sampled poses (poseWedges in lodbake/core/pose_samples.h;
    // the simplify stage fills it from the asset's rig). Each collapse's cost is its vertex
    // deviation in the bind pose and in every sampled pose, the largest, and so is each level's
    // maxDeviation, so a level stays within it when posed at those times. Empty = bind pose only.
    // \bug Under an error target (LevelTarget::maxError) the exact measure of attached points is
    //      taken in the bind pose; the level's maxDeviation still counts the posed pairs.
    PosedWedges posed;
    // Candidate evaluation and simplification pairs run on this many threads (the collapse walk
    // is sequential); results are identical for any value.
    int threads = 1;
    // Progress in [0,1]; return false to cancel (throws Cancelled). May be empty.
    std::function<bool(double)> progress;
};

struct SimplifyResult {
    Multires multires;
    double diagonal = 0;  // bounding-box diagonal of the input, model units
};

// \pre mesh has finite positions and valid indices (the reader guarantees it).
// \throw Impossible when the mesh has no triangles.
SimplifyResult simplify(const TriMesh& mesh, const SimplifyOptions& options);

}  // namespace lodbake
