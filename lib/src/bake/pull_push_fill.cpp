// Pull-push fill (lodbake/bake/texture_fetch.h): pull = coverage-weighted [1 3 3 1] tent down to
// 1 x 1 (a coarse texel with any covered weight is covered), push = each uncovered texel takes the
// bilinear value of the next coarser, already filled level. Every texel of a level depends only on
// the level below or above, so rows run in parallel with the same result for any thread count.
//
// The images of one bake share their coverage: one pass fills them all, the taps and weights of a
// texel found once and applied to each image in the same order a pass of its own takes them.
#include <algorithm>
#include <cmath>

#include "lodbake/bake/texture_fetch.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/parallel.h"
#include "lodbake/core/touched_fill.h"

namespace lodbake {
namespace {

constexpr float kTent[4] = {1, 3, 3, 1};

// A covered texel of the level below under a coarse texel's tent, and its weight.
struct Tap {
    size_t index;
    float weight;
};

// One image's levels: values of `channels` floats per texel, level 0 the image itself.
struct Pyramid {
    size_t channels;
    std::vector<float*> v;
    std::vector<std::vector<float>> store;  // levels 1 and up
};

// dv = the weighted mean of sv over the taps, each channel summed in tap order. NC = channels as a
// compile-time count for the usual ones (0: any, read from nc), so the channel loops unroll.
template <size_t NC>
void pullTexel(size_t nc, const Tap* taps, int count, float wsum, const float* sv, float* dv) {
    const size_t n = NC ? NC : nc;
    float fixed[NC ? NC : 1];
    std::vector<float> any(NC ? 0 : nc);
    float* acc = NC ? fixed : any.data();
    std::fill(acc, acc + n, 0.0f);
    for (int t = 0; t < count; ++t) {
        const float* p = &sv[taps[t].index * n];
        for (size_t c = 0; c < n; ++c) acc[c] += taps[t].weight * p[c];
    }
    for (size_t c = 0; c < n; ++c) dv[c] = acc[c] / wsum;
}

void pullTexelAny(size_t nc, const Tap* taps, int count, float wsum, const float* sv, float* dv) {
    if (nc == 1)
        pullTexel<1>(nc, taps, count, wsum, sv, dv);
    else if (nc == 3)
        pullTexel<3>(nc, taps, count, wsum, sv, dv);
    else if (nc == 4)
        pullTexel<4>(nc, taps, count, wsum, sv, dv);
    else
        pullTexel<0>(nc, taps, count, wsum, sv, dv);
}

}  // namespace

void pullPushFill(const std::vector<FillImage>& images, const std::vector<uint8_t>& covered, int w, int h, int threads) {
    if (w < 1 || h < 1 || covered.size() != size_t(w) * size_t(h)) throw InvalidInput("pull-push fill: image and coverage sizes differ");
    for (const FillImage& im : images)
        if (!im.values || im.channels < 1 || im.values->size() != size_t(w) * size_t(h) * size_t(im.channels))
            throw InvalidInput("pull-push fill: image and coverage sizes differ");
    if (images.empty() || std::none_of(covered.begin(), covered.end(), [](uint8_t c) { return c != 0; })) return;
    struct Level {
        int w, h;
        const uint8_t* a;
        std::vector<uint8_t> as;
    };
    std::vector<Level> levels;
    levels.push_back({w, h, covered.data(), {}});
    std::vector<Pyramid> pyramids(images.size());
    for (size_t m = 0; m < images.size(); ++m) {
        pyramids[m].channels = size_t(images[m].channels);
        pyramids[m].v.push_back(images[m].values->data());
    }
    // Pull: coverage-weighted tent of the level below.
    while (levels.back().w > 1 || levels.back().h > 1) {
        const size_t k = levels.size() - 1;
        const Level& s = levels.back();
        Level d{(s.w + 1) / 2, (s.h + 1) / 2, nullptr, {}};
        const size_t texels = size_t(d.w) * size_t(d.h);
        d.as.assign(texels, 0);
        for (Pyramid& p : pyramids) {
            p.store.emplace_back();
            assignTouched(p.store.back(), texels * p.channels, 0.0f, threads);
            p.v.push_back(p.store.back().data());
        }
        parallelFor(size_t(d.h), threads, [&](size_t yy) {
            const int y = int(yy);
            Tap taps[16];
            for (int x = 0; x < d.w; ++x) {
                int count = 0;
                float wsum = 0;
                for (int j = 0; j < 4; ++j) {
                    const int sy = 2 * y - 1 + j;
                    if (sy < 0 || sy >= s.h) continue;
                    for (int i = 0; i < 4; ++i) {
                        const int sx = 2 * x - 1 + i;
                        if (sx < 0 || sx >= s.w) continue;
                        const size_t si = size_t(sy) * size_t(s.w) + size_t(sx);
                        if (!s.a[si]) continue;
                        const float wt = kTent[j] * kTent[i];
                        wsum += wt;
                        taps[count++] = {si, wt};
                    }
                }
                if (!(wsum > 0)) continue;
                const size_t di = size_t(y) * size_t(d.w) + size_t(x);
                d.as[di] = 1;
                for (Pyramid& p : pyramids) pullTexelAny(p.channels, taps, count, wsum, p.v[k], &p.v[k + 1][di * p.channels]);
            }
        });
        d.a = d.as.data();
        levels.push_back(std::move(d));
    }
    // Push: uncovered texels take the bilinear value of the filled level above (the 1 x 1 top
    // is covered: some texel is).
    for (size_t k = levels.size() - 1; k-- > 0;) {
        const Level& f = levels[k];
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
                const size_t i00 = size_t(ya) * size_t(c.w) + size_t(xa), i10 = size_t(ya) * size_t(c.w) + size_t(xb);
                const size_t i01 = size_t(yb) * size_t(c.w) + size_t(xa), i11 = size_t(yb) * size_t(c.w) + size_t(xb);
                for (Pyramid& p : pyramids) {
                    const size_t nc = p.channels;
                    const float* cv = p.v[k + 1];
                    const float *p00 = &cv[i00 * nc], *p10 = &cv[i10 * nc], *p01 = &cv[i01 * nc], *p11 = &cv[i11 * nc];
                    float* o = &p.v[k][fi * nc];
                    for (size_t ch = 0; ch < nc; ++ch)
                        o[ch] = (1 - fy) * ((1 - fx) * p00[ch] + fx * p10[ch]) + fy * ((1 - fx) * p01[ch] + fx * p11[ch]);
                }
            }
        });
        for (Pyramid& p : pyramids) p.store[k] = {};  // level k + 1: read for the last time
    }
}

void pullPushFill(std::vector<float>& values, int channels, const std::vector<uint8_t>& covered, int w, int h, int threads) {
    if (channels < 1 || w < 1 || h < 1 || values.size() != size_t(w) * size_t(h) * size_t(channels) ||
        covered.size() != size_t(w) * size_t(h))
        throw InvalidInput("pull-push fill: image and coverage sizes differ");
    pullPushFill({FillImage{&values, channels}}, covered, w, h, threads);
}

}  // namespace lodbake
