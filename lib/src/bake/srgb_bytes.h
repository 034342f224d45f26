// Linear float -> 8-bit sRGB byte, lround(linearToSrgb(double(v)) * 255) (color_space.h), without
// a pow per value. That byte never decreases as v grows, so it is the number of the 255 steps
// b = 1..255 whose first float (the least v whose byte is >= b, found once by bisection over the
// floats in [0, 1] with the formula itself) is <= v: the formula's byte for every float, NaN and
// values outside [0, 1] included (checked over every float in [0, 1] when it was written, and by
// tests/unit/test_srgb_bytes.cpp at each step's edges and a sample of floats).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "lodbake/texture/color_space.h"

namespace lodbake::bake_detail {

// The byte the bake stores for linear value v, by the formula.
inline uint8_t srgbByteByFormula(float v) { return uint8_t(std::lround(linearToSrgb(double(v)) * 255)); }

class SrgbBytes {
public:
    SrgbBytes() {
        first_[0] = 0.0f;
        for (int b = 1; b < 256; ++b) {
            // Bisection over the bit patterns of the floats in [0, 1] (ordered as the values).
            uint32_t lo = bits(0.0f), hi = bits(1.0f);  // byte(lo) < b <= byte(hi)
            while (hi - lo > 1) {
                const uint32_t mid = lo + (hi - lo) / 2;
                if (srgbByteByFormula(value(mid)) >= b) hi = mid;
                else lo = mid;
            }
            first_[size_t(b)] = value(hi);
        }
    }
    uint8_t operator()(float v) const {
        if (!(v > 0.0f)) return 0;  // NaN, zero and below
        return uint8_t(std::upper_bound(first_.begin() + 1, first_.end(), v) - first_.begin() - 1);
    }
    // The least float whose byte is >= b (b in 1..255).
    float first(int b) const { return first_[size_t(b)]; }

private:
    static uint32_t bits(float f) {
        uint32_t u;
        std::memcpy(&u, &f, sizeof u);
        return u;
    }
    static float value(uint32_t u) {
        float f;
        std::memcpy(&f, &u, sizeof f);
        return f;
    }
    std::array<float, 256> first_{};
};

// The table, built on first use (about 8000 evaluations of the formula).
inline const SrgbBytes& srgbBytes() {
    static const SrgbBytes table;
    return table;
}

}  // namespace lodbake::bake_detail
