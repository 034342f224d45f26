// Least-squares conformal map of a disk chart (Lévy, Petitjean, Ray, Maillot 2002, "Least
// squares conformal maps for automatic texture atlas generation"): the start the Ceres solve
// refines when it is injective. Its free boundary follows the chart's shape, so on large curved
// charts it starts far closer to isometric than Tutte's circle and the solve needs few steps.
//
// Per triangle with corners z_j = x_j + i y_j in its own plane (CCW), the map U_j = u_j + i v_j is
// conformal when sum_j W_j U_j = 0 with W_j = z_k - z_l (j, k, l cyclic); the residual, scaled by
// 1 / sqrt(2 area), is two real rows. Two boundary vertices far apart are pinned; the rest solve
// the normal equations (SPD once two vertices are pinned on a connected chart).
#include <algorithm>
#include <cmath>

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include "lodbake/core/adjacency.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/key_set.h"
#include "lodbake/param/chart_uv.h"
#include "param/solver_output.h"
#include "param/solver_threads.h"

namespace lodbake {
namespace {

// From this many unknowns the normal equations are factorised by CHOLMOD's supernodal Cholesky
// (dense blocks through BLAS), far faster on a chart of 10k+ vertices than Eigen's simplicial
// LDLT, which keeps smaller charts (and so every small asset's output) as they were.
constexpr long kSupernodalFrom = 20000;

// x with AtA x = b; false when the system could not be factorised or solved.
template <class Solver>
bool solveNormal(const Eigen::SparseMatrix<double>& AtA, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    Solver solver;
    solver.compute(AtA);
    if (solver.info() != Eigen::Success) return false;
    x = solver.solve(b);
    return solver.info() == Eigen::Success && x.allFinite();
}

}  // namespace
namespace {

// The two boundary vertices farthest apart along the chart's longest bounding-box axis (lowest
// index on ties): pinned at (0, 0) and (their 3D distance, 0).
std::pair<uint32_t, uint32_t> pinPair(const ChartMesh& chart) {
    KeySet half(chart.triangles.size() * 3);
    for (const Tri& t : chart.triangles)
        for (int k = 0; k < 3; ++k) half.insert(directedEdgeKey(t[k], t[(k + 1) % 3]));
    std::vector<uint32_t> boundary;
    for (const Tri& t : chart.triangles)
        for (int k = 0; k < 3; ++k)
            if (!half.contains(directedEdgeKey(t[(k + 1) % 3], t[k]))) boundary.push_back(t[k]);
    if (boundary.size() < 3) throw Impossible("chart has no boundary (closed surface); it cannot be flattened");
    std::sort(boundary.begin(), boundary.end());
    boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());
    Vec3 lo = chart.positions[boundary[0]], hi = lo;
    for (uint32_t v : boundary) {
        const Vec3& p = chart.positions[v];
        lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
        hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    const Vec3 ext = hi - lo;
    auto coord = [&](uint32_t v) {
        const Vec3& p = chart.positions[v];
        return ext.x >= ext.y && ext.x >= ext.z ? p.x : (ext.y >= ext.z ? p.y : p.z);
    };
    uint32_t a = boundary[0], b = boundary[0];
    for (uint32_t v : boundary) {
        if (coord(v) < coord(a)) a = v;
        if (coord(v) > coord(b)) b = v;
    }
    if (a == b) b = boundary[1];
    return {a, b};
}

}  // namespace

std::vector<Vec2> lscmEmbedding(const ChartMesh& chart) {
    const size_t n = chart.positions.size();
    const auto [pinA, pinB] = pinPair(chart);
    const double pinDist = length(chart.positions[pinB] - chart.positions[pinA]);
    if (!(pinDist > 0)) throw SolverError("LSCM pins coincide");

    // Unknowns: (u, v) of every free vertex, interleaved; pinned ones go to the right-hand side.
    std::vector<int> slot(n, -1);
    int m = 0;
    for (size_t v = 0; v < n; ++v)
        if (v != pinA && v != pinB) slot[v] = m++;
    std::vector<Vec2> uv(n);
    uv[pinA] = {0, 0};
    uv[pinB] = {pinDist, 0};

    std::vector<Eigen::Triplet<double>> trip;
    trip.reserve(chart.triangles.size() * 12);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(long(2 * chart.triangles.size()));
    long row = 0;
    for (const Tri& t : chart.triangles) {
        const Vec3 p0 = chart.positions[t[0]], p1 = chart.positions[t[1]], p2 = chart.positions[t[2]];
        const Vec3 e1 = p1 - p0, e2 = p2 - p0;
        const double l1 = length(e1), a2 = length(cross(e1, e2));  // a2 = 2 x area
        if (!(l1 > 0) || !(a2 > 1e-300)) continue;                 // degenerate: no constraint
        // Local frame: p0 at the origin, p1 on +x, p2 above.
        const double z[3][2] = {{0, 0}, {l1, 0}, {dot(e2, e1) / l1, a2 / l1}};
        const double s = 1 / std::sqrt(a2);
        for (int j = 0; j < 3; ++j) {
            const int k = (j + 1) % 3, l = (j + 2) % 3;
            const double wr = s * (z[l][0] - z[k][0]), wi = s * (z[l][1] - z[k][1]);
            // Re: wr u - wi v;  Im: wi u + wr v.
            const uint32_t v = t[size_t(j)];
            if (slot[v] >= 0) {
                trip.emplace_back(row, 2 * slot[v], wr);
                trip.emplace_back(row, 2 * slot[v] + 1, -wi);
                trip.emplace_back(row + 1, 2 * slot[v], wi);
                trip.emplace_back(row + 1, 2 * slot[v] + 1, wr);
            } else {
                rhs[row] -= wr * uv[v].x - wi * uv[v].y;
                rhs[row + 1] -= wi * uv[v].x + wr * uv[v].y;
            }
        }
        row += 2;
    }
    if (m > 0) {
        // Only the normal equations stay for the factorisation (on a large chart its memory peak):
        // the triplets and A go first.
        // CHOLMOD reads only the lower triangle of a symmetric matrix it is handed as such, so
        // only that half is kept for it: the same entries, half the matrix held beside its factor.
        const bool supernodal = 2 * long(m) >= kSupernodalFrom;
        Eigen::SparseMatrix<double> AtA;
        Eigen::VectorXd b;
        {
            Eigen::SparseMatrix<double> A(row, 2 * m);
            A.setFromTriplets(trip.begin(), trip.end());
            std::vector<Eigen::Triplet<double>>().swap(trip);
            AtA = A.transpose() * A;
            b = A.transpose() * rhs.head(row);
            if (supernodal) {
                A = Eigen::SparseMatrix<double>();
                Eigen::SparseMatrix<double> lower = AtA.triangularView<Eigen::Lower>();
                AtA.swap(lower);
            }
        }
        Eigen::VectorXd x;
        silenceSolverOutput();  // CHOLMOD's warnings (a matrix not positive definite) are the result's
        keepSolverThreadsSerial();
        const bool solved = supernodal
                                ? solveNormal<Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>>>(AtA, b, x)
                                : solveNormal<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>>(AtA, b, x);
        if (!solved) throw SolverError("LSCM system could not be factorised or solved");
        for (size_t v = 0; v < n; ++v)
            if (slot[v] >= 0) uv[v] = {x[2 * slot[v]], x[2 * slot[v] + 1]};
    }

    // Orientation and scale: counter-clockwise like the triangles, total UV area = 3D area.
    double a3 = 0, auv = 0;
    for (const Tri& t : chart.triangles) {
        a3 += length(cross(chart.positions[t[1]] - chart.positions[t[0]], chart.positions[t[2]] - chart.positions[t[0]]));
        auv += cross(uv[t[1]] - uv[t[0]], uv[t[2]] - uv[t[0]]);
    }
    if (auv < 0) {
        for (Vec2& p : uv) p.y = -p.y;
        auv = -auv;
    }
    const double s = (auv > 0 && a3 > 0) ? std::sqrt(a3 / auv) : 1;
    for (Vec2& p : uv) p = p * s;
    return uv;
}

}  // namespace lodbake
