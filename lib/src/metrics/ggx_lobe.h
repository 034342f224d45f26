// The GGX specular lobe the renderer's Pbr mode uses for the base and the clearcoat: Trowbridge-
// Reitz distribution with a = roughness^2 and Smith-Schlick geometry with k = (roughness + 1)^2 / 8
// (the glTF sample viewer's and three.js's direct-light terms). Fresnel is the caller's: the
// base's F0 is per channel, the coat's fixed.
#pragma once

#include <algorithm>

#include "lodbake/core/math.h"

namespace lodbake::metrics_detail {

struct GgxLobe {
    double a2 = 0, k = 0;  // a^2 = roughness^4; the geometry term's k
    double nv = 0, gv = 0;  // n.v (at least 1e-4) and its geometry factor

    // `roughness`: perceptual, already clamped by the caller; N, V unit, V towards the eye.
    GgxLobe(double roughness, const Vec3& N, const Vec3& V)
        : a2(roughness * roughness * roughness * roughness), k((roughness + 1) * (roughness + 1) / 8),
          nv(std::max(dot(N, V), 1e-4)), gv(nv / (nv * (1 - k) + k)) {}

    // D x G for unit light direction L with n.l = nl > 0; `vh` receives v.h (the Fresnel's cosine).
    double dg(const Vec3& N, const Vec3& L, const Vec3& V, double nl, double& vh) const {
        const Vec3 H = normalize(L + V);
        const double nh = std::max(dot(N, H), 0.0);
        vh = std::max(dot(V, H), 0.0);
        const double d = nh * nh * (a2 - 1) + 1;
        return a2 / (kPi * d * d) * (gv * nl / (nl * (1 - k) + k));
    }
};

}  // namespace lodbake::metrics_detail
