// The software rasteriser of render.h, laid out as a pipeline:
//   sphereViews; per triangle: cullBackFace, cornerAttributes, toScreen (toCamera, clipNear,
//   projection); per sub-triangle: rasterizeTriangle (setupInterpolants, pixel scan with z-test,
//   shadeBaseColor or Lambert grey); encodeSrgb.
// Perspective-correct interpolation: 1/z and b_k/z (b = barycentrics of the original triangle)
// are affine in screen space; their screen gradients give exact UV derivatives for the mip level
// (trilinear filtering, as in the OpenGL spec's scale factor rho).
#include "lodbake/metrics/render.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "lodbake/texture/color_space.h"
#include "lodbake/texture/texture_transform.h"

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

// Per-triangle material data resolved once.
struct TriMaterial {
    Vec4 factor{1, 1, 1, 1};
    const MipImage* texture = nullptr;
    int texCoord = 0;
    const TextureTransform* transform = nullptr;
    int wrapS = kRepeat, wrapT = kRepeat;
    bool doubleSided = false;
    bool mask = false;
    double cutoff = 0.5;
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
    int t = mat.baseColor.texture;
    if (t >= 0 && static_cast<size_t>(t) < asset.textures.size()) {
        int i = asset.textures[t].image;
        if (i >= 0 && static_cast<size_t>(i) < scene.images.size() && !scene.images[i].levels.empty())
            r.texture = &scene.images[i];
        int s = asset.textures[t].sampler;
        if (s >= 0 && static_cast<size_t>(s) < asset.samplers.size()) {
            r.wrapS = asset.samplers[s].wrapS;
            r.wrapT = asset.samplers[s].wrapT;
        }
    }
    r.texCoord = mat.baseColor.transform.present && mat.baseColor.transform.texCoord >= 0
                     ? mat.baseColor.transform.texCoord
                     : mat.baseColor.texCoord;
    r.transform = &mat.baseColor.transform;
    return r;
}

}  // namespace

std::vector<Camera> sphereViews(int count, Vec3 center, double radius, double fovY) {
    std::vector<Camera> views;
    if (count <= 0) return views;
    if (!(radius > 0)) radius = 1;
    const double golden = 3.14159265358979323846 * (3 - std::sqrt(5.0));
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

// What a triangle carries to its pixels: corner UVs (after the texture transform) and colours,
// and the grey of Lambert shading (shaded mode: one value per triangle).
struct CornerAttributes {
    bool textured = false, colored = false;
    Vec2 uv[3] = {};
    Vec4 col[3];
    float grey = 0;
};

// \pre n is the triangle's unit normal.
CornerAttributes cornerAttributes(const TriMesh& mesh, size_t t, const TriMaterial& mat, bool shaded, Vec3 n, const Frame& f) {
    CornerAttributes at;
    const Tri* cw = mesh.cornerWedges.size() == mesh.triangles.size() ? &mesh.cornerWedges[t] : nullptr;
    at.textured = !shaded && mat.texture != nullptr && cw != nullptr;
    if (at.textured) {
        const std::vector<Vec2>& set = mat.texCoord == 1 ? mesh.wedges.uv1 : mesh.wedges.uv0;
        if (set.size() != mesh.wedges.size()) at.textured = false;
        else
            for (int k = 0; k < 3; ++k) at.uv[k] = applyTextureTransform(*mat.transform, set[(*cw)[k]]);
    }
    at.colored = !shaded && cw != nullptr && mesh.wedges.color.size() == mesh.wedges.size() && !mesh.wedges.color.empty();
    if (at.colored)
        for (int k = 0; k < 3; ++k) at.col[k] = mesh.wedges.color[(*cw)[k]];
    if (shaded) {
        double lambert = std::fabs(dot(n, f.forward));
        at.grey = static_cast<float>(0.8 * (0.1 + 0.9 * lambert));
    }
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

// Base colour at a pixel (dx, dy from screen vertex a, depth z): material factor x texture x
// vertex colour. Returns false when alpha masking discards the fragment.
bool shadeBaseColor(const TriMaterial& mat, const CornerAttributes& at, const Screen& a, const Interpolants& in, double dx,
                    double dy, double z, float out[3]) {
    Vec3 bq = a.bq + in.bdx * dx + in.bdy * dy;
    Vec3 bar = bq * z;
    float rgba[4] = {static_cast<float>(mat.factor.x), static_cast<float>(mat.factor.y), static_cast<float>(mat.factor.z),
                     static_cast<float>(mat.factor.w)};
    if (at.textured) {
        Vec2 tc = at.uv[0] * bar[0] + at.uv[1] * bar[1] + at.uv[2] * bar[2];
        // d(b/z)/dx * z - b * z * dq/dx  = db/dx
        Vec3 dbx = (in.bdx - bar * in.qdx) * z, dby = (in.bdy - bar * in.qdy) * z;
        Vec2 dtx = at.uv[0] * dbx[0] + at.uv[1] * dbx[1] + at.uv[2] * dbx[2];
        Vec2 dty = at.uv[0] * dby[0] + at.uv[1] * dby[1] + at.uv[2] * dby[2];
        float tex[4];
        sampleTexture(*mat.texture, tc, dtx, dty, mat.wrapS, mat.wrapT, tex);
        for (int ch = 0; ch < 4; ++ch) rgba[ch] *= tex[ch];
    }
    if (at.colored) {
        double cc[4] = {0, 0, 0, 0};
        for (int k = 0; k < 3; ++k) {
            cc[0] += at.col[k].x * bar[k];
            cc[1] += at.col[k].y * bar[k];
            cc[2] += at.col[k].z * bar[k];
            cc[3] += at.col[k].w * bar[k];
        }
        for (int ch = 0; ch < 4; ++ch) rgba[ch] *= static_cast<float>(cc[ch]);
    }
    if (mat.mask && rgba[3] < mat.cutoff) return false;
    out[0] = rgba[0];
    out[1] = rgba[1];
    out[2] = rgba[2];
    return true;
}

// Scans the pixels whose centres lie inside screen triangle (a, b, c) (either winding), depth-
// tests them and writes the shaded colour, its depth and coverage.
void rasterizeTriangle(const Screen& a, const Screen& b, const Screen& c, const TriMaterial& mat, const CornerAttributes& at,
                       bool shaded, Target& target, Rendering& img) {
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
            if (shaded) out[0] = out[1] = out[2] = at.grey;
            else if (!shadeBaseColor(mat, at, a, in, dx, dy, z, out)) continue;
            target.depth[pix] = z;
            img.coverage[pix] = 1;
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
    Target target;
    target.width = W;
    target.height = H;
    target.linear.assign(static_cast<size_t>(W) * H * 3, 0.f);
    target.depth.assign(static_cast<size_t>(W) * H, std::numeric_limits<double>::infinity());
    const Frame f = makeFrame(camera, W, H);
    const bool shaded = options.mode == RenderMode::Shaded;

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
        const CornerAttributes at = cornerAttributes(mesh, t, mat, shaded, n, f);
        Screen s[4];
        const int np = toScreen(P, f, camera.zNear, s);
        for (int fan = 1; fan + 1 < np; ++fan) rasterizeTriangle(s[0], s[fan], s[fan + 1], mat, at, shaded, target, img);
    }
    // encodeSrgb
    for (size_t i = 0; i < target.linear.size(); ++i) img.rgb[i] = linearToSrgb(target.linear[i]);
    return img;
}

}  // namespace lodbake
