// FaceGrid (lib/include/lodbake/core/face_grid.h): facesIn lists each face whose box meets the query
// box once, ascending; closestFaceIn finds the closest face of a subset through the grid as a scan
// of the subset in id order finds it, ties included, and FaceSetSearch does so for sets that hold
// index-degenerate faces too.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/parallel.h"
#include "synthetic_meshes.h"

using namespace lodbake;

namespace {

// Checks closestFaceIn against closestSurfacePoint for `points` over `faces` of `mesh`: the same
// face (so the same of equally close ones) and the same barycentrics, bit for bit.
void expectSameAsScan(const TriMesh& mesh, const FaceGrid& grid, const std::vector<uint32_t>& faces,
                      const std::vector<Vec3>& points, double radius) {
    for (const Vec3& p : points) {
        uint32_t scanFace = 0;
        std::array<double, 3> scanBary{};
        closestSurfacePoint(mesh, faces, p, scanFace, scanBary);
        size_t index = 0;
        std::array<double, 3> bary{};
        ASSERT_TRUE(closestFaceIn(mesh, grid, faces, p, radius, index, bary));
        ASSERT_LT(index, faces.size());
        EXPECT_EQ(faces[index], scanFace) << "at " << p.x << " " << p.y << " " << p.z;
        for (size_t k = 0; k < 3; ++k) EXPECT_EQ(bary[k], scanBary[k]);
    }
}

}  // namespace

// A bumpy 60 x 60 grid: a random half of its faces as the set, points above and beside it, on its
// vertices and edge midpoints (equally close to several faces), and far away (the box must grow).
TEST(FaceGrid, ClosestFaceInMatchesTheScanWithTies) {
    const TriMesh mesh = test::grid(60, 60, [](int i, int j) { return 0.3 * std::sin(0.4 * i) * std::cos(0.3 * j); });
    const FaceGrid grid(mesh);
    std::mt19937 rng(7);
    std::vector<uint32_t> half;
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f)
        if (rng() % 2) half.push_back(f);
    std::vector<Vec3> points;
    std::uniform_real_distribution<double> u(-5, 65), h(-2, 2);
    for (int i = 0; i < 300; ++i) points.push_back({u(rng), u(rng), h(rng)});
    for (uint32_t v = 0; v < mesh.vertexCount(); v += 7) points.push_back(mesh.positions[v]);
    for (uint32_t f = 0; f < mesh.triangleCount(); f += 11) {
        const Tri& t = mesh.triangles[f];
        points.push_back((mesh.positions[t[0]] + mesh.positions[t[1]]) * 0.5);
    }
    points.push_back({500, -300, 40});
    expectSameAsScan(mesh, grid, half, points, 1.0);
    expectSameAsScan(mesh, grid, half, points, 1e-6);  // a tiny first box only costs doublings
    // A set of one corner of the grid, queried from the far corner.
    std::vector<uint32_t> corner;
    for (uint32_t f = 0; f < 200; ++f) corner.push_back(f);
    expectSameAsScan(mesh, grid, corner, {Vec3{60, 60, 0}, Vec3{59.5, 0.5, 1}}, 1.0);
    // The faces numbered against the cells' order (the grid meets the higher id first), every
    // face in the set: at a vertex every face around it lies at distance 0 (exact ties), and the
    // box's faces keep the scan's lowest id.
    TriMesh reversed = mesh;
    std::reverse(reversed.triangles.begin(), reversed.triangles.end());
    const FaceGrid reversedGrid(reversed);
    std::vector<uint32_t> all(reversed.triangleCount());
    for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
    std::vector<Vec3> vertices;
    for (uint32_t v = 0; v < reversed.vertexCount(); v += 5) vertices.push_back(reversed.positions[v]);
    expectSameAsScan(reversed, reversedGrid, all, vertices, 1.0);
}

TEST(FaceGrid, ClosestFaceInOfNoFacesIsFalse) {
    const TriMesh mesh = test::grid(4, 4);
    const FaceGrid grid(mesh);
    size_t index = 0;
    std::array<double, 3> bary{};
    EXPECT_FALSE(closestFaceIn(mesh, grid, {}, Vec3{1, 1, 0}, 1.0, index, bary));
}

