// The Gaussian-sphere cells of the M-AGSphere (thesis 2.4.2-2.4.3): octants split into four,
// recursively, by the midpoint subdivision of the octahedron's faces projected onto the sphere.
//
// A direction n maps to the octant of its signs and to barycentric coordinates
// (|x|, |y|, |z|) / (|x| + |y| + |z|) on that octant's face of the octahedron; each step picks the
// child whose (planar) triangle holds the point and rescales the coordinates to it, exactly.
// Corners are kept as integer points of the octahedron scaled by 2^depth, so shared edges (also
// across octants) compare exactly.
#include <array>
#include <cmath>
#include <map>

#include "agsphere/sphere_table.h"
#include "lodbake/agsphere/agsphere.h"

namespace lodbake {

using IPoint = std::array<int64_t, 3>;

uint64_t sphereCellCount(int depth) { return uint64_t(8) << (2 * depth); }

uint32_t sphereCell(Vec3 n, int depth) {
    uint32_t cell = (n.x < 0 ? 1u : 0u) | (n.y < 0 ? 2u : 0u) | (n.z < 0 ? 4u : 0u);
    double l1 = std::fabs(n.x) + std::fabs(n.y) + std::fabs(n.z);
    double l[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3};
    if (l1 > 0 && std::isfinite(l1)) l[0] = std::fabs(n.x) / l1, l[1] = std::fabs(n.y) / l1, l[2] = std::fabs(n.z) / l1;
    for (int d = 0; d < depth; ++d) {
        uint32_t child = 3;
        for (uint32_t k = 0; k < 3; ++k)
            if (l[k] >= 0.5) {
                child = k;
                break;
            }
        if (child < 3) {
            for (uint32_t k = 0; k < 3; ++k) l[k] = k == child ? 2 * l[k] - 1 : 2 * l[k];
        } else {
            for (double& v : l) v = 1 - 2 * v;
        }
        cell = cell * 4 + child;
    }
    return cell;
}

// Corners as integer barycentric points (sum 2^depth) and the octant.
static std::array<IPoint, 3> cornersInt(uint32_t cell, int depth, uint32_t& octant) {
    octant = cell >> (2 * depth);
    const int64_t S = int64_t(1) << depth;
    std::array<IPoint, 3> P = {IPoint{S, 0, 0}, IPoint{0, S, 0}, IPoint{0, 0, S}};
    auto mid = [](const IPoint& a, const IPoint& b) { return IPoint{(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2}; };
    for (int d = 0; d < depth; ++d) {
        uint32_t digit = (cell >> (2 * (depth - 1 - d))) & 3u;
        IPoint m01 = mid(P[0], P[1]), m12 = mid(P[1], P[2]), m02 = mid(P[0], P[2]);
        switch (digit) {
            case 0: P = {P[0], m01, m02}; break;
            case 1: P = {m01, P[1], m12}; break;
            case 2: P = {m02, m12, P[2]}; break;
            default: P = {m12, m02, m01}; break;
        }
    }
    return P;
}

static IPoint toOctahedron(const IPoint& b, uint32_t octant) {
    return {octant & 1u ? -b[0] : b[0], octant & 2u ? -b[1] : b[1], octant & 4u ? -b[2] : b[2]};
}

std::array<Vec3, 3> sphereCellCorners(uint32_t cell, int depth) {
    uint32_t oct = 0;
    auto P = cornersInt(cell, depth, oct);
    std::array<Vec3, 3> out;
    for (int k = 0; k < 3; ++k) {
        IPoint q = toOctahedron(P[size_t(k)], oct);
        out[size_t(k)] = normalize(Vec3{double(q[0]), double(q[1]), double(q[2])});
    }
    return out;
}

Vec3 sphereCellCenter(uint32_t cell, int depth) {
    uint32_t oct = 0;
    auto P = cornersInt(cell, depth, oct);
    Vec3 c;
    for (const IPoint& b : P) {
        IPoint q = toOctahedron(b, oct);
        c += Vec3{double(q[0]), double(q[1]), double(q[2])};
    }
    return normalize(c);
}

double sphereCellRadius(uint32_t cell, int depth) {
    Vec3 c = sphereCellCenter(cell, depth);
    double r = 0;
    for (const Vec3& p : sphereCellCorners(cell, depth)) r = std::fmax(r, std::acos(std::fmin(1.0, std::fmax(-1.0, dot(c, p)))));
    return r;
}

// Edge keys of one cell (integer octahedron points, ordered).
static std::array<std::pair<IPoint, IPoint>, 3> cellEdges(uint32_t cell, int depth) {
    uint32_t oct = 0;
    auto P = cornersInt(cell, depth, oct);
    std::array<std::pair<IPoint, IPoint>, 3> e;
    for (int k = 0; k < 3; ++k) {
        IPoint a = toOctahedron(P[size_t(k)], oct), b = toOctahedron(P[size_t((k + 1) % 3)], oct);
        if (b < a) std::swap(a, b);
        e[size_t(k)] = {a, b};
    }
    return e;
}

std::vector<std::array<uint32_t, 3>> sphereNeighbourTable(int depth) {
    const uint64_t n = sphereCellCount(depth);
    std::map<std::pair<IPoint, IPoint>, std::vector<uint32_t>> owners;
    for (uint32_t c = 0; c < n; ++c)
        for (const auto& e : cellEdges(c, depth)) owners[e].push_back(c);
    std::vector<std::array<uint32_t, 3>> table(n, {UINT32_MAX, UINT32_MAX, UINT32_MAX});
    for (uint32_t c = 0; c < n; ++c) {
        auto e = cellEdges(c, depth);
        for (int k = 0; k < 3; ++k)
            for (uint32_t o : owners[e[size_t(k)]])
                if (o != c) table[c][size_t(k)] = o;
    }
    return table;
}

std::vector<uint32_t> sphereCellNeighbours(uint32_t cell, int depth) {
    auto mine = cellEdges(cell, depth);
    std::vector<uint32_t> out;
    const uint64_t n = sphereCellCount(depth);
    for (uint32_t c = 0; c < n; ++c) {
        if (c == cell) continue;
        auto e = cellEdges(c, depth);
        bool shares = false;
        for (const auto& a : mine)
            for (const auto& b : e) shares |= a == b;
        if (shares) out.push_back(c);
    }
    return out;
}

}  // namespace lodbake
