// Vertex placement of a coarse level (vertex_placement.h). Each round's linear least squares is
// solved through its normal equations: a term's Jacobian block on vertex k is w_k I, so the
// normal matrix is N (x) I3 with N over the free vertices alone, one sparse Cholesky factorisation
// for the three coordinates.
#include "lod/vertex_placement.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <utility>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "lodbake/core/closest_point.h"
#include "lodbake/core/face_grid.h"
#include "lodbake/core/parallel.h"

namespace lodbake::lod_detail {
namespace {

// Levels up to this many triangles are searched without a grid.
constexpr size_t kSmallLevel = 64;

// A point of the level as a weighted sum of its vertices (local ids, distinct).
struct Combination {
    std::array<uint32_t, 3> vertex{};
    std::array<double, 3> weight{};
    int count = 0;
    void add(uint32_t v, double w) {
        if (!(w != 0)) return;
        for (int k = 0; k < count; ++k)
            if (vertex[size_t(k)] == v) { weight[size_t(k)] += w; return; }
        vertex[size_t(count)] = v;
        weight[size_t(count)] = w;
        ++count;
    }
};

// The simplification pairs' terms of the normal equations. A pair's vertices are the same every
// round (only its weight changes), so the matrix entries its products add to are found once: a
// round sums each entry's products in the pairs' order, the order setFromTriplets sums the
// triplets of one entry in, and hands the sums on as one triplet per entry, ahead of the other
// terms' triplets. Entries of row r (an unknown): [rowStart[r], rowStart[r + 1]) of `column`.
struct PairTerms {
    std::vector<Combination> combination;  // per pair with a term, the level point it pulls
    std::vector<Vec3> target;               // and the removed vertex it pulls towards
    std::vector<uint32_t> entry;            // per pair in order, the entry of each unknown x unknown product
    std::vector<uint32_t> rowStart, column;
};

// Calls fn(uj, uk) for each product of two unknowns of c, in the order the normal equations add them.
template <class Fn>
void forEachProduct(const Combination& c, const std::vector<uint32_t>& unknown, Fn&& fn) {
    for (int j = 0; j < c.count; ++j) {
        const uint32_t uj = unknown[c.vertex[size_t(j)]];
        if (uj == UINT32_MAX) continue;
        for (int k = 0; k < c.count; ++k) {
            const uint32_t uk = unknown[c.vertex[size_t(k)]];
            if (uk != UINT32_MAX) fn(uj, uk);
        }
    }
}

PairTerms pairTerms(const TriMesh& original, const Level& level, const std::vector<uint32_t>& local,
                    const std::vector<uint32_t>& unknown, uint32_t unknowns) {
    PairTerms pt;
    // Reserved, not grown by doubling: a million-triangle level's terms are some 60 MB, and two
    // levels are placed side by side at the measure's peak.
    pt.combination.reserve(level.pairs.size());
    pt.target.reserve(level.pairs.size());
    for (const SimplificationPair& p : level.pairs) {
        if (p.vertex >= original.vertexCount()) continue;
        Combination c;
        bool valid = true;
        for (size_t k = 0; k < 3; ++k) {
            if (p.coarse[k] >= local.size() || local[p.coarse[k]] == UINT32_MAX) { valid = false; break; }
            c.add(local[p.coarse[k]], double(p.bary[k]));
        }
        if (!valid || c.count == 0) continue;
        pt.combination.push_back(c);
        pt.target.push_back(original.positions[p.vertex]);
    }
    // Each row's distinct columns in the order first met: every row gets room for all the products
    // it receives, then the rows are packed.
    std::vector<uint32_t> room(size_t(unknowns) + 1, 0);
    for (const Combination& c : pt.combination) forEachProduct(c, unknown, [&](uint32_t uj, uint32_t) { ++room[uj + 1]; });
    for (uint32_t r = 0; r < unknowns; ++r) room[r + 1] += room[r];
    std::vector<uint32_t> columns(room.back()), used(unknowns, 0);
    for (const Combination& c : pt.combination)
        forEachProduct(c, unknown, [&](uint32_t uj, uint32_t uk) {
            uint32_t* const first = columns.data() + room[uj];
            uint32_t* const last = first + used[uj];
            if (std::find(first, last, uk) == last) *last = uk, ++used[uj];
        });
    pt.rowStart.assign(size_t(unknowns) + 1, 0);
    for (uint32_t r = 0; r < unknowns; ++r) pt.rowStart[r + 1] = pt.rowStart[r] + used[r];
    pt.column.reserve(pt.rowStart.back());
    for (uint32_t r = 0; r < unknowns; ++r) pt.column.insert(pt.column.end(), columns.begin() + room[r], columns.begin() + room[r] + used[r]);
    std::vector<uint32_t>().swap(columns);
    pt.entry.reserve(room.back());
    for (const Combination& c : pt.combination)
        forEachProduct(c, unknown, [&](uint32_t uj, uint32_t uk) {
            const auto first = pt.column.begin() + pt.rowStart[uj], last = pt.column.begin() + pt.rowStart[uj + 1];
            pt.entry.push_back(uint32_t(std::find(first, last, uk) - pt.column.begin()));
        });
    return pt;
}

// Points spread over triangles by area: stratified along the cumulative area, barycentrics from
// the R2 low-discrepancy sequence. Each sample is (triangle index, barycentrics).
struct SurfaceSample {
    uint32_t triangle = 0;
    std::array<double, 3> bary{};
};

std::vector<SurfaceSample> areaSamples(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles, size_t count) {
    std::vector<double> cumulative(triangles.size());
    double total = 0;
    for (size_t t = 0; t < triangles.size(); ++t) {
        const Tri& f = triangles[t];
        total += triangleArea(positions[f[0]], positions[f[1]], positions[f[2]]);
        cumulative[t] = total;
    }
    std::vector<SurfaceSample> out;
    if (!(total > 0)) return out;
    out.resize(count);
    for (size_t i = 0; i < count; ++i) {
        const double u = (double(i) + 0.5) / double(count) * total;
        const size_t t = size_t(std::upper_bound(cumulative.begin(), cumulative.end(), u) - cumulative.begin());
        double a = fractionalPart(0.5 + double(i) * 0.7548776662466927), b = fractionalPart(0.5 + double(i) * 0.5698402909980532);
        if (a + b > 1) { a = 1 - a; b = 1 - b; }
        out[i] = {uint32_t(std::min(t, triangles.size() - 1)), {1 - a - b, a, b}};
    }
    return out;
}

Vec3 pointOf(const std::vector<Vec3>& positions, const Tri& t, const std::array<double, 3>& b) {
    return positions[t[0]] * b[0] + positions[t[1]] * b[1] + positions[t[2]] * b[2];
}

// The closest point of `mesh`'s faces to p through its grid, as closestSurfacePoint over them all
// finds it (the first closest face by id): the search box grows from half-side r until the best
// face found lies within it (then no face outside the box can be as close). A face `hint` (a
// nearby query's answer; UINT32_MAX for none) no farther than `hintReach` sizes the box at once: it
// lies in a box of its distance (widened by `margin`, far past rounding). Returns the squared
// distance (1e300 when the mesh has no faces).
double closestThroughGrid(const TriMesh& mesh, const FaceGrid& grid, Vec3 p, double r, double limit, uint32_t hint,
                          double hintReach, double margin, uint32_t& face, std::array<double, 3>& bary) {
    if (hint != UINT32_MAX) {
        const Tri& t = mesh.triangles[hint];
        const auto w = closestOnTriangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
        const double rh = length(pointOf(mesh.positions, t, w) - p) * (1 + 1e-9) + margin;
        if (rh <= hintReach) r = rh;
    }
    for (;; r *= 2) {
        bool any = false;
        const double d = grid.closestIn(mesh, p - Vec3{r, r, r}, p + Vec3{r, r, r}, p, face, bary, any);
        if (any) {
            if (d <= r * r || r > limit) return d;
        } else if (r > limit) {
            return 1e300;
        }
    }
}

}  // namespace

PlacementResult placeLevelVertices(const TriMesh& original, const DistanceReference& surface, const Level& level,
                                   const PlacementOptions& options) {
    PlacementResult res;
    res.positions = original.positions;
    if (level.triangles.empty()) return res;
    std::vector<Vec3>& pos = res.positions;

    // The level's vertices (ascending welded ids) and local ids.
    std::vector<uint32_t> verts;
    for (const Tri& t : level.triangles) verts.insert(verts.end(), t.begin(), t.end());
    std::sort(verts.begin(), verts.end());
    verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
    std::vector<uint32_t> local(original.vertexCount(), UINT32_MAX);
    for (uint32_t i = 0; i < verts.size(); ++i) local[verts[i]] = i;
    const size_t nv = verts.size();

    // Vertices on an edge used by one level triangle or by more than two stay put.
    std::vector<char> fixed(nv, 0);
    {
        std::vector<uint64_t> edges;  // (lower id, higher id), once per use
        edges.reserve(3 * level.triangles.size());
        for (const Tri& t : level.triangles) {
            if (degenerateIndices(t)) continue;
            for (size_t k = 0; k < 3; ++k) {
                const auto [a, b] = std::minmax(t[k], t[(k + 1) % 3]);
                edges.push_back(uint64_t(a) << 32 | b);
            }
        }
        std::sort(edges.begin(), edges.end());
        for (size_t i = 0, j = 0; i < edges.size(); i = j) {
            while (j < edges.size() && edges[j] == edges[i]) ++j;
            if (j - i != 2) fixed[local[uint32_t(edges[i] >> 32)]] = fixed[local[uint32_t(edges[i])]] = 1;
        }
    }
    for (char f : fixed) res.fixed += size_t(f);
    if (res.fixed == nv) return res;

    // Reference orientation of every level face (as simplify left it).
    const size_t nt = level.triangles.size();
    std::vector<Vec3> reference(nt);
    for (size_t t = 0; t < nt; ++t) {
        const Tri& f = level.triangles[t];
        reference[t] = cross(pos[f[1]] - pos[f[0]], pos[f[2]] - pos[f[0]]);
    }
    auto faceHolds = [&](size_t t) {
        const Tri& f = level.triangles[t];
        const Vec3 n = cross(pos[f[1]] - pos[f[0]], pos[f[2]] - pos[f[0]]);
        return dot(n, reference[t]) > 0 && length(n) > 1e-3 * length(reference[t]);
    };

    const double diagonal = bounds(original).diagonal();
    // First search radius: most closest points of a coarse level lie within a few thousandths of
    // the diagonal; the search widens from there.
    const double reach = std::min(std::max(level.maxDeviation, 1e-4 * diagonal), 2e-3 * diagonal);
    double originalArea = 0;
    for (const Tri& f : original.triangles) originalArea += triangleArea(pos[f[0]], pos[f[1]], pos[f[2]]);
    // The samples resolve the original's detail (the level has fewer triangles than the original),
    // so their count on either side follows the original's triangles, capped by the level's free
    // vertices (the unknowns to fit).
    const size_t sideCap = original.triangles.size() > options.largeOriginal
                               ? options.samplesPerSideLarge
                               : std::clamp(original.triangles.size(), options.samplesPerSide, options.samplesPerSideMax);
    const size_t sampleCount = std::min({sideCap, std::max(options.minSamples, options.samplesPerTriangle * original.triangles.size()),
                                         std::max(options.minSamples, options.samplesPerVertex * (nv - res.fixed))});
    const std::vector<SurfaceSample> originalSamples = areaSamples(original.positions, original.triangles, sampleCount);
    std::vector<Vec3> originalPoints(originalSamples.size());
    for (size_t i = 0; i < originalSamples.size(); ++i)
        originalPoints[i] = pointOf(original.positions, original.triangles[originalSamples[i].triangle], originalSamples[i].bary);

    // The unknowns: the free vertices, three coordinates each.
    std::vector<uint32_t> unknown(nv, UINT32_MAX);
    uint32_t nu = 0;
    for (size_t i = 0; i < nv; ++i)
        if (!fixed[i]) unknown[i] = nu++;
    const PairTerms pairs = pairTerms(original, level, local, unknown, nu);
    const double pairWeight = level.pairs.empty() ? 0 : 0.5 * originalArea / double(level.pairs.size());

    std::vector<char> movedEver(nv, 0);
    // Each original sample's closest point on the level (face, barycentrics), kept round to round.
    std::vector<std::pair<uint32_t, std::array<double, 3>>> onLevel(originalPoints.size(), {UINT32_MAX, {}});
    // The level's samples of the previous round and their closest points on the original.
    std::vector<SurfaceSample> previousSamples;
    std::vector<Vec3> previousOnOriginal;
    for (int round = 0; round < options.rounds; ++round) {
        // The level as it stands: its area, samples on it, closest points both ways.
        TriMesh current;
        current.positions = pos;
        current.triangles = level.triangles;
        double levelArea = 0;
        for (const Tri& f : level.triangles) levelArea += triangleArea(pos[f[0]], pos[f[1]], pos[f[2]]);
        if (!(levelArea > 0) || !(originalArea > 0)) break;
        // A small level is searched face by face (pruned by boxes, the previous sample's face as
        // the hint: consecutive samples lie close together), a large one through a grid.
        std::unique_ptr<FaceGrid> currentGrid;
        std::unique_ptr<BoxedFaces> currentFaces;
        if (nt > kSmallLevel) {
            currentGrid = std::make_unique<FaceGrid>(current, 1.0, options.threads);
        } else {
            std::vector<uint32_t> all(nt);
            for (uint32_t t = 0; t < nt; ++t) all[t] = t;
            currentFaces = std::make_unique<BoxedFaces>(current, std::move(all));
        }
        double margin = 0;  // 1e-9 of the level's coordinates
        for (uint32_t v : verts) margin = std::max({margin, std::abs(pos[v].x), std::abs(pos[v].y), std::abs(pos[v].z)});
        margin *= 1e-9;
        parallelChunks(originalPoints.size(), 256, options.threads, [&](size_t begin, size_t end, size_t) {
            uint32_t hint = UINT32_MAX;
            for (size_t i = begin; i < end; ++i) {
                uint32_t f = 0;
                std::array<double, 3> b{};
                // The sample's face of the previous round (the level moved little), else the
                // previous sample's when it lies near.
                const uint32_t last = onLevel[i].first;
                const double d = currentGrid ? closestThroughGrid(current, *currentGrid, originalPoints[i], reach, 4 * diagonal,
                                                                  last != UINT32_MAX ? last : hint, last != UINT32_MAX ? 1e300 : 2 * reach,
                                                                  margin, f, b)
                                             : currentFaces->closest(originalPoints[i], hint, f, b);
                onLevel[i] = {UINT32_MAX, {}};
                if (d < 1e300) onLevel[i] = {f, b}, hint = f;
            }
        });
        const std::vector<SurfaceSample> levelSamples = areaSamples(pos, level.triangles, sampleCount);
        std::vector<Vec3> levelPoints(levelSamples.size());
        for (size_t i = 0; i < levelSamples.size(); ++i)
            levelPoints[i] = pointOf(pos, level.triangles[levelSamples[i].triangle], levelSamples[i].bary);
        // Round to round a sample that stays on its triangle moves little: its previous answer
        // bounds its search.
        std::vector<Vec3> near(levelPoints.size(), Vec3{std::nan(""), 0, 0});
        for (size_t i = 0; i < levelSamples.size() && i < previousSamples.size(); ++i)
            if (previousSamples[i].triangle == levelSamples[i].triangle) near[i] = previousOnOriginal[i];
        std::vector<Vec3> onOriginal = surface.closestPoints(levelPoints, options.threads, near);

        double rms = 0;
        {
            double sum = 0;
            size_t n = 0;
            for (size_t i = 0; i < originalPoints.size(); ++i)
                if (onLevel[i].first != UINT32_MAX) {
                    sum += length2(pointOf(pos, level.triangles[onLevel[i].first], onLevel[i].second) - originalPoints[i]);
                    ++n;
                }
            for (size_t i = 0; i < levelSamples.size(); ++i, ++n)
                sum += length2(pointOf(pos, level.triangles[levelSamples[i].triangle], levelSamples[i].bary) - onOriginal[i]);
            rms = n ? std::sqrt(sum / double(n)) : 0;
        }
        // The linear least squares of this round, as normal equations over the free vertices:
        // N x = rhs, one column per coordinate; fixed vertices move their terms to the right side.
        std::vector<Eigen::Triplet<double>> entries;
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(nu, 3);
        auto reweighted = [&](const Combination& c, Vec3 target, double weight) {
            if (options.reweightPower > 0 && rms > 0) {
                Vec3 p{0, 0, 0};
                for (int k = 0; k < c.count; ++k) p += pos[verts[c.vertex[size_t(k)]]] * c.weight[size_t(k)];
                weight *= 1 + std::pow(length(p - target) / rms, options.reweightPower);
            }
            return weight;
        };
        // Adds the term's products through `product` (the entry's row, column and value) and its
        // right-hand side, with its weight as reweighted.
        auto addWeighted = [&](const Combination& c, Vec3 target, double weight, auto&& product) {
            Vec3 known = target;
            for (int k = 0; k < c.count; ++k)
                if (fixed[c.vertex[size_t(k)]]) known -= pos[verts[c.vertex[size_t(k)]]] * c.weight[size_t(k)];
            for (int j = 0; j < c.count; ++j) {
                const uint32_t uj = unknown[c.vertex[size_t(j)]];
                if (uj == UINT32_MAX) continue;
                const double wj = weight * c.weight[size_t(j)];
                for (int k = 0; k < c.count; ++k) {
                    const uint32_t uk = unknown[c.vertex[size_t(k)]];
                    if (uk != UINT32_MAX) product(uj, uk, wj * c.weight[size_t(k)]);
                }
                for (int a = 0; a < 3; ++a) rhs(uj, a) += wj * known[a];
            }
        };
        auto addTerm = [&](const Combination& c, Vec3 target, double weight) {
            if (c.count == 0) return;
            addWeighted(c, target, reweighted(c, target, weight),
                        [&](uint32_t uj, uint32_t uk, double v) { entries.emplace_back(uj, uk, v); });
        };
        auto combinationOf = [&](const Tri& t, const std::array<double, 3>& b) {
            Combination c;
            for (size_t k = 0; k < 3; ++k) c.add(local[t[k]], b[k]);
            return c;
        };
        {
            const size_t np = pairs.combination.size();
            std::vector<double> weight(np);
            parallelChunks(np, 4096, options.threads, [&](size_t begin, size_t end, size_t) {
                for (size_t i = begin; i < end; ++i) weight[i] = reweighted(pairs.combination[i], pairs.target[i], pairWeight);
            });
            std::vector<double> sum(pairs.column.size(), -0.0);  // -0.0 + x == x for every x: the first product as it is
            size_t e = 0;
            for (size_t i = 0; i < np; ++i)
                addWeighted(pairs.combination[i], pairs.target[i], weight[i],
                            [&](uint32_t, uint32_t, double v) { sum[pairs.entry[e++]] += v; });
            entries.reserve(sum.size());
            for (uint32_t r = 0; r < nu; ++r)
                for (uint32_t k = pairs.rowStart[r]; k < pairs.rowStart[r + 1]; ++k) entries.emplace_back(r, pairs.column[k], sum[k]);
        }
        const double originalWeight = originalArea / double(std::max<size_t>(1, originalPoints.size()));
        for (size_t i = 0; i < originalPoints.size(); ++i)
            if (onLevel[i].first != UINT32_MAX)
                addTerm(combinationOf(level.triangles[onLevel[i].first], onLevel[i].second), originalPoints[i], originalWeight);
        const double levelWeight = levelArea / double(std::max<size_t>(1, levelSamples.size()));
        for (size_t i = 0; i < levelSamples.size(); ++i)
            addTerm(combinationOf(level.triangles[levelSamples[i].triangle], levelSamples[i].bary), onOriginal[i], levelWeight);
        previousSamples = levelSamples;
        previousOnOriginal = std::move(onOriginal);
        const double anchorWeight = options.damping * levelArea / double(nv);
        for (size_t i = 0; i < nv; ++i) {
            if (fixed[i]) continue;
            Combination c;
            c.add(uint32_t(i), 1);
            addTerm(c, pos[verts[i]], anchorWeight);
        }
        Eigen::SparseMatrix<double> normal(nu, nu);
        normal.setFromTriplets(entries.begin(), entries.end());
        entries = {};
        Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(normal);
        ++res.rounds;
        if (ldlt.info() != Eigen::Success) break;
        const Eigen::MatrixXd solved = ldlt.solve(rhs);
        if (ldlt.info() != Eigen::Success || !solved.allFinite()) break;
        std::vector<double> x(3 * nv), start(3 * nv);
        for (size_t i = 0; i < nv; ++i)
            for (int a = 0; a < 3; ++a) {
                start[3 * i + size_t(a)] = pos[verts[i]][a];
                x[3 * i + size_t(a)] = fixed[i] ? pos[verts[i]][a] : solved(unknown[i], a);
            }

        // Take the step, shortened per vertex until no face that held at the round's start flips:
        // halved up to 8 times, then withdrawn.
        std::vector<char> heldBefore(nt);
        for (size_t t = 0; t < nt; ++t) heldBefore[t] = faceHolds(t);
        std::vector<double> alpha(nv, 1.0);
        std::vector<int> halvings(nv, 0);
        for (int pass = 0;; ++pass) {
            for (size_t i = 0; i < nv; ++i)
                for (int a = 0; a < 3; ++a) {
                    const size_t j = 3 * i + size_t(a);
                    double& p = a == 0 ? pos[verts[i]].x : a == 1 ? pos[verts[i]].y : pos[verts[i]].z;
                    p = start[j] + alpha[i] * (x[j] - start[j]);
                }
            bool flipped = false;
            for (size_t t = 0; t < nt; ++t) {
                if (!heldBefore[t] || faceHolds(t)) continue;
                flipped = true;
                for (uint32_t v : level.triangles[t]) {
                    const uint32_t i = local[v];
                    if (alpha[i] == 0) continue;
                    ++res.shortened;
                    alpha[i] = ++halvings[i] > 8 ? 0 : 0.5 * alpha[i];
                }
            }
            if (!flipped) break;
        }
        for (size_t i = 0; i < nv; ++i)
            if (alpha[i] > 0 && !fixed[i]) movedEver[i] = 1;
    }
    for (char m : movedEver) res.moved += size_t(m);
    return res;
}

}  // namespace lodbake::lod_detail
