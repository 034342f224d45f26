// Small meshes built in code for the unit tests (no files). All faces are counter-clockwise seen
// from +z (flat ones) or from outside (closed ones). Every mesh gets one wedge per welded vertex
// and material 0 unless stated otherwise.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "lodbake/core/mesh.h"

namespace lodbake::test {

// One wedge per vertex (uv = xy), cornerWedges = triangles, material 0.
inline void addDefaultWedges(TriMesh& m) {
    m.wedges = Wedges{};
    for (uint32_t v = 0; v < m.positions.size(); ++v) {
        m.wedges.vertex.push_back(v);
        m.wedges.uv0.push_back({m.positions[v].x, m.positions[v].y});
    }
    m.cornerWedges = m.triangles;
    m.triangleMaterial.assign(m.triangles.size(), 0);
}

// Flat grid of nx * ny quads in [0,nx] x [0,ny] at z = 0 (or z = height(x, y)); vertex (i, j) has
// id j*(nx+1)+i; each quad is split along its (i,j)-(i+1,j+1) diagonal:
//
//   (i,j+1) +---+ (i+1,j+1)
//           | / |
//     (i,j) +---+ (i+1,j)
template <class Height>
inline TriMesh grid(int nx, int ny, Height height) {
    TriMesh m;
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) m.positions.push_back({double(i), double(j), height(i, j)});
    auto id = [&](int i, int j) { return uint32_t(j * (nx + 1) + i); };
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        }
    addDefaultWedges(m);
    return m;
}
inline TriMesh grid(int nx, int ny) {
    return grid(nx, ny, [](int, int) { return 0.0; });
}

// Regular hexagon fan: centre 0 at the origin, ring vertices 1..6 at angles 0, 60, ... 300 deg.
//
//        3 ----- 2
//       / \     / \  .
//      /   \   /   \  .
//     4 ---- 0 ---- 1        faces k = (0, k+1, (k+1)%6+1), k = 0..5
//      \   /   \   /
//       \ /     \ /
//        5 ----- 6
inline TriMesh hexagonFan() {
    TriMesh m;
    m.positions.push_back({0, 0, 0});
    for (int k = 0; k < 6; ++k) {
        double a = k * kPi / 3;
        m.positions.push_back({std::cos(a), std::sin(a), 0});
    }
    for (uint32_t k = 0; k < 6; ++k) m.triangles.push_back({0, k + 1, (k + 1) % 6 + 1});
    addDefaultWedges(m);
    return m;
}

// Closed unit sphere: octahedron subdivided `levels` times (8 * 4^levels faces), projected.
inline TriMesh sphere(int levels) {
    TriMesh m;
    m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    m.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto midpoint = [&](uint32_t a, uint32_t b) {
            auto key = std::minmax(a, b);
            auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            uint32_t id = uint32_t(m.positions.size());
            m.positions.push_back(normalize(m.positions[a] + m.positions[b]));
            mid.emplace(key, id);
            return id;
        };
        std::vector<Tri> next;
        next.reserve(m.triangles.size() * 4);
        for (const Tri& t : m.triangles) {
            uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
            next.push_back({t[0], a, c});
            next.push_back({a, t[1], b});
            next.push_back({c, b, t[2]});
            next.push_back({a, b, c});
        }
        m.triangles = std::move(next);
    }
    addDefaultWedges(m);
    return m;
}

// Upper half (z >= 0) of sphere(levels): an open surface with one boundary loop.
inline TriMesh hemisphere(int levels) {
    TriMesh s = sphere(levels), m;
    std::vector<uint32_t> remap(s.positions.size(), UINT32_MAX);
    for (const Tri& t : s.triangles) {
        if (s.positions[t[0]].z + s.positions[t[1]].z + s.positions[t[2]].z < 0) continue;
        Tri n;
        for (int k = 0; k < 3; ++k) {
            if (remap[t[k]] == UINT32_MAX) {
                remap[t[k]] = uint32_t(m.positions.size());
                m.positions.push_back(s.positions[t[k]]);
            }
            n[k] = remap[t[k]];
        }
        m.triangles.push_back(n);
    }
    addDefaultWedges(m);
    return m;
}

