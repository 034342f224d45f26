// Channel shading: what the original material shows at a texel's hit (texel_raster.h). Each
// channel is factor x filtered texture fetch (at the original UV, with the footprint of the
// texel -> original UV Jacobian) x vertex colour where glTF multiplies one in; colours in linear
// space, normals and directions in world space (bake_target.h expresses them in the page's
// frames). The bake (bake.cpp) encodes, fills and quantises the values afterwards.
#pragma once

#include <array>
#include <vector>

#include "bake/bake_sources.h"
#include "bake/texel_raster.h"
#include "lodbake/bake/bake.h"

namespace lodbake::bake_detail {

// What shading a texel reads: the asset, its decoded sources, the original's tangent frames
// (per UV set, for its normal maps) and the bake's UVs and islands.
struct ShadeContext {
    const Asset& asset;
    const std::vector<std::array<Vec2, 3>>& cornerUV;
    const std::vector<BakeIsland>& islands;
    std::vector<SourceTexture>& sources;
    const std::array<std::vector<Vec4>, 2>& tangents;
    int size;
    bool extendCharts;  // BakeOptions::extendCharts
};

// The linear RGB of one covered texel: base colour factor x COLOR_0 x the filtered texture
// lookup at the original UV (derivatives from the texel -> original UV Jacobian). Returns
// whether a texture was sampled; `alpha` gets the same product's alpha.
bool shadeTexel(const ShadeContext& c, const TexelHit& h, double rgb[3], double* alpha = nullptr);
// Occlusion, roughness and metallic of the original material at hit h (linear, [0,1]).
void shadeOrm(const ShadeContext& c, const TexelHit& h, double orm[3]);
// Linear emissive radiance of the original material at hit h (may exceed 1 with emissive strength).
void shadeEmissive(const ShadeContext& c, const TexelHit& h, double e[3]);

// The original's interpolated normal at hit h, world space (the face's normal when the file has
// none): the N the three functions below take, found once for a texel.
Vec3 interpolatedNormal(const ShadeContext& c, const TexelHit& h);
// The original's shading normal at hit h, world space (its material's normal map; N =
// interpolatedNormal(c, h)).
Vec3 shadingNormal(const ShadeContext& c, const TexelHit& h, Vec3 N);
// The original's clearcoat normal at hit h (the coat's own normal map; without one the
// interpolated normal N, as glTF defines it).
Vec3 clearcoatNormal(const ShadeContext& c, const TexelHit& h, Vec3 N);
// The original's anisotropy at hit h (interpolated normal N): its strength (0 where the material
// has none) and its direction in world space (the tangent rotated by anisotropyRotation, then by
// the texture's RG direction, in the original tangent frame of the texture's UV set).
double anisotropyAt(const ShadeContext& c, const TexelHit& h, Vec3 N, Vec3& direction);

// Extension channels: each fills v (3 or 4 values, BakeChannels' packing) with the original
// material at hit h; colours linear here (bakeMaterial encodes them as sRGB after the fill).
// An extension the material lacks reads as its neutral value (the struct's defaults).
void shadeClearcoat(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v);
void shadeSheen(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v);
void shadeSpecular(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v);
void shadeTransmission(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v);
void shadeIridescence(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v);
void shadeDiffuseTransmission(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v);

}  // namespace lodbake::bake_detail
