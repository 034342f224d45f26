// Channel shading (texel_shading.h): the texture lookup at a hit (original UV and footprint,
// KHR_texture_transform, the sampler's wrap), the original's normals and tangent frames, and one
// shading function per channel.
#include "bake/texel_shading.h"

#include <algorithm>
#include <cmath>

#include "bake/island_bake.h"
#include "lodbake/core/tangents.h"
#include "lodbake/texture/color_space.h"
#include "lodbake/texture/texture_transform.h"

namespace lodbake::bake_detail {
namespace {

const Material& materialOf(const ShadeContext& c, uint32_t f) {
    static const Material kDefault;
    const TriMesh& mesh = c.asset.mesh;
    int mi = f < mesh.triangleMaterial.size() ? mesh.triangleMaterial[f] : -1;
    return (mi >= 0 && mi < int(c.asset.materials.size())) ? c.asset.materials[size_t(mi)] : kDefault;
}

// True when two texture references read the same texels at the same UVs (the usual
// occlusion-in-red of a metallic-roughness texture): one lookup serves both.
bool sameLookup(const TextureRef& a, const TextureRef& b) {
    const TextureTransform &s = a.transform, &t = b.transform;
    const int setA = s.texCoord >= 0 ? s.texCoord : a.texCoord, setB = t.texCoord >= 0 ? t.texCoord : b.texCoord;
    return a.texture == b.texture && setA == setB && s.present == t.present && s.offset.x == t.offset.x &&
           s.offset.y == t.offset.y && s.rotation == t.rotation && s.scale.x == t.scale.x && s.scale.y == t.scale.y;
}

// The filtered texel of texture reference `ref` at hit h (bilinear / trilinear over the texel's
// footprint, as a renderer samples it): RGBA as stored (no colour conversion; grey images fill
// RGB, images without alpha give alpha 1). False when the material has no such texture (or no UVs
// of its set): `out` is then untouched.
bool lookup(const ShadeContext& c, const TextureRef& ref, const TexelHit& h, float out[4]) {
    const TriMesh& mesh = c.asset.mesh;
    const uint32_t f = uint32_t(h.face);
    int ti = ref.texture;
    if (ti < 0 || ti >= int(c.asset.textures.size())) return false;
    const Texture& tex = c.asset.textures[size_t(ti)];
    int set = ref.transform.texCoord >= 0 ? ref.transform.texCoord : ref.texCoord;
    const std::vector<Vec2>& uvs = set == 1 ? mesh.wedges.uv1 : mesh.wedges.uv0;
    if (tex.image < 0 || size_t(tex.image) >= c.sources.size() || !c.sources[size_t(tex.image)].used || uvs.empty())
        return false;
    const Tri& cw = mesh.cornerWedges[f];
    Vec2 T[3];
    for (int k = 0; k < 3; ++k) T[k] = uvs[cw[size_t(k)]];
    Vec2 uv = T[0] * h.bary[0] + T[1] * h.bary[1] + T[2] * h.bary[2];
    // Jacobian d(uv)/d(texel) of the affine map atlas texel -> original UV.
    Vec2 dx, dy;
    if (h.island >= 0) {
        islandDerivatives(mesh, c.islands[size_t(h.island)], c.size, f, T, dx, dy);
    } else {
        Vec2 P[3];
        for (int k = 0; k < 3; ++k) P[k] = {c.cornerUV[f][size_t(k)].x * c.size, c.cornerUV[f][size_t(k)].y * c.size};
        Vec2 e1 = P[1] - P[0], e2 = P[2] - P[0], g1 = T[1] - T[0], g2 = T[2] - T[0];
        double det = cross(e1, e2);
        // inverse of [e1 e2] = 1/det [e2.y -e2.x; -e1.y e1.x]
        dx = (g1 * e2.y - g2 * e1.y) * (1 / det);   // d uv / d x
        dy = (g2 * e1.x - g1 * e2.x) * (1 / det);   // d uv / d y
        if (c.extendCharts) uv = uv + dx * double(h.beyond[0]) + dy * double(h.beyond[1]);
    }
    const std::array<double, 4> lm = textureTransformLinear(ref.transform);
    Vec2 st = applyTextureTransform(ref.transform, uv);
    Vec2 tdx = applyLinear(lm, dx);
    Vec2 tdy = applyLinear(lm, dy);
    Sampler smp;
    if (tex.sampler >= 0 && tex.sampler < int(c.asset.samplers.size())) smp = c.asset.samplers[size_t(tex.sampler)];
    FetchOptions opt;
    opt.wrapS = textureWrapFromGl(smp.wrapS);
    opt.wrapT = textureWrapFromGl(smp.wrapT);
    float r[4];
    fetchFiltered(decodedSource(c.asset, c.sources[size_t(tex.image)], size_t(tex.image)), opt, st, tdx, tdy, r);
    for (int i = 0; i < 4; ++i) out[i] = r[i];
    return true;
}

// The original's tangent T and bitangent B at hit h around normal N, for UV set `set` (the file's
// TANGENT, else the frames BakeSources computed). False when there is none.
bool originalTangentFrame(const ShadeContext& c, const TexelHit& h, int set, Vec3 N, TangentFrame& frame) {
    const TriMesh& mesh = c.asset.mesh;
    const Tri& cw = mesh.cornerWedges[uint32_t(h.face)];
    const std::vector<Vec4>& tangents = mesh.wedges.tangent.empty() ? c.tangents[set == 1 ? 1 : 0] : mesh.wedges.tangent;
    if (tangents.empty()) return false;
    return tangentFrameAt(N, {tangents[cw[0]], tangents[cw[1]], tangents[cw[2]]}, {h.bary[0], h.bary[1], h.bary[2]}, frame);
}

// The interpolated normal N at hit h perturbed by normal map `map` of its material in the original
// tangent frame (N itself without the map or a frame).
Vec3 perturbedNormal(const ShadeContext& c, const TexelHit& h, const TextureRef& map, Vec3 N) {
    float r[4];
    if (!lookup(c, map, h, r)) return N;
    const int set = map.transform.texCoord >= 0 ? map.transform.texCoord : map.texCoord;
    TangentFrame frame;
    if (!originalTangentFrame(c, h, set, N, frame)) return N;
    const Vec3 out = normalize(frame.toWorld(tangentNormalOfTexel(r, map.scale)));
    return length(out) > 0.5 ? out : N;
}

// Channel `k` of texture `ref` at h, clamped to [0,1]; 1 without a texture.
double texel(const ShadeContext& c, const TextureRef& ref, const TexelHit& h, int k) {
    float r[4];
    return lookup(c, ref, h, r) ? std::clamp(double(r[k]), 0.0, 1.0) : 1.0;
}

// A colour factor x the linear RGB of an sRGB texture `ref` at h.
void texelColor(const ShadeContext& c, const TextureRef& ref, const TexelHit& h, Vec3 factor, double* rgb) {
    float r[4];
    const bool t = lookup(c, ref, h, r);
    const double f[3] = {factor.x, factor.y, factor.z};
    for (int i = 0; i < 3; ++i) rgb[i] = f[i] * (t ? srgbToLinear(std::clamp(double(r[i]), 0.0, 1.0)) : 1.0);
}

}  // namespace

bool shadeTexel(const ShadeContext& c, const TexelHit& h, double rgb[3], double* alpha) {
    const TriMesh& mesh = c.asset.mesh;
    const uint32_t f = uint32_t(h.face);
    const Material& m = materialOf(c, f);
    rgb[0] = m.baseColorFactor.x;
    rgb[1] = m.baseColorFactor.y;
    rgb[2] = m.baseColorFactor.z;
    double a = m.baseColorFactor.w;
    const Tri& cw = mesh.cornerWedges[f];
    if (!mesh.wedges.color.empty()) {
        double col[4] = {0, 0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            const Vec4& vc = mesh.wedges.color[cw[size_t(k)]];
            col[0] += h.bary[size_t(k)] * vc.x;
            col[1] += h.bary[size_t(k)] * vc.y;
            col[2] += h.bary[size_t(k)] * vc.z;
            col[3] += h.bary[size_t(k)] * vc.w;
        }
        for (int i = 0; i < 3; ++i) rgb[i] *= col[i];
        a *= col[3];
    }
    float r[4];
    const bool textured = lookup(c, m.baseColor, h, r);
    if (textured) {
        for (int i = 0; i < 3; ++i) rgb[i] *= srgbToLinear(std::clamp(double(r[i]), 0.0, 1.0));
        a *= std::clamp(double(r[3]), 0.0, 1.0);
    }
    if (alpha) *alpha = m.alphaMode == AlphaMode::Opaque ? 1.0 : a;
    return textured;
}

void shadeOrm(const ShadeContext& c, const TexelHit& h, double orm[3]) {
    const Material& m = materialOf(c, uint32_t(h.face));
    orm[0] = 1;
    orm[1] = m.roughnessFactor;
    orm[2] = m.metallicFactor;
    float r[4];
    const bool mr = lookup(c, m.metallicRoughness, h, r);
    if (mr) {
        orm[1] *= std::clamp(double(r[1]), 0.0, 1.0);
        orm[2] *= std::clamp(double(r[2]), 0.0, 1.0);
    }
    float sg[4];
    if (lookup(c, m.specularGlossiness, h, sg)) orm[1] = 1 - m.glossinessFactor * std::clamp(double(sg[3]), 0.0, 1.0);
    if ((mr && sameLookup(m.occlusion, m.metallicRoughness)) || lookup(c, m.occlusion, h, r))
        orm[0] = 1 + m.occlusion.scale * (std::clamp(double(r[0]), 0.0, 1.0) - 1);
    for (int i = 0; i < 3; ++i) orm[i] = std::clamp(orm[i], 0.0, 1.0);
}

void shadeEmissive(const ShadeContext& c, const TexelHit& h, double e[3]) {
    const Material& m = materialOf(c, uint32_t(h.face));
    const Vec3 f = m.emissiveFactor * m.emissiveStrength;
    e[0] = f.x;
    e[1] = f.y;
    e[2] = f.z;
    float r[4];
    if ((e[0] > 0 || e[1] > 0 || e[2] > 0) && lookup(c, m.emissive, h, r))
        for (int i = 0; i < 3; ++i) e[i] *= srgbToLinear(std::clamp(double(r[i]), 0.0, 1.0));
}

Vec3 interpolatedNormal(const ShadeContext& c, const TexelHit& h) {
    const TriMesh& mesh = c.asset.mesh;
    const uint32_t f = uint32_t(h.face);
    const Tri& t = mesh.triangles[f];
    const Tri& cw = mesh.cornerWedges[f];
    const Vec3 face = normalize(cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]));
    Vec3 N = face;
    if (!mesh.wedges.normal.empty()) {
        Vec3 n{};
        for (int k = 0; k < 3; ++k) n += mesh.wedges.normal[cw[size_t(k)]] * h.bary[size_t(k)];
        if (length(n) > 1e-12) N = normalize(n);
    }
    return N;
}

