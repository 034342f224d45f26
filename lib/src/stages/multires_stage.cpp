// What simplify and agsphere-build share (multires_stage.h): reading a mesh, writing the levels,
// the report entries both give.
#include "stages/multires_stage.h"

#include "lodbake/core/errors.h"
#include "lodbake/core/timing.h"
#include "lodbake/gltf/gltf.h"

namespace lodbake {

Asset loadMeshInput(const StageCommon& common, double& seconds, const std::string& noTriangles) {
    Asset asset = loadStageInput(common, seconds);
    if (asset.mesh.triangleCount() == 0) throw Impossible(common.input + ": " + noTriangles);
    return asset;
}

nlohmann::json inputJson(const StageCommon& common, const Asset& asset, double diagonal) {
    const TriMesh& m = asset.mesh;
    return {{"path", common.input},
            {"triangles", m.triangleCount()},
            {"vertices", m.vertexCount()},
            {"wedges", m.wedges.size()},
            {"materials", asset.materials.size()},
            {"primitives", asset.stats.primitives},
            {"diagonal", diagonal}};
}

nlohmann::json levelJson(const TriMesh& mesh, const Level& level, size_t k, double diagonal) {
    std::vector<uint8_t> seen(mesh.vertexCount(), 0);
    size_t usedVertices = 0;
    for (const Tri& t : level.triangles)
        for (uint32_t v : t)
            if (v < seen.size() && !seen[v]) {
                seen[v] = 1;
                ++usedVertices;
            }
    size_t triangles = level.triangles.size();
    return {{"level", k},
            {"triangles", triangles},
            {"vertices", usedVertices},
            {"ratio", mesh.triangleCount() ? double(triangles) / mesh.triangleCount() : 0.0},
            {"maxDeviation", level.maxDeviation},
            {"meanDeviation", level.meanDeviation},
            {"maxDeviationRelative", diagonal > 0 ? level.maxDeviation / diagonal : 0.0},
            {"meanDeviationRelative", diagonal > 0 ? level.meanDeviation / diagonal : 0.0},
            {"pairs", level.pairs.size()},
            {"seconds", level.seconds}};
}

std::string inputStatistics(const Asset& asset) {
    std::string out;
    appendf(out, "input: %zu triangles, %zu vertices\n", asset.mesh.triangleCount(), asset.mesh.vertexCount());
    return out;
}

}  // namespace lodbake
