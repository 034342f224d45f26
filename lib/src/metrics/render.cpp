// The software rasteriser of render.h, laid out as a pipeline:
//   sphereViews; per triangle: cullBackFace, cornerAttributes, toScreen (toCamera, clipNear,
//   projection); per sub-triangle: rasterizeTriangle (setupInterpolants, pixel scan with z-test,
//   shadeBaseColor, Lambert grey or shadePbr, its clearcoat layer in clearcoat_layer.h); encodeSrgb.
// Perspective-correct interpolation: 1/z and b_k/z (b = barycentrics of the original triangle)
// are affine in screen space; their screen gradients give exact UV derivatives for the mip level
// (trilinear filtering, as in the OpenGL spec's scale factor rho).
#include "lodbake/metrics/render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "lodbake/core/math.h"
#include "lodbake/core/tangents.h"
#include "lodbake/texture/color_space.h"
#include "lodbake/texture/texture_transform.h"
#include "metrics/clearcoat_layer.h"
#include "metrics/ggx_lobe.h"

namespace lodbake {
namespace {

constexpr int kRepeat = 10497, kClamp = 33071, kMirror = 33648;

struct Frame {
    Vec3 right, up, forward;  // orthonormal camera basis; camera looks along +forward
    Vec3 eye;
    double focal = 1;         // 1 / tan(fovY / 2)
    int width = 0, height = 0;
};

Frame makeFrame(const Camera& c, int width, int height) {
    Frame f;
    f.eye = c.eye;
    f.forward = normalize(c.target - c.eye);
    f.right = normalize(cross(f.forward, c.up));
    if (length2(f.right) == 0) f.right = normalize(cross(f.forward, Vec3{1, 0, 0}));
    if (length2(f.right) == 0) f.right = normalize(cross(f.forward, Vec3{0, 0, 1}));
    f.up = cross(f.right, f.forward);
    f.focal = 1.0 / std::tan(c.fovY / 2);
    f.width = width;
    f.height = height;
    return f;
}

// A vertex in camera space carrying barycentrics of the original triangle.
struct ClipVertex {
    Vec3 cam;  // x right, y up, z depth (> 0 in front)
    Vec3 bary;
};

// Sutherland-Hodgman against z >= zNear; returns up to 4 vertices.
int clipNear(const ClipVertex in[3], double zNear, ClipVertex out[4]) {
    int n = 0;
    for (int i = 0; i < 3; ++i) {
        const ClipVertex& a = in[i];
        const ClipVertex& b = in[(i + 1) % 3];
        bool ina = a.cam.z >= zNear, inb = b.cam.z >= zNear;
        if (ina) out[n++] = a;
        if (ina != inb) {
            double t = (zNear - a.cam.z) / (b.cam.z - a.cam.z);
            out[n++] = {a.cam + (b.cam - a.cam) * t, a.bary + (b.bary - a.bary) * t};
        }
    }
    return n;
}

float wrapCoord(double t, int wrap) {
    if (wrap == kClamp) return static_cast<float>(std::fmin(std::fmax(t, 0.0), 1.0));
    if (wrap == kMirror) {
        double p = std::fmod(t, 2.0);
        if (p < 0) p += 2;
        return static_cast<float>(p > 1 ? 2 - p : p);
    }
    double p = t - std::floor(t);
    return static_cast<float>(p);
}

int wrapIndex(int i, int n, int wrap) {
    if (wrap == kRepeat) {
        i %= n;
        return i < 0 ? i + n : i;
    }
    if (wrap == kMirror) {
        int period = 2 * n;
        i %= period;
        if (i < 0) i += period;
        return i < n ? i : period - 1 - i;
    }
    return std::min(std::max(i, 0), n - 1);
}

void bilinear(const MipImage::Level& l, double u, double v, int wrapS, int wrapT, float out[4]) {
    double x = u * l.width - 0.5, y = v * l.height - 0.5;
    double fx = std::floor(x), fy = std::floor(y);
    int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
    float ax = static_cast<float>(x - fx), ay = static_cast<float>(y - fy);
    int xs[2] = {wrapIndex(x0, l.width, wrapS), wrapIndex(x0 + 1, l.width, wrapS)};
    int ys[2] = {wrapIndex(y0, l.height, wrapT), wrapIndex(y0 + 1, l.height, wrapT)};
    const float* p00 = &l.rgba[(static_cast<size_t>(ys[0]) * l.width + xs[0]) * 4];
    const float* p10 = &l.rgba[(static_cast<size_t>(ys[0]) * l.width + xs[1]) * 4];
    const float* p01 = &l.rgba[(static_cast<size_t>(ys[1]) * l.width + xs[0]) * 4];
    const float* p11 = &l.rgba[(static_cast<size_t>(ys[1]) * l.width + xs[1]) * 4];
    for (int c = 0; c < 4; ++c)
        out[c] = (1 - ay) * ((1 - ax) * p00[c] + ax * p10[c]) + ay * ((1 - ax) * p01[c] + ax * p11[c]);
}

// Trilinear sample; duv* are the UV derivatives along screen x and y.
void sampleTexture(const MipImage& mip, Vec2 uv, Vec2 duvdx, Vec2 duvdy, int wrapS, int wrapT, float out[4]) {
    const MipImage::Level& l0 = mip.levels[0];
    double rx = std::hypot(duvdx.x * l0.width, duvdx.y * l0.height);
    double ry = std::hypot(duvdy.x * l0.width, duvdy.y * l0.height);
    double rho = std::max(rx, ry);
    double lambda = rho > 1 ? std::log2(rho) : 0.0;
    double maxLevel = static_cast<double>(mip.levels.size() - 1);
    lambda = std::min(lambda, maxLevel);
    // Wrap the coordinate once (bilinear also wraps its neighbour indices).
    double u = wrapCoord(uv.x, wrapS), v = wrapCoord(uv.y, wrapT);
    int l = static_cast<int>(std::floor(lambda));
    float t = static_cast<float>(lambda - l);
    bilinear(mip.levels[l], u, v, wrapS, wrapT, out);
    if (t > 0 && l + 1 < static_cast<int>(mip.levels.size())) {
        float hi[4];
        bilinear(mip.levels[l + 1], u, v, wrapS, wrapT, hi);
        for (int c = 0; c < 4; ++c) out[c] = (1 - t) * out[c] + t * hi[c];
    }
}

// The texture channels of a metallic-roughness material and its clearcoat.
enum Channel { kBaseColor, kMetallicRoughness, kOcclusion, kNormal, kEmissive, kCoat, kCoatRoughness, kCoatNormal, kChannels };

// One texture reference of a material, resolved: its decoded pyramid (null: none or undecodable),
// UV set, transform and wrap modes.
struct TexSlot {
    const MipImage* image = nullptr;
    int texCoord = 0;
    const TextureTransform* transform = nullptr;
    int wrapS = kRepeat, wrapT = kRepeat;
};

TexSlot resolveTexture(const Asset& asset, const std::vector<MipImage>& images, const TextureRef& ref) {
    TexSlot r;
    int t = ref.texture;
    if (t >= 0 && static_cast<size_t>(t) < asset.textures.size()) {
        int i = asset.textures[t].image;
        if (i >= 0 && static_cast<size_t>(i) < images.size() && !images[i].levels.empty()) r.image = &images[i];
        int s = asset.textures[t].sampler;
        if (s >= 0 && static_cast<size_t>(s) < asset.samplers.size()) {
            r.wrapS = asset.samplers[s].wrapS;
            r.wrapT = asset.samplers[s].wrapT;
        }
    }
    r.texCoord = textureCoordSet(ref);
    r.transform = &ref.transform;
    return r;
}

// Per-triangle material data resolved once; defaults are the glTF default material's.
struct TriMaterial {
    Vec4 factor{1, 1, 1, 1};
    TexSlot tex[kChannels];
    bool doubleSided = false;
    bool mask = false;
    double cutoff = 0.5;
    bool unlit = false;
    double metallic = 1, roughness = 1;
    double occlusionStrength = 1, normalScale = 1;
    Vec3 emissive{0, 0, 0};  // emissiveFactor x emissiveStrength, linear
    double coat = 0, coatRoughness = 0, coatNormalScale = 1;  // KHR_materials_clearcoat (coat 0: none)
};

TriMaterial resolveMaterial(const RenderScene& scene, int32_t m) {
    TriMaterial r;
    const Asset& asset = *scene.asset;
    if (m < 0 || static_cast<size_t>(m) >= asset.materials.size()) return r;
    const Material& mat = asset.materials[m];
    r.factor = mat.baseColorFactor;
    r.doubleSided = mat.doubleSided;
    r.mask = mat.alphaMode == AlphaMode::Mask;
    r.cutoff = mat.alphaCutoff;
    r.unlit = mat.unlit;
    r.metallic = mat.metallicFactor;
    r.roughness = mat.roughnessFactor;
    r.occlusionStrength = mat.occlusion.scale;
    r.normalScale = mat.normal.scale;
    r.emissive = mat.emissiveFactor * mat.emissiveStrength;
    r.tex[kBaseColor] = resolveTexture(asset, scene.images, mat.baseColor);
    r.tex[kEmissive] = resolveTexture(asset, scene.images, mat.emissive);
    r.tex[kMetallicRoughness] = resolveTexture(asset, scene.dataImages, mat.metallicRoughness);
    r.tex[kOcclusion] = resolveTexture(asset, scene.dataImages, mat.occlusion);
    r.tex[kNormal] = resolveTexture(asset, scene.dataImages, mat.normal);
    const ClearcoatExtension& cc = mat.ext.clearcoat;
    if (cc.present && cc.factor > 0) {
        r.coat = cc.factor;
        r.coatRoughness = cc.roughnessFactor;
        r.coatNormalScale = cc.normalTexture.scale;
        r.tex[kCoat] = resolveTexture(asset, scene.dataImages, cc.texture);
        r.tex[kCoatRoughness] = resolveTexture(asset, scene.dataImages, cc.roughnessTexture);
        r.tex[kCoatNormal] = resolveTexture(asset, scene.dataImages, cc.normalTexture);
    }
    return r;
}

}  // namespace

std::vector<Camera> sphereViews(int count, Vec3 center, double radius, double fovY) {
    std::vector<Camera> views;
    if (count <= 0) return views;
    if (!(radius > 0)) radius = 1;
    const double golden = kPi * (3 - std::sqrt(5.0));
    double distance = radius / std::sin(fovY / 2);
    for (int i = 0; i < count; ++i) {
        double y = count == 1 ? 0.0 : 1 - 2 * (i + 0.5) / count;
        double r = std::sqrt(std::max(0.0, 1 - y * y));
        double phi = golden * i;
        Vec3 dir{r * std::cos(phi), y, r * std::sin(phi)};
        Camera c;
        c.eye = center + dir * distance;
        c.target = center;
        c.up = std::fabs(y) > 0.99 ? Vec3{0, 0, 1} : Vec3{0, 1, 0};
        c.fovY = fovY;
        c.zNear = std::max(distance - radius * 4, distance * 1e-3);
        c.zFar = distance + radius * 4;
        views.push_back(c);
    }
    return views;
}

namespace {

// The render target while triangles are drawn: linear colour and depth per pixel.
struct Target {
    int width = 0, height = 0;
    std::vector<float> linear;  // RGB, linear
    std::vector<double> depth;  // camera z of the nearest fragment; +inf where nothing is drawn
};

// What a triangle carries to its pixels: per texture channel its corner UVs (after the texture
// transform), corner colours, the grey of Lambert shading (shaded mode: one value per triangle),
// and for Pbr the corner positions, normals and tangents.
struct CornerAttributes {
    bool textured[kChannels] = {};  // the channel has a texture and the mesh its UV set
    Vec2 uv[kChannels][3] = {};
    bool colored = false;
    Vec4 col[3];
    float grey = 0;
    Vec3 pos[3];
    Vec3 faceNormal;                // geometric unit normal (front side)
    bool smooth = false;            // wedge normals present
    Vec3 normal[3];
    bool tangents = false;          // wedge tangents present (normal map)
    Vec4 tangent[3];
    bool coatTangents = false;      // the same for the clearcoat normal map
    Vec4 coatTangent[3];
    bool back = false;              // the camera sees the back side (double-sided materials only)
};

// Corner UVs of texture slot `s` on triangle corners `cw`; false when there is nothing to sample.
bool cornerUvs(const TriMesh& mesh, const Tri* cw, const TexSlot& s, Vec2 uv[3]) {
    if (s.image == nullptr || cw == nullptr) return false;
    const std::vector<Vec2>& set = s.texCoord == 1 ? mesh.wedges.uv1 : mesh.wedges.uv0;
    if (set.size() != mesh.wedges.size()) return false;
    for (int k = 0; k < 3; ++k) uv[k] = applyTextureTransform(*s.transform, set[(*cw)[k]]);
    return true;
}

// The tangents of corners `cw` for normal map `s`: the mesh's own, else those computed for its UV
// set; false when there are none.
bool cornerTangents(const RenderScene& scene, const Tri& cw, const TexSlot& s, Vec4 tangent[3]) {
    const TriMesh& mesh = *scene.mesh;
    const std::vector<Vec4>& own = mesh.wedges.tangent;
    const std::vector<Vec4>& computed = scene.tangents[s.texCoord == 1 ? 1 : 0];
    const std::vector<Vec4>* tangents = own.size() == mesh.wedges.size() ? &own
                                        : computed.size() == mesh.wedges.size() ? &computed
                                                                                : nullptr;
    if (tangents == nullptr) return false;
    for (int k = 0; k < 3; ++k) tangent[k] = (*tangents)[cw[k]];
    return true;
}

// \pre n is the triangle's unit normal; P its corners.
CornerAttributes cornerAttributes(const RenderScene& scene, size_t t, const TriMaterial& mat, RenderMode mode, Vec3 n,
                                  const Vec3 P[3], bool back, const Frame& f) {
    const TriMesh& mesh = *scene.mesh;
    const bool shaded = mode == RenderMode::Shaded, pbr = mode == RenderMode::Pbr;
    CornerAttributes at;
    const Tri* cw = mesh.cornerWedges.size() == mesh.triangles.size() ? &mesh.cornerWedges[t] : nullptr;
    if (!shaded) at.textured[kBaseColor] = cornerUvs(mesh, cw, mat.tex[kBaseColor], at.uv[kBaseColor]);
    at.colored = !shaded && cw != nullptr && mesh.wedges.color.size() == mesh.wedges.size() && !mesh.wedges.color.empty();
    if (at.colored)
        for (int k = 0; k < 3; ++k) at.col[k] = mesh.wedges.color[(*cw)[k]];
    if (shaded) {
        double lambert = std::fabs(dot(n, f.forward));
        at.grey = static_cast<float>(0.8 * (0.1 + 0.9 * lambert));
    }
    if (!pbr || mat.unlit) return at;
    for (int c = kMetallicRoughness; c < kChannels; ++c) at.textured[c] = cornerUvs(mesh, cw, mat.tex[c], at.uv[c]);
    at.faceNormal = n;
    at.back = back;
    for (int k = 0; k < 3; ++k) at.pos[k] = P[k];
    at.smooth = cw != nullptr && mesh.wedges.normal.size() == mesh.wedges.size();
    if (at.smooth)
        for (int k = 0; k < 3; ++k) at.normal[k] = mesh.wedges.normal[(*cw)[k]];
    if (at.textured[kNormal]) at.tangents = cornerTangents(scene, *cw, mat.tex[kNormal], at.tangent);
    if (at.textured[kCoatNormal]) at.coatTangents = cornerTangents(scene, *cw, mat.tex[kCoatNormal], at.coatTangent);
    return at;
}

// A clipped vertex on screen: pixel coordinates, 1/z and barycentrics / z.
struct Screen {
    double x, y, q;
    Vec3 bq;
};

// toCamera + clipNear + projection of triangle P; returns the polygon's vertex count (< 3: nothing
// in front of the near plane).
int toScreen(const Vec3 P[3], const Frame& f, double zNear, Screen s[4]) {
    ClipVertex cv[3];
    for (int k = 0; k < 3; ++k) {
        Vec3 d = P[k] - f.eye;
        cv[k].cam = {dot(d, f.right), dot(d, f.up), dot(d, f.forward)};
    }
    cv[0].bary = {1, 0, 0};
    cv[1].bary = {0, 1, 0};
    cv[2].bary = {0, 0, 1};
    ClipVertex poly[4];
    const int np = clipNear(cv, zNear, poly);
    if (np < 3) return np;
    const double halfH = 0.5 * f.height, halfW = 0.5 * f.width;
    for (int k = 0; k < np; ++k) {
        double q = 1.0 / poly[k].cam.z;
        s[k].x = halfW + poly[k].cam.x * q * f.focal * halfH;
        s[k].y = halfH - poly[k].cam.y * q * f.focal * halfH;
        s[k].q = q;
        s[k].bq = poly[k].bary * q;
    }
    return np;
}

// Screen gradients of 1/z and b/z over a screen triangle (affine in screen space).
struct Interpolants {
    double qdx = 0, qdy = 0;
    Vec3 bdx, bdy;
};

// \pre area = twice the signed screen area of (a, b, c), not 0.
Interpolants setupInterpolants(const Screen& a, const Screen& b, const Screen& c, double area) {
    auto grad = [&](double fa, double fb, double fc, double& dx, double& dy) {
        dx = ((fb - fa) * (c.y - a.y) - (fc - fa) * (b.y - a.y)) / area;
        dy = ((fc - fa) * (b.x - a.x) - (fb - fa) * (c.x - a.x)) / area;
    };
    Interpolants in;
    grad(a.q, b.q, c.q, in.qdx, in.qdy);
    for (int j = 0; j < 3; ++j) grad(a.bq[j], b.bq[j], c.bq[j], in.bdx[j], in.bdy[j]);
    return in;
}

// Barycentrics of the original triangle at a pixel (dx, dy from screen vertex a, depth z) and
// their screen derivatives.
struct PixelBary {
    Vec3 bar, dbx, dby;
};

PixelBary pixelBary(const Screen& a, const Interpolants& in, double dx, double dy, double z) {
    PixelBary p;
    Vec3 bq = a.bq + in.bdx * dx + in.bdy * dy;
    p.bar = bq * z;
    // d(b/z)/dx * z - b * z * dq/dx  = db/dx
    p.dbx = (in.bdx - p.bar * in.qdx) * z;
    p.dby = (in.bdy - p.bar * in.qdy) * z;
    return p;
}

// Trilinear sample of texture slot `s` at the pixel, with corner UVs `uv`.
void sampleChannel(const TexSlot& s, const Vec2 uv[3], const PixelBary& p, float out[4]) {
    Vec2 tc = uv[0] * p.bar[0] + uv[1] * p.bar[1] + uv[2] * p.bar[2];
    Vec2 dtx = uv[0] * p.dbx[0] + uv[1] * p.dbx[1] + uv[2] * p.dbx[2];
    Vec2 dty = uv[0] * p.dby[0] + uv[1] * p.dby[1] + uv[2] * p.dby[2];
    sampleTexture(*s.image, tc, dtx, dty, s.wrapS, s.wrapT, out);
}

// Base colour (linear RGBA) at a pixel: material factor x texture x vertex colour. Returns false
// when alpha masking discards the fragment.
bool shadeBaseColor(const TriMaterial& mat, const CornerAttributes& at, const PixelBary& p, float rgba[4]) {
    rgba[0] = static_cast<float>(mat.factor.x);
    rgba[1] = static_cast<float>(mat.factor.y);
    rgba[2] = static_cast<float>(mat.factor.z);
    rgba[3] = static_cast<float>(mat.factor.w);
    if (at.textured[kBaseColor]) {
        float tex[4];
        sampleChannel(mat.tex[kBaseColor], at.uv[kBaseColor], p, tex);
        for (int ch = 0; ch < 4; ++ch) rgba[ch] *= tex[ch];
    }
    if (at.colored) {
        const Vec3& bar = p.bar;
        double cc[4] = {0, 0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            cc[0] += at.col[k].x * bar[k];
            cc[1] += at.col[k].y * bar[k];
            cc[2] += at.col[k].z * bar[k];
            cc[3] += at.col[k].w * bar[k];
        }
        for (int ch = 0; ch < 4; ++ch) rgba[ch] *= static_cast<float>(cc[ch]);
    }
    return !(mat.mask && rgba[3] < mat.cutoff);
}

// --- Pbr --------------------------------------------------------------------------------------

// A directional light fixed in camera space: unit-less direction towards the light in camera
// coordinates (x right, y up, z towards the viewer) and its irradiance on a surface facing it.
struct CameraLight {
    double x, y, z;
    double irradiance;
};
// Key light from the upper left, in front of the object; weaker fill light from the right.
constexpr CameraLight kPbrLights[] = {{-0.5, 0.6, 0.62, 2.4}, {0.8, 0.05, 0.6, 0.8}};
// Ambient light: diffuse ambient = base colour x (1 - metallic) x kAmbientDiffuse, specular
// ambient = F0 x kAmbientSpecular, both times occlusion.
constexpr double kAmbientDiffuse = 0.25, kAmbientSpecular = 0.25;
// Perceptual roughness floor: keeps the GGX highlight of a mirror finite on a pixel grid.
constexpr double kMinRoughness = 0.04;
constexpr size_t kLightCount = sizeof(kPbrLights) / sizeof(kPbrLights[0]);

// The lights of one render in world space.
struct WorldLights {
    Vec3 toLight[kLightCount];
    double irradiance[kLightCount];
    Vec3 eye;
};

WorldLights worldLights(const Frame& f) {
    WorldLights w;
    for (size_t i = 0; i < kLightCount; ++i) {
        const CameraLight& l = kPbrLights[i];
        w.toLight[i] = normalize(f.right * l.x + f.up * l.y - f.forward * l.z);
        w.irradiance[i] = l.irradiance;
    }
    w.eye = f.eye;
    return w;
}

// Shading normal at a pixel: interpolated wedge normal (face normal without them), perturbed by
// the tangent-space normal map of `channel` (+X along u, +Y up the image, scaled by `scale`),
// flipped when the back side is seen.
Vec3 shadingNormal(const TriMaterial& mat, const CornerAttributes& at, const PixelBary& p, Channel channel, double scale,
                   bool tangents, const Vec4 tangent[3]) {
    const Vec3& b = p.bar;
    Vec3 N = at.faceNormal;
    if (at.smooth) {
        Vec3 s = normalize(at.normal[0] * b[0] + at.normal[1] * b[1] + at.normal[2] * b[2]);
        if (length2(s) > 0) N = s;
    }
    if (at.textured[channel] && tangents) {
        float tex[4];
        sampleChannel(mat.tex[channel], at.uv[channel], p, tex);
        const Vec3 tn = tangentNormalOfTexel(tex, scale);
        TangentFrame frame;
        if (tangentFrameAt(N, {tangent[0], tangent[1], tangent[2]}, {b[0], b[1], b[2]}, frame)) {
            const Vec3 m = normalize(frame.toWorld(tn));
            if (length2(m) > 0) N = m;
        }
    }
    return at.back ? -N : N;
}

// The clearcoat layer at a pixel: factor x texture R, roughness factor x texture G, and the coat's
// own normal (the interpolated normal, perturbed by the clearcoat normal map only).
metrics_detail::ClearcoatLayer clearcoatAt(const TriMaterial& mat, const CornerAttributes& at, const PixelBary& p) {
    metrics_detail::ClearcoatLayer layer;
    layer.coat = mat.coat;
    double roughness = mat.coatRoughness;
    float tex[4];
    if (at.textured[kCoat]) {
        sampleChannel(mat.tex[kCoat], at.uv[kCoat], p, tex);
        layer.coat *= tex[0];
    }
    if (at.textured[kCoatRoughness]) {
        sampleChannel(mat.tex[kCoatRoughness], at.uv[kCoatRoughness], p, tex);
        roughness *= tex[1];
    }
    layer.coat = std::clamp(layer.coat, 0.0, 1.0);
    layer.roughness = std::clamp(roughness, kMinRoughness, 1.0);
    layer.normal = shadingNormal(mat, at, p, kCoatNormal, mat.coatNormalScale, at.coatTangents, at.coatTangent);
    return layer;
}

// Cook-Torrance GGX + Lambert under the camera lights plus occluded ambient and emissive, linear
// RGB at a pixel. Returns false when alpha masking discards the fragment.
bool shadePbr(const TriMaterial& mat, const CornerAttributes& at, const PixelBary& p, const WorldLights& lights,
              float out[3]) {
    float rgba[4];
    if (!shadeBaseColor(mat, at, p, rgba)) return false;
    if (mat.unlit) {
        for (int c = 0; c < 3; ++c) out[c] = rgba[c];
        return true;
    }
    const double base[3] = {rgba[0], rgba[1], rgba[2]};
    double metallic = mat.metallic, roughness = mat.roughness, occlusion = 1;
    Vec3 emissive = mat.emissive;
    float tex[4];
    if (at.textured[kMetallicRoughness]) {
        sampleChannel(mat.tex[kMetallicRoughness], at.uv[kMetallicRoughness], p, tex);
        roughness *= tex[1];
        metallic *= tex[2];
    }
    if (at.textured[kOcclusion]) {
        sampleChannel(mat.tex[kOcclusion], at.uv[kOcclusion], p, tex);
        occlusion = 1 + mat.occlusionStrength * (tex[0] - 1);
    }
    if (at.textured[kEmissive]) {
        sampleChannel(mat.tex[kEmissive], at.uv[kEmissive], p, tex);
        emissive = {emissive.x * tex[0], emissive.y * tex[1], emissive.z * tex[2]};
    }
    metallic = std::clamp(metallic, 0.0, 1.0);
    roughness = std::clamp(roughness, kMinRoughness, 1.0);
    double f0[3], rgb[3];
    for (int c = 0; c < 3; ++c) {
        f0[c] = 0.04 + (base[c] - 0.04) * metallic;
        rgb[c] = occlusion * (base[c] * (1 - metallic) * kAmbientDiffuse + f0[c] * kAmbientSpecular);
    }
    const Vec3 N = shadingNormal(mat, at, p, kNormal, mat.normalScale, at.tangents, at.tangent);
    const Vec3 pos = at.pos[0] * p.bar[0] + at.pos[1] * p.bar[1] + at.pos[2] * p.bar[2];
    const Vec3 V = normalize(lights.eye - pos);
    const metrics_detail::GgxLobe lobe(roughness, N, V);
    for (size_t i = 0; i < kLightCount; ++i) {
        const Vec3& L = lights.toLight[i];
        const double nl = dot(N, L);
        if (!(nl > 0)) continue;
        double vh = 0;
        const double dg = lobe.dg(N, L, V, nl, vh);
        const double m = 1 - vh, fresnel = m * m * m * m * m;
        for (int c = 0; c < 3; ++c) {
            const double F = f0[c] + (1 - f0[c]) * fresnel;
            const double specular = dg * F / (4 * nl * lobe.nv);
            const double diffuse = (1 - F) * (1 - metallic) * base[c] / kPi;
            rgb[c] += (diffuse + specular) * lights.irradiance[i] * nl;
        }
    }
    const double e[3] = {emissive.x, emissive.y, emissive.z};
    for (int c = 0; c < 3; ++c) rgb[c] += e[c];
    if (mat.coat > 0)
        metrics_detail::addClearcoat(clearcoatAt(mat, at, p), V, lights.toLight, lights.irradiance, kLightCount,
                                     kAmbientSpecular, occlusion, rgb);
    for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(std::clamp(rgb[c], 0.0, 1.0));
    return true;
}

// Whether the pixel lies within `band` pixels of one of the triangle's seam edges (bit k: the
// edge opposite corner k + 2, where that barycentric is 0; its screen distance is the
// barycentric over its screen gradient).
bool nearSeam(uint8_t seamBits, const PixelBary& p, double band) {
    for (int k = 0; k < 3; ++k) {
        if (!(seamBits & (1u << k))) continue;
        const int j = (k + 2) % 3;
        const double grad = std::sqrt(p.dbx[j] * p.dbx[j] + p.dby[j] * p.dby[j]);
        if (p.bar[j] <= band * grad) return true;
    }
    return false;
}

// Scans the pixels whose centres lie inside screen triangle (a, b, c) (either winding), depth-
// tests them and writes the shaded colour, its depth, coverage and seam mark.
void rasterizeTriangle(const Screen& a, const Screen& b, const Screen& c, const TriMaterial& mat, const CornerAttributes& at,
                       RenderMode mode, const WorldLights& lights, uint8_t seamBits, double seamBand, Target& target,
                       Rendering& img) {
    double area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (std::fabs(area) < 1e-12) return;
    const Interpolants in = setupInterpolants(a, b, c, area);
    const int W = target.width, H = target.height;
    int x0 = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}))));
    int x1 = std::min(W - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}))));
    int y0 = std::max(0, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}))));
    int y1 = std::min(H - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}))));
    const double sign = area > 0 ? 1 : -1;
    for (int py = y0; py <= y1; ++py) {
        double y = py + 0.5;
        for (int px = x0; px <= x1; ++px) {
            double x = px + 0.5;
            double w0 = sign * ((b.x - x) * (c.y - y) - (b.y - y) * (c.x - x));
            double w1 = sign * ((c.x - x) * (a.y - y) - (c.y - y) * (a.x - x));
            double w2 = sign * ((a.x - x) * (b.y - y) - (a.y - y) * (b.x - x));
            if (w0 < 0 || w1 < 0 || w2 < 0) continue;
            double dx = x - a.x, dy = y - a.y;
            double q = a.q + in.qdx * dx + in.qdy * dy;
            if (!(q > 0)) continue;
            double z = 1.0 / q;
            size_t pix = static_cast<size_t>(py) * W + px;
            if (!(z < target.depth[pix])) continue;
            float out[3];
            if (mode == RenderMode::Shaded) {
                out[0] = out[1] = out[2] = at.grey;
            } else if (mode == RenderMode::BaseColor) {
                float rgba[4];
                if (!shadeBaseColor(mat, at, pixelBary(a, in, dx, dy, z), rgba)) continue;
                for (int ch = 0; ch < 3; ++ch) out[ch] = rgba[ch];
            } else if (!shadePbr(mat, at, pixelBary(a, in, dx, dy, z), lights, out)) {
                continue;
            }
            target.depth[pix] = z;
            img.coverage[pix] = 1;
            img.seam[pix] = seamBits != 0 && nearSeam(seamBits, pixelBary(a, in, dx, dy, z), seamBand);
            for (int ch = 0; ch < 3; ++ch) target.linear[pix * 3 + ch] = out[ch];
        }
    }
}

}  // namespace