Vec3 shadingNormal(const ShadeContext& c, const TexelHit& h, Vec3 N) {
    return perturbedNormal(c, h, materialOf(c, uint32_t(h.face)).normal, N);
}

Vec3 clearcoatNormal(const ShadeContext& c, const TexelHit& h, Vec3 N) {
    return perturbedNormal(c, h, materialOf(c, uint32_t(h.face)).ext.clearcoat.normalTexture, N);
}

double anisotropyAt(const ShadeContext& c, const TexelHit& h, Vec3 N, Vec3& direction) {
    const AnisotropyExtension& e = materialOf(c, uint32_t(h.face)).ext.anisotropy;
    direction = {};
    if (!e.present) return 0;
    double strength = e.strength, dx = 1, dy = 0;
    float r[4];
    if (lookup(c, e.texture, h, r)) {
        dx = 2.0 * r[0] - 1;
        dy = 2.0 * r[1] - 1;
        strength *= std::clamp(double(r[2]), 0.0, 1.0);
    }
    const double cr = std::cos(e.rotation), sr = std::sin(e.rotation);
    const double x = cr * dx - sr * dy, y = sr * dx + cr * dy;
    const int set = e.texture.transform.texCoord >= 0 ? e.texture.transform.texCoord : e.texture.texCoord;
    TangentFrame frame;
    if (!originalTangentFrame(c, h, set, N, frame)) return 0;
    direction = frame.toWorld({x, y, 0});
    return std::clamp(strength, 0.0, 1.0);
}

