// Unit tests for the atlas packers (lib/src/atlas/atlas.cpp, shelf_pack.cpp) on charts built in code.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "lodbake/atlas/atlas.h"

using namespace lodbake;

namespace {

// An axis-aligned w x h rectangle chart (two triangles) at (x, y).
AtlasChart rectChart(double x, double y, double w, double h) {
    AtlasChart c;
    c.points = {{x, y}, {x + w, y}, {x + w, y + h}, {x, y + h}};
    c.uvArea = w * h;
    return c;
}

// The chart's corners on the page (texels).
std::vector<Vec2> placed(const AtlasChart& c, const ChartPlacement& p) {
    std::vector<Vec2> out;
    for (const Vec2& q : c.points) out.push_back(p.apply(q));
    return out;
}

// Whether p lies in triangle t (either winding, boundary included).
bool inside(const std::array<Vec2, 3>& t, Vec2 p) {
    double d0 = cross(t[1] - t[0], p - t[0]), d1 = cross(t[2] - t[1], p - t[1]), d2 = cross(t[0] - t[2], p - t[2]);
    return (d0 >= 0 && d1 >= 0 && d2 >= 0) || (d0 <= 0 && d1 <= 0 && d2 <= 0);
}

// Distance from p to the segment ab.
double pointToSegment(Vec2 p, Vec2 a, Vec2 b) {
    Vec2 e = b - a;
    double u = std::clamp(dot(p - a, e) / dot(e, e), 0.0, 1.0);
    Vec2 q{a.x + u * e.x - p.x, a.y + u * e.y - p.y};
    return std::sqrt(dot(q, q));
}

// A one-triangle chart.
AtlasChart triangleChart(Vec2 a, Vec2 b, Vec2 d) {
    AtlasChart c;
    c.triangles.push_back({a, b, d});
    c.points.assign(c.triangles[0].begin(), c.triangles[0].end());
    c.uvArea = 0.5 * std::abs(cross(b - a, d - a));
    return c;
}

// The charts packed on one thread, after checking that every other thread count gives the same
// page and chart maps.
AtlasResult packedAlikeOnAnyThreads(const std::vector<AtlasChart>& charts, AtlasOptions o, std::initializer_list<int> threads) {
    o.threads = 1;
    AtlasResult one = packAtlas(charts, o);
    for (int n : threads) {
        o.threads = n;
        const AtlasResult r = packAtlas(charts, o);
        EXPECT_EQ(r.width, one.width) << n << " threads";
        EXPECT_EQ(r.height, one.height) << n << " threads";
        for (size_t i = 0; i < charts.size() && i < r.charts.size(); ++i) EXPECT_EQ(r.charts[i].m, one.charts[i].m) << "chart " << i;
    }
    return one;
}

struct Box { double x0, y0, x1, y1; };
Box boxOf(const std::vector<Vec2>& pts) {
    Box b{1e300, 1e300, -1e300, -1e300};
    for (const Vec2& p : pts) { b.x0 = std::min(b.x0, p.x); b.y0 = std::min(b.y0, p.y); b.x1 = std::max(b.x1, p.x); b.y1 = std::max(b.y1, p.y); }
    return b;
}

}  // namespace

