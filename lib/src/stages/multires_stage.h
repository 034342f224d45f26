// What the stages that turn any glTF into a multiresolution glTF share (simplify,
// agsphere-build): reading a mesh, writing the levels, and the report entries both give.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "lodbake/core/multires.h"
#include "lodbake/stages/stage.h"

namespace lodbake {

// Reads common.input (images stay encoded).
// \throw Impossible with "INPUT: <noTriangles>" when the scene has no triangles; the errors of readGltf.
Asset loadMeshInput(const StageCommon& common, double& seconds, const std::string& noTriangles);

// The report's "input" object: path, counts and the bounding-box diagonal.
nlohmann::json inputJson(const StageCommon& common, const Asset& asset, double diagonal);

// The entries of level k (1-based) every multires report has: level, triangles, vertices used,
// ratio to the input, max/mean deviation (absolute and relative to `diagonal`), pairs, seconds.
nlohmann::json levelJson(const TriMesh& mesh, const Level& level, size_t k, double diagonal);

// "input: N triangles, M vertices\n"
std::string inputStatistics(const Asset& asset);

}  // namespace lodbake
