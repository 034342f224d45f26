// The clearcoat layer of the Pbr mode (clearcoat_layer.h).
#include "metrics/clearcoat_layer.h"

#include <algorithm>

namespace lodbake::metrics_detail {
namespace {

constexpr double kCoatF0 = 0.04;  // the coat's reflectance at normal incidence (IOR 1.5)

double schlick(double cosine) {
    const double m = 1 - cosine;
    return kCoatF0 + (1 - kCoatF0) * m * m * m * m * m;
}

}  // namespace

void addClearcoat(const ClearcoatLayer& layer, const Vec3& view, const Vec3* toLight, const double* irradiance,
                  size_t count, double ambientSpecular, double occlusion, double rgb[3]) {
    if (!(layer.coat > 0)) return;
    const Vec3& N = layer.normal;
    const double r = layer.roughness;
    const double a2 = r * r * r * r;  // a = roughness^2
    const double k = (r + 1) * (r + 1) / 8;
    const double nv = std::max(dot(N, view), 1e-4);
    const double gv = nv / (nv * (1 - k) + k);
    const double fc = schlick(nv);
    double specular = fc * ambientSpecular * occlusion;
    for (size_t i = 0; i < count; ++i) {
        const Vec3& L = toLight[i];
        const double nl = dot(N, L);
        if (!(nl > 0)) continue;
        const Vec3 H = normalize(L + view);
        const double nh = std::max(dot(N, H), 0.0), vh = std::max(dot(view, H), 0.0);
        const double d = nh * nh * (a2 - 1) + 1;
        const double D = a2 / (kPi * d * d);
        const double G = gv * nl / (nl * (1 - k) + k);
        specular += D * G * schlick(vh) / (4 * nl * nv) * irradiance[i] * nl;
    }
    for (int c = 0; c < 3; ++c) rgb[c] = rgb[c] * (1 - layer.coat * fc) + layer.coat * specular;
}

}  // namespace lodbake::metrics_detail