// Four 0.25 x 0.25 squares at 256 texels per unit: 64 x 64 texels each, gutter 4.
//   +----+----+
//   | c0 | c1 |      4 texels between charts, none along the page border (clamped samplers):
//   +----+----+      the page is about 132 x 132
//   +----+----+
//   | c2 | c3 |
//   +----+----+
TEST(PackAtlas, SquaresFitWithGuttersAndNoOverlap) {
    std::vector<AtlasChart> charts;
    for (int i = 0; i < 4; ++i) charts.push_back(rectChart(0.3 * i, 0, 0.25, 0.25));
    AtlasOptions o;
    o.maxTexelsPerUnit = 256;
    o.gutter = 4;
    AtlasResult r = packAtlas(charts, o);
    EXPECT_DOUBLE_EQ(r.texelsPerUnit, 256);
    EXPECT_EQ(r.gutter, 4);
    ASSERT_EQ(r.charts.size(), 4u);
    std::vector<Box> boxes;
    for (size_t i = 0; i < 4; ++i) {
        Box b = boxOf(placed(charts[i], r.charts[i]));
        EXPECT_NEAR(b.x1 - b.x0, 64, 1e-6);
        EXPECT_NEAR(b.y1 - b.y0, 64, 1e-6);
        EXPECT_GE(b.x0, -1e-9);
        EXPECT_GE(b.y0, -1e-9);
        EXPECT_LE(b.x1, r.width + 1e-9);
        EXPECT_LE(b.y1, r.height + 1e-9);
        boxes.push_back(b);
    }
    for (size_t i = 0; i < 4; ++i)
        for (size_t j = i + 1; j < 4; ++j) {
            double gapX = std::max(boxes[j].x0 - boxes[i].x1, boxes[i].x0 - boxes[j].x1);
            double gapY = std::max(boxes[j].y0 - boxes[i].y1, boxes[i].y0 - boxes[j].y1);
            EXPECT_GE(std::max(gapX, gapY), 4 - 1e-9) << i << " " << j;  // the gutter separates them
        }
    EXPECT_GT(r.utilisation, 0.75);
    EXPECT_LE(r.utilisation, 1.0);
    EXPECT_NEAR(r.utilisation, r.boxUtilisation, 1e-12);  // rectangles: coverage = box
}

// A long thin chart turned by 30 degrees is packed along its minimum-area rectangle.
// The samplers clamp to the page edge, so a chart may touch the border: one 64 x 64 texel chart
// fills a 64 x 64 page whatever the gutter.
TEST(PackAtlas, TexelAlignedChartsKeepTheirOrientationAndLandOnWholeBlocks) {
    // Charts in source texels at odd positions, one tilted (a free packing would turn it).
    std::vector<AtlasChart> charts = {rectChart(3.25, 7.5, 40, 20), rectChart(100.5, 1, 20, 30),
                                      triangleChart({0.5, 0.5}, {30.5, 10.5}, {5.5, 25.5})};
    AtlasOptions o;
    o.maxTexelsPerUnit = 1;
    o.gutter = 4;
    o.maxSize = 256;
    o.texelAligned = true;
    const AtlasResult r = packedAlikeOnAnyThreads(charts, o, {2});
    EXPECT_EQ(r.texelsPerUnit, 1.0);
    ASSERT_EQ(r.charts.size(), charts.size());
    for (const ChartPlacement& p : r.charts) {
        // Unturned, unit scale, and shifted by whole multiples of 16 texels: every source texel
        // centre is a page texel centre, and 2x2 .. 16x16 blocks (mips 1-4) stay blocks.
        EXPECT_EQ(p.m[0], 1.0);
        EXPECT_EQ(p.m[1], 0.0);
        EXPECT_EQ(p.m[3], 0.0);
        EXPECT_EQ(p.m[4], 1.0);
        EXPECT_EQ(std::fmod(p.m[2], 16.0), 0.0);
        EXPECT_EQ(std::fmod(p.m[5], 16.0), 0.0);
    }
    for (size_t i = 0; i < charts.size(); ++i)
        for (const Vec2& q : placed(charts[i], r.charts[i])) {
            EXPECT_GE(q.x, 0);
            EXPECT_GE(q.y, 0);
            EXPECT_LE(q.x, r.width);
            EXPECT_LE(q.y, r.height);
        }
}

TEST(PackAtlas, TexelAlignedChartsThatDoNotFitLowerTheDensity) {
    AtlasOptions o;
    o.maxTexelsPerUnit = 1;
    o.maxSize = 64;
    o.texelAligned = true;
    const AtlasResult r = packAtlas({rectChart(0, 0, 100, 100)}, o);
    EXPECT_LT(r.texelsPerUnit, 1.0);  // the caller falls back (lod_chain: sourceTexels)
}

