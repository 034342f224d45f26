// Rigs built in code for the unit tests: a root joint at the origin and a child joint at
// (1, 0, 0) that turns about z, the bind pose being the rest pose.
#pragma once

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "lodbake/core/pose.h"

namespace lodbake::test {

// Joint 0 (`rootName`, node 0) and joint 1 (`childName`, node 1 at x = 1); animation 0 turns
// joint 1 about z by anglesDeg[k] at times[k] (rotation keys, linear).
inline Rig kneeRig(const char* rootName, const char* childName, const std::vector<double>& times,
                   const std::vector<double>& anglesDeg) {
    Rig r;
    RigNode root, child;
    root.name = rootName;
    child.name = childName;
    child.parent = 0;
    child.translation = {1, 0, 0};
    r.nodes = {root, child};
    r.joints = {0, 1};
    for (const Mat4& g : poseNodes(r, -1, 0)) {
        Mat4 inv;
        EXPECT_TRUE(invertAffine(g, inv));
        r.inverseBind.push_back(inv);
    }
    Animation turn;
    AnimationSampler s;
    s.comps = 4;
    s.times = times;
    for (double deg : anglesDeg) {
        const double half = deg * 3.14159265358979323846 / 360;
        s.values.insert(s.values.end(), {0, 0, std::sin(half), std::cos(half)});
    }
    turn.samplers = {s};
    turn.channels = {AnimationChannel{0, 1, AnimationPath::Rotation}};
    r.animations = {turn};
    return r;
}

}  // namespace lodbake::test
