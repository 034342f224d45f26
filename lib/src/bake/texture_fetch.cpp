// MIP levels, filtered fetch and pull-push fill for the bake (lodbake/bake/texture_fetch.h).
//
// Fetch: the footprint's two derivative vectors, in level-0 texels, give a major and a minor
// length; the minor one (raised to major / maxAnisotropy) picks the MIP level (log2, trilinear
// between the two nearest), and bilinear taps spread evenly along the major vector, at most one
// texel of that level apart, cover the footprint's length. A footprint under a texel reads level
// 0 with one bilinear tap.
// The pull-push fill lives in pull_push_fill.cpp.
#include "lodbake/bake/texture_fetch.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "lodbake/core/errors.h"

namespace lodbake {
namespace {

constexpr float kUnit = 1.0f / 255.0f;

// An empty level of w x h texels, every tile whole.
MipTexture::Level makeLevel(int w, int h) {
    MipTexture::Level L;
    L.width = w;
    L.height = h;
    L.tilesX = size_t(w + 3) / 4;
    L.rgba.assign(L.tilesX * size_t(h + 3) / 4 * 64, 0);
    return L;
}

// Texture coordinate reduced to a range where texel indices stay small (any finite input):
// [0, 1) repeating, [0, 2) mirrored, [-1, 2] clamped.
double reduceCoord(double s, TextureWrap m) {
    if (!std::isfinite(s)) return 0;
    if (m == TextureWrap::Repeat) return s - std::floor(s);
    if (m == TextureWrap::Mirror) return s - 2 * std::floor(s / 2);
    return std::clamp(s, -1.0, 2.0);
}

// Texel index i of a reduced coordinate's neighbourhood (i in [-n - 1, 2n]) -> [0, n).
int wrapIndex(int i, int n, TextureWrap m) {
    if (m == TextureWrap::Repeat) return i < 0 ? i + n : (i >= n ? i - n : i);
    if (m == TextureWrap::Mirror) {
        if (i < 0) i = -1 - i;             // mirrored about 0
        if (i >= 2 * n) i -= 2 * n;        // the next period
        return i < n ? i : 2 * n - 1 - i;  // mirrored about n
    }
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

// acc += weight x the bilinear RGBA of level L at (s, t) (0..255).
void addBilinear(const MipTexture::Level& L, const FetchOptions& o, double s, double t, float weight, float acc[4]) {
    const double x = reduceCoord(s, o.wrapS) * L.width - 0.5, y = reduceCoord(t, o.wrapT) * L.height - 0.5;
    const double xf = std::floor(x), yf = std::floor(y);
    const float fx = float(x - xf), fy = float(y - yf);
    const int xi = int(xf), yi = int(yf);
    const int x0 = wrapIndex(xi, L.width, o.wrapS), x1 = wrapIndex(xi + 1, L.width, o.wrapS);
    const int y0 = wrapIndex(yi, L.height, o.wrapT), y1 = wrapIndex(yi + 1, L.height, o.wrapT);
    const uint8_t* p00 = &L.rgba[L.at(x0, y0)];
    const uint8_t* p10 = &L.rgba[L.at(x1, y0)];
    const uint8_t* p01 = &L.rgba[L.at(x0, y1)];
    const uint8_t* p11 = &L.rgba[L.at(x1, y1)];
    const float w00 = weight * (1 - fx) * (1 - fy), w10 = weight * fx * (1 - fy), w01 = weight * (1 - fx) * fy, w11 = weight * fx * fy;
#if defined(__SSE2__)
    // The four channels side by side: each lane takes the scalar sum's products and additions in
    // its order, so the same floats.
    auto texel = [](const uint8_t* p) {
        int32_t word;
        std::memcpy(&word, p, sizeof word);
        const __m128i zero = _mm_setzero_si128();
        return _mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(_mm_cvtsi32_si128(word), zero), zero));
    };
    __m128 sum = _mm_mul_ps(_mm_set1_ps(w00), texel(p00));
    sum = _mm_add_ps(sum, _mm_mul_ps(_mm_set1_ps(w10), texel(p10)));
    sum = _mm_add_ps(sum, _mm_mul_ps(_mm_set1_ps(w01), texel(p01)));
    sum = _mm_add_ps(sum, _mm_mul_ps(_mm_set1_ps(w11), texel(p11)));
    _mm_storeu_ps(acc, _mm_add_ps(_mm_loadu_ps(acc), sum));
#else
    for (int c = 0; c < 4; ++c) acc[c] += w00 * float(p00[c]) + w10 * float(p10[c]) + w01 * float(p01[c]) + w11 * float(p11[c]);
#endif
}

}  // namespace

