// Closest point on a triangle, in 3D (shared by simplify's vertex deviation and pairs,
// parameterize's projected level corners and atlas application, texture-refine and pack) and in
// the plane (the bake's texel coverage, texture deviation's UV lookups), and closest points of
// face sets. Header-only.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
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

// Barycentric coordinates w of p in the plane triangle (a, b, c); false (w untouched) for a
// degenerate triangle. Coordinates outside [0, 1] place p outside the triangle.
inline bool barycentric(Vec2 p, Vec2 a, Vec2 b, Vec2 c, std::array<double, 3>& w) {
    double d = cross(b - a, c - a);
    if (!(std::abs(d) > 0)) return false;
    w[1] = cross(p - a, c - a) / d;
    w[2] = cross(b - a, p - a) / d;
    w[0] = 1 - w[1] - w[2];
    return true;
}

// The closest point to p of segment ab, as the parameter in [0, 1] along ab (0 when a == b).
inline double closestOnSegment(Vec2 p, Vec2 a, Vec2 b) {
    Vec2 e = b - a;
    double l2 = dot(e, e);
    return l2 > 0 ? std::clamp(dot(p - a, e) / l2, 0.0, 1.0) : 0.0;
}

// The point of plane triangle t closest to p, as barycentrics `w`; returns the squared distance
// (0 inside). A degenerate triangle is measured along its edges.
inline double closestOnTriangle(Vec2 p, const std::array<Vec2, 3>& t, std::array<double, 3>& w) {
    if (barycentric(p, t[0], t[1], t[2], w) && w[0] >= 0 && w[1] >= 0 && w[2] >= 0) return 0;
    double best = 1e300;
    for (int k = 0; k < 3; ++k) {
        Vec2 a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
        double s = closestOnSegment(p, a, b);
        Vec2 q = a + (b - a) * s;
        double d = dot(q - p, q - p);
        if (d < best) {
            best = d;
            w = {0, 0, 0};
            w[size_t(k)] = 1 - s;
            w[size_t((k + 1) % 3)] = s;
        }
    }
    return best;
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

// Axis-aligned bounding box of face f: {min x, min y, min z, max x, max y, max z}.
inline std::array<double, 6> faceBox(const TriMesh& mesh, uint32_t f) {
    const Tri& t = mesh.triangles[f];
    std::array<double, 6> b{};
    for (int a = 0; a < 3; ++a) {
        b[size_t(a)] = std::min({mesh.positions[t[0]][a], mesh.positions[t[1]][a], mesh.positions[t[2]][a]});
        b[size_t(a + 3)] = std::max({mesh.positions[t[0]][a], mesh.positions[t[1]][a], mesh.positions[t[2]][a]});
    }
    return b;
}

// Squared distance from p to box b (0 inside): a lower bound of the distance to the face.
inline double boxDistance2(const std::array<double, 6>& b, Vec3 p) {
    double d2 = 0;
    for (int a = 0; a < 3; ++a) {
        double e = p[a] < b[size_t(a)] ? b[size_t(a)] - p[a] : (p[a] > b[size_t(a + 3)] ? p[a] - b[size_t(a + 3)] : 0);
        d2 += e * e;
    }
    return d2;
}

// Squared distance from p to face f, and its closest point's barycentrics (when `bary`): the
// arithmetic every closest-face search shares, so that they agree bit for bit.
inline double faceDistance2(const TriMesh& mesh, uint32_t f, Vec3 p, std::array<double, 3>* bary) {
    const Tri& t = mesh.triangles[f];
    const auto b = closestOnTriangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    const Vec3 q = mesh.positions[t[0]] * b[0] + mesh.positions[t[1]] * b[1] + mesh.positions[t[2]] * b[2];
    if (bary) *bary = b;
    return length2(q - p);
}

// Faces with their bounding boxes, for many closest-point queries near one place (an island's
// texels or samples): a query skips every face whose box is farther than a hint face (the
// previous query's answer), so it returns exactly what closestSurfacePoint returns over the same
// faces in the same order, ties included.
class BoxedFaces {
public:
    BoxedFaces(const TriMesh& mesh, std::vector<uint32_t> faces) : mesh_(mesh), faces_(std::move(faces)) {
        box_.reserve(faces_.size());
        for (uint32_t f : faces_) {
            const std::array<double, 6> b = faceBox(mesh, f);
            box_.push_back(b);
            for (int a = 0; a < 3; ++a) extent_ = std::max({extent_, std::abs(b[size_t(a)]), std::abs(b[size_t(a + 3)])});
        }
    }
    // Squared distance to the closest point (1e300 when there are no faces); `face` and `bary`
    // receive it. `hint` (a face id, or any value not among the faces) only speeds the search.
    double closest(Vec3 p, uint32_t hint, uint32_t& face, std::array<double, 3>& bary) const {
        // The bound, with a margin far above rounding (relative, and absolute at the faces' scale):
        // a face as near as the hint, or touching p, always stays in.
        double bound = 1e300;
        if (std::find(faces_.begin(), faces_.end(), hint) != faces_.end()) {
            double r = std::sqrt(distance2(p, hint, nullptr)) * (1 + 1e-9) + 1e-9 * extent_;
            bound = r * r;
        }
        double best = 1e300;
        for (size_t i = 0; i < faces_.size(); ++i) {
            if (boxDistance2(box_[i], p) > bound) continue;  // farther than the hint: neither the closest nor a tie
            std::array<double, 3> w;
            double d = distance2(p, faces_[i], &w);
            if (d < best) {
                best = d;
                face = faces_[i];
                bary = w;
            }
        }
        return best;
    }
    // The face whose box is nearest to p (the first on ties; ~0u without faces): a good hint.
    uint32_t nearestBox(Vec3 p) const {
        uint32_t face = ~0u;
        double best = 1e300;
        for (size_t i = 0; i < faces_.size(); ++i) {
            const double d = boxDistance2(box_[i], p);
            if (d < best) {
                best = d;
                face = faces_[i];
            }
        }
        return face;
    }
    // The faces whose boxes lie within `reach` of p, in their order.
    std::vector<uint32_t> within(Vec3 p, double reach) const {
        std::vector<uint32_t> out;
        for (size_t i = 0; i < faces_.size(); ++i)
            if (boxDistance2(box_[i], p) <= reach * reach) out.push_back(faces_[i]);
        return out;
    }

private:
    double distance2(Vec3 p, uint32_t f, std::array<double, 3>* bary) const { return faceDistance2(mesh_, f, p, bary); }
    const TriMesh& mesh_;
    std::vector<uint32_t> faces_;
    std::vector<std::array<double, 6>> box_;
    double extent_ = 0;  // largest |coordinate| of the faces
};

// `faces` in their order, less every face whose corners lie exactly where an earlier face's do, in
// the same order (instanced parts that coincide): such a copy measures every point's distance with
// the same arithmetic as the earlier face and loses every tie to it, so no closest-point answer
// over the set changes, while a search among k coincident copies costs k times one.
inline std::vector<uint32_t> withoutCopies(const TriMesh& mesh, const std::vector<uint32_t>& faces) {
    auto corners = [&](uint32_t f) {
        const Tri& t = mesh.triangles[f];
        const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
        return std::array<double, 9>{a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z};
    };
    // Grouped by a hash of the corners (16 bytes a face, so a million-face surface stays cheap),
    // then compared exactly within a group.
    std::vector<std::pair<uint64_t, size_t>> hashed(faces.size());
    for (size_t i = 0; i < faces.size(); ++i) {
        uint64_t h = 1469598103934665603ull;
        for (double x : corners(faces[i])) {
            uint64_t bits = 0;
            std::memcpy(&bits, &x, sizeof bits);
            h = (h ^ bits) * 1099511628211ull;
        }
        hashed[i] = {h, i};
    }
    std::sort(hashed.begin(), hashed.end());
    std::vector<char> copy(faces.size(), 0);
    for (size_t g = 0; g < hashed.size();) {
        size_t e = g + 1;
        while (e < hashed.size() && hashed[e].first == hashed[g].first) ++e;
        for (size_t i = g + 1; i < e; ++i)  // earlier positions first within the group
            for (size_t j = g; j < i && !copy[hashed[i].second]; ++j)
                if (!copy[hashed[j].second] && corners(faces[hashed[j].second]) == corners(faces[hashed[i].second]))
                    copy[hashed[i].second] = 1;
        g = e;
    }
    std::vector<uint32_t> out;
    out.reserve(faces.size());
    for (size_t i = 0; i < faces.size(); ++i)
        if (!copy[i]) out.push_back(faces[i]);
    return out;
}

// The faces of `faces` that can hold the closest point of some point of triangle `tri`: those
// whose bounding box lies within d0 + 2r of the triangle's centroid c, with d0 = the distance from
// c to `faces` and r = the largest |corner - c|. (For X on the triangle, its closest face f has
// d(X, f) <= d(X, f0) <= d0 + r, f0 being c's closest face, so d(c, f) <= d0 + 2r.) The closest
// point of any point of the triangle is the same over these faces as over all of them. d0 is
// closestSurfacePoint's, found by BoxedFaces from the face whose box is nearest to c: only the
// faces whose boxes are as near are measured exactly.
inline std::vector<uint32_t> facesNearTriangle(const TriMesh& mesh, const std::vector<uint32_t>& faces,
                                               const std::array<Vec3, 3>& tri) {
    const Vec3 c = (tri[0] + tri[1] + tri[2]) * (1.0 / 3);
    const BoxedFaces boxed(mesh, faces);
    uint32_t f0 = 0;
    std::array<double, 3> b0{};
    const double d0 = boxed.closest(c, boxed.nearestBox(c), f0, b0);
    if (!(d0 < 1e300)) return {};
    double r = 0;
    for (const Vec3& q : tri) r = std::max(r, length(q - c));
    const double reach = (std::sqrt(d0) + 2 * r) * (1 + 1e-9) + 1e-12;
    return boxed.within(c, reach);
}

}  // namespace lodbake
