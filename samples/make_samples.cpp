// make-samples OUTDIR: writes the sample assets lodbake generates itself (deterministic, small):
//
//   hemisphere9.glb  open hemisphere, 9 materials (3 longitude sectors x 3 latitude bands), each
//                    with its own patterned 128x128 image; ~9.5k triangles
//   wall5.glb        wavy wall, 5 vertical strips each with its own image; 5,000 triangles
//   colors.glb       closed sphere banded into 6 colour-only materials; ~5.1k triangles
//   seamball.glb     closed cube-sphere, 6 separate UV islands in one 384x256 texture; 4,800 triangles
//   pbrscene.glb     every material channel: a dome with base colour, metallic-roughness,
//                    occlusion (TEXCOORD_1), emissive and normal maps on a plate whose bumps live
//                    only in its normal map, before an alpha-masked double-sided panel; 7,488 triangles
//   walker.glb       a skinned, textured walker: a torso on two legs that swing back and forth in a
//                    one-second loop (3 joints, legs blended into the hips near the top); 3,104 triangles
//   drum.glb         a large open, double-sided textured backdrop cylinder on a floor disk around 21
//                    small detailed parts (spheres, capped cylinders, crossed-sheet trees); 8,640 triangles
//   critter.glb      a low-poly rigged quadruped: body, head, thin ears, tail and four two-joint legs
//                    (11 joints, weights blended at every joint, rest pose != bind pose) with a
//                    one-second trot; one texture of four coloured cells; 452 triangles
//   materials.glb    four spheres on a floor, each on a KHR_materials_* extension: sheen (cloth),
//                    clearcoat (paint), transmission + volume + ior (glass), specular colour
//   facets.glb       a flat-shaded low-poly gem: a noisy geodesic icosphere whose every corner
//                    carries its face's normal (hard edges everywhere), latitude-longitude UVs into
//                    one small banded texture; 720 triangles
//   variants.glb     KHR_materials_variants: a textured ball on a grey pedestal with variants "red",
//                    "blue" and "gold" that change the ball, the pedestal or both, and "classic" that
//                    maps both to their default materials; 1,440 triangles
//   tiles.glb        a draped sheet whose one material repeats: a 64x64 woven base colour and its
//                    normal map tiled 8 x 8 by KHR_texture_transform (scale 8, -8); 3,200 triangles
//
// `--scale S` multiplies every grid's resolution by S (about S^2 times the triangles) for
// benchmarks; S = 1 gives the samples above.
//
// Every mesh is welded: positions shared across UV seams and material boundaries are computed
// from the same integer lattice coordinates, so they are bit-identical and weld. Each wedge carries
// a normal and uv0. Images are drawn procedurally (checkerboard + a 7-segment digit in distinct
// colours) and PNG-encoded in memory (lodbake/texture/codec.h).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <tuple>

#include "common/cli.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/math.h"
#include "lodbake/core/pose.h"
#include "lodbake/core/tangents.h"
#include "lodbake/gltf/gltf.h"
#include "lodbake/texture/codec.h"