void shadeClearcoat(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const ClearcoatExtension& e = materialOf(c, uint32_t(h.face)).ext.clearcoat;
    v[0] = e.factor * texel(c, e.texture, h, 0);
    v[1] = e.present ? e.roughnessFactor * texel(c, e.roughnessTexture, h, 1) : ch.clearcoatRoughnessFill;
    v[2] = 0;
}

void shadeSheen(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const SheenExtension& e = materialOf(c, uint32_t(h.face)).ext.sheen;
    texelColor(c, e.colorTexture, h, e.colorFactor, v);
    v[3] = e.present ? e.roughnessFactor * texel(c, e.roughnessTexture, h, 3) : ch.sheenRoughnessFill;
}

void shadeSpecular(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const SpecularExtension& e = materialOf(c, uint32_t(h.face)).ext.specular;
    texelColor(c, e.colorTexture, h, e.colorFactor * (1 / ch.specularColorScale), v);
    v[3] = e.factor * texel(c, e.texture, h, 3);
}

void shadeTransmission(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const MaterialExtensions& e = materialOf(c, uint32_t(h.face)).ext;
    v[0] = e.transmission.factor * texel(c, e.transmission.texture, h, 0);
    v[1] = e.volume.thicknessFactor * texel(c, e.volume.thicknessTexture, h, 1) / ch.thicknessScale;
    v[2] = 0;
}

