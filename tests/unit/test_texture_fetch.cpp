// The bake's own texture sampling and gap fill (bake/texture_fetch.h) on images built in code.
// Texels are 8-bit: fetched values are within 2e-3 of exact ones.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "lodbake/bake/texture_fetch.h"

namespace lodbake {
namespace {

// A w x h image of `channels` channels whose texel (x, y) holds f(x, y, c).
template <class F>
DecodedImage makeImage(int w, int h, int channels, F f) {
    DecodedImage img;
    img.width = w;
    img.height = h;
    img.channels = channels;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < channels; ++c) img.pixels.push_back(float(f(x, y, c)));
    return img;
}

TEST(TextureFetch, MipLevelsHalveDownToOneTexelAndKeepTheMean) {
    const MipTexture t = buildMipTexture(makeImage(6, 3, 3, [](int x, int y, int c) { return ((x + y + c) % 4) / 3.0; }));
    ASSERT_EQ(t.levels.size(), 4u);  // 6x3, 3x2, 2x1, 1x1
    EXPECT_EQ(t.levels[1].width, 3);
    EXPECT_EQ(t.levels[1].height, 2);
    EXPECT_EQ(t.levels[3].width, 1);
    EXPECT_EQ(t.levels[3].height, 1);
    EXPECT_EQ(t.levels[0].rgba[3], 255);  // no alpha: opaque
}

// An 8-bit PNG decoded as bytes and decoded as floats gives the same MIP levels (the bake keeps
// 8-bit sources as bytes), with or without alpha. Without alpha the bytes are the encoded ones and
// the floats byte / 255 (OpenImageIO converts alpha images between straight and associated alpha
// on the way, so those are not compared with the encoded bytes).
TEST(TextureFetch, EightBitSourcesAsBytesGiveTheSameLevelsAsFloats) {
    for (int channels : {1, 2, 3, 4}) {
        std::vector<uint8_t> px;
        for (int i = 0; i < 7 * 5 * channels; ++i) px.push_back(uint8_t((i * 37 + 11) % 256));
        const Image png = encodePng(px, 7, 5, "test", channels);
        DecodedImage asBytes, asFloats;
        std::string error;
        ASSERT_TRUE(decodeImage(png, asBytes, error, DecodeDepth::KeepEightBit)) << error;
        ASSERT_TRUE(decodeImage(png, asFloats, error)) << error;
        EXPECT_TRUE(asBytes.pixels.empty());
        ASSERT_EQ(asBytes.bytes.size(), px.size());
        ASSERT_EQ(asFloats.pixels.size(), px.size());
        EXPECT_TRUE(asFloats.bytes.empty());
        if (channels % 2 == 1) {
            EXPECT_EQ(asBytes.bytes, px);
            for (size_t i = 0; i < px.size(); ++i) EXPECT_FLOAT_EQ(asFloats.pixels[i], px[i] / 255.0f) << i;
        }
        for (size_t i = 0; i < px.size(); ++i) EXPECT_FLOAT_EQ(asFloats.pixels[i], asBytes.bytes[i] / 255.0f) << i;
        const MipTexture a = buildMipTexture(asBytes), b = buildMipTexture(asFloats);
        ASSERT_EQ(a.levels.size(), b.levels.size());
        for (size_t k = 0; k < a.levels.size(); ++k) EXPECT_EQ(a.levels[k].rgba, b.levels[k].rgba) << channels << " channels, level " << k;
    }
}

TEST(TextureFetch, GreyAndGreyAlphaFillRgb) {
    const MipTexture g = buildMipTexture(makeImage(2, 2, 2, [](int, int, int c) { return c == 0 ? 0.25 : 0.5; }));
    float out[4];
    fetchFiltered(g, {}, {0.5, 0.5}, {0.01, 0}, {0, 0.01}, out);
    EXPECT_NEAR(out[0], 0.25, 2e-3);
    EXPECT_NEAR(out[1], 0.25, 2e-3);
    EXPECT_NEAR(out[2], 0.25, 2e-3);
    EXPECT_NEAR(out[3], 0.5, 2e-3);
}

TEST(TextureFetch, MagnifiedFetchIsBilinearAtTexelCentres) {
    // A horizontal ramp: texel x holds x / 7.
    const MipTexture t = buildMipTexture(makeImage(8, 8, 1, [](int x, int, int) { return x / 7.0; }));
    FetchOptions clamp;
    clamp.wrapS = clamp.wrapT = TextureWrap::Clamp;
    float out[4];
    fetchFiltered(t, clamp, {(3 + 0.5) / 8, 0.5}, {0.01, 0}, {0, 0.01}, out);
    EXPECT_NEAR(out[0], 3 / 7.0, 2e-3);
    fetchFiltered(t, clamp, {4.0 / 8, 0.5}, {0.01, 0}, {0, 0.01}, out);  // between texels 3 and 4
    EXPECT_NEAR(out[0], 3.5 / 7.0, 2e-3);
    fetchFiltered(t, clamp, {-3.0, 0.5}, {0.01, 0}, {0, 0.01}, out);  // clamped to texel 0
    EXPECT_NEAR(out[0], 0.0, 2e-3);
}

TEST(TextureFetch, WrapModesRepeatAndMirror) {
    const MipTexture t = buildMipTexture(makeImage(4, 1, 1, [](int x, int, int) { return x / 3.0; }));
    const Vec2 d{1e-5, 0}, e{0, 1e-5};  // a point-like footprint
    float a[4], b[4];
    fetchFiltered(t, {}, {0.375, 0.5}, d, e, a);
    fetchFiltered(t, {}, {5.375, 0.5}, d, e, b);  // repeat: whole periods away
    EXPECT_NEAR(a[0], b[0], 1e-5);
    FetchOptions mirror;
    mirror.wrapS = TextureWrap::Mirror;
    fetchFiltered(t, mirror, {1.125, 0.5}, d, e, b);  // mirrored: u = 1.125 reads u = 0.875 (texel 3)
    EXPECT_NEAR(b[0], 1.0, 2e-3);
}

TEST(TextureFetch, MinifiedFootprintAveragesAStripeBeyondNyquist) {
    // One-texel stripes: a footprint of 8 texels per output texel shows their mean, a point fetch
    // would alias to 0 or 1.
    const MipTexture t = buildMipTexture(makeImage(64, 64, 1, [](int x, int, int) { return x % 2; }));
    for (double u : {0.1, 0.3, 0.77}) {
        float out[4];
        fetchFiltered(t, {}, {u, 0.4}, {8.0 / 64, 0}, {0, 8.0 / 64}, out);
        EXPECT_NEAR(out[0], 0.5, 0.02) << u;
        // Anisotropic: long only along v, stripes along u stay sharp where read at a texel centre.
        fetchFiltered(t, {}, {(10 + 0.5) / 64, 0.4}, {0.5 / 64, 0}, {0, 8.0 / 64}, out);
        EXPECT_NEAR(out[0], 0.0, 0.02);
    }
}

TEST(PullPushFill, CoveredTexelsStayAndGapsTakeNearbyValues) {
    const int w = 37, h = 21;
    std::vector<float> v(size_t(w * h) * 2, 0.0f);
    std::vector<uint8_t> cov(size_t(w * h), 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if (x < 10) {  // left strip covered: channel 0 = 0.2, channel 1 = 0.9
                cov[size_t(y * w + x)] = 1;
                v[size_t(y * w + x) * 2] = 0.2f;
                v[size_t(y * w + x) * 2 + 1] = 0.9f;
            } else if (x > 30) {  // right strip covered: 0.8, 0.1
                cov[size_t(y * w + x)] = 1;
                v[size_t(y * w + x) * 2] = 0.8f;
                v[size_t(y * w + x) * 2 + 1] = 0.1f;
            } else {
                v[size_t(y * w + x) * 2] = 1e6f;  // garbage under uncovered texels is ignored
            }
    std::vector<float> one = v, two = v;
    pullPushFill(one, 2, cov, w, h, 1);
    pullPushFill(two, 2, cov, w, h, 3);
    EXPECT_EQ(one, two);  // any thread count, same bytes
    for (int y = 0; y < h; ++y) {
        EXPECT_EQ(one[size_t(y * w + 3) * 2], 0.2f);
        EXPECT_EQ(one[size_t(y * w + 33) * 2 + 1], 0.1f);
        EXPECT_NEAR(one[size_t(y * w + 10) * 2], 0.2, 0.1);  // next to the left strip
        EXPECT_NEAR(one[size_t(y * w + 30) * 2], 0.8, 0.1);  // next to the right strip
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < 2; ++c) {
                const float f = one[size_t(y * w + x) * 2 + size_t(c)];
                EXPECT_GE(f, 0.1f - 1e-6f);
                EXPECT_LE(f, 0.9f + 1e-6f);
            }
    }
    // A joint fill of several images gives each its own fill's bytes.
    std::vector<float> grey(size_t(w * h));
    for (size_t i = 0; i < grey.size(); ++i) grey[i] = v[2 * i] * 0.5f + 0.01f * float(i % 7);
    std::vector<float> greyAlone = grey, joint = v;
    pullPushFill(greyAlone, 1, cov, w, h, 1);
    pullPushFill({FillImage{&joint, 2}, FillImage{&grey, 1}}, cov, w, h, 2);
    EXPECT_EQ(joint, one);
    EXPECT_EQ(grey, greyAlone);
    // Nothing covered: nothing changes.
    std::vector<float> none = v;
    pullPushFill(none, 2, std::vector<uint8_t>(cov.size(), 0), w, h, 1);
    EXPECT_EQ(none, v);
}

}  // namespace
}  // namespace lodbake