// facesIn against a scan of every face's box: boxes small and large (a face listed in many cells
// is listed once), inside, across and beyond the mesh; entriesIn counts at least the faces found.
TEST(FaceGrid, FacesInListsEveryOverlappingFaceOnceAscending) {
    const TriMesh mesh = test::grid(40, 40, [](int i, int j) { return 0.5 * std::sin(0.3 * i) * std::cos(0.2 * j); });
    const FaceGrid grid(mesh, 4.0);  // many cells per face: most faces span several cells
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-5, 45), half(0, 12), h(-1, 1);
    for (int q = 0; q < 200; ++q) {
        const Vec3 c{u(rng), u(rng), h(rng)};
        const double r = q % 10 == 0 ? 30.0 : half(rng);
        const Vec3 lo = c - Vec3{r, r, 0.2 * r}, hi = c + Vec3{r, r, 0.2 * r};
        std::vector<uint32_t> expected;
        for (uint32_t f = 0; f < mesh.triangleCount(); ++f) {
            const auto b = faceBox(mesh, f);
            if (b[0] <= hi.x && b[3] >= lo.x && b[1] <= hi.y && b[4] >= lo.y && b[2] <= hi.z && b[5] >= lo.z) expected.push_back(f);
        }
        EXPECT_EQ(grid.facesIn(lo, hi), expected) << "query " << q;
        EXPECT_GE(grid.entriesIn(lo, hi), expected.size());
    }
}

// A grid over a subset of the faces (every third) lists only the subset's faces that overlap the
// query box, ascending.
TEST(FaceGrid, GridOverASubsetListsOnlyItsFaces) {
    const TriMesh mesh = test::grid(30, 30, [](int i, int j) { return 0.4 * std::sin(0.3 * i) * std::cos(0.2 * j); });
    std::vector<uint32_t> held;
    for (uint32_t f = 0; f < mesh.triangleCount(); f += 3) held.push_back(f);
    const FaceGrid grid(mesh, held);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-5, 35), half(0, 10), h(-1, 1);
    for (int q = 0; q < 100; ++q) {
        const Vec3 c{u(rng), u(rng), h(rng)};
        const double r = half(rng);
        const Vec3 lo = c - Vec3{r, r, r}, hi = c + Vec3{r, r, r};
        std::vector<uint32_t> expected;
        for (uint32_t f : held) {
            const auto b = faceBox(mesh, f);
            if (b[0] <= hi.x && b[3] >= lo.x && b[1] <= hi.y && b[4] >= lo.y && b[2] <= hi.z && b[5] >= lo.z) expected.push_back(f);
        }
        EXPECT_EQ(grid.facesIn(lo, hi), expected) << "query " << q;
    }
}

// closestIn answers closestSurfacePoint over facesIn's list of the same box, bit for bit, ties
// included (points on vertices and edge midpoints of a bumpy grid), and says whether the box holds
// a face at all.
TEST(FaceGrid, ClosestInIsTheScanOfFacesIn) {
    const TriMesh mesh = test::grid(50, 40, [](int i, int j) { return 0.3 * std::sin(0.4 * i) * std::cos(0.3 * j); });
    const FaceGrid grid(mesh);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-5, 55), h(-2, 2), r(0.01, 4);
    std::vector<Vec3> points;
    for (int i = 0; i < 400; ++i) points.push_back({u(rng), u(rng), h(rng)});
    for (uint32_t v = 0; v < mesh.vertexCount(); v += 5) points.push_back(mesh.positions[v]);
    for (uint32_t f = 0; f < mesh.triangleCount(); f += 7) {
        const Tri& t = mesh.triangles[f];
        points.push_back((mesh.positions[t[0]] + mesh.positions[t[1]]) * 0.5);
    }
    for (const Vec3& p : points) {
        const double half = r(rng);
        const Vec3 lo = p - Vec3{half, half, half}, hi = p + Vec3{half, half, half};
        const std::vector<uint32_t> listed = grid.facesIn(lo, hi);
        uint32_t scanFace = UINT32_MAX, face = UINT32_MAX;
        std::array<double, 3> scanBary{}, bary{};
        const double scan = closestSurfacePoint(mesh, listed, p, scanFace, scanBary);
        bool any = false;
        const double d = grid.closestIn(mesh, lo, hi, p, face, bary, any);
        EXPECT_EQ(any, !listed.empty());
        EXPECT_EQ(d, scan);
        EXPECT_EQ(face, scanFace);
        for (size_t k = 0; k < 3; ++k) EXPECT_EQ(bary[k], scanBary[k]);
    }
}

