// core/pose: TRS matrices, affine inverses, animation sampling and linear blend skinning, and the
// rig's round trip through a written glTF (writeGltf then readGltf keeps joints, weights and keys).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "lodbake/core/pose.h"
#include "lodbake/gltf/gltf.h"
#include "rig_fixtures.h"

using namespace lodbake;

namespace {

// One triangle bound to joint 1 (a child of joint 0 at x = 1), which turns 90 degrees about z
// between t = 0 and t = 1.
Asset turningTriangle() {
    Asset a;
    TriMesh& m = a.mesh;
    m.positions = {{1, 0, 0}, {2, 0, 0}, {1, 1, 0}};
    m.triangles = {{0, 1, 2}};
    m.cornerWedges = {{0, 1, 2}};
    m.triangleMaterial = {-1};
    m.wedges.vertex = {0, 1, 2};
    m.wedges.joints = {{1, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}};
    m.wedges.weights = {{1, 0, 0, 0}, {1, 0, 0, 0}, {0.5, 0.5, 0, 0}};
    a.rig = test::kneeRig("root", "arm", {0, 1}, {0, 90});
    return a;
}

TEST(Pose, InverseOfTrsIsIdentity) {
    Mat4 m = trsMatrix({1, 2, 3}, {0.2, -0.4, 0.1, 0.9}, {2, 0.5, 3}), inv;
    ASSERT_TRUE(invertAffine(m, inv));
    Mat4 id = mul(m, inv);
    for (size_t i = 0; i < 16; ++i) EXPECT_NEAR(id[i], identity4()[i], 1e-12);
    Mat4 singular = identity4();
    singular[5] = 0;
    EXPECT_FALSE(invertAffine(singular, inv));
}

TEST(Pose, RestPoseKeepsPositionsAndKeysMoveJoints) {
    Asset a = turningTriangle();
    TriMesh rest = poseMesh(a.rig, a.mesh, -1, 0);
    ASSERT_EQ(rest.positions.size(), 3u);
    for (size_t v = 0; v < 3; ++v) EXPECT_NEAR(length(rest.positions[v] - a.mesh.positions[v]), 0, 1e-12);
    // At t = 1 the arm has turned 90 degrees about z around (1, 0, 0): (2, 0, 0) -> (1, 1, 0).
    TriMesh end = poseMesh(a.rig, a.mesh, 0, 1);
    EXPECT_NEAR(length(end.positions[1] - Vec3{1, 1, 0}), 0, 1e-9);
    EXPECT_NEAR(length(end.positions[0] - Vec3{1, 0, 0}), 0, 1e-9);
    // Half weight on the arm: the average of (1, 1, 0) unmoved and turned (0, 0, 0).
    EXPECT_NEAR(length(end.positions[2] - Vec3{0.5, 0.5, 0}), 0, 1e-9);
    // Halfway: 45 degrees (spherical interpolation of the keys).
    TriMesh mid = poseMesh(a.rig, a.mesh, 0, 0.5);
    EXPECT_NEAR(length(mid.positions[1] - Vec3{1 + std::sqrt(0.5), std::sqrt(0.5), 0}), 0, 1e-9);
    // Before the first key and after the last: clamped.
    EXPECT_NEAR(length(poseMesh(a.rig, a.mesh, 0, 5).positions[1] - Vec3{1, 1, 0}), 0, 1e-9);
    TimeRange t = animationTimes(a.rig.animations[0]);
    EXPECT_EQ(t.start, 0);
    EXPECT_EQ(t.end, 1);
}

TEST(Pose, RigRoundTripsThroughGltf) {
    Asset a = turningTriangle();
    const std::string path = (std::filesystem::temp_directory_path() / "lodbake_pose_roundtrip.glb").string();
    writeGltf(path, a);
    Asset b = readGltf(path);
    std::filesystem::remove(path);
    ASSERT_EQ(b.rig.joints.size(), a.rig.joints.size());
    ASSERT_EQ(b.rig.nodes.size(), a.rig.nodes.size());
    ASSERT_EQ(b.rig.animations.size(), 1u);
    EXPECT_EQ(b.rig.nodes[1].parent, 0);
    EXPECT_EQ(b.rig.nodes[1].name, "arm");
    for (size_t j = 0; j < a.rig.joints.size(); ++j)
        for (size_t e = 0; e < 16; ++e) EXPECT_NEAR(b.rig.inverseBind[j][e], a.rig.inverseBind[j][e], 1e-7);
    ASSERT_EQ(b.mesh.wedges.joints.size(), b.mesh.wedges.size());
    // Posed the same at every key: the file keeps the skin's meaning.
    for (double t : {0.0, 0.5, 1.0}) {
        TriMesh pa = poseMesh(a.rig, a.mesh, 0, t), pb = poseMesh(b.rig, b.mesh, 0, t);
        Box3 ba = bounds(pa), bb = bounds(pb);
        EXPECT_NEAR(length(ba.min - bb.min) + length(ba.max - bb.max), 0, 1e-6) << "t = " << t;
    }
}

}  // namespace
