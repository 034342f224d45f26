// The bake target: the surface that will wear the baked page (BakeTarget, lodbake/bake/bake.h).
// Normal, clearcoat normal and anisotropy texels are stored in the tangent frames of the level
// triangle each texel lies in, not the original's; this file finds that triangle per texel and
// expresses world directions in its frame.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "bake/texel_raster.h"
#include "lodbake/bake/bake.h"

namespace lodbake::bake_detail {

// A texel's place on the target surface: the target triangle and barycentrics (-1 = none).
struct TargetHit {
    int32_t tri = -1;
    float dist = 1e30f;
    std::array<float, 3> bary{};
};

// Per texel of the region, the target triangle it lies in or the nearest within
// target.reach texels (the earlier triangle on ties). Rows in bands on `threads` threads (the
// same hits for any count).
std::vector<TargetHit> rasterizeTarget(const BakeTarget& target, const TexelRegion& g, int threads);

// World normal N expressed in the target's tangent frame at hit th, as an encoded colour; the
// unperturbed (0, 0, 1) without a target or a hit.
void encodeInTarget(const BakeTarget* targetOrNull, const TargetHit& th, Vec3 N, double rgb[3]);

// An anisotropy texel for the target: RG = world direction D in the target's tangent plane at
// th (unit, encoded x 0.5 + 0.5; the tangent without a target, a hit or a direction), B = strength.
void encodeAnisotropyInTarget(const BakeTarget* targetOrNull, const TargetHit& th, Vec3 D, double strength, double rgb[3]);

}  // namespace lodbake::bake_detail
