// The clearcoat layer of the renderer's Pbr mode (KHR_materials_clearcoat): a dielectric coat
// (F0 0.04) over the lit base, composed as three.js's MeshPhysicalMaterial composes it, base x
// (1 - coat x Fc) + coat x (coat specular), with Fc the Schlick Fresnel of the coat normal and the
// view. At grazing angles the coat reflects most of the light and the base shows little.
#pragma once

#include <cstddef>

#include "lodbake/core/math.h"

namespace lodbake::metrics_detail {

struct ClearcoatLayer {
    double coat = 0;       // clearcoatFactor x clearcoat texture R, in [0, 1]
    double roughness = 1;  // perceptual: clearcoatRoughnessFactor x texture G, clamped by the caller
    Vec3 normal;           // unit coat normal on the viewer's side
};

// The coat over `rgb` (linear light leaving the base, emission included), in place: GGX specular
// (Smith-Schlick geometry, Schlick Fresnel, as the base's specular lobe) under `count` directional
// lights (unit directions towards each, irradiance on a surface facing it), plus the ambient the
// coat reflects, Fc x ambientSpecular x occlusion. `view`: unit direction towards the eye.
void addClearcoat(const ClearcoatLayer& layer, const Vec3& view, const Vec3* toLight, const double* irradiance,
                  size_t count, double ambientSpecular, double occlusion, double rgb[3]);

}  // namespace lodbake::metrics_detail
