// SrgbBytes (lib/src/bake/srgb_bytes.h): the table gives the formula's byte
// lround(linearToSrgb(double(v)) * 255) for every float; here on both sides of every step's first
// float, on an even sample of the floats in [0, 1] and on values outside it.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "bake/srgb_bytes.h"

using namespace lodbake::bake_detail;

TEST(SrgbBytes, MatchesTheFormulaAtEveryStepEdge) {
    const SrgbBytes& t = srgbBytes();
    for (int b = 1; b < 256; ++b) {
        const float f = t.first(b);
        EXPECT_EQ(t(f), srgbByteByFormula(f)) << b;
        EXPECT_EQ(srgbByteByFormula(f), b) << b;
        const float below = std::nextafter(f, 0.0f);
        EXPECT_EQ(t(below), srgbByteByFormula(below)) << b;
        EXPECT_LT(srgbByteByFormula(below), b) << b;
    }
}

TEST(SrgbBytes, MatchesTheFormulaOnASampleOfFloats) {
    const SrgbBytes& t = srgbBytes();
    for (uint32_t u = 0; u <= 0x3f800000u; u += 1021) {
        float f;
        std::memcpy(&f, &u, sizeof f);
        ASSERT_EQ(t(f), srgbByteByFormula(f)) << f;
    }
    for (float f : {-0.0f, -1e-30f, -1.0f, 1.0f, 1.0000001f, 2.0f, 1e30f, std::numeric_limits<float>::infinity(),
                    -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()})
        EXPECT_EQ(t(f), srgbByteByFormula(f)) << f;
}
