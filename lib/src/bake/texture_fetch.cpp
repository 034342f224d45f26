// MIP levels, filtered fetch and pull-push fill for the bake (lodbake/bake/texture_fetch.h).
//
// Fetch: the footprint's two derivative vectors, in level-0 texels, give a major and a minor
// length; the minor one (raised to major / maxAnisotropy) picks the MIP level (log2, trilinear
// between the two nearest), and bilinear taps spread evenly along the major vector, at most one
// texel of that level apart, cover the footprint's length. A footprint under a texel reads level
// 0 with one bilinear tap.
// Fill: pull = coverage-weighted [1 3 3 1] tent down to 1 x 1 (a coarse texel with any covered
// weight is covered), push = each uncovered texel takes the bilinear value of the next coarser,
// already filled level. Every texel of a level depends only on the level below or above, so rows
// run in parallel with the same result for any thread count.
#include "lodbake/bake/texture_fetch.h"

#include <algorithm>
#include <cmath>

#include "lodbake/core/errors.h"
#include "lodbake/core/parallel.h"

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
    for (int c = 0; c < 4; ++c) acc[c] += w00 * float(p00[c]) + w10 * float(p10[c]) + w01 * float(p01[c]) + w11 * float(p11[c]);
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

namespace {

// One pull level of pullPushFill: row y of d (dw texels) from the coverage-weighted [1 3 3 1] tent
// of s (sw x sh, values `sv` of nc channels, coverage `sa`). NC = nc as a compile-time count for
// the usual ones (0: any, read from nc), so the channel loops unroll; every sum is taken in the
// same order either way.
template <size_t NC>
void pullRow(size_t nc, int y, int dw, int sw, int sh, const float* sv, const uint8_t* sa, float* dv, uint8_t* da) {
    static constexpr float kTent[4] = {1, 3, 3, 1};
    const size_t n = NC ? NC : nc;
    float fixed[NC ? NC : 1];
    std::vector<float> any(NC ? 0 : nc);
    float* acc = NC ? fixed : any.data();
    for (int x = 0; x < dw; ++x) {
        std::fill(acc, acc + n, 0.0f);
        float wsum = 0;
        for (int j = 0; j < 4; ++j) {
            const int sy = 2 * y - 1 + j;
            if (sy < 0 || sy >= sh) continue;
            for (int i = 0; i < 4; ++i) {
                const int sx = 2 * x - 1 + i;
                if (sx < 0 || sx >= sw) continue;
                const size_t si = size_t(sy) * size_t(sw) + size_t(sx);
                if (!sa[si]) continue;
                const float wt = kTent[j] * kTent[i];
                wsum += wt;
                const float* p = &sv[si * n];
                for (size_t c = 0; c < n; ++c) acc[c] += wt * p[c];
            }
        }
        if (wsum > 0) {
            const size_t di = size_t(y) * size_t(dw) + size_t(x);
            da[di] = 1;
            for (size_t c = 0; c < n; ++c) dv[di * n + c] = acc[c] / wsum;
        }
    }
}

}  // namespace

void pullPushFill(std::vector<float>& values, int channels, const std::vector<uint8_t>& covered, int w, int h, int threads) {
    const size_t nc = size_t(channels);
    if (channels < 1 || w < 1 || h < 1 || values.size() != size_t(w) * size_t(h) * nc || covered.size() != size_t(w) * size_t(h))
        throw InvalidInput("pull-push fill: image and coverage sizes differ");
    if (std::none_of(covered.begin(), covered.end(), [](uint8_t c) { return c != 0; })) return;
    struct Level {
        int w, h;
        float* v;
        const uint8_t* a;
        std::vector<float> vs;
        std::vector<uint8_t> as;
    };
    std::vector<Level> levels;
    levels.push_back({w, h, values.data(), covered.data(), {}, {}});
    // Pull: coverage-weighted tent of the level below.
    while (levels.back().w > 1 || levels.back().h > 1) {
        const Level& s = levels.back();
        Level d{(s.w + 1) / 2, (s.h + 1) / 2, nullptr, nullptr, {}, {}};
        d.vs.assign(size_t(d.w) * size_t(d.h) * nc, 0.0f);
        d.as.assign(size_t(d.w) * size_t(d.h), 0);
        parallelFor(size_t(d.h), threads, [&](size_t yy) {
            const int y = int(yy);
            float* dv = d.vs.data();
            uint8_t* da = d.as.data();
            if (nc == 1)
                pullRow<1>(nc, y, d.w, s.w, s.h, s.v, s.a, dv, da);
            else if (nc == 3)
                pullRow<3>(nc, y, d.w, s.w, s.h, s.v, s.a, dv, da);
            else if (nc == 4)
                pullRow<4>(nc, y, d.w, s.w, s.h, s.v, s.a, dv, da);
            else
                pullRow<0>(nc, y, d.w, s.w, s.h, s.v, s.a, dv, da);
        });
        d.v = d.vs.data();
        d.a = d.as.data();
        levels.push_back(std::move(d));
    }
    // Push: uncovered texels take the bilinear value of the filled level above (the 1 x 1 top
    // is covered: some texel is).
    for (size_t k = levels.size() - 1; k-- > 0;) {
        Level& f = levels[k];
        const Level& c = levels[k + 1];
        parallelFor(size_t(f.h), threads, [&](size_t yy) {
            const int y = int(yy);
            const double cy = (y + 0.5) / 2 - 0.5;
            const int cy0 = int(std::floor(cy));
            const float fy = float(cy - cy0);
            const int ya = std::clamp(cy0, 0, c.h - 1), yb = std::clamp(cy0 + 1, 0, c.h - 1);
            for (int x = 0; x < f.w; ++x) {
                const size_t fi = size_t(y) * size_t(f.w) + size_t(x);
                if (f.a[fi]) continue;
                const double cx = (x + 0.5) / 2 - 0.5;
                const int cx0 = int(std::floor(cx));
                const float fx = float(cx - cx0);
                const int xa = std::clamp(cx0, 0, c.w - 1), xb = std::clamp(cx0 + 1, 0, c.w - 1);
                const float* p00 = &c.v[(size_t(ya) * size_t(c.w) + size_t(xa)) * nc];
                const float* p10 = &c.v[(size_t(ya) * size_t(c.w) + size_t(xb)) * nc];
                const float* p01 = &c.v[(size_t(yb) * size_t(c.w) + size_t(xa)) * nc];
                const float* p11 = &c.v[(size_t(yb) * size_t(c.w) + size_t(xb)) * nc];
                float* o = &f.v[fi * nc];
                for (size_t ch = 0; ch < nc; ++ch)
                    o[ch] = (1 - fy) * ((1 - fx) * p00[ch] + fx * p10[ch]) + fy * ((1 - fx) * p01[ch] + fx * p11[ch]);
            }
        });
    }
}

}  // namespace lodbake
