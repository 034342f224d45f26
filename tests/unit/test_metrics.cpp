// Unit tests of the metrics module on tiny synthetic meshes built in code.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

// CGAL's own AABB tree is the oracle of DistanceReference's closest points.
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "lodbake/core/errors.h"
#include "lodbake/metrics/compare.h"
#include "lodbake/metrics/distance.h"
#include "lodbake/metrics/image_metrics.h"
#include "lodbake/metrics/render.h"
#include "synthetic_meshes.h"

using namespace lodbake;

namespace {

// An axis-aligned box [0,sx] x [0,sy] x [0,sz], 12 triangles, outward CCW, one wedge per corner
// with uv0 (per face [0,1]^2) and the face normal.
TriMesh box(Vec3 size, Vec3 offset = {}) {
    TriMesh m;
    for (int i = 0; i < 8; ++i)
        m.positions.push_back(Vec3{(i & 1) * size.x, ((i >> 1) & 1) * size.y, ((i >> 2) & 1) * size.z} + offset);
    //   quads as (v0 v1 v2 v3) CCW from outside
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    const Vec2 uvs[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (const auto& q : quads) {
        Vec3 n = normalize(cross(m.positions[q[1]] - m.positions[q[0]], m.positions[q[2]] - m.positions[q[0]]));
        uint32_t w0 = static_cast<uint32_t>(m.wedges.size());
        for (int k = 0; k < 4; ++k) {
            m.wedges.vertex.push_back(q[k]);
            m.wedges.uv0.push_back(uvs[k]);
            m.wedges.normal.push_back(n);
        }
        m.triangles.push_back({uint32_t(q[0]), uint32_t(q[1]), uint32_t(q[2])});
        m.cornerWedges.push_back({w0, w0 + 1, w0 + 2});
        m.triangles.push_back({uint32_t(q[0]), uint32_t(q[2]), uint32_t(q[3])});
        m.cornerWedges.push_back({w0, w0 + 2, w0 + 3});
        m.triangleMaterial.push_back(0);
        m.triangleMaterial.push_back(0);
    }
    return m;
}

// A unit square in the plane z = h:
//   (0,1)---(1,1)
//     |   /   |
//   (0,0)---(1,0)
TriMesh square(double h) {
    TriMesh m;
    m.positions = {{0, 0, h}, {1, 0, h}, {1, 1, h}, {0, 1, h}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    m.cornerWedges = m.triangles;
    m.wedges.vertex = {0, 1, 2, 3};
    m.wedges.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    m.triangleMaterial = {0, 0};
    return m;
}

// An asset with one material whose base colour texture is image 0 (decoded pyramid given by hand).
Asset texturedAsset(const TriMesh& mesh) {
    Asset a;
    a.mesh = mesh;
    Material mat;
    mat.baseColor.texture = 0;
    a.materials.push_back(mat);
    a.textures.push_back(Texture{0, -1});
    Image img;
    img.width = img.height = 16;
    a.images.push_back(img);
    return a;
}

// A 16x16 linear-RGBA checkerboard (red/blue, 4x4 texel squares) or flat grey, with its pyramid.
MipImage pyramid(bool checker) {
    MipImage mip;
    for (int s = 16; s >= 1; s /= 2) {
        MipImage::Level l;
        l.width = l.height = s;
        for (int y = 0; y < s; ++y)
            for (int x = 0; x < s; ++x) {
                bool red = ((x * 16 / s) / 4 + (y * 16 / s) / 4) % 2 == 0;
                if (!checker || s < 8) red = false;
                float g = checker && s >= 8 ? 0.f : 0.25f;
                if (checker && s < 8) l.rgba.insert(l.rgba.end(), {0.5f, 0.f, 0.5f, 1.f});
                else if (checker) l.rgba.insert(l.rgba.end(), {red ? 1.f : 0.f, g, red ? 0.f : 1.f, 1.f});
                else l.rgba.insert(l.rgba.end(), {0.25f, 0.25f, 0.25f, 1.f});
            }
        mip.levels.push_back(l);
    }
    return mip;
}

RenderScene sceneOf(const Asset& a, bool checker) {
    RenderScene s;
    s.asset = &a;
    s.mesh = &a.mesh;
    s.images = {pyramid(checker)};
    return s;
}

}  // namespace

// --- geometric distance -------------------------------------------------------------------

TEST(SurfaceDistance, IdenticalMeshesAreAtZero) {
    TriMesh m = box({1, 2, 3});
    GeometricDistance d = surfaceDistance(m, m, DistanceOptions{20000});
    EXPECT_EQ(d.hausdorff, 0.0);
    EXPECT_EQ(d.rms, 0.0);
    EXPECT_NEAR(d.diagonal, std::sqrt(14.0), 1e-12);
    EXPECT_EQ(d.aToB.samples, 20000u + 8u);  // area samples + vertices
}

TEST(SurfaceDistance, ParallelSquaresAreTheirSeparationApart) {
    GeometricDistance d = surfaceDistance(square(0), square(0.25), DistanceOptions{5000});
    EXPECT_NEAR(d.hausdorff, 0.25, 1e-12);
    EXPECT_NEAR(d.mean, 0.25, 1e-12);
    EXPECT_NEAR(d.rms, 0.25, 1e-12);
    EXPECT_NEAR(d.relHausdorff, 0.25 / std::sqrt(2.0), 1e-12);
}

TEST(SurfaceDistance, ShiftByOnePercentOfDiagonalGivesOnePercentHausdorff) {
    TriMesh a = box({1, 2, 3});
    double shift = 0.01 * std::sqrt(14.0);
    TriMesh b = box({1, 2, 3}, {shift, 0, 0});
    GeometricDistance d = surfaceDistance(a, b, DistanceOptions{50000});
    EXPECT_NEAR(d.relHausdorff, 0.01, 1e-9);
    EXPECT_GT(d.rms, 0.0);
    EXPECT_LT(d.rms, shift);  // most of the surface slides within itself
}

TEST(SurfaceDistance, ResultDoesNotDependOnThreads) {
    TriMesh a = box({1, 2, 3});
    TriMesh b = box({1.1, 2, 2.9}, {0.01, -0.02, 0.03});
    DistanceOptions o1{30000}, o2{30000};
    o1.threads = 1;
    o2.threads = 3;
    GeometricDistance d1 = surfaceDistance(a, b, o1), d2 = surfaceDistance(a, b, o2);
    EXPECT_EQ(d1.hausdorff, d2.hausdorff);
    EXPECT_EQ(d1.mean, d2.mean);
    EXPECT_EQ(d1.rms, d2.rms);
}

TEST(SurfaceDistance, DegenerateMeshIsImpossible) {
    TriMesh a = square(0);
    TriMesh flat = a;
    flat.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}};  // collinear: zero area
    EXPECT_THROW(surfaceDistance(a, flat), Impossible);
}

