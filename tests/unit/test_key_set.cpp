// KeySet (lib/include/lodbake/core/key_set.h): membership as std::set gives it, through growth
// and for every key, the all-ones key its table marks free slots with included.
#include <gtest/gtest.h>

#include <random>
#include <set>

#include "lodbake/core/adjacency.h"
#include "lodbake/core/key_set.h"

using namespace lodbake;

TEST(KeySet, MembershipMatchesAnOrderedSetThroughGrowth) {
    std::mt19937_64 rng(7);
    KeySet keys;  // room for few keys: it grows many times
    std::set<uint64_t> reference;
    for (int i = 0; i < 200000; ++i) {
        // Edge keys of a small vertex range repeat often; the wide ones almost never.
        const uint64_t key = i % 2 ? edgeKey(uint32_t(rng() % 300), uint32_t(rng() % 300)) : rng();
        EXPECT_EQ(keys.insert(key), reference.insert(key).second);
    }
    EXPECT_EQ(keys.size(), reference.size());
    for (int i = 0; i < 20000; ++i) {
        const uint64_t key = i % 2 ? edgeKey(uint32_t(rng() % 400), uint32_t(rng() % 400)) : rng();
        EXPECT_EQ(keys.contains(key), reference.count(key) == 1);
    }
}

TEST(KeySet, TheAllOnesKeyIsAKeyLikeAnyOther) {
    KeySet keys(4);
    const uint64_t ones = ~uint64_t(0);
    EXPECT_FALSE(keys.contains(ones));
    EXPECT_TRUE(keys.insert(ones));
    EXPECT_FALSE(keys.insert(ones));
    EXPECT_TRUE(keys.contains(ones));
    EXPECT_FALSE(keys.contains(0));
    EXPECT_TRUE(keys.insert(0));
    EXPECT_EQ(keys.size(), 2u);
}
