// Rigged meshes: the vertex deviation and the level deviation measured in sampled poses as well as
// in the bind pose, so a level stays within its reported deviation when the asset moves
// (docs/simplify.md, "Skinned meshes"). Posed positions come per wedge
// (lodbake/core/pose_samples.h): a corner poses with the influences of its own wedge. Private to
// lib/src/simplify.
#pragma once

#include "collapse_rules.h"
#include "lodbake/core/pose_samples.h"

namespace lodbake::simplify_detail {

// The vertex deviation of collapse (v_i -> v_j) in the sampled poses: V_i and its farthest
// attached point each land, in the bind pose, on their closest point of the new fan (the faces of
// v_i's fan moved to v_j, whose new corner takes v_j's influences); the cost is the largest
// distance, over the poses, between each posed point and its landing point posed with its face
// (what the level's simplification pair will measure). 0 when every point involved moves with one
// rigid joint (the bind-pose cost is then the posed one) or without posed wedges.
// \pre the collapse passed influenceRule (v_i and v_j each bind one way).
double posedDeviation(const CollapseProfile& p, const PosedWedges& posed);

// The largest posed distance of the latest level's simplification pairs (each removed vertex to
// its pair's point on the level, both posed, at every sample), model units; raises that level's
// maxDeviation and the recorder's levelMax to it. Call right after snapshotLevel (pairs still in
// internal ids, the mesh as snapshotted).
void raisePosedLevelDeviation(const CollapseState& s, const PosedWedges& posed, int threads, HierarchyRecorder& rec);

}  // namespace lodbake::simplify_detail