TEST(SurfaceDistance, ReferenceReusedGivesTheSameFigures) {
    const TriMesh a = box({1, 2, 3});
    const DistanceReference reference(a);
    for (double shift : {0.01, 0.2}) {
        const TriMesh b = box({1.1, 2, 2.9}, {shift, -0.02, 0.03});
        const DistanceOptions o{20000};
        const GeometricDistance once = surfaceDistance(a, b, o), shared = surfaceDistance(reference, b, o);
        EXPECT_EQ(once.hausdorff, shared.hausdorff);
        EXPECT_EQ(once.mean, shared.mean);
        EXPECT_EQ(once.rms, shared.rms);
        EXPECT_EQ(once.relHausdorff, shared.relHausdorff);
        EXPECT_EQ(once.aToB.samples, shared.aToB.samples);
    }
    EXPECT_THROW(DistanceReference(TriMesh{}), Impossible);
}

TEST(SurfaceDistance, ReferenceClosestPointLiesOnTheSurface) {
    const DistanceReference reference(box({1, 2, 3}));
    const Vec3 outside = reference.closestPoint({0.5, 1, 4});  // above the top face
    EXPECT_NEAR(length(outside - Vec3{0.5, 1, 3}), 0, 1e-12);
    const Vec3 inside = reference.closestPoint({0.9, 1, 1.5});  // nearest the x = 1 face
    EXPECT_NEAR(length(inside - Vec3{1, 1, 1.5}), 0, 1e-12);
}

// Many queries at once (a walk that starts each search from the previous answer) give each
// query's own closest point, for any thread count.
TEST(SurfaceDistance, ReferenceClosestPointsAreEachPointsClosestPoint) {
    const DistanceReference reference(box({1, 2, 3}));
    std::vector<Vec3> points;
    for (int i = 0; i < 9000; ++i)  // a spiral around and through the box: near and far in turn
        points.push_back({0.5 + 1.5 * std::cos(0.01 * i), 1 + 2.5 * std::sin(0.013 * i), 1.5 + 2 * std::sin(0.003 * i)});
    const std::vector<Vec3> one = reference.closestPoints(points, 1), two = reference.closestPoints(points, 2);
    ASSERT_EQ(one.size(), points.size());
    for (size_t i = 0; i < points.size(); ++i) {
        EXPECT_NEAR(length(one[i] - points[i]), length(reference.closestPoint(points[i]) - points[i]), 1e-12);
        EXPECT_EQ(one[i].x, two[i].x);
        EXPECT_EQ(one[i].y, two[i].y);
        EXPECT_EQ(one[i].z, two[i].z);
    }
}

