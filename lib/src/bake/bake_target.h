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
#include "lodbake/core/tangents.h"

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

// The target's tangent frame at hit th (lodbake/core/tangents.h: the level triangle's
// interpolated normal and tangent); false without a target, a hit or a usable frame. A texel's
// frame serves each of its direction channels.
bool targetFrame(const BakeTarget* targetOrNull, const TargetHit& th, TangentFrame& frame);

// World normal N expressed in tangent frame `frameOrNull` (targetFrame's), as an encoded colour;
// the unperturbed (0, 0, 1) without a frame.
void encodeInFrame(const TangentFrame* frameOrNull, Vec3 N, double rgb[3]);

// An anisotropy texel: RG = world direction D in the tangent plane of `frameOrNull` (unit,
// encoded x 0.5 + 0.5; the tangent without a frame or a direction), B = strength.
void encodeAnisotropyInFrame(const TangentFrame* frameOrNull, Vec3 D, double strength, double rgb[3]);

}  // namespace lodbake::bake_detail