MipTexture buildMipTexture(const DecodedImage& image) {
    const size_t values = size_t(image.width) * size_t(image.height) * size_t(image.channels);
    const bool bytes = !image.bytes.empty();
    if (image.width < 1 || image.height < 1 || image.channels < 1 || (bytes ? image.bytes.size() : image.pixels.size()) != values ||
        (bytes && !image.pixels.empty()))
        throw InvalidInput("texture fetch: decoded image has no or inconsistent pixels");
    MipTexture t;
    MipTexture::Level base = makeLevel(image.width, image.height);
    const int nc = image.channels, used = std::min(nc, 4);  // channels past RGBA are not read
    // One texel as RGBA bytes from p[0..nc) (an 8-bit value as it is, a float rounded to 8 bits:
    // the same bytes for an 8-bit image decoded either way).
    auto store = [used](const auto* p, auto q, uint8_t* d) {
        d[0] = q(p[0]);
        d[1] = used >= 3 ? q(p[1]) : d[0];
        d[2] = used >= 3 ? q(p[2]) : d[0];
        d[3] = used == 2 ? q(p[1]) : (used == 4 ? q(p[3]) : uint8_t(255));
    };
    auto q = [](float v) { return uint8_t(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f); };
    auto same = [](uint8_t v) { return v; };
    for (int y = 0; y < image.height; ++y)
        for (int x = 0; x < image.width; ++x) {
            const size_t i = (size_t(y) * size_t(image.width) + size_t(x)) * size_t(nc);
            uint8_t* d = &base.rgba[base.at(x, y)];
            if (bytes)
                store(&image.bytes[i], same, d);
            else
                store(&image.pixels[i], q, d);
        }
    t.levels.push_back(std::move(base));
    while (t.levels.back().width > 1 || t.levels.back().height > 1) {
        const MipTexture::Level& s = t.levels.back();
        MipTexture::Level d = makeLevel((s.width + 1) / 2, (s.height + 1) / 2);
        for (int y = 0; y < d.height; ++y) {
            const int ya = 2 * y, yb = std::min(2 * y + 1, s.height - 1);
            for (int x = 0; x < d.width; ++x) {
                const int xa = 2 * x, xb = std::min(2 * x + 1, s.width - 1);
                const uint8_t *a = &s.rgba[s.at(xa, ya)], *b = &s.rgba[s.at(xb, ya)];
                const uint8_t *c = &s.rgba[s.at(xa, yb)], *e = &s.rgba[s.at(xb, yb)];
                uint8_t* o = &d.rgba[d.at(x, y)];
                for (int k = 0; k < 4; ++k) o[k] = uint8_t((unsigned(a[k]) + b[k] + c[k] + e[k] + 2) / 4);
            }
        }
        t.levels.push_back(std::move(d));
    }
    return t;
}

TextureWrap textureWrapFromGl(int gl) {
    if (gl == 33071) return TextureWrap::Clamp;
    if (gl == 33648) return TextureWrap::Mirror;
    return TextureWrap::Repeat;
}

void fetchFiltered(const MipTexture& texture, const FetchOptions& o, Vec2 st, Vec2 dx, Vec2 dy, float out[4]) {
    const MipTexture::Level& L0 = texture.levels.front();
    const double ax = dx.x * L0.width, ay = dx.y * L0.height, bx = dy.x * L0.width, by = dy.y * L0.height;
    const double la = std::sqrt(ax * ax + ay * ay), lb = std::sqrt(bx * bx + by * by);
    double major = std::max(la, lb), minor = std::min(la, lb);
    Vec2 axis = la >= lb ? dx : dy;
    if (!std::isfinite(major)) major = minor = 0, axis = {0, 0};
    const int maxAniso = std::max(1, o.maxAnisotropy);
    minor = std::max(minor, major / maxAniso);
    // Taps at most one texel of the level read apart (a magnified footprint reads level 0).
    const double spacing = std::max(minor, 1.0);
    const int taps = std::clamp(int(std::ceil(major / spacing - 1e-3)), 1, maxAniso);
    const int top = int(texture.levels.size()) - 1;
    const double lod = std::min(minor > 1 ? std::log2(minor) : 0.0, double(top));
    const int l0 = std::min(int(lod), top);
    const float frac = l0 < top ? float(lod - l0) : 0.0f;
    float acc[4] = {0, 0, 0, 0};
    for (int i = 0; i < taps; ++i) {
        const double off = (i + 0.5) / taps - 0.5;
        const double s = st.x + axis.x * off, t = st.y + axis.y * off;
        addBilinear(texture.levels[size_t(l0)], o, s, t, (1 - frac) / float(taps), acc);
        if (frac > 0) addBilinear(texture.levels[size_t(l0) + 1], o, s, t, frac / float(taps), acc);
    }
    for (int c = 0; c < 4; ++c) out[c] = std::clamp(acc[c] * kUnit, 0.0f, 1.0f);
}

}  // namespace lodbake