// A coarse level far from a bumpy original everywhere (every run of samples is "hot"): the
// refined measure keeps the exhaustive maximum while querying only the samples that the strided
// ones' distance bound cannot rule out.
TEST(SurfaceDistance, RefinedMaximumIsTheExhaustiveOneWithFewerQueries) {
    TriMesh bumpy;
    const int n = 24;
    for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x)
            bumpy.positions.push_back({double(x) / n, double(y) / n, 0.04 * std::sin(9.0 * x / n) * std::cos(7.0 * y / n)});
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const uint32_t v = uint32_t(y * (n + 1) + x);
            bumpy.triangles.push_back({v, v + 1, v + uint32_t(n) + 2});
            bumpy.triangles.push_back({v, v + uint32_t(n) + 2, v + uint32_t(n) + 1});
        }
    const TriMesh coarse = square(0.3);
    DistanceOptions exhaustive{40000}, refined{40000};
    refined.refineStride = 16;
    const GeometricDistance e = surfaceDistance(bumpy, coarse, exhaustive), r = surfaceDistance(bumpy, coarse, refined);
    EXPECT_EQ(r.aToB.max, e.aToB.max);
    EXPECT_EQ(r.bToA.max, e.bToA.max);
    EXPECT_EQ(r.hausdorff, e.hausdorff);
    EXPECT_LT(10 * (r.aToB.samples + r.bToA.samples), 6 * (e.aToB.samples + e.bToA.samples));
}

// A measure bounded by stopAbove stops exactly when the full Hausdorff distance exceeds the bound
// (whatever the threads), and otherwise gives the full figures.
TEST(SurfaceDistance, BoundedMeasureStopsExactlyAboveTheBound) {
    const TriMesh a = square(0), b = square(0.25);
    for (size_t stride : {size_t(1), size_t(8)}) {
        DistanceOptions o{20000};
        o.refineStride = stride;
        const GeometricDistance full = surfaceDistance(a, b, o);
        EXPECT_FALSE(full.stopped);
        for (double bound : {0.0, 0.5 * full.hausdorff, full.hausdorff, 2 * full.hausdorff})
            for (int threads : {1, 3}) {
                DistanceOptions bounded = o;
                bounded.stopAbove = bound;
                bounded.threads = threads;
                const GeometricDistance d = surfaceDistance(a, b, bounded);
                EXPECT_EQ(d.stopped, full.hausdorff > bound) << "bound " << bound;
                if (d.stopped) {
                    EXPECT_GT(d.hausdorff, bound);
                } else {
                    EXPECT_EQ(d.hausdorff, full.hausdorff);
                    EXPECT_EQ(d.rms, full.rms);
                    EXPECT_EQ(d.mean, full.mean);
                }
            }
    }
}

