// Closest point on a triangle, shared by simplify (vertex deviation, pairs), parameterize
// (projected level corners, atlas application), texture-refine and pack. Header-only.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "lodbake/core/math.h"
#include "lodbake/core/mesh.h"

namespace lodbake {

// Barycentric coordinates of the point of triangle abc closest to p (Ericson, Real-Time
// Collision Detection 5.1.5). A degenerate triangle gives {1, 0, 0}.
inline std::array<double, 3> closestOnTriangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
    Vec3 ab = b - a, ac = c - a, ap = p - a;
    double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
    Vec3 bp = p - b;
    double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        return {1 - v, v, 0};
    }
    Vec3 cp = p - c;
    double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double w = d2 / (d2 - d6);
        return {1 - w, 0, w};
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {0, 1 - w, w};
    }
    double den = va + vb + vc;
    if (!(std::fabs(den) > 0)) return {1, 0, 0};
    double v = vb / den, w = vc / den;
    return {1 - v - w, v, w};
}

// The point of `faces` (ids of mesh triangles) closest to p: its face and barycentrics (first
// face on ties); returns the squared distance (1e300 when faces is empty).
inline double closestSurfacePoint(const TriMesh& mesh, const std::vector<uint32_t>& faces, Vec3 p, uint32_t& face,
                                  std::array<double, 3>& bary) {
    double best = 1e300;
    for (uint32_t f : faces) {
        const Tri& t = mesh.triangles[f];
        auto b = closestOnTriangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
        Vec3 q = mesh.positions[t[0]] * b[0] + mesh.positions[t[1]] * b[1] + mesh.positions[t[2]] * b[2];
        double d = length2(q - p);
        if (d < best) {
            best = d;
            face = f;
            bary = b;
        }
    }
    return best;
}

// The texture coordinate of the point of `faces` closest to p, interpolated from the faces'
// per-corner UVs (cornerUV[f][k]). {0, 0} when faces is empty.
inline Vec2 closestSurfaceUV(const TriMesh& mesh, const std::vector<std::array<Vec2, 3>>& cornerUV,
                             const std::vector<uint32_t>& faces, Vec3 p) {
    uint32_t f = 0;
    std::array<double, 3> b{};
    if (closestSurfacePoint(mesh, faces, p, f, b) >= 1e300) return {};
    return cornerUV[f][0] * b[0] + cornerUV[f][1] * b[1] + cornerUV[f][2] * b[2];
}

}  // namespace lodbake
