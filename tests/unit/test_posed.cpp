// Rigged meshes simplified against sampled poses: the sampled times (core/pose_samples), the
// posed wedges and their rigid joints, and simplify's posed measure on a tube bent at a knee.
#include <gtest/gtest.h>

#include <cmath>

#include "lodbake/core/pose.h"
#include "lodbake/core/pose_samples.h"
#include "lodbake/metrics/distance.h"
#include "lodbake/metrics/posed_distance.h"
#include "lodbake/simplify/simplify.h"
#include "rig_fixtures.h"

using namespace lodbake;

namespace {

// A closed tube of radius 0.1 along x from 0 to 2 (41 rings of 16 vertices, capped by one vertex at
// each end), bound to a thigh joint at the origin and a shin joint at x = 1 that bends 90 degrees
// about z from t = 0 to t = 1 (keys at 0, 0.5, 1). Weights go linearly from the thigh to the shin
// over x in [0.8, 1.2]; one wedge per vertex.
//
//   thigh ==========[blend]========== shin
//   x = 0          0.8  1  1.2              2
Asset bentTube() {
    Asset a;
    TriMesh& m = a.mesh;
    constexpr int kRings = 41, kSides = 16;
    for (int r = 0; r < kRings; ++r)
        for (int s = 0; s < kSides; ++s) {
            const double t = 2 * kPi * s / kSides;
            m.positions.push_back({2.0 * r / (kRings - 1), 0.1 * std::cos(t), 0.1 * std::sin(t)});
        }
    const uint32_t capA = uint32_t(m.positions.size());
    m.positions.push_back({0, 0, 0});
    const uint32_t capB = uint32_t(m.positions.size());
    m.positions.push_back({2, 0, 0});
    auto id = [&](int r, int s) { return uint32_t(r * kSides + (s % kSides)); };
    for (int r = 0; r + 1 < kRings; ++r)
        for (int s = 0; s < kSides; ++s) {
            m.triangles.push_back({id(r, s), id(r + 1, s), id(r + 1, s + 1)});
            m.triangles.push_back({id(r, s), id(r + 1, s + 1), id(r, s + 1)});
        }
    for (int s = 0; s < kSides; ++s) {
        m.triangles.push_back({capA, id(0, s), id(0, s + 1)});
        m.triangles.push_back({capB, id(kRings - 1, s + 1), id(kRings - 1, s)});
    }
    m.cornerWedges = m.triangles;
    m.triangleMaterial.assign(m.triangles.size(), -1);
    for (uint32_t v = 0; v < m.positions.size(); ++v) {
        m.wedges.vertex.push_back(v);
        const double shin = std::clamp((m.positions[v].x - 0.8) / 0.4, 0.0, 1.0);
        m.wedges.joints.push_back({0, 1, 0, 0});
        m.wedges.weights.push_back({1 - shin, shin, 0, 0});
    }
    a.rig = test::kneeRig("thigh", "shin", {0, 0.5, 1}, {0, 45, 90});
    return a;
}

// The largest distance, over the sampled poses, of an original vertex to the posed level (model units).
double posedVertexDeviation(const Asset& a, const Level& level, const std::vector<PoseSample>& poses) {
    TriMesh coarse = a.mesh;
    coarse.triangles = level.triangles;
    coarse.cornerWedges = level.cornerWedges;
    DistanceOptions vertices;
    vertices.samplesPerSide = 0;  // vertices only: what simplify's deviation bounds
    double worst = 0;
    for (const PoseSample& s : poses)
        worst = std::max(worst, surfaceDistance(poseMesh(a.rig, a.morph, a.mesh, s.animation, s.time),
                                                poseMesh(a.rig, a.morph, coarse, s.animation, s.time), vertices).aToB.max);
    return worst;
}

}  // namespace