// DistanceReference's closest points are those of CGAL's AABB tree over the same triangles, bit
// for bit, ties included: points above a flat grid's vertices and edges are equally close to
// several faces (whose projections can differ in the last bit), and points of a bumpy grid; with
// and without `near` points (good ones, the answers themselves, and far ones), on 1 and 3 threads.
TEST(SurfaceDistance, ClosestPointsAreCgalTreesTiesIncluded) {
    using K = CGAL::Simple_cartesian<double>;
    using Triangles = std::vector<K::Triangle_3>;
    using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>>>;
    for (bool flat : {true, false}) {
        const TriMesh mesh = test::grid(40, 30, [&](int i, int j) { return flat ? 0.0 : 0.3 * std::sin(0.4 * i) * std::cos(0.3 * j); });
        Triangles triangles;
        for (const Tri& t : mesh.triangles) {
            const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
            triangles.emplace_back(K::Point_3(a.x, a.y, a.z), K::Point_3(b.x, b.y, b.z), K::Point_3(c.x, c.y, c.z));
        }
        const Tree tree(triangles.begin(), triangles.end());
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> u(-3, 43), h(-2, 2);
        std::vector<Vec3> points;
        for (int i = 0; i < 2000; ++i) points.push_back({u(rng), u(rng), h(rng)});
        for (uint32_t v = 0; v < mesh.vertexCount(); v += 3) points.push_back(mesh.positions[v] + Vec3{0.1, -0.05, 0.7});
        for (uint32_t f = 0; f < mesh.triangleCount(); f += 2) {
            const Tri& t = mesh.triangles[f];
            points.push_back((mesh.positions[t[0]] + mesh.positions[t[1]]) * 0.5 + Vec3{0, 0, 0.37});
            points.push_back((mesh.positions[t[1]] + mesh.positions[t[2]]) * 0.5 + Vec3{0.01, 0, 1.3});
        }
        const DistanceReference reference(mesh);
        const std::vector<Vec3> answers = reference.closestPoints(points, 1);
        std::vector<Vec3> far(points.size(), mesh.positions[0]);
        for (size_t i = 0; i < points.size(); i += 2) far[i] = Vec3{std::nan(""), 0, 0};
        for (const std::vector<Vec3>& near : {std::vector<Vec3>{}, answers, far})
            for (int threads : {1, 3}) {
                const std::vector<Vec3> got = reference.closestPoints(points, threads, near);
                for (size_t i = 0; i < points.size(); ++i) {
                    const K::Point_3 c = tree.closest_point(K::Point_3(points[i].x, points[i].y, points[i].z));
                    ASSERT_EQ(got[i].x, c.x()) << i;
                    ASSERT_EQ(got[i].y, c.y()) << i;
                    ASSERT_EQ(got[i].z, c.z()) << i;
                }
            }
        const Vec3 one = reference.closestPoint(points[5]);
        EXPECT_EQ(one.x, answers[5].x);
        EXPECT_EQ(one.y, answers[5].y);
        EXPECT_EQ(one.z, answers[5].z);
    }
}

// --- rendering and image metrics ----------------------------------------------------------

TEST(Render, SquareSeenFromAboveCoversTheCentre) {
    Asset a = texturedAsset(square(0));
    RenderScene s = sceneOf(a, true);
    Camera c;
    c.eye = {0.5, 0.5, 2};
    c.target = {0.5, 0.5, 0};
    Rendering r = render(s, c, RenderOptions{64, 64, RenderMode::Shaded});
    EXPECT_EQ(r.coverage[32 * 64 + 32], 1);
    EXPECT_EQ(r.coverage[0], 0);
    // Headlight straight on: grey = 0.8 (linear) -> sRGB.
    EXPECT_NEAR(r.rgb[(32 * 64 + 32) * 3], 0.9063, 1e-3);
    // Seen from below, the single-sided square is culled.
    c.eye = {0.5, 0.5, -2};
    Rendering back = render(s, c, RenderOptions{64, 64, RenderMode::Shaded});
    EXPECT_EQ(back.coverage[32 * 64 + 32], 0);
}

TEST(Render, TextureSeamsAreTheEdgesWhoseUvsJump) {
    const TriMesh m = test::seamGrid(8);
    const std::vector<uint8_t> seams = textureSeamEdges(m);
    ASSERT_EQ(seams.size(), m.triangles.size());
    size_t marked = 0;
    for (size_t f = 0; f < m.triangles.size(); ++f)
        for (int k = 0; k < 3; ++k) {
            if (!(seams[f] & (1u << k))) continue;
            ++marked;
            // A marked edge runs along the seam column x = 4.
            EXPECT_EQ(m.positions[m.triangles[f][size_t(k)]].x, 4.0);
            EXPECT_EQ(m.positions[m.triangles[f][size_t((k + 1) % 3)]].x, 4.0);
        }
    EXPECT_EQ(marked, 16u);  // 8 edges on the column, each from both sides
    EXPECT_EQ(textureSeamEdges(square(0)), std::vector<uint8_t>(2, 0));
}

TEST(Render, SeamBandMarksThePixelsNearAVisibleSeamOnly) {
    TriMesh split = square(0);
    // The second triangle gets its own wedges with shifted UVs: the diagonal becomes a seam.
    split.wedges.vertex = {0, 1, 2, 3, 0, 2};
    split.wedges.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}, {0.5, 1}, {1.5, 0}};
    split.cornerWedges = {{0, 1, 2}, {4, 5, 3}};
    Camera c;
    c.eye = {0.5, 0.5, 2};
    c.target = {0.5, 0.5, 0};
    for (bool seamed : {false, true}) {
        Asset a = texturedAsset(seamed ? split : square(0));
        RenderScene s = sceneOf(a, true);
        s.seamEdges = textureSeamEdges(a.mesh);
        const Rendering r = render(s, c, RenderOptions{64, 64, RenderMode::BaseColor});
        size_t near = 0, far = 0;
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < 64; ++x) {
                if (!r.seam[size_t(y) * 64 + size_t(x)]) continue;
                // The diagonal runs through the image corners (0, 0)-(1, 1) of the square: on
                // screen from bottom-left to top-right, about where x + y = 63.
                (std::abs(x + y - 63) <= 8 ? near : far) += 1;
            }
        EXPECT_EQ(far, 0u);
        if (seamed) EXPECT_GT(near, 20u);
        else EXPECT_EQ(near, 0u);
        const ImageMetrics m = compareImages(r, r);
        EXPECT_EQ(m.seamPixels, near);
        EXPECT_EQ(m.seamPsnr, kMaxPsnr);
    }
}

