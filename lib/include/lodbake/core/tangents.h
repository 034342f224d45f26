// Tangent frames for normal mapping, as glTF defines them: TANGENT.xyz points along increasing u,
// the bitangent is cross(NORMAL, TANGENT.xyz) * TANGENT.w and points along decreasing v (glTF's
// v runs down the image, normal maps store +Y "up"), the convention MikkTSpace gives with glTF's
// flipped v. The bake that writes a level's normal map and the file that carries the level use
// the same tangents, so the map decodes exactly as it was encoded.
#pragma once

#include <array>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

// Per-vertex tangents of an indexed triangle mesh.
// Each triangle's tangent and bitangent (dP/du, -dP/dv) are accumulated at its corners weighted by
// the corner angle (as MikkTSpace does), then made orthogonal to the vertex normal; w = +1 when
// (N, T, B) is right-handed, -1 when the UVs are mirrored. A vertex with no usable UV gradient
// (degenerate UV triangles only) gets a unit vector orthogonal to its normal and w = +1.
// \pre normals.size() == uvs.size() == positions.size(); every index < positions.size();
//      normals are unit length (a zero normal yields an arbitrary unit tangent).
std::vector<Vec4> computeTangents(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                                  const std::vector<Vec2>& uvs, const std::vector<Tri>& triangles);

// The same for the wedges of `mesh` (a wedge is a glTF vertex) with texture coordinates `uv`
// (one per wedge; the UV set as the normal map reads it: texture/texture_transform.h
// normalMapUVs): the frames the original's normal maps are shown in when the file has no TANGENT.
// Normals come from the wedges, or from the welded faces when the file has none.
std::vector<Vec4> computeWedgeTangents(const TriMesh& mesh, const std::vector<Vec2>& uv);

// The tangent frame at a point of a triangle, the one convention the bake (decoding the
// original's maps, encoding a level's), compare's renderer and the level files share: N is the
// unit shading normal; T the corners' tangents interpolated by `bary`, made orthogonal to N; B =
// cross(N, T) times the sign of the interpolated handedness w, as a renderer interpolating the
// TANGENT attribute sees it. False (frame untouched) when T vanishes.
struct TangentFrame {
    Vec3 T, B, N;
    // A tangent-space vector (x along T, y along B, z along N) in world space, and back.
    Vec3 toWorld(Vec3 t) const { return T * t.x + B * t.y + N * t.z; }
    Vec3 toTangent(Vec3 v) const { return {dot(v, T), dot(v, B), dot(v, N)}; }
};
bool tangentFrameAt(Vec3 N, const std::array<Vec4, 3>& corners, const std::array<double, 3>& bary, TangentFrame& frame);

// A normal map texel (its first three channels in [0, 1]) as the tangent-space vector it holds:
// x and y scaled by the map's scale (glTF normalTexture.scale), not normalised.
inline Vec3 tangentNormalOfTexel(const float* rgb, double scale) {
    return {(2.0 * rgb[0] - 1) * scale, (2.0 * rgb[1] - 1) * scale, 2.0 * rgb[2] - 1};
}

}  // namespace lodbake