TEST(PackAtlas, InPlaceChartsKeepTheirTexelsWhenNoSearchFits) {
    // Four 30 x 30 islands of a 64 x 64 texture, 2 texels apart at odd offsets: on 16-texel blocks
    // with gutters no search fits them in 64 x 64; kept where they are they do.
    std::vector<AtlasChart> charts;
    for (double y : {33.0, 1.0})
        for (double x : {33.0, 1.0}) {
            charts.push_back(rectChart(x, y, 30, 30));
            charts.back().inPlace = true;
        }
    AtlasOptions o;
    o.maxTexelsPerUnit = 1;
    o.gutter = 2;
    o.maxSize = 64;
    o.texelAligned = true;
    const AtlasResult r = packedAlikeOnAnyThreads(charts, o, {2});
    EXPECT_EQ(r.texelsPerUnit, 1.0);
    EXPECT_EQ(r.width, 64);
    EXPECT_EQ(r.height, 64);
    for (const ChartPlacement& p : r.charts) EXPECT_EQ(p.m, (std::array<double, 6>{1, 0, 0, 0, 1, 0}));
    // Unmarked, the same charts are packed afresh (on whole texels, as no 16-texel block search
    // fits them), away from their texture places.
    for (AtlasChart& c : charts) c.inPlace = false;
    const AtlasResult searched = packAtlas(charts, o);
    EXPECT_TRUE(std::any_of(searched.charts.begin(), searched.charts.end(),
                            [](const ChartPlacement& p) { return p.m != std::array<double, 6>{1, 0, 0, 0, 1, 0}; }));
}

TEST(PackAtlas, NoGutterAlongThePageBorder) {
    std::vector<AtlasChart> charts{rectChart(0, 0, 0.25, 0.25)};
    AtlasOptions o;
    o.maxTexelsPerUnit = 256;
    o.gutter = 8;
    AtlasResult r = packAtlas(charts, o);
    EXPECT_EQ(r.width, 64);
    EXPECT_EQ(r.height, 64);
    EXPECT_NEAR(r.utilisation, 1.0, 1e-9);
    Box b = boxOf(placed(charts[0], r.charts[0]));
    EXPECT_NEAR(b.x0, 0, 1e-9);
    EXPECT_NEAR(b.y0, 0, 1e-9);
}

TEST(PackAtlas, RotatedChartUsesMinimumAreaRectangle) {
    const double a = 30 * 3.14159265358979 / 180, c = std::cos(a), s = std::sin(a);
    AtlasChart chart;
    for (Vec2 p : {Vec2{0, 0}, Vec2{1, 0}, Vec2{1, 0.1}, Vec2{0, 0.1}}) chart.points.push_back({c * p.x - s * p.y, s * p.x + c * p.y});
    chart.uvArea = 0.1;
    AtlasOptions o;
    o.maxTexelsPerUnit = 100;
    o.gutter = 2;
    AtlasResult r = packAtlas({chart}, o);
    Box b = boxOf(placed(chart, r.charts[0]));
    double w = b.x1 - b.x0, h = b.y1 - b.y0;
    EXPECT_NEAR(std::max(w, h), 100, 1e-6);
    EXPECT_NEAR(std::min(w, h), 10, 1e-6);
    EXPECT_GT(r.boxUtilisation, 0.7);
    // Orientation preserved (no mirroring): the affine map has a positive determinant.
    const auto& m = r.charts[0].m;
    EXPECT_GT(m[0] * m[4] - m[1] * m[3], 0);
}