namespace lodbake {
namespace {

// --- images -------------------------------------------------------------------------------

struct Rgb {
    uint8_t r, g, b;
};

// Distinct, saturated colours (index mod 12).
Rgb palette(int i) {
    static const Rgb k[12] = {{230, 60, 50},  {60, 170, 75},  {50, 100, 220}, {240, 200, 40},
                              {150, 70, 200}, {40, 190, 200}, {240, 130, 40}, {200, 60, 150},
                              {130, 200, 50}, {90, 90, 90},   {160, 110, 60}, {250, 250, 250}};
    return k[((i % 12) + 12) % 12];
}

// 7-segment digit test: is (x, y) in [0,1]^2 (y down) inside digit d's lit segments?
bool digitCovers(int d, double x, double y) {
    static const uint8_t kSeg[10] = {0x3f, 0x06, 0x5b, 0x4f, 0x66, 0x6d, 0x7d, 0x07, 0x7f, 0x6f};
    const double t = 0.14;  // stroke thickness
    auto hbar = [&](double cy) { return x >= 0.1 && x <= 0.9 && std::fabs(y - cy) <= t / 2; };
    auto vbar = [&](double cx, double y0, double y1) { return std::fabs(x - cx) <= t / 2 && y >= y0 && y <= y1; };
    uint8_t s = kSeg[((d % 10) + 10) % 10];
    return ((s & 1) && hbar(0.07)) || ((s & 2) && vbar(0.9, 0.07, 0.5)) || ((s & 4) && vbar(0.9, 0.5, 0.93)) ||
           ((s & 8) && hbar(0.93)) || ((s & 16) && vbar(0.1, 0.5, 0.93)) || ((s & 32) && vbar(0.1, 0.07, 0.5)) ||
           ((s & 64) && hbar(0.5));
}

// Fills the cell [x0, x0+w) x [y0, y0+h) of an RGB image with a checkerboard of colour `c` and a
// lighter tint, plus digit `digit` in the centre, a gradient along x and a dark border.
void drawCell(std::vector<uint8_t>& px, int width, int x0, int y0, int w, int h, int c, int digit) {
    Rgb a = palette(c), b = palette(c + 5);
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) {
            double u = (x - x0 + 0.5) / w, v = (y - y0 + 0.5) / h;
            bool check = (static_cast<int>(u * 8) + static_cast<int>(v * 8)) % 2 == 0;
            Rgb col = check ? a : Rgb{static_cast<uint8_t>((a.r + 255) / 2), static_cast<uint8_t>((a.g + 255) / 2),
                                      static_cast<uint8_t>((a.b + 255) / 2)};
            double shade = 0.75 + 0.25 * u;
            col = {static_cast<uint8_t>(col.r * shade), static_cast<uint8_t>(col.g * shade),
                   static_cast<uint8_t>(col.b * shade)};
            if (u > 0.25 && u < 0.75 && v > 0.2 && v < 0.8 && digitCovers(digit, (u - 0.25) / 0.5, (v - 0.2) / 0.6))
                col = b;
            if (u < 0.03 || u > 0.97 || v < 0.03 || v > 0.97) col = {20, 20, 20};
            uint8_t* p = &px[(static_cast<size_t>(y) * width + x) * 3];
            p[0] = col.r;
            p[1] = col.g;
            p[2] = col.b;
        }
}

// Adds an image, a texture using it and a material using the texture; returns the material index.
int addTexturedMaterial(Asset& asset, const std::string& name, Image image) {
    asset.images.push_back(std::move(image));
    Texture t;
    t.image = static_cast<int>(asset.images.size()) - 1;
    t.sampler = 0;
    asset.textures.push_back(t);
    Material m;
    m.name = name;
    m.baseColor.texture = static_cast<int>(asset.textures.size()) - 1;
    m.metallicFactor = 0;
    m.roughnessFactor = 0.8;
    asset.materials.push_back(m);
    return static_cast<int>(asset.materials.size()) - 1;
}

// --- meshes -------------------------------------------------------------------------------

// Builds a welded TriMesh: vertices are keyed by an integer lattice key (so seams weld exactly),
// wedges by (vertex, material, uv, normal).
class MeshBuilder {
public:
    using Key = std::tuple<int64_t, int64_t, int64_t>;
    uint32_t vertex(const Key& key, Vec3 position) {
        auto it = vertexIndex_.find(key);
        if (it != vertexIndex_.end()) return it->second;
        uint32_t i = static_cast<uint32_t>(mesh_.positions.size());
        mesh_.positions.push_back(position);
        vertexIndex_.emplace(key, i);
        return i;
    }
    uint32_t wedge(uint32_t v, int material, Vec2 uv, Vec3 normal) {
        auto key = std::make_tuple(v, material, uv.x, uv.y, normal.x, normal.y, normal.z);
        auto it = wedgeIndex_.find(key);
        if (it != wedgeIndex_.end()) return it->second;
        uint32_t i = static_cast<uint32_t>(mesh_.wedges.vertex.size());
        mesh_.wedges.vertex.push_back(v);
        mesh_.wedges.uv0.push_back(uv);
        mesh_.wedges.normal.push_back(normal);
        wedgeIndex_.emplace(key, i);
        return i;
    }
    // A triangle from three (vertex, wedge) corners, counter-clockwise seen from outside.
    void triangle(int material, std::array<uint32_t, 3> w) {
        Tri t{mesh_.wedges.vertex[w[0]], mesh_.wedges.vertex[w[1]], mesh_.wedges.vertex[w[2]]};
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return;  // collapsed at a pole
        mesh_.triangles.push_back(t);
        mesh_.cornerWedges.push_back(w);
        mesh_.triangleMaterial.push_back(material);
    }
    size_t vertexCount() const { return mesh_.positions.size(); }
    Vec3 position(uint32_t v) const { return mesh_.positions[v]; }
    size_t triangleCount() const { return mesh_.triangles.size(); }
    TriMesh take() { return std::move(mesh_); }

private:
    TriMesh mesh_;
    std::map<Key, uint32_t> vertexIndex_;
    std::map<std::tuple<uint32_t, int, double, double, double, double, double>, uint32_t> wedgeIndex_;
};

Asset newAsset(const std::string& name) {
    Asset a;
    a.sourcePath = name;
    a.samplers.push_back(Sampler{9729, 9987, 10497, 10497});  // linear, linear-mipmap-linear, repeat
    return a;
}

// Point on the unit sphere at latitude index i of nLat (0 = south pole .. nLat = north pole)
// and longitude index j of nLon (wrapping, so j = nLon welds with j = 0).
Vec3 spherePoint(int i, int nLat, int j, int nLon) {
    double theta = kPi * i / nLat - kPi / 2;  // latitude
    double phi = 2 * kPi * (j % nLon) / nLon;
    if (i == 0) return {0, -1, 0};
    if (i == nLat) return {0, 1, 0};
    return {std::cos(theta) * std::cos(phi), std::sin(theta), -std::cos(theta) * std::sin(phi)};
}

// n scaled by s, rounded to a positive multiple of `multiple`.
int scaled(int n, double s, int multiple) { return std::max(multiple, int(std::lround(n * s / multiple)) * multiple); }

MeshBuilder::Key sphereKey(int i, int nLat, int j, int nLon) {
    if (i == 0 || i == nLat) return {i, 0, 0};
    return {i, j % nLon, 0};
}

// hemisphere9: latitude from the equator (i = nLat/2) to the north pole, 3 sectors x 3 bands.
Asset makeHemisphere9(double scale) {
    Asset asset = newAsset("hemisphere9");
    for (int m = 0; m < 9; ++m) {
        const int S = 128;
        std::vector<uint8_t> px(S * S * 3);
        drawCell(px, S, 0, 0, S, S, m, m + 1);
        addTexturedMaterial(asset, "patch" + std::to_string(m + 1), encodePng(px, S, S, "patch" + std::to_string(m + 1)));
    }
    const int nLat = scaled(80, scale, 2), nLon = scaled(120, scale, 3);  // full-sphere counts; the hemisphere uses half the rings
    const int i0 = nLat / 2, rings = nLat - i0;
    MeshBuilder mb;
    for (int i = i0; i < nLat; ++i)
        for (int j = 0; j < nLon; ++j) {
            int sector = j * 3 / nLon, band = (i - i0) * 3 / rings;
            int mat = band * 3 + sector;
            // Local UVs: the block spans [j0, j1) x [b0, b1) in (longitude, ring) steps.
            int j0 = sector * nLon / 3, j1 = (sector + 1) * nLon / 3;
            int b0 = i0 + band * rings / 3, b1 = i0 + (band + 1) * rings / 3;
            auto corner = [&](int ii, int jj) {
                Vec3 p = spherePoint(ii, nLat, jj, nLon);
                uint32_t v = mb.vertex(sphereKey(ii, nLat, jj, nLon), p);
                double u = static_cast<double>(jj - j0) / (j1 - j0);
                if (ii == nLat) u = (j + 0.5 - j0) / (j1 - j0);
                double vv = 1.0 - static_cast<double>(ii - b0) / (b1 - b0);
                return mb.wedge(v, mat, {u, vv}, p);
            };
            uint32_t a = corner(i, j), b = corner(i, j + 1), c = corner(i + 1, j + 1), d = corner(i + 1, j);
            mb.triangle(mat, {a, b, c});
            mb.triangle(mat, {a, c, d});
        }
    asset.mesh = mb.take();
    return asset;
}

// wall5: a wavy wall 2 x 1 (x, y) with z = bumps, 50 x 50 quads, 5 strips of 10 columns.
Asset makeWall5(double scale) {
    Asset asset = newAsset("wall5");
    for (int m = 0; m < 5; ++m) {
        const int S = 128;
        std::vector<uint8_t> px(S * S * 3);
        drawCell(px, S, 0, 0, S, S, 2 * m + 1, m + 1);
        addTexturedMaterial(asset, "strip" + std::to_string(m + 1), encodePng(px, S, S, "strip" + std::to_string(m + 1)));
    }
    const int nx = scaled(50, scale, 5), ny = scaled(50, scale, 1);
    auto height = [](double x, double y) { return 0.04 * std::sin(3 * kPi * x) * std::cos(2 * kPi * y) + 0.02 * std::sin(7 * x + 5 * y); };
    auto normalAt = [&](double x, double y) {
        double e = 1e-4;
        double dx = (height(x + e, y) - height(x - e, y)) / (2 * e);
        double dy = (height(x, y + e) - height(x, y - e)) / (2 * e);
        return normalize(Vec3{-dx, -dy, 1});
    };
    MeshBuilder mb;
    for (int i = 0; i < ny; ++i)
        for (int j = 0; j < nx; ++j) {
            const int strip = nx / 5;
            int mat = j / strip;
            auto corner = [&](int ii, int jj) {
                double x = 2.0 * jj / nx, y = 1.0 * ii / ny;
                uint32_t v = mb.vertex({ii, jj, 0}, {x, y, height(x, y)});
                Vec2 uv{(jj - mat * strip) / static_cast<double>(strip), 1.0 - ii / static_cast<double>(ny)};
                return mb.wedge(v, mat, uv, normalAt(x, y));
            };
            uint32_t a = corner(i, j), b = corner(i, j + 1), c = corner(i + 1, j + 1), d = corner(i + 1, j);
            mb.triangle(mat, {a, b, c});
            mb.triangle(mat, {a, c, d});
        }
    asset.mesh = mb.take();
    return asset;
}

// colors: a closed sphere, 6 latitude bands with colour-only materials; uv0 = (longitude, latitude).
Asset makeColors(double scale) {
    Asset asset = newAsset("colors");
    asset.samplers.clear();
    for (int m = 0; m < 6; ++m) {
        Material mat;
        mat.name = "band" + std::to_string(m + 1);
        Rgb c = palette(m);
        auto lin = [](uint8_t v) {
            double s = v / 255.0;
            return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
        };
        mat.baseColorFactor = {lin(c.r), lin(c.g), lin(c.b), 1};
        mat.metallicFactor = 0;
        mat.roughnessFactor = 0.6;
        asset.materials.push_back(mat);
    }
    const int nLat = scaled(50, scale, 1), nLon = scaled(52, scale, 1);
    MeshBuilder mb;
    for (int i = 0; i < nLat; ++i)
        for (int j = 0; j < nLon; ++j) {
            int mat = i * 6 / nLat;
            auto corner = [&](int ii, int jj) {
                Vec3 p = spherePoint(ii, nLat, jj, nLon);
                uint32_t v = mb.vertex(sphereKey(ii, nLat, jj, nLon), p);
                double u = static_cast<double>(jj) / nLon;
                if (ii == 0 || ii == nLat) u = (j + 0.5) / nLon;
                return mb.wedge(v, mat, {u, 1.0 - static_cast<double>(ii) / nLat}, p);
            };
            uint32_t a = corner(i, j), b = corner(i, j + 1), c = corner(i + 1, j + 1), d = corner(i + 1, j);
            mb.triangle(mat, {a, b, c});
            mb.triangle(mat, {a, c, d});
        }
    asset.mesh = mb.take();
    return asset;
}

// seamball: cube-sphere; face f is an n x n grid on the cube [-n/2, n/2]^3 (integer lattice keys),
// projected to the unit sphere; its UV island is cell (f % 3, f / 3) of a 3 x 2 atlas, inset 4 texels.
Asset makeSeamball(double scale) {
    Asset asset = newAsset("seamball");
    const int C = 128, W = 3 * C, H = 2 * C;
    std::vector<uint8_t> px(static_cast<size_t>(W) * H * 3);
    for (int f = 0; f < 6; ++f) drawCell(px, W, (f % 3) * C, (f / 3) * C, C, C, f * 2, f + 1);
    int mat = addTexturedMaterial(asset, "seamball", encodePng(px, W, H, "seamball"));
    asset.samplers[0].wrapS = asset.samplers[0].wrapT = 33071;  // clamp: islands must not bleed across
    const int n = scaled(20, scale, 2), h = n / 2;
    // Face frames: origin corner + two axes on the integer lattice; normal = cross(du, dv) outward.
    struct Face {
        std::array<int, 3> origin, du, dv;
    };
    const Face faces[6] = {
        {{h, -h, h}, {0, 0, -1}, {0, 1, 0}},    // +x
        {{-h, -h, -h}, {0, 0, 1}, {0, 1, 0}},   // -x
        {{-h, h, h}, {1, 0, 0}, {0, 0, -1}},    // +y
        {{-h, -h, -h}, {1, 0, 0}, {0, 0, 1}},   // -y
        {{-h, -h, h}, {1, 0, 0}, {0, 1, 0}},    // +z
        {{h, -h, -h}, {-1, 0, 0}, {0, 1, 0}},   // -z
    };
    MeshBuilder mb;
    for (int f = 0; f < 6; ++f) {
        const Face& F = faces[f];
        double cu0 = (f % 3) * C + 4, cv0 = (f / 3) * C + 4, cs = C - 8;
        auto corner = [&](int a, int b) {
            std::array<int64_t, 3> q;
            for (int k = 0; k < 3; ++k) q[k] = F.origin[k] + a * F.du[k] + b * F.dv[k];
            Vec3 p = normalize(Vec3{static_cast<double>(q[0]), static_cast<double>(q[1]), static_cast<double>(q[2])});
            uint32_t v = mb.vertex({q[0], q[1], q[2]}, p);
            Vec2 uv{(cu0 + cs * a / n) / W, (cv0 + cs * (n - b) / n) / H};
            return mb.wedge(v, mat, uv, p);
        };
        for (int b = 0; b < n; ++b)
            for (int a = 0; a < n; ++a) {
                uint32_t w0 = corner(a, b), w1 = corner(a + 1, b), w2 = corner(a + 1, b + 1), w3 = corner(a, b + 1);
                mb.triangle(mat, {w0, w1, w2});
                mb.triangle(mat, {w0, w2, w3});
            }
    }
    asset.mesh = mb.take();
    return asset;
}

// --- pbrscene: every material channel, with a ground truth for normal maps -------------------

// An RGB tangent-space normal map (glTF: +X along u, +Y up the image) of the height field
// h(x, y) (texel units in, texel units out; y down); `gain` scales the slopes.
std::vector<uint8_t> normalMapOf(int S, double gain, const std::function<double(double, double)>& h) {
    std::vector<uint8_t> px(size_t(S) * S * 3);
    for (int y = 0; y < S; ++y)
        for (int x = 0; x < S; ++x) {
            const double cx = x + 0.5, cy = y + 0.5, e = 0.5;
            const double dx = (h(cx + e, cy) - h(cx - e, cy)) / (2 * e), dy = (h(cx, cy + e) - h(cx, cy - e)) / (2 * e);
            const Vec3 n = normalize(Vec3{-gain * dx, gain * dy, 1});  // up the image = -y
            uint8_t* p = &px[(size_t(y) * S + x) * 3];
            p[0] = uint8_t(std::lround((n.x * 0.5 + 0.5) * 255));
            p[1] = uint8_t(std::lround((n.y * 0.5 + 0.5) * 255));
            p[2] = uint8_t(std::lround((n.z * 0.5 + 0.5) * 255));
        }
    return px;
}

int addImage(Asset& asset, Image image) {
    asset.images.push_back(std::move(image));
    asset.textures.push_back(Texture{int(asset.images.size()) - 1, 0});
    return int(asset.textures.size()) - 1;
}

// A dome with all five maps (base colour, metallic-roughness, occlusion on TEXCOORD_1, emissive,
// normal) standing on a flat plate whose bumps exist only in its normal map, in front of an
// alpha-masked, double-sided lattice panel.
Asset makePbrScene(double scale) {
    Asset asset = newAsset("pbrscene");
    const int S = 256;
    // Dome material: every channel varies.
    Material body;
    body.name = "body";
    {
        std::vector<uint8_t> px(size_t(S) * S * 3);
        for (int c = 0; c < 4; ++c) drawCell(px, S, (c % 2) * S / 2, (c / 2) * S / 2, S / 2, S / 2, c * 3, c + 2);
        body.baseColor.texture = addImage(asset, encodePng(px, S, S, "body_baseColor"));
        for (int y = 0; y < S; ++y)
            for (int x = 0; x < S; ++x) {
                uint8_t* p = &px[(size_t(y) * S + x) * 3];
                const bool metal = (x * 8 / S) % 2 == 1;
                p[0] = 0;
                p[1] = uint8_t(std::lround(255 * (0.15 + 0.75 * y / double(S))));  // roughness
                p[2] = metal ? 255 : 0;                                            // metallic
            }
        body.metallicRoughness.texture = addImage(asset, encodePng(px, S, S, "body_metallicRoughness"));
        for (int y = 0; y < S; ++y)
            for (int x = 0; x < S; ++x) {
                const double d = std::fabs(std::fmod(y + 0.5, S / 4.0) - S / 8.0) / (S / 8.0);  // 1 at band centres
                const uint8_t o = uint8_t(std::lround(255 * (0.35 + 0.65 * std::min(1.0, d * 1.6))));
                uint8_t* p = &px[(size_t(y) * S + x) * 3];
                p[0] = p[1] = p[2] = o;
            }
        body.occlusion.texture = addImage(asset, encodePng(px, S, S, "body_occlusion"));
        body.occlusion.texCoord = 1;
        for (int y = 0; y < S; ++y)
            for (int x = 0; x < S; ++x) {
                const double u = (x + 0.5) / S, v = (y + 0.5) / S;
                const bool lit = std::hypot(std::fmod(u * 6, 1.0) - 0.5, std::fmod(v * 4, 1.0) - 0.5) < 0.18;
                uint8_t* p = &px[(size_t(y) * S + x) * 3];
                p[0] = lit ? 255 : 0;
                p[1] = lit ? 170 : 0;
                p[2] = lit ? 60 : 0;
            }
        body.emissive.texture = addImage(asset, encodePng(px, S, S, "body_emissive"));
        body.emissiveFactor = {1, 1, 1};
        const auto grooves = [&](double x, double) { return 2.0 * std::sin(2 * kPi * x * 12 / S); };  // across u
        body.normal.texture = addImage(asset, encodePng(normalMapOf(S, 1.0, grooves), S, S, "body_normal"));
    }
    // Plate material: flat geometry, bumps only in the normal map.
    Material plate;
    plate.name = "bumps";
    plate.metallicFactor = 0;
    plate.roughnessFactor = 0.45;
    {
        std::vector<uint8_t> px(size_t(S) * S * 3);
        for (int y = 0; y < S; ++y)
            for (int x = 0; x < S; ++x) {
                const bool check = ((x * 4 / S) + (y * 4 / S)) % 2 == 0;
                uint8_t* p = &px[(size_t(y) * S + x) * 3];
                p[0] = check ? 200 : 150;
                p[1] = check ? 190 : 140;
                p[2] = check ? 170 : 120;
            }
        plate.baseColor.texture = addImage(asset, encodePng(px, S, S, "bumps_baseColor"));
        const double cell = S / 8.0, radius = 0.38 * cell;
        const auto bumps = [&](double x, double y) {  // hemispherical bumps
            const double dx = std::fmod(x, cell) - cell / 2, dy = std::fmod(y, cell) - cell / 2;
            const double r2 = radius * radius - dx * dx - dy * dy;
            return r2 > 0 ? std::sqrt(r2) : 0.0;
        };
        plate.normal.texture = addImage(asset, encodePng(normalMapOf(S, 1.0, bumps), S, S, "bumps_normal"));
    }
    // Panel material: alpha-masked holes, double-sided.
    Material panel;
    panel.name = "lattice";
    panel.metallicFactor = 0;
    panel.roughnessFactor = 0.7;
    panel.alphaMode = AlphaMode::Mask;
    panel.alphaCutoff = 0.5;
    panel.doubleSided = true;
    {
        std::vector<uint8_t> px(size_t(S) * S * 4);
        for (int y = 0; y < S; ++y)
            for (int x = 0; x < S; ++x) {
                const double u = std::fmod((x + 0.5) / S * 6, 1.0) - 0.5, v = std::fmod((y + 0.5) / S * 5, 1.0) - 0.5;
                const Rgb c = palette(1 + (x * 6 / S) % 3);
                uint8_t* p = &px[(size_t(y) * S + x) * 4];
                p[0] = c.r;
                p[1] = c.g;
                p[2] = c.b;
                p[3] = std::hypot(u, v) < 0.33 ? 0 : 255;
            }
        panel.baseColor.texture = addImage(asset, encodePng(px, S, S, "lattice_baseColor", 4));
    }
    asset.materials = {body, plate, panel};

    MeshBuilder mb;
    // Dome: radius 0.6 on the plate, latitude rings from the equator to the pole.
    const int nLat = scaled(40, scale, 2), nLon = scaled(64, scale, 1), i0 = nLat / 2, rings = nLat - i0;
    for (int i = i0; i < nLat; ++i)
        for (int j = 0; j < nLon; ++j) {
            auto corner = [&](int ii, int jj) {
                const Vec3 n = spherePoint(ii, nLat, jj, nLon);
                const uint32_t v = mb.vertex(sphereKey(ii, nLat, jj, nLon), n * 0.6);
                double u = double(jj) / nLon;
                if (ii == nLat) u = (j + 0.5) / nLon;
                return mb.wedge(v, 0, {u, 1.0 - double(ii - i0) / rings}, n);
            };
            const uint32_t a = corner(i, j), b = corner(i, j + 1), c = corner(i + 1, j + 1), d = corner(i + 1, j);
            mb.triangle(0, {a, b, c});
            mb.triangle(0, {a, c, d});
        }
    // Plate: y = 0, x and z in [-1, 1], facing up; u along +x, v along +z.
    const int np = scaled(48, scale, 1);
    for (int i = 0; i < np; ++i)
        for (int j = 0; j < np; ++j) {
            auto corner = [&](int ii, int jj) {
                const double x = -1 + 2.0 * jj / np, z = -1 + 2.0 * ii / np;
                const uint32_t v = mb.vertex({ii, jj, 1 << 20}, {x, 0, z});
                return mb.wedge(v, 1, {double(jj) / np, double(ii) / np}, {0, 1, 0});
            };
            const uint32_t a = corner(i, j), b = corner(i, j + 1), c = corner(i + 1, j + 1), d = corner(i + 1, j);
            mb.triangle(1, {a, c, b});
            mb.triangle(1, {a, d, c});
        }
    // Panel: z = -1, x in [-1, 1], y in [0, 1.2], facing +z.
    const int nx = scaled(16, scale, 1), ny = scaled(12, scale, 1);
    for (int i = 0; i < ny; ++i)
        for (int j = 0; j < nx; ++j) {
            auto corner = [&](int ii, int jj) {
                const double x = -1 + 2.0 * jj / nx, y = 1.2 * ii / ny;
                const uint32_t v = mb.vertex({ii, jj, 2 << 20}, {x, y, -1.02});
                return mb.wedge(v, 2, {double(jj) / nx, 1.0 - double(ii) / ny}, {0, 0, 1});
            };
            const uint32_t a = corner(i, j), b = corner(i, j + 1), c = corner(i + 1, j + 1), d = corner(i + 1, j);
            mb.triangle(2, {a, b, c});
            mb.triangle(2, {a, c, d});
        }
    asset.mesh = mb.take();
    asset.mesh.wedges.uv1 = asset.mesh.wedges.uv0;  // the body's occlusion reads TEXCOORD_1
    asset.mesh.wedges.tangent = computeWedgeTangents(asset.mesh, asset.mesh.wedges.uv0);
    return asset;
}

// A rig node at translation t from its parent (-1 = a root).
RigNode rigNode(const std::string& name, int parent, Vec3 t) {
    RigNode n;
    n.name = name;
    n.parent = parent;
    n.translation = t;
    return n;
}

// Every node of the rig becomes a joint, bound in the nodes' current pose.
void bindEveryNode(Rig& rig) {
    const std::vector<Mat4> bind = poseNodes(rig, -1, 0);
    for (size_t j = 0; j < rig.nodes.size(); ++j) {
        Mat4 inv;
        invertAffine(bind[j], inv);
        rig.joints.push_back(int(j));
        rig.inverseBind.push_back(inv);
    }
}

// --- walker: a skinned sample with a walking-style animation -----------------------------------

// A closed cylinder (side + two caps) of radius r around the vertical axis through (cx, cz), from
// y0 to y1: `seg` segments around, `rings` along; part = a key prefix so parts never weld.
void addCylinder(MeshBuilder& mb, int mat, int64_t part, Vec3 centre, double r, double y0, double y1, int seg, int rings, Vec2 uvMin, Vec2 uvMax) {
    auto side = [&](int ring, int j) {
        const double phi = 2 * kPi * (j % seg) / seg, y = y0 + (y1 - y0) * ring / rings;
        Vec3 n{std::cos(phi), 0, -std::sin(phi)};
        uint32_t v = mb.vertex({part, ring, j % seg}, Vec3{centre.x + r * n.x, y, centre.z + r * n.z});
        Vec2 uv{uvMin.x + (uvMax.x - uvMin.x) * j / seg, uvMax.y - (uvMax.y - uvMin.y) * ring / rings};
        return mb.wedge(v, mat, uv, n);
    };
    for (int ring = 0; ring < rings; ++ring)
        for (int j = 0; j < seg; ++j) {
            uint32_t a = side(ring, j), b = side(ring, j + 1), c = side(ring + 1, j + 1), d = side(ring + 1, j);
            mb.triangle(mat, {a, b, c});
            mb.triangle(mat, {a, c, d});
        }
    for (int top = 0; top < 2; ++top) {
        const double y = top ? y1 : y0;
        const Vec3 n{0, top ? 1.0 : -1.0, 0};
        const Vec2 mid{0.5 * (uvMin.x + uvMax.x), 0.5 * (uvMin.y + uvMax.y)};
        uint32_t c = mb.wedge(mb.vertex({part, top ? rings + 1 : -1, 0}, Vec3{centre.x, y, centre.z}), mat, mid, n);
        auto rim = [&](int j) {
            const double phi = 2 * kPi * (j % seg) / seg;
            uint32_t v = mb.vertex({part, top ? rings : 0, j % seg}, Vec3{centre.x + r * std::cos(phi), y, centre.z - r * std::sin(phi)});
            return mb.wedge(v, mat, Vec2{mid.x + 0.2 * std::cos(phi) * (uvMax.x - uvMin.x), mid.y + 0.2 * std::sin(phi) * (uvMax.y - uvMin.y)}, n);
        };
        for (int j = 0; j < seg; ++j) {
            if (top) mb.triangle(mat, {c, rim(j), rim(j + 1)});
            else mb.triangle(mat, {c, rim(j + 1), rim(j)});
        }
    }
}

Asset makeWalker(double scale) {
    Asset asset = newAsset("walker");
    const int C = 128, W = 2 * C, H = C;
    std::vector<uint8_t> px(static_cast<size_t>(W) * H * 3);
    for (int f = 0; f < 2; ++f) drawCell(px, W, f * C, 0, C, C, f * 3 + 1, f + 1);
    int mat = addTexturedMaterial(asset, "walker", encodePng(px, W, H, "walker"));
    const double hipY = 1.0, legX = 0.18, blend = 0.15;
    MeshBuilder mb;
    const int seg = scaled(32, scale, 4), rings = scaled(16, scale, 2);
    addCylinder(mb, mat, 0, Vec3{0, 0, 0}, 0.35, hipY, 1.8, seg, rings, Vec2{0, 0}, Vec2{0.5, 1});
    const size_t torsoVertices = mb.vertexCount();
    addCylinder(mb, mat, 1, Vec3{-legX, 0, 0}, 0.12, 0.0, hipY + 0.05, seg * 3 / 4, rings * 5 / 4, Vec2{0.5, 0}, Vec2{1, 1});
    addCylinder(mb, mat, 2, Vec3{legX, 0, 0}, 0.12, 0.0, hipY + 0.05, seg * 3 / 4, rings * 5 / 4, Vec2{0.5, 0}, Vec2{1, 1});
    asset.mesh = mb.take();

    // Joints: 0 hips (at the hip height), 1 left leg, 2 right leg (at the hip joints).
    Rig& rig = asset.rig;
    rig.nodes = {rigNode("hips", -1, {0, hipY, 0}), rigNode("leftLeg", 0, {-legX, 0, 0}), rigNode("rightLeg", 0, {legX, 0, 0})};
    bindEveryNode(rig);
    // Each leg belongs to its joint, blended into the hips over its top `blend`.
    Wedges& Wd = asset.mesh.wedges;
    for (size_t w = 0; w < Wd.size(); ++w) {
        const uint32_t v = Wd.vertex[w];
        const Vec3& p = asset.mesh.positions[v];
        if (v < torsoVertices) {
            Wd.joints.push_back({0, 0, 0, 0});
            Wd.weights.push_back({1, 0, 0, 0});
            continue;
        }
        const uint16_t leg = p.x < 0 ? 1 : 2;
        const double toHips = std::clamp((p.y - (hipY - blend)) / (2 * blend), 0.0, 0.5);
        Wd.joints.push_back({leg, 0, 0, 0});
        Wd.weights.push_back({1 - toHips, toHips, 0, 0});
    }
    // The walk: legs swing +-30 degrees about x in opposition, one-second loop, 9 linear keys.
    Animation walk;
    walk.name = "walk";
    for (int leg = 0; leg < 2; ++leg) {
        AnimationSampler s;
        s.comps = 4;
        for (int k = 0; k <= 8; ++k) {
            const double t = k / 8.0, angle = (leg ? -1 : 1) * (kPi / 6) * std::cos(2 * kPi * t);
            s.times.push_back(t);
            s.values.insert(s.values.end(), {std::sin(angle / 2), 0.0, 0.0, std::cos(angle / 2)});
        }
        walk.samplers.push_back(s);
        walk.channels.push_back(AnimationChannel{leg, leg + 1, AnimationPath::Rotation});
    }
    rig.animations.push_back(walk);
    return asset;
}

// --- critter: a low-poly rigged quadruped (the shape of a game character's LOD0) ---------------

// A tapered tube from `a` to `b` (radius ra at a, rb at b; 0 = a cone's tip): `seg` segments
// around, `rings` along, a flat cap at each end of non-zero radius; part = a key prefix so parts
// never weld. uv = (around, along) mapped into [uvMin, uvMax]. Returns the part's first vertex.
size_t addTube(MeshBuilder& mb, int mat, int64_t part, Vec3 a, Vec3 b, double ra, double rb, int seg, int rings,
               Vec2 uvMin, Vec2 uvMax) {
    const size_t first = mb.vertexCount();
    const Vec3 axis = normalize(b - a);
    const Vec3 side = normalize(cross(std::fabs(axis.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0}, axis));
    const Vec3 up = cross(axis, side);
    // A ring of zero radius is one vertex (the tip), keyed by its ring alone.
    auto radius = [&](int ring) { return ra + (rb - ra) * ring / rings; };
    auto point = [&](int ring, int j) {
        const double r = radius(ring), phi = 2 * kPi * (j % seg) / seg;
        const Vec3 n = side * std::cos(phi) + up * std::sin(phi);
        const Vec3 centre = a + (b - a) * (double(ring) / rings);
        return std::make_pair(mb.vertex({part, ring, r > 0 ? j % seg : 0}, centre + n * r), n);
    };
    auto sideWedge = [&](int ring, int j) {
        auto [v, n] = point(ring, j);
        const Vec2 uv{uvMin.x + (uvMax.x - uvMin.x) * j / seg, uvMax.y - (uvMax.y - uvMin.y) * ring / rings};
        return mb.wedge(v, mat, uv, n);
    };
    for (int ring = 0; ring < rings; ++ring)
        for (int j = 0; j < seg; ++j) {
            const uint32_t p = sideWedge(ring, j), q = sideWedge(ring, j + 1), r = sideWedge(ring + 1, j + 1), s = sideWedge(ring + 1, j);
            mb.triangle(mat, {p, q, r});  // counter-clockwise seen from outside: (side, up, axis) is right-handed
            mb.triangle(mat, {p, r, s});
        }
    for (int end = 0; end < 2; ++end) {
        const int ring = end ? rings : 0;
        if (!(radius(ring) > 0)) continue;
        const Vec3 n = end ? axis : axis * -1.0;
        const Vec2 mid{0.5 * (uvMin.x + uvMax.x), 0.5 * (uvMin.y + uvMax.y)};
        const uint32_t c = mb.wedge(mb.vertex({part, end ? rings + 1 : -1, 0}, end ? b : a), mat, mid, n);
        auto rim = [&](int j) {
            const double phi = 2 * kPi * (j % seg) / seg;
            const Vec2 uv{mid.x + 0.4 * std::cos(phi) * (uvMax.x - uvMin.x), mid.y + 0.4 * std::sin(phi) * (uvMax.y - uvMin.y)};
            return mb.wedge(point(ring, j).first, mat, uv, n);
        };
        for (int j = 0; j < seg; ++j) {
            if (end) mb.triangle(mat, {c, rim(j), rim(j + 1)});
            else mb.triangle(mat, {c, rim(j + 1), rim(j)});
        }
    }
    return first;
}

// A quaternion (x, y, z, w) turning by `angle` radians about the unit axis (x, y, z).
Vec4 axisAngle(Vec3 axis, double angle) {
    const double s = std::sin(angle / 2);
    return {axis.x * s, axis.y * s, axis.z * s, std::cos(angle / 2)};
}

// The rotation b, then a (Hamilton product a b).
Vec4 quatMul(Vec4 a, Vec4 b) {
    return {a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y, a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
            a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w, a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
}

Asset makeCritter(double scale) {
    Asset asset = newAsset("critter");
    // Four cells of distinct colours (body, head, legs, ears and tail): a level whose atlas lost
    // the texture shows one flat colour instead.
    const int C = 64, W = 2 * C, H = 2 * C;
    std::vector<uint8_t> px(static_cast<size_t>(W) * H * 3);
    const int colour[4] = {0, 3, 6, 4};  // palette: red, yellow, orange, purple
    for (int cell = 0; cell < 4; ++cell) drawCell(px, W, (cell % 2) * C, (cell / 2) * C, C, C, colour[cell], cell + 1);
    const int mat = addTexturedMaterial(asset, "critter", encodePng(px, W, H, "critter"));
    const Vec2 cellMin[4] = {{0, 0}, {0.5, 0}, {0, 0.5}, {0.5, 0.5}};
    auto cellMax = [&](int c) { return cellMin[c] + Vec2{0.5, 0.5}; };

    // Joints (bind pose): 0 body, 1 head, 2 tail, 3 + 2k upper leg k, 4 + 2k lower leg k (k = front
    // left, front right, hind left, hind right).
    const Vec3 body{0, 0.55, 0}, neck{0, 0.62, 0.36}, tailBase{0, 0.6, -0.42};
    const double legX = 0.12, hipY = 0.5, kneeY = 0.26, frontZ = 0.24, hindZ = -0.28;
    const Vec3 hips[4] = {{-legX, hipY, frontZ}, {legX, hipY, frontZ}, {-legX, hipY, hindZ}, {legX, hipY, hindZ}};

    MeshBuilder mb;
    const int seg = scaled(8, scale, 2), thin = scaled(6, scale, 2), rings = scaled(4, scale, 1);
    struct Part {
        size_t first;    // first vertex
        Vec3 a, b;       // axis: t = 0 at a, 1 at b
        int joint;       // the joint at b's side (t = 1)
        int base;        // the joint it blends into towards a (t = 0), -1 = none
        double blend;    // t below which it blends into `base` (half and half at t = 0)
        int knee = -1;   // a leg's lower joint, taking over around t = 0.5
    };
    std::vector<Part> parts;
    auto add = [&](Part p, double ra, double rb, int s, int r, int cell) {
        p.first = addTube(mb, mat, int64_t(parts.size()), p.a, p.b, ra, rb, s, r, cellMin[cell], cellMax(cell));
        parts.push_back(p);
    };
    add({0, tailBase + Vec3{0, -0.04, 0.02}, neck + Vec3{0, -0.02, 0.06}, 0, -1, 0}, 0.17, 0.15, seg, rings, 0);
    add({0, neck + Vec3{0, 0, -0.05}, neck + Vec3{0, 0.1, 0.34}, 1, 0, 0.35}, 0.13, 0.035, seg, rings - 1, 1);
    for (int side = 0; side < 2; ++side) {  // ears: thin cones on the head
        const double x = side ? 0.06 : -0.06;
        add({0, neck + Vec3{x, 0.1, 0.1}, neck + Vec3{1.6 * x, 0.3, 0.06}, 1, -1, 0}, 0.035, 0, 4, 2, 3);
    }
    add({0, tailBase + Vec3{0, 0, 0.05}, tailBase + Vec3{0, 0.12, -0.4}, 2, 0, 0.3}, 0.06, 0, thin, rings - 1, 3);
    for (int k = 0; k < 4; ++k) {
        Part leg{0, hips[k] + Vec3{0, 0.05, 0}, Vec3{hips[k].x, 0.0, hips[k].z}, 3 + 2 * k, 0, 0.2};
        leg.knee = 4 + 2 * k;
        add(leg, 0.05, 0.03, thin, rings, 2);
    }
    asset.mesh = mb.take();

    Rig& rig = asset.rig;
    rig.nodes = {rigNode("body", -1, body), rigNode("head", 0, neck - body), rigNode("tail", 0, tailBase - body)};
    const char* legName[4] = {"frontLeft", "frontRight", "hindLeft", "hindRight"};
    for (int k = 0; k < 4; ++k) {
        rig.nodes.push_back(rigNode(std::string(legName[k]) + "Upper", 0, hips[k] - body));
        rig.nodes.push_back(rigNode(std::string(legName[k]) + "Lower", int(rig.nodes.size()) - 1, Vec3{0, kneeY - hipY, 0}));
    }
    bindEveryNode(rig);
    // The rest pose is not the bind pose (as in many exported characters): the head looks down a
    // little and the tail hangs lower.
    rig.nodes[1].rotation = axisAngle({1, 0, 0}, 0.2);
    rig.nodes[2].rotation = axisAngle({1, 0, 0}, -0.35);

    // Influences blend smoothly, as a painted rig's do: each part's joint fades into its base
    // joint towards the part's root, and a leg's upper joint into its lower one around the knee,
    // so most vertices carry their own weights.
    Wedges& Wd = asset.mesh.wedges;
    std::vector<std::array<uint16_t, 4>> vJoints(asset.mesh.positions.size());
    std::vector<Vec4> vWeights(asset.mesh.positions.size());
    for (size_t i = 0; i < parts.size(); ++i) {
        const Part& p = parts[i];
        const size_t end = i + 1 < parts.size() ? parts[i + 1].first : asset.mesh.positions.size();
        const Vec3 axis = p.b - p.a;
        for (size_t v = p.first; v < end; ++v) {
            const double t = std::clamp(dot(asset.mesh.positions[v] - p.a, axis) / dot(axis, axis), 0.0, 1.0);
            double own = 1, base = 0;
            if (p.base >= 0 && t < p.blend) base = 0.5 * (1 - t / p.blend), own = 1 - base;
            std::array<uint16_t, 4> j{uint16_t(p.joint), uint16_t(p.base >= 0 ? p.base : 0), 0, 0};
            Vec4 w{own, base, 0, 0};
            if (p.knee >= 0) {  // upper over t < 0.35, lower over t > 0.65, linear between
                const double lower = std::clamp((t - 0.35) / 0.3, 0.0, 1.0);
                j = {uint16_t(p.joint), uint16_t(p.knee), uint16_t(p.base), 0};
                w = {own * (1 - lower), own * lower, base, 0};
            }
            vJoints[v] = j;
            vWeights[v] = w;
        }
    }
    for (size_t w = 0; w < Wd.size(); ++w) {
        Wd.joints.push_back(vJoints[Wd.vertex[w]]);
        Wd.weights.push_back(vWeights[Wd.vertex[w]]);
    }

    // The trot: one second, 9 linear keys; diagonal legs swing together (+-25 degrees at the hip,
    // the knee bending up to 40 degrees on the forward swing), the tail wags, the head nods.
    Animation trot;
    trot.name = "trot";
    auto channel = [&](int nodeIndex, const std::function<Vec4(double)>& rotation) {
        AnimationSampler s;
        s.comps = 4;
        for (int k = 0; k <= 8; ++k) {
            const double t = k / 8.0;
            const Vec4 q = rotation(t);
            s.times.push_back(t);
            s.values.insert(s.values.end(), {q.x, q.y, q.z, q.w});
        }
        trot.samplers.push_back(s);
        trot.channels.push_back(AnimationChannel{int(trot.samplers.size()) - 1, nodeIndex, AnimationPath::Rotation});
    };
    for (int k = 0; k < 4; ++k) {
        const double phase = (k == 0 || k == 3) ? 0 : kPi;
        channel(3 + 2 * k, [&](double t) { return axisAngle({1, 0, 0}, 0.44 * std::sin(2 * kPi * t + phase)); });
        channel(4 + 2 * k, [&](double t) { return axisAngle({1, 0, 0}, -0.35 * (1 + std::cos(2 * kPi * t + phase))); });
    }
    channel(2, [&](double t) { return quatMul(axisAngle({0, 1, 0}, 0.5 * std::sin(2 * kPi * t)), axisAngle({1, 0, 0}, -0.35)); });
    channel(1, [&](double t) { return axisAngle({1, 0, 0}, 0.2 + 0.15 * std::sin(4 * kPi * t)); });
    rig.animations.push_back(trot);
    return asset;
}

// --- drum: a large open backdrop around many small detailed parts ---------------------------

// A closed UV sphere of radius r at `centre`: nLat rings from pole to pole, nLon segments; part = a
// key prefix so parts never weld. uv = (longitude, latitude) mapped into [uvMin, uvMax].
void addSphere(MeshBuilder& mb, int mat, int64_t part, Vec3 centre, double r, int nLat, int nLon, Vec2 uvMin, Vec2 uvMax) {
    for (int i = 0; i < nLat; ++i)
        for (int j = 0; j < nLon; ++j) {
            auto corner = [&](int ii, int jj) {
                const Vec3 n = spherePoint(ii, nLat, jj, nLon);
                const MeshBuilder::Key k = sphereKey(ii, nLat, jj, nLon);
                uint32_t v = mb.vertex({part, std::get<0>(k) * 100000 + std::get<1>(k), -1}, centre + n * r);
                double u = double(jj) / nLon;
                if (ii == 0 || ii == nLat) u = (j + 0.5) / nLon;
                const double t = double(ii) / nLat;
                return mb.wedge(v, mat, Vec2{uvMin.x + (uvMax.x - uvMin.x) * u, uvMax.y - (uvMax.y - uvMin.y) * t}, n);
            };
            uint32_t a = corner(i, j), b = corner(i, j + 1), c = corner(i + 1, j + 1), d = corner(i + 1, j);
            mb.triangle(mat, {a, b, c});
            mb.triangle(mat, {a, c, d});
        }
}

// A "tree" of two crossed vertical sheets (a classic billboard cross) standing on `base`: each
// sheet is cols x rows quads, width w, height h; the sheets share their middle column of vertices,
// so the spine's edges each have four faces (non-manifold: those vertices never move).
void addCrossedSheets(MeshBuilder& mb, int mat, int64_t part, Vec3 base, double w, double h, int cols, int rows, Vec2 uvMin, Vec2 uvMax) {
    for (int sheet = 0; sheet < 2; ++sheet) {
        const Vec3 axis = sheet ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
        const Vec3 n = sheet ? Vec3{1, 0, 0} : Vec3{0, 0, -1};
        auto corner = [&](int i, int j) {
            const bool spine = 2 * j == cols;
            const Vec3 p = base + axis * (w * (double(j) / cols - 0.5)) + Vec3{0, h * i / rows, 0};
            uint32_t v = mb.vertex({part, i, spine ? -1 : sheet * 1000 + j}, p);
            return mb.wedge(v, mat, Vec2{uvMin.x + (uvMax.x - uvMin.x) * j / cols, uvMax.y - (uvMax.y - uvMin.y) * i / rows}, n);
        };
        for (int i = 0; i < rows; ++i)
            for (int j = 0; j < cols; ++j) {
                uint32_t a = corner(i, j), b = corner(i, j + 1), c = corner(i + 1, j + 1), d = corner(i + 1, j);
                mb.triangle(mat, {a, b, c});
                mb.triangle(mat, {a, c, d});
            }
    }
}

// drum: a diorama whose outer geometry is a large open backdrop: a double-sided textured cylinder
// (radius 4, height 3, facing inwards) on a floor disk welded to its bottom rim, around 21 small
// detailed parts (7 spheres, 7 capped cylinders, 7 crossed-sheet trees whose spines are
// non-manifold) standing on the floor. Most triangles belong to the small parts, most of the
// silhouette and surface to the drum: a coarse level must spend its budget where it shows.
Asset makeDrum(double scale) {
    Asset asset = newAsset("drum");
    const int C = 128;
    std::vector<uint8_t> px(size_t(4 * C) * C * 3);
    for (int c = 0; c < 4; ++c) drawCell(px, 4 * C, c * C, 0, C, C, c * 2 + 1, c + 1);
    const int drumMat = addTexturedMaterial(asset, "backdrop", encodePng(px, 4 * C, C, "backdrop"));
    asset.materials[size_t(drumMat)].doubleSided = true;
    std::vector<uint8_t> ground(size_t(C) * C * 3);
    drawCell(ground, C, 0, 0, C, C, 9, 0);
    const int floorMat = addTexturedMaterial(asset, "floor", encodePng(ground, C, C, "floor"));
    std::vector<uint8_t> parts(size_t(2 * C) * C * 3);
    for (int c = 0; c < 2; ++c) drawCell(parts, 2 * C, c * C, 0, C, C, c * 5 + 2, c + 5);
    const int partMat = addTexturedMaterial(asset, "parts", encodePng(parts, 2 * C, C, "parts"));
    MeshBuilder mb;
    // The drum: seg x rings quads, wound to face the axis; ring 0 is also the floor's rim.
    const double R = 4, height = 3;
    const int seg = scaled(64, scale, 4), rings = scaled(8, scale, 1), floorRings = scaled(4, scale, 1);
    auto rimVertex = [&](int ring, int j) {
        const double phi = 2 * kPi * (j % seg) / seg;
        return mb.vertex({-1, ring, j % seg}, Vec3{R * std::cos(phi), height * ring / rings, -R * std::sin(phi)});
    };
    auto drum = [&](int ring, int j) {
        const double phi = 2 * kPi * (j % seg) / seg;
        return mb.wedge(rimVertex(ring, j), drumMat, Vec2{double(j) / seg, 1.0 - double(ring) / rings},
                        Vec3{-std::cos(phi), 0, std::sin(phi)});
    };
    for (int ring = 0; ring < rings; ++ring)
        for (int j = 0; j < seg; ++j) {
            uint32_t a = drum(ring, j), b = drum(ring, j + 1), c = drum(ring + 1, j + 1), d = drum(ring + 1, j);
            mb.triangle(drumMat, {a, c, b});
            mb.triangle(drumMat, {a, d, c});
        }
    // The floor: floorRings concentric rings from the centre (k = 0) to the rim (k = floorRings).
    auto floor = [&](int k, int j) {
        const double phi = 2 * kPi * (j % seg) / seg, r = R * k / floorRings;
        uint32_t v = k == floorRings ? rimVertex(0, j)
                     : k == 0        ? mb.vertex({-2, 0, 0}, Vec3{0, 0, 0})
                                     : mb.vertex({-2, k, j % seg}, Vec3{r * std::cos(phi), 0, -r * std::sin(phi)});
        return mb.wedge(v, floorMat, Vec2{0.5 + 0.5 * r / R * std::cos(phi), 0.5 + 0.5 * r / R * std::sin(phi)},
                        Vec3{0, 1, 0});
    };
    for (int k = 0; k < floorRings; ++k)
        for (int j = 0; j < seg; ++j) {
            uint32_t a = floor(k, j), b = floor(k, j + 1), c = floor(k + 1, j + 1), d = floor(k + 1, j);
            mb.triangle(floorMat, {a, c, b});
            mb.triangle(floorMat, {a, d, c});
        }
    // The parts: a circle of 14 at radius 2.4 and 7 at radius 1.2; sphere, cylinder, tree in turn.
    const int nLat = scaled(12, scale, 2), nLon = scaled(16, scale, 4);
    int part = 0;
    for (int circle = 0; circle < 2; ++circle) {
        const int count = circle ? 7 : 14;
        const double radius = circle ? 1.2 : 2.4;
        for (int k = 0; k < count; ++k, ++part) {
            const double phi = 2 * kPi * (k + 0.5 * circle) / count;
            const Vec3 at{radius * std::cos(phi), 0, -radius * std::sin(phi)};
            const Vec2 uv0{0.5 * (part % 2), 0}, uv1{0.5 * (part % 2) + 0.5, 1};
            if (part % 3 == 0)
                addSphere(mb, partMat, part, at + Vec3{0, 0.25, 0}, 0.25, nLat, nLon, uv0, uv1);
            else if (part % 3 == 1)
                addCylinder(mb, partMat, part, at, 0.18, 0.0, 0.6, nLon, nLat - 2, uv0, uv1);
            else
                addCrossedSheets(mb, partMat, part, at, 0.5, 0.5, nLon / 2, nLat - 2, uv0, uv1);
        }
    }
    asset.mesh = mb.take();
    return asset;
}

// --- materials: KHR_materials_* extensions with a known look ------------------------------

// An RGB image S x S whose texel (x, y) is colour(u, v) with u, v in [0,1] at texel centres.
Image imageOf(int S, const std::string& name, const std::function<Rgb(double, double)>& colour) {
    std::vector<uint8_t> px(size_t(S) * S * 3);
    for (int y = 0; y < S; ++y)
        for (int x = 0; x < S; ++x) {
            const Rgb c = colour((x + 0.5) / S, (y + 0.5) / S);
            uint8_t* p = &px[(size_t(y) * S + x) * 3];
            p[0] = c.r;
            p[1] = c.g;
            p[2] = c.b;
        }
    return encodePng(px, S, S, name);
}

// A material with base colour, metallic and roughness factors only.
Material plainMaterial(const char* name, Vec4 baseColor, double metallic, double roughness) {
    Material m;
    m.name = name;
    m.baseColorFactor = baseColor;
    m.metallicFactor = metallic;
    m.roughnessFactor = roughness;
    return m;
}

// materials: four spheres in a row on a textured floor, each showing one extension whose look
// is unmistakable: velvet cloth (dark base colour, sheen colour striped by a texture), car paint
// (red base under a clearcoat whose strength is banded by a texture), glass (transmission 1, a
// thickness and a green attenuation, ior 1.5) and a dielectric whose specular colour comes from a
// rainbow texture. The floor has no extension: its neutral values are part of the bake.
Asset makeMaterials(double scale) {
    Asset asset = newAsset("materials");
    const int S = 64;
    Material cloth = plainMaterial("cloth", {0.04, 0.02, 0.12, 1}, 0, 1);
    cloth.ext.sheen.present = true;
    cloth.ext.sheen.colorFactor = {1, 0.6, 0.8};
    cloth.ext.sheen.colorTexture.texture = addImage(asset, imageOf(S, "cloth_sheenColor", [](double u, double) {
        return int(u * 8) % 2 ? Rgb{255, 255, 255} : Rgb{255, 140, 60};
    }));
    cloth.ext.sheen.roughnessFactor = 0.5;
    Material paint = plainMaterial("paint", {0.55, 0.02, 0.03, 1}, 0.4, 0.6);
    paint.ext.clearcoat.present = true;
    paint.ext.clearcoat.factor = 1;
    paint.ext.clearcoat.texture.texture = addImage(asset, imageOf(S, "paint_clearcoat", [](double, double v) {
        const uint8_t c = int(v * 6) % 2 ? 255 : 64;
        return Rgb{c, c, c};
    }));
    paint.ext.clearcoat.roughnessFactor = 0.05;
    Material glass = plainMaterial("glass", {1, 1, 1, 1}, 0, 0.05);
    glass.ext.transmission.present = true;
    glass.ext.transmission.factor = 1;
    glass.ext.volume.present = true;
    glass.ext.volume.thicknessFactor = 0.8;
    glass.ext.volume.attenuationDistance = 0.5;
    glass.ext.volume.attenuationColor = {0.5, 0.9, 0.6};
    glass.ext.ior.present = true;
    glass.ext.ior.ior = 1.5;
    Material specular = plainMaterial("specular", {0.08, 0.08, 0.08, 1}, 0, 0.25);
    specular.ext.specular.present = true;
    specular.ext.specular.factor = 1;
    specular.ext.specular.colorTexture.texture = addImage(asset, imageOf(S, "specular_color", [](double u, double) {
        const double h = 6 * u;  // hue around the sphere
        auto ramp = [&](double c) { return uint8_t(std::lround(255 * std::clamp(std::fabs(std::fmod(h + c, 6.0) - 3) - 1, 0.0, 1.0))); };
        return Rgb{ramp(0), ramp(4), ramp(2)};
    }));
    std::vector<uint8_t> ground(size_t(2 * S) * 2 * S * 3);
    drawCell(ground, 2 * S, 0, 0, 2 * S, 2 * S, 7, 3);
    const int floorMat = addTexturedMaterial(asset, "floor", encodePng(ground, 2 * S, 2 * S, "floor"));
    const int mats[4] = {int(asset.materials.size()), int(asset.materials.size()) + 1, int(asset.materials.size()) + 2,
                         int(asset.materials.size()) + 3};
    for (Material* m : {&cloth, &paint, &glass, &specular}) asset.materials.push_back(*m);
    MeshBuilder mb;
    const int n = scaled(8, scale, 1);
    auto floor = [&](int i, int j) {
        const Vec3 p{-2.5 + 5.0 * i / n, 0, -1.5 + 3.0 * j / n};
        return mb.wedge(mb.vertex({-1, i, j}, p), floorMat, Vec2{double(i) / n, double(j) / n}, Vec3{0, 1, 0});
    };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            uint32_t a = floor(i, j), b = floor(i + 1, j), c = floor(i + 1, j + 1), d = floor(i, j + 1);
            mb.triangle(floorMat, {a, c, b});
            mb.triangle(floorMat, {a, d, c});
        }
    const int nLat = scaled(16, scale, 2), nLon = scaled(24, scale, 4);
    for (int k = 0; k < 4; ++k)
        addSphere(mb, mats[k], k, Vec3{-1.8 + 1.2 * k, 0.5, 0}, 0.5, nLat, nLon, Vec2{0, 0}, Vec2{1, 1});
    asset.mesh = mb.take();
    return asset;
}

// --- facets: a flat-shaded, low-poly gem (hard edges everywhere) ----------------------------

// A deterministic hash of an integer lattice key to [0, 1) (splitmix64's finaliser).
double hashUnit(const MeshBuilder::Key& key) {
    uint64_t h = 0x9e3779b97f4a7c15ull;
    for (int64_t k : {std::get<0>(key), std::get<1>(key), std::get<2>(key)}) {
        h ^= uint64_t(k) + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
        h = (h ^ (h >> 30)) * 0xbf58476d1ce4e5b9ull;
        h = (h ^ (h >> 27)) * 0x94d049bb133111ebull;
        h ^= h >> 31;
    }
    return double(h >> 11) / double(uint64_t(1) << 53);
}

// facets: a rock-like gem as a flat-shaded low-poly export writes it: a geodesic icosphere
// (frequency n, 20 n^2 triangles) pushed in and out by deterministic radial noise, every corner
// carrying its face's normal (split normals, so every edge is a hard edge), with continuous
// latitude-longitude UVs (a seam where longitude wraps) into a small banded texture: eight
// coloured strata along v, each with a checker tint along u.
Asset makeFacets(double scale) {
    Asset asset = newAsset("facets");
    const int S = 64;
    const int mat = addTexturedMaterial(asset, "facets", imageOf(S, "facets", [](double u, double v) {
        const int band = std::min(7, int(v * 8));
        const Rgb a = palette(band * 5);  // 0, 5, 10, 3, 8, 1, 6, 11: neighbouring bands differ
        if ((int(u * 8) + band) % 2 == 0) return a;
        return Rgb{uint8_t((a.r * 3 + 255) / 4), uint8_t((a.g * 3 + 255) / 4), uint8_t((a.b * 3 + 255) / 4)};
    }));
    asset.materials[mat].roughnessFactor = 0.4;  // glossier than the other samples: facets catch the light
    const double phi = (1 + std::sqrt(5.0)) / 2;
    const Vec3 ico[12] = {{-1, phi, 0}, {1, phi, 0}, {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi}, {0, 1, phi},
                          {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1}, {phi, 0, 1}, {-phi, 0, -1}, {-phi, 0, 1}};
    const int faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                              {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                              {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    const int n = scaled(6, scale, 1);
    MeshBuilder mb;
    // The lattice point with weights w over icosahedron corners c (sum n): keyed and summed in
    // corner order, so the copies on shared edges and corners are bit-identical and weld.
    auto vertex = [&](std::array<int, 3> c, std::array<int, 3> w) {
        std::array<std::pair<int, int>, 3> cw{{{c[0], w[0]}, {c[1], w[1]}, {c[2], w[2]}}};
        std::sort(cw.begin(), cw.end());
        std::array<int64_t, 3> key{-1, -1, -1};
        Vec3 p{0, 0, 0};
        int m = 0;
        for (auto [corner, weight] : cw)
            if (weight > 0) {
                key[m++] = int64_t(corner) * (n + 1) + weight;
                p += ico[corner] * double(weight);
            }
        const MeshBuilder::Key k{key[0], key[1], key[2]};
        const Vec3 d = normalize(p);
        // Low-frequency bumps plus a per-vertex jitter; y squashed a little, as a pebble.
        const double r = 1 + 0.12 * std::sin(2.1 * d.x + 1.3) * std::cos(1.7 * d.y - 0.4) +
                         0.08 * std::sin(3.3 * d.z + 2.2 * d.x) + 0.1 * (hashUnit(k) - 0.5);
        const Vec3 q = d * r;
        return mb.vertex(k, Vec3{q.x, 0.8 * q.y, q.z});
    };
    for (const auto& f : faces)
        for (int i = 0; i < n; ++i)
            for (int j = 0; i + j < n; ++j) {
                // (i, j): i steps towards f[1], j towards f[2]; up triangles, then the down one.
                std::vector<std::array<std::array<int, 2>, 3>> tris{{{{i, j}, {i + 1, j}, {i, j + 1}}}};
                if (i + j < n - 1) tris.push_back({{{i + 1, j}, {i + 1, j + 1}, {i, j + 1}}});
                for (const auto& t : tris) {
                    std::array<uint32_t, 3> v;
                    std::array<Vec3, 3> pos;
                    for (int c = 0; c < 3; ++c) {
                        v[c] = vertex({f[0], f[1], f[2]}, {n - t[c][0] - t[c][1], t[c][0], t[c][1]});
                        pos[c] = mb.position(v[c]);
                    }
                    const Vec3 normal = normalize(cross(pos[1] - pos[0], pos[2] - pos[0]));
                    // Longitude and latitude UVs; a face across the wrap takes u + 1 on its small
                    // side (the sampler repeats), a corner on the axis the mean u of the others.
                    std::array<Vec2, 3> uv;
                    std::array<bool, 3> onAxis{};
                    for (int c = 0; c < 3; ++c) {
                        const Vec3 d = normalize(pos[c]);
                        onAxis[c] = std::hypot(d.x, d.z) < 1e-9;
                        uv[c] = {onAxis[c] ? 0 : 0.5 + std::atan2(d.z, d.x) / (2 * kPi),
                                 0.5 - std::asin(std::clamp(d.y, -1.0, 1.0)) / kPi};
                    }
                    double uMax = 0;
                    for (int c = 0; c < 3; ++c)
                        if (!onAxis[c]) uMax = std::max(uMax, uv[c].x);
                    for (int c = 0; c < 3; ++c)
                        if (!onAxis[c] && uMax - uv[c].x > 0.5) uv[c].x += 1;
                    for (int c = 0; c < 3; ++c)
                        if (onAxis[c]) uv[c].x = 0.5 * (uv[(c + 1) % 3].x + uv[(c + 2) % 3].x);
                    mb.triangle(mat, {mb.wedge(v[0], mat, uv[0], normal), mb.wedge(v[1], mat, uv[1], normal),
                                      mb.wedge(v[2], mat, uv[2], normal)});
                }
            }
    asset.mesh = mb.take();
    return asset;
}

// variants: a ball (checkerboard texture) on a pedestal (grey), and KHR_materials_variants with a
// ground truth anyone can see: "red" paints the ball plain red; "blue" gives the ball a blue
// checkerboard and the pedestal the red; "gold" leaves the ball and makes the pedestal a rough
// gold metal; "classic" names the default look explicitly (both parts mapped to their own
// materials, as product files often do). Two primitives (ball, pedestal), five materials.
Asset makeVariants(double scale) {
    Asset asset = newAsset("variants");
    const int S = 64;
    std::vector<uint8_t> px(size_t(S) * S * 3);
    drawCell(px, S, 0, 0, S, S, 4, 5);
    const int ball = addTexturedMaterial(asset, "ball", encodePng(px, S, S, "ball"));
    const int pedestal = int(asset.materials.size());
    asset.materials.push_back(plainMaterial("pedestal", {0.35, 0.35, 0.35, 1}, 0, 0.7));
    const int red = int(asset.materials.size());
    asset.materials.push_back(plainMaterial("red", {0.8, 0.05, 0.04, 1}, 0, 0.5));
    const int blue = addImage(asset, imageOf(S, "ball_blue", [](double u, double v) {
        return (int(u * 8) + int(v * 8)) % 2 ? Rgb{30, 70, 220} : Rgb{220, 230, 255};
    }));
    asset.materials.push_back(plainMaterial("blue", {1, 1, 1, 1}, 0, 0.6));
    asset.materials.back().baseColor.texture = blue;
    const int blueMat = int(asset.materials.size()) - 1;
    const int gold = int(asset.materials.size());
    asset.materials.push_back(plainMaterial("gold", {1.0, 0.76, 0.33, 1}, 1, 0.45));
    MeshBuilder mb;
    const int nLat = scaled(20, scale, 2), nLon = scaled(30, scale, 2);
    addSphere(mb, ball, 0, Vec3{0, 1.1, 0}, 0.6, nLat, nLon, Vec2{0, 0}, Vec2{1, 1});
    const size_t ballTriangles = mb.triangleCount();
    addCylinder(mb, pedestal, 1, Vec3{0, 0, 0}, 0.45, 0, 0.5, scaled(30, scale, 2), scaled(4, scale, 1), Vec2{0, 0}, Vec2{1, 1});
    asset.mesh = mb.take();
    MaterialVariants& v = asset.variants;
    v.names = {"red", "blue", "gold", "classic"};
    v.mappings = {{red, blueMat, -1, ball}, {-1, red, gold, pedestal}};  // the ball's, the pedestal's
    v.triangleMapping.assign(asset.mesh.triangleCount(), 1);
    std::fill(v.triangleMapping.begin(), v.triangleMapping.begin() + long(ballTriangles), 0);
    return asset;
}

// tiles: a draped sheet 2 x 2 (x, z) with one woven material whose textures repeat 8 times each
// way (KHR_texture_transform scale (8, -8) on UVs spanning [0,1]: the flip is SheenCloth's), the
// case pack keeps tiled. Both images are periodic, so the tile's edges meet seamlessly.
Asset makeTiles(double scale) {
    Asset asset = newAsset("tiles");
    const int S = 64;
    // Threads along u and v, over and under each other: a weave whose period is the image.
    auto weave = [](double x, double y) {  // texel units, period S
        const double a = std::sin(2 * kPi * 4 * x / S), b = std::sin(2 * kPi * 4 * y / S);
        return 1.5 * (a * a * (b > 0 ? 1 : 0.4) + b * b * (a > 0 ? 0.4 : 1));
    };
    Image colour = imageOf(S, "weave_baseColor", [&](double u, double v) {
        const double w = weave(u * S, v * S) / 3;
        return Rgb{uint8_t(40 + 150 * w), uint8_t(60 + 120 * w), uint8_t(160 + 80 * w)};
    });
    Material m = plainMaterial("weave", {1, 1, 1, 1}, 0, 0.7);
    m.baseColor.texture = addImage(asset, std::move(colour));
    m.normal.texture = addImage(asset, encodePng(normalMapOf(S, 1.0, weave), S, S, "weave_normal"));
    for (TextureRef* r : {&m.baseColor, &m.normal}) {
        r->transform.present = true;
        r->transform.scale = {8, -8};
    }
    asset.materials.push_back(m);
    const int n = scaled(40, scale, 1);
    auto height = [](double x, double z) { return 0.15 * std::sin(2.5 * x) * std::cos(1.7 * z) + 0.05 * std::sin(4 * x + 3 * z); };
    auto normalAt = [&](double x, double z) {
        const double e = 1e-4;
        const double dx = (height(x + e, z) - height(x - e, z)) / (2 * e), dz = (height(x, z + e) - height(x, z - e)) / (2 * e);
        return normalize(Vec3{-dx, 1, -dz});
    };
    MeshBuilder mb;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            auto corner = [&](int ii, int jj) {
                const double x = 2.0 * jj / n - 1, z = 1 - 2.0 * ii / n;
                const uint32_t v = mb.vertex({ii, jj, 0}, {x, height(x, z), z});
                return mb.wedge(v, 0, {double(jj) / n, double(ii) / n}, normalAt(x, z));
            };
            const uint32_t a = corner(i, j), b = corner(i, j + 1), c = corner(i + 1, j + 1), d = corner(i + 1, j);
            mb.triangle(0, {a, b, c});
            mb.triangle(0, {a, c, d});
        }
    asset.mesh = mb.take();
    return asset;
}

}  // namespace
}  // namespace lodbake

