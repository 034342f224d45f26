// assignTouched (lib/include/lodbake/core/touched_fill.h): the buffer std::vector::assign leaves, for
// buffers below and above the size whose pages are touched on several threads, fresh or reused.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <vector>

#include "lodbake/core/touched_fill.h"

using namespace lodbake;

namespace {

struct Hit {
    int32_t face = -1;
    float dist = 1e30f;
    std::array<float, 3> bary{};
};

bool sameHits(const std::vector<Hit>& a, const std::vector<Hit>& b) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i)
        if (a[i].face != b[i].face || a[i].dist != b[i].dist || a[i].bary != b[i].bary) return false;
    return true;
}

}  // namespace

TEST(TouchedFill, FillsAsAssignOnAnyThreadCount) {
    const Hit value{7, 2.5f, {0.25f, 0.5f, 0.25f}};
    // 100 entries (filled as they are) and some 3 million (past the threshold: touched first).
    for (size_t n : {size_t(100), size_t(3) << 20})
        for (int threads : {1, 2, 3}) {
            std::vector<Hit> expected;
            expected.assign(n, value);
            std::vector<Hit> v;
            assignTouched(v, n, value, threads);
            EXPECT_TRUE(sameHits(v, expected)) << n << " entries, " << threads << " threads";
        }
}

TEST(TouchedFill, AReusedBufferIsRefilled) {
    std::vector<float> v(5u << 20, 3.0f);
    assignTouched(v, 4u << 20, 0.0f, 2);  // fits the capacity it has
    ASSERT_EQ(v.size(), size_t(4) << 20);
    for (float x : v) ASSERT_EQ(x, 0.0f);
    assignTouched(v, 6u << 20, 1.0f, 2);  // grows
    ASSERT_EQ(v.size(), size_t(6) << 20);
    for (float x : v) ASSERT_EQ(x, 1.0f);
}