// --pot: power-of-two sides; --max-size: the density drops until the charts fit.
TEST(PackAtlas, PowerOfTwoAndMaxSize) {
    std::vector<AtlasChart> charts;
    for (int i = 0; i < 10; ++i) charts.push_back(rectChart(0, 0, 0.3, 0.2));
    AtlasOptions o;
    o.maxTexelsPerUnit = 1000;
    o.gutter = 8;
    o.powerOfTwo = true;
    o.maxSize = 256;
    AtlasResult r = packAtlas(charts, o);
    EXPECT_EQ(r.width & (r.width - 1), 0);
    EXPECT_EQ(r.height & (r.height - 1), 0);
    EXPECT_LE(r.width, 256);
    EXPECT_LE(r.height, 256);
    EXPECT_LT(r.texelsPerUnit, 1000);
    for (size_t i = 0; i < charts.size(); ++i) {
        Box b = boxOf(placed(charts[i], r.charts[i]));
        EXPECT_GE(b.x0, 0);
        EXPECT_GE(b.y0, 0);
        EXPECT_LE(b.x1, r.width);
        EXPECT_LE(b.y1, r.height);
    }
}

// A density limit far beyond any page (a level that switches at a huge screen coverage, as a
// near-exact simplification does): the charts are never rasterised at that density, so the
// packer neither runs out of memory nor overflows texel counts, and it packs the densest fit of
// the page, free size and power of two alike.
TEST(PackAtlas, HugeDensityLimitPacksTheDensestFitOfThePage) {
    std::vector<AtlasChart> charts;
    for (int i = 0; i < 40; ++i) charts.push_back(rectChart(0, 0, 0.05 + 0.01 * (i % 7), 0.04));
    for (bool pot : {false, true}) {
        AtlasOptions o;
        o.maxTexelsPerUnit = 1e12;
        o.gutter = 4;
        o.maxSize = 512;
        o.powerOfTwo = pot;
        AtlasResult r = packAtlas(charts, o);
        EXPECT_LE(r.width, 512);
        EXPECT_LE(r.height, 512);
        EXPECT_GT(r.texelsPerUnit, 500);  // the charts' 0.1 square units fill much of 512^2 texels
        EXPECT_LT(r.texelsPerUnit, 2000);
        for (size_t i = 0; i < charts.size(); ++i) {
            Box b = boxOf(placed(charts[i], r.charts[i]));
            EXPECT_GE(b.x0, -1e-6);
            EXPECT_GE(b.y0, -1e-6);
            EXPECT_LE(b.x1, r.width + 1e-6);
            EXPECT_LE(b.y1, r.height + 1e-6);
        }
    }
}

// A minimum density (AtlasOptions::minTexelsPerUnit) changes nothing at or below the densest fit,
// the same placements and figures; above it the search may stop early, with a page still below it.
TEST(PackAtlas, MinimumDensityKeepsTheDensestFitAndStopsShortBelowIt) {
    std::vector<AtlasChart> charts;
    for (int i = 0; i < 40; ++i) charts.push_back(rectChart(0, 0, 0.05 + 0.01 * (i % 7), 0.04));
    for (int threads : {1, 2}) {
        AtlasOptions o;
        o.maxTexelsPerUnit = 1e4;
        o.gutter = 4;
        o.maxSize = 512;
        o.threads = threads;
        const AtlasResult densest = packAtlas(charts, o);
        ASSERT_LT(densest.texelsPerUnit, o.maxTexelsPerUnit);  // the density search ran
        for (double min : {densest.texelsPerUnit * 0.5, densest.texelsPerUnit}) {
            o.minTexelsPerUnit = min;
            const AtlasResult same = packAtlas(charts, o);
            EXPECT_EQ(same.texelsPerUnit, densest.texelsPerUnit);
            EXPECT_EQ(same.width, densest.width);
            EXPECT_EQ(same.height, densest.height);
            for (size_t i = 0; i < charts.size(); ++i) EXPECT_EQ(same.charts[i].m, densest.charts[i].m);
        }
        o.minTexelsPerUnit = densest.texelsPerUnit * 1.001;
        const AtlasResult below = packAtlas(charts, o);
        EXPECT_LT(below.texelsPerUnit, o.minTexelsPerUnit);
        EXPECT_LE(below.texelsPerUnit, densest.texelsPerUnit);
        EXPECT_GT(below.texelsPerUnit, 0);
    }
}

