// KHR_texture_transform as an affine map of texture coordinates:
//     uv' = L uv + offset,  L = R(rotation) S(scale),  R = [cos sin; -sin cos]
// (rows; the rotation of the extension's example: offset (0,1), rotation pi/2, scale 0.5 maps the
// unit square onto the lower-left quadrant, v down).
#pragma once

#include <array>
#include <cmath>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake {

// L as a column-major 2x2 {L00, L10, L01, L11}; the identity when the transform is absent.
inline std::array<double, 4> textureTransformLinear(const TextureTransform& t) {
    if (!t.present) return {1, 0, 0, 1};
    const double c = std::cos(t.rotation), s = std::sin(t.rotation);
    return {c * t.scale.x, -s * t.scale.x, s * t.scale.y, c * t.scale.y};
}

// L d: a UV difference or derivative under the transform's linear part.
inline Vec2 applyLinear(const std::array<double, 4>& m, Vec2 d) { return {m[0] * d.x + m[2] * d.y, m[1] * d.x + m[3] * d.y}; }

// uv' = L uv + offset; uv itself when the transform is absent.
inline Vec2 applyTextureTransform(const TextureTransform& t, Vec2 uv) {
    if (!t.present) return uv;
    return applyLinear(textureTransformLinear(t), uv) + t.offset;
}

// The TEXCOORD_n set a texture reference samples: the transform's texCoord override when given.
inline int textureCoordSet(const TextureRef& r) {
    return r.transform.present && r.transform.texCoord >= 0 ? r.transform.texCoord : r.texCoord;
}

// Per wedge of `mesh`, its UV set `set` as its material's normal map reads it: through the normal
// texture's transform (else the clearcoat normal's, else the anisotropy texture's). Without
// TANGENT in the file, viewers derive the tangent frames from these coordinates (three.js: screen
// derivatives of the transformed UVs), so a transform that rotates or mirrors the map turns its
// frames too. Wedges of materials without such a map keep their UVs.
inline std::vector<Vec2> normalMapUVs(const TriMesh& mesh, const std::vector<Material>& materials, int set) {
    std::vector<Vec2> uv = set == 1 ? mesh.wedges.uv1 : mesh.wedges.uv0;
    std::vector<char> done(uv.size(), 0);
    for (size_t f = 0; f < mesh.triangleCount() && f < mesh.triangleMaterial.size(); ++f) {
        const int32_t m = mesh.triangleMaterial[f];
        if (m < 0 || size_t(m) >= materials.size()) continue;
        const Material& mat = materials[size_t(m)];
        const TextureRef* map = nullptr;
        for (const TextureRef* r : {&mat.normal, &mat.ext.clearcoat.normalTexture, &mat.ext.anisotropy.texture})
            if (!map && r->texture >= 0 && textureCoordSet(*r) == set) map = r;
        if (!map || !map->transform.present) continue;
        for (uint32_t w : mesh.cornerWedges[f])
            if (w < uv.size() && !done[w]) {
                uv[w] = applyTextureTransform(map->transform, uv[w]);
                done[w] = 1;
            }
    }
    return uv;
}

}  // namespace lodbake