Rendering render(const RenderScene& scene, const Camera& camera, const RenderOptions& options) {
    const TriMesh& mesh = *scene.mesh;
    const int W = options.width, H = options.height;
    Rendering img;
    img.width = W;
    img.height = H;
    img.rgb.assign(static_cast<size_t>(W) * H * 3, 0.f);
    img.coverage.assign(static_cast<size_t>(W) * H, 0);
    img.seam.assign(static_cast<size_t>(W) * H, 0);
    Target target;
    target.width = W;
    target.height = H;
    target.linear.assign(static_cast<size_t>(W) * H * 3, 0.f);
    target.depth.assign(static_cast<size_t>(W) * H, std::numeric_limits<double>::infinity());
    const Frame f = makeFrame(camera, W, H);
    const WorldLights lights = worldLights(f);

    // Materials by index + 1 (slot 0: no material, also for out-of-range indices), resolved when
    // the first triangle is drawn.
    std::vector<TriMaterial> materials;
    auto materialOf = [&](int32_t m) -> const TriMaterial& {
        size_t slot = static_cast<size_t>(m + 1);
        if (materials.empty()) {
            materials.push_back(resolveMaterial(scene, -1));
            for (size_t i = 0; i < scene.asset->materials.size(); ++i)
                materials.push_back(resolveMaterial(scene, static_cast<int32_t>(i)));
        }
        return slot < materials.size() ? materials[slot] : materials[0];
    };

    for (size_t t = 0; t < mesh.triangles.size(); ++t) {
        const Tri& tri = mesh.triangles[t];
        const Vec3 P[3] = {mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]};
        Vec3 n = cross(P[1] - P[0], P[2] - P[0]);
        double nl = length(n);
        if (!(nl > 0)) continue;
        n = n / nl;
        const TriMaterial& mat = materialOf(mesh.triangleMaterial.empty() ? -1 : mesh.triangleMaterial[t]);
        // cullBackFace
        double facing = dot(n, f.eye - P[0]);
        if (facing <= 0 && !mat.doubleSided) continue;
        const CornerAttributes at = cornerAttributes(scene, t, mat, options.mode, n, P, facing <= 0, f);
        Screen s[4];
        const int np = toScreen(P, f, camera.zNear, s);
        const uint8_t seamBits = t < scene.seamEdges.size() ? scene.seamEdges[t] : 0;
        for (int fan = 1; fan + 1 < np; ++fan)
            rasterizeTriangle(s[0], s[fan], s[fan + 1], mat, at, options.mode, lights, seamBits, options.seamBand, target, img);
    }
    // encodeSrgb
    for (size_t i = 0; i < target.linear.size(); ++i) img.rgb[i] = linearToSrgb(target.linear[i]);
    return img;
}

}  // namespace lodbake