// Shapes, not boxes: two right triangles whose bounding boxes cannot share a row or column
// without wasting half of each box nest into one square (one turned by 180 degrees), and their
// placed triangles stay at least the gutter apart.
TEST(PackAtlas, TrianglesNestByShape) {
    std::vector<AtlasChart> charts;
    for (int i = 0; i < 2; ++i) {
        AtlasChart c;
        double x = 0.6 * i;
        c.triangles = {{Vec2{x, 0}, Vec2{x + 0.5, 0}, Vec2{x, 0.5}}};
        c.points = {c.triangles[0][0], c.triangles[0][1], c.triangles[0][2]};
        c.uvArea = 0.125;
        charts.push_back(c);
    }
    AtlasOptions o;
    o.maxTexelsPerUnit = 256;
    o.gutter = 2;
    AtlasResult r = packAtlas(charts, o);
    EXPECT_DOUBLE_EQ(r.texelsPerUnit, 256);
    EXPECT_GT(r.utilisation, 0.7);  // two boxes side by side would give at most 0.5
    EXPECT_GT(r.boxUtilisation, 1.0);  // the boxes overlap: only the shapes are kept apart
    // No point of one triangle is
    // within the gutter (2 texels) of the other (sampled on a quarter-texel grid).
    std::array<std::array<Vec2, 3>, 2> placedTri;
    for (size_t i = 0; i < 2; ++i)
        for (size_t k = 0; k < 3; ++k) placedTri[i][k] = r.charts[i].apply(charts[i].triangles[0][k]);
    auto distToTri = [&](const std::array<Vec2, 3>& t, Vec2 p) {
        if (inside(t, p)) return 0.0;
        double best = 1e300;
        for (size_t k = 0; k < 3; ++k) best = std::min(best, pointToSegment(p, t[k], t[(k + 1) % 3]));
        return best;
    };
    for (double y = 0; y < r.height; y += 0.25)
        for (double x = 0; x < r.width; x += 0.25) {
            Vec2 p{x, y};
            if (inside(placedTri[0], p)) {
                EXPECT_GE(distToTri(placedTri[1], p), 2.0 - 1e-6) << x << " " << y;
            }
        }
}

namespace {

// Every placed one-triangle chart inside the page, and every pair at least `gutter` texels apart:
// the distance between two disjoint triangles is reached at a corner of one of them, and two
// triangles overlap only if an edge of one crosses an edge of the other or a corner lies inside.
void expectInsideAndApart(const std::vector<AtlasChart>& charts, const AtlasResult& one, double gutter) {
    std::vector<std::array<Vec2, 3>> tri(charts.size());
    for (size_t i = 0; i < charts.size(); ++i)
        for (size_t k = 0; k < 3; ++k) {
            tri[i][k] = one.charts[i].apply(charts[i].triangles[0][k]);
            EXPECT_GE(tri[i][k].x, -1e-6);
            EXPECT_GE(tri[i][k].y, -1e-6);
            EXPECT_LE(tri[i][k].x, one.width + 1e-6);
            EXPECT_LE(tri[i][k].y, one.height + 1e-6);
        }
    auto cross2 = [](Vec2 a, Vec2 b, Vec2 c, Vec2 d) {  // segments ab and cd properly intersect
        auto side = [](Vec2 p, Vec2 q, Vec2 r) { return cross(q - p, r - p); };
        return side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0;
    };
    for (size_t i = 0; i < tri.size(); ++i)
        for (size_t j = i + 1; j < tri.size(); ++j) {
            double dist = 1e300;
            for (size_t k = 0; k < 3; ++k) {
                EXPECT_FALSE(inside(tri[j], tri[i][k]) || inside(tri[i], tri[j][k])) << i << " " << j;
                for (size_t l = 0; l < 3; ++l) {
                    EXPECT_FALSE(cross2(tri[i][k], tri[i][(k + 1) % 3], tri[j][l], tri[j][(l + 1) % 3])) << i << " " << j;
                    dist = std::min({dist, pointToSegment(tri[i][k], tri[j][l], tri[j][(l + 1) % 3]),
                                     pointToSegment(tri[j][l], tri[i][k], tri[i][(k + 1) % 3])});
                }
            }
            EXPECT_GE(dist, gutter - 1e-6) << "charts " << i << " and " << j;
        }
}

// `count` one-triangle charts, x apart, with sizes from a fixed seed.
std::vector<AtlasChart> seededTriangles(int count, double x) {
    std::vector<AtlasChart> charts;
    uint64_t seed = 12345;
    auto next = [&] {
        seed = seed * 6364136223846793005ull + 1442695040888963407ull;
        return double(seed >> 11) / double(uint64_t(1) << 53);
    };
    for (int i = 0; i < count; ++i) {
        const double s = 0.05 + 0.3 * next(), t = 0.05 + 0.3 * next(), x0 = x * i;
        const double apex = x0 + 0.5 * s * next();
        charts.push_back(triangleChart({x0, 0}, {x0 + s, 0}, {apex, t}));
    }
    return charts;
}

}  // namespace

