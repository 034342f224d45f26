// Private to lib/src/agsphere: a built level as the Multires Level that every tool reads.
#pragma once

#include "agsphere/retriangulate.h"
#include "agsphere/topology.h"
#include "lodbake/core/multires.h"

namespace lodbake::agsphere_detail {

// Triangles region by region with their original faces and corner wedges, faceRegion, and the
// simplification pairs of every removed vertex (interior: closest point on its region's new
// triangles; removed run vertex: closest point on its simplified run edge), sorted by vertex.
// Targets, stop reason and seconds are left to the caller.
Level assembleLevel(const Topology& t, const LevelBuild& build);

}  // namespace lodbake::agsphere_detail
