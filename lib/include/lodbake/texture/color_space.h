// The sRGB transfer function (IEC 61966-2-1), both directions, computed in the argument's type
// (float or double: convert a float channel to double for double precision).
// glTF base-colour textures and vertex-colour-free outputs are sRGB-encoded; shading happens in
// linear light.
#pragma once

#include <algorithm>
#include <cmath>

namespace lodbake {

// sRGB-encoded value -> linear light. Input clamped to [0,1] (a NaN passes through).
template <class T>
T srgbToLinear(T c) {
    c = std::clamp(c, T(0), T(1));
    return c <= T(0.04045) ? c / T(12.92) : std::pow((c + T(0.055)) / T(1.055), T(2.4));
}

// Linear light -> sRGB-encoded value in [0,1]. Input clamped to [0,1] (a NaN becomes 0).
template <class T>
T linearToSrgb(T c) {
    c = std::fmin(std::fmax(c, T(0)), T(1));
    return c <= T(0.0031308) ? c * T(12.92) : T(1.055) * std::pow(c, T(1) / T(2.4)) - T(0.055);
}

}  // namespace lodbake
