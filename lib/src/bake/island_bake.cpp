// Island baking (island_bake.h): the level islands of a chart layout as the bake takes them
// (layoutBakeIslands), their texels' closest points on the original surface (rasterizeIslands),
// and the texel -> original UV Jacobian a filtered fetch needs at an island texel
// (islandDerivatives).
#include "bake/island_bake.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/face_tree.h"
#include "lodbake/core/parallel.h"
#include "lodbake/core/touched_fill.h"

namespace lodbake {
namespace bake_detail {
namespace {

constexpr size_t kIslandTreeFrom = 64;  // island texels from which a FaceTree answers them
// Grid entries a texel's own lookup (closestNearFace) scans, about: below a listing's entries
// (nearEntries) per texel, an island's texels are looked up one by one instead of listed.
constexpr size_t kLookupEntries = 512;
// Grid entries up to which a projected island's box is listed whole (one query) rather than
// described and searched around the island (several queries, each a part of the box's).
constexpr size_t kListEntries = 1024;
// Cosine between an original face's normal and an island's at or below which the face belongs to
// a sheet facing the other way (about 143 degrees): the two sheets of a thin wall are near 180
// degrees apart, faces around a crease the island cuts across far less.
constexpr double kOppositeCos = -0.8;

// Whether original face f faces the way of an island whose (unnormalised) normal is n: its
// geometric normal not opposite n (cosine above kOppositeCos). A coarse triangle lies between the
// sheets of a thin part (a glass wall's outer and inner surface, the two sides of a lamp shade);
// the nearest point can then be on the sheet behind it, facing the other way, whose texels (and
// normals) are not what this side shows.
bool facesIslandWay(const TriMesh& mesh, uint32_t f, Vec3 n) {
    const Tri& t = mesh.triangles[f];
    const Vec3& p0 = mesh.positions[t[0]];
    const Vec3 nf = cross(mesh.positions[t[1]] - p0, mesh.positions[t[2]] - p0);
    return dot(nf, n) > kOppositeCos * length(nf) * length(n);
}

Vec3 islandNormal(const std::array<Vec3, 3>& tri) { return cross(tri[1] - tri[0], tri[2] - tri[0]); }

// The faces of `faces` that face the island's way; all of them when none do (a degenerate island,
// or a level that folded a thin part onto one sheet).
std::vector<uint32_t> facingFaces(const TriMesh& mesh, const std::vector<uint32_t>& faces, const std::array<Vec3, 3>& tri) {
    const Vec3 n = islandNormal(tri);
    std::vector<uint32_t> out;
    out.reserve(faces.size());
    for (uint32_t f : faces)
        if (facesIslandWay(mesh, f, n)) out.push_back(f);
    return out.empty() ? faces : out;
}

}  // namespace

bool clipToBox(Vec3 c, double h, Vec3 lo, Vec3 hi, Vec3& qlo, Vec3& qhi) {
    bool meets = true;
    for (int a = 0; a < 3; ++a) {
        qlo[a] = std::max(c[a] - h, lo[a]);
        qhi[a] = std::min(c[a] + h, hi[a]);
        meets = meets && qlo[a] <= qhi[a];
    }
    return meets;
}

size_t nearEntries(const IslandNear& near) {
    Vec3 lo, hi;
    return clipToBox(near.centre, near.reach, near.lo, near.hi, lo, hi) ? near.grid->entriesIn(lo, hi) : 0;
}

bool boxFarther(const std::array<double, 6>& box, Vec3 p, double best2, double margin) {
    if (!(best2 < 1e300)) return false;
    const double bound = std::sqrt(best2) + margin;
    return boxDistance2(box, p) > bound * bound;
}

bool inNear(const TriMesh& mesh, const IslandNear& near, Vec3 n, uint32_t f) {
    const std::array<double, 6> bx = faceBox(mesh, f);
    return boxDistance2(bx, near.centre) <= near.reach * near.reach && (near.allFaces || facesIslandWay(mesh, f, n));
}

// Cubes around p doubling from `start`, each clipped to the described region (the box [lo, hi]
// and the cube of half-side reach around the centre: a face of the set meets both), until the
// closest face found lies inside the cube: every face as close has its box inside it too, and of
// the cube's faces (in cell order) the least (distance, id) pair wins, so the first closest is
// the first of the whole set. A box pruned against the best so far is strictly farther than it.
double closestNearFace(const TriMesh& mesh, const IslandNear& near, Vec3 n, Vec3 p, double start, uint32_t& face,
                       std::array<double, 3>& bary) {
    Vec3 lo, hi;
    if (!clipToBox(near.centre, near.reach, near.lo, near.hi, lo, hi)) return 1e300;
    const double scale = 1e-9 * (1 + std::abs(p.x) + std::abs(p.y) + std::abs(p.z));
    for (double rho = std::max(start, scale);; rho *= 2) {
        bool covers = true;
        for (int a = 0; a < 3; ++a) covers = covers && p[a] - rho <= lo[a] && p[a] + rho >= hi[a];
        Vec3 qlo, qhi;
        double best = 1e300;
        bool found = false;
        if (clipToBox(p, rho, lo, hi, qlo, qhi))
            near.grid->forEachFaceIn(qlo, qhi, [&](uint32_t f) {
                if (boxFarther(faceBox(mesh, f), p, best, scale) || !inNear(mesh, near, n, f)) return;
                std::array<double, 3> b;
                const double d = faceDistance2(mesh, f, p, &b);
                if (d < best || (found && d == best && f < face)) {
                    best = d;
                    face = f;
                    bary = b;
                    found = true;
                }
            });
        if (covers || (best < 1e300 && std::sqrt(best) * (1 + 1e-6) + scale <= rho)) return best;
    }
}

// The texels of each island are measured over facesNearTriangle of its facing faces, which holds
// the closest point of every point X of the island's triangle among them; the merge is in island
// order (island_bake.h).
void rasterizeIslands(const TriMesh& mesh, const std::vector<BakeIsland>& islands, const TexelRegion& g, double dilation,
                      int threads, std::vector<TexelHit>& hits) {
    for (size_t i = 0; i < islands.size(); ++i)
        if (islands[i].faces.empty() && !islands[i].near.grid)
            throw InvalidInput("bake: island " + std::to_string(i) + " has no faces to sample");
    // Which island each texel goes to, from the texel distances alone (the nearest, the earlier
    // island on ties, nearer than the face's hit): only that island measures the texel's closest
    // point, the one the merge below would keep.
    std::vector<int32_t> owner;
    std::vector<float> ownerDist;
    assignTouched(owner, hits.size(), int32_t(-1), threads);
    assignTouched(ownerDist, hits.size(), 0.0f, threads);
    for (size_t t = 0; t < hits.size(); ++t) ownerDist[t] = hits[t].dist;
    auto texelTriangle = [&](const BakeIsland& isl, Vec2 (&P)[3]) {
        for (int k = 0; k < 3; ++k) P[k] = {isl.uv[size_t(k)].x * g.size, isl.uv[size_t(k)].y * g.size};
        return std::fabs(cross(P[1] - P[0], P[2] - P[0])) >= 1e-12;
    };
    parallelChunks(size_t(g.h), kRasterRows, threads, [&](size_t rowBegin, size_t rowEnd, size_t) {
        for (size_t i = 0; i < islands.size(); ++i) {
            Vec2 P[3];
            if (!texelTriangle(islands[i], P) || offBand(P, dilation, rowBegin, rowEnd)) continue;
            const EdgeDistanceBound bound(P);
            forEachTexelNear(
                P, g, dilation,
                [&](int x, int y, double d, const std::array<double, 3>&) {
                    const size_t t = g.at(x, y);
                    if (!(float(d) < ownerDist[t])) return;
                    ownerDist[t] = float(d);
                    owner[t] = int32_t(i);
                },
                int(rowBegin), int(rowEnd), [&](int x, int y) { return cannotTake(bound, dilation, ownerDist[g.at(x, y)], x, y); });
        }
    });
    std::vector<std::vector<std::pair<size_t, TexelHit>>> found(islands.size());
    parallelFor(islands.size(), threads, [&](size_t i) {
        const BakeIsland& isl = islands[i];
        Vec2 P[3];
        if (!texelTriangle(isl, P)) return;
        // The texels first: a few of them are answered faster by BoxedFaces' scan than by
        // building a FaceTree (both give the scan's answer).
        struct Query {
            size_t texel;
            float d;
            Vec3 X;
        };
        std::vector<Query> queries;
        forEachTexelNear(P, g, dilation, [&](int x, int y, double d, const std::array<double, 3>& b) {
            if (owner[g.at(x, y)] != int32_t(i)) return;  // a face's hit or another island's is nearer
            queries.push_back({g.at(x, y), float(d), isl.position[0] * b[0] + isl.position[1] * b[1] + isl.position[2] * b[2]});
        });
        if (queries.empty()) return;
        auto answer = [&](const auto& near, auto&& closest) {
            for (const Query& q : queries) {
                std::array<double, 3> fb{};
                uint32_t f = closest(near, q.X, fb);
                found[i].push_back({q.texel, {int32_t(f), q.d, {float(fb[0]), float(fb[1]), float(fb[2])}, int32_t(i)}});
            }
        };
        if (isl.near.grid && queries.size() * kLookupEntries < nearEntries(isl.near)) {
            // Few texels for the faces listed: each looked up around itself, starting from a cell
            // of the grid or the previous texel's distance (only a speed choice: the answer is the
            // list's).
            const Vec3 n = islandNormal(isl.position);
            double start = isl.near.grid->cellSide();
            answer(isl.near, [&](const IslandNear& near, Vec3 X, std::array<double, 3>& fb) {
                uint32_t f = 0;
                start = std::max(isl.near.grid->cellSide(), 1.25 * std::sqrt(closestNearFace(mesh, near, n, X, start, f, fb)));
                return f;
            });
            return;
        }
        // Copies are dropped after the nearness filter, which keeps or drops a face's copies with it
        // (same box, same distance), so the set is the same and the hashing sees far fewer faces.
        std::vector<uint32_t> faces =
            isl.near.grid ? withoutCopies(mesh, nearFaces(mesh, isl.near, isl.position))
                          : withoutCopies(mesh, facesNearTriangle(mesh, facingFaces(mesh, isl.faces, isl.position), isl.position));
        if (queries.size() < kIslandTreeFrom) {
            uint32_t f = 0xffffffffu;  // the previous texel's face: the next texel's search bound
            answer(BoxedFaces(mesh, std::move(faces)), [&](const BoxedFaces& near, Vec3 X, std::array<double, 3>& fb) {
                near.closest(X, f, f, fb);
                return f;
            });
        } else {
            uint32_t hint = UINT32_MAX;  // the previous texel's answer: the next texel's start
            answer(FaceTree(mesh, std::move(faces)), [&](const FaceTree& near, Vec3 X, std::array<double, 3>& fb) {
                uint32_t f = 0;
                near.closest(X, f, fb, hint);
                return f;
            });
        }
    });
    for (const auto& list : found)
        for (const auto& [texel, hit] : list)
            if (hit.dist < hits[texel].dist) hits[texel] = hit;
}

// d(original UV)/d(texel x) and /d(texel y) at an island texel: texel -> 3D on the island's
// triangle (affine), then 3D -> original UV on face f (its tangent plane, affine).
void islandDerivatives(const TriMesh& mesh, const BakeIsland& isl, int size, uint32_t f, const Vec2 T[3], Vec2& dx, Vec2& dy) {
    dx = dy = Vec2{0, 0};
    Vec2 P[3];
    for (int k = 0; k < 3; ++k) P[k] = {isl.uv[size_t(k)].x * size, isl.uv[size_t(k)].y * size};
    Vec2 e1 = P[1] - P[0], e2 = P[2] - P[0];
    double det = cross(e1, e2);
    if (!(std::fabs(det) > 0)) return;
    Vec3 E1 = isl.position[1] - isl.position[0], E2 = isl.position[2] - isl.position[0];
    Vec3 dXdx = (E1 * e2.y - E2 * e1.y) * (1 / det), dXdy = (E2 * e1.x - E1 * e2.x) * (1 / det);
    const Tri& t = mesh.triangles[f];
    Vec3 a1 = mesh.positions[t[1]] - mesh.positions[t[0]], a2 = mesh.positions[t[2]] - mesh.positions[t[0]];
    double g11 = dot(a1, a1), g12 = dot(a1, a2), g22 = dot(a2, a2), gd = g11 * g22 - g12 * g12;
    if (!(gd > 0)) return;
    auto map = [&](Vec3 v) {
        double r1 = dot(a1, v), r2 = dot(a2, v);
        double al = (g22 * r1 - g12 * r2) / gd, be = (g11 * r2 - g12 * r1) / gd;
        return (T[1] - T[0]) * al + (T[2] - T[0]) * be;
    };
    dx = map(dXdx);
    dy = map(dXdy);
}

}  // namespace bake_detail

std::vector<BakeIsland> layoutBakeIslands(const TriMesh& mesh, const ChartLayout& layout) {
    std::vector<BakeIsland> out;
    if (layout.islands.empty()) return out;
    std::vector<std::vector<uint32_t>> vertexCharts(mesh.vertexCount());
    std::vector<std::vector<uint32_t>> chartFaces(layout.chartCount);  // ascending ids
    std::vector<uint32_t> unindexed;  // faces with a repeated corner index: FaceGrid leaves them out
    for (uint32_t f = 0; f < mesh.triangleCount(); ++f) {
        const uint32_t c = layout.faceChart.at(f);
        if (c >= layout.chartCount) throw InvalidInput("layout: chart id out of range");
        for (uint32_t v : mesh.triangles[f]) vertexCharts[v].push_back(c);
        chartFaces[c].push_back(f);
        if (degenerateIndices(mesh.triangles[f])) unindexed.push_back(f);
    }
    // An island samples the faces of every chart that holds one of its corners, but the bake
    // (facesNearTriangle) keeps only those whose box lies within d0 + 2r of the island's centroid
    // c (d0: c's distance to them, r: the largest |corner - c|). A corner lies on such a face, so
    // d0 <= r: the faces within 4r of c hold all it keeps, in the same order (by chart, then id),
    // and the island's face list stays proportional to its own size, not its charts'. Those faces
    // are the grid's faces in the box around c within 4r (plus the faces the grid leaves out), found
    // through the grid or by a scan of the charts' faces, whichever visits fewer: the same faces.
    const FaceGrid grid(mesh);
    for (size_t i = 0; i < layout.islands.size(); ++i) {
        const LayoutIsland& isl = layout.islands[i];
        BakeIsland b;
        b.uv = isl.uv;
        std::vector<uint32_t> charts;
        for (size_t k = 0; k < 3; ++k) {
            if (isl.vertices[k] >= mesh.vertexCount()) throw InvalidInput("layout island " + std::to_string(i) + ": vertex out of range");
            b.position[k] = mesh.positions[isl.vertices[k]];
            charts.insert(charts.end(), vertexCharts[isl.vertices[k]].begin(), vertexCharts[isl.vertices[k]].end());
        }
        std::sort(charts.begin(), charts.end());
        charts.erase(std::unique(charts.begin(), charts.end()), charts.end());
        if (charts.empty()) throw InvalidInput("layout island " + std::to_string(i) + " touches no chart");
        const Vec3 c = (b.position[0] + b.position[1] + b.position[2]) * (1.0 / 3);
        double r = 0;
        for (const Vec3& q : b.position) r = std::max(r, length(q - c));
        const double reach = 4 * r * (1 + 1e-6) + 1e-9 * (1 + length(c));
        const Vec3 lo = c - Vec3{reach, reach, reach}, hi = c + Vec3{reach, reach, reach};
        size_t scan = 0;
        for (uint32_t ch : charts) scan += chartFaces[ch].size();
        if (scan <= grid.entriesIn(lo, hi)) {
            for (uint32_t ch : charts)
                for (uint32_t f : chartFaces[ch]) {
                    const std::array<double, 6> bx = faceBox(mesh, f);
                    // FaceGrid::facesIn's test, for the faces it lists
                    const bool inBox = degenerateIndices(mesh.triangles[f]) ||
                                       (bx[0] <= hi.x && bx[3] >= lo.x && bx[1] <= hi.y && bx[4] >= lo.y && bx[2] <= hi.z && bx[5] >= lo.z);
                    if (inBox && boxDistance2(bx, c) <= reach * reach) b.faces.push_back(f);
                }
        } else {
            std::vector<uint32_t> near = grid.facesIn(lo, hi);
            near.insert(near.end(), unindexed.begin(), unindexed.end());
            for (uint32_t f : near)
                if (std::binary_search(charts.begin(), charts.end(), layout.faceChart[f]) && boxDistance2(faceBox(mesh, f), c) <= reach * reach)
                    b.faces.push_back(f);
            std::sort(b.faces.begin(), b.faces.end(), [&](uint32_t x, uint32_t y) {
                return std::make_pair(layout.faceChart[x], x) < std::make_pair(layout.faceChart[y], y);
            });
            b.faces.erase(std::unique(b.faces.begin(), b.faces.end()), b.faces.end());
        }
        if (b.faces.empty()) throw InvalidInput("layout island " + std::to_string(i) + " touches no chart");
        out.push_back(std::move(b));
    }
    return out;
}

// The bake keeps, of an island's faces S, facesNearTriangle(facingFaces(S)): the faces whose box
// lies within d0 + 2r of the triangle's centroid c, d0 being c's distance to the facing faces.
// d0 is found around c instead of over all of S: from cubes around c that double until the
// nearest facing face of S found lies inside the cube (every nearer face's box then overlaps it)
// or the cube holds [lo, hi]. Each cube is queried clipped to [lo, hi] (bake_detail::clipToBox):
// a face box meeting both boxes meets their intersection (boxes meet axis by axis, and intervals
// that meet pairwise share a point), so a query lists exactly the faces of S in the cube, at no
// more cost than S's own query. Same arithmetic for d0 as facesNearTriangle's.
bool projectedIslandNear(const TriMesh& mesh, const FaceGrid& grid, const std::array<Vec3, 3>& tri, Vec3 lo, Vec3 hi,
                         IslandNear& near) {
    const Vec3 n = bake_detail::islandNormal(tri);
    const Vec3 c = (tri[0] + tri[1] + tri[2]) * (1.0 / 3);
    double r = 0;
    for (const Vec3& q : tri) r = std::max(r, length(q - c));
    const double scale = 1e-9 * (1 + std::abs(c.x) + std::abs(c.y) + std::abs(c.z));
    double facing = 1e300, any = 1e300;  // squared distances from c to S's facing faces, to all of S
    // From a grid cell (or r, when smaller): the centroid of a coarse island lies far nearer the
    // original than r, and a cube's scan costs as the faces in it (the doublings sum to a few
    // times the last one's).
    for (double rho = std::max(std::min(r, grid.cellSide()), scale);; rho *= 2) {
        bool covers = true;
        for (int a = 0; a < 3; ++a) covers = covers && c[a] - rho <= lo[a] && c[a] + rho >= hi[a];
        Vec3 qlo, qhi;
        facing = any = 1e300;
        // Minima: the faces' order does not matter.
        if (bake_detail::clipToBox(c, rho, lo, hi, qlo, qhi))
            grid.forEachFaceIn(qlo, qhi, [&](uint32_t f) {
                const bool way = bake_detail::facesIslandWay(mesh, f, n);
                // any <= facing: a box farther than the face's minimum changes neither
                if (bake_detail::boxFarther(faceBox(mesh, f), c, way ? facing : any, scale)) return;
                const double d = faceDistance2(mesh, f, c, nullptr);
                any = std::min(any, d);
                if (way) facing = std::min(facing, d);
            });
        if (covers || (facing < 1e300 && std::sqrt(facing) * (1 + 1e-6) + scale <= rho)) break;
    }
    near.allFaces = !(facing < 1e300);  // no face of S faces the island's way: facingFaces keeps all
    const double d0 = near.allFaces ? any : facing;
    if (!(d0 < 1e300)) return false;
    near.grid = &grid;
    near.lo = lo;
    near.hi = hi;
    near.centre = c;
    near.reach = (std::sqrt(d0) + 2 * r) * (1 + 1e-9) + 1e-12;
    return true;
}

bool projectedIslandFaces(const TriMesh& mesh, const FaceGrid& grid, Vec3 lo, Vec3 hi, BakeIsland& island) {
    if (grid.entriesIn(lo, hi) > bake_detail::kListEntries) return projectedIslandNear(mesh, grid, island.position, lo, hi, island.near);
    island.faces = grid.facesIn(lo, hi);
    return !island.faces.empty();
}

std::vector<uint32_t> nearFaces(const TriMesh& mesh, const IslandNear& near, const std::array<Vec3, 3>& tri) {
    const Vec3 n = bake_detail::islandNormal(tri);
    Vec3 qlo, qhi;
    std::vector<uint32_t> out;
    if (!bake_detail::clipToBox(near.centre, near.reach, near.lo, near.hi, qlo, qhi)) return out;
    for (uint32_t f : near.grid->facesIn(qlo, qhi))
        if (bake_detail::inNear(mesh, near, n, f)) out.push_back(f);
    return out;
}

}  // namespace lodbake
