// Angle-weighted per-vertex tangent frames (see tangents.h for the convention).
#include "lodbake/core/tangents.h"

#include <algorithm>
#include <cmath>

namespace lodbake {
namespace {

// The angle of triangle (a, b, c) at a, radians.
double cornerAngle(Vec3 a, Vec3 b, Vec3 c) {
    Vec3 u = normalize(b - a), v = normalize(c - a);
    return std::acos(std::clamp(dot(u, v), -1.0, 1.0));
}

// Any unit vector orthogonal to n.
Vec3 orthogonal(Vec3 n) {
    Vec3 axis = std::fabs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    Vec3 t = normalize(axis - n * dot(axis, n));
    return length(t) > 0.5 ? t : Vec3{1, 0, 0};
}

}  // namespace

std::vector<Vec4> computeTangents(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                                  const std::vector<Vec2>& uvs, const std::vector<Tri>& triangles) {
    const size_t n = positions.size();
    std::vector<Vec3> tan(n), bit(n);
    for (const Tri& t : triangles) {
        const Vec3 p0 = positions[t[0]], p1 = positions[t[1]], p2 = positions[t[2]];
        // v flipped so that the frame is the one glTF's normal maps are authored in.
        const Vec2 q0{uvs[t[0]].x, -uvs[t[0]].y}, q1{uvs[t[1]].x, -uvs[t[1]].y}, q2{uvs[t[2]].x, -uvs[t[2]].y};
        const Vec3 e1 = p1 - p0, e2 = p2 - p0;
        const Vec2 d1 = q1 - q0, d2 = q2 - q0;
        const double det = cross(d1, d2);
        if (!(std::fabs(det) > 1e-20)) continue;
        // The sign of det carries mirroring; normalising T and B keeps each triangle's weight its angle.
        const Vec3 T = normalize((e1 * d2.y - e2 * d1.y) * (1 / det));
        const Vec3 B = normalize((e2 * d1.x - e1 * d2.x) * (1 / det));
        if (!isFinite(T) || !isFinite(B)) continue;
        const double w[3] = {cornerAngle(p0, p1, p2), cornerAngle(p1, p2, p0), cornerAngle(p2, p0, p1)};
        for (int k = 0; k < 3; ++k) {
            tan[t[size_t(k)]] += T * w[k];
            bit[t[size_t(k)]] += B * w[k];
        }
    }
    std::vector<Vec4> out(n);
    for (size_t v = 0; v < n; ++v) {
        const Vec3 N = normals[v];
        Vec3 T = normalize(tan[v] - N * dot(tan[v], N));
        if (!(length(T) > 0.5)) {
            const Vec3 o = orthogonal(N);
            out[v] = {o.x, o.y, o.z, 1};
            continue;
        }
        const double w = dot(cross(N, T), bit[v]) < 0 ? -1.0 : 1.0;
        out[v] = {T.x, T.y, T.z, w};
    }
    return out;
}

std::vector<Vec4> computeWedgeTangents(const TriMesh& mesh, const std::vector<Vec2>& uv) {
    const Wedges& W = mesh.wedges;
    const size_t n = W.size();
    std::vector<Vec3> positions(n), normals(n);
    for (size_t w = 0; w < n; ++w) positions[w] = mesh.positions[W.vertex[w]];
    if (!W.normal.empty()) {
        normals = W.normal;
    } else {
        for (size_t f = 0; f < mesh.triangleCount(); ++f) {
            const Tri& t = mesh.triangles[f];
            const Vec3 fn = cross(mesh.positions[t[1]] - mesh.positions[t[0]], mesh.positions[t[2]] - mesh.positions[t[0]]);
            for (uint32_t w : mesh.cornerWedges[f]) normals[w] += fn;
        }
        for (Vec3& nv : normals) nv = normalize(nv);
    }
    if (uv.size() != n) return std::vector<Vec4>(n, Vec4{1, 0, 0, 1});
    return computeTangents(positions, normals, uv, mesh.cornerWedges);
}

bool tangentFrameAt(Vec3 N, const std::array<Vec4, 3>& corners, const std::array<double, 3>& bary, TangentFrame& frame) {
    Vec3 T{};
    double w = 0;
    for (size_t k = 0; k < 3; ++k) {
        T += Vec3{corners[k].x, corners[k].y, corners[k].z} * bary[k];
        w += corners[k].w * bary[k];
    }
    T = normalize(T - N * dot(T, N));
    if (!(length(T) > 0.5)) return false;
    frame = {T, cross(N, T) * (w < 0 ? -1.0 : 1.0), N};
    return true;
}

}  // namespace lodbake
