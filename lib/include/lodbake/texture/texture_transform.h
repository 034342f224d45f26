// KHR_texture_transform as an affine map of texture coordinates:
//     uv' = L uv + offset,  L = R(rotation) S(scale),  R = [cos sin; -sin cos]
// (rows; the rotation of the extension's example: offset (0,1), rotation pi/2, scale 0.5 maps the
// unit square onto the lower-left quadrant, v down).
#pragma once

#include <array>
#include <cmath>

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

}  // namespace lodbake