TEST(Render, SphereViewsAreDeterministicAndFrameTheSphere) {
    std::vector<Camera> v = sphereViews(16, {1, 2, 3}, 2);
    ASSERT_EQ(v.size(), 16u);
    for (const Camera& c : v) EXPECT_NEAR(length(c.eye - Vec3{1, 2, 3}), 4.0, 1e-9);  // r / sin(30 deg)
    EXPECT_EQ(sphereViews(16, {1, 2, 3}, 2)[5].eye.x, v[5].eye.x);
}

TEST(ImageMetrics, ModelAgainstItselfIsPerfect) {
    Asset a = texturedAsset(box({1, 1, 1}));
    RenderScene s = sceneOf(a, true);
    ImageMetrics total;
    for (const Camera& c : sphereViews(6, {0.5, 0.5, 0.5}, 0.87))
        for (RenderMode mode : {RenderMode::BaseColor, RenderMode::Shaded}) {
            Rendering r1 = render(s, c, RenderOptions{64, 64, mode});
            Rendering r2 = render(s, c, RenderOptions{64, 64, mode});
            accumulate(total, compareImages(r1, r2));
        }
    EXPECT_EQ(total.psnr, kMaxPsnr);
    EXPECT_EQ(total.iou, 1.0);
    EXPECT_NEAR(total.ssim, 1.0, 1e-12);
    EXPECT_GT(total.unionPixels, 0u);
}

TEST(ImageMetrics, FlatGreyTextureLowersBaseColourPsnrOnly) {
    Asset a = texturedAsset(box({1, 1, 1}));
    RenderScene checker = sceneOf(a, true), grey = sceneOf(a, false);
    ImageMetrics base, shaded;
    for (const Camera& c : sphereViews(6, {0.5, 0.5, 0.5}, 0.87)) {
        accumulate(base, compareImages(render(checker, c, {64, 64, RenderMode::BaseColor}),
                                       render(grey, c, {64, 64, RenderMode::BaseColor})));
        accumulate(shaded, compareImages(render(checker, c, {64, 64, RenderMode::Shaded}),
                                         render(grey, c, {64, 64, RenderMode::Shaded})));
    }
    EXPECT_LT(base.psnr, 10.0);
    EXPECT_LT(base.ssim, 0.9);
    EXPECT_EQ(base.iou, 1.0);
    EXPECT_EQ(shaded.psnr, kMaxPsnr);
}

TEST(ImageMetrics, DisjointSilhouettesHaveZeroIou) {
    Rendering a, b;
    a.width = b.width = a.height = b.height = 8;
    a.rgb.assign(8 * 8 * 3, 0.f);
    b.rgb = a.rgb;
    a.coverage.assign(64, 0);
    b.coverage.assign(64, 0);
    a.coverage[0] = 1;
    b.coverage[63] = 1;
    ImageMetrics m = compareImages(a, b);
    EXPECT_EQ(m.iou, 0.0);
    EXPECT_EQ(m.unionPixels, 2u);
}

TEST(CompareAssets, CountsAndNoImagesWithoutViews) {
    Asset a;
    a.mesh = box({1, 1, 1});
    a.materials.resize(1);
    CompareOptions o;
    o.views = 0;
    o.distance.samplesPerSide = 1000;
    CompareResult r = compareAssets(a, a.mesh, a, a.mesh, o);
    EXPECT_EQ(r.a.triangles, 12u);
    EXPECT_EQ(r.a.positions, 8u);
    EXPECT_EQ(r.a.vertices, 24u);
    EXPECT_EQ(r.a.materials, 1u);
    EXPECT_EQ(r.a.drawCalls, 1u);
    EXPECT_EQ(r.distance.hausdorff, 0.0);
    EXPECT_EQ(r.baseColor.views, 0u);
}