TEST(PoseSamples, RestPoseThenEvenTimesOfEachAnimation) {
    Asset a = bentTube();
    std::vector<PoseSample> p = samplePoses(a.rig, {});
    ASSERT_EQ(p.size(), 6u);
    EXPECT_EQ(p[0].animation, -1);
    const double times[] = {0, 0.25, 0.5, 0.75, 1};
    for (size_t k = 0; k < 5; ++k) {
        EXPECT_EQ(p[k + 1].animation, 0);
        EXPECT_DOUBLE_EQ(p[k + 1].time, times[k]);
    }
    // Many animations share maxPoses: each keeps at least its middle.
    a.rig.animations.resize(40, a.rig.animations[0]);
    PoseSampleOptions o;
    o.maxPoses = 16;
    p = samplePoses(a.rig, o);
    EXPECT_EQ(p.size(), 16u);
    EXPECT_DOUBLE_EQ(p[1].time, 0.5);
    o.perAnimation = 0;
    EXPECT_TRUE(samplePoses(a.rig, o).empty());
    EXPECT_TRUE(samplePoses(Rig{}, {}).empty());
}

TEST(PoseSamples, PosedWedgesMatchPoseMeshAndRigidJoints) {
    Asset a = bentTube();
    const std::vector<PoseSample> poses = samplePoses(a.rig, {});
    PosedWedges posed = poseWedges(a.rig, a.morph, a.mesh, poses);
    ASSERT_EQ(posed.positions.size(), poses.size());
    const TriMesh end = poseMesh(a.rig, a.morph, a.mesh, 0, 1);
    for (uint32_t w = 0; w < a.mesh.wedges.size(); ++w) {
        EXPECT_NEAR(length(posed.positions.back()[w] - end.positions[end.wedges.vertex[w]]), 0, 1e-12);
        const Vec4& q = a.mesh.wedges.weights[w];
        const uint32_t expected = q.y == 0 ? 0u : q.x == 0 ? 1u : PosedWedges::kNotRigid;
        EXPECT_EQ(posed.rigidJoint[w], expected) << a.mesh.positions[w].x;
    }
    // The shin turns 90 degrees at t = 1: the tube's end goes from (2, 0, 0) to (1, 1, 0).
    EXPECT_NEAR(length(posed.positions.back()[a.mesh.wedges.size() - 1] - Vec3{1, 1, 0}), 0, 1e-9);
}

// Without posed wedges a level is measured flat (the tube is straight in the bind pose): its
// chords across the knee stick out when the knee bends, beyond its reported maxDeviation. With
// them, every original vertex stays within the level's maxDeviation at every sampled pose, and so
// does the sampled two-sided distance (to the sampling's precision), far below the flat level's.
TEST(SimplifyPosed, LevelsStayWithinTheirDeviationWhenPosed) {
    const Asset a = bentTube();
    const std::vector<PoseSample> poses = samplePoses(a.rig, {});
    SimplifyOptions bind;
    bind.levels = {{0.5, 0, 0}, {0.1, 0, 0}};
    bind.maxInfluenceChange = 1;  // the influence rule off: only the posed measure guards the knee
    SimplifyOptions posedOptions = bind;
    posedOptions.posed = poseWedges(a.rig, a.morph, a.mesh, poses);
    const SimplifyResult flat = simplify(a.mesh, bind);
    const SimplifyResult posed = simplify(a.mesh, posedOptions);
    ASSERT_EQ(posed.multires.levels.size(), 2u);
    for (size_t k = 0; k < 2; ++k) {
        const Level& L = posed.multires.levels[k];
        const Level& F = flat.multires.levels[k];
        EXPECT_EQ(L.triangles.size(), F.triangles.size());
        const double posedDev = posedVertexDeviation(a, L, poses), flatDev = posedVertexDeviation(a, F, poses);
        EXPECT_LE(posedDev, L.maxDeviation * (1 + 1e-9) + 1e-12) << "level " << k + 1;
        EXPECT_LT(posedDev, flatDev) << "level " << k + 1;
        EXPECT_GT(flatDev, F.maxDeviation) << "level " << k + 1;
        // Both sides, sampled: what compare measures of the posed levels.
        TriMesh lm = a.mesh, fm = a.mesh;
        lm.triangles = L.triangles;
        lm.cornerWedges = L.cornerWedges;
        fm.triangles = F.triangles;
        fm.cornerWedges = F.cornerWedges;
        DistanceOptions d;
        d.samplesPerSide = 2000;
        d.threads = 1;
        const double hl = posedSurfaceDistance(a.rig, a.morph, a.mesh, lm, poses, d).hausdorff;
        const double hf = posedSurfaceDistance(a.rig, a.morph, a.mesh, fm, poses, d).hausdorff;
        EXPECT_LE(hl, 1.1 * L.maxDeviation + 1e-12) << "level " << k + 1;
        EXPECT_LT(hl, hf) << "level " << k + 1;
        // One reference for both levels (the original's posed trees built once): the same figures.
        PosedDistanceReference reference(a.rig, a.morph, a.mesh, poses);
        EXPECT_EQ(reference.distance(lm, d).hausdorff, hl) << "level " << k + 1;
        EXPECT_EQ(reference.distance(fm, d).hausdorff, hf) << "level " << k + 1;
        EXPECT_EQ(reference.distance(lm, d).rms, posedSurfaceDistance(a.rig, a.morph, a.mesh, lm, poses, d).rms);
    }
}

