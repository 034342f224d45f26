// Chart extraction (parameterize step 2): each chart of the layout as a local mesh (LocalChart)
// with the simplification pairs and the level triangles it carries, the input of its solve.
#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "lodbake/core/face_grid.h"
#include "lodbake/core/mesh.h"
#include "lodbake/core/multires.h"
#include "lodbake/param/parameterize.h"

namespace lodbake::param_detail {

struct LocalChart {
    std::vector<uint32_t> faces;            // original faces (non-degenerate)
    std::vector<uint32_t> vertices;         // local -> global, sorted
    std::unordered_map<uint32_t, uint32_t> local;  // global -> local
    ChartMesh mesh;
    std::vector<ChartPair> pairs;
    std::vector<Vec2> uv;                   // final map, model units
};

// The mesh's surface area: its triangles' areas summed in order (model units^2).
double surfaceArea(const TriMesh& mesh);

// The square root of the mean face area: a face's usual size.
double typicalFaceSize(const TriMesh& mesh);

// (2) The charts as local meshes with their simplification pairs and level triangles.
std::vector<LocalChart> localCharts(const TriMesh& mesh, const Multires& multires, const ChartResult& cr, const FaceGrid& grid,
                                    double radius);

}  // namespace lodbake::param_detail
