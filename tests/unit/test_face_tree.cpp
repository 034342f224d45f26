// FaceTree (lib/include/lodbake/core/face_tree.h): the closest point of a face set found through
// the tree is the one closestSurfacePoint's scan of the set in its order finds, ties included.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/face_tree.h"
#include "synthetic_meshes.h"

using namespace lodbake;

namespace {

// The same face (so the same of equally close ones), barycentrics and distance, bit for bit,
// without a hint and with the previous query's answer as the hint.
void expectSameAsScan(const TriMesh& mesh, const std::vector<uint32_t>& faces, const std::vector<Vec3>& points) {
    const FaceTree tree(mesh, faces);
    ASSERT_EQ(tree.size(), faces.size());
    uint32_t hint = UINT32_MAX;
    for (const Vec3& p : points) {
        uint32_t hintedFace = 0;
        std::array<double, 3> hintedBary{};
        const double hinted = tree.closest(p, hintedFace, hintedBary, hint);
        uint32_t scanFace = 0, treeFace = 0;
        std::array<double, 3> scanBary{}, treeBary{};
        const double scan = closestSurfacePoint(mesh, faces, p, scanFace, scanBary);
        const double d = tree.closest(p, treeFace, treeBary);
        EXPECT_EQ(d, scan);
        EXPECT_EQ(treeFace, scanFace) << "at " << p.x << " " << p.y << " " << p.z;
        for (size_t k = 0; k < 3; ++k) EXPECT_EQ(treeBary[k], scanBary[k]);
        EXPECT_EQ(hinted, scan);
        EXPECT_EQ(hintedFace, scanFace);
        ASSERT_LT(hint, faces.size());
        EXPECT_EQ(faces[hint], scanFace);
        for (size_t k = 0; k < 3; ++k) EXPECT_EQ(hintedBary[k], scanBary[k]);
    }
}

std::vector<Vec3> probes(const TriMesh& mesh, std::mt19937& rng) {
    std::uniform_real_distribution<double> u(-2, 62), h(-3, 3);
    std::vector<Vec3> points;
    for (int k = 0; k < 300; ++k) points.push_back({u(rng), u(rng), h(rng)});
    // On vertices and edge midpoints: equally close to several faces.
    for (size_t v = 0; v < mesh.positions.size(); v += 37) points.push_back(mesh.positions[v]);
    for (size_t f = 0; f < mesh.triangleCount(); f += 53) {
        const Tri& t = mesh.triangles[f];
        points.push_back((mesh.positions[t[0]] + mesh.positions[t[1]]) * 0.5);
    }
    points.push_back({500, -300, 40});  // far from every face
    return points;
}

}  // namespace

// A bumpy 60 x 60 grid; the whole face set in id order, a random half shuffled (ties then go to
// the earlier in the set's order, not the smaller id), and a set below the leaf size.
TEST(FaceTree, ClosestMatchesTheScanWithTies) {
    const TriMesh mesh = test::grid(60, 60, [](int i, int j) { return 0.3 * std::sin(0.4 * i) * std::cos(0.3 * j); });
    std::mt19937 rng(11);
    std::vector<uint32_t> all(mesh.triangleCount());
    for (uint32_t f = 0; f < all.size(); ++f) all[f] = f;
    expectSameAsScan(mesh, all, probes(mesh, rng));
    std::vector<uint32_t> half;
    for (uint32_t f : all)
        if (rng() % 2) half.push_back(f);
    std::shuffle(half.begin(), half.end(), rng);
    expectSameAsScan(mesh, half, probes(mesh, rng));
    expectSameAsScan(mesh, {half.begin(), half.begin() + 5}, probes(mesh, rng));
}

// A flat grid: many faces exactly equally close to points above their shared vertices.
TEST(FaceTree, ClosestOnAFlatGridKeepsTheScansTie) {
    const TriMesh mesh = test::grid(20, 20, [](int, int) { return 0.0; });
    std::vector<uint32_t> faces(mesh.triangleCount());
    for (uint32_t f = 0; f < faces.size(); ++f) faces[f] = uint32_t(faces.size() - 1 - f);
    std::vector<Vec3> points;
    for (const Vec3& v : mesh.positions) points.push_back(v + Vec3{0, 0, 1});
    expectSameAsScan(mesh, faces, points);
}

TEST(FaceTree, ClosestOfNoFacesIsFar) {
    const TriMesh mesh = test::grid(3, 3, [](int, int) { return 0.0; });
    const FaceTree tree(mesh, {});
    uint32_t face = 7;
    std::array<double, 3> bary{};
    EXPECT_GE(tree.closest({0, 0, 0}, face, bary), 1e300);
    EXPECT_EQ(face, 7u);
}
