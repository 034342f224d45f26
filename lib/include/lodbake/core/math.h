// Small fixed-size vector types and the geometric primitives on them used across lodbake (pi,
// triangle areas, 4x4 transforms). Header-only, no dependencies.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace lodbake {

constexpr double kPi = 3.14159265358979323846;

// x mod 1 for finite x >= 0, equal to std::fmod(x, 1.0) bit for bit (below 2^52 the difference
// x - floor(x) is exact) at a fraction of its cost: the low-discrepancy sequences of the samplers.
inline double fractionalPart(double x) { return x - std::floor(x); }

struct Vec2 {
    double x = 0, y = 0;
};

struct Vec3 {
    double x = 0, y = 0, z = 0;
    double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
};

struct Vec4 {
    double x = 0, y = 0, z = 0, w = 0;
};

inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(Vec2 a, double s) { return {a.x * s, a.y * s}; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
// Index of the triangle corner opposite its longest edge (the first on ties).
inline size_t cornerOppositeLongestEdge(const std::array<Vec2, 3>& t) {
    size_t apex = 0;
    double longest = -1;
    for (size_t k = 0; k < 3; ++k) {
        Vec2 e = t[(k + 1) % 3] - t[(k + 2) % 3];
        if (dot(e, e) > longest) {
            longest = dot(e, e);
            apex = k;
        }
    }
    return apex;
}

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(Vec3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator*(double s, Vec3 a) { return a * s; }
inline Vec3 operator/(Vec3 a, double s) { return {a.x / s, a.y / s, a.z / s}; }
inline Vec3& operator+=(Vec3& a, Vec3 b) { a = a + b; return a; }
inline Vec3& operator-=(Vec3& a, Vec3 b) { a = a - b; return a; }
inline double dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline double length2(Vec3 a) { return dot(a, a); }
inline Vec3 normalize(Vec3 a) {
    double l = length(a);
    return l > 0 ? a / l : Vec3{};
}
// Area of triangle abc (model units^2): half the length of the edge cross product.
inline double triangleArea(Vec3 a, Vec3 b, Vec3 c) { return 0.5 * length(cross(b - a, c - a)); }
// Signed area of triangle abc in the plane: positive when a, b, c turn counter-clockwise (x right,
// y up).
inline double signedArea(Vec2 a, Vec2 b, Vec2 c) { return 0.5 * cross(b - a, c - a); }
// Area of triangle abc in the plane (either orientation).
inline double triangleArea(Vec2 a, Vec2 b, Vec2 c) { return std::abs(signedArea(a, b, c)); }
inline bool isFinite(Vec3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }

// Axis-aligned box; empty when min > max.
struct Box3 {
    Vec3 min{1e300, 1e300, 1e300};
    Vec3 max{-1e300, -1e300, -1e300};
    void extend(Vec3 p) {
        min = {std::fmin(min.x, p.x), std::fmin(min.y, p.y), std::fmin(min.z, p.z)};
        max = {std::fmax(max.x, p.x), std::fmax(max.y, p.y), std::fmax(max.z, p.z)};
    }
    bool empty() const { return min.x > max.x; }
    double diagonal() const { return empty() ? 0.0 : length(max - min); }
    double longestSide() const {
        return empty() ? 0.0 : std::fmax(max.x - min.x, std::fmax(max.y - min.y, max.z - min.z));
    }
};

// Column-major 4x4 matrix, as glTF stores it.
using Mat4 = std::array<double, 16>;
inline Mat4 identity4() { return {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}; }
inline Mat4 mul(const Mat4& a, const Mat4& b) {
    Mat4 r{};
    for (int c = 0; c < 4; ++c)
        for (int rr = 0; rr < 4; ++rr) {
            double s = 0;
            for (int k = 0; k < 4; ++k) s += a[k * 4 + rr] * b[c * 4 + k];
            r[c * 4 + rr] = s;
        }
    return r;
}
inline Vec3 transformPoint(const Mat4& m, Vec3 p) {
    return {m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12], m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13],
            m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14]};
}
inline Vec3 transformVector(const Mat4& m, Vec3 v) {
    return {m[0] * v.x + m[4] * v.y + m[8] * v.z, m[1] * v.x + m[5] * v.y + m[9] * v.z,
            m[2] * v.x + m[6] * v.y + m[10] * v.z};
}
inline double det3(const Mat4& m) {
    return m[0] * (m[5] * m[10] - m[9] * m[6]) - m[4] * (m[1] * m[10] - m[9] * m[2]) +
           m[8] * (m[1] * m[6] - m[5] * m[2]);
}

}  // namespace lodbake