// grid(n, n) whose wedges are split along column x = n/2: faces left of it use material 0 and
// uv = (x, y) / n, faces right of it material 1 and uv = (x, y) / n + (5, 0); the welded vertices
// on the seam column carry two wedges.
inline TriMesh seamGrid(int n) {
    TriMesh m = grid(n, n, [](int i, int j) { return 0.05 * std::sin(0.7 * i) * std::cos(0.5 * j); });
    int seam = n / 2;
    m.wedges = Wedges{};
    std::vector<uint32_t> left(m.positions.size()), right(m.positions.size());
    for (uint32_t v = 0; v < m.positions.size(); ++v) {
        Vec3 p = m.positions[v];
        left[v] = uint32_t(m.wedges.size());
        m.wedges.vertex.push_back(v);
        m.wedges.uv0.push_back({p.x / n, p.y / n});
        right[v] = left[v];
        if (int(p.x) == seam) {
            right[v] = uint32_t(m.wedges.size());
            m.wedges.vertex.push_back(v);
            m.wedges.uv0.push_back({p.x / n + 5, p.y / n});
        }
    }
    m.cornerWedges.clear();
    m.triangleMaterial.clear();
    for (const Tri& t : m.triangles) {
        double cx = (m.positions[t[0]].x + m.positions[t[1]].x + m.positions[t[2]].x) / 3;
        bool isLeft = cx < seam;
        m.cornerWedges.push_back(isLeft ? Tri{left[t[0]], left[t[1]], left[t[2]]}
                                        : Tri{right[t[0]], right[t[1]], right[t[2]]});
        m.triangleMaterial.push_back(isLeft ? 0 : 1);
    }
    return m;
}

// Rule-3 fixture: a hexagonal disk split by the line k - i - j into an upper fan around u and a
// lower fan around w (10 faces). i is lifted by `lift` out of the z = 0 plane.
//
//          t0 ------- t1
//         /  \       /  \  .
//        /     \  u /     \          u = (0, 1), w = (0, -1)
//      k ------- i ------- j         k = (-2, 0), i = (0, 0, lift), j = (2, 0)
//        \     /  w \     /
//         \  /       \  /
//          b0 ------- b1
//
// Ids: k0 i1 j2 t0=3 t1=4 b0=5 b1=6 u7 w8.
inline TriMesh splitDisk(double lift) {
    TriMesh m;
    m.positions = {{-2, 0, 0}, {0, 0, lift}, {2, 0, 0}, {-1, 2, 0}, {1, 2, 0}, {-1, -2, 0}, {1, -2, 0}, {0, 1, 0}, {0, -1, 0}};
    // Upper polygon k, i, j, t1, t0 (CCW) around u; lower polygon k, b0, b1, j, i (CCW) around w.
    uint32_t up[5] = {0, 1, 2, 4, 3}, lo[5] = {0, 5, 6, 2, 1};
    for (int a = 0; a < 5; ++a) m.triangles.push_back({7, up[a], up[(a + 1) % 5]});
    for (int a = 0; a < 5; ++a) m.triangles.push_back({8, lo[a], lo[(a + 1) % 5]});
    addDefaultWedges(m);
    return m;
}

// Appends mesh b to a, scaled by `scale` and moved by `offset` (vertex ids of b follow a's).
inline void append(TriMesh& a, const TriMesh& b, double scale, Vec3 offset) {
    uint32_t off = uint32_t(a.positions.size());
    for (Vec3 p : b.positions) a.positions.push_back(p * scale + offset);
    for (Tri t : b.triangles) a.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
    addDefaultWedges(a);
}

}  // namespace lodbake::test