int main(int argc, char** argv) {
    using namespace lodbake;
    return cli::runTool("make-samples", [&]() -> int {
        std::vector<std::string> dirs;
        bool verbose = false;
        double scale = 1;
        cli::ArgParser p("make-samples", "OUTDIR\n\nWrites hemisphere9.glb, wall5.glb, colors.glb, seamball.glb, pbrscene.glb, walker.glb, drum.glb,\n"
                                         "critter.glb, materials.glb, facets.glb, variants.glb and tiles.glb into OUTDIR\n"
                                         "(created if missing). Output is byte-identical on every run.");
        p.positionals("OUTDIR", [&](const std::string& v) { dirs.push_back(v); });
        p.flag("-v", "print one line per sample", [&] { verbose = true; });
        p.option("--scale", "S", "multiply every grid's resolution by S (about S^2 times the triangles; default 1)",
                 [&](const std::string& v) {
                     scale = cli::parseDouble("--scale", v);
                     if (!(scale > 0 && scale <= 64)) throw UsageError("--scale must be in (0, 64]");
                 });
        if (!p.parse(argc, argv)) return cli::kOk;
        if (dirs.size() != 1) throw UsageError("expected one OUTDIR");
        std::error_code ec;
        std::filesystem::create_directories(dirs[0], ec);
        if (!std::filesystem::is_directory(dirs[0])) throw IOError(dirs[0] + ": cannot create folder");
        struct Sample {
            const char* file;
            Asset (*make)(double);
        };
        const Sample samples[] = {{"hemisphere9.glb", makeHemisphere9},
                                  {"wall5.glb", makeWall5},
                                  {"colors.glb", makeColors},
                                  {"seamball.glb", makeSeamball},
                                  {"pbrscene.glb", makePbrScene},
                                  {"walker.glb", makeWalker},
                                  {"drum.glb", makeDrum},
                                  {"critter.glb", makeCritter},
                                  {"materials.glb", makeMaterials},
                                  {"facets.glb", makeFacets},
                                  {"variants.glb", makeVariants},
                                  {"tiles.glb", makeTiles}};
        for (const Sample& s : samples) {
            Asset a = s.make(scale);
            std::string path = (std::filesystem::path(dirs[0]) / s.file).string();
            a.sourcePath = path;
            writeGltf(path, a);
            if (verbose)
                std::cout << path << ": " << a.mesh.triangleCount() << " triangles, " << a.mesh.vertexCount()
                          << " vertices, " << a.mesh.wedges.size() << " wedges, " << a.materials.size()
                          << " materials, " << a.images.size() << " images\n";
        }
        return cli::kOk;
    });
}
