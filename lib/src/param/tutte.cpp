// Tutte embedding of a disk chart (Tutte 1963; mean-value weights: Floater 2003, "Mean value
// coordinates"). The only Eigen user of the param module besides the Ceres bridge.
#include <algorithm>
#include <cmath>
#include <unordered_map>

#include <Eigen/Sparse>
#include <Eigen/SparseLU>

#include "lodbake/core/adjacency.h"
#include "lodbake/core/errors.h"
#include "lodbake/core/key_set.h"
#include "lodbake/core/math.h"
#include "lodbake/param/chart_uv.h"

namespace lodbake {
namespace {

// The boundary loop, oriented like the triangles (interior on the left).
std::vector<uint32_t> findBoundaryLoop(const ChartMesh& chart) {
    KeySet half(chart.triangles.size() * 3);
    for (const Tri& t : chart.triangles)
        for (int k = 0; k < 3; ++k) half.insert(directedEdgeKey(t[k], t[(k + 1) % 3]));
    std::unordered_map<uint32_t, uint32_t> next;
    size_t count = 0;
    uint32_t start = UINT32_MAX;
    for (const Tri& t : chart.triangles)
        for (int k = 0; k < 3; ++k) {
            uint32_t a = t[k], b = t[(k + 1) % 3];
            if (half.contains(directedEdgeKey(b, a))) continue;
            if (!next.emplace(a, b).second) throw Impossible("chart boundary is not a simple loop");
            ++count;
            start = std::min(start, a);
        }
    if (count < 3) throw Impossible("chart has no boundary (closed surface); it cannot be flattened");
    std::vector<uint32_t> loop{start};
    uint32_t cur = next.at(start);
    while (cur != start) {
        loop.push_back(cur);
        auto it = next.find(cur);
        if (it == next.end() || loop.size() > count) throw Impossible("chart boundary is not a simple loop");
        cur = it->second;
    }
    if (loop.size() != count) throw Impossible("chart has more than one boundary loop (not a disk)");
    return loop;
}

}  // namespace

std::vector<Vec2> tutteEmbedding(const ChartMesh& chart) {
    const size_t n = chart.positions.size();
    std::vector<uint32_t> loop = findBoundaryLoop(chart);
    std::vector<Vec2> uv(n);
    std::vector<char> onBoundary(n, 0);

    // (1) Boundary on the unit circle by arc length, counter-clockwise.
    double total = 0;
    std::vector<double> cum(loop.size() + 1, 0);
    for (size_t i = 0; i < loop.size(); ++i) {
        double l = length(chart.positions[loop[(i + 1) % loop.size()]] - chart.positions[loop[i]]);
        cum[i + 1] = cum[i] + (l > 0 ? l : 0);
    }
    total = cum[loop.size()];
    for (size_t i = 0; i < loop.size(); ++i) {
        double t = total > 0 ? cum[i] / total : double(i) / double(loop.size());
        uv[loop[i]] = {std::cos(2 * kPi * t), std::sin(2 * kPi * t)};
        onBoundary[loop[i]] = 1;
    }

    // (2) Mean-value weights w_ij = (tan(a/2) + tan(b/2)) / |x_i - x_j| (per corner contributions).
    std::vector<std::unordered_map<uint32_t, double>> w(n);
    std::vector<char> uniform(n, 0);
    for (const Tri& t : chart.triangles)
        for (int k = 0; k < 3; ++k) {
            uint32_t i = t[k], j = t[(k + 1) % 3], l = t[(k + 2) % 3];
            Vec3 e1 = chart.positions[j] - chart.positions[i], e2 = chart.positions[l] - chart.positions[i];
            double l1 = length(e1), l2 = length(e2);
            double c = (l1 > 0 && l2 > 0) ? std::clamp(dot(e1, e2) / (l1 * l2), -1.0, 1.0) : 1;
            double th = std::tan(std::acos(c) / 2);
            double wj = th / l1, wl = th / l2;
            if (!(std::isfinite(wj) && std::isfinite(wl) && wj > 1e-12 && wl > 1e-12)) uniform[i] = 1;
            w[i][j] += std::isfinite(wj) ? wj : 0;
            w[i][l] += std::isfinite(wl) ? wl : 0;
        }

    // (3) Interior system: sum_j w_ij (u_i - u_j) = 0.
    std::vector<int> slot(n, -1);
    int m = 0;
    for (size_t v = 0; v < n; ++v)
        if (!onBoundary[v] && !w[v].empty()) slot[v] = m++;
    if (m > 0) {
        std::vector<Eigen::Triplet<double>> trip;
        Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(m, 2);
        for (size_t v = 0; v < n; ++v) {
            if (slot[v] < 0) continue;
            std::vector<std::pair<uint32_t, double>> row(w[v].begin(), w[v].end());
            std::sort(row.begin(), row.end());
            double sum = 0;
            for (auto& [j, wij] : row) {
                double ww = uniform[v] ? 1.0 : wij;
                sum += ww;
                if (slot[j] >= 0) trip.emplace_back(slot[v], slot[j], -ww);
                else {
                    rhs(slot[v], 0) += ww * uv[j].x;
                    rhs(slot[v], 1) += ww * uv[j].y;
                }
            }
            trip.emplace_back(slot[v], slot[v], sum);
        }
        Eigen::SparseMatrix<double> A(m, m);
        A.setFromTriplets(trip.begin(), trip.end());
        A.makeCompressed();
        Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
        lu.compute(A);
        if (lu.info() != Eigen::Success) throw SolverError("Tutte system could not be factorised");
        Eigen::MatrixXd x = lu.solve(rhs);
        if (lu.info() != Eigen::Success) throw SolverError("Tutte system could not be solved");
        for (size_t v = 0; v < n; ++v)
            if (slot[v] >= 0) uv[v] = {x(slot[v], 0), x(slot[v], 1)};
    }

    // (4) Area match: total UV area = total 3D area.
    double a3 = 0, a2 = 0;
    for (const Tri& t : chart.triangles) {
        a3 += length(cross(chart.positions[t[1]] - chart.positions[t[0]], chart.positions[t[2]] - chart.positions[t[0]]));
        a2 += cross(uv[t[1]] - uv[t[0]], uv[t[2]] - uv[t[0]]);
    }
    double s = (a2 > 0 && a3 > 0) ? std::sqrt(a3 / a2) : 1;
    for (Vec2& p : uv) p = p * s;
    return uv;
}

}  // namespace lodbake
