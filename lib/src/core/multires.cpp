// levelMesh: the TriMesh of one level of a multiresolution model (no format libraries here).
#include "lodbake/core/multires.h"

#include <string>

#include "lodbake/core/errors.h"

namespace lodbake {

TriMesh levelMesh(const TriMesh& mesh, const Multires& multires, size_t level) {
    if (level == 0) return mesh;
    if (level > multires.levels.size())
        throw InvalidInput("levelMesh: level " + std::to_string(level) + " does not exist (" +
                           std::to_string(multires.levels.size()) + " levels)");
    const Level& L = multires.levels[level - 1];
    TriMesh out;
    out.positions = mesh.positions;
    out.wedges = mesh.wedges;
    out.triangles = L.triangles;
    out.cornerWedges = L.cornerWedges;
    if (!L.triangleMaterial.empty()) {
        out.triangleMaterial = L.triangleMaterial;
        out.triangleMaterial.resize(L.triangles.size(), -1);
        return out;
    }
    out.triangleMaterial.resize(L.triangles.size(), -1);
    for (size_t i = 0; i < L.faces.size() && i < out.triangleMaterial.size(); ++i)
        if (L.faces[i] < mesh.triangleMaterial.size()) out.triangleMaterial[i] = mesh.triangleMaterial[L.faces[i]];
    return out;
}

}  // namespace lodbake
