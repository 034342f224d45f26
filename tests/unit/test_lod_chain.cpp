// packLodChain on a parameterized hemisphere: the profile is only a side channel (the chain is
// the same with and without one), and a progress callback that returns false cancels.
#include <gtest/gtest.h>

#include "lodbake/core/errors.h"
#include "lodbake/lod/lod_chain.h"
#include "parameterized_assets.h"

using namespace lodbake;

namespace {

PackOptions smallPack() {
    PackOptions o;
    o.maxSize = 256;
    o.distanceSamples = 2000;
    o.threads = 2;
    return o;
}

}  // namespace

TEST(LodChain, ProfileIsFilledAndChangesNothing) {
    const test::Parameterized& p = test::hemisphereAsset();
    const PackResult plain = packLodChain(p.asset, p.mr, smallPack());
    PackProfile profile;
    PackOptions o = smallPack();
    o.profile = &profile;
    const PackResult profiled = packLodChain(p.asset, p.mr, o);
    ASSERT_EQ(profiled.levels.size(), plain.levels.size());
    EXPECT_EQ(profiled.screenCoverage, plain.screenCoverage);
    for (size_t k = 0; k < plain.levels.size(); ++k) {
        EXPECT_EQ(profiled.levels[k].positions, plain.levels[k].positions);
        EXPECT_EQ(profiled.levels[k].uvs, plain.levels[k].uvs);
        EXPECT_EQ(profiled.levels[k].indices, plain.levels[k].indices);
        EXPECT_EQ(profiled.reports[k].width, plain.reports[k].width);
    }
    ASSERT_EQ(profile.levels.size(), plain.reports.size());
    EXPECT_GT(profile.seconds, 0);
    EXPECT_LE(profile.measureSeconds, profile.seconds);
    for (const PackLevelProfile& l : profile.levels) EXPECT_GE(l.wall.page, 0);
}

TEST(LodChain, ProgressFalseCancels) {
    const test::Parameterized& p = test::hemisphereAsset();
    PackOptions o = smallPack();
    int calls = 0;
    o.progress = [&](double) { return ++calls < 2; };
    EXPECT_THROW(packLodChain(p.asset, p.mr, o), Cancelled);
    EXPECT_EQ(calls, 2);
}