void shadeIridescence(const ShadeContext& c, const BakeChannels& ch, const TexelHit& h, double* v) {
    const IridescenceExtension& e = materialOf(c, uint32_t(h.face)).ext.iridescence;
    v[0] = e.factor * texel(c, e.texture, h, 0);
    float r[4];
    // The thickness in nm (glTF: the maximum without a thickness texture), then its place in the
    // chain's range. A part without iridescence takes the range's minimum.
    const double nm = !e.present ? ch.iridescenceThicknessMin
                      : lookup(c, e.thicknessTexture, h, r)
                          ? e.thicknessMinimum + (e.thicknessMaximum - e.thicknessMinimum) * std::clamp(double(r[1]), 0.0, 1.0)
                          : e.thicknessMaximum;
    const double span = ch.iridescenceThicknessMax - ch.iridescenceThicknessMin;
    v[1] = span > 0 ? (nm - ch.iridescenceThicknessMin) / span : 0;
    v[2] = 0;
}

void shadeDiffuseTransmission(const ShadeContext& c, const BakeChannels&, const TexelHit& h, double* v) {
    const DiffuseTransmissionExtension& e = materialOf(c, uint32_t(h.face)).ext.diffuseTransmission;
    texelColor(c, e.colorTexture, h, e.colorFactor, v);
    v[3] = e.factor * texel(c, e.texture, h, 3);
}

}  // namespace lodbake::bake_detail