// Index-degenerate faces (a corner repeated: the grid lists none) inside the sets, one of them a
// copy of a proper face's edge: the search still answers as the scan of each set does.
TEST(FaceGrid, FaceSetSearchMatchesTheScanWithDegenerateFaces) {
    TriMesh mesh = test::grid(30, 30, [](int i, int j) { return 0.2 * std::sin(0.5 * i + 0.2 * j); });
    const Tri& first = mesh.triangles[40];
    mesh.triangles.push_back({first[0], first[1], first[1]});  // lies on face 40's edge
    mesh.triangles.push_back({5, 5, 900});                     // a segment across the grid
    const uint32_t a = uint32_t(mesh.triangleCount() - 2), b = a + 1;
    std::vector<uint32_t> sets[3];
    for (uint32_t f = 0; f < a; ++f) sets[f % 3 == 0 ? 0 : 1].push_back(f);
    sets[0].push_back(a);
    sets[0].push_back(b);
    sets[2] = {b};
    FaceSetSearch search(mesh);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-3, 33), h(-1.5, 1.5);
    std::vector<Vec3> points;
    for (int i = 0; i < 200; ++i) points.push_back({u(rng), u(rng), h(rng)});
    for (uint32_t v = 0; v < mesh.vertexCount(); v += 13) points.push_back(mesh.positions[v]);
    points.push_back((mesh.positions[first[0]] + mesh.positions[first[1]]) * 0.5);
    for (const auto& faces : sets)
        for (const Vec3& p : points) {
            uint32_t want = 0, got = 0;
            std::array<double, 3> wantBary{}, gotBary{};
            const double d = closestSurfacePoint(mesh, faces, p, want, wantBary);
            ASSERT_EQ(search.closest(faces, p, got, gotBary), d);
            EXPECT_EQ(got, want) << "at " << p.x << " " << p.y << " " << p.z;
            EXPECT_EQ(gotBary, wantBary);
        }
    uint32_t f = 0;
    std::array<double, 3> bary{};
    EXPECT_EQ(search.closest({}, Vec3{}, f, bary), 1e300);
}

// Threads sharing one search (its grid and its sets' degenerate faces found by whichever thread
// asks first) answer as one thread alone does.
TEST(FaceGrid, FaceSetSearchSharedByThreadsAnswersAsAlone) {
    TriMesh mesh = test::grid(40, 40, [](int i, int j) { return 0.3 * std::cos(0.4 * i - 0.3 * j); });
    mesh.triangles.push_back({7, 7, 1200});  // index-degenerate
    std::vector<uint32_t> sets[4];
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f) sets[f % 4].push_back(f);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-2, 42), h(-1, 1);
    std::vector<Vec3> points;
    for (int i = 0; i < 2000; ++i) points.push_back({u(rng), u(rng), h(rng)});
    auto answers = [&](FaceSetSearch& search, int threads) {
        std::vector<std::pair<uint32_t, double>> out(points.size());
        parallelFor(points.size(), threads, [&](size_t i) {
            std::array<double, 3> bary{};
            out[i].second = search.closest(sets[i % 4], points[i], out[i].first, bary);
        });
        return out;
    };
    FaceSetSearch alone(mesh), shared(mesh);
    EXPECT_EQ(answers(shared, 2), answers(alone, 1));
}

// A grid built in parts (its faces counted and listed side by side) lists each cell's faces in
// ascending ids, as one pass over them does, whatever the threads: a point's cell is visited in
// ascending order, and any box's visits come in the same sequence on 1 and 3 threads.
TEST(FaceGrid, BuiltInPartsListsEachCellInFaceOrder) {
    const TriMesh mesh = test::grid(300, 300, [](int i, int j) { return 0.5 * std::sin(0.05 * i) * std::cos(0.07 * j); });
    ASSERT_GT(mesh.triangleCount(), 2u * 65536u);  // two parts or more
    const FaceGrid one(mesh, 1.0, 1), three(mesh, 1.0, 3);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-5, 305), r(0.1, 20);
    for (int q = 0; q < 200; ++q) {
        const Vec3 c{u(rng), u(rng), 0};
        std::vector<uint32_t> cell;
        three.forEachFaceIn(c, c, [&](uint32_t f) { cell.push_back(f); });
        EXPECT_TRUE(std::is_sorted(cell.begin(), cell.end()));
        const double h = r(rng);
        std::vector<uint32_t> a, b;
        one.forEachFaceIn(c - Vec3{h, h, 1}, c + Vec3{h, h, 1}, [&](uint32_t f) { a.push_back(f); });
        three.forEachFaceIn(c - Vec3{h, h, 1}, c + Vec3{h, h, 1}, [&](uint32_t f) { b.push_back(f); });
        ASSERT_EQ(a, b);
    }
}