// Few charts (the order search applies): nine right triangles of different sizes and turns. The
// layout is the same for any thread count, and no two charts come closer than the gutter.
TEST(PackAtlas, FewChartsSameLayoutForAnyThreadCountAndKeepTheGutter) {
    std::vector<AtlasChart> charts;
    for (int i = 0; i < 9; ++i) {
        const double s = 0.1 + 0.05 * i, x = 0.7 * i;
        charts.push_back(triangleChart({x, 0}, i % 2 ? Vec2{x + s, s} : Vec2{x + s, 0}, {x, s}));
    }
    AtlasOptions o;
    o.maxTexelsPerUnit = 256;
    o.gutter = 2;
    const AtlasResult one = packedAlikeOnAnyThreads(charts, o, {2, 3});
    EXPECT_DOUBLE_EQ(one.texelsPerUnit, 256);
    EXPECT_GT(one.utilisation, 0.5);
    expectInsideAndApart(charts, one, 2);
}

// A page over 1024 texels across with hundreds of trials: trials and order swaps are ranked on a
// coarser grid first and only the near-best are packed on the search grid. The layout is still
// the same for any thread count, every chart keeps its gutter, and the page is no looser than the
// small page's packing of the same charts scaled up (utilisation within a few points).
TEST(PackAtlas, RankedSearchOnLargePagesKeepsTheLayoutAndTheGutter) {
    const std::vector<AtlasChart> charts = seededTriangles(8, 0.5);
    AtlasOptions o;
    o.maxTexelsPerUnit = 3072;
    o.gutter = 4;
    const AtlasResult large = packedAlikeOnAnyThreads(charts, o, {2});
    EXPECT_DOUBLE_EQ(large.texelsPerUnit, 3072);
    EXPECT_GT(std::max(large.width, large.height), 1024);
    expectInsideAndApart(charts, large, 4);
    o.maxTexelsPerUnit = 512;
    const AtlasResult small = packAtlas(charts, o);
    EXPECT_GT(large.utilisation, small.utilisation - 0.05);
}

// Enough charts for every search stage (orders, rules, strip widths, the local search of swaps),
// with sizes from a fixed seed. Trials that cannot beat the best finished one stop early, and the
// trials running at once share that best: the layout must still be the same for any thread count.
TEST(PackAtlas, TrialBoundsKeepTheLayoutForAnyThreadCount) {
    const std::vector<AtlasChart> charts = seededTriangles(24, 0.5);
    AtlasOptions o;
    o.maxTexelsPerUnit = 256;
    o.gutter = 4;
    const AtlasResult one = packedAlikeOnAnyThreads(charts, o, {2, 4});
    EXPECT_DOUBLE_EQ(one.texelsPerUnit, 256);
    EXPECT_GT(one.utilisation, 0.4);
}