// A pose repeated (a looping animation's last key) or one that leaves the tube as bound measures
// nothing new: the figures are those of the poses without it, refined or not.
TEST(PosedDistance, RepeatedPosesMeasureTheSame) {
    const Asset a = bentTube();
    const std::vector<PoseSample> poses = samplePoses(a.rig, {});
    ASSERT_GE(poses.size(), 2u);
    std::vector<PoseSample> repeated = poses;
    repeated.insert(repeated.begin() + 1, poses.back());
    repeated.push_back(poses[1]);
    SimplifyOptions so;
    so.levels = {{0.1, 0, 0}};
    so.posed = poseWedges(a.rig, a.morph, a.mesh, poses);
    const SimplifyResult simplified = simplify(a.mesh, so);
    const Level& L = simplified.multires.levels[0];
    TriMesh lm = a.mesh;
    lm.triangles = L.triangles;
    lm.cornerWedges = L.cornerWedges;
    for (size_t stride : {size_t(1), size_t(8)}) {
        DistanceOptions d;
        d.samplesPerSide = 4000;
        d.threads = 1;
        d.refineStride = stride;
        const GeometricDistance once = posedSurfaceDistance(a.rig, a.morph, a.mesh, lm, poses, d);
        const GeometricDistance twice = posedSurfaceDistance(a.rig, a.morph, a.mesh, lm, repeated, d);
        EXPECT_EQ(once.hausdorff, twice.hausdorff) << "stride " << stride;
        EXPECT_EQ(once.rms, twice.rms) << "stride " << stride;
        EXPECT_EQ(once.mean, twice.mean) << "stride " << stride;
        EXPECT_GT(once.hausdorff, surfaceDistance(a.mesh, lm, d).hausdorff) << "stride " << stride;
    }
}

