// The clearcoat layer of the Pbr mode (clearcoat_layer.h).
#include "metrics/clearcoat_layer.h"

#include "metrics/ggx_lobe.h"

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
    const GgxLobe lobe(layer.roughness, N, view);
    const double fc = schlick(lobe.nv);
    double specular = fc * ambientSpecular * occlusion;
    for (size_t i = 0; i < count; ++i) {
        const Vec3& L = toLight[i];
        const double nl = dot(N, L);
        if (!(nl > 0)) continue;
        double vh = 0;
        const double dg = lobe.dg(N, L, view, nl, vh);
        specular += dg * schlick(vh) / (4 * nl * lobe.nv) * irradiance[i] * nl;
    }
    for (int c = 0; c < 3; ++c) rgb[c] = rgb[c] * (1 - layer.coat * fc) + layer.coat * specular;
}

}  // namespace lodbake::metrics_detail