// A caller that packs the same charts again hands packAtlas and atlasStartGutter the frames it
// found once: the page and every chart map are those found without them, for free and
// texel-aligned charts alike.
TEST(PackAtlas, GivenFramesPackAsFoundFrames) {
    const std::vector<AtlasChart> charts = seededTriangles(24, 0.5);
    for (bool aligned : {false, true}) {
        AtlasOptions o;
        o.maxTexelsPerUnit = aligned ? 1 : 256;
        o.gutter = 8;
        o.texelAligned = aligned;
        std::vector<AtlasChart> scaled = charts;
        if (aligned)
            for (AtlasChart& c : scaled) {
                for (Vec2& p : c.points) p = p * 200.0;
                for (auto& t : c.triangles) for (Vec2& p : t) p = p * 200.0;
                c.uvArea *= 200.0 * 200.0;
            }
        const std::vector<ChartFrame> frames = chartFrames(scaled, o);
        ASSERT_EQ(frames.size(), scaled.size());
        EXPECT_EQ(atlasStartGutter(scaled, o, &frames), atlasStartGutter(scaled, o));
        const AtlasResult found = packAtlas(scaled, o), given = packAtlas(scaled, o, &frames);
        EXPECT_EQ(given.width, found.width);
        EXPECT_EQ(given.height, found.height);
        EXPECT_EQ(given.texelsPerUnit, found.texelsPerUnit);
        for (size_t i = 0; i < scaled.size(); ++i) EXPECT_EQ(given.charts[i].m, found.charts[i].m) << "chart " << i;
    }
}

// shelfPackCapacity is the count shelfPack places on the page at some density: one more item
// with area never fits there.
TEST(ShelfPack, CapacityIsTheMostItemsThatFit) {
    for (int gutter : {0, 2, 4}) {
        const size_t capacity = shelfPackCapacity(64, gutter);
        std::vector<std::vector<Vec2>> squares(capacity + 1, std::vector<Vec2>{{0, 0}, {1, 0}, {1, 1}, {0, 1}});
        std::vector<const std::vector<Vec2>*> items;
        for (const auto& sq : squares) items.push_back(&sq);
        ShelfPackOptions o;
        o.size = 64;
        o.gutter = gutter;
        items.pop_back();
        EXPECT_EQ(shelfPack(items, double(items.size()), o).size, 64) << "gutter " << gutter;
        items.push_back(&squares.back());
        EXPECT_ANY_THROW(shelfPack(items, double(items.size()), o)) << "gutter " << gutter;
    }
}

// The T0 shelf packer: more items than a 64-texel page holds at any density (each box is at least
// 2 texels with 4-texel gutters: 10 x 10 of them; 12 x 12 would fit only at density 0) grow the
// page up to maxSize, and without maxSize they throw.
TEST(ShelfPack, ItemsThatDoNotFitAtOneTexelEachGrowThePage) {
    std::vector<std::vector<Vec2>> squares;
    for (int i = 0; i < 120; ++i) squares.push_back({{0, 0}, {1, 0}, {1, 1}, {0, 1}});
    std::vector<const std::vector<Vec2>*> items;
    for (const auto& s : squares) items.push_back(&s);
    ShelfPackOptions o;
    o.size = 64;
    EXPECT_ANY_THROW(shelfPack(items, 120, o));
    o.maxSize = 1024;
    const ShelfPackResult r = shelfPack(items, 120, o);
    EXPECT_EQ(r.size, 128);
    ASSERT_EQ(r.items.size(), items.size());
    for (size_t i = 0; i < items.size(); ++i)
        for (const Vec2& p : squares[i]) {
            const Vec2 uv = r.atlasUV(i, p);
            EXPECT_GT(uv.x, 0);
            EXPECT_LT(uv.x, 1);
            EXPECT_GT(uv.y, 0);
            EXPECT_LT(uv.y, 1);
        }
    o.size = 1024;  // a page that holds them keeps its side
    EXPECT_EQ(shelfPack(items, 120, o).size, 1024);
}