// A posed measure bounded by stopAbove stops at the first pose above the bound, exactly when the
// full figures' Hausdorff distance exceeds it; below, it gives the full figures.
TEST(PosedDistance, BoundedMeasureStopsExactlyAboveTheBound) {
    const Asset a = bentTube();
    const std::vector<PoseSample> poses = samplePoses(a.rig, {});
    SimplifyOptions so;
    so.levels = {{0.1, 0, 0}};
    so.posed = poseWedges(a.rig, a.morph, a.mesh, poses);
    const SimplifyResult simplified = simplify(a.mesh, so);
    const Level& L = simplified.multires.levels[0];
    TriMesh lm = a.mesh;
    lm.triangles = L.triangles;
    lm.cornerWedges = L.cornerWedges;
    DistanceOptions d;
    d.samplesPerSide = 4000;
    d.refineStride = 8;
    d.threads = 1;
    const GeometricDistance full = posedSurfaceDistance(a.rig, a.morph, a.mesh, lm, poses, d);
    const double bind = surfaceDistance(a.mesh, lm, d).hausdorff;
    ASSERT_GT(full.hausdorff, bind);
    for (double bound : {0.5 * bind, 0.5 * (bind + full.hausdorff), full.hausdorff}) {
        DistanceOptions bounded = d;
        bounded.stopAbove = bound;
        const GeometricDistance g = posedSurfaceDistance(a.rig, a.morph, a.mesh, lm, poses, bounded);
        EXPECT_EQ(g.stopped, full.hausdorff > bound) << "bound " << bound;
        if (g.stopped) {
            EXPECT_GT(g.hausdorff, bound);
        } else {
            EXPECT_EQ(g.hausdorff, full.hausdorff);
            EXPECT_EQ(g.rms, full.rms);
        }
    }
    // Taken a pose at a time: running figures never above the full ones, the full ones at the end.
    PosedDistanceReference reference(a.rig, a.morph, a.mesh, poses);
    PosedDistanceReference::Measure m = reference.measure(lm);
    size_t steps = 0;
    for (; !m.done(); ++steps) {
        m.step(d);
        EXPECT_LE(m.figures().hausdorff, full.hausdorff);
    }
    EXPECT_EQ(steps, poses.size() + 1);
    EXPECT_EQ(m.figures().hausdorff, full.hausdorff);
    EXPECT_EQ(m.figures().rms, full.rms);
    EXPECT_EQ(m.figures().relMean, full.relMean);
}

// The influence rule's default: with sampled animation poses the posed measure judges a collapse
// between differently bound vertices, so the tube's blend rings (each bound 0.125 apart in total
// variation) collapse and a 2% level reaches its target; in the bind pose only, with the rest
// pose alone, or with the limit set explicitly, the rule's 0.1 keeps those rings apart and the
// level stops above its target.
TEST(SimplifyPosed, InfluenceRuleOnlyWithoutPosesByDefault) {
    const Asset a = bentTube();
    const size_t target = size_t(0.02 * double(a.mesh.triangleCount()));
    SimplifyOptions bindOnly;
    bindOnly.levels = {{0.02, 0, 0}};
    ASSERT_EQ(bindOnly.maxInfluenceChange, SimplifyOptions::kAutoInfluenceChange);
    SimplifyOptions posed = bindOnly;
    posed.posed = poseWedges(a.rig, a.morph, a.mesh, samplePoses(a.rig, {}));
    SimplifyOptions posedLimited = posed;
    posedLimited.maxInfluenceChange = SimplifyOptions::kBindPoseInfluenceChange;

    const Level flat = simplify(a.mesh, bindOnly).multires.levels.at(0);
    EXPECT_GT(flat.triangles.size(), target);
    EXPECT_EQ(flat.stopReason, "skin: joint influences differ");
    const Level limited = simplify(a.mesh, posedLimited).multires.levels.at(0);
    EXPECT_GT(limited.triangles.size(), target);
    EXPECT_EQ(limited.stopReason, "skin: joint influences differ");
    const Level judged = simplify(a.mesh, posed).multires.levels.at(0);
    EXPECT_LE(judged.triangles.size(), target);
    EXPECT_EQ(judged.stopReason, "target");
    // Judged by the posed surface it leaves: every original vertex within the level's deviation.
    EXPECT_LE(posedVertexDeviation(a, judged, samplePoses(a.rig, {})), judged.maxDeviation * (1 + 1e-9) + 1e-12);
    // A skin without animations has the rest pose alone: no motion to judge by, the rule stays.
    Asset still = a;
    still.rig.animations.clear();
    SimplifyOptions restOnly = bindOnly;
    restOnly.posed = poseWedges(still.rig, still.morph, still.mesh, samplePoses(still.rig, {}));
    ASSERT_EQ(restOnly.posed.positions.size(), 1u);
    const Level rest = simplify(still.mesh, restOnly).multires.levels.at(0);
    EXPECT_GT(rest.triangles.size(), target);
    EXPECT_EQ(rest.stopReason, "skin: joint influences differ");
}
